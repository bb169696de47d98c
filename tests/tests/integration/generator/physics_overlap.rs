use kernel_gen::physics::overlap::*;

fn close(a: &Coefficients<f64>, b: &Coefficients<f64>, tol: f64) {
    let (a, b) = (
        [a.f1, a.f2, a.k_ul, a.k_of, a.g1, a.g2],
        [b.f1, b.f2, b.k_ul, b.k_of, b.g1, b.g2],
    );
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= tol * (1.0 + y.abs()), "{a:?} vs {b:?}");
    }
}

/// The overlapping form meets the far form at contact and the nested form at
/// `r = |a_a - a_b|` (a few roundings of terms of order one: 1e-14).
#[test]
fn branches_meet() {
    for (aa, ab) in [(1.0, 1.0), (1.0, 0.4), (0.3, 2.0)] {
        let s: f64 = aa + ab;
        close(&overlapping(&s, &aa, &ab), &far(&s, &aa, &ab), 1e-14);
        let d: f64 = (aa - ab).abs();
        if d > 0.0 {
            let nest = nested(&d, &aa.max(ab), aa > ab);
            close(&overlapping(&d, &aa, &ab), &nest, 1e-14);
        }
    }
}
