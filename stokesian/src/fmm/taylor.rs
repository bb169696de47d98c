//! Cartesian Taylor expansions of fields made of derivatives of the potential
//! `phi(r) = |r|` (`kernels::expansion`): multipole and local expansions, their
//! translations, and the potential's derivatives.
//!
//! Multi-indices `nu = (nu_1, nu_2, nu_3)` of total order `|nu| <= p`, graded then
//! lexicographic; `nu! = nu_1! nu_2! nu_3!`, `x^nu = x_1^nu_1 x_2^nu_2 x_3^nu_3`.
//!
//! - Multipole about `c`: `Psi(x) = sum_nu M_nu d^nu phi(x - c)`. A derivative source
//!   `s d^alpha phi(x - y)`, `y = c + delta`, has `M_{alpha + mu} += s (-delta)^mu / mu!`
//!   (Taylor's theorem in `y`); a multipole about `c` moved to `c'` has
//!   `M'_{nu + mu} += M_nu (c' - c)^mu / mu!` (the same with `delta = c - c'`).
//! - Local about `t`: `Psi(t + xi) = sum_beta L_beta xi^beta`. From a multipole (M2L):
//!   `L_beta = sum_nu M_nu D_{nu + beta}(t - c) / beta!`, `D_gamma = d^gamma phi`,
//!   `|nu| + |beta| <= p`; moved to `t'` (L2L): `L'_beta = sum_{gamma >= beta} L_gamma
//!   C(gamma, beta) (t' - t)^(gamma - beta)`; derivatives at `t + xi`:
//!   `d^kappa Psi = sum_{beta >= kappa} L_beta beta!/(beta - kappa)! xi^(beta - kappa)`.
//! - The potential's derivatives by the chain rule for a function of `s = R.R`:
//!   `T^(n)_gamma = d^gamma [f^(n)(s)]` with `T^(n)_0 = f^(n)(s) = RADIAL[n] s^(1/2 - n)`
//!   (generated, `kernels::expansion::RADIAL`) and, for `gamma_i > 0`,
//!   `T^(n)_gamma = 2 R_i T^(n+1)_{gamma - e_i} + 2 (gamma_i - 1) T^(n+1)_{gamma - 2 e_i}`
//!   (`d_i f^(n) = 2 R_i f^(n+1)` and Leibniz's rule); `D = T^(0)`.

use kernels::expansion::RADIAL;
use kernels::lanes::Lane;

/// The multi-indices of total order `<= p` and the index tables of the expansions'
/// operators, built once per order.
#[derive(Debug)]
pub(crate) struct Indices {
    /// The order `p`.
    pub p: usize,
    /// The multi-indices, graded then lexicographic.
    pub nu: Vec<[u8; 3]>,
    /// `1/nu!` of each.
    pub inv_factorial: Vec<f64>,
    /// The index of `nu` in a `(p+1)^3` cube (`usize::MAX` beyond order `p`).
    cube: Vec<usize>,
    /// For each `nu`: the pairs `(mu, nu + mu)` with `|nu + mu| <= p` (shifts).
    pub shift: Vec<Vec<(u32, u32)>>,
    /// The M2L triples `(nu, beta, nu + beta)` with `|nu| + |beta| <= p`.
    pub m2l: Vec<(u32, u32, u32)>,
    /// For each `(gamma, i)`, `gamma_i > 0`: the index of `gamma - e_i`, and of
    /// `gamma - 2 e_i` where `gamma_i > 1`; the first `i` with `gamma_i > 0`.
    recurrence: Vec<(usize, u8, Option<usize>)>,
}

impl Indices {
    /// The tables of order `p`.
    pub fn new(p: usize) -> Indices {
        let mut nu = Vec::new();
        for order in 0..=p {
            for a in (0..=order).rev() {
                for b in (0..=order - a).rev() {
                    nu.push([a as u8, b as u8, (order - a - b) as u8]);
                }
            }
        }
        let side = p + 1;
        let mut cube = vec![usize::MAX; side * side * side];
        for (k, n) in nu.iter().enumerate() {
            cube[(n[0] as usize * side + n[1] as usize) * side + n[2] as usize] = k;
        }
        let fact = |n: u8| (1..=n).map(f64::from).product::<f64>();
        let inv_factorial = nu
            .iter()
            .map(|n| 1.0 / (fact(n[0]) * fact(n[1]) * fact(n[2])))
            .collect();
        let mut me = Indices {
            p,
            nu,
            inv_factorial,
            cube,
            shift: Vec::new(),
            m2l: Vec::new(),
            recurrence: Vec::new(),
        };
        let order = |n: &[u8; 3]| n.iter().map(|&e| e as usize).sum::<usize>();
        me.shift = (0..me.nu.len())
            .map(|a| {
                let na = me.nu[a];
                (0..me.nu.len())
                    .filter(|&m| order(&na) + order(&me.nu[m]) <= p)
                    .map(|m| {
                        let nm = me.nu[m];
                        let sum = [na[0] + nm[0], na[1] + nm[1], na[2] + nm[2]];
                        (m as u32, me.index(sum) as u32)
                    })
                    .collect()
            })
            .collect();
        me.m2l = (0..me.nu.len())
            .flat_map(|a| me.shift[a].iter().map(move |&(b, s)| (a as u32, b, s)))
            .collect();
        me.recurrence = me
            .nu
            .iter()
            .map(|g| match (0..3).find(|&i| g[i] > 0) {
                None => (usize::MAX, 0, None),
                Some(i) => {
                    let mut one = *g;
                    one[i] -= 1;
                    let two = (g[i] > 1).then(|| {
                        let mut t = one;
                        t[i] -= 1;
                        me.index(t)
                    });
                    (me.index(one), i as u8, two)
                }
            })
            .collect();
        me
    }

    /// The number of multi-indices.
    pub fn len(&self) -> usize {
        self.nu.len()
    }

    /// The index of `nu` (`|nu| <= p`).
    pub fn index(&self, n: [u8; 3]) -> usize {
        let side = self.p + 1;
        self.cube[(n[0] as usize * side + n[1] as usize) * side + n[2] as usize]
    }

    /// `v^mu / mu!` for every `mu`, into `out`.
    pub fn monomials(&self, v: [f64; 3], out: &mut [f64]) {
        out[0] = 1.0;
        for k in 1..self.len() {
            let (prev, i, _) = self.recurrence[k];
            // nu = prev + e_i: v^nu / nu! = v^prev / prev! * v_i / nu_i
            out[k] = out[prev] * v[i as usize] / self.nu[k][i as usize] as f64;
        }
    }

    /// `D_gamma(r) = d^gamma |r|` for every `|gamma| <= p`, into `out`, on lanes (one
    /// `r` per lane); `work` holds `len()` values.
    #[inline(always)]
    pub fn potential_derivatives<L: Lane<Elem = f64>>(
        &self,
        r: [L; 3],
        out: &mut [L],
        work: &mut [L],
    ) {
        let s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        let inv_s = L::splat(1.0) / s;
        // T^(n) for n = p down to 0 over |gamma| <= p - n, held in `out` (this n) and
        // `work` (n + 1); f^(n)(s) = RADIAL[n] s^(1/2 - n)
        let mut radial = s.sqrt() * inv_s.powi(self.p as i32);
        let count = |order: usize| (order + 1) * (order + 2) * (order + 3) / 6;
        let two = L::splat(2.0);
        for n in (0..=self.p).rev() {
            let len = count(self.p - n);
            out[0] = L::splat(RADIAL[n]) * radial;
            for k in 1..len {
                let (one, i, second) = self.recurrence[k];
                let i = i as usize;
                let mut v = two * r[i] * work[one];
                if let Some(second) = second {
                    v = L::splat(2.0 * (self.nu[k][i] as f64 - 1.0)).mul_add(work[second], v);
                }
                out[k] = v;
            }
            work[..len].copy_from_slice(&out[..len]);
            radial = radial * s;
        }
    }
}

/// `M_{alpha + mu} += s (-delta)^mu / mu!` for every `mu` (a derivative source
/// `s d^alpha phi(x - c - delta)`), `mono` holding `(-delta)^mu / mu!`.
#[inline]
pub(crate) fn add_source(ix: &Indices, alpha: usize, s: f64, mono: &[f64], m: &mut [f64]) {
    for &(mu, sum) in &ix.shift[alpha] {
        m[sum as usize] += s * mono[mu as usize];
    }
}

/// A multipole moved by `(c' - c)`: `M'_{nu + mu} += M_nu (c' - c)^mu / mu!`, `mono`
/// holding `(c' - c)^mu / mu!`.
pub(crate) fn translate_multipole(ix: &Indices, m: &[f64], mono: &[f64], out: &mut [f64]) {
    for (nu, &v) in m.iter().enumerate() {
        if v != 0.0 {
            add_source(ix, nu, v, mono, out);
        }
    }
}

/// `L_beta += sum_nu M_nu D_{nu + beta}` (without the `1/beta!` of the local
/// expansion, which the caller applies once) for the three channels of `m` (each
/// `len()` long, one after the other) and of `l` (each a third of `l`, a local
/// expansion of order at most `p`), which share `D`; one multipole per lane. For each
/// `beta` the `nu` with `|nu| <= p - |beta|` are a prefix of the graded order, so each
/// sum is a dot product of that prefix of `M` with `D` gathered at `nu + beta`
/// ([`Indices::shift`]): the same indices in every lane.
#[inline(always)]
pub(crate) fn multipole_to_local<L: Lane<Elem = f64>>(ix: &Indices, m: &[L], d: &[L], l: &mut [L]) {
    let len = ix.len();
    let llen = l.len() / 3;
    debug_assert!(llen <= len);
    let (m0, rest) = m.split_at(len);
    let (m1, m2) = rest.split_at(len);
    let zero = L::splat(0.0);
    for (beta, pairs) in ix.shift[..llen].iter().enumerate() {
        // four partial sums per channel, so that the fused multiply-adds do not wait
        // on each other
        let mut acc = [[zero; 3]; 4];
        let whole = pairs.len() / 4 * 4;
        for (k, quad) in pairs[..whole].chunks_exact(4).enumerate() {
            for (u, &(_, sum)) in quad.iter().enumerate() {
                let (k, dv) = (4 * k + u, d[sum as usize]);
                acc[u][0] = m0[k].mul_add(dv, acc[u][0]);
                acc[u][1] = m1[k].mul_add(dv, acc[u][1]);
                acc[u][2] = m2[k].mul_add(dv, acc[u][2]);
            }
        }
        for (k, &(_, sum)) in pairs.iter().enumerate().skip(whole) {
            let dv = d[sum as usize];
            acc[0][0] = m0[k].mul_add(dv, acc[0][0]);
            acc[0][1] = m1[k].mul_add(dv, acc[0][1]);
            acc[0][2] = m2[k].mul_add(dv, acc[0][2]);
        }
        for (c, slot) in [beta, llen + beta, 2 * llen + beta].into_iter().enumerate() {
            l[slot] = l[slot] + ((acc[0][c] + acc[1][c]) + (acc[2][c] + acc[3][c]));
        }
    }
}

/// A local expansion moved by `v = t' - t`: `L'_beta += sum_{gamma >= beta} L_gamma
/// C(gamma, beta) v^(gamma - beta)`, `mono` holding `v^mu / mu!`:
/// `C(gamma, beta) v^mu = gamma!/beta! (v^mu/mu!)`.
pub(crate) fn translate_local(ix: &Indices, l: &[f64], mono: &[f64], out: &mut [f64]) {
    for (beta, pairs) in ix.shift.iter().enumerate() {
        let mut acc = 0.0;
        for &(mu, gamma) in pairs {
            acc += l[gamma as usize] * mono[mu as usize] / ix.inv_factorial[gamma as usize];
        }
        out[beta] += acc * ix.inv_factorial[beta];
    }
}

/// `d^kappa Psi(t + xi) = sum_{beta >= kappa} L_beta beta!/(beta - kappa)! xi^(beta -
/// kappa)`, `mono` holding `xi^mu / mu!`: `beta!/(beta-kappa)! xi^mu = beta! (xi^mu/mu!)`.
pub(crate) fn local_derivative(ix: &Indices, l: &[f64], kappa: usize, mono: &[f64]) -> f64 {
    let mut acc = 0.0;
    for &(mu, beta) in &ix.shift[kappa] {
        acc += l[beta as usize] * mono[mu as usize] / ix.inv_factorial[beta as usize];
    }
    acc
}
