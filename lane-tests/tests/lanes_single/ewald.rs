//! The single-precision lane kernels of the building block `ewald_real` (the real part
//! of the Ewald split; scenes `ewald_real_f`, `ewald_real_ft`) equal its scalar `f64`
//! kernels to single precision on every instruction set this processor has: the lowered
//! `exp` and `erfc` with their coefficients rounded to `f32`.

use lane_tests::ewald_lanes::ewald_real_lanes_against_scalar;

/// Tolerance 2e-5 of each output group's largest entry (as for the confinements' `f32`
/// lanes): the inputs and some thousand operations per pair each round at 6e-8,
/// amplified by the cancellation within the jets' sums as in `f64` (2.4e-15 there, 20
/// `f64` ulps). Measured 4.7e-6, printed by `--nocapture`.
#[test]
fn single_precision_lanes_equal_the_scalar_kernels_on_every_instruction_set() {
    for (isa, worst) in ewald_real_lanes_against_scalar::<f32>(2e-5) {
        println!("ewald_real f32 lanes on {isa:?}: worst {worst:e} of the largest entry");
    }
}
