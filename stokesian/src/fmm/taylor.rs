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
    /// `nu!` of each.
    pub factorial: Vec<f64>,
    /// The index of `nu` in a `(p+1)^3` cube (`usize::MAX` beyond order `p`).
    cube: Vec<usize>,
    /// For each `nu`: the pairs `(mu, nu + mu)` with `|nu + mu| <= p` (shifts).
    pub shift: Vec<Vec<(u32, u32)>>,
    /// The M2L triples `(nu, beta, nu + beta)` with `|nu| + |beta| <= p`.
    pub m2l: Vec<(u32, u32, u32)>,
    /// For each `(gamma, i)`, `gamma_i > 0`: the index of `gamma - e_i`, and of
    /// `gamma - 2 e_i` where `gamma_i > 1`; the first `i` with `gamma_i > 0`.
    recurrence: Vec<(usize, u8, Option<usize>)>,
    /// `1/nu_i` of each `nu` for its recurrence's `i` (no divisions in the monomials).
    inv_index: Vec<f64>,
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
        let factorial: Vec<f64> = nu
            .iter()
            .map(|n| fact(n[0]) * fact(n[1]) * fact(n[2]))
            .collect();
        let inv_factorial = factorial.iter().map(|f| 1.0 / f).collect();
        let mut me = Indices {
            p,
            nu,
            inv_factorial,
            factorial,
            cube,
            shift: Vec::new(),
            m2l: Vec::new(),
            recurrence: Vec::new(),
            inv_index: Vec::new(),
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
        me.inv_index = me
            .recurrence
            .iter()
            .zip(&me.nu)
            .map(|(&(_, i, _), n)| 1.0 / f64::from(n[i as usize].max(1)))
            .collect();
        me
    }

    /// The total order `|nu|` of the multi-index at `k`.
    pub fn order(&self, k: usize) -> usize {
        self.nu[k].iter().map(|&e| e as usize).sum()
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
        self.monomials_to(self.p, v, out);
    }

    /// `v^mu / mu!` for every `|mu| <= order` (a prefix of the graded order), into `out`.
    pub fn monomials_to(&self, order: usize, v: [f64; 3], out: &mut [f64]) {
        out[0] = 1.0;
        for k in 1..count(order) {
            let (prev, i, _) = self.recurrence[k];
            // nu = prev + e_i: v^nu / nu! = v^prev / prev! * v_i / nu_i
            out[k] = out[prev] * v[i as usize] * self.inv_index[k];
        }
    }

    /// `D_gamma(r) = d^gamma |r|` for every `|gamma| <= top` (`top <= p`: a prefix of
    /// the graded order), into `out`, on lanes (one `r` per lane); `work` holds `len()`
    /// values.
    #[inline(always)]
    pub fn potential_derivatives<L: Lane<Elem = f64>>(
        &self,
        r: [L; 3],
        top: usize,
        out: &mut [L],
        work: &mut [L],
    ) {
        debug_assert!(top <= self.p);
        let s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        let inv_s = L::splat(1.0) / s;
        // T^(n) for n = p down to 0 over |gamma| <= p - n, held in `out` (this n) and
        // `work` (n + 1); f^(n)(s) = RADIAL[n] s^(1/2 - n)
        let mut radial = s.sqrt() * inv_s.powi(top as i32);
        let two = L::splat(2.0);
        for n in (0..=top).rev() {
            let len = count(top - n);
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

/// The number of multi-indices of total order at most `order`.
pub(crate) fn count(order: usize) -> usize {
    (order + 1) * (order + 2) * (order + 3) / 6
}

/// `M_{alpha + mu} += s (-delta)^mu / mu!` for every `mu` with `|alpha + mu| <= top`
/// (a derivative source `s d^alpha phi(x - c - delta)`), `mono` holding `(-delta)^mu /
/// mu!`.
#[inline]
pub(crate) fn add_source(
    ix: &Indices,
    top: usize,
    alpha: usize,
    s: f64,
    mono: &[f64],
    m: &mut [f64],
) {
    for &(mu, sum) in &ix.shift[alpha][..count(top - ix.order(alpha))] {
        m[sum as usize] += s * mono[mu as usize];
    }
}

/// Three multipoles of order `top` (channels of `len()` each, one after the other)
/// moved by `(c' - c)`: `M'_{nu + mu} += M_nu (c' - c)^mu / mu!` for `|nu + mu| <= top`,
/// `mono` holding `(c' - c)^mu / mu!`; the channels share each index.
pub(crate) fn translate_multipole(
    ix: &Indices,
    top: usize,
    m: &[f64],
    mono: &[f64],
    out: &mut [f64],
) {
    let len = ix.len();
    let (m0, rest) = m.split_at(len);
    let (m1, m2) = rest.split_at(len);
    let (o0, rest) = out.split_at_mut(len);
    let (o1, o2) = rest.split_at_mut(len);
    for (nu, pairs) in ix.shift[..count(top)].iter().enumerate() {
        let (v0, v1, v2) = (m0[nu], m1[nu], m2[nu]);
        if v0 == 0.0 && v1 == 0.0 && v2 == 0.0 {
            continue;
        }
        for &(mu, sum) in &pairs[..count(top - ix.order(nu))] {
            let (w, sum) = (mono[mu as usize], sum as usize);
            o0[sum] += v0 * w;
            o1[sum] += v1 * w;
            o2[sum] += v2 * w;
        }
    }
}

/// `L_beta += sum_nu M_nu D_{nu + beta}` over `|nu| + |beta| <= top` (without the
/// `1/beta!` of the local expansion, which the caller applies once) for the three
/// channels of `m` (each `len()` long, one after the other) and of `l` (each a third of
/// `l`, a local expansion of order at most `p`), which share `D`; one multipole per
/// lane. For each `beta` the `nu` with `|nu| <= top - |beta|` are a prefix of the graded
/// order, so each sum is a dot product of that prefix of `M` with `D` gathered at `nu +
/// beta` ([`Indices::shift`]): the same indices in every lane.
#[inline(always)]
pub(crate) fn multipole_to_local<L: Lane<Elem = f64>>(
    ix: &Indices,
    top: usize,
    m: &[L],
    d: &[L],
    l: &mut [L],
) {
    let len = ix.len();
    let llen = l.len() / 3;
    debug_assert!(llen <= len && top <= ix.p);
    let (m0, rest) = m.split_at(len);
    let (m1, m2) = rest.split_at(len);
    let betas = llen.min(count(top));
    let zero = L::splat(0.0);
    // four `beta` of one order at a time share each load of `M` (their prefixes are as
    // long): twelve independent sums, and a quarter of the multipoles' traffic
    let mut beta = 0;
    while beta < betas {
        let order = ix.order(beta);
        let end = betas.min(count(order));
        let n = count(top - order);
        while beta + 4 <= end {
            let p: [&[(u32, u32)]; 4] = std::array::from_fn(|u| &ix.shift[beta + u][..n]);
            let mut acc = [[zero; 3]; 4];
            for k in 0..n {
                let (a, b, c) = (m0[k], m1[k], m2[k]);
                for u in 0..4 {
                    let dv = d[p[u][k].1 as usize];
                    acc[u][0] = a.mul_add(dv, acc[u][0]);
                    acc[u][1] = b.mul_add(dv, acc[u][1]);
                    acc[u][2] = c.mul_add(dv, acc[u][2]);
                }
            }
            for (u, sums) in acc.iter().enumerate() {
                for (c, &v) in sums.iter().enumerate() {
                    let slot = c * llen + beta + u;
                    l[slot] = l[slot] + v;
                }
            }
            beta += 4;
        }
        while beta < end {
            let pairs = &ix.shift[beta][..n];
            // four partial sums per channel, so that the fused multiply-adds do not
            // wait on each other
            let mut acc = [[zero; 3]; 4];
            let whole = n / 4 * 4;
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
            for c in 0..3 {
                let slot = c * llen + beta;
                l[slot] = l[slot] + ((acc[0][c] + acc[1][c]) + (acc[2][c] + acc[3][c]));
            }
            beta += 1;
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
            acc += l[gamma as usize] * mono[mu as usize] * ix.factorial[gamma as usize];
        }
        out[beta] += acc * ix.inv_factorial[beta];
    }
}

/// The polynomials in `xi^mu / mu!` whose values at a target `t + xi` are the Faxén
/// functional's parts, from the three channels' local expansions `l` about `t`: `Psi_k`
/// (`k < 3`), `lap Psi_k` (`3 + k`), and with `curl`, `1/2 (d_j Psi_k - d_k Psi_j)`
/// (`6 + m`, `(m, j, k)` cyclic), one after the other, `len()` coefficients each. In
/// that basis `Psi = sum_beta c_beta xi^beta / beta!` with `c_beta = beta! L_beta`, and
/// a derivative `d_i` moves the coefficients, `(d_i c)_gamma = c_{gamma + e_i}` (zero
/// beyond the order).
pub(crate) fn faxen_polynomials(ix: &Indices, l: &[f64], curl: bool) -> Vec<f64> {
    let len = ix.len();
    let c: Vec<f64> = (0..3 * len).map(|q| l[q] * ix.factorial[q % len]).collect();
    let up = |gamma: usize, i: usize| -> Option<usize> {
        let mut n = ix.nu[gamma];
        (n.iter().map(|&e| e as usize).sum::<usize>() < ix.p).then(|| {
            n[i] += 1;
            ix.index(n)
        })
    };
    let mut out = vec![0.0; if curl { 9 } else { 6 } * len];
    out[..3 * len].copy_from_slice(&c);
    for k in 0..3 {
        let ck = &c[k * len..(k + 1) * len];
        for gamma in 0..len {
            out[(3 + k) * len + gamma] = (0..3)
                .filter_map(|i| up(gamma, i).and_then(|once| up(once, i)))
                .map(|twice| ck[twice])
                .sum();
        }
    }
    if curl {
        for m in 0..3 {
            let (j, k) = ((m + 1) % 3, (m + 2) % 3);
            for gamma in 0..len {
                let d = |ch: usize, i: usize| up(gamma, i).map_or(0.0, |g| c[ch * len + g]);
                out[(6 + m) * len + gamma] = 0.5 * (d(k, j) - d(j, k));
            }
        }
    }
    out
}
