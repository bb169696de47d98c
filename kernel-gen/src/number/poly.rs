//! Sparse polynomials in the components `(e1, e2, e3)` of a unit vector (and up to
//! [`VARS`] variables in all: a block entry collected whole also carries the
//! dimensionless `h/|R|`, `a_a^2/|R|^2`, `a_b^2/|R|^2`), with double-double
//! coefficients: the derivatives of the potentials in closed form, and their evaluation
//! by multivariate Horner.
//!
//! Every derivative of a potential `|R|^p` about the unit vector `e = R/|R|` is
//! `|R|^(p - n)` times a universal polynomial in `e` (the jets of
//! [`crate::physics::derivatives::Structured`] compute exactly these polynomials, one
//! coefficient at a time). [`Poly`] is a [`Scalar`], so the same jet rules run on it
//! once per potential and degree, at generation time, and return the polynomials
//! themselves with coefficients exact to about 1e-32. A block entry is a linear
//! combination of such derivatives per expansion centre and power of `|R|`; collected
//! as one polynomial and evaluated by Horner's rule ([`Poly::eval`]), it costs about one
//! multiply-add per monomial, where the jet recurrences cost several operations per
//! coefficient of every order. Components known to be zero (the second lateral one in
//! the canonical frame, [`crate::physics::frame`]) drop their monomials before any node is built.

use crate::number::dd::Dd;
use crate::number::scalar::Scalar;
use std::collections::BTreeMap;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Number of variables of a [`Poly`]: the unit vector's three components first.
pub const VARS: usize = 6;

/// A monomial's exponents.
pub type Monomial = [u8; VARS];

/// A polynomial `sum c_m v^m` in [`VARS`] variables; no zero coefficients are stored.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Poly(pub BTreeMap<Monomial, Dd>);

fn is_zero(d: &Dd) -> bool {
    d.hi == 0.0 && d.lo == 0.0
}

impl Poly {
    /// The variable `e_k`.
    pub fn var(k: usize) -> Poly {
        let mut m = [0u8; VARS];
        m[k] = 1;
        Poly(BTreeMap::from([(m, Dd::new(1.0))]))
    }

    /// The constant `c`.
    pub fn constant(c: Dd) -> Poly {
        let mut p = Poly::default();
        p.add_term([0; VARS], c);
        p
    }

    fn add_term(&mut self, m: Monomial, c: Dd) {
        if is_zero(&c) {
            return;
        }
        let e = self.0.entry(m).or_insert(Dd::new(0.0));
        *e = *e + c;
        if is_zero(e) {
            self.0.remove(&m);
        }
    }

    /// `self + c q`.
    pub fn add_scaled(&mut self, q: &Poly, c: Dd) {
        for (m, v) in &q.0 {
            self.add_term(*m, c * *v);
        }
    }

    /// `self + c v^shift q`: `q` times a monomial.
    pub fn add_shifted(&mut self, q: &Poly, c: Dd, shift: Monomial) {
        for (m, v) in &q.0 {
            self.add_term(std::array::from_fn(|k| m[k] + shift[k]), c * *v);
        }
    }

    /// Whether there are no monomials.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The constant term, if the polynomial is a constant.
    fn as_constant(&self) -> Option<Dd> {
        match self.0.len() {
            0 => Some(Dd::new(0.0)),
            1 => self.0.get(&[0; VARS]).copied(),
            _ => None,
        }
    }

    /// The value at `e` by multivariate Horner: the variable of highest degree
    /// outermost (by steps of the gcd of its exponents, so an even polynomial is
    /// evaluated in `e_k^2`), its coefficients recursively; monomials of components
    /// known to be zero are dropped first. Coefficients enter rounded once
    /// ([`Scalar::from_dd`]).
    pub fn eval<S: Scalar>(&self, e: &[S; 3]) -> S {
        let z = || S::cst(0.0);
        self.eval_all(&[e[0].clone(), e[1].clone(), e[2].clone(), z(), z(), z()])
    }

    /// The cheapest of the forms this polynomial takes on the unit sphere
    /// `e1^2 + e2^2 + e3^2 = 1`: as it is, or with every even power of one component
    /// `e_k` rewritten by `e_k^2 = 1 - (the other components' squares)` (components in
    /// `zero`, known to be zero, left out), whichever has the fewest monomials that
    /// survive the known zeros (about one multiply-add each in Horner's rule). A
    /// rewritten form is taken only if the sum of its coefficients' absolute values,
    /// which bounds its rounding error on the sphere, is at most twice the original's.
    /// Valid only where `e` is a unit vector.
    pub fn on_unit_sphere(&self, zero: [bool; 3]) -> Poly {
        let kept = |m: &Monomial| (0..3).all(|k| m[k] == 0 || !zero[k]);
        let size = |p: &Poly| p.0.keys().filter(|m| kept(m)).count();
        let norm = |p: &Poly| p.0.values().fold(0.0, |s, c| s + c.to_f64().abs());
        let bound = 2.0 * norm(self);
        let mut best = (size(self), self.clone());
        for k in (0..3).filter(|&k| !zero[k]) {
            let mut rest = Poly::cst(1.0);
            for j in (0..3).filter(|&j| j != k && !zero[j]) {
                rest = rest - Poly::var(j) * Poly::var(j);
            }
            let mut reduced = Poly::default();
            for (m, c) in self.0.iter().filter(|(m, _)| kept(m)) {
                let mut low = *m;
                low[k] = m[k] % 2;
                reduced.add_shifted(&rest.powi(i32::from(m[k] / 2)), *c, low);
            }
            let n = size(&reduced);
            if n < best.0 && norm(&reduced) <= bound {
                best = (n, reduced);
            }
        }
        best.1
    }

    /// The value at all [`VARS`] variables `v`, as [`Poly::eval`].
    pub fn eval_all<S: Scalar>(&self, v: &[S; VARS]) -> S {
        let terms: Vec<(Monomial, Dd)> = self
            .0
            .iter()
            .filter(|(m, _)| (0..VARS).all(|k| m[k] == 0 || !v[k].is_known_zero()))
            .map(|(m, c)| (*m, *c))
            .collect();
        horner(&terms, v).unwrap_or_else(|| S::cst(0.0))
    }
}

fn gcd(a: u8, b: u8) -> u8 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// The coefficient polynomials of `x = v_k^step` in `terms`, from `x^0` up, with the
/// step (the gcd of the exponents of `v_k`, so an even polynomial goes by `v_k^2`).
fn split(terms: &[(Monomial, Dd)], k: usize) -> (u8, Vec<Vec<(Monomial, Dd)>>) {
    let deg = terms.iter().map(|(m, _)| m[k]).max().unwrap_or(0);
    let step = terms.iter().fold(0u8, |g, (m, _)| gcd(g, m[k]));
    let top = (deg / step) as usize;
    let mut by_power: Vec<Vec<(Monomial, Dd)>> = vec![Vec::new(); top + 1];
    for (m, c) in terms {
        let mut rest = *m;
        rest[k] = 0;
        by_power[(m[k] / step) as usize].push((rest, *c));
    }
    (step, by_power)
}

/// The variable of highest degree (the lowest index among equals), `None` for a
/// constant.
fn highest(terms: &[(Monomial, Dd)]) -> Option<usize> {
    let (k, deg) = (0..VARS)
        .map(|k| (k, terms.iter().map(|(m, _)| m[k]).max().unwrap_or(0)))
        .max_by_key(|&(k, d)| (d, std::cmp::Reverse(k)))?;
    (deg > 0).then_some(k)
}

/// Horner's rule over `terms` (`None` for no terms), the variable of highest degree
/// outermost at each level. (Choosing at each level the variable whose scheme costs
/// least, one level ahead, made single polynomials cheaper but kernels dearer: entries
/// evaluated in a common order share more subexpressions; measured wall F product
/// 333 -> 334 operations, slit 384 -> 420.)
fn horner<S: Scalar>(terms: &[(Monomial, Dd)], e: &[S; VARS]) -> Option<S> {
    horner_pending(terms, e).map(Pending::value)
}

/// A value `c v` whose constant factor `c` has not been multiplied in yet (`v = None`:
/// the constant alone), so that a coefficient that is a single monomial times a constant
/// meets the powers of the outer variables first: `c (m x)`, whose `m x` other entries
/// share, rather than `(c m) x`.
struct Pending<S> {
    c: Dd,
    v: Option<S>,
}

impl<S: Scalar> Pending<S> {
    fn value(self) -> S {
        match self.v {
            None => S::from_dd(self.c),
            Some(v) if self.c.hi == 1.0 && self.c.lo == 0.0 => v,
            Some(v) => S::from_dd(self.c) * v,
        }
    }
}

/// [`horner`] with the constant factor of a single-monomial coefficient kept apart
/// ([`Pending`]) until a sum needs it.
fn horner_pending<S: Scalar>(terms: &[(Monomial, Dd)], e: &[S; VARS]) -> Option<Pending<S>> {
    if terms.is_empty() {
        return None;
    }
    let Some(k) = highest(terms) else {
        let c: Dd = terms.iter().fold(Dd::new(0.0), |acc, (_, c)| acc + *c);
        return Some(Pending { c, v: None });
    };
    let (step, by_power) = split(terms, k);
    let x = e[k].clone().powi(step as i32);
    let mut acc: Option<Pending<S>> = None;
    for q in (0..by_power.len()).rev() {
        if let Some(a) = acc.take() {
            let v = match a.v {
                None => x.clone(),
                Some(v) => v * x.clone(),
            };
            acc = Some(Pending { c: a.c, v: Some(v) });
        }
        if let Some(c) = horner_pending(&by_power[q], e) {
            acc = Some(match acc {
                None => c,
                Some(a) => Pending {
                    c: Dd::new(1.0),
                    v: Some(a.value() + c.value()),
                },
            });
        }
    }
    acc
}

impl Add for Poly {
    type Output = Poly;
    fn add(mut self, b: Poly) -> Poly {
        self.add_scaled(&b, Dd::new(1.0));
        self
    }
}

impl Sub for Poly {
    type Output = Poly;
    fn sub(mut self, b: Poly) -> Poly {
        self.add_scaled(&b, Dd::new(-1.0));
        self
    }
}

impl Neg for Poly {
    type Output = Poly;
    fn neg(self) -> Poly {
        Poly(self.0.into_iter().map(|(m, c)| (m, -c)).collect())
    }
}

impl Mul for Poly {
    type Output = Poly;
    fn mul(self, b: Poly) -> Poly {
        let mut out = Poly::default();
        for (m, c) in &self.0 {
            out.add_shifted(&b, *c, *m);
        }
        out
    }
}

impl Div for Poly {
    type Output = Poly;
    /// Division by a constant only (the jets of the potentials about a unit vector
    /// divide by their constant term, which is 1).
    fn div(self, b: Poly) -> Poly {
        let d = b
            .as_constant()
            .expect("a polynomial divides only by a constant");
        Poly(self.0.into_iter().map(|(m, c)| (m, c / d)).collect())
    }
}

impl Scalar for Poly {
    fn cst(c: f64) -> Self {
        Poly::constant(Dd::new(c))
    }
    fn ratio(n: f64, d: f64) -> Self {
        Poly::constant(Dd::ratio(n, d))
    }
    fn from_dd(d: Dd) -> Self {
        Poly::constant(d)
    }
    fn sqrt(&self) -> Self {
        let c = self
            .as_constant()
            .expect("the square root of a constant polynomial only");
        Poly::constant(c.sqrt())
    }
    fn exp(&self) -> Self {
        let c = self
            .as_constant()
            .expect("the exponential of a constant polynomial only");
        Poly::constant(c.exp())
    }
    fn erfc(&self) -> Self {
        let c = self
            .as_constant()
            .expect("the error function of a constant polynomial only");
        Poly::constant(c.erfc())
    }
    fn powi(&self, n: i32) -> Self {
        assert!(n >= 0, "non-negative powers of a polynomial only");
        let mut acc = Poly::cst(1.0);
        for _ in 0..n {
            acc = acc * self.clone();
        }
        acc
    }
    fn to_f64(&self) -> f64 {
        self.as_constant().map_or(f64::NAN, |c| c.to_f64())
    }
    fn is_known_zero(&self) -> bool {
        self.0.is_empty()
    }
}
