//! The atoms of the structured path: every derivative of the Stokeslet is a
//! combination of derivatives of the scalar potentials `r` and `1/r`,
//! `J_ab = (delta_ab lap - d_a d_b) r`, reduced to `nu_3 <= 1` by
//! `d_3^2 = lap - d_1^2 - d_2^2`.

use std::collections::BTreeMap;

pub(super) fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

pub(super) fn binomial(n: usize, k: usize) -> f64 {
    factorial(n) / (factorial(k) * factorial(n - k))
}

/// The scalar potential a Stokeslet derivative reduces to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Potential {
    /// `r` (biharmonic: `J_ab = (delta_ab lap - d_a d_b) r`).
    R,
    /// `1/r` (harmonic; `lap r = 2/r`).
    InvR,
}

/// `d^nu phi` of a potential at one expansion centre, with `nu_3 <= 1` after reduction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Atom {
    /// 0: the free-space separation `r = x - y`; `1 + t`: `R` of mirror plane `t`;
    /// `1 + n + t` (`n` planes): the difference `phi(R) - phi(r)` for plane `t`.
    pub centre: usize,
    /// Which potential.
    pub pot: Potential,
    /// Derivative multi-index.
    pub nu: [u8; 3],
}

/// `d^nu phi` as a combination of derivatives with `nu_3 <= 1`, by
/// `d_3^2 = lap - d_1^2 - d_2^2`, `lap r = 2/r`, `lap (1/r) = 0` (away from `r = 0`).
fn reduce(pot: Potential, nu: [u8; 3], coef: f64, out: &mut BTreeMap<(Potential, [u8; 3]), f64>) {
    if nu[2] < 2 {
        *out.entry((pot, nu)).or_insert(0.0) += coef;
        return;
    }
    let base = [nu[0], nu[1], nu[2] - 2];
    if pot == Potential::R {
        reduce(Potential::InvR, base, 2.0 * coef, out);
    }
    reduce(pot, [base[0] + 2, base[1], base[2]], -coef, out);
    reduce(pot, [base[0], base[1] + 2, base[2]], -coef, out);
}

/// `d^mu J_ab = delta_ab d^mu lap r - d^(mu + e_a + e_b) r`, reduced.
pub(super) fn stokeslet_atoms(
    a: usize,
    b: usize,
    mu: [u8; 3],
    coef: f64,
) -> BTreeMap<(Potential, [u8; 3]), f64> {
    let mut out = BTreeMap::new();
    if a == b {
        reduce(Potential::InvR, mu, 2.0 * coef, &mut out);
    }
    let mut nu = mu;
    nu[a] += 1;
    nu[b] += 1;
    reduce(Potential::R, nu, -coef, &mut out);
    out.retain(|_, c| *c != 0.0);
    out
}

/// The non-atom factor of a group of atoms: `weight * h_plane^q`, or 1 for free space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(super) enum Factor {
    Free,
    Image { plane: usize, weight: usize, q: u8 },
}
