//! Truncated multivariate Taylor series (jets), generic over the coefficient type.
//!
//! A [`Jet`] in `n` variables truncated at total degree `D` holds the coefficients
//! `c_m` of `f(x0 + dx) = sum_{|m| <= D} c_m dx^m`, so that the partial derivative
//! `d^m f (x0) = m! c_m` with `m! = prod_v m_v!`. Coefficients may be `f64`,
//! double-double, expression nodes or jets themselves: anything that is a
//! [`Scalar`]. A jet is itself a [`Scalar`], so a Green's function written generic
//! over its scalar is differentiated simply by calling it on jets.
//!
//! Each primitive is one rule, from the Cauchy product `(ab)_m = sum_{i+j=m} a_i b_j`:
//! - product: the Cauchy product;
//! - quotient `c = a/b`: from `b c = a`, `c_m = (a_m - sum_{i != 0} b_i c_{m-i}) / b_0`
//!   (`1/b_0` formed once);
//! - reciprocal: the quotient with `a = 1`;
//! - square root `c^2 = a`: `c_m = (a_m - sum_{i,j != 0} c_i c_j) / (2 c_0)` (`1/(2 c_0)`
//!   formed once);
//! - power `c = a^alpha` (real alpha): from `a d_v c = alpha c d_v a` along a variable
//!   `v` with `m_v > 0`: `c_m = sum_{i != 0} (alpha i_v - (m-i)_v) a_i c_{m-i} / (m_v a_0)`;
//! - integer powers: binary powering by products for `n >= 0`, the power rule below 0;
//! - exponential `c = e^a`: from `d_v c = c d_v a` along a variable `v` with `m_v > 0`:
//!   `c_m = sum_{i != 0} (i_v / m_v) a_i c_{m-i}` (Griewank & Walther, *Evaluating
//!   Derivatives*, 2nd ed., SIAM 2008, Sec. 13.2);
//! - complementary error function `c = erfc(a)`: from `d_v c = -(2/sqrt(pi)) e d_v a`
//!   with the jet `e = exp(-a a)` (a product, then the exponential):
//!   `c_m = -(2/sqrt(pi)) sum_{i != 0} (i_v / m_v) a_i e_{m-i}`.
//!
//! Monomials are stored in graded order (all of degree 0, then 1, ...); the products
//! `(i, j) -> i + j` are tabulated once per `(n, D)` in a [`Layout`] shared by all jets.

use crate::number::scalar::Scalar;
use std::cell::RefCell;
use std::collections::HashMap;
use std::ops::{Add, Div, Mul, Neg, Sub};
use std::rc::Rc;

/// Monomial bookkeeping for `n` variables truncated at total degree `D`.
#[derive(Debug)]
pub struct Layout {
    /// Number of variables.
    pub nvars: usize,
    /// Truncation degree.
    pub degree: usize,
    /// Exponent vectors of the monomials, graded order.
    pub monos: Vec<Vec<u8>>,
    index: HashMap<Vec<u8>, usize>,
    /// For each monomial `m`, the pairs `(i, j)` with `mono(i) + mono(j) = m`.
    pairs: Vec<Vec<(u32, u32)>>,
}

impl Layout {
    fn new(nvars: usize, degree: usize) -> Layout {
        let mut monos: Vec<Vec<u8>> = Vec::new();
        for d in 0..=degree {
            let mut cur = vec![0u8; nvars];
            gen_degree(nvars, d, 0, &mut cur, &mut monos);
        }
        let index: HashMap<Vec<u8>, usize> = monos
            .iter()
            .enumerate()
            .map(|(k, m)| (m.clone(), k))
            .collect();
        let mut pairs = vec![Vec::new(); monos.len()];
        for (i, mi) in monos.iter().enumerate() {
            for (j, mj) in monos.iter().enumerate() {
                let di: usize = mi.iter().map(|&e| e as usize).sum();
                let dj: usize = mj.iter().map(|&e| e as usize).sum();
                if di + dj > degree {
                    continue;
                }
                let s: Vec<u8> = mi.iter().zip(mj).map(|(a, b)| a + b).collect();
                pairs[index[&s]].push((i as u32, j as u32));
            }
        }
        Layout {
            nvars,
            degree,
            monos,
            index,
            pairs,
        }
    }

    /// The shared layout for `(nvars, degree)` (cached per thread).
    pub fn get(nvars: usize, degree: usize) -> Rc<Layout> {
        thread_local! {
            static CACHE: RefCell<HashMap<(usize, usize), Rc<Layout>>> = RefCell::new(HashMap::new());
        }
        CACHE.with(|c| {
            c.borrow_mut()
                .entry((nvars, degree))
                .or_insert_with(|| Rc::new(Layout::new(nvars, degree)))
                .clone()
        })
    }

    /// Number of monomials.
    pub fn len(&self) -> usize {
        self.monos.len()
    }

    /// True if there are no monomials (never: the constant is always there).
    pub fn is_empty(&self) -> bool {
        self.monos.is_empty()
    }

    /// Index of the monomial with exponents `m`, if its degree is within the truncation.
    pub fn index_of(&self, m: &[u8]) -> Option<usize> {
        self.index.get(m).copied()
    }
}

/// All exponent vectors of total degree `d` in lexicographically decreasing order.
fn gen_degree(n: usize, d: usize, k: usize, cur: &mut Vec<u8>, out: &mut Vec<Vec<u8>>) {
    if k == n - 1 {
        cur[k] = d as u8;
        out.push(cur.clone());
        return;
    }
    for e in (0..=d).rev() {
        cur[k] = e as u8;
        gen_degree(n, d - e, k + 1, cur, out);
    }
    cur[k] = 0;
}

/// A truncated multivariate Taylor series with coefficients of type `S`.
///
/// A jet without a layout is a constant (what [`Scalar::cst`] makes); it is promoted
/// when combined with a jet that has one.
#[derive(Clone, Debug)]
pub struct Jet<S> {
    layout: Option<Rc<Layout>>,
    c: Vec<S>,
}

impl<S: Scalar> Jet<S> {
    /// The constant jet `v`.
    pub fn constant(v: S) -> Self {
        Jet {
            layout: None,
            c: vec![v],
        }
    }

    /// The independent variable `var` expanded about `value`: `value + dx_var`.
    pub fn variable(layout: &Rc<Layout>, var: usize, value: S) -> Self {
        let mut c = vec![S::cst(0.0); layout.len()];
        c[0] = value;
        if layout.degree >= 1 {
            let mut m = vec![0u8; layout.nvars];
            m[var] = 1;
            c[layout.index_of(&m).expect("degree >= 1")] = S::cst(1.0);
        }
        Jet {
            layout: Some(layout.clone()),
            c,
        }
    }

    /// The layout, if this jet is not a constant.
    pub fn layout(&self) -> Option<&Rc<Layout>> {
        self.layout.as_ref()
    }

    /// The value (coefficient of degree 0).
    pub fn value(&self) -> &S {
        &self.c[0]
    }

    /// The Taylor coefficient of the monomial with exponents `m` (zero for a constant
    /// jet and `m != 0`).
    pub fn coeff(&self, m: &[u8]) -> S {
        match &self.layout {
            None => {
                if m.iter().all(|&e| e == 0) {
                    self.c[0].clone()
                } else {
                    S::cst(0.0)
                }
            }
            Some(l) => self.c[l.index_of(m).expect("monomial beyond the truncation")].clone(),
        }
    }

    /// The partial derivative `d^m f` at the expansion point: `m! c_m` (the factorials
    /// in `f64`: exact to `22!`, correctly rounded products beyond, where an integer
    /// product would overflow).
    pub fn derivative(&self, m: &[u8]) -> S {
        let fact: f64 = m
            .iter()
            .map(|&e| (1..=e).map(f64::from).product::<f64>())
            .product();
        let c = self.coeff(m);
        if fact == 1.0 {
            c
        } else {
            S::cst(fact) * c
        }
    }

    fn promote(&self, l: &Rc<Layout>) -> Vec<S> {
        match &self.layout {
            Some(_) => self.c.clone(),
            None => {
                let mut c = vec![S::cst(0.0); l.len()];
                c[0] = self.c[0].clone();
                c
            }
        }
    }

    fn common(a: &Self, b: &Self) -> Option<Rc<Layout>> {
        match (&a.layout, &b.layout) {
            (Some(la), Some(lb)) => {
                assert!(Rc::ptr_eq(la, lb), "jets of different layouts combined");
                Some(la.clone())
            }
            (Some(l), None) | (None, Some(l)) => Some(l.clone()),
            (None, None) => None,
        }
    }

    /// Apply a coefficient-wise binary operation after promotion.
    fn zip(a: &Self, b: &Self, f: impl Fn(S, S) -> S) -> Self {
        match Self::common(a, b) {
            None => Jet::constant(f(a.c[0].clone(), b.c[0].clone())),
            Some(l) => {
                let (x, y) = (a.promote(&l), b.promote(&l));
                Jet {
                    c: x.into_iter().zip(y).map(|(p, q)| f(p, q)).collect(),
                    layout: Some(l),
                }
            }
        }
    }

    /// `sum_{(i, j) in pairs(m), keep(i, j)} w(i, j) * x_i * y_j`, skipping structural zeros.
    fn cauchy_sum(
        l: &Layout,
        m: usize,
        x: &[S],
        y: &[S],
        keep: impl Fn(u32, u32) -> bool,
        w: impl Fn(u32, u32) -> (f64, f64),
    ) -> Option<S> {
        let mut acc: Option<S> = None;
        for &(i, j) in &l.pairs[m] {
            if !keep(i, j) {
                continue;
            }
            let (xi, yj) = (&x[i as usize], &y[j as usize]);
            if xi.is_known_zero() || yj.is_known_zero() {
                continue;
            }
            let (num, den) = w(i, j);
            if num == 0.0 {
                continue;
            }
            let mut t = xi.clone() * yj.clone();
            if num != den {
                t = S::ratio(num, den) * t;
            }
            acc = Some(match acc {
                None => t,
                Some(a) => a + t,
            });
        }
        acc
    }

    /// Product rule: the Cauchy product.
    fn mul_rule(a: &Self, b: &Self) -> Self {
        let Some(l) = Self::common(a, b) else {
            return Jet::constant(a.c[0].clone() * b.c[0].clone());
        };
        let (x, y) = (a.promote(&l), b.promote(&l));
        let c = (0..l.len())
            .map(|m| {
                Self::cauchy_sum(&l, m, &x, &y, |_, _| true, |_, _| (1.0, 1.0))
                    .unwrap_or(S::cst(0.0))
            })
            .collect();
        Jet { layout: Some(l), c }
    }

    /// Quotient rule: `c_m = (a_m - sum_{i != 0} b_i c_{m-i}) / b_0`.
    fn div_rule(a: &Self, b: &Self) -> Self {
        let Some(l) = Self::common(a, b) else {
            return Jet::constant(a.c[0].clone() / b.c[0].clone());
        };
        let (x, y) = (a.promote(&l), b.promote(&l));
        // c is filled in graded order; the sums only read entries already computed.
        // One reciprocal for every coefficient (a division costs several products).
        let mut c: Vec<S> = vec![S::cst(0.0); l.len()];
        let inv_b0 = y[0].recip();
        c[0] = x[0].clone() * inv_b0.clone();
        for m in 1..l.len() {
            let s = Self::cauchy_sum(&l, m, &y, &c, |i, _| i != 0, |_, _| (1.0, 1.0));
            let num = match s {
                None => x[m].clone(),
                Some(s) => x[m].clone() - s,
            };
            c[m] = if num.is_known_zero() {
                num
            } else {
                num * inv_b0.clone()
            };
        }
        Jet { layout: Some(l), c }
    }

    /// Square-root rule: `c_m = (a_m - sum_{i, j != 0} c_i c_j) / (2 c_0)`.
    fn sqrt_rule(&self) -> Self {
        let Some(l) = self.layout.clone() else {
            return Jet::constant(self.c[0].sqrt());
        };
        let x = &self.c;
        let mut c: Vec<S> = vec![S::cst(0.0); l.len()];
        c[0] = x[0].sqrt();
        let inv_two_c0 = (S::cst(2.0) * c[0].clone()).recip();
        for m in 1..l.len() {
            let s = Self::cauchy_sum(&l, m, &c, &c, |i, j| i != 0 && j != 0, |_, _| (1.0, 1.0));
            let num = match s {
                None => x[m].clone(),
                Some(s) => x[m].clone() - s,
            };
            c[m] = if num.is_known_zero() {
                num
            } else {
                num * inv_two_c0.clone()
            };
        }
        Jet { layout: Some(l), c }
    }

    /// Power rule for a real exponent `alpha` (requires a non-zero value `a_0`):
    /// `c_m = sum_{i != 0} (alpha i_v - (m-i)_v) a_i c_{m-i} / (m_v a_0)`.
    pub fn powf(&self, alpha: f64, pow0: S) -> Self {
        let Some(l) = self.layout.clone() else {
            return Jet::constant(pow0);
        };
        let x = &self.c;
        // 1/a_0 once; the weights (alpha i_v - (m-i)_v) / m_v are folded constants.
        let inv_a0 = x[0].recip();
        let mut c: Vec<S> = vec![S::cst(0.0); l.len()];
        c[0] = pow0;
        for m in 1..l.len() {
            let mm = &l.monos[m];
            let v = mm.iter().position(|&e| e > 0).expect("m != 0");
            let mv = mm[v] as f64;
            let s = Self::cauchy_sum(
                &l,
                m,
                x,
                &c,
                |i, _| i != 0,
                |i, j| {
                    (
                        alpha * l.monos[i as usize][v] as f64 - l.monos[j as usize][v] as f64,
                        mv,
                    )
                },
            );
            c[m] = match s {
                None => S::cst(0.0),
                Some(s) => s * inv_a0.clone(),
            };
        }
        Jet { layout: Some(l), c }
    }
}

impl<S: Scalar> Jet<S> {
    /// `sum_{i != 0} (i_v / m_v) a_i e_{m-i}` along the first variable `v` of the
    /// monomial `m != 0` with `m_v > 0`: the coefficient `m` of the jet whose derivative
    /// along `v` is `e d_v a` (the chain rule of [`Jet::exp_rule`] and
    /// [`Jet::erfc_rule`]); `None` when every term is a structural zero.
    fn chain_sum(l: &Layout, m: usize, a: &[S], e: &[S]) -> Option<S> {
        let mm = &l.monos[m];
        let v = mm.iter().position(|&k| k > 0).expect("m != 0");
        let mv = mm[v] as f64;
        Self::cauchy_sum(
            l,
            m,
            a,
            e,
            |i, _| i != 0,
            |i, _| (l.monos[i as usize][v] as f64, mv),
        )
    }

    /// Exponential rule: `c_0 = e^{a_0}`, `c_m = sum_{i != 0} (i_v / m_v) a_i c_{m-i}`.
    fn exp_rule(&self) -> Self {
        let Some(l) = self.layout.clone() else {
            return Jet::constant(self.c[0].exp());
        };
        let mut c: Vec<S> = vec![S::cst(0.0); l.len()];
        c[0] = self.c[0].exp();
        for m in 1..l.len() {
            // c is filled in graded order; the sum reads only c_{m-i}, i != 0
            c[m] = Self::chain_sum(&l, m, &self.c, &c).unwrap_or(S::cst(0.0));
        }
        Jet { layout: Some(l), c }
    }

    /// Complementary error function rule: with `e = exp(-a a)`, `c_0 = erfc(a_0)`,
    /// `c_m = -(2/sqrt(pi)) sum_{i != 0} (i_v / m_v) a_i e_{m-i}`.
    fn erfc_rule(&self) -> Self {
        let Some(l) = self.layout.clone() else {
            return Jet::constant(self.c[0].erfc());
        };
        let e = (-(self.clone() * self.clone())).exp_rule();
        let k = -S::from_dd(crate::number::dd::Dd::two_over_sqrt_pi());
        let mut c: Vec<S> = vec![S::cst(0.0); l.len()];
        c[0] = self.c[0].erfc();
        for (m, cm) in c.iter_mut().enumerate().skip(1) {
            if let Some(s) = Self::chain_sum(&l, m, &self.c, &e.c) {
                *cm = k.clone() * s;
            }
        }
        Jet { layout: Some(l), c }
    }
}

impl<S: Scalar> Add for Jet<S> {
    type Output = Jet<S>;
    fn add(self, b: Self) -> Self {
        Jet::zip(&self, &b, |p, q| p + q)
    }
}
impl<S: Scalar> Sub for Jet<S> {
    type Output = Jet<S>;
    fn sub(self, b: Self) -> Self {
        Jet::zip(&self, &b, |p, q| p - q)
    }
}
impl<S: Scalar> Mul for Jet<S> {
    type Output = Jet<S>;
    fn mul(self, b: Self) -> Self {
        Jet::mul_rule(&self, &b)
    }
}
impl<S: Scalar> Div for Jet<S> {
    type Output = Jet<S>;
    fn div(self, b: Self) -> Self {
        Jet::div_rule(&self, &b)
    }
}
impl<S: Scalar> Neg for Jet<S> {
    type Output = Jet<S>;
    fn neg(self) -> Self {
        Jet {
            layout: self.layout,
            c: self.c.into_iter().map(|p| -p).collect(),
        }
    }
}

impl<S: Scalar> Scalar for Jet<S> {
    fn cst(c: f64) -> Self {
        Jet::constant(S::cst(c))
    }
    fn from_dd(d: crate::number::dd::Dd) -> Self {
        Jet::constant(S::from_dd(d))
    }
    fn ratio(n: f64, d: f64) -> Self {
        Jet::constant(S::ratio(n, d))
    }
    fn sqrt(&self) -> Self {
        self.sqrt_rule()
    }
    fn powi(&self, n: i32) -> Self {
        if n < 0 {
            return self.powf(n as f64, self.c[0].powi(n));
        }
        let mut base = self.clone();
        let mut e = n as u32;
        let mut acc = Jet::cst(1.0);
        while e > 0 {
            if e & 1 == 1 {
                acc = acc * base.clone();
            }
            e >>= 1;
            if e > 0 {
                base = base.clone() * base;
            }
        }
        acc
    }
    fn exp(&self) -> Self {
        self.exp_rule()
    }
    fn erfc(&self) -> Self {
        self.erfc_rule()
    }
    fn recip(&self) -> Self {
        Jet::div_rule(&Jet::cst(1.0), self)
    }
    fn to_f64(&self) -> f64 {
        self.c[0].to_f64()
    }
}
