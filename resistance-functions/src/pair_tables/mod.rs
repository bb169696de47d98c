//! Generated tables of the 22 two-sphere resistance functions at every separation `s' =
//! 2r/(a1 + a2) > 2` and size ratio `lambda = a2/a1` in `[1e-2, 1e2]`: 2-D Chebyshev
//! fits made by `cargo xtask gen` from the twin-multipole series of
//! [`crate::two_sphere`] and committed in `src/generated/two_sphere_far.bin` and
//! `src/generated/two_sphere_near.bin`. No series is built at run time.
//!
//! - **Far** (`s' >= S_MIN = 3`): each function is a power series in `t = 2/s'` with
//!   coefficients that are polynomials in `mu = lambda/(1 + lambda)` ([`crate::two_sphere`],
//!   module docs): analytic on `t < 1`, so on `t <= 2/3` a few terms in `t` and `mu`
//!   fit it to 4e-11 with no singular part to take out (the lubrication singularities
//!   sit at contact, `t = 1`).
//! - **Near** (`2 < s' < 3`, gap `xi = s' - 2` in `(0, 1)`): the series' closed forms
//!   carry the singular terms `1/xi`, `ln(1/xi)` and `xi ln(1/xi)` exactly
//!   ([`crate::two_sphere::SingularForms`], evaluated at run time); the tables fit only
//!   the regular remainder ([`crate::two_sphere::PairSeries::regular`]), continuous up to
//!   contact, in `u = ln xi` and `ln lambda`. In `u` the remainder's first non-analytic
//!   term, `xi^2 ln xi`, is smooth, and the remainder tends to its contact value
//!   exponentially as `u -> -infinity`. The table reaches `xi = exp(U_MIN)` (2.3e-16),
//!   below the smallest gap of a separation in `f64` (`s' - 2` is a multiple of
//!   4.4e-16), so it covers every separation with no clamp (tried: cut at `xi = 3.8e-11`
//!   and held constant below, the remainder's `O(xi)` slope, up to a few hundred at
//!   `lambda = 100`, left 3e-9 at `xi = 1e-14`). The patches in `u` shrink towards
//!   `xi = 1`, where the remainder varies most;
//!   `ln lambda` resolves the large-ratio remainders near contact, which vary too fast in
//!   `mu` near `mu = 1` for a few patches (tried: 16 patches in `mu` were still 2.7e-2
//!   off, 8 in `ln lambda` 6e-10).
//!
//! Each table file holds, patch by patch (separation variable, then ratio variable),
//! every function's `terms` x `terms` coefficients (separation x ratio), the terms that
//! no function needs zeroed by the generator ([`crate::generate`]: 64 of 160 terms kept
//! on an average near patch, 48 of 80 far). Read once, each patch is packed with the
//! functions in lanes: per kept term `(i, j)` one weight `T_i T_j` and one multiply-add
//! per vector of functions, from two contiguous blocks (the terms kept in double
//! precision, then those kept in single precision, `NARROW`), with no sums across lanes.
//! [`pair_scalars`] gives both spheres' functions of a pair in one call.
//!
//! [`AtRatio`] contracts both tables at one size ratio (the ratio sums done once), for
//! the many pairs of a suspension that share it: their functions then cost about a
//! third.
//!
//! Accuracy against the series between the nodes (the integration tests of the
//! two-sphere tables): see docs/lubrication.md.

mod sums;

use super::two_sphere::{PairScalars, SingularForms, LAMBDA_MIN};
use kernels::lanes::{dispatch_with, Isa};
use std::sync::OnceLock;
use sums::{chebyshev_values, RowSums, TermSums};

/// The smallest separation `s'` of the far table, the largest (excluded) of the near one.
pub const S_MIN: f64 = 3.0;
/// `ln xi` at the near table's contact end (`xi` = 2.3e-16, below the smallest gap of a
/// separation `s' > 2` in `f64`; a smaller `ln xi` would be taken as `U_MIN`).
pub const U_MIN: f64 = -36.0;
/// The functions, in the order of [`PairScalars::to_array`].
pub(crate) const FUNCTIONS: usize = 22;
/// The most Chebyshev coefficients in a separation or ratio variable.
pub(crate) const MAX_TERMS: usize = 20;
const _: () = assert!(
    FAR.separation.terms <= MAX_TERMS
        && NEAR.separation.terms <= MAX_TERMS
        && FAR.ratio.terms <= MAX_TERMS
        && NEAR.ratio.terms <= MAX_TERMS
);

/// One variable of a table: `patches` parts of `[lo, hi]`, part `k` ending at `hi - (hi -
/// lo) g(1 - (k + 1)/patches)` with `g` of the [`Grading`], and `terms` Chebyshev
/// coefficients on each.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Axis {
    lo: f64,
    hi: f64,
    pub(crate) patches: usize,
    grading: Grading,
    pub(crate) terms: usize,
}

/// How the parts of an [`Axis`] are spaced.
#[derive(Clone, Copy, Debug)]
enum Grading {
    /// Equal parts: `g(v) = v`.
    Equal,
    /// Parts shrinking quadratically towards `hi`: `g(v) = v^2`.
    TowardsHi,
    /// Parts shrinking towards both ends: `g(v) = (1 - cos(pi v))/2`.
    TowardsEnds,
}

impl Axis {
    /// The left end of part `k` (`k = patches`: `hi`).
    pub(crate) fn bound(&self, k: usize) -> f64 {
        if k == 0 {
            return self.lo;
        }
        let left = 1.0 - k as f64 / self.patches as f64;
        let scaled = match self.grading {
            Grading::Equal => left,
            Grading::TowardsHi => left * left,
            Grading::TowardsEnds => 0.5 * (1.0 - (std::f64::consts::PI * left).cos()),
        };
        self.hi - (self.hi - self.lo) * scaled
    }

    /// The ends of every part: [`Axis::bound`] of `0..=patches`.
    fn bounds(&self) -> Vec<f64> {
        (0..=self.patches).map(|k| self.bound(k)).collect()
    }
}

/// The part of an axis with ends `bounds` ([`Axis::bounds`]) holding `x` (clamped to
/// the ends), and `x` mapped to `[-1, 1]` on it.
fn locate(bounds: &[f64], x: f64) -> (usize, f64) {
    let parts = bounds.len() - 1;
    // the inner ends at or below x
    let p = bounds[1..parts].partition_point(|&b| b <= x);
    let (a, b) = (bounds[p], bounds[p + 1]);
    (p, ((2.0 * x - a - b) / (b - a)).clamp(-1.0, 1.0))
}

/// A table: its file, its two variables (separation, ratio) and the coefficients, read once.
pub(crate) struct Table {
    file: &'static [u8],
    pub(crate) separation: Axis,
    pub(crate) ratio: Axis,
    read: &'static OnceLock<Option<Read>>,
}

/// A table's file as read, packed for sums with the functions in lanes: for each patch
/// (separation, then ratio), the terms `(i, j)` (separation, ratio) that any function
/// keeps (the generator, [`crate::generate`], zeroes the others), and for each such term
/// the 22 functions' coefficients side by side ([`PADDED`] numbers), in double precision or,
/// where the rounding costs no function more than [`NARROW`] on the patch, in single
/// precision (half the memory to read); the sums read nothing else.
struct Read {
    /// The terms kept in double precision.
    wide: Terms<f64>,
    /// The terms kept in single precision.
    narrow: Terms<f32>,
    /// [`Axis::bound`] of the separation's parts, and of the ratio's.
    bounds: (Vec<f64>, Vec<f64>),
}

/// Kept terms of every patch of a table, in precision `T`.
struct Terms<T> {
    /// The coefficients: patch after patch, term after term.
    coefficients: Vec<[T; PADDED]>,
    /// The terms `(i, j)`, in the same order.
    terms: Vec<[u8; 2]>,
    /// Where each patch's terms start (and the end).
    starts: Vec<usize>,
}

impl<T> Terms<T> {
    fn new() -> Self {
        Terms {
            coefficients: Vec::new(),
            terms: Vec::new(),
            starts: vec![0],
        }
    }

    /// The coefficients and terms of patch `p`.
    #[inline]
    fn patch(&self, p: usize) -> (&[[T; PADDED]], &[[u8; 2]]) {
        let kept = self.starts[p]..self.starts[p + 1];
        (&self.coefficients[kept.clone()], &self.terms[kept])
    }
}

/// The most that rounding a patch's terms to single precision may change a function
/// there (each `|T_i T_j| <= 1`; a coefficient `c` rounds by at most `2^-24 |c|`), in Kim
/// & Karrila's normalisation, as the generator's trimming: 80% of the kept terms are
/// then read in single precision (51.5 of 64.6 on an average near patch, 38.3 of 48.3
/// far), and the tables'
/// errors against the series are unchanged to two digits (6.6e-10 near, 3.8e-11 far).
const NARROW: f64 = 5e-12;

/// `mu = lambda/(1 + lambda)`, the far table's ratio variable.
const fn mu(lambda: f64) -> f64 {
    lambda / (1.0 + lambda)
}

/// `t = 2/s'` on four patches of `[0, 2/S_MIN]` shrinking quadratically towards `S_MIN`,
/// 10 terms; `mu` on twelve patches of `[mu(1e-2), mu(1e2)]` shrinking towards both ends,
/// 8 terms: 80 coefficients per function, 3.8e-11 off the series. Tried: 2 x 4 equal
/// patches of 16 x 16 terms (3.1e-12, but a call for all 22 functions took twice as
/// long: it reads the coefficients from beyond the first-level cache); 3 x 4 patches of
/// 12 x 16 (5.9e-12); 8 equal `mu` patches of 8 terms (5.1e-9 at `lambda = 100`).
pub(crate) static FAR: Table = Table {
    file: include_bytes!("../generated/two_sphere_far.bin"),
    separation: Axis {
        lo: 0.0,
        hi: 2.0 / S_MIN,
        patches: 4,
        grading: Grading::TowardsHi,
        terms: 10,
    },
    ratio: Axis {
        lo: mu(LAMBDA_MIN),
        hi: mu(1.0 / LAMBDA_MIN),
        patches: 12,
        grading: Grading::TowardsEnds,
        terms: 8,
    },
    read: &FAR_READ,
};
static FAR_READ: OnceLock<Option<Read>> = OnceLock::new();

/// `u = ln xi` on 24 patches of `[U_MIN, 0]` shrinking quadratically towards `xi = 1`
/// (ends -36, -33.06, ..., -1, -0.563, -0.25, -0.063, 0), 10 terms; `ln lambda` on
/// eight equal patches of `[ln 1e-2, ln 1e2]`, 16 terms: 160 coefficients per function,
/// 6.6e-10 off the series. Tried: six patches of 20 terms in `u` (1.1e-9, but twice the
/// coefficients per call, and a call for all 22 functions took half as long again); 12, 16 and 20 patches of 10 terms (1.1e-6, 1.5e-8 and 2.3e-9 at
/// `lambda = 100`); 16 patches of 8 terms in `ln lambda` (3.4e-6).
pub(crate) static NEAR: Table = Table {
    file: include_bytes!("../generated/two_sphere_near.bin"),
    separation: Axis {
        lo: U_MIN,
        hi: 0.0,
        patches: 24,
        grading: Grading::TowardsHi,
        terms: 10,
    },
    ratio: Axis {
        // ln 1e-2 (`ln` is not `const`; `ln 1e2` rounds one ulp above `hi`, which
        // `Axis::locate` clamps)
        lo: -4.605_170_185_988_091,
        hi: 4.605_170_185_988_091,
        patches: 8,
        grading: Grading::Equal,
        terms: 16,
    },
    read: &NEAR_READ,
};
static NEAR_READ: OnceLock<Option<Read>> = OnceLock::new();

impl Table {
    /// Numbers in the table.
    pub(crate) fn len(&self) -> usize {
        self.separation.patches * self.ratio.patches * FUNCTIONS * self.patch()
    }

    /// Coefficients of one function on one patch.
    pub(crate) fn patch(&self) -> usize {
        self.separation.terms * self.ratio.terms
    }

    /// The coefficients (little-endian `f64` in the file), packed ([`Read`]); `None` if
    /// the file does not have the table's shape (then the callers take the series, and
    /// `cargo xtask gen --check` reports the file). Not typed by length, so that a file
    /// of another shape (the axes changed, the file not yet regenerated) still compiles.
    fn read(&self) -> Option<&'static Read> {
        self.read
            .get_or_init(|| (self.file.len() == self.len() * 8).then(|| self.pack()))
            .as_ref()
    }

    /// The file's coefficients packed as [`Read`] holds them.
    fn pack(&self) -> Read {
        let (rows, terms, size) = (self.separation.terms, self.ratio.terms, self.patch());
        let mut read = Read {
            wide: Terms::new(),
            narrow: Terms::new(),
            bounds: (self.separation.bounds(), self.ratio.bounds()),
        };
        // (read from the file's bytes as needed: no copy of the whole file)
        for patch in self.file.chunks_exact(FUNCTIONS * size * 8) {
            let mut kept: Vec<([u8; 2], [f64; PADDED])> = Vec::with_capacity(size);
            for i in 0..rows {
                for j in 0..terms {
                    let mut c = [0.0; PADDED];
                    for (c, f) in c.iter_mut().zip(patch.chunks_exact(size * 8)) {
                        let at = (i * terms + j) * 8;
                        *c = f64::from_le_bytes(f[at..at + 8].try_into().expect("eight bytes"));
                    }
                    if c.iter().any(|&c| c != 0.0) {
                        // (at most MAX_TERMS of each, asserted at compile time)
                        kept.push(([i as u8, j as u8], c));
                    }
                }
            }
            // the smallest terms (by their largest coefficient) in single precision,
            // while every function's rounding stays within NARROW
            let mut order: Vec<(f64, usize)> = kept
                .iter()
                .enumerate()
                .map(|(t, (_, c))| (c.iter().fold(0.0, |m: f64, c| m.max(c.abs())), t))
                .collect();
            order.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut narrow = vec![false; kept.len()];
            let mut rounding = [0.0; PADDED];
            for (_, t) in order {
                // (2^-24 |c| bounds the rounding of a normal f32; 1e-45 a subnormal's)
                let r = kept[t].1.map(|c| c.abs() * 2f64.powi(-24) + 1e-45);
                if rounding.iter().zip(&r).any(|(sum, r)| sum + r > NARROW) {
                    break;
                }
                rounding.iter_mut().zip(&r).for_each(|(sum, r)| *sum += r);
                narrow[t] = true;
            }
            for ((term, c), narrow) in kept.into_iter().zip(narrow) {
                if narrow {
                    read.narrow.coefficients.push(c.map(|c| c as f32));
                    read.narrow.terms.push(term);
                } else {
                    read.wide.coefficients.push(c);
                    read.wide.terms.push(term);
                }
            }
            read.wide.starts.push(read.wide.coefficients.len());
            read.narrow.starts.push(read.narrow.coefficients.len());
        }
        read
    }

    /// Where `x` falls on the separation axis: the patch and `T_i` there (`None` if the
    /// file does not have the table's shape).
    #[inline]
    fn at_separation(&self, x: f64) -> Option<(usize, [f64; MAX_TERMS])> {
        let read = self.read()?;
        let (px, x) = locate(&read.bounds.0, x);
        Some((px, chebyshev_values(x, self.separation.terms)))
    }

    /// The first `count` functions at separation variable `x` and ratio variable `y`, on
    /// the lanes of `isa` (`None` if this processor lacks it, or if the file does not
    /// have the table's shape).
    fn evaluate(&self, isa: Isa, x: f64, y: f64, count: usize) -> Option<[f64; FUNCTIONS]> {
        let (px, cx) = self.at_separation(x)?;
        self.evaluate_at(isa, (px, &cx), y, count)
    }

    /// [`Table::evaluate`] with the separation located ([`Table::at_separation`]).
    #[inline]
    fn evaluate_at(
        &self,
        isa: Isa,
        (px, cx): (usize, &[f64; MAX_TERMS]),
        y: f64,
        count: usize,
    ) -> Option<[f64; FUNCTIONS]> {
        let read = self.read()?;
        let (py, y) = locate(&read.bounds.1, y);
        let cy = chebyshev_values(y, self.ratio.terms);
        let patch = px * self.ratio.patches + py;
        let (wide, narrow) = (read.wide.patch(patch), read.narrow.patch(patch));
        let mut out = [0.0; PADDED];
        let count = count.min(FUNCTIONS);
        // the functions asked for, in as few lanes as serve them
        let terms = (wide, narrow);
        let done = if count <= FT_LANES {
            TermSums::<FT_LANES>::run_on(isa, terms, (cx, &cy), &mut out)
        } else {
            TermSums::<PADDED>::run_on(isa, terms, (cx, &cy), &mut out)
        };
        done.then(|| std::array::from_fn(|k| if k < count { out[k] } else { 0.0 }))
    }

    /// The table contracted at ratio variable `y` ([`Column`]; `None` if the file does
    /// not have the table's shape): on each separation patch, row `i` of function `k` is
    /// `sum_j T_j(y) c_ij` over the kept terms (the others zero).
    fn column(&self, y: f64) -> Option<Column> {
        let read = self.read()?;
        let (py, y) = locate(&read.bounds.1, y);
        let cy = chebyshev_values(y, self.ratio.terms);
        let rows_per_patch = self.separation.terms;
        let mut coefficients = vec![0.0; self.separation.patches * rows_per_patch * PADDED];
        let mut rows = vec![1u8; self.separation.patches];
        for (px, (column, used)) in coefficients
            .chunks_exact_mut(rows_per_patch * PADDED)
            .zip(&mut rows)
            .enumerate()
        {
            let patch = px * self.ratio.patches + py;
            let mut add = |[i, j]: [u8; 2], c: &[f64; PADDED]| {
                *used = (*used).max(i + 1);
                let row = &mut column[usize::from(i) * PADDED..][..PADDED];
                for (r, c) in row.iter_mut().zip(c) {
                    *r += c * cy[usize::from(j)];
                }
            };
            let (coefficients, terms) = read.wide.patch(patch);
            for (c, &term) in coefficients.iter().zip(terms) {
                add(term, c);
            }
            let (coefficients, terms) = read.narrow.patch(patch);
            for (c, &term) in coefficients.iter().zip(terms) {
                add(term, &c.map(f64::from));
            }
        }
        Some(Column {
            separation: self.separation,
            bounds: read.bounds.0.clone(),
            coefficients,
            rows,
        })
    }
}

/// The functions padded to a multiple of every lane width (the widest: 8 `f64`).
pub(crate) const PADDED: usize = 24;
/// The force-torque functions (the first ten) padded the same way.
const FT_LANES: usize = 16;
const _: () = assert!(
    PADDED >= FUNCTIONS && PADDED.is_multiple_of(8) && FT_LANES >= 10 && FT_LANES.is_multiple_of(8)
);

/// One table contracted at one size ratio ([`Table::column`]): on each separation patch,
/// row after row (separation terms), the 22 functions' coefficients side by side
/// ([`PADDED`] numbers), and the rows to sum on each patch (the most any function keeps).
struct Column {
    separation: Axis,
    /// [`Axis::bound`] of the separation's parts.
    bounds: Vec<f64>,
    coefficients: Vec<f64>,
    rows: Vec<u8>,
}

impl Column {
    /// Every function at separation variable `x`, on the lanes of `isa` (`None` if this
    /// processor lacks it).
    fn evaluate(&self, isa: Isa, x: f64) -> Option<[f64; FUNCTIONS]> {
        let (px, x) = locate(&self.bounds, x);
        let terms = self.separation.terms;
        let rows = usize::from(self.rows[px]);
        let cx = chebyshev_values(x, terms);
        let start = px * terms * PADDED;
        let mut out = [0.0; PADDED];
        let sums = RowSums {
            block: &self.coefficients[start..start + rows * PADDED],
            cx: &cx[..rows],
            out: &mut out,
        };
        dispatch_with(isa, sums).ok()?;
        Some(std::array::from_fn(|k| out[k]))
    }
}

/// The far and near tables contracted at one size ratio `lambda` (the sums over the
/// ratio terms done once), with the near-contact coefficients of the singular closed
/// forms at that ratio: the functions of a pair at this ratio then cost one row of
/// multiply-adds per separation term for all 22 together (about a third of the cost of
/// [`scalars`]: the cost test of the two-sphere integration tests). Building one reads
/// both tables' column at `lambda` once (as much as some hundreds of calls of
/// [`scalars`]): worth it for a ratio that many pairs share, as in [`crate::System::resistance`]. The same functions
/// as [`scalars`] to rounding (the two sums in the other order).
pub struct AtRatio {
    far: Column,
    near: Column,
    singular: [[f64; 3]; FUNCTIONS],
}

impl AtRatio {
    /// The tables at `lambda` in `[1e-2, 1e2]`; `None` outside (or if a committed file
    /// does not have its table's shape).
    pub fn new(lambda: f64) -> Option<Self> {
        if !in_range(lambda) {
            return None;
        }
        Some(AtRatio {
            far: FAR.column(mu(lambda))?,
            near: NEAR.column(lambda.ln())?,
            singular: super::two_sphere::singular_coefficients(lambda).ok()?,
        })
    }

    /// The first `count` functions at `s_dash > 2` (as [`scalars`]; the others zero);
    /// `None` at or inside contact.
    pub fn scalars(&self, s_dash: f64, count: usize) -> Option<PairScalars> {
        let count = count.min(FUNCTIONS);
        let mut out = if s_dash >= S_MIN {
            self.far.evaluate(Isa::best(), 2.0 / s_dash)?
        } else if s_dash > 2.0 {
            let forms = SingularForms::new(s_dash).ok()?;
            let regular = self.near.evaluate(Isa::best(), forms.ln_gap().max(U_MIN))?;
            let singular = forms.parts_from(&self.singular, count);
            std::array::from_fn(|k| singular[k] + regular[k])
        } else {
            return None;
        };
        out[count..].fill(0.0);
        Some(PairScalars::from_array(out))
    }
}

/// Whether `lambda` is in the tables' range.
fn in_range(lambda: f64) -> bool {
    (LAMBDA_MIN..=1.0 / LAMBDA_MIN).contains(&lambda)
}

/// The first `count` functions (10: the force-torque ones; 22: all, in the order of
/// [`PairScalars::to_array`]; the others zero) at any `s_dash > 2` and `lambda` in `[1e-2,
/// 1e2]`, from the far or the near table; `None` outside (or if a committed file does
/// not have its table's shape).
pub fn scalars(s_dash: f64, lambda: f64, count: usize) -> Option<PairScalars> {
    far_scalars(s_dash, lambda, count).or_else(|| near_scalars(s_dash, lambda, count))
}

/// The functions of one pair seen from each sphere: the first `count` (as [`scalars`])
/// at `s_dash > 2` and the size ratios `lambdas = [a2/a1, a1/a2]` (each in `[1e-2,
/// 1e2]`); `None` outside. The same numbers as [`scalars`] at each ratio, bit for bit,
/// for less: the separation is located and its Chebyshev terms and closed forms
/// computed once for both.
pub fn pair_scalars(s_dash: f64, lambdas: [f64; 2], count: usize) -> Option<[PairScalars; 2]> {
    if !(s_dash > 2.0 && lambdas.iter().all(|&l| in_range(l))) {
        return None;
    }
    let isa = Isa::best();
    let [first, second] = lambdas;
    let (first, second) = if s_dash >= S_MIN {
        let (px, cx) = FAR.at_separation(2.0 / s_dash)?;
        (
            FAR.evaluate_at(isa, (px, &cx), mu(first), count)?,
            FAR.evaluate_at(isa, (px, &cx), mu(second), count)?,
        )
    } else {
        let forms = SingularForms::new(s_dash).ok()?;
        let (px, cx) = NEAR.at_separation(forms.ln_gap().max(U_MIN))?;
        (
            near_view(isa, &forms, (px, &cx), first, count)?,
            near_view(isa, &forms, (px, &cx), second, count)?,
        )
    };
    Some([
        PairScalars::from_array(first),
        PairScalars::from_array(second),
    ])
}

/// The far table: `s_dash >= S_MIN`, else `None` (as [`scalars`]).
pub fn far_scalars(s_dash: f64, lambda: f64, count: usize) -> Option<PairScalars> {
    if !(s_dash >= S_MIN && in_range(lambda)) {
        return None;
    }
    FAR.evaluate(Isa::best(), 2.0 / s_dash, mu(lambda), count)
        .map(PairScalars::from_array)
}

/// The near table and the singular closed forms: `2 < s_dash < S_MIN`, else `None` (as
/// [`scalars`]).
pub fn near_scalars(s_dash: f64, lambda: f64, count: usize) -> Option<PairScalars> {
    if !(s_dash > 2.0 && s_dash < S_MIN && in_range(lambda)) {
        return None;
    }
    let forms = SingularForms::new(s_dash).ok()?;
    let (px, cx) = NEAR.at_separation(forms.ln_gap().max(U_MIN))?;
    near_view(Isa::best(), &forms, (px, &cx), lambda, count).map(PairScalars::from_array)
}

/// The near table's regular remainders at the located separation plus the closed forms'
/// singular parts, at ratio `lambda`. The table's separation variable is `u = ln xi`
/// ([`SingularForms::ln_gap`]: `xi = s' - 2` exact for `s'` in `(2, 4]`, Sterbenz), no
/// smaller than [`U_MIN`].
#[inline]
fn near_view(
    isa: Isa,
    forms: &SingularForms,
    at: (usize, &[f64; MAX_TERMS]),
    lambda: f64,
    count: usize,
) -> Option<[f64; FUNCTIONS]> {
    let regular = NEAR.evaluate_at(isa, at, lambda.ln(), count)?;
    let singular = forms.parts(lambda, count).ok()?;
    Some(std::array::from_fn(|k| singular[k] + regular[k]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tables contracted at a ratio give the functions of [`scalars`] to rounding:
    /// the same coefficients summed in the other order (and the singular coefficients
    /// computed once), so they differ by a few ulps of the sums. Near contact at large
    /// ratios the regular remainders cancel the singular parts: a function of order 1
    /// is the sum of coefficients whose absolute values add up to 2.5e3 (`lambda` near
    /// 100, one ulp of which is 4.5e-13), so the sums' rounding reaches a few ulps of
    /// that (measured 1.4e-12 of `max(|F|, 1)`, near contact at the largest ratios); 1e-11
    /// (about 20 such ulps) allows for that with a margin and is far below the tables'
    /// errors against the series (6.6e-10 near). Ratios across both ends and
    /// interior ones, not at the nodes; separations through both tables, the step
    /// between them and contact.
    #[test]
    fn tables_at_a_ratio_give_the_functions_of_the_tables() {
        let mut worst = 0.0f64;
        for i in 0..=24 {
            let lambda = 10f64.powf(-2.0 + 4.0 * f64::from(i) / 24.0);
            let at = AtRatio::new(lambda).expect("in range");
            let mut separations: Vec<f64> = (1..=200)
                .map(|j| 2.0 + 40.0 * (f64::from(j) / 200.0).powi(3))
                .collect();
            separations.extend([2.0 + 4.0 * f64::EPSILON, 2.0 + 1e-9, S_MIN, f64::INFINITY]);
            for s in separations {
                for count in [10, 22] {
                    let want = scalars(s, lambda, count).expect("in range").to_array();
                    let got = at.scalars(s, count).expect("in range").to_array();
                    for (g, w) in got.iter().zip(&want) {
                        let e = (g - w).abs() / w.abs().max(1.0);
                        worst = worst.max(e);
                        assert!(e <= 1e-11, "lambda {lambda}, s' {s}: {g} against {w}");
                    }
                    assert!(got[count..].iter().all(|&v| v == 0.0));
                }
            }
        }
        println!("tables at a ratio against the tables: {worst:.1e}");
        assert!(AtRatio::new(0.009).is_none() && AtRatio::new(f64::NAN).is_none());
        let at = AtRatio::new(1.0).expect("in range");
        assert!(at.scalars(2.0, 22).is_none() && at.scalars(f64::NAN, 22).is_none());
    }

    /// A pair's functions in one call ([`pair_scalars`]) are those of [`scalars`] at each
    /// sphere's ratio, bit for bit: the same sums in the same order, only the location
    /// of the separation and the closed forms shared. Ratios across the range, both
    /// tables, the step between them, contact and infinity.
    #[test]
    fn a_pair_in_one_call_gives_each_spheres_functions() {
        for i in 0..=40 {
            let lambda = 10f64.powf(-2.0 + 4.0 * f64::from(i) / 40.0);
            let separations = [
                2.0 + 4.0 * f64::EPSILON,
                2.0 + 1e-9,
                2.3,
                2.999,
                S_MIN,
                3.5,
                40.0,
            ];
            for s in separations.into_iter().chain([f64::INFINITY]) {
                for count in [10, 22] {
                    let lambdas = [lambda, 1.0 / lambda];
                    let views = pair_scalars(s, lambdas, count).expect("in range");
                    for (view, lambda) in views.iter().zip(lambdas) {
                        let alone = scalars(s, lambda, count).expect("in range");
                        assert_eq!(view.to_array(), alone.to_array(), "lambda {lambda}, s' {s}");
                    }
                }
            }
        }
        for (s, lambdas) in [
            (2.0, [1.0, 1.0]),
            (f64::NAN, [1.0, 1.0]),
            (2.5, [200.0, 0.005]),
        ] {
            assert!(pair_scalars(s, lambdas, 22).is_none());
        }
        assert!(pair_scalars(2.5, [1.0, f64::NAN], 22).is_none());
    }

    /// Every instruction set this processor has gives the same functions to rounding:
    /// each is a sum of at most 160 or 192 products, so fused and unfused multiply-adds and the
    /// lanes' order of summing differ by a few ulps of `max(|F|, 1)` (measured 8.9e-16
    /// between the scalar and AVX2 lanes); 1e-14 allows for that with a margin and is far
    /// below the tables' errors against the series (3.8e-11 far, 6.6e-10 near).
    #[test]
    fn every_instruction_set_gives_the_same_functions() {
        let best = Isa::best();
        for table in [&FAR, &NEAR] {
            let (sx, sy) = (table.separation, table.ratio);
            for i in 0..=16 {
                for j in 0..=16 {
                    let x = sx.lo + (sx.hi - sx.lo) * (f64::from(i) + 0.3) / 17.0;
                    let y = sy.lo + (sy.hi - sy.lo) * (f64::from(j) + 0.6) / 17.0;
                    let want = table.evaluate(best, x, y, 22).expect("committed tables");
                    for isa in Isa::all_available() {
                        let got = table.evaluate(isa, x, y, 22).expect("available");
                        for (g, w) in got.iter().zip(&want) {
                            assert!(
                                (g - w).abs() <= 1e-14 * w.abs().max(1.0),
                                "{isa:?} at ({x}, {y}): {g} against {w}"
                            );
                        }
                    }
                }
            }
        }
    }
}
