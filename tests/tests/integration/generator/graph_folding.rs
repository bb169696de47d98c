use kernel_gen::graph::{Ex, Trace};
use kernel_gen::number::scalar::Scalar;

#[test]
fn identities_fold_as_nodes_are_built() {
    let t = Trace::begin();
    let x = t.input("x");
    let zero = Ex::cst(0.0);
    let one = Ex::cst(1.0);
    assert_eq!(x + zero, x);
    assert_eq!(x * one, x);
    assert_eq!(x * zero, zero);
    assert_eq!(-(-x), x);
    assert_eq!(x - x, zero);
    assert_eq!(x / one, x);
    assert_eq!((Ex::cst(2.0) + Ex::cst(3.0)).as_const(), Some(5.0));
    // negations are pushed outward: a*(-b) is -(a*b)
    let y = t.input("y");
    assert_eq!(x * (-y), -(x * y));
    assert_eq!(x + (-y), x - y);
    // constant factors merge
    assert_eq!(Ex::cst(2.0) * (Ex::cst(3.0) * x), Ex::cst(6.0) * x);
    drop(t);
}
