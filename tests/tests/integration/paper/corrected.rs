//! The corrected appendices on their own (`integration_tests::paper::corrected`): the
//! rolling sign of B2, which the printed form has the other way round, and the strain
//! blocks of Appendix C are traceless in every strain index pair.

use integration_tests::paper::corrected::{b2_of, c5_ef, c6_el, c7_es};
use integration_tests::paper::printed;

#[test]
fn rolling_sign() {
    // A force +x makes a sphere above the wall roll: Omega_y > 0.
    assert!(b2_of(2.0)[1][0] > 0.0);
    assert!(printed::b2_of(2.0)[1][0] < 0.0);
}

#[test]
#[allow(clippy::needless_range_loop)]
fn corrected_strain_blocks_are_traceless() {
    let (xa, xb) = ([0.3, 1.2, 2.5], [2.1, -0.7, 1.7]);
    let (ef, el, es) = (c5_ef(xa, xb), c6_el(xa, xb), c7_es(xa, xb));
    for n in 0..3 {
        assert!((ef[0][0][n] + ef[1][1][n] + ef[2][2][n]).abs() < 1e-15);
        assert!((el[0][0][n] + el[1][1][n] + el[2][2][n]).abs() < 1e-15);
    }
    for p in 0..3 {
        for q in 0..3 {
            assert!((es[p][q][0][0] + es[p][q][1][1] + es[p][q][2][2]).abs() < 1e-15);
            assert!((es[0][0][p][q] + es[1][1][p][q] + es[2][2][p][q]).abs() < 1e-15);
        }
    }
}
