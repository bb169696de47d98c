//! The multipole expansion at the source (Eq. 8) and the Faxén laws at the field point
//! (Eqs. 12-15), as linear functionals of the derivatives of `G(x, y)`.
//!
//! A block of the grand mobility is a field-point functional (rows: `U`, `Omega`, `E`)
//! times a source functional (columns: `F`, `L`, `S`), each a short list of
//! [`Side`] terms `coef * a^(2 k) * d^m G`. Their product is a list of [`Term`]s
//! `coef * a_a^(2 k_a) a_b^(2 k_b) * d_x^alpha d_y^beta G_ij`; [`apply`] evaluates it
//! against any source of derivatives (jets of any scalar, finite differences).
//!
//! Field point (particle `a`, Eqs. 12-15):
//! - `U`:      `(1 + a_a^2/6 lap_x) G_pj`
//! - `Omega`:  `1/2 eps_mki d_{x_k} G_ij`
//! - `E`:      `1/2 (d_{x_p} G_qj + d_{x_q} G_pj)` with `(1 + a_a^2/10 lap_x)`
//!
//! Source (particle `b`, Eqs. 8-9):
//! - `F`:      `(1 + a_b^2/6 lap_y) G_ij`
//! - `L`:      `1/2 eps_mkj d_{y_k} G_ij` (the antisymmetric first moment; torque `L`)
//! - `S`:      `1/2 (d_{y_k} G_il + d_{y_l} G_ik)` with `(1 + a_b^2/10 lap_y)` (Eq. 9)
//!
//! Strain and stresslet are either Cartesian pairs `(p, q)` (9 components, row-major)
//! or the 5-component orthonormal basis [`STRAIN_BASIS`] of symmetric traceless
//! tensors (Frobenius inner product), which keeps the grand mobility symmetric.

use crate::number::scalar::Scalar;
use std::collections::BTreeMap;

const S2: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// `1/sqrt(6)` and `2/sqrt(6)`.
const S6: f64 = 0.408_248_290_463_863_016_366_214_012_450_981_698_8;
const S6X2: f64 = 0.816_496_580_927_726_032_732_428_024_901_963_797_3;

/// The orthonormal basis of symmetric traceless 3x3 tensors (docs/conventions.md):
/// `B1 = (e1e2 + e2e1)/sqrt2`, `B2 = (e1e3 + e3e1)/sqrt2`, `B3 = (e2e3 + e3e2)/sqrt2`,
/// `B4 = (e1e1 - e2e2)/sqrt2`, `B5 = (2e3e3 - e1e1 - e2e2)/sqrt6`.
pub const STRAIN_BASIS: [[[f64; 3]; 3]; 5] = [
    [[0.0, S2, 0.0], [S2, 0.0, 0.0], [0.0, 0.0, 0.0]],
    [[0.0, 0.0, S2], [0.0, 0.0, 0.0], [S2, 0.0, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, S2], [0.0, S2, 0.0]],
    [[S2, 0.0, 0.0], [0.0, -S2, 0.0], [0.0, 0.0, 0.0]],
    [[-S6, 0.0, 0.0], [0.0, -S6, 0.0], [0.0, 0.0, S6X2]],
];

/// [`STRAIN_BASIS`] before normalisation, `B_p = STRAIN_INTEGER[p] / sqrt(STRAIN_NORM2[p])`:
/// integer entries, so that the operators' coefficients are exact in `f64` and exact
/// cancellations (free Stokeslet against its image) stay exact; the irrational
/// normalisation multiplies each block entry once, last ([`Block::norm`]).
pub const STRAIN_INTEGER: [[[f64; 3]; 3]; 5] = [
    [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
    [[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 0.0]],
    [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 2.0]],
];

/// Squared Frobenius norms of [`STRAIN_INTEGER`].
pub const STRAIN_NORM2: [f64; 5] = [2.0, 2.0, 2.0, 2.0, 6.0];

/// Levi-Civita symbol, `eps_012 = +1` (right-handed).
pub fn eps(i: usize, j: usize, k: usize) -> f64 {
    ((i as i64 - j as i64) * (j as i64 - k as i64) * (k as i64 - i as i64)) as f64 / 2.0
}

/// How strains and stresslets are represented.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Basis {
    /// The 5-component orthonormal basis [`STRAIN_BASIS`].
    Orthonormal,
    /// Cartesian pairs `(p, q)`, 9 components, row-major (the paper's appendices).
    Cartesian,
}

/// Field-point response (a row of the grand mobility).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Response {
    /// Translational velocity (Eq. 12).
    U,
    /// Angular velocity (Eq. 13).
    Omega,
    /// Rate of strain (Eqs. 14-15).
    E,
}

/// Source moment (a column of the grand mobility).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Moment {
    /// Force.
    F,
    /// Torque.
    L,
    /// Stresslet.
    S,
}

/// The nine blocks in the order the kernels return them.
pub const BLOCKS: [(Response, Moment); 9] = [
    (Response::U, Moment::F),
    (Response::U, Moment::L),
    (Response::U, Moment::S),
    (Response::Omega, Moment::F),
    (Response::Omega, Moment::L),
    (Response::Omega, Moment::S),
    (Response::E, Moment::F),
    (Response::E, Moment::L),
    (Response::E, Moment::S),
];

/// Lower-case block name, e.g. `uf`, `os`, `es`.
pub fn block_name(r: Response, m: Moment) -> String {
    let a = match r {
        Response::U => "u",
        Response::Omega => "o",
        Response::E => "e",
    };
    let b = match m {
        Moment::F => "f",
        Moment::L => "l",
        Moment::S => "s",
    };
    format!("{a}{b}")
}

fn strain_dim(b: Basis) -> usize {
    match b {
        Basis::Orthonormal => 5,
        Basis::Cartesian => 9,
    }
}

/// Number of components of a response.
pub fn response_dim(r: Response, b: Basis) -> usize {
    match r {
        Response::U | Response::Omega => 3,
        Response::E => strain_dim(b),
    }
}

/// Number of components of a moment.
pub fn moment_dim(m: Moment, b: Basis) -> usize {
    match m {
        Moment::F | Moment::L => 3,
        Moment::S => strain_dim(b),
    }
}

/// One term of a one-sided functional: `coef * a^(2 a2) * d^d G_{comp, .}` (field
/// side: `comp` is the row index `i` of `G`; source side: the column index `j`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Side {
    /// Component of `G` (row for the field side, column for the source side).
    pub comp: usize,
    /// Derivative multi-index.
    pub d: [u8; 3],
    /// Coefficient.
    pub coef: f64,
    /// Power of `a^2` (0 or 1).
    pub a2: u8,
}

/// A derivative of `G`: `d_x^dx d_y^dy G_ij`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Deriv {
    /// Row of `G` (the velocity component at `x`).
    pub i: usize,
    /// Column of `G` (the force component at `y`).
    pub j: usize,
    /// Derivative orders in `x`.
    pub dx: [u8; 3],
    /// Derivative orders in `y`.
    pub dy: [u8; 3],
}

impl Deriv {
    /// Total order `|dx| + |dy|`.
    pub fn order(&self) -> usize {
        self.dx.iter().chain(&self.dy).map(|&e| e as usize).sum()
    }
}

/// One term of a block entry: `coef * a_a^(2 pa) a_b^(2 pb) * d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Term {
    /// Coefficient.
    pub coef: f64,
    /// Power of `a_a^2` (field particle).
    pub pa: u8,
    /// Power of `a_b^2` (source particle).
    pub pb: u8,
    /// The derivative of `G`.
    pub d: Deriv,
}

fn unit(k: usize, n: u8) -> [u8; 3] {
    let mut d = [0u8; 3];
    d[k] = n;
    d
}

fn add_d(a: [u8; 3], b: [u8; 3]) -> [u8; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `coef * (1 + c a^2 lap) d^d G_comp`, the Faxén factor `c` ([`faxen`]) left out of
/// the coefficients (it multiplies `a^2`).
fn with_laplacian(comp: usize, d: [u8; 3], coef: f64) -> Vec<Side> {
    let mut v = vec![Side {
        comp,
        d,
        coef,
        a2: 0,
    }];
    for k in 0..3 {
        v.push(Side {
            comp,
            d: add_d(d, unit(k, 2)),
            coef,
            a2: 1,
        });
    }
    v
}

/// Symmetrised gradient `1/2 (d_p G_q + d_q G_p)` with `(1 + a^2/10 lap)`, Cartesian
/// (the `1/10` left to [`faxen`]).
fn sym_gradient(p: usize, q: usize) -> Vec<Side> {
    let mut v = with_laplacian(q, unit(p, 1), 0.5);
    v.extend(with_laplacian(p, unit(q, 1), 0.5));
    v
}

/// Curl `1/2 eps_mki d_k G_i`.
fn half_curl(m: usize) -> Vec<Side> {
    let mut v = Vec::new();
    for k in 0..3 {
        for i in 0..3 {
            let e = eps(m, k, i);
            if e != 0.0 {
                v.push(Side {
                    comp: i,
                    d: unit(k, 1),
                    coef: 0.5 * e,
                    a2: 0,
                });
            }
        }
    }
    v
}

/// Strain/stresslet components from the Cartesian symmetrised gradients.
fn strain_components(b: Basis) -> Vec<Vec<Side>> {
    let cart: Vec<Vec<Side>> = (0..9).map(|pq| sym_gradient(pq / 3, pq % 3)).collect();
    match b {
        Basis::Cartesian => cart,
        Basis::Orthonormal => STRAIN_INTEGER
            .iter()
            .map(|bn| {
                let mut v = Vec::new();
                for pq in 0..9 {
                    let w = bn[pq / 3][pq % 3];
                    if w != 0.0 {
                        v.extend(cart[pq].iter().map(|s| Side {
                            coef: s.coef * w,
                            ..*s
                        }));
                    }
                }
                merge_sides(v)
            })
            .collect(),
    }
}

fn merge_sides(v: Vec<Side>) -> Vec<Side> {
    let mut m: BTreeMap<(usize, [u8; 3], u8), f64> = BTreeMap::new();
    for s in v {
        *m.entry((s.comp, s.d, s.a2)).or_insert(0.0) += s.coef;
    }
    m.into_iter()
        .filter(|(_, c)| *c != 0.0)
        .map(|((comp, d, a2), coef)| Side { comp, d, coef, a2 })
        .collect()
}

/// The Faxén functional at the field point (Eqs. 12-15), one list per component, with
/// exact coefficients: the `a^2` terms without their factor [`faxen`], the strain
/// components in the integer basis [`STRAIN_INTEGER`] (normalised by [`norm`]).
pub fn field(r: Response, b: Basis) -> Vec<Vec<Side>> {
    match r {
        Response::U => (0..3).map(|p| with_laplacian(p, [0; 3], 1.0)).collect(),
        Response::Omega => (0..3).map(half_curl).collect(),
        Response::E => strain_components(b),
    }
}

/// The multipole functional at the source (Eqs. 8-9), one list per component.
/// Identical in form to the field side: force <-> velocity with `a^2/6`, torque <->
/// rotation through the half curl, stresslet <-> strain through the symmetrised
/// gradient with `a^2/10`.
pub fn source(m: Moment, b: Basis) -> Vec<Vec<Side>> {
    match m {
        Moment::F => field(Response::U, b),
        Moment::L => field(Response::Omega, b),
        Moment::S => field(Response::E, b),
    }
}

/// The factor `c` of `a^2 lap` in the Faxén law of a response (`U`: 1/6, Eq. 12;
/// `E`: 1/10, Eq. 14; `Omega`: none, 0) and, by the same form, in the multipole
/// moment of the corresponding source (`F`, `S`, `L`).
pub fn faxen(r: Response) -> f64 {
    match r {
        Response::U => 1.0 / 6.0,
        Response::Omega => 0.0,
        Response::E => 1.0 / 10.0,
    }
}

/// A Faxén factor [`faxen`] as a scalar: `1/6` or `1/10` rounded once in `f64`, exact in
/// a scalar that carries more precision ([`Scalar::ratio`]); 0 where there is none.
pub fn faxen_factor<S: Scalar>(v: f64) -> S {
    if v == 0.0 {
        S::cst(0.0)
    } else {
        S::ratio(1.0, (1.0 / v).round())
    }
}

fn moment_response(m: Moment) -> Response {
    match m {
        Moment::F => Response::U,
        Moment::L => Response::Omega,
        Moment::S => Response::E,
    }
}

/// Squared norm of component `k` of a response or moment in basis `b`: 1 except the
/// orthonormal strain components ([`STRAIN_NORM2`]).
fn norm2(r: Response, b: Basis, k: usize) -> f64 {
    match (r, b) {
        (Response::E, Basis::Orthonormal) => STRAIN_NORM2[k],
        _ => 1.0,
    }
}

/// The normalisation of entry `(row, col)` of block `(r, m)`: `1/sqrt(n_row n_col)`,
/// correctly rounded (1 outside the orthonormal strain basis).
pub fn norm(r: Response, m: Moment, b: Basis, row: usize, col: usize) -> f64 {
    let n = norm2(r, b, row) * norm2(moment_response(m), b, col);
    if n == 1.0 {
        1.0
    } else {
        crate::number::dd::Dd::new(n).sqrt().recip().to_f64()
    }
}

/// A block with exact coefficients: entry `(i, j)` is
/// `norm[i][j] * sum_t coef_t (fa a_a^2)^pa_t (fb a_b^2)^pb_t d_t`. The coefficients
/// `coef_t` are small dyadic rationals (sums and products of them are exact in `f64`),
/// so terms that cancel in exact arithmetic cancel in any scalar; the irrational or
/// non-dyadic factors (the strain normalisation, the Faxén `1/6`, `1/10`) multiply
/// once, outside.
#[derive(Clone, Debug)]
pub struct Block {
    /// The terms of every entry `[row][col]`.
    pub entries: Vec<Vec<Vec<Term>>>,
    /// `norm[row][col]`, see [`norm`].
    pub norm: Vec<Vec<f64>>,
    /// Faxén factor of the field particle's `a_a^2` ([`faxen`] of the response).
    pub fa: f64,
    /// Faxén factor of the source particle's `a_b^2`.
    pub fb: f64,
}

/// Block `(r, m)` with exact coefficients (see [`Block`]).
pub fn exact_block(r: Response, m: Moment, b: Basis) -> Block {
    let f = field(r, b);
    let s = source(m, b);
    let entries = f
        .iter()
        .map(|fr| {
            s.iter()
                .map(|sc| {
                    let mut terms = Vec::new();
                    for a in fr {
                        for c in sc {
                            terms.push(Term {
                                coef: a.coef * c.coef,
                                pa: a.a2,
                                pb: c.a2,
                                d: Deriv {
                                    i: a.comp,
                                    j: c.comp,
                                    dx: a.d,
                                    dy: c.d,
                                },
                            });
                        }
                    }
                    terms
                })
                .collect()
        })
        .collect();
    let norm = (0..f.len())
        .map(|i| (0..s.len()).map(|j| norm(r, m, b, i, j)).collect())
        .collect();
    Block {
        entries,
        norm,
        fa: faxen(r),
        fb: faxen(moment_response(m)),
    }
}

/// The terms of every entry `[row][col]` of block `(r, m)`, every factor folded into
/// the coefficients (`coef norm fa^pa fb^pb`): for sources that evaluate a term at a
/// time and need no exact cancellation (finite differences).
pub fn block(r: Response, m: Moment, b: Basis) -> Vec<Vec<Vec<Term>>> {
    let blk = exact_block(r, m, b);
    blk.entries
        .iter()
        .zip(&blk.norm)
        .map(|(row, norms)| {
            row.iter()
                .zip(norms)
                .map(|(entry, n)| {
                    entry
                        .iter()
                        .map(|t| {
                            let mut coef = t.coef * n;
                            if t.pa == 1 {
                                coef *= blk.fa;
                            }
                            if t.pb == 1 {
                                coef *= blk.fb;
                            }
                            Term { coef, ..*t }
                        })
                        .collect()
                })
                .collect()
        })
        .collect()
}

/// Highest total derivative order that block `(r, m)` needs.
pub fn max_order(r: Response, m: Moment) -> usize {
    block(r, m, Basis::Cartesian)
        .iter()
        .flatten()
        .flatten()
        .map(|t| t.d.order())
        .max()
        .unwrap_or(0)
}

/// A source of derivatives of `G` (jets of any scalar, finite differences, ...).
pub trait Derivatives<S: Scalar> {
    /// `d_x^dx d_y^dy G_ij` at the kernel's `(x, y)`.
    fn get(&mut self, d: &Deriv) -> S;

    /// One block entry `sum coef a_a^(2 pa) a_b^(2 pb) d`. The default asks for each
    /// derivative; a source that knows more structure may collect terms first.
    fn combine(&mut self, terms: &[Term], aa2: &S, ab2: &S) -> S
    where
        Self: Sized,
    {
        combine_each(terms, aa2, ab2, self)
    }
}

/// Evaluate one block entry (see [`Derivatives::combine`]).
pub fn apply<S: Scalar, D: Derivatives<S>>(terms: &[Term], aa2: &S, ab2: &S, src: &mut D) -> S {
    src.combine(terms, aa2, ab2)
}

/// Evaluate one block entry derivative by derivative, grouped by the radius factors so
/// that each is multiplied once.
pub fn combine_each<S: Scalar, D: Derivatives<S> + ?Sized>(
    terms: &[Term],
    aa2: &S,
    ab2: &S,
    src: &mut D,
) -> S {
    let mut groups: BTreeMap<(u8, u8), Option<S>> = BTreeMap::new();
    for t in terms {
        let v = src.get(&t.d);
        if v.is_known_zero() {
            continue;
        }
        let v = if t.coef == 1.0 { v } else { S::cst(t.coef) * v };
        let g = groups.entry((t.pa, t.pb)).or_insert(None);
        *g = Some(match g.take() {
            None => v,
            Some(acc) => acc + v,
        });
    }
    let mut out: Option<S> = None;
    for ((pa, pb), s) in groups {
        let Some(mut s) = s else { continue };
        for _ in 0..pa {
            s = aa2.clone() * s;
        }
        for _ in 0..pb {
            s = ab2.clone() * s;
        }
        out = Some(match out {
            None => s,
            Some(o) => o + s,
        });
    }
    out.unwrap_or_else(|| S::cst(0.0))
}

/// The isolated-sphere part of a self block (Eqs. 12-14 with `u' = 0`), in units of
/// `1/(8 pi eta)`: `U F`: `(4/3) / a`; `Omega L`: `1 / a^3`; `E S`: `(6/5) / a^3` times
/// the identity on symmetric traceless tensors. Zero for the other blocks.
pub fn isolated<S: Scalar>(r: Response, m: Moment, b: Basis, a: &S) -> Vec<Vec<S>> {
    let (nr, nc) = (response_dim(r, b), moment_dim(m, b));
    let zero = || vec![vec![S::cst(0.0); nc]; nr];
    let inv_a = a.recip();
    let inv_a3 = inv_a.clone() * inv_a.clone() * inv_a.clone();
    let diag = |c: S| {
        let mut z = zero();
        for (k, row) in z.iter_mut().enumerate() {
            row[k] = c.clone();
        }
        z
    };
    match (r, m) {
        (Response::U, Moment::F) => diag(S::cst(4.0 / 3.0) * inv_a),
        (Response::Omega, Moment::L) => diag(inv_a3),
        (Response::E, Moment::S) => {
            let c = S::cst(6.0 / 5.0) * inv_a3;
            match b {
                Basis::Orthonormal => diag(c),
                Basis::Cartesian => {
                    // c [ (d_pk d_ql + d_pl d_qk)/2 - d_pq d_kl / 3 ]
                    let d = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
                    let mut z = zero();
                    for (pq, row) in z.iter_mut().enumerate() {
                        for (kl, v) in row.iter_mut().enumerate() {
                            let (p, q, k, l) = (pq / 3, pq % 3, kl / 3, kl % 3);
                            let w = 0.5 * (d(p, k) * d(q, l) + d(p, l) * d(q, k))
                                - d(p, q) * d(k, l) / 3.0;
                            if w != 0.0 {
                                *v = S::cst(w) * c.clone();
                            }
                        }
                    }
                    z
                }
            }
        }
        _ => zero(),
    }
}
