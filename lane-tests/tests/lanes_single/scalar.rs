//! The single-precision lane kernels (`f32` lanes of `kernels::product_f_lanes`, `product_ft_lanes`, and the pair
//! blocks `pair_f_lanes_ordered`, `pair_ft_lanes_ordered`, `pair_lanes_ordered` times the
//! moments: the same traces emitted over
//! `lanes::Lane`, branch-free per lane, with fused multiply-adds) equal the scalar kernels, on every instruction set this processor has, for every confinement:
//! on random pairs, and on pairs straddling every branch of the scalar kernels (the
//! exchange of roles at equal heights, the lateral far-field switch, `rho = 0` where
//! the canonical frame is the identity), with near and far lanes mixed in one vector.
//! The `*_lanes_ordered` kernels (no exchange of roles) equal the exchanging ones bit for
//! bit on pairs ordered by height, as the tiled product passes them.

use lane_tests::lane_checks::{lanes_against_scalar, ordered_lanes_equal_exchanging};

/// The single-precision twins (`f32` lanes: the same generated kernels, literals and
/// inputs rounded to `f32`) against the `f64` scalar kernels. Tolerance 2e-5 of the
/// larger output vector's norm plus 8 `f32` ulps times the wall's cancellation factor:
/// the inputs and some 300 operations per pair each round at 6e-8, which add up like a
/// random walk to a few 1e-7 on the outputs (the report's scalar `f32` kernels: 1e-6 to
/// 6e-6 per block), with a margin of a few; the direct sum's cancellation amplifies
/// them as in `f64`. Measured: printed by `-- --nocapture`.
#[test]
fn single_precision_lanes_equal_the_scalar_kernels_on_every_instruction_set() {
    lanes_against_scalar::<f32>(6, |cancel| 2e-5 + 8.0 * f64::from(f32::EPSILON) * cancel);
}

/// The kernels without the exchange of roles (`product_f_lanes_ordered`,
/// `product_ft_lanes_ordered`) on pairs with `a` at least as high as `b` (the order of the
/// tiled product) give the exchanging kernels' values bit for bit: the exchange is then
/// the identity in every lane, equal heights included. Every confinement, F and FT,
/// every instruction set, `f32` lanes.
#[test]
fn ordered_lane_kernels_equal_the_exchanging_ones_on_ordered_pairs() {
    ordered_lanes_equal_exchanging::<f32>(8);
}
