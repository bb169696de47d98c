//! The 22 functions as sums over the recurrences' triangles: which triangle, factor,
//! parity and shift each takes (JO84, J92 as corrected by Townsend 2023; module docs of
//! [`crate::two_sphere`]), and the coefficients of their singular terms near
//! contact.

use super::check_lambda;
use super::recurrences::Table;
use super::TwoSphereError;

/// One scalar function: `F = sign c sum_{m of parity} a_m t^m`, `a_m = sum_q R_{m-q,q}
/// lambda^q (1+lambda)^{-m}` (times `lambda` for odd `m` when `shifted`).
pub(super) struct Function {
    pub(super) table: Table,
    /// index of the triangle in the family's outputs
    pub(super) output: usize,
    /// constant `c` including the sign of the function
    factor: f64,
    shifted: bool,
    pub(super) odd: bool,
    /// `[h1, h2, h3]`: coefficients of `1/xi`, `ln(1/xi)`, `xi ln(1/xi)` near contact
    pub(super) singular: fn(f64) -> [f64; 3],
}

/// The distinct triangles of [`FUNCTIONS`]: each "11" function shares its triangle with
/// the "12" function of the other parity, so function `k` reads triangle `k / 2`.
pub(super) const SOURCES: usize = 11;

/// The triangles of the ten force-torque functions (`x11a` to `y12c`): the first five.
pub(super) const FT_SOURCES: usize = 5;

impl Function {
    /// `a_m` for this `lambda` (the factor included) from the sum of its triangle's row
    /// `m` by the series' `row_sums` and `power`: `nu^m sum R_q lambda^q` for `lambda <= 1`, and
    /// `mu^m sum R_q lambda^{q-m}` otherwise, `mu = lambda/(1+lambda)`, `nu = 1/(1+lambda)`
    /// (`power` is `nu^m` or `mu^m`).
    #[inline]
    pub(super) fn coefficient(&self, sum: f64, power: f64, lambda: f64, m: usize) -> f64 {
        let shift = if self.shifted && m % 2 == 1 {
            lambda
        } else {
            1.0
        };
        self.factor * (sum * power) * shift
    }
}

fn cube(l: f64) -> f64 {
    (1.0 + l).powi(3)
}
fn square(l: f64) -> f64 {
    (1.0 + l).powi(2)
}

// Singular coefficients (JO84; J92; as corrected by Townsend 2023).
fn s_x11a(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        2.0 * l * l * inv,
        l * (1.0 + 7.0 * l + l * l) * inv * (1.0 / 5.0),
        (1.0 + 18.0 * l - 29.0 * l * l + 18.0 * l.powi(3) + l.powi(4)) * inv * (1.0 / 42.0),
    ]
}
fn s_x12a(l: f64) -> [f64; 3] {
    neg(s_x11a(l))
}
fn s_y11a(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        0.0,
        4.0 * l * (2.0 + l + 2.0 * l * l) * inv * (1.0 / 15.0),
        2.0 * (16.0 - 45.0 * l + 58.0 * l * l - 45.0 * l.powi(3) + 16.0 * l.powi(4))
            * inv
            * (1.0 / 375.0),
    ]
}
fn s_y12a(l: f64) -> [f64; 3] {
    neg(s_y11a(l))
}
fn s_y11b(l: f64) -> [f64; 3] {
    let inv = 1.0 / square(l);
    [
        0.0,
        -l * (4.0 + l) * inv * (1.0 / 5.0),
        -(32.0 - 33.0 * l + 83.0 * l * l + 43.0 * l.powi(3)) * inv * (1.0 / 250.0),
    ]
}
fn s_y12b(l: f64) -> [f64; 3] {
    neg(s_y11b(l))
}
fn s_x11c(l: f64) -> [f64; 3] {
    let inv = 1.0 / (1.0 + l);
    [0.0, 0.0, -l * l * inv * (1.0 / 4.0)]
}
fn s_x12c(l: f64) -> [f64; 3] {
    neg(s_x11c(l))
}
fn s_y11c(l: f64) -> [f64; 3] {
    let inv = 1.0 / (1.0 + l);
    [
        0.0,
        2.0 * l * inv * (1.0 / 5.0),
        (8.0 + 6.0 * l + 33.0 * l * l) * inv * (1.0 / 125.0),
    ]
}
fn s_y12c(l: f64) -> [f64; 3] {
    let inv = 1.0 / (1.0 + l);
    [
        0.0,
        l * l * inv * (1.0 / 10.0),
        l * (43.0 - 24.0 * l + 43.0 * l * l) * inv * (1.0 / 500.0),
    ]
}
fn s_x11g(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        3.0 * l * l * inv,
        3.0 * (l + 12.0 * l * l - 4.0 * l.powi(3)) * inv * (1.0 / 10.0),
        (5.0 + 181.0 * l - 453.0 * l * l + 566.0 * l.powi(3) - 65.0 * l.powi(4))
            * inv
            * (1.0 / 140.0),
    ]
}
fn s_x12g(l: f64) -> [f64; 3] {
    neg(s_x11g(l))
}
fn s_y11g(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        0.0,
        (4.0 * l - l * l + 7.0 * l.powi(3)) * inv * (1.0 / 10.0),
        (32.0 - 179.0 * l + 532.0 * l * l - 356.0 * l.powi(3) + 221.0 * l.powi(4))
            * inv
            * (1.0 / 500.0),
    ]
}
fn s_y12g(l: f64) -> [f64; 3] {
    neg(s_y11g(l))
}
fn s_y11h(l: f64) -> [f64; 3] {
    let inv = 1.0 / square(l);
    [
        0.0,
        (2.0 * l - l * l) * inv * (1.0 / 10.0),
        (16.0 - 61.0 * l + 180.0 * l * l + 2.0 * l.powi(3)) * inv * (1.0 / 500.0),
    ]
}
fn s_y12h(l: f64) -> [f64; 3] {
    let inv = 1.0 / square(l);
    [
        0.0,
        (l * l + 7.0 * l.powi(3)) * inv * (1.0 / 20.0),
        (43.0 * l + 147.0 * l * l - 185.0 * l.powi(3) + 221.0 * l.powi(4)) * inv * (1.0 / 1000.0),
    ]
}
fn s_x11m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        6.0 * l * l * inv * (1.0 / 5.0),
        3.0 * (l + 17.0 * l * l - 9.0 * l.powi(3)) * inv * (1.0 / 25.0),
        (5.0 + 272.0 * l - 831.0 * l * l + 1322.0 * l.powi(3) - 415.0 * l.powi(4))
            * inv
            * (1.0 / 350.0),
    ]
}
fn s_x12m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        6.0 * l.powi(3) * inv * (1.0 / 5.0),
        3.0 * (-4.0 * l * l + 17.0 * l.powi(3) - 4.0 * l.powi(4)) * inv * (1.0 / 25.0),
        (-65.0 * l + 832.0 * l * l - 1041.0 * l.powi(3) + 832.0 * l.powi(4) - 65.0 * l.powi(5))
            * inv
            * (1.0 / 350.0),
    ]
}
fn s_y11m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        0.0,
        6.0 * (l - l * l + 4.0 * l.powi(3)) * inv * (1.0 / 25.0),
        (24.0 - 201.0 * l + 882.0 * l * l - 1182.0 * l.powi(3) + 591.0 * l.powi(4))
            * inv
            * (1.0 / 625.0),
    ]
}
fn s_y12m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [
        0.0,
        3.0 * (7.0 * l * l - 10.0 * l.powi(3) + 7.0 * l.powi(4)) * inv * (1.0 / 50.0),
        3.0 * l
            * (221.0 - 728.0 * l + 1902.0 * l * l - 728.0 * l.powi(3) + 221.0 * l.powi(4))
            * inv
            * (1.0 / 2500.0),
    ]
}
fn s_z11m(l: f64) -> [f64; 3] {
    let inv = 1.0 / cube(l);
    [0.0, 0.0, -3.0 * (l * l + l.powi(4)) * inv * (1.0 / 10.0)]
}
fn s_z12m(l: f64) -> [f64; 3] {
    neg(s_z11m(l))
}
fn neg(h: [f64; 3]) -> [f64; 3] {
    [-h[0], -h[1], -h[2]]
}

macro_rules! function {
    ($table:ident, $out:expr, $factor:expr, $shifted:expr, $odd:expr, $sing:ident) => {
        Function {
            table: Table::$table,
            output: $out,
            factor: $factor,
            shifted: $shifted,
            odd: $odd,
            singular: $sing,
        }
    };
}

/// The 22 functions in the order of [`super::NAMES`]. The "11" function takes one parity of a
/// sequence, the "12" function the other, with the sign of JO84/J92 (module docs).
pub(super) static FUNCTIONS: [Function; 22] = [
    function!(Xa, 0, 1.0, false, false, s_x11a),
    function!(Xa, 0, -1.0, false, true, s_x12a),
    function!(Ya, 0, 1.0, false, false, s_y11a),
    function!(Ya, 0, -1.0, false, true, s_y12a),
    function!(Ya, 1, 2.0, false, true, s_y11b),
    function!(Ya, 1, -2.0, false, false, s_y12b),
    function!(Xc, 0, 1.0, true, false, s_x11c),
    function!(Xc, 0, -1.0, true, true, s_x12c),
    function!(Yc, 0, 1.0, true, false, s_y11c),
    function!(Yc, 0, 1.0, true, true, s_y12c),
    function!(Xa, 1, 0.75, false, true, s_x11g),
    function!(Xa, 1, -0.75, false, false, s_x12g),
    function!(Ya, 2, 0.75, false, true, s_y11g),
    function!(Ya, 2, -0.75, false, false, s_y12g),
    function!(Yc, 1, -0.375, true, false, s_y11h),
    function!(Yc, 1, -0.375, true, true, s_y12h),
    function!(Xm, 0, 1.0, true, false, s_x11m),
    function!(Xm, 0, 1.0, true, true, s_x12m),
    function!(Ym, 0, 1.0, true, false, s_y11m),
    function!(Ym, 0, 1.0, true, true, s_y12m),
    function!(Zm, 0, 1.0, true, false, s_z11m),
    function!(Zm, 0, -1.0, true, true, s_z12m),
];

/// The singular coefficients `[h1, h2, h3]` of each function near contact (`1/xi`,
/// `ln(1/xi)`, `xi ln(1/xi)`), JO84 and J92 as corrected by Townsend 2023, in the order of [`super::NAMES`].
pub fn singular_coefficients(lambda: f64) -> Result<[[f64; 3]; 22], TwoSphereError> {
    check_lambda(lambda)?;
    let mut out = [[0.0; 3]; 22];
    for (k, f) in FUNCTIONS.iter().enumerate() {
        out[k] = (f.singular)(lambda);
    }
    Ok(out)
}
