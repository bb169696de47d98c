//! Sec. III A made concrete: differentiating Blake's image as a function of x - y'
//! only (the error the paper attributes to Bossis, Meunier & Sherwood 1991) gives an
//! asymmetric grand mobility; the correct kernels (Eq. 10) are symmetric to round-off.
//! The wrong variant exists only behind the generator option
//! `Path::StructuredNoExplicitHeight`; it is traced and interpreted here, never emitted.

use integration_tests::two_sphere_mobility;
use kernel_gen::kernel::Path;
use nalgebra::DMatrix;

fn asymmetry(m: &DMatrix<f64>) -> f64 {
    (m - m.transpose()).norm() / m.norm()
}

/// Measured: ||M - M^T|| / ||M|| = 7.1e-2 for the x - y' variant at h = 1.5 a,
/// separation 3 a; the correct kernels give 8.2e-17 (round-off).
#[test]
fn differentiating_through_x_minus_y_prime_only_breaks_symmetry() {
    let wrong = asymmetry(&two_sphere_mobility(
        Path::StructuredNoExplicitHeight,
        1.5,
        3.0,
    ));
    let right = asymmetry(&two_sphere_mobility(Path::Structured, 1.5, 3.0));
    println!("||M - M^T|| / ||M||: x - y' only {wrong:e}, Eq. 10 {right:e}");
    assert!(
        wrong > 1e-2,
        "the x - y' variant should be visibly asymmetric: {wrong:e}"
    );
    assert!(
        right < 1e-15,
        "the Eq. 10 kernels should be symmetric to round-off: {right:e}"
    );
}
