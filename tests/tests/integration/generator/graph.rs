use kernel_gen::graph::Trace;

#[test]
fn hash_consing_shares_subexpressions() {
    let t = Trace::begin();
    let x = t.input("x");
    let y = t.input("y");
    let a = x * y + x;
    let b = y * x + x; // commuted: same nodes
    assert_eq!(a, b);
    let g = t.finish();
    // inputs x, y; x*y; x*y + x
    assert_eq!(g.len(), 4);
}
