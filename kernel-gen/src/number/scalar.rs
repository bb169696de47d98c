//! The number trait every evaluator shares.
//!
//! A Green's function is written once, generic over [`Scalar`], and is then run on
//! plain `f64` (spot values), on double-double [`crate::number::dd::Dd`] (references), on
//! expression nodes [`crate::graph::Ex`] (tracing, for emission) and on Taylor jets
//! [`crate::number::jet::Jet`] of any of these (derivatives).

use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Arithmetic that the Green's functions, the jets and the operators need.
///
/// Operations take values by reference-free clone semantics: implementors are cheap
/// to clone (`f64`, `Dd`, `Ex` are `Copy`; a jet clones a coefficient vector).
pub trait Scalar:
    Clone
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The constant `c` (exact for every `f64`).
    fn cst(c: f64) -> Self;
    /// The rational constant `n / d` of small integers (or dyadic numbers): rounded
    /// to `f64` once (what emitted code holds), or exact in a scalar that carries more
    /// precision (double-double), so that identities between such weights (the jet
    /// rules' `(alpha i - j) / m`) hold in the references.
    fn ratio(n: f64, d: f64) -> Self {
        Self::cst(n / d)
    }
    /// A double-double constant: rounded to `f64` once, or kept exactly by a scalar
    /// that carries more precision.
    fn from_dd(d: crate::number::dd::Dd) -> Self {
        Self::cst(d.to_f64())
    }
    /// Square root.
    fn sqrt(&self) -> Self;
    /// Integer power.
    fn powi(&self, n: i32) -> Self;
    /// `e^self`. Traced ([`crate::graph::Ex`]), for a non-positive argument only: the
    /// lowering into arithmetic serves Gaussians `e^{-t}`, `t >= 0`.
    fn exp(&self) -> Self;
    /// The complementary error function `erfc(self) = (2/sqrt(pi)) int_self^inf e^{-t^2} dt`.
    fn erfc(&self) -> Self;
    /// `1 / self`.
    fn recip(&self) -> Self {
        Self::cst(1.0) / self.clone()
    }
    /// The leading `f64` part, for diagnostics and for choosing branches that do not
    /// change the value (never for control flow that changes the result).
    fn to_f64(&self) -> f64;
    /// True when the value is known to be exactly zero without evaluating anything
    /// (a folded constant); lets jets skip structural zeros.
    fn is_known_zero(&self) -> bool {
        false
    }
}

impl Scalar for f64 {
    fn cst(c: f64) -> Self {
        c
    }
    fn sqrt(&self) -> Self {
        f64::sqrt(*self)
    }
    fn powi(&self, n: i32) -> Self {
        f64::powi(*self, n)
    }
    fn exp(&self) -> Self {
        f64::exp(*self)
    }
    /// `erfc` is not in `std`: the double-double value, rounded (spot values only).
    fn erfc(&self) -> Self {
        crate::number::dd::Dd::new(*self).erfc().to_f64()
    }
    fn recip(&self) -> Self {
        1.0 / *self
    }
    fn to_f64(&self) -> f64 {
        *self
    }
}
