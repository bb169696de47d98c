//! The sums of the two-sphere tables on the `lanes` vectors, the 22 functions side by
//! side in lanes ([`kernels::lanes`]), and the Chebyshev polynomials they weigh the
//! coefficients with.

use super::{MAX_TERMS, PADDED};
use kernels::lanes::{dispatch_with, Isa, Lane, WithLanes};

/// `sum_ij T_i(x) T_j(y) c_ij` of the first `N` functions of one patch ([`Read`]'s
/// packing), the functions in lanes ([`kernels::lanes`]): one weight `T_i(x) T_j(y)` per
/// kept term and one multiply-add per vector of functions (independent chains side by
/// side); no sum across lanes.
pub(super) struct TermSums<'a, const N: usize> {
    /// The patch's terms kept in double precision: coefficients and `(i, j)`.
    wide: (&'a [[f64; PADDED]], &'a [[u8; 2]]),
    /// Those kept in single precision.
    narrow: (&'a [[f32; PADDED]], &'a [[u8; 2]]),
    /// `T_i(x)`.
    cx: &'a [f64; MAX_TERMS],
    /// `T_j(y)`.
    cy: &'a [f64; MAX_TERMS],
    /// The sums, the first `N` set.
    out: &'a mut [f64; PADDED],
}

impl<'a, const N: usize> TermSums<'a, N> {
    /// The sums of the patch's `(wide, narrow)` terms at `(T_i(x), T_j(y))` into `out`
    /// on the lanes of `isa`; false if this processor lacks it.
    pub(super) fn run_on(
        isa: Isa,
        (wide, narrow): TermsOf<'a>,
        (cx, cy): (&'a [f64; MAX_TERMS], &'a [f64; MAX_TERMS]),
        out: &'a mut [f64; PADDED],
    ) -> bool {
        let sums = TermSums::<N> {
            wide,
            narrow,
            cx,
            cy,
            out,
        };
        dispatch_with(isa, sums).is_ok()
    }
}

/// A patch's kept terms, double and single precision: coefficients and `(i, j)`.
type TermsOf<'a> = (
    (&'a [[f64; PADDED]], &'a [[u8; 2]]),
    (&'a [[f32; PADDED]], &'a [[u8; 2]]),
);

impl<const N: usize> WithLanes for TermSums<'_, N> {
    type Elem = f64;
    type Output = ();

    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) {
        let vectors = N / L::WIDTH;
        let mut acc = [L::splat(0.0); PADDED];
        // (no closure: closures do not inherit the target features, ARCHITECTURE.md)
        let (cx, cy) = (self.cx, self.cy);
        for (c, &[i, j]) in self.wide.0.iter().zip(self.wide.1) {
            let w = L::splat(cx[usize::from(i)] * cy[usize::from(j)]);
            for (v, a) in acc.iter_mut().take(vectors).enumerate() {
                *a = L::load(&c[v * L::WIDTH..]).mul_add(w, *a);
            }
        }
        for (c, &[i, j]) in self.narrow.0.iter().zip(self.narrow.1) {
            let w = L::splat(cx[usize::from(i)] * cy[usize::from(j)]);
            for (v, a) in acc.iter_mut().take(vectors).enumerate() {
                *a = L::load_f32(&c[v * L::WIDTH..]).mul_add(w, *a);
            }
        }
        for (v, a) in acc.iter().take(vectors).enumerate() {
            a.store(&mut self.out[v * L::WIDTH..]);
        }
    }
}

/// `sum_i T_i(x) c_ik` of every function `k` of a [`Column`] patch: the functions in
/// lanes, one multiply-add per row and vector (independent chains side by side).
pub(super) struct RowSums<'a> {
    /// The patch's rows, [`PADDED`] numbers each.
    pub(super) block: &'a [f64],
    /// `T_i(x)` of the rows.
    pub(super) cx: &'a [f64],
    pub(super) out: &'a mut [f64; PADDED],
}

impl WithLanes for RowSums<'_> {
    type Elem = f64;
    type Output = ();

    #[inline(always)]
    fn run<L: Lane<Elem = f64>>(self) {
        let vectors = PADDED / L::WIDTH;
        let mut acc = [L::splat(0.0); PADDED];
        for (row, &x) in self.block.chunks_exact(PADDED).zip(self.cx) {
            let x = L::splat(x);
            for (v, a) in acc.iter_mut().take(vectors).enumerate() {
                *a = L::load(&row[v * L::WIDTH..]).mul_add(x, *a);
            }
        }
        for (v, a) in acc.iter().take(vectors).enumerate() {
            a.store(&mut self.out[v * L::WIDTH..]);
        }
    }
}

/// `T_0(x) ... T_(terms-1)(x)` (the rest zero; at least four are computed): beyond
/// `T_3` by `T_j = 2 T_2 T_(j-2) - T_(j-4)` (from `2 T_m T_n = T_(m+n) + T_(m-n)`), the
/// even and odd terms two independent chains, half the latency of the usual recurrence.
pub(super) fn chebyshev_values(x: f64, terms: usize) -> [f64; MAX_TERMS] {
    let mut t = [0.0; MAX_TERMS];
    t[0] = 1.0;
    t[1] = x;
    t[2] = 2.0 * x * x - 1.0;
    t[3] = 2.0 * x * t[2] - x;
    let two_t2 = 2.0 * t[2];
    for j in 4..terms.min(MAX_TERMS) {
        t[j] = two_t2 * t[j - 2] - t[j - 4];
    }
    t
}
