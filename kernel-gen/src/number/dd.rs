//! Double-double arithmetic: an unevaluated sum `hi + lo` of two `f64` carrying about
//! 106 bits (~32 decimal digits).
//!
//! This is the reference scalar of the verification ladder: the expression graph is
//! interpreted in `Dd`, and finite differences of the Green's functions are taken in
//! `Dd`, so that the f64 kernels can be measured against something far more precise.
//! Algorithms: Dekker's and Knuth's error-free transformations (two-sum, two-product by
//! fused multiply-add), as in Hida, Li & Bailey's QD library.

use crate::number::scalar::Scalar;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A double-double number `hi + lo`, `|lo| <= ulp(hi) / 2`.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd, Default)]
pub struct Dd {
    /// Leading part.
    pub hi: f64,
    /// Trailing part.
    pub lo: f64,
}

/// Error-free sum: `a + b = s + e` exactly (Knuth).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Error-free sum when `|a| >= |b|` (Dekker).
#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// Error-free product: `a * b = p + e` exactly (fused multiply-add).
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl Dd {
    /// The exact value of an `f64`.
    pub const fn new(x: f64) -> Self {
        Dd { hi: x, lo: 0.0 }
    }

    /// Parse a decimal string to full double-double precision (for constants such as
    /// pi that must be exact beyond f64).
    pub fn from_decimal(s: &str) -> Self {
        let s = s.trim();
        let (neg, s) = match s.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, s),
        };
        let mut v = Dd::new(0.0);
        let mut scale = Dd::new(1.0);
        let mut after_point = false;
        for ch in s.chars() {
            if ch == '.' {
                after_point = true;
                continue;
            }
            let d = ch
                .to_digit(10)
                .expect("from_decimal: digits and one '.' only") as f64;
            if after_point {
                scale = scale / Dd::new(10.0);
                v = v + scale * Dd::new(d);
            } else {
                v = v * Dd::new(10.0) + Dd::new(d);
            }
        }
        if neg {
            -v
        } else {
            v
        }
    }

    /// pi to double-double precision.
    pub fn pi() -> Self {
        Dd {
            hi: std::f64::consts::PI,
            lo: 1.224_646_799_147_353_2e-16,
        }
    }

    /// Rounded to the nearest `f64`.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// Absolute value.
    pub fn abs(self) -> Self {
        if self.hi < 0.0 {
            -self
        } else {
            self
        }
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Self {
        Dd::new(x)
    }
}

impl Add for Dd {
    type Output = Dd;
    /// Accurate (IEEE-style) double-double addition.
    fn add(self, b: Dd) -> Dd {
        let (s1, s2) = two_sum(self.hi, b.hi);
        let (t1, t2) = two_sum(self.lo, b.lo);
        let s2 = s2 + t1;
        let (s1, s2) = quick_two_sum(s1, s2);
        let s2 = s2 + t2;
        let (hi, lo) = quick_two_sum(s1, s2);
        Dd { hi, lo }
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, b: Dd) -> Dd {
        self + (-b)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, b: Dd) -> Dd {
        let (p1, p2) = two_prod(self.hi, b.hi);
        let p2 = p2 + (self.hi * b.lo + self.lo * b.hi);
        let (hi, lo) = quick_two_sum(p1, p2);
        Dd { hi, lo }
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Long division: three quotient digits.
    fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self - b * Dd::new(q1);
        let q2 = r.hi / b.hi;
        let r = r - b * Dd::new(q2);
        let q3 = r.hi / b.hi;
        let (q1, q2) = quick_two_sum(q1, q2);
        Dd { hi: q1, lo: q2 } + Dd::new(q3)
    }
}

impl Scalar for Dd {
    fn cst(c: f64) -> Self {
        Dd::new(c)
    }
    fn from_dd(d: Dd) -> Self {
        d
    }
    fn ratio(n: f64, d: f64) -> Self {
        Dd::new(n) / Dd::new(d)
    }
    /// One Newton step from the f64 root: `x + (a - x^2) / (2x)`.
    fn sqrt(&self) -> Self {
        if self.hi <= 0.0 {
            return Dd::new(self.hi.sqrt());
        }
        let x = Dd::new(self.hi.sqrt());
        x + (*self - x * x) / (Dd::new(2.0) * x)
    }
    /// Binary powering; negative powers through one final division.
    fn powi(&self, n: i32) -> Self {
        let mut base = *self;
        let mut e = n.unsigned_abs();
        let mut acc = Dd::new(1.0);
        while e > 0 {
            if e & 1 == 1 {
                acc = acc * base;
            }
            base = base * base;
            e >>= 1;
        }
        if n < 0 {
            Dd::new(1.0) / acc
        } else {
            acc
        }
    }
    fn to_f64(&self) -> f64 {
        self.hi + self.lo
    }
    fn is_known_zero(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: Dd, b: Dd) -> f64 {
        ((a - b).to_f64() / b.to_f64()).abs()
    }

    #[test]
    fn third_times_three_is_one_beyond_f64() {
        let third = Dd::new(1.0) / Dd::new(3.0);
        let back = third * Dd::new(3.0);
        // Double-double carries ~106 bits: the residual is below 1e-31.
        assert!((back - Dd::new(1.0)).to_f64().abs() < 1e-31);
        // f64 alone would leave the low part: check it is really carried.
        assert!(third.lo != 0.0);
    }

    #[test]
    fn sqrt_two_squared() {
        let s = Dd::new(2.0).sqrt();
        assert!(rel(s * s, Dd::new(2.0)) < 1e-31);
        // Known digits of sqrt(2): 1.41421356237309504880168872420969807856967
        let known = Dd::from_decimal("1.41421356237309504880168872420969807856967");
        assert!(rel(s, known) < 1e-31);
    }

    #[test]
    fn pi_matches_decimal() {
        let known = Dd::from_decimal("3.14159265358979323846264338327950288419716939937510");
        assert!(rel(Dd::pi(), known) < 1e-31);
    }

    #[test]
    fn powi_and_negative_powers() {
        let x = Dd::from_decimal("1.1");
        let p = x.powi(7);
        let known = Dd::from_decimal("1.9487171"); // 1.1^7 exactly
        assert!(rel(p, known) < 1e-31);
        assert!(rel(x.powi(-3) * x.powi(3), Dd::new(1.0)) < 1e-31);
    }

    #[test]
    fn catastrophic_cancellation_is_resolved() {
        // (1 + 1e-20) - 1 is zero in f64 but exact here.
        let a = Dd::new(1.0) + Dd::new(1e-20);
        assert_eq!((a - Dd::new(1.0)).to_f64(), 1e-20);
    }
}
