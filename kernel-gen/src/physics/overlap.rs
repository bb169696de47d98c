//! The Rotne-Prager-Yamakawa forms of two spheres in free space, far apart and
//! overlapping: the F and FT blocks `M^{ab}` whose difference, overlapping minus far, is
//! the correction kernel `overlap_f` / `overlap_ft` of the `kernels` crate.
//!
//! The RPY tensor of spheres `a`, `b` is the double surface average of the Stokeslet
//! over the two spheres (translation), and the same with the angular velocity taken as
//! `Omega_a = 3 / (8 pi a_a^3) oint_{S_a} n x u dS` and a torque spread over `S_b` as
//! the surface density `3 / (8 pi a_b^3) L x n` (rotation). Far apart it is the
//! Faxén-corrected Stokeslet, exactly our free-space pair kernel (Eqs. 12-16 with
//! `G = J`); overlapping it keeps the mobility symmetric positive definite, which the far
//! form, evaluated at `r < a_a + a_b`, does not.
//!
//! In units of `1 / (8 pi eta)`, with `r = x_a - x_b`, `r = |r|`, `rr = r r^T / r^2`,
//! `[v]_x` the matrix of `w -> v x w`, and `s = a_a + a_b`, `d = a_a - a_b`:
//!
//! ```text
//! M_UF = f1 I + f2 rr,   M_UL = -k_UL [r/r]_x,   M_OmegaF = -k_OmegaF [r/r]_x,
//! M_OmegaL = g1 I + g2 rr.
//! far (r >= s):   f1 = 1/r + (a_a^2 + a_b^2)/(3 r^3),  f2 = 1/r - (a_a^2 + a_b^2)/r^3,
//!                 k_UL = k_OmegaF = 1/r^2,  g1 = -1/(2 r^3),  g2 = 3/(2 r^3);
//! overlapping (|d| < r < s):
//!   f1 = 4/(3 a_a a_b) (16 r^3 s - (d^2 + 3 r^2)^2) / (32 r^3),
//!   f2 = 4/(3 a_a a_b) 3 (d^2 - r^2)^2 / (32 r^3),
//!   g1 = (5 r^6 - 27 r^4 (a_a^2 + a_b^2) + 32 r^3 (a_a^3 + a_b^3) - 9 r^2 (a_a^2 - a_b^2)^2
//!         - d^4 (a_a^2 + 4 a_a a_b + a_b^2)) / (64 r^3 a_a^3 a_b^3),
//!   g2 = 3 (d^2 - r^2)^2 (a_a^2 + 4 a_a a_b + a_b^2 - r^2) / (64 r^3 a_a^3 a_b^3),
//!   k_OmegaF = c(a_a, a_b),  k_UL = c(a_b, a_a),
//!   c(p, q) = (p - q + r)^2 (q^2 + 2 q (p + r) - 3 (p - r)^2) / (16 r^2 p^3 q);
//! nested (r <= |d|, the smaller sphere inside the larger, of radius a_max):
//!   f1 = 4/(3 a_max),  f2 = 0,  g1 = 1/a_max^3,  g2 = 0,
//!   k_OmegaF = r/a_a^3 if a_a > a_b else 0,  k_UL = r/a_b^3 if a_b > a_a else 0.
//! ```
//!
//! The translational forms are those of Zuk, Wajnryb, Mizerski and Szymczak, J. Fluid
//! Mech. 741, R5 (2014) (the generalisation of Rotne and Prager to unequal and
//! overlapping spheres); the rotational and coupling forms those of the same
//! generalisation by Wajnryb, Mizerski, Zuk and Szymczak (J. Fluid Mech., 2013), whose
//! printed form was not at hand: the quadrature of the definition below is their
//! reference here. At equal radii they are
//! the forms of libMobility's NBody solver (units of `a`: `M_UF = [(1 - 9r/32) I +
//! (3r/32) rr] / (6 pi eta a)`, `M_OmegaL = [(1 - 27r/32 + 5r^3/64) I + (9r/32 -
//! 3r^3/64) rr] / (8 pi eta a^3)`, coupling `(1/2)(1 - 3r/8)` times the cross product
//! with `r`, over `8 pi eta a^2`). The nested couplings are not zero: inside the larger
//! sphere the field of its torque is a rigid rotation, which carries the smaller sphere
//! along at `L x r / (8 pi eta a_max^3)`; the forms above are continuous at `r = |d|`
//! and at `r = s` (the far forms), which is what makes the correction vanish at contact.
//! The integration tests check every block against a quadrature of the definition
//! (the surface average over `S_a` of the closed-form field of `b`'s surface forces:
//! Faxén-corrected Stokeslet outside, uniform translation inside; rotlet outside, rigid
//! rotation inside).
//!
//! The branches are selected by the caller (a traced kernel selects with the graph's
//! comparisons; a reference compares numbers): every function here is straight-line
//! arithmetic over any [`Scalar`].

use crate::number::scalar::Scalar;

/// The F and FT blocks of one pair, in units of `1 / (8 pi eta)`, row-major
/// `[response][moment]`.
#[derive(Clone, Debug)]
pub struct Blocks<S> {
    /// Velocity of `a` from the force on `b`.
    pub uf: [[S; 3]; 3],
    /// Velocity of `a` from the torque on `b`.
    pub ul: [[S; 3]; 3],
    /// Angular velocity of `a` from the force on `b`.
    pub of: [[S; 3]; 3],
    /// Angular velocity of `a` from the torque on `b`.
    pub ol: [[S; 3]; 3],
}

/// The scalar coefficients of [`Blocks`] (module docs): `f1 I + f2 rr`,
/// `-k_ul [r/r]_x`, `-k_of [r/r]_x`, `g1 I + g2 rr`.
#[derive(Clone, Debug)]
pub struct Coefficients<S> {
    /// `M_UF` along `I`.
    pub f1: S,
    /// `M_UF` along `rr`.
    pub f2: S,
    /// `M_UL = -k_ul [r/r]_x`.
    pub k_ul: S,
    /// `M_OmegaF = -k_of [r/r]_x`.
    pub k_of: S,
    /// `M_OmegaL` along `I`.
    pub g1: S,
    /// `M_OmegaL` along `rr`.
    pub g2: S,
}

impl<S: Scalar> Coefficients<S> {
    /// The blocks of these coefficients for `r = x_a - x_b` of length `len`.
    pub fn blocks(&self, r: &[S; 3], len: &S) -> Blocks<S> {
        let u: [S; 3] = std::array::from_fn(|i| r[i].clone() / len.clone());
        let iso = |c1: &S, c2: &S| -> [[S; 3]; 3] {
            std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    let aniso = c2.clone() * u[i].clone() * u[j].clone();
                    if i == j {
                        c1.clone() + aniso
                    } else {
                        aniso
                    }
                })
            })
        };
        // -k [u]_x: entry (i, k) is -k eps_ijk u_j
        let cross = |k: &S| -> [[S; 3]; 3] {
            std::array::from_fn(|i| {
                std::array::from_fn(|m| {
                    if i == m {
                        return S::cst(0.0);
                    }
                    let j = 3 - i - m;
                    // eps_ijm = +1 for (i, j, m) a cyclic turn of (0, 1, 2)
                    let sign = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
                    S::cst(-sign) * k.clone() * u[j].clone()
                })
            })
        };
        Blocks {
            uf: iso(&self.f1, &self.f2),
            ul: cross(&self.k_ul),
            of: cross(&self.k_of),
            ol: iso(&self.g1, &self.g2),
        }
    }
}

/// The far RPY form (`r >= a_a + a_b`): the free-space pair kernel's blocks.
pub fn far<S: Scalar>(r: &S, aa: &S, ab: &S) -> Coefficients<S> {
    let q = aa.clone() * aa.clone() + ab.clone() * ab.clone();
    let inv = r.recip();
    let inv2 = inv.clone() * inv.clone();
    let inv3 = inv2.clone() * inv.clone();
    Coefficients {
        f1: inv.clone() + q.clone() * inv3.clone() * S::ratio(1.0, 3.0),
        f2: inv - q * inv3.clone(),
        k_ul: inv2.clone(),
        k_of: inv2,
        g1: inv3.clone() * S::cst(-0.5),
        g2: inv3 * S::cst(1.5),
    }
}

/// `c(p, q)` of the module docs: the coupling `k_OmegaF` of overlapping spheres, `p`
/// the radius of the sphere that turns, `q` that of the sphere the force acts on.
fn coupling<S: Scalar>(r: &S, p: &S, q: &S) -> S {
    let t = p.clone() - q.clone() + r.clone();
    let u = p.clone() - r.clone();
    let bracket = q.clone() * q.clone() + S::cst(2.0) * q.clone() * (p.clone() + r.clone())
        - S::cst(3.0) * u.clone() * u;
    t.clone() * t * bracket / (S::cst(16.0) * r.clone() * r.clone() * p.powi(3) * q.clone())
}

/// The overlapping RPY form (`|a_a - a_b| < r < a_a + a_b`).
pub fn overlapping<S: Scalar>(r: &S, aa: &S, ab: &S) -> Coefficients<S> {
    let (r2, s, d) = (
        r.clone() * r.clone(),
        aa.clone() + ab.clone(),
        aa.clone() - ab.clone(),
    );
    let (d2, r3, ab_) = (
        d.clone() * d.clone(),
        r2.clone() * r.clone(),
        aa.clone() * ab.clone(),
    );
    let w = d2.clone() + S::cst(3.0) * r2.clone();
    let e = d2.clone() - r2.clone();
    let uf = S::cst(4.0) / (S::cst(3.0) * ab_.clone() * S::cst(32.0) * r3.clone());
    let (aa2, ab2) = (aa.clone() * aa.clone(), ab.clone() * ab.clone());
    let mixed = aa2.clone() + S::cst(4.0) * ab_.clone() + ab2.clone();
    let diff = aa2.clone() - ab2.clone();
    let a = S::cst(5.0) * r3.clone() * r3.clone()
        - S::cst(27.0) * r2.clone() * r2.clone() * (aa2.clone() + ab2.clone())
        + S::cst(32.0) * r3.clone() * (aa2 * aa.clone() + ab2 * ab.clone())
        - S::cst(9.0) * r2.clone() * diff.clone() * diff
        - d2.clone() * d2 * mixed.clone();
    let b = S::cst(3.0) * e.clone() * e.clone() * (mixed - r2);
    let ol = (S::cst(64.0) * r3.clone() * ab_.powi(3)).recip();
    Coefficients {
        f1: (S::cst(16.0) * r3 * s - w.clone() * w) * uf.clone(),
        f2: S::cst(3.0) * e.clone() * e * uf,
        k_ul: coupling(r, ab, aa),
        k_of: coupling(r, aa, ab),
        g1: a * ol.clone(),
        g2: b * ol,
    }
}

/// The nested RPY form (`r <= |a_a - a_b|`), the smaller sphere inside the larger of
/// radius `amax`; `a_larger`: whether that is `a`.
pub fn nested<S: Scalar>(r: &S, amax: &S, a_larger: bool) -> Coefficients<S> {
    let inv3 = amax.powi(3).recip();
    let carried = r.clone() * inv3.clone();
    let (k_ul, k_of) = if a_larger {
        (S::cst(0.0), carried)
    } else {
        (carried, S::cst(0.0))
    };
    Coefficients {
        f1: S::ratio(4.0, 3.0) / amax.clone(),
        f2: S::cst(0.0),
        k_ul,
        k_of,
        g1: inv3,
        g2: S::cst(0.0),
    }
}
