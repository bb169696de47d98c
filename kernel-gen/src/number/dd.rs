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

    /// `ln 2` to double-double precision.
    pub fn ln2() -> Self {
        Dd {
            hi: std::f64::consts::LN_2,
            lo: 2.319_046_813_846_299_6e-17,
        }
    }

    /// `2 / sqrt(pi)` to double-double precision (the factor of `erf' = (2/sqrt(pi)) e^{-x^2}`).
    pub fn two_over_sqrt_pi() -> Self {
        Dd {
            hi: std::f64::consts::FRAC_2_SQRT_PI,
            lo: 1.533_545_961_316_588e-17,
        }
    }

    /// `x 2^k`, exact (both parts scaled by a power of two; no overflow for the
    /// arguments of [`Dd::exp`]).
    fn times_power_of_two(self, k: i32) -> Self {
        let s = 2f64.powi(k);
        Dd {
            hi: self.hi * s,
            lo: self.lo * s,
        }
    }

    /// `e^x`: `x = k ln 2 + r` with `|r| <= ln 2 / 2`, then `e^r = (e^{r/64})^64`, the
    /// Taylor series of `e^{r/64}` (`|r/64| < 0.0055`: terms below `1e-34` after the
    /// twelfth) and six squarings, each of which doubles the relative error: about
    /// `64 eps_dd`, `1e-30` relative (tested against 32-digit constants). Zero below
    /// `-745` (the `f64` underflow), infinite above `709.8`.
    pub fn exp(self) -> Self {
        if self.hi < -745.2 {
            return Dd::new(0.0);
        }
        if self.hi > 709.8 {
            return Dd::new(f64::INFINITY);
        }
        let k = (self.hi / std::f64::consts::LN_2).round();
        let r = (self - Dd::ln2() * Dd::new(k)).times_power_of_two(-6);
        let mut sum = Dd::new(1.0);
        let mut term = Dd::new(1.0);
        for n in 1..=20 {
            term = term * r / Dd::new(n as f64);
            sum = sum + term;
            if term.hi.abs() < 1e-35 {
                break;
            }
        }
        for _ in 0..6 {
            sum = sum * sum;
        }
        sum.times_power_of_two(k as i32)
    }

    /// The complementary error function `erfc x = (2/sqrt(pi)) int_x^inf e^{-t^2} dt`:
    /// `erfc(-x) = 2 - erfc(x)`; for `0 <= x < 2`, `1 - erf x` with
    /// `erf x = (2/sqrt(pi)) e^{-x^2} sum_n 2^n x^(2n+1) / (1 3 ... (2n+1))` (positive
    /// terms, at most 48 of them; `1 - erf` loses at most `log10(1/erfc(2)) = 2.3`
    /// digits); above, `e^{-x^2}` times [`Dd::erfcx`]'s continued fraction. About
    /// `1e-30` relative (tested against 32-digit constants).
    pub fn erfc(self) -> Self {
        if self.hi < 0.0 {
            return Dd::new(2.0) - (-self).erfc();
        }
        if self.hi < 2.0 {
            return Dd::new(1.0) - self.erf_series();
        }
        (-(self * self)).exp() * self.erfcx()
    }

    /// `erf x` for `0 <= x < 2` by the series of [`Dd::erfc`].
    fn erf_series(self) -> Self {
        let two_x2 = Dd::new(2.0) * self * self;
        let mut term = self;
        let mut sum = self;
        for n in 1..200 {
            term = term * two_x2 / Dd::new((2 * n + 1) as f64);
            sum = sum + term;
            if term.hi < 1e-34 * sum.hi {
                break;
            }
        }
        Dd::two_over_sqrt_pi() * (-(self * self)).exp() * sum
    }

    /// The scaled complementary error function `erfcx x = e^{x^2} erfc x` for `x >= 2`
    /// by Laplace's continued fraction
    /// `sqrt(pi) erfcx x = 1/(x + (1/2)/(x + 1/(x + (3/2)/(x + ...))))`, evaluated by
    /// Lentz's method until a factor is within `1e-33` of 1 (213 terms at `x = 2`,
    /// 40 at `x = 6`); below 2, `e^{x^2} erfc x` (no cancellation beyond
    /// [`Dd::erfc`]'s).
    pub fn erfcx(self) -> Self {
        if self.hi < 2.0 {
            return (self * self).exp() * self.erfc();
        }
        let mut f = self;
        let (mut c, mut d) = (f, Dd::new(0.0));
        for n in 1..2000 {
            let a = Dd::new(n as f64 / 2.0);
            d = Dd::new(1.0) / (self + a * d);
            c = self + a / c;
            let delta = c * d;
            f = f * delta;
            if (delta - Dd::new(1.0)).abs().hi < 1e-33 {
                break;
            }
        }
        Dd::two_over_sqrt_pi() / (Dd::new(2.0) * f)
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
    fn exp(&self) -> Self {
        Dd::exp(*self)
    }
    fn erfc(&self) -> Self {
        Dd::erfc(*self)
    }
    fn to_f64(&self) -> f64 {
        self.hi + self.lo
    }
    fn is_known_zero(&self) -> bool {
        false
    }
}
