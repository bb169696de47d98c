use kernel_gen::graph::{OpCount, Trace};
use kernel_gen::number::dd::Dd;
use kernel_gen::number::scalar::Scalar;

#[test]
fn dead_code_elimination_and_counts() {
    let t = Trace::begin();
    let x = t.input("x");
    let y = t.input("y");
    let used = (x + y).sqrt() * x;
    let _dead = x / y - y.powi(3);
    let g = t.finish();
    let c = g.op_count(&[used.0]);
    assert_eq!(
        c,
        OpCount {
            add: 1,
            mul: 1,
            sqrt: 1,
            ..OpCount::default()
        }
    );
    assert!(g.len() > 5);
}

#[test]
fn interpreter_in_f64_and_double_double() {
    let t = Trace::begin();
    let x = t.input("x");
    let y = t.input("y");
    let out = (x * x - y * y) / (x - y); // = x + y, computed with cancellation
    let g = t.finish();
    let v: Vec<f64> = g.eval(&[3.0, 2.0], &[out.0]);
    assert_eq!(v[0], 5.0);
    let xd = Dd::new(1.0) + Dd::new(1e-20);
    let w: Vec<Dd> = g.eval(&[xd, Dd::new(1.0)], &[out.0]);
    assert!((w[0] - Dd::new(2.0)).to_f64().abs() < 1e-30);
}
