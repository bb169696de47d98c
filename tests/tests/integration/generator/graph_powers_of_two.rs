use kernel_gen::graph::{Ex, Id, Op, Trace};
use kernel_gen::number::scalar::Scalar;

#[test]
fn powers_of_two_are_carried_exactly() {
    let t = Trace::begin();
    let x = t.input("x");
    let y = t.input("y");
    let z = t.input("z");
    let two = Ex::cst(2.0);
    // e1 (2 e3) and (2 e1) e3 are one node once the doubling is carried
    let p = x * (two * y);
    let q = (two * x) * y;
    let sum = Ex::cst(0.5) * p - q; // = -x y
    let root = (Ex::cst(4.0) * (x * x + z * z)).sqrt() * Ex::cst(0.25);
    let guarded = Ex::select_gt(two * z, Ex::cst(1.0), Ex::cst(3.0) * x, -y) / Ex::cst(8.0);
    let mixed = two * x + Ex::cst(3.0) * (y * z) + Ex::cst(0.75);
    // a negative multiple carries its sign: 60 z and -60 z are one node
    let (up, down) = (Ex::cst(60.0) * z + x, y - Ex::cst(-60.0) * z);
    let g = t.finish();
    let outs = [p.0, q.0, sum.0, root.0, guarded.0, mixed.0, up.0, down.0];
    for through_sums in [false, true] {
        let (c, map) = g.powers_of_two_carried(through_sums);
        let new: Vec<Id> = outs.iter().map(|&o| map[o as usize]).collect();
        assert_eq!(new[0], new[1], "one product");
        let sixty = c.find(Op::Const(60.0f64.to_bits())).expect("60 kept");
        let z_new = map[z.0 as usize];
        assert!(c
            .find(Op::Mul(sixty, z_new))
            .or(c.find(Op::Mul(z_new, sixty)))
            .is_some());
        let live = c.live(&new);
        let minus = c.find(Op::Const((-60.0f64).to_bits()));
        assert!(minus.is_none_or(|m| !live[m as usize]), "no product by -60");
        assert!(
            c.op_count(&new).total() < g.op_count(&outs).total(),
            "{} against {}",
            c.op_count(&new),
            g.op_count(&outs)
        );
        // scaling by a power of two is exact: the same values, bit for bit, on both
        // sides of the select
        for inputs in [[0.3, 1.7, 0.9], [-2.5, 0.1, 0.2], [1e3, -7.0, 4e-3]] {
            let want: Vec<f64> = g.eval(&inputs, &outs);
            let got: Vec<f64> = c.eval(&inputs, &new);
            assert_eq!(want, got, "{inputs:?}");
        }
    }
}
