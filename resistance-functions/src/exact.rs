//! Exact resistance functions of one sphere near a plane wall and of two equal spheres,
//! from the bispherical-coordinate solutions. The sphere-wall functions are the `R^W`
//! of the lubrication-corrected resistance (Swan & Brady 2007, Eq. 19) for gaps from
//! 1e-3 a up to the wall cutoff; all of them are the references of the tests.
//!
//! Everything here is `std` only, double precision, and written from the published
//! formulas (sources below; collected with a second check in `docs/lubrication.md`,
//! "Reference formulas"). Each series is rewritten so that no step cancels
//! catastrophically (see "Numerics"), and every function is checked against an
//! independent 40-digit `mpmath` evaluation of the formulas as printed
//! (`tests/derivations/exact_check.py`) in the integration tests of the exact
//! references.
//!
//! # Conventions
//!
//! One sphere: wall `z = 0`, unit normal `n = e_z` into the fluid, sphere radius `a`, centre
//! height `h`, gap `delta = h - a`, `eps = delta/a`, bispherical parameter
//! `alpha = arccosh(h/a)`. `(F, L)` are the force and the torque about the centre exerted by
//! a quiescent fluid on the sphere moving with `(U, Omega)`. All coefficients are the
//! (positive) entries of the resistance matrix:
//!
//! ```text
//! F_z = -6 pi mu a   U_z     X^A_w        L_z = -8 pi mu a^3 Omega_z X^C_w
//! F_x = -6 pi mu a   U_x     Y^A_w        L_y = -8 pi mu a^3 Omega_y Y^C_w
//! L_y = +8 pi mu a^2 U_x     T^t*         F_x = +6 pi mu a^2 Omega_y F^r*
//! ```
//!
//! with `F^r* = (4/3) T^t*` (reciprocity). In tensor form `R_FU = 6 pi mu a [X^A_w nn +
//! Y^A_w (I - nn)]`, `R_LOmega = 8 pi mu a^3 [X^C_w nn + Y^C_w (I - nn)]`, `(R_FOmega)_ij =
//! -6 pi mu a^2 F^r* eps_ijk n_k`, `R_LU = R_FOmega^T`. In "SD units" (`6 pi mu a^n`)
//! `T^t*`, `Y^C_w`, `X^C_w` are multiplied by 4/3. Published names: `X^A_w` = Brenner's
//! (1961) `lambda`; `Y^A_w` = `-F_x^t*`, `T^t*` = `T_y^t*`, `F^r*` = `F_x^r*`, `Y^C_w` =
//! `-T_y^r*` of Goldman, Cox & Brenner (1967, "GCB"); `Y^A_w` = O'Neill's (1964) `F*`,
//! `T^t*` = his `G*`; `X^C_w` = Jeffery's (1915) couple coefficient.
//!
//! Two equal spheres (radius `a`, centres `r` apart, `xi = r/a - 2`), Kim & Karrila
//! normalisation (Kim & Karrila 1991, sec. 7.2; `d` the unit vector from sphere 1 to sphere 2):
//! `F_1 = -6 pi mu a [X11A d d . U_1 + X12A d d . U_2] + ...`, `L_1 = -8 pi mu a^3 [X11C d d
//! . Omega_1 + X12C d d . Omega_2] + ...`. For equal spheres each function splits into a
//! symmetric and an antisymmetric motion (`cosh alpha = r/(2a)`, i.e. `h = r/2`):
//!
//! ```text
//! X11A + X12A = Stimson & Jeffery (1926)        X11A - X12A = Brenner (1961), free surface
//! X11C + X12C = Jeffery sum, shear-free plane    X11C - X12C = Jeffery (1915), rigid wall
//! ```
//!
//! Spheres translating together along the line of centres are the Stimson-Jeffery
//! problem; spheres approaching each other (`U_2 = -U_1`) have a symmetry plane that is
//! impermeable and free of shear stress, i.e. one sphere approaching a flat free surface at
//! distance `h = r/2`. Spheres spinning about the line of centres the same way leave the
//! azimuthal velocity even in `z` (`dv/dz = 0` on the plane: shear-free), spinning
//! oppositely make it odd (`v = 0`: a rigid wall).
//!
//! # Sources
//!
//! * Brenner, Chem. Eng. Sci. 16, 242 (1961), eq. 2.19 (rigid wall) and the free-surface
//!   case of the same paper ([`brenner_xa_wall`], [`brenner_xa_free_surface`]; the
//!   free-surface series is written from memory of that paper and *validated* against the
//!   independent far-field series of Jeffrey & Onishi 1984 and the near-contact forms
//!   of two equal spheres of Jeffrey & Onishi 1984, see its docs).
//! * Stimson & Jeffery, Proc. R. Soc. A 111, 110 (1926) ([`stimson_jeffery`]).
//! * O'Neill, Mathematika 11, 67 (1964), eqs. 23, 26, 27 ([`oneill_parallel`]).
//! * Dean & O'Neill, Mathematika 10, 13 (1963), as corrected by GCB (Chem. Eng. Sci. 22,
//!   637, 1967) ([`rotation_parallel`]): the same matrix as O'Neill's, another right-hand
//!   side and inhomogeneous terms in `C_n`, `E_n`. The formulation was taken from two
//!   independent public ports of those papers (MATLAB: `bishopgroup/CCEPdynamics`
//!   `SpherePlaneNF/CalcYBYC.m` and `haloless/StupidCFD` `WallBody/WallParallelRot.m`,
//!   which agree term by term) and is *validated*, not trusted: the force it gives equals
//!   `(4/3) T^t*` of the independent translation problem to 1e-40 in 50-digit arithmetic
//!   (`exact_check.py`) and to 8e-14 here (`h/a <= 2`), and both problems reproduce the
//!   published Chaoui & Feuillebois (2003) fits (below) to 1.5e-9 or better.
//! * Jeffery, Proc. London Math. Soc. (2) 14, 327 (1915); `X^C_w` as quoted by Cox & Brenner
//!   (Chem. Eng. Sci. 22, 1753, 1967, eq. 3.2) ([`jeffery_xc_wall`]); the shear-free
//!   counterpart ([`jeffery_xc_free_surface`]) was derived here by images and is checked
//!   by an explicit image sum in `exact_check.py`.
//! * Chaoui & Feuillebois, Q. J. Mech. Appl. Math. 56, 381 (2003), Tables 9-13 (module
//!   `chaoui_feuillebois`): published high-accuracy fits of `Y^A_w`, `T^t*`, `Y^C_w`. The
//!   GCB (1967) and O'Neill (1964) tables themselves were not found in the searchable
//!   corpus, so they are not used.
//!
//! No exact values of the two-sphere functions for motion *across* the line of centres
//! (`Y^A`, `Y^B`, `Y^C`: O'Neill & Majumdar 1970, Jeffrey & Onishi 1984 tables) were found
//! in the searchable corpus; none are provided here.
//!
//! # Numerics
//!
//! `alpha` is computed from `delta = h/a - 1` as `ln_1p(delta + sqrt(delta (2 + delta)))`
//! and `sinh alpha = sqrt(delta (2 + delta))`, so nothing is lost near contact. Every
//! hyperbolic function of `(n + 1/2) alpha` is carried scaled by `exp(-(n + 1/2) alpha)` (no
//! overflow for any `n`). The differences that cancel for small `alpha` are rewritten
//! exactly: `sinh(c b) - c sinh b` is summed from its Taylor series (all terms positive)
//! when `c b < 2`; `k_n = m coth(m alpha) - coth alpha` is `[g(m alpha) - g(alpha)]/alpha`
//! with `g(y) = y coth y - 1` from a positive series; the second difference of `coth` in
//! O'Neill's right-hand side is `-2 sinh^2(alpha) coth(m alpha) / (sinh((m+1) alpha)
//! sinh((m-1) alpha))`; Dean & O'Neill's right-hand side is put over a common
//! denominator in which every term is positive. Accuracy, measured against a 50-digit
//! evaluation at the exact binary inputs (`exact_check.py --tables`; tests
//! `wall_functions_match_40_digit_reference`, `two_sphere_functions_match_40_digit_reference`)
//! for `1.0001 <= h/a <= 100`: relative error below 2e-15 for `X^A_w`, `X^C_w`, `Y^C_w`,
//! below 2.5e-15 for the two-sphere functions (`1e-4 <= xi <= 1`) and below 8e-15 for
//! `Y^A_w`; for the couplings `T^t*`, `F^r*` below 4e-14 up to `h/a = 2`, but beyond that
//! their sums cancel from O(1) terms to `~(a/h)^4` and the relative error grows like
//! `1e-16 (2h/a)^5` (measured 9e-13 at `h/a = 3`, 1.8e-10 at 10, 3e-5 at 100), while the
//! absolute error stays below 4e-14.
//!
//! Conditioning: near contact the functions are sensitive to `h` itself (`X^A_w ~ a/(h -
//! a)`): `1.0001_f64` is `1 + 1e-4 (1 - 1.1e-12)`, which changes `X^A_w` by 1.1e-13
//! relative. Compare with references at the same binary `h/a` (or `eps = h/a - 1` computed
//! in f64).

use std::f64::consts::SQRT_2;

/// Apery's constant `zeta(3)`, the contact value of [`jeffery_xc_wall`].
pub const ZETA3: f64 = 1.202_056_903_159_594_3;

/// Relative size of the estimated remainder at which the axisymmetric series stop.
const SERIES_TOL: f64 = 1e-16;

/// Bispherical geometry from `delta = h/a - 1 > 0`.
#[derive(Clone, Copy, Debug)]
struct Geom {
    alpha: f64,
    /// `sinh alpha`
    s1: f64,
    /// `cosh alpha = h/a`
    c1: f64,
}

fn geom(delta: f64) -> Geom {
    assert!(
        delta.is_finite() && delta > 0.0,
        "exact series need a positive finite gap, got h/a - 1 = {delta}"
    );
    let s1 = (delta * (2.0 + delta)).sqrt();
    Geom {
        alpha: (delta + s1).ln_1p(),
        s1,
        c1: 1.0 + delta,
    }
}

fn geom_h(h_over_a: f64) -> Geom {
    assert!(
        h_over_a.is_finite() && h_over_a > 1.0,
        "h/a must be finite and > 1, got {h_over_a}"
    );
    geom(h_over_a - 1.0)
}

/// Neumaier (compensated) summation.
#[derive(Default)]
struct Sum {
    s: f64,
    c: f64,
}

impl Sum {
    fn add(&mut self, x: f64) {
        let t = self.s + x;
        if self.s.abs() >= x.abs() {
            self.c += (self.s - t) + x;
        } else {
            self.c += (x - t) + self.s;
        }
        self.s = t;
    }
    fn value(&self) -> f64 {
        self.s + self.c
    }
}

/// `exp(-c b) [sinh(c b) - c sinh b]` for `c > 1`, `b > 0`, given `sinh b`. Positive Taylor
/// series `sum_{k>=1} c (c^{2k} - 1) b^{2k+1}/(2k+1)!` when `c b < 2` (no cancellation),
/// the direct difference (relative loss below a factor 3) otherwise.
fn sinh_excess_scaled(c: f64, b: f64, sinh_b: f64) -> f64 {
    let x = c * b;
    if x < 2.0 {
        let b2 = b * b;
        let c2 = c * c;
        let mut u = b; // b^{2k+1}/(2k+1)!
        let mut c2k = 1.0; // c^{2k}
        let mut s = 0.0;
        for k in 1..60 {
            let kf = k as f64;
            u *= b2 / ((2.0 * kf) * (2.0 * kf + 1.0));
            c2k *= c2;
            let t = c * (c2k - 1.0) * u;
            s += t;
            if t <= 1e-17 * s {
                break;
            }
        }
        s * (-x).exp()
    } else {
        -0.5 * (-2.0 * x).exp_m1() - c * sinh_b * (-x).exp()
    }
}

/// `csch(z)` for `z > 0`, without overflow and accurate for small `z`.
fn csch(z: f64) -> f64 {
    2.0 * (-z).exp() / -(-2.0 * z).exp_m1()
}

/// `exp(-z) sinh z` for `z >= 0`.
fn sinh_scaled(z: f64) -> f64 {
    -0.5 * (-2.0 * z).exp_m1()
}

/// Sum of positive terms `t(n)`, `n = 1, 2, ...`, until the estimated remainder
/// `t_n q/(1 - q)` (with `q = max(t_n/t_{n-1}, q_asym)`, `q_asym` the asymptotic ratio)
/// falls below `SERIES_TOL` of the sum. Returns (sum, number of terms).
fn sum_positive(q_asym: f64, mut t: impl FnMut(usize) -> f64) -> (f64, usize) {
    let mut s = Sum::default();
    let mut prev = f64::INFINITY;
    let mut n = 1;
    loop {
        let tn = t(n);
        s.add(tn);
        let q = (tn / prev).max(q_asym);
        if tn == 0.0 || (n > 2 && q < 1.0 && tn * q / (1.0 - q) <= SERIES_TOL * s.value()) {
            return (s.value(), n);
        }
        assert!(n < 100_000_000, "series did not converge");
        prev = tn;
        n += 1;
    }
}

/// `n (n + 1) / ((2n - 1)(2n + 3))`.
fn brenner_weight(n: usize) -> f64 {
    let nf = n as f64;
    nf * (nf + 1.0) / ((2.0 * nf - 1.0) * (2.0 * nf + 3.0))
}

/// The numerator `2 sinh x + M sinh 2a` minus the denominator `4 sinh^2(x/2) - M^2 sinh^2
/// a` of Brenner's rigid-wall bracket, times `exp(-x)` (`x = M alpha`, `M = 2n + 1`): all
/// terms positive. Shared by the rigid-wall, free-surface (with `+ 2 exp(-x)`) and
/// Stimson-Jeffery series.
fn brenner_p(g: Geom, mf: f64, ex: f64, free: bool) -> f64 {
    let s2 = 2.0 * g.s1 * g.c1;
    let lead = if free {
        2.0 * (1.0 + ex)
    } else {
        2.0 * (1.0 - ex)
    };
    ex * (lead + mf * s2 + mf * mf * g.s1 * g.s1)
}

/// `exp(-x) [4 sinh^2(x/2) - M^2 sinh^2 alpha]`, `x = M alpha`.
fn brenner_d_wall(g: Geom, n: usize) -> f64 {
    let m = n as f64 + 0.5;
    let y = m * g.alpha;
    let ey = (-y).exp();
    4.0 * sinh_excess_scaled(m, g.alpha, g.s1) * (sinh_scaled(y) + m * g.s1 * ey)
}

/// Brenner's (1961) normal-approach coefficient for a rigid wall, eq. 2.19, with the
/// number of terms summed (relative accuracy 2e-15):
///
/// ```text
/// X^A_w = (4/3) sinh a sum_{n>=1} n(n+1)/((2n-1)(2n+3)) { [2 sinh((2n+1)a) + (2n+1) sinh 2a]
///          / [4 sinh^2((n+1/2)a) - (2n+1)^2 sinh^2 a] - 1 },        a = arccosh(h/a).
/// ```
///
/// Normalisation: `F_z = -6 pi mu a U_z X^A_w`. The bracket minus one is evaluated as
/// `[2(1 - e^{-x}) + M sinh 2a + M^2 sinh^2 a] e^{-x} / (e^{-x} D)` (`x = M a`, `M = 2n+1`,
/// all terms positive, `D` from the positive series of `sinh(x/2) - (x/2a) sinh a`).
/// Truncation: stop when the geometric estimate of the remainder is below 1e-16 of the
/// partial sum (terms decay like `n^2 exp(-2n a)`). Terms needed (measured by the tests):
/// 1164 at `h/a = 1.0001`, 7 at `h/a = 10`.
pub fn brenner_xa_wall_terms(h_over_a: f64) -> (f64, usize) {
    let g = geom_h(h_over_a);
    axisym(g, Kind::Wall)
}

/// [`brenner_xa_wall_terms`] without the term count: `X^A_w(h/a)`, rigid wall.
pub fn brenner_xa_wall(h_over_a: f64) -> f64 {
    brenner_xa_wall_terms(h_over_a).0
}

/// Brenner's (1961) normal-approach coefficient for a plane *free* surface (flat,
/// impermeable, shear-free), `F_z = -6 pi mu a U_z X`:
///
/// ```text
/// X = (4/3) sinh a sum_{n>=1} n(n+1)/((2n-1)(2n+3)) { [4 cosh^2((n+1/2)a) + (2n+1)^2 sinh^2 a]
///      / [2 sinh((2n+1)a) - (2n+1) sinh 2a] - 1 }.
/// ```
///
/// Same evaluation and truncation as [`brenner_xa_wall`]. Checked against the far-field
/// series of Jeffrey & Onishi (1984) for two spheres (`exact_check.py`, agreement to all
/// 17 printed digits at `h/a = 4`), and its near-contact form `1/(4 eps) + (9/40) ln(1/eps) +
/// ...` against the equal-sphere forms of Jeffrey & Onishi (1984) (tests).
pub fn brenner_xa_free_surface(h_over_a: f64) -> f64 {
    axisym(geom_h(h_over_a), Kind::Free).0
}

/// Stimson & Jeffery (1926): two equal spheres, centres `2 h` apart (so `cosh a = h/a`),
/// translating together with velocity `U` along their line of centres; drag on each
/// `= -6 pi mu a U X`,
///
/// ```text
/// X = (4/3) sinh a sum_{n>=1} n(n+1)/((2n-1)(2n+3)) { 1 - [4 sinh^2((n+1/2)a) - (2n+1)^2 sinh^2 a]
///      / [2 sinh((2n+1)a) + (2n+1) sinh 2a] }.
/// ```
///
/// Evaluated as `P/N` with the positive `P` of [`brenner_xa_wall`]; same truncation.
/// Limit at contact 0.6451414 (Jeffrey & Onishi 1984; measured 0.645141483632 at `xi =
/// 1e-6` by `exact_check.py`).
pub fn stimson_jeffery(h_over_a: f64) -> f64 {
    axisym(geom_h(h_over_a), Kind::Together).0
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Wall,
    Free,
    Together,
}

fn axisym(g: Geom, kind: Kind) -> (f64, usize) {
    let q_asym = (-2.0 * g.alpha).exp();
    let (s, n) = sum_positive(q_asym, |n| {
        let mf = 2.0 * n as f64 + 1.0;
        let x = mf * g.alpha;
        let ex = (-x).exp();
        let p = brenner_p(g, mf, ex, kind == Kind::Free);
        let den = match kind {
            Kind::Wall => brenner_d_wall(g, n),
            // exp(-x) [2 sinh x - M sinh 2a] = 2 exp(-x) [sinh(M a) - (M/2) sinh(2a)]
            Kind::Free => 2.0 * sinh_excess_scaled(0.5 * mf, 2.0 * g.alpha, 2.0 * g.s1 * g.c1),
            // exp(-x) [2 sinh x + M sinh 2a]
            Kind::Together => -(-2.0 * x).exp_m1() + mf * 2.0 * g.s1 * g.c1 * ex,
        };
        brenner_weight(n) * p / den
    });
    (4.0 / 3.0 * g.s1 * s, n)
}

/// Jeffery's (1915) couple on a sphere spinning about the normal to a rigid wall,
/// `L_z = -8 pi mu a^3 Omega_z X^C_w`:
///
/// ```text
/// X^C_w = sinh^3 a sum_{n>=1} csch^3(n a)        (-> zeta(3) at contact).
/// ```
///
/// Terms are `(sinh a / sinh n a)^3` with `csch` evaluated overflow-free. Truncation: as
/// for [`brenner_xa_wall`] (remainder estimate below 1e-16; the terms fall like `n^-3` until
/// `n a ~ 1`, then like `exp(-3 n a)`): 686 terms at `h/a = 1.0001`.
pub fn jeffery_xc_wall(h_over_a: f64) -> f64 {
    jeffery_xc_wall_terms(h_over_a).0
}

/// [`jeffery_xc_wall`] with the number of terms summed.
pub fn jeffery_xc_wall_terms(h_over_a: f64) -> (f64, usize) {
    jeffery_xc(geom_h(h_over_a))
}

/// [`jeffery_xc_wall_terms`] of a geometry.
fn jeffery_xc(g: Geom) -> (f64, usize) {
    sum_positive((-3.0 * g.alpha).exp(), |n| {
        (g.s1 * csch(n as f64 * g.alpha)).powi(3)
    })
}

/// The same couple next to a flat shear-free surface (`dv_phi/dz = 0` on `z = 0`):
/// the images of the rotlets alternate in sign,
///
/// ```text
/// X = sinh^3 a sum_{n>=1} (-1)^{n+1} csch^3(n a)       (-> (3/4) zeta(3) at contact).
/// ```
///
/// Derivation: `v_phi(rho, z) cos(phi)` is harmonic, so a spinning sphere is an x-dipole,
/// the plane reflects it with factor -1 (rigid) or +1 (shear-free) and the sphere (zero
/// Dirichlet data for the correction) by Kelvin inversion, `p -> -p (a/d)^3`; summing the
/// images reproduces Jeffery's rigid-wall sum and gives this one (checked to 20 digits in
/// `exact_check.py`). Alternating series: stops when a term is below 1e-16 of the sum.
pub fn jeffery_xc_free_surface(h_over_a: f64) -> f64 {
    let g = geom_h(h_over_a);
    let mut s = Sum::default();
    let mut n = 1usize;
    loop {
        let t = (g.s1 * csch(n as f64 * g.alpha)).powi(3);
        s.add(if n % 2 == 1 { t } else { -t });
        if t <= SERIES_TOL * s.value().abs() {
            return s.value();
        }
        n += 1;
    }
}

/// Two equal spheres, gap `xi = r/a - 2 > 0`, motion along the line of centres: `(X11A,
/// X12A)` in the Kim & Karrila normalisation (force on sphere 1 `= -6 pi mu a (X11A U_1 +
/// X12A U_2)` along `d`), exact:
///
/// ```text
/// X11A + X12A = stimson_jeffery(1 + xi/2),    X11A - X12A = brenner_xa_free_surface(1 + xi/2).
/// ```
///
/// Near contact (Jeffrey & Onishi 1984, equal spheres) `X11A = 1/(4 xi) + (9/40) ln(1/xi) + 0.99536 + (3/112)
/// xi ln(1/xi)`, `X12A = -X11A + 0.64514...`; far away `X11A -> 1`, `X12A -> -3/(2 rho)`.
pub fn two_sphere_xa(xi: f64) -> (f64, f64) {
    assert!(xi.is_finite() && xi > 0.0, "gap xi must be > 0, got {xi}");
    let g = geom(0.5 * xi);
    let sum = axisym(g, Kind::Together).0;
    let diff = axisym(g, Kind::Free).0;
    (0.5 * (sum + diff), 0.5 * (sum - diff))
}

/// Two equal spheres, gap `xi = r/a - 2 > 0`, rotation about the line of centres: `(X11C,
/// X12C)` (KK: torque on sphere 1 `= -8 pi mu a^3 (X11C Omega_1 + X12C Omega_2)` along `d`),
/// from Jeffery (1915):
///
/// ```text
/// X11C - X12C = jeffery_xc_wall(1 + xi/2),    X11C + X12C = jeffery_xc_free_surface(1 + xi/2).
/// ```
///
/// Contact values `X11C -> (7/8) zeta(3)`, `X12C -> -(1/8) zeta(3)`.
pub fn two_sphere_xc(xi: f64) -> (f64, f64) {
    assert!(xi.is_finite() && xi > 0.0, "gap xi must be > 0, got {xi}");
    let h = 1.0 + 0.5 * xi;
    let w = jeffery_xc_wall(h);
    let f = jeffery_xc_free_surface(h);
    (0.5 * (f + w), 0.5 * (f - w))
}

// ------------------------------------------------------------------ O'Neill / Dean & O'Neill

/// `g(y) = y coth y - 1`, `y > 0`, without cancellation: for `y < 1` the numerator `y cosh y
/// - sinh y = sum_{k>=1} 2k y^{2k+1}/(2k+1)!` (positive terms) over `sinh y`.
fn ycoth_m1(y: f64) -> f64 {
    if y < 1.0 {
        let y2 = y * y;
        let mut u = y; // y^{2k+1}/(2k+1)!
        let mut s = 0.0;
        for k in 1..40 {
            let kf = k as f64;
            u *= y2 / ((2.0 * kf) * (2.0 * kf + 1.0));
            let t = 2.0 * kf * u;
            s += t;
            if t <= 1e-17 * s {
                break;
            }
        }
        s / y.sinh()
    } else {
        y / y.tanh() - 1.0
    }
}

/// Number of unknowns `A_1 .. A_N` used by [`oneill_parallel`] and [`rotation_parallel`]:
/// `N = ceil(30/alpha) + 10`. The coefficients fall like `exp(-2 n alpha)`; with this `N`
/// doubling `N` changes the results by less than 1e-15 relative (tests). `N = 2132` at
/// `h/a = 1.0001`, 21 at `h/a = 10`.
pub fn oneill_terms(h_over_a: f64) -> usize {
    terms(geom_h(h_over_a))
}

/// [`oneill_terms`] of a geometry.
fn terms(g: Geom) -> usize {
    (30.0 / g.alpha).ceil() as usize + 10
}

/// Which parallel problem: translation (O'Neill 1964) or rotation (Dean & O'Neill 1963).
#[derive(Clone, Copy, PartialEq)]
enum Parallel {
    Translation,
    Rotation,
}

/// Solves O'Neill's tridiagonal system (eq. 23 of O'Neill 1964, shared by Dean & O'Neill
/// 1963) for `A_1 .. A_N` (`A_0 = A_{N+1} = 0`) and returns the two sums
/// `(sum_n [E_n + n(n+1) C_n], sum_n {(2 + e)[2n(n+1)A_n + n(n+1) C_n coth a - (2n+1 - coth a)
/// E_n] + (2 - e)[n(n+1) B_n coth a - (2n+1 - coth a) D_n]})`, `e = exp(-(2n+1)a)`.
fn parallel_sums(g: Geom, nmax: usize, which: Parallel) -> (f64, f64) {
    let a = g.alpha;
    let (s1, c1) = (g.s1, g.c1);
    let coth_a = c1 / s1;
    let ga = ycoth_m1(a);
    // k_n = m coth(m a) - coth a = [g(m a) - g(a)]/a, n = 0 ..= N+2
    let k: Vec<f64> = (0..nmax + 3)
        .map(|n| {
            let m = n as f64 + 0.5;
            (ycoth_m1(m * a) - ga) / a
        })
        .collect();

    // Tridiagonal system, rows n = 1..=N (index n-1).
    let mut lo = vec![0.0; nmax];
    let mut di = vec![0.0; nmax];
    let mut up = vec![0.0; nmax];
    let mut r = vec![0.0; nmax];
    for n in 1..=nmax {
        let nf = n as f64;
        let ca = (2.0 * nf - 1.0) * k[n - 1] - (2.0 * nf - 3.0) * k[n];
        let cb = (2.0 * nf + 5.0) * k[n] - (2.0 * nf + 3.0) * k[n + 1];
        lo[n - 1] = ca * (nf - 1.0) / (2.0 * nf - 1.0);
        di[n - 1] = -ca * nf / (2.0 * nf + 1.0) - cb * (nf + 1.0) / (2.0 * nf + 1.0);
        up[n - 1] = cb * (nf + 2.0) / (2.0 * nf + 3.0);
        let m = nf + 0.5;
        r[n - 1] = match which {
            // sqrt2 [2 coth(m a) - coth((m-1)a) - coth((m+1)a)]
            //   = -2 sqrt2 sinh^2 a coth(m a) csch((m+1)a) csch((m-1)a)
            Parallel::Translation => {
                -2.0 * SQRT_2 * s1 * s1 / (m * a).tanh() * csch((m + 1.0) * a) * csch((m - 1.0) * a)
            }
            // -sqrt2 e^{-m a}/(p sinh a) [p^2 (e^a/(p-2) + e^{-a}/(p+2)) csch(m a)
            //    - (p-2) csch((m-1)a) - (p+2) csch((m+1)a)],  p = 2n+1, over a common,
            // all-positive denominator (see module docs).
            Parallel::Rotation => {
                let p = 2.0 * nf + 1.0;
                let e = (-m * a).exp();
                let s0 = sinh_scaled(m * a);
                let c0 = 0.5 * (1.0 + e * e);
                let sm = sinh_scaled((m - 1.0) * a);
                let sp = sinh_scaled((m + 1.0) * a);
                let diff = 2.0 * sinh_excess_scaled(m, a, s1); // 2 e^{-m a}(sinh m a - m sinh a)
                let num = 2.0 * p * c1 * diff * (2.0 * s0 + p * s1 * e)
                    + 4.0 * (p * p - 4.0) * s0 * c0 * s1
                    + 4.0 * p * p * s1 * sm * sp;
                -SQRT_2 * e * e * num / ((p * p - 4.0) * p * s1 * s0 * sm * sp)
            }
        };
    }
    // Thomas algorithm.
    for i in 1..nmax {
        let w = lo[i] / di[i - 1];
        di[i] -= w * up[i - 1];
        r[i] -= w * r[i - 1];
    }
    // A[n], n = 0 ..= N+2 (A_0 = A_{N+1} = A_{N+2} = 0).
    let mut av = vec![0.0; nmax + 3];
    av[nmax] = r[nmax - 1] / di[nmax - 1];
    for i in (0..nmax - 1).rev() {
        av[i + 1] = (r[i] - up[i] * av[i + 2]) / di[i];
    }

    let mut sf = Sum::default();
    let mut st = Sum::default();
    for n in 0..=nmax + 1 {
        let nf = n as f64;
        let m = nf + 0.5;
        let an = av[n];
        let am = if n >= 1 { av[n - 1] } else { 0.0 };
        let ap = av[n + 1];
        let (bn, mut cn) = if n >= 1 {
            (
                (nf - 1.0) * am - (2.0 * nf + 1.0) * an + (nf + 2.0) * ap,
                2.0 * k[n]
                    * (an
                        - (nf + 2.0) / (2.0 * nf + 3.0) * ap
                        - (nf - 1.0) / (2.0 * nf - 1.0) * am),
            )
        } else {
            (0.0, 0.0)
        };
        let dn = 0.5 * (nf + 1.0) * (nf + 2.0) * ap - 0.5 * (nf - 1.0) * nf * am;
        let mut en = -k[n]
            * ((nf + 1.0) * (nf + 2.0) / (2.0 * nf + 3.0) * ap
                - (nf - 1.0) * nf / (2.0 * nf - 1.0) * am);
        let cs = csch(m * a);
        match which {
            // 2 sqrt2 e^{-m a} / sinh(m a)
            Parallel::Translation => en += 2.0 * SQRT_2 * (-m * a).exp() * cs,
            Parallel::Rotation => {
                let p = 2.0 * nf + 1.0;
                // L_n = -(1/sqrt2)(e^{-(n-1/2)a}/(2n-1) - e^{-(n+3/2)a}/(2n+3))
                let ln = -(-m * a).exp() * (2.0 * p * s1 + 4.0 * c1) / ((p * p - 4.0) * SQRT_2);
                if n >= 1 {
                    cn += 4.0 * ln / s1 * cs;
                }
                en += (SQRT_2 * p * (-m * a).exp() - ln / s1) * cs;
            }
        }
        let nn1 = nf * (nf + 1.0);
        sf.add(en + nn1 * cn);
        let e = (-(2.0 * nf + 1.0) * a).exp();
        let w = 2.0 * nf + 1.0 - coth_a;
        st.add((2.0 + e) * (2.0 * nn1 * an + nn1 * cn * coth_a - w * en));
        st.add((2.0 - e) * (nn1 * bn * coth_a - w * dn));
    }
    (sf.value(), st.value())
}

/// `(Y^A_w, T^t*)` of O'Neill (1964) with `N` unknowns; see [`oneill_parallel`].
pub fn oneill_parallel_truncated(h_over_a: f64, nmax: usize) -> (f64, f64) {
    translation(geom_h(h_over_a), nmax)
}

/// [`oneill_parallel_truncated`] of a geometry.
fn translation(g: Geom, nmax: usize) -> (f64, f64) {
    assert!(nmax >= 2);
    let (sf, st) = parallel_sums(g, nmax, Parallel::Translation);
    (SQRT_2 / 6.0 * g.s1 * sf, g.s1 * g.s1 / (12.0 * SQRT_2) * st)
}

/// Sphere translating parallel to a rigid wall (O'Neill 1964): `(Y^A_w, T^t*)` with
/// `F_x = -6 pi mu a U_x Y^A_w` and `L_y = +8 pi mu a^2 U_x T^t*`.
///
/// O'Neill's eq. 23 (tridiagonal in `A_n`, right-hand side `sqrt2 [2 coth((n+1/2)a) -
/// coth((n-1/2)a) - coth((n+3/2)a)]`), then `B_n .. E_n` and the force and torque sums
/// (eqs. 26, 27):
///
/// ```text
/// Y^A_w = (sqrt2/6) sinh a sum_n [E_n + n(n+1) C_n],
/// T^t*  = (sinh^2 a/(12 sqrt2)) sum_n {(2+e)[2n(n+1)A_n + n(n+1)C_n coth a - (2n+1-coth a)E_n]
///                                    + (2-e)[n(n+1)B_n coth a - (2n+1-coth a)D_n]},  e = e^{-(2n+1)a}.
/// ```
///
/// Truncation: `N = `[`oneill_terms`] unknowns, `A_{N+1} = 0`; sums to `n = N + 1`
/// (doubling `N` changes nothing at `1.0001 <= h/a <= 100`). Accuracy against a 50-digit
/// evaluation: `Y^A_w` 8e-15 relative; `T^t*` 4e-14 relative up to `h/a = 2`, then
/// `~1e-16 (2h/a)^5` relative (cancellation; 1.8e-10 at `h/a = 10`), absolute error below
/// 4e-14 everywhere (module docs). Validated against Chaoui & Feuillebois (2003) Tables
/// 9-11 (module `chaoui_feuillebois`). Cost: `O(N)` (the system is tridiagonal), N = 2132
/// at `h/a = 1.0001`.
pub fn oneill_parallel(h_over_a: f64) -> (f64, f64) {
    oneill_parallel_truncated(h_over_a, oneill_terms(h_over_a))
}

/// `(F^r*, Y^C_w)` of Dean & O'Neill (1963) with `N` unknowns; see [`rotation_parallel`].
pub fn rotation_parallel_truncated(h_over_a: f64, nmax: usize) -> (f64, f64) {
    rotation(geom_h(h_over_a), nmax)
}

/// [`rotation_parallel_truncated`] of a geometry.
fn rotation(g: Geom, nmax: usize) -> (f64, f64) {
    assert!(nmax >= 2);
    let (sf, st) = parallel_sums(g, nmax, Parallel::Rotation);
    (
        -SQRT_2 / 6.0 * g.s1 * g.s1 * sf,
        (1.0 - g.s1.powi(3) / (4.0 * SQRT_2) * st) / 3.0,
    )
}

/// Sphere rotating about an axis parallel to a rigid wall (Dean & O'Neill 1963, corrected
/// by GCB 1967): `(F^r*, Y^C_w)` with `F_x = +6 pi mu a^2 Omega_y F^r*` and `L_y = -8 pi mu
/// a^3 Omega_y Y^C_w`.
///
/// Same matrix as [`oneill_parallel`]; right-hand side (`m = n + 1/2`, `p = 2n + 1`)
///
/// ```text
/// -sqrt2 e^{-m a}/(p sinh a) [p^2 (e^a/(p-2) + e^{-a}/(p+2)) csch(m a)
///                             - (p-2) csch((m-1)a) - (p+2) csch((m+1)a)];
/// ```
///
/// `C_n` gains `4 L_n csch a csch(m a)` and `E_n` has the inhomogeneous part `(sqrt2 p
/// e^{-m a} - L_n csch a) csch(m a)` instead of O'Neill's, with `L_n = -(e^{-(m-1)a}/(p-2) -
/// e^{-(m+1)a}/(p+2))/sqrt2`; then
///
/// ```text
/// F^r* = -(sqrt2/6) sinh^2 a sum_n [E_n + n(n+1) C_n],
/// Y^C_w = (1/3) [1 - (sinh^3 a/(4 sqrt2)) (the torque sum of oneill_parallel)].
/// ```
///
/// Truncation, accuracy and cost as [`oneill_parallel`] (`Y^C_w` 2e-15 relative). The
/// reciprocity `F^r* = (4/3) T^t*` holds to 8e-14 relative for `h/a <= 2` and within the
/// rounding model of the couplings beyond (test `reciprocity_...`).
pub fn rotation_parallel(h_over_a: f64) -> (f64, f64) {
    rotation_parallel_truncated(h_over_a, oneill_terms(h_over_a))
}

/// The five sphere-wall functions `(X^A_w, Y^A_w, F^r*, Y^C_w, X^C_w)` of
/// [`brenner_xa_wall`], [`oneill_parallel`], [`rotation_parallel`] and
/// [`jeffery_xc_wall`] at the gap over radius `eps = h/a - 1` given as such: the
/// bispherical geometry is computed from `eps` itself, not from `h/a = 1 + eps`, whose
/// rounding alone would change `eps` by `1e-16/eps` relative (1e-9 at `eps = 1e-7`, and
/// `X^A_w ~ 1/eps` with it).
pub fn wall_functions_at_gap(eps: f64) -> [f64; 5] {
    let g = geom(eps);
    let (ya, _) = translation(g, terms(g));
    let (fr, yc) = rotation(g, terms(g));
    [axisym(g, Kind::Wall).0, ya, fr, yc, jeffery_xc(g).0]
}
