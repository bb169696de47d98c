//! The lane kernels of the building block `ewald_real` (the real part of the Ewald split;
//! scenes `ewald_real_f`, `ewald_real_ft`) equal its scalar kernels on every instruction
//! set this processor has, `f64` lanes: the pair blocks and the fused pair products.

use lane_tests::ewald_lanes::ewald_real_lanes_against_scalar;

/// Tolerance 1e-13 of each output group's largest entry: the lanes perform the scalar
/// kernels' operations except that multiply-adds round once and square roots may come
/// from refined reciprocal square roots (a few ulps each), amplified by the cancellation
/// within the jets' sums; the lowered `exp` and `erfc` choose their branches by
/// comparisons of inputs that agree to those ulps. Measured 2.4e-15 (AVX-512), printed
/// by `--nocapture`.
#[test]
fn lane_kernels_equal_the_scalar_kernels_on_every_instruction_set() {
    for (isa, worst) in ewald_real_lanes_against_scalar::<f64>(1e-13) {
        println!("ewald_real f64 lanes on {isa:?}: worst {worst:e} of the largest entry");
    }
}
