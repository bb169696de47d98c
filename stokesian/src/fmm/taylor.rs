//! Cartesian Taylor expansions of fields made of derivatives of the potential
//! `phi(r) = |r|` (`kernels::expansion`): multipole and local expansions, their
//! translations (M2L in the reduced bases the biharmonic `phi` allows, [`Biharmonic`]),
//! the potential's derivatives, and the index tables of a set of orders ([`Bases`]).
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

/// The multi-indices of total order `<= p` (those with `nu_1 <= cap` where a cap is
/// given, [`Indices::capped`]) and the index tables of the expansions' operators, built
/// once per order.
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
    /// The number of multi-indices of total order at most `o`, for each `o <= p`.
    prefix: Vec<usize>,
    /// The index of `nu` in a `(p+1)^3` cube (`usize::MAX` beyond order `p` or the cap).
    cube: Vec<usize>,
    /// For each `nu`: the pairs `(mu, nu + mu)` with `|nu + mu| <= p` (shifts; without
    /// a cap only).
    pub shift: Vec<Vec<(u32, u32)>>,
    /// For each `(gamma, i)`, `gamma_i > 0`: the index of `gamma - e_i`, and of
    /// `gamma - 2 e_i` where `gamma_i > 1`; the first `i` with `gamma_i > 0`.
    recurrence: Vec<(usize, u8, Option<usize>)>,
    /// `1/nu_i` of each `nu` for its recurrence's `i` (no divisions in the monomials).
    inv_index: Vec<f64>,
}

impl Indices {
    /// The tables of order `p`.
    pub fn new(p: usize) -> Indices {
        Indices::capped(p, p)
    }

    /// The tables of the multi-indices of order `<= p` with `nu_1 <= cap`: a set that
    /// holds `nu - e_1` and `nu - 2 e_1` with `nu`, so that the recurrences (which lower
    /// the first non-zero index) stay in it. With `cap < p` the shifts are not built.
    pub fn capped(p: usize, cap: usize) -> Indices {
        let mut nu = Vec::new();
        let mut prefix = Vec::new();
        for order in 0..=p {
            for a in (0..=order.min(cap)).rev() {
                for b in (0..=order - a).rev() {
                    nu.push([a as u8, b as u8, (order - a - b) as u8]);
                }
            }
            prefix.push(nu.len());
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
            prefix,
            cube,
            shift: Vec::new(),
            recurrence: Vec::new(),
            inv_index: Vec::new(),
        };
        let order = |n: &[u8; 3]| n.iter().map(|&e| e as usize).sum::<usize>();
        if cap >= p {
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
        }
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

    /// The number of multi-indices of total order at most `order` (`<= p`).
    pub fn count(&self, order: usize) -> usize {
        self.prefix[order]
    }

    /// The total order `|nu|` of the multi-index at `k`.
    pub fn order(&self, k: usize) -> usize {
        self.nu[k].iter().map(|&e| e as usize).sum()
    }

    /// The number of multi-indices.
    pub fn len(&self) -> usize {
        self.nu.len()
    }

    /// The index of `nu` (`|nu| <= p`; `usize::MAX` beyond the cap).
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
        for k in 1..self.count(order) {
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
            let len = self.count(top - n);
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
    for &(mu, sum) in &ix.shift[alpha][..ix.count(top - ix.order(alpha))] {
        m[sum as usize] += s * mono[mu as usize];
    }
}

/// The monomials `mono[mu]` of order `<= top` that are not zero, with their index and
/// order, in the graded order (a translation along one axis: [`translate_multipole`]).
fn nonzero(ix: &Indices, top: usize, mono: &[f64]) -> Vec<(usize, usize, f64)> {
    (0..ix.count(top))
        .filter(|&mu| mono[mu] != 0.0)
        .map(|mu| (mu, ix.order(mu), mono[mu]))
        .collect()
}

/// Three multipoles (channels of `m.1` and `out.1` coefficients, one after the other, at
/// least `count(top)`) moved by `(c' - c)`: `M'_{nu + mu} += M_nu (c' - c)^mu / mu!` for
/// `|nu + mu| <= top`, `mono` holding `(c' - c)^mu / mu!`; the channels share each index. Only the `mu` whose
/// monomial is not zero take part: a binary tree's child lies along one axis from its
/// parent (its box's centre, that centre's image in a mirror normal to an axis, or its
/// projection on such a mirror), and a monomial with a power of another axis is exactly
/// zero, so the sum is the same to the last bit with a twelfth of the terms.
pub(crate) fn translate_multipole(
    ix: &Indices,
    top: usize,
    (m, from): (&[f64], usize),
    mono: &[f64],
    (out, to): (&mut [f64], usize),
) {
    let (m0, rest) = m.split_at(from);
    let (m1, m2) = rest.split_at(from);
    let (o0, rest) = out.split_at_mut(to);
    let (o1, o2) = rest.split_at_mut(to);
    let shifts = nonzero(ix, top, mono);
    for (nu, pairs) in ix.shift[..ix.count(top)].iter().enumerate() {
        let (v0, v1, v2) = (m0[nu], m1[nu], m2[nu]);
        if v0 == 0.0 && v1 == 0.0 && v2 == 0.0 {
            continue;
        }
        let rest = top - ix.order(nu);
        for &(mu, _, w) in shifts.iter().take_while(|s| s.1 <= rest) {
            let sum = pairs[mu].1 as usize;
            o0[sum] += v0 * w;
            o1[sum] += v1 * w;
            o2[sum] += v2 * w;
        }
    }
}

/// The index tables one fast product takes: the multipoles' (`ix`), the local
/// expansions' (`lx`), the particles' moments' (`mx`) and the translation's reduced
/// bases (`bh`), built once per process for each set of orders ([`Bases::of`]: a small
/// product, of a few hundred spheres in a Brownian step, would otherwise spend most of
/// its time building them).
#[derive(Debug)]
pub(crate) struct Bases {
    pub ix: Indices,
    pub lx: Indices,
    pub mx: Indices,
    pub bh: Biharmonic,
}

impl Bases {
    /// The tables of the orders `(ix, lx, mx)`, shared.
    pub fn of(orders: (usize, usize, usize)) -> std::sync::Arc<Bases> {
        use std::collections::HashMap;
        use std::sync::{Arc, Mutex, OnceLock};
        type Built = HashMap<(usize, usize, usize), Arc<Bases>>;
        static BUILT: OnceLock<Mutex<Built>> = OnceLock::new();
        let built = BUILT.get_or_init(|| Mutex::new(HashMap::new()));
        let mut built = built
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        built
            .entry(orders)
            .or_insert_with(|| {
                let (ix, lx) = (Indices::new(orders.0), Indices::new(orders.1));
                let bh = Biharmonic::new(&ix, &lx);
                Arc::new(Bases {
                    mx: Indices::new(orders.2),
                    ix,
                    lx,
                    bh,
                })
            })
            .clone()
    }
}

/// The five multi-indices and coefficients of the biharmonic relation that gives the
/// derivative `nu` (`nu_1 >= 4`) of a biharmonic function (`lap^2 f = 0`) from those
/// with `nu_1` lower by two or four, of the same order:
/// `f_nu = -f_{nu - 4e1 + 4e2} - f_{nu - 4e1 + 4e3} - 2 f_{nu - 2e1 + 2e2}
/// - 2 f_{nu - 2e1 + 2e3} - 2 f_{nu - 4e1 + 2e2 + 2e3}` (`d^(nu - 4 e1)` of
/// `lap^2 = d1^4 + d2^4 + d3^4 + 2 d1^2 d2^2 + 2 d1^2 d3^2 + 2 d2^2 d3^2`).
fn biharmonic_partners(n: [u8; 3]) -> [([u8; 3], f64); 5] {
    let [a, b, c] = n;
    debug_assert!(a >= 4);
    [
        ([a - 4, b + 4, c], -1.0),
        ([a - 4, b, c + 4], -1.0),
        ([a - 2, b + 2, c], -2.0),
        ([a - 2, b, c + 2], -2.0),
        ([a - 4, b + 2, c + 2], -2.0),
    ]
}

/// The multipole-to-local translation in reduced bases. The potential `phi = |r|` is
/// biharmonic away from `r = 0`, and so is every field made of its derivatives: the
/// derivatives `D_nu` with `nu_1 >= 4` are sums of those with `nu_1` lower
/// ([`biharmonic_partners`]), so a multipole `sum_nu M_nu D_nu` equals one with
/// `nu_1 <= 3` alone (each `M_nu`, `nu_1 >= 4`, folded into its partners, the highest
/// `nu_1` first), and a local expansion's coefficients with `beta_1 >= 4` follow from
/// those with `beta_1 <= 3` (the lowest first). The translation then sums over
/// `4n - 2` multi-indices of each order `n >= 3` on both sides instead of
/// `(n + 1)(n + 2)/2`, and needs the derivatives with `gamma_1 <= 6` alone; each
/// truncation `|nu| + |beta| <= top` holds the relation order by order, so the result is
/// the full sum's.
#[derive(Debug)]
pub(crate) struct Biharmonic {
    /// The multipoles' reduced basis: `nu_1 <= 3`, to the multipoles' order.
    pub m: Indices,
    /// The derivatives the translation takes: `gamma_1 <= 6`.
    pub d: Indices,
    /// The local expansions' reduced basis: `beta_1 <= 3`, to their order.
    pub l: Indices,
    /// For each `beta` of `l`: the index in `d` of `nu + beta` for the `nu` of `m` with
    /// `|nu| + |beta| <= m.p` (a prefix of `m`).
    pairs: Vec<Vec<u32>>,
    /// The folds of a full multipole (indices of the full basis), highest `nu_1` first.
    fold: Vec<(usize, [(usize, f64); 5])>,
    /// The full basis' index of each of `m`.
    gather: Vec<usize>,
    /// The local coefficients with `beta_1 >= 4` from their partners (indices of the
    /// full basis), lowest `beta_1` first.
    unfold: Vec<(usize, [(usize, f64); 5])>,
    /// The full basis' index of each of `l`.
    scatter: Vec<usize>,
}

impl Biharmonic {
    /// The tables for multipoles in the basis `full` and local expansions in `local`.
    pub fn new(full: &Indices, local: &Indices) -> Biharmonic {
        let m = Indices::capped(full.p, 3);
        let d = Indices::capped(full.p, 6);
        let l = Indices::capped(local.p, 3);
        let order = |n: [u8; 3]| n.iter().map(|&e| e as usize).sum::<usize>();
        let pairs =
            l.nu.iter()
                .map(|&b| {
                    m.nu[..m.count(m.p - order(b))]
                        .iter()
                        .map(|&n| d.index([n[0] + b[0], n[1] + b[1], n[2] + b[2]]) as u32)
                        .collect()
                })
                .collect();
        let relations = |ix: &Indices, highest_first: bool| {
            let mut at: Vec<usize> = (0..ix.len()).filter(|&k| ix.nu[k][0] >= 4).collect();
            at.sort_by_key(|&k| ix.nu[k][0]);
            if highest_first {
                at.reverse();
            }
            at.into_iter()
                .map(|k| {
                    let partners = biharmonic_partners(ix.nu[k]).map(|(n, c)| (ix.index(n), c));
                    (k, partners)
                })
                .collect::<Vec<_>>()
        };
        Biharmonic {
            pairs,
            fold: relations(full, true),
            gather: m.nu.iter().map(|&n| full.index(n)).collect(),
            unfold: relations(local, false),
            scatter: l.nu.iter().map(|&n| local.index(n)).collect(),
            m,
            d,
            l,
        }
    }

    /// One channel of a multipole in the full basis (`full`, folded in place: the
    /// orders it holds, a prefix of the graded order) in the reduced basis (`out`: the
    /// orders it holds).
    pub fn reduce(&self, full: &mut [f64], out: &mut [f64]) {
        // a partner has its multi-index's order, so lies in the prefix with it
        let len = full.len();
        for &(k, partners) in self.fold.iter().filter(|f| f.0 < len) {
            let v = full[k];
            if v != 0.0 {
                for (j, c) in partners {
                    full[j] += c * v;
                }
            }
        }
        for (o, &k) in out.iter_mut().zip(&self.gather) {
            *o = full[k];
        }
    }

    /// One channel of a local expansion's coefficients in the reduced basis (`reduced`)
    /// in the full basis (`out`: every coefficient).
    pub fn expand(&self, reduced: &[f64], out: &mut [f64]) {
        for (&k, &v) in self.scatter.iter().zip(reduced) {
            out[k] = v;
        }
        for &(k, partners) in &self.unfold {
            out[k] = partners.iter().map(|&(j, c)| c * out[j]).sum();
        }
    }
}

/// `L_beta += sum_nu M_nu D_{nu + beta}` over `|nu| + |beta| <= top` in the reduced
/// bases ([`Biharmonic`]; without the `1/beta!` of the local expansion, which the caller
/// applies once) for the three channels of `m` (each `bh.m.len()` long, one after the
/// other) and of `l` (each `bh.l.len()`), which share `D` (`bh.d`); one multipole per
/// lane. For each `beta` the `nu` with `|nu| <= top - |beta|` are a prefix of the graded
/// order, so each sum is a dot product of that prefix of `M` with `D` gathered at `nu +
/// beta`: the same indices in every lane.
#[inline(always)]
pub(crate) fn multipole_to_local<L: Lane<Elem = f64>>(
    bh: &Biharmonic,
    top: usize,
    m: &[L],
    d: &[L],
    l: &mut [L],
) {
    let (len, llen) = (bh.m.len(), bh.l.len());
    debug_assert!(top <= bh.m.p && l.len() == 3 * llen);
    let (m0, rest) = m.split_at(len);
    let (m1, m2) = rest.split_at(len);
    let betas = bh.l.count(top.min(bh.l.p));
    let zero = L::splat(0.0);
    // four `beta` of one order at a time share each load of `M` (their prefixes are as
    // long): twelve independent sums, and a quarter of the multipoles' traffic
    let mut beta = 0;
    while beta < betas {
        let order = bh.l.order(beta);
        let end = betas.min(bh.l.count(order));
        let n = bh.m.count(top - order);
        while beta + 4 <= end {
            let p: [&[u32]; 4] = std::array::from_fn(|u| &bh.pairs[beta + u][..n]);
            let mut acc = [[zero; 3]; 4];
            for k in 0..n {
                let (a, b, c) = (m0[k], m1[k], m2[k]);
                for u in 0..4 {
                    let dv = d[p[u][k] as usize];
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
            let pairs = &bh.pairs[beta][..n];
            // four partial sums per channel, so that the fused multiply-adds do not
            // wait on each other
            let mut acc = [[zero; 3]; 4];
            let whole = n / 4 * 4;
            for (k, quad) in pairs[..whole].chunks_exact(4).enumerate() {
                for (u, &sum) in quad.iter().enumerate() {
                    let (k, dv) = (4 * k + u, d[sum as usize]);
                    acc[u][0] = m0[k].mul_add(dv, acc[u][0]);
                    acc[u][1] = m1[k].mul_add(dv, acc[u][1]);
                    acc[u][2] = m2[k].mul_add(dv, acc[u][2]);
                }
            }
            for (k, &sum) in pairs.iter().enumerate().skip(whole) {
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
/// `C(gamma, beta) v^mu = gamma!/beta! (v^mu/mu!)`. Only the `mu` whose monomial is not
/// zero take part ([`translate_multipole`]).
pub(crate) fn translate_local(ix: &Indices, l: &[f64], mono: &[f64], out: &mut [f64]) {
    let shifts = nonzero(ix, ix.p, mono);
    for (beta, pairs) in ix.shift.iter().enumerate() {
        let rest = ix.p - ix.order(beta);
        let mut acc = 0.0;
        for &(mu, _, w) in shifts.iter().take_while(|s| s.1 <= rest) {
            let gamma = pairs[mu].1 as usize;
            acc += l[gamma] * w * ix.factorial[gamma];
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
