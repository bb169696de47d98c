//! The lane kernels (`kernels::product_f_lanes`, `product_ft_lanes`, and the pair
//! blocks `pair_f_lanes_ordered`, `pair_ft_lanes_ordered`, `pair_lanes_ordered` times the
//! moments: the same traces emitted over
//! `lanes::Lane`, branch-free per lane, with fused multiply-adds) equal the scalar kernels, on every instruction set this processor has, for every confinement:
//! on random pairs, and on pairs straddling every branch of the scalar kernels (the
//! exchange of roles at equal heights, the lateral far-field switch, `rho = 0` where
//! the canonical frame is the identity), with near and far lanes mixed in one vector.
//! The `*_lanes_ordered` kernels (no exchange of roles) equal the exchanging ones bit for
//! bit on pairs ordered by height, as the tiled product passes them.

use lane_tests::lane_checks::{lanes_against_scalar, ordered_lanes_equal_exchanging};

/// Tolerance 1e-13 of the larger output vector's norm, plus, for the wall, 8 ulps times
/// the direct sum's cancellation factor `rho^2 / (h_a h_b)`: the lane kernels perform
/// the same operations as the scalar ones except that multiply-adds round once instead
/// of twice and reciprocals share divisions (a few ulps each; blending the far and
/// near branches rather than branching is exact), so they differ by the kernels'
/// round-off amplified by the cancellation between the terms of the direct sum (about
/// 1e2 at most away from the wall's lateral switch, `rho^2 / (h_a h_b)` up to 4e4 just
/// below it). Measured: printed by `-- --nocapture`.
#[test]
fn lane_kernels_equal_the_scalar_kernels_on_every_instruction_set() {
    lanes_against_scalar::<f64>(5, |cancel| 1e-13 + 8.0 * f64::EPSILON * cancel);
}

/// The kernels without the exchange of roles (`product_f_lanes_ordered`,
/// `product_ft_lanes_ordered`) on pairs with `a` at least as high as `b` (the order of the
/// tiled product) give the exchanging kernels' values bit for bit: the exchange is then
/// the identity in every lane, equal heights included. Every confinement, F and FT,
/// every instruction set, `f64` lanes.
#[test]
fn ordered_lane_kernels_equal_the_exchanging_ones_on_ordered_pairs() {
    ordered_lanes_equal_exchanging::<f64>(7);
}
