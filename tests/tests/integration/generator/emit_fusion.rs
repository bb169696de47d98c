use kernel_gen::emit::Fusion;

#[test]
fn a_negated_multiply_add_is_one_operation() {
    use kernel_gen::graph::Trace;
    let t = Trace::begin();
    let (x, y, z) = (t.input("x"), t.input("y"), t.input("z"));
    let s = x * y + z;
    let n = -s;
    let g = t.finish();
    let f = Fusion::of(&g, &g.live(&[n.0]), &[n.0]);
    assert!(f.negated[n.0 as usize], "-(x y + z) is one neg_mul_sub");
    assert!(f.fused[s.0 as usize], "and the sum is not emitted");
    assert_eq!(
        f.count(&g.live(&[n.0])),
        2,
        "of three operations, two saved"
    );
    // a sum that is an output itself is kept, and its negation with it
    let both = [n.0, s.0];
    let f = Fusion::of(&g, &g.live(&both), &both);
    assert!(!f.negated[n.0 as usize] && !f.fused[s.0 as usize]);
}
