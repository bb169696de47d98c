use kernel_gen::graph::{Ex, Trace};
use kernel_gen::number::dd::Dd;
use kernel_gen::number::scalar::Scalar;

/// The lowered function of one input, evaluated by the interpreter in `f64` (the
/// operations of the emitted code) at every point of `xs`.
fn lowered(f: fn(Ex) -> Ex, xs: &[f64]) -> Vec<f64> {
    let t = Trace::begin();
    let x = t.input("x");
    let y = f(x);
    let g = t.finish();
    xs.iter().map(|&v| g.eval(&[v], &[y.0])[0]).collect()
}

/// `e^{-t}` on 64001 points of `[0, 64]` against double-double: 1e-15 relative
/// (9 units of round-off `u = 2^-53`) bounds the seven rounded factors and the Horner
/// sum (measured 5.8e-16); past 64 the value is 0, within `e^{-64}` absolute.
#[test]
fn exp_against_double_double() {
    let neg: Vec<f64> = (0..=64000).map(|k| k as f64 * -1e-3).collect();
    let got = lowered(|a| a.exp(), &neg);
    let mut worst: f64 = 0.0;
    for (&a, g) in neg.iter().zip(got) {
        let want = Dd::new(a).exp();
        worst = worst.max(((Dd::new(g) - want).to_f64() / want.to_f64()).abs());
    }
    assert!(worst < 1e-15, "worst relative error {worst:e}");
    for v in lowered(|a| a.exp(), &[-64.5, -100.0, -1e300]) {
        assert_eq!(v, 0.0);
    }
}

/// `erfc` on 32001 points of `[-8, 8]` against double-double, relative error at most
/// `(x^2 + 8) u`, `u = 2^-53`: the rounding of `x^2` alone changes `e^{-x^2}` by
/// `x^2 u` (the function's own condition, 5.4e-15 at `x = 7`), and the rest (the
/// exponential, `t`, Horner's sums) was measured at most `4.5 u`.
#[test]
fn erfc_against_double_double() {
    let u = f64::EPSILON / 2.0;
    let xs: Vec<f64> = (-16000..=16000).map(|k| k as f64 * 5e-4).collect();
    let got = lowered(|a| a.erfc(), &xs);
    for (&x, g) in xs.iter().zip(got) {
        let want = Dd::new(x).erfc();
        let err = ((Dd::new(g) - want).to_f64() / want.to_f64()).abs();
        assert!(
            err <= (x * x + 8.0) * u,
            "erfc({x}): relative error {err:e}"
        );
    }
}

/// Constants fold, `exp(0) = erfc(0) = 1` among them.
#[test]
fn constants_fold() {
    let t = Trace::begin();
    assert_eq!(Ex::cst(0.0).exp().as_const(), Some(1.0));
    assert_eq!(Ex::cst(0.0).erfc().as_const(), Some(1.0));
    assert_eq!(Ex::cst(-1.0).exp().as_const(), Some((-1f64).exp()));
    drop(t);
}
