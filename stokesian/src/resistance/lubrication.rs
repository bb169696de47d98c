//! The resistance with lubrication, Swan & Brady Eq. 19:
//! `R = M^-1 + R^P + R^W - (R^{P,inf} + R^{W,inf})`, at the FT and FTS levels.
//!
//! - `R^P`: the exact two-sphere resistance ([`crate::resistance::two_sphere`]: Jeffrey & Onishi
//!   1984 and Jeffrey 1992 as corrected by Townsend 2023, any size ratio, Kim & Karrila
//!   normalisation; all 22 functions at FTS; from the generated tables of
//!   [`crate::resistance::pair_tables`], no series built at run time), for every pair whose correction may
//!   exceed a stated tolerance, switched off smoothly beyond ([`Lubrication::pair_window`]:
//!   no step, no kink); `R^{P,inf}` the inverse of the FT or FTS mobility of the
//!   isolated pair in unbounded fluid, from our own kernels.
//! - `R^W`: the exact sphere-wall resistance (Brenner 1961; O'Neill 1964; Dean & O'Neill
//!   1963 with Goldman, Cox & Brenner 1967; Jeffery 1915), from the generated tables of
//!   [`crate::resistance::wall_tables`], for every sphere and every boundary the
//!   confinement declares no-slip (`Confinement::boundaries`, any unit normal `n`), with
//!   `eps = (h - a)/a < wall_cutoff`, `h` the distance along `n` (by default
//!   every sphere closer than 1000 radii, beyond which `R^W` equals `R^{W,inf}` to 1e-12:
//!   no switch, the correction is continuous and smooth in the height);
//!   `R^{W,inf}` the inverse of the self mobility of the sphere with that wall alone,
//!   from our kernels: for a plane `x3 = const` the wall's own, for any other normal the
//!   wall `x3 = 0`'s at the same distance turned by the rotation taking `e3` to `n`
//!   ([`crate::mobility::rotation`]), which is the single wall of that normal exactly. At
//!   FTS the wall's stresslet rows keep the far-field inverse.
//! - `R^W` at a flat free surface (every boundary declared a free surface, its image
//!   along the normal): exact in every block, stresslets included, because
//!   the sphere and its mirror image are two equal spheres (`s' = 2h/a`) moving as
//!   each other's reflection; switched off like a pair correction; `R^{W,inf}` the
//!   inverse of our own free-surface self mobility (turned like the wall's).
//!
//! The near-contact coefficients are those of the literature cited where they are used
//! (two spheres: Jeffrey & Onishi 1984, Jeffrey 1992, as corrected by Townsend 2023; a
//! sphere and a wall: Brenner 1961, Cox & Brenner 1967, Goldman, Cox & Brenner 1967),
//! each checked against the exact series (`docs/lubrication.md`, "Reference formulas").
//!
//! Sign: the resistance maps `(U, Omega)` to the force and torque the particles exert
//! on the fluid (the inverse of the mobility's convention), so every lubrication block
//! enters with the sign of a positive-definite resistance.

use super::pair_tables::{self, AtRatio};
use super::tensors::{mirror, pair_block, wall_block};
use super::two_sphere::{PairScalars, PairSeries, TwoSphereError};
use super::wall_tables::EPS_MAX;
use crate::linalg::Cholesky;
use crate::mobility::rotation;
use crate::system::{global, Moments, System};
use kernels::{pair, pair_ft, self_ft, self_mobility, Boundary, Condition, Confinement};
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::collections::HashMap;
use thiserror::Error;

/// Where lubrication is switched on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lubrication {
    /// The two-sphere correction `R^P - R^{P,inf}` is kept in full wherever it may exceed
    /// this tolerance (its largest entry, lengths in units of the larger radius, over the
    /// drag `6 pi eta a` of the smaller sphere),
    /// and switched off smoothly beyond ([`Lubrication::pair_window`]): `0` keeps it at
    /// every separation, `INFINITY` drops it everywhere.
    pub pair_tolerance: f64,
    /// Spheres with gap over radius `eps < wall_cutoff` from a no-slip wall get
    /// `R^W - R^{W,inf}` (never beyond [`EPS_MAX`], where it is below
    /// 1e-12 of the far field).
    pub wall_cutoff: f64,
}

impl Default for Lubrication {
    /// Pairs: tolerance 1e-6 (the correction kept in full out to `s' = 52.3` at FT and
    /// `s' = 17.6` at FTS, `s' = 2r/(a1 + a2)`), so that two spheres get the exact
    /// functions to 1e-6 of the smaller sphere's drag at every separation; 1e-3 (out to
    /// `s' = 9.3` and 5.6) costs a quarter to a third less in a dense suspension and
    /// drops corrections that add up to 0.6% of a diagonal entry there (docs/lubrication.md). Wall: no
    /// cutoff (`INFINITY`):
    /// the exact sphere-wall functions from the tables wherever they differ from the far
    /// field by more than 1e-12, so that the resistance is continuous and smooth in the
    /// height.
    fn default() -> Self {
        Lubrication {
            pair_tolerance: 1e-6,
            wall_cutoff: f64::INFINITY,
        }
    }
}

/// Far from contact the largest entry of the two-sphere correction `R^P - R^{P,inf}`
/// (lengths in units of the larger radius) over `6 pi eta a_min` is below `C s'^-k`: `(C, k)` at FT and FTS. Measured
/// over `lambda = 0.01, 0.03, 0.1, 0.3, 1` (the others follow by exchanging the spheres)
/// and `s' = 3 ... 40`: the correction decays as `s'^-4` at FT (the far-field FT mobility
/// misses the `O(r^-4)` reflections) and as `s'^-6` at FTS; the largest products were
/// 7.4 (FT, `lambda = 0.3`, `s' = 3`) and 29.6 (FTS, `lambda = 0.3`, `s' = 3`). Test
/// `pair_correction_is_below_the_tolerance_outside_its_window`.
const PAIR_DECAY: [(f64, i32); 2] = [(7.5, 4), (30.0, 6)];

impl Lubrication {
    /// No correction anywhere: the resistance is the inverse of the far-field mobility.
    pub const fn none() -> Self {
        Lubrication {
            pair_tolerance: f64::INFINITY,
            wall_cutoff: 0.0,
        }
    }

    /// Lubrication with the two-sphere correction at every separation and the
    /// sphere-wall correction at every height.
    pub fn everywhere() -> Self {
        Lubrication {
            pair_tolerance: 0.0,
            wall_cutoff: f64::INFINITY,
        }
    }

    /// The same with the pair tolerance `tol` ([`Lubrication::pair_tolerance`]).
    pub fn with_pair_tolerance(self, tol: f64) -> Self {
        Lubrication {
            pair_tolerance: tol,
            ..self
        }
    }

    /// The settings are usable: a pair tolerance `>= 0` (`INFINITY` switches the pair
    /// correction off) and a wall cutoff that is not NaN. [`System::resistance`] checks
    /// them before anything is computed.
    pub fn check(&self) -> Result<(), ResistanceError> {
        if self.pair_tolerance.is_nan() || self.pair_tolerance < 0.0 {
            return Err(ResistanceError::Setting {
                what: "pair tolerance",
                value: self.pair_tolerance,
                need: "must be a number >= 0 (0: every pair corrected; inf: none)",
            });
        }
        if self.wall_cutoff.is_nan() {
            return Err(ResistanceError::Setting {
                what: "wall cutoff",
                value: self.wall_cutoff,
                need: "must be a number (inf: every height; 0 or below: no wall correction)",
            });
        }
        Ok(())
    }

    /// The separations `(s0, s1)`, `s' = 2r/(a1 + a2)`, between which the pair correction
    /// is switched off: in full below `s0 = (C/tol)^(1/k)` (the bound of `PAIR_DECAY`, so
    /// that beyond `s0` it is below the tolerance), times a quintic smoothstep falling
    /// from 1 to 0 on `[s0, 1.25 s0]` (continuous with two continuous derivatives), and
    /// not at all beyond. `moments` is FT or FTS (F has no lubrication).
    pub fn pair_window(&self, moments: Moments) -> (f64, f64) {
        let (c, k) = PAIR_DECAY[usize::from(moments == Moments::FTS)];
        let s0 = (c / self.pair_tolerance).powf(1.0 / f64::from(k));
        (s0, 1.25 * s0)
    }
}

/// The weight of the pair correction at `s'` for the window `(s0, s1)`
/// ([`Lubrication::pair_window`]): 1 below `s0`, 0 above `s1`, `1 - x^3 (10 - 15 x + 6 x^2)`
/// between, `x = (s' - s0)/(s1 - s0)`.
fn pair_weight(s_dash: f64, (s0, s1): (f64, f64)) -> f64 {
    if s_dash <= s0 {
        1.0
    } else if s_dash >= s1 {
        0.0
    } else {
        let x = (s_dash - s0) / (s1 - s0);
        1.0 - x * x * x * (10.0 + x * (-15.0 + 6.0 * x))
    }
}

/// Why a resistance cannot be formed.
#[derive(Debug, Error, PartialEq)]
pub enum ResistanceError {
    /// A setting of [`Lubrication`] out of its range.
    #[error("lubrication: the {what} is {value}: it {need}")]
    Setting {
        /// Which setting.
        what: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        need: &'static str,
    },
    /// The F level has no rotations, so no resistance with lubrication.
    #[error("lubrication needs torques and rotations: use FT or FTS (asked for {0:?})")]
    Unsupported(Moments),
    /// The two-sphere functions cannot be evaluated (size ratio beyond 1e2).
    #[error("pair lubrication: {0}")]
    TwoSphere(TwoSphereError),
    /// The far-field mobility is not positive definite (overlaps, narrow slit).
    #[error("the far-field mobility is not positive definite, so it cannot be inverted (overlapping spheres or a slit too narrow for the superposition)")]
    MobilityNotPositiveDefinite,
    /// The corrected resistance is not positive definite.
    #[error("the resistance with lubrication is not positive definite")]
    ResistanceNotPositiveDefinite,
    /// Spheres overlap or cut a boundary with [`crate::Overlap::Rpy`]: lubrication has
    /// no overlap form.
    #[error("{0}")]
    Overlap(#[from] crate::system::overlap::OverlapError),
    /// Lubrication in a periodic box ([`crate::periodic`]).
    #[error("{0}")]
    Periodic(#[from] crate::periodic::PeriodicError),
}

/// The self mobility (per-particle layout `[U, Omega, E]`, truncated to `k` = 6 or 11
/// components) of a sphere at `x` with the boundary `b` alone (a no-slip wall or a free
/// surface: Blake's image, or the mirror image), turned to `b`'s normal by
/// [`about_boundary`].
fn single_boundary_self(b: &Boundary, eta: f64, x: [f64; 3], a: f64, k: usize) -> DMatrix<f64> {
    about_boundary(b, x, k, |height, y, _| {
        let plane = match b.condition {
            Condition::NoSlip => Confinement::Wall { height },
            Condition::FreeSurface => Confinement::FreeSurface { height },
            Condition::Interface => unreachable!("no lubrication at a liquid-liquid interface"),
        };
        let m = self_mobility(&plane, eta, y, a).matrix();
        DMatrix::from_fn(k, k, |i, j| m[(i, j)])
    })
}

/// A `k x k` quantity of a sphere at `x` and the plane boundary `b` alone, from
/// `f(c, y, up)`, the same quantity of a sphere at `y` and a plane `x3 = c` whose normal
/// into the fluid is `up e3` (`up = +-1`):
/// - a plane normal to `e3` (`n = +-e3`): `f(n . e3 offset, x, n3)` in the world frame
///   itself, the plane's own kernels (a horizontal plane's image holds on either side of
///   it, as Blake's does for the slit's upper wall: kernel-gen `green::slit`);
/// - any other normal: `Q f(0, [0, 0, d], 1) Q^T`, the sphere at its distance `d` above
///   the plane `x3 = 0`, turned by the rotation `R` taking `e3` to `n`
///   ([`crate::mobility::rotation`]: `Q = diag(R, R, Q5)`).
fn about_boundary(
    b: &Boundary,
    x: [f64; 3],
    k: usize,
    f: impl FnOnce(f64, [f64; 3], f64) -> DMatrix<f64>,
) -> DMatrix<f64> {
    if b.is_horizontal() {
        return f(b.offset * b.normal[2], x, b.normal[2]);
    }
    let q = rotation::on_components(&rotation::taking_e3_to(b.normal), k);
    let m = f(0.0, [0.0, 0.0, b.distance(x)], 1.0);
    &q * m * q.transpose()
}

/// `R^W` of a sphere of radius `a` at distance `h` from a flat free surface `x3 = const`
/// whose normal into the fluid is `up e3` (`k` = 6 or 11 components, every block exact):
/// by symmetry the sphere and its mirror image moving as its reflection, two equal
/// spheres at `s' = 2h/a` (`f`, the two-sphere functions there at size ratio 1), so
/// `R^W = R_11 + R_12 Q` with the two-sphere blocks seen from the sphere (the image along
/// `-up e3`) and `Q` the mirror map (Brenner 1961 for the
/// normal translation, `X11A - X12A`; Jeffery 1915 for the rotation about the normal,
/// `X11C + X12C`; the others by the same reflection).
fn free_surface_block(f: PairScalars, eta: f64, a: f64, up: f64, k: usize) -> DMatrix<f64> {
    let pair = pair_block(eta, [(a, f), (a, f)], [0.0, 0.0, -up], k);
    let r11 = pair.view((0, 0), (k, k));
    let r12 = pair.view((0, k), (k, k));
    r11 + r12 * mirror(k)
}

/// Occurrences of a size ratio among the close pairs from which the tables contracted at
/// it ([`AtRatio`]) pay: building one costs as much as 300 (near contact) to 700 (far)
/// calls of [`pair_tables::scalars`], and each of its calls then costs about a third of
/// one (the cost test of the two-sphere integration tests); at 64 shared calls a build
/// costs at most about as much as 300 calls more than it saves, and a ratio shared by
/// fewer stays on the two-dimensional tables.
const SHARED_RATIO: usize = 64;

/// The two-sphere functions of the pairs of one resistance, from the generated tables
/// ([`crate::resistance::pair_tables`], far and near, within 6.6e-10 (near) and 3.8e-11 (far) of the
/// series): contracted once at each size ratio that at least [`SHARED_RATIO`] of the
/// calls need ([`AtRatio`]), evaluated in two dimensions at the others (the same
/// functions to rounding); only if a committed table file does not have its table's
/// shape, from the series, built once per size ratio in the process
/// ([`PairSeries::cached_at`]).
struct PairFunctions {
    /// The tables at each shared ratio, by the ratio's bits.
    at: HashMap<u64, AtRatio>,
}

impl PairFunctions {
    /// For calls at the size ratios `ratios` (one item per call).
    fn new(ratios: impl Iterator<Item = f64>) -> Self {
        let mut count: HashMap<u64, usize> = HashMap::new();
        for lambda in ratios {
            *count.entry(lambda.to_bits()).or_default() += 1;
        }
        let at = count
            .into_par_iter()
            .filter(|&(_, n)| n >= SHARED_RATIO)
            .filter_map(|(bits, _)| AtRatio::new(f64::from_bits(bits)).map(|t| (bits, t)))
            .collect();
        PairFunctions { at }
    }

    /// The functions at `s_dash` seen from a sphere whose partner is `lambda` times its
    /// size (all 22, or the ten force-torque ones when `ft_only`).
    fn scalars(
        &self,
        s_dash: f64,
        lambda: f64,
        ft_only: bool,
    ) -> Result<PairScalars, ResistanceError> {
        let count = if ft_only { 10 } else { 22 };
        let tables = match self.at.get(&lambda.to_bits()) {
            Some(at) => at.scalars(s_dash, count),
            None => pair_tables::scalars(s_dash, lambda, count),
        };
        tables.map_or_else(|| Self::series(s_dash, lambda, ft_only), Ok)
    }

    /// The functions of one pair at `s_dash` seen from each sphere, `lambdas` its
    /// partner's size over its own (as [`PairFunctions::scalars`] for each, the same
    /// numbers; from the two-dimensional tables in one call, which locates the
    /// separation once).
    fn pair(
        &self,
        s_dash: f64,
        lambdas: [f64; 2],
        ft_only: bool,
    ) -> Result<[PairScalars; 2], ResistanceError> {
        let count = if ft_only { 10 } else { 22 };
        let shared = lambdas.map(|l| self.at.get(&l.to_bits()));
        let tables = match shared {
            [Some(first), Some(second)] => first
                .scalars(s_dash, count)
                .zip(second.scalars(s_dash, count))
                .map(<[PairScalars; 2]>::from),
            _ => pair_tables::pair_scalars(s_dash, lambdas, count),
        };
        match tables {
            Some(views) => Ok(views),
            None => Ok([
                Self::series(s_dash, lambdas[0], ft_only)?,
                Self::series(s_dash, lambdas[1], ft_only)?,
            ]),
        }
    }

    /// The functions from the series (if a committed table file does not have its
    /// table's shape).
    fn series(s_dash: f64, lambda: f64, ft_only: bool) -> Result<PairScalars, ResistanceError> {
        PairSeries::cached_at(lambda, ft_only, s_dash)
            .and_then(|s| s.scalars(s_dash))
            .map_err(ResistanceError::TwoSphere)
    }
}

/// The mobility of an isolated pair of spheres in unbounded fluid, per-particle layout
/// `[U_1, Omega_1, E_1, U_2, Omega_2, E_2]` truncated to `k` = 6 or 11 components each.
fn free_pair_mobility(
    eta: f64,
    (x1, a1): ([f64; 3], f64),
    (x2, a2): ([f64; 3], f64),
    k: usize,
) -> DMatrix<f64> {
    let free = &Confinement::Free;
    let assemble = |s1: &dyn Fn(usize, usize) -> f64,
                    s2: &dyn Fn(usize, usize) -> f64,
                    p: &dyn Fn(usize, usize) -> f64| {
        DMatrix::from_fn(2 * k, 2 * k, |i, j| match (i / k, j / k) {
            (0, 0) => s1(i, j),
            (1, 1) => s2(i - k, j - k),
            (0, 1) => p(i, j - k),
            _ => p(j, i - k),
        })
    };
    if k == 6 {
        // the FT kernels: the FTS ones would compute the stresslet blocks to drop them
        let s1 = self_ft(free, eta, x1, a1).matrix();
        let s2 = self_ft(free, eta, x2, a2).matrix();
        let p = pair_ft(free, eta, x1, a1, x2, a2).matrix();
        assemble(&|i, j| s1[i][j], &|i, j| s2[i][j], &|i, j| p[i][j])
    } else {
        let s1 = self_mobility(free, eta, x1, a1).matrix();
        let s2 = self_mobility(free, eta, x2, a2).matrix();
        let p = pair(free, eta, x1, a1, x2, a2).matrix();
        assemble(&|i, j| s1[(i, j)], &|i, j| s2[(i, j)], &|i, j| p[(i, j)])
    }
}

/// Add `weight (exact - far^-1)` to `r` on the rows and columns `idx` (per-particle blocks of
/// `k` components): where the exact resistance is known, which is the leading `known`
/// components of each particle (`known` = 6: force-torque only); elsewhere the
/// far-field inverse is kept (the correction is zero).
fn add_correction(
    r: &mut DMatrix<f64>,
    idx: &[usize],
    exact: &DMatrix<f64>,
    far: DMatrix<f64>,
    k: usize,
    known: usize,
    weight: f64,
) -> Result<(), ResistanceError> {
    let c = correction(exact, far, k, known, weight)?;
    scatter(r, idx, &c, k, known);
    Ok(())
}

/// `weight (exact - far^-1)` in the layout of `far` (particles of `k` components; `exact`
/// holds the leading `known` of each), zero where the exact resistance is not known.
fn correction(
    exact: &DMatrix<f64>,
    far: DMatrix<f64>,
    k: usize,
    known: usize,
    weight: f64,
) -> Result<DMatrix<f64>, ResistanceError> {
    let far_inv = Cholesky::new(&far)
        .ok_or(ResistanceError::MobilityNotPositiveDefinite)?
        .inverse();
    let ek = exact.nrows() / (far.nrows() / k); // components per particle in `exact`
    let local = |i: usize| (i / k) * ek + i % k;
    Ok(DMatrix::from_fn(far.nrows(), far.ncols(), |i, j| {
        if i % k < known && j % k < known {
            weight * (exact[(local(i), local(j))] - far_inv[(i, j)])
        } else {
            0.0
        }
    }))
}

/// Add the correction `c` (from [`correction`]) to `r` on the rows and columns `idx`.
fn scatter(r: &mut DMatrix<f64>, idx: &[usize], c: &DMatrix<f64>, k: usize, known: usize) {
    for i in 0..idx.len() {
        for j in 0..idx.len() {
            if i % k < known && j % k < known {
                r[(idx[i], idx[j])] += c[(i, j)];
            }
        }
    }
}

/// Two spheres within the window of the pair correction: `a <= b`, `b` (or, in a
/// periodic box, one of its images: `a == b` for a sphere's own image) at `xb`.
struct ClosePair {
    a: usize,
    b: usize,
    /// `xb - x_a`.
    r: [f64; 3],
    /// `|r|`.
    dist: f64,
    /// The source's centre (the image's, in a periodic box).
    xb: [f64; 3],
    /// The window's weight ([`pair_weight`]).
    weight: f64,
}

impl System {
    /// The pairs within the window `(s0, s1)` in a fixed order: each unordered pair once
    /// and, in a periodic box, every image of the second sphere within the window (and
    /// every sphere with its own images, one of each `+-n`).
    fn close_pairs(&self, window: (f64, f64)) -> Vec<ClosePair> {
        let ps = self.particles();
        let n = ps.len();
        let pair = |a: usize, b: usize, r: [f64; 3], xb: [f64; 3]| {
            let dist = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
            let weight = pair_weight(2.0 * dist / (ps[a].a + ps[b].a), window);
            (weight != 0.0).then_some(ClosePair {
                a,
                b,
                r,
                dist,
                xb,
                weight,
            })
        };
        let Some(bx) = self.periodic_box() else {
            return (0..n)
                .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
                .filter_map(|(a, b)| {
                    let (x, y) = (ps[a].x, ps[b].x);
                    pair(a, b, std::array::from_fn(|c| y[c] - x[c]), y)
                })
                .collect();
        };
        // beyond s' = s1 the weight is 0
        let reach = |a: usize, b: usize| 0.5 * window.1 * (ps[a].a + ps[b].a);
        (0..n)
            .flat_map(|a| (a..n).map(move |b| (a, b)))
            .flat_map(|(a, b)| {
                let x = ps[a].x;
                let images = if a == b {
                    bx.own_images(reach(a, a))
                } else {
                    bx.separations(x, ps[b].x, reach(a, b))
                };
                images.into_iter().filter_map(move |r| {
                    let xb = std::array::from_fn(|c| x[c] + r[c]);
                    pair(a, b, r, xb)
                })
            })
            .collect()
    }
}

impl System {
    /// The grand resistance with lubrication (Eq. 19) at the FT or FTS level, in the
    /// layout of [`System::mobility`] with rows `(F, L[, S])` and columns
    /// `(U, Omega[, -E_inf])`. At FTS the pair and free-surface corrections cover every
    /// block; the no-slip walls' only the force-torque blocks (exact sphere-wall
    /// stresslet functions are not available), their stresslet rows and columns keep the
    /// far-field inverse. Overlapping spheres are rejected at construction unless allowed;
    /// with [`crate::Overlap::Rpy`] here ([`ResistanceError::Overlap`]). In a periodic box
    /// `M^-1` is the periodic mobility's and the pair corrections are added for every image
    /// within the window ([`crate::periodic`]); a sphere and its own image move, rotate and
    /// strain alike, so their four blocks add on its diagonal block at FTS as at FT (FTS
    /// in the triply periodic box; near periodic walls the mobility is FT).
    pub fn resistance(
        &self,
        moments: Moments,
        lub: &Lubrication,
    ) -> Result<DMatrix<f64>, ResistanceError> {
        let k = match moments {
            Moments::FT => 6,
            Moments::FTS => 11,
            Moments::F => return Err(ResistanceError::Unsupported(moments)),
        };
        lub.check()?;
        if let Some(rpy) = self.rpy() {
            rpy.refuse("lubrication")?;
        }
        let parts = moments.parts();
        let n = self.len();
        let eta = self.viscosity();
        let ps = self.particles();
        let m = self.mobility(moments);
        let mut r = Cholesky::new(&m)
            .ok_or(ResistanceError::MobilityNotPositiveDefinite)?
            .inverse();
        let boundaries = self.confinement().boundaries();
        // R^W - R^{W,inf}, per sphere and no-slip boundary (of any normal).
        for (a, p) in ps.iter().enumerate() {
            for b in boundaries
                .iter()
                .filter(|b| b.condition == Condition::NoSlip)
            {
                let eps = (b.distance(p.x) - p.a) / p.a;
                if eps >= lub.wall_cutoff || eps > EPS_MAX {
                    continue;
                }
                let block = wall_block(eta, p.a, eps, b.normal);
                let exact = DMatrix::from_fn(6, 6, |i, j| block[(i, j)]);
                let idx: Vec<usize> = (0..k).map(|c| global(parts, n, a, c)).collect();
                let far = single_boundary_self(b, eta, p.x, p.a, k);
                add_correction(&mut r, &idx, &exact, far, k, 6, 1.0)?;
            }
        }
        // R^P - R^{P,inf}, per close pair (all 22 two-sphere functions at FTS, the ten
        // force-torque ones at FT: PairFunctions)
        let window = lub.pair_window(moments);
        // R^W - R^{W,inf} at a free surface: a pair correction, sphere and image (equal
        // spheres), for the spheres within the window
        let surface: Vec<(usize, &Boundary, f64, f64)> = boundaries
            .iter()
            .filter(|b| b.condition == Condition::FreeSurface)
            .flat_map(|b| {
                ps.iter().enumerate().filter_map(move |(a, p)| {
                    let s_dash = 2.0 * b.distance(p.x) / p.a;
                    let weight = pair_weight(s_dash, window);
                    (weight != 0.0).then_some((a, b, s_dash, weight))
                })
            })
            .collect();
        // the pairs within the window, in order; their corrections evaluated in parallel
        // and added in that order, so the sum does not depend on the threads
        let close = self.close_pairs(window);
        let functions = PairFunctions::new(
            surface.iter().map(|_| 1.0).chain(
                close
                    .iter()
                    .flat_map(|c| [ps[c.b].a / ps[c.a].a, ps[c.a].a / ps[c.b].a]),
            ),
        );
        for &(a, b, s_dash, weight) in &surface {
            let p = &ps[a];
            let f = functions.scalars(s_dash, 1.0, k != 11)?;
            let exact =
                about_boundary(b, p.x, k, |_, _, up| free_surface_block(f, eta, p.a, up, k));
            let idx: Vec<usize> = (0..k).map(|c| global(parts, n, a, c)).collect();
            let far = single_boundary_self(b, eta, p.x, p.a, k);
            add_correction(&mut r, &idx, &exact, far, k, k, weight)?;
        }
        // (in chunks, so that the corrections waiting to be added stay a few MB)
        for chunk in close.chunks(2048) {
            let corrections: Vec<DMatrix<f64>> = chunk
                .par_iter()
                .map(|c| {
                    let (p, q) = (&ps[c.a], &ps[c.b]);
                    let s_dash = 2.0 * c.dist / (p.a + q.a);
                    let [fi, fj] = functions.pair(s_dash, [q.a / p.a, p.a / q.a], k != 11)?;
                    let d: [f64; 3] = std::array::from_fn(|i| c.r[i] / c.dist);
                    let exact = pair_block(eta, [(p.a, fi), (q.a, fj)], d, k);
                    let far = free_pair_mobility(eta, (p.x, p.a), (c.xb, q.a), k);
                    correction(&exact, far, k, k, c.weight)
                })
                .collect::<Result<_, _>>()?;
            // a sphere and its own image (a == b): the four blocks add on its diagonal
            // block, which is the correction of the sphere moving with its image
            for (&ClosePair { a, b, .. }, c) in chunk.iter().zip(&corrections) {
                let idx: Vec<usize> = (0..2 * k)
                    .map(|i| global(parts, n, if i < k { a } else { b }, i % k))
                    .collect();
                scatter(&mut r, &idx, c, k, k);
            }
        }
        // Exact symmetry (the corrections are symmetric to round-off).
        let r = (&r + r.transpose()) * 0.5;
        Ok(r)
    }
}

/// Velocities from forces with lubrication: `R x = f` solved by Cholesky.
/// Returns the solution and a condition estimate `(max L_ii / min L_ii)^2` of `R`
/// (a lower bound on the 2-norm condition number, cheap from the factor).
pub fn solve_resistance(r: &DMatrix<f64>, f: &[f64]) -> Result<(Vec<f64>, f64), ResistanceError> {
    let c = Cholesky::new(r).ok_or(ResistanceError::ResistanceNotPositiveDefinite)?;
    let (mx, mn) = c
        .diagonal()
        .iter()
        .fold((0.0f64, f64::INFINITY), |(mx, mn), &v| {
            (mx.max(v), mn.min(v))
        });
    Ok((c.solve(f), (mx / mn).powi(2)))
}

/// Velocities of rigid spheres from forces, torques and an imposed strain with the FTS
/// resistance `r` (`11N x 11N`, rows `F, L, S`, columns `U - U_inf, Omega - Omega_inf,
/// -E_inf`): the force-torque rows give
/// `R_{FL,U Omega} (U - U_inf, Omega - Omega_inf) = (F, L) - R_{FL,E} (-E_inf)`, solved by
/// [`solve_resistance`]. Returns the `6N` velocities (moment-major) and the condition
/// estimate of the force-torque block.
pub fn solve_resistance_fts(
    r: &DMatrix<f64>,
    fl: &[f64],
    e_inf: &[f64; 5],
) -> Result<(Vec<f64>, f64), ResistanceError> {
    let n = r.nrows() / 11;
    let y_e = nalgebra::DVector::from_fn(5 * n, |i, _| -e_inf[i % 5]);
    let rhs = nalgebra::DVector::from_column_slice(fl) - r.view((0, 6 * n), (6 * n, 5 * n)) * y_e;
    let block = r.view((0, 0), (6 * n, 6 * n)).into_owned();
    solve_resistance(&block, rhs.as_slice())
}
