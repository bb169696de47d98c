//! The atoms of the structured path: every derivative of the kernel
//! `J_ab = (delta_ab lap - d_a d_b) phi` is a combination of derivatives of radial
//! potentials, reduced to `nu_3 <= 1` by `d_3^2 = lap - d_1^2 - d_2^2`, the Laplacian of
//! a radial potential being a radial potential again ([`Potential::laplacian`]): for the
//! Stokeslet (`phi = r`) the homogeneous `r` and `1/r` (`lap r = 2/r`, `lap 1/r = 0`); for
//! a declared radial `phi` ([`crate::physics::green::Green::radial`]) its Laplacians
//! `lap^m phi`, each its own potential.

use std::collections::BTreeMap;

pub(super) fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

pub(super) fn binomial(n: usize, k: usize) -> f64 {
    factorial(n) / (factorial(k) * factorial(n - k))
}

/// The scalar potential a kernel derivative reduces to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Potential {
    /// `r` (biharmonic: `J_ab = (delta_ab lap - d_a d_b) r`).
    R,
    /// `1/r` (harmonic; `lap r = 2/r`).
    InvR,
    /// `lap^m phi` of the radial potential `phi` a Green's function declares
    /// ([`crate::physics::green::Green::radial`]): not homogeneous, so its derivatives
    /// about a unit vector carry run-time radial coefficients (`Structured::radial`).
    Radial(u8),
}

impl Potential {
    /// The potential of the kernel `J = (delta lap - d d) phi`: `r`, or the declared
    /// radial `phi`.
    pub(super) fn kernel(radial: bool) -> Potential {
        if radial {
            Potential::Radial(0)
        } else {
            Potential::R
        }
    }

    /// `lap phi` as `coef * potential`, `None` where it is zero (away from `r = 0`).
    fn laplacian(self) -> Option<(Potential, f64)> {
        match self {
            Potential::R => Some((Potential::InvR, 2.0)),
            Potential::InvR => None,
            Potential::Radial(m) => Some((Potential::Radial(m + 1), 1.0)),
        }
    }

    /// The dimension `p` of the potential, a power of length (`|R|^p` for the
    /// homogeneous ones; `phi` has the dimension of `r`).
    pub(super) fn dimension(self) -> i32 {
        match self {
            Potential::R => 1,
            Potential::InvR => -1,
            Potential::Radial(m) => 1 - 2 * i32::from(m),
        }
    }
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
/// `d_3^2 = lap - d_1^2 - d_2^2` ([`Potential::laplacian`]).
fn reduce(pot: Potential, nu: [u8; 3], coef: f64, out: &mut BTreeMap<(Potential, [u8; 3]), f64>) {
    if nu[2] < 2 {
        *out.entry((pot, nu)).or_insert(0.0) += coef;
        return;
    }
    let base = [nu[0], nu[1], nu[2] - 2];
    if let Some((lap, c)) = pot.laplacian() {
        reduce(lap, base, c * coef, out);
    }
    reduce(pot, [base[0] + 2, base[1], base[2]], -coef, out);
    reduce(pot, [base[0], base[1] + 2, base[2]], -coef, out);
}

/// `d^mu J_ab = delta_ab d^mu lap phi - d^(mu + e_a + e_b) phi` of the kernel's
/// potential `phi` ([`Potential::kernel`]), reduced.
pub(super) fn stokeslet_atoms(
    phi: Potential,
    a: usize,
    b: usize,
    mu: [u8; 3],
    coef: f64,
) -> BTreeMap<(Potential, [u8; 3]), f64> {
    let mut out = BTreeMap::new();
    if a == b {
        if let Some((lap, c)) = phi.laplacian() {
            reduce(lap, mu, c * coef, &mut out);
        }
    }
    let mut nu = mu;
    nu[a] += 1;
    nu[b] += 1;
    reduce(phi, nu, -coef, &mut out);
    out.retain(|_, c| *c != 0.0);
    out
}

/// The non-atom factor of a group of atoms: `weight * h_plane^q`, or 1 for free space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(super) enum Factor {
    Free,
    Image { plane: usize, weight: usize, q: u8 },
}
