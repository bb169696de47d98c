use kernel_gen::graph::{Ex, Id, Op, Trace};
use kernel_gen::number::scalar::Scalar;

#[test]
fn lane_form_takes_reciprocals_of_square_roots_without_divisions() {
    let t = Trace::begin();
    let x = t.input("x");
    let y = t.input("y");
    let z = t.input("z");
    let (sx, sy) = (x.sqrt(), y.sqrt());
    // 1/|R|, 1/(rho |R|) guarded at rho = 0, |R|/|r| as the traces build them
    let inv = Ex::cst(1.0) / sx;
    let guarded = Ex::cst(3.0) / (Ex::select_gt(y, Ex::cst(0.0), sy, Ex::cst(2.0)) * sx);
    let ratio = Ex::cst(1.0) / (sy * inv);
    // a divisor with one factor that needs a division keeps just that one
    let mixed = z / (sx * (y + z));
    let g = t.finish();
    let outs = [inv.0, guarded.0, ratio.0, mixed.0];
    let (l, map) = g.lane_form();
    let new: Vec<Id> = outs.iter().map(|&o| map[o as usize]).collect();
    let c = l.op_count(&new[..3]);
    // rsqrt(x), rsqrt(y) and sqrt(x) (which the lanes take from rsqrt(x))
    assert_eq!((c.div, c.sqrt), (0, 3), "{c}");
    assert_eq!(l.op_count(&new[3..]).div, 1);
    assert!(l.find(Op::Rsqrt(map[x.0 as usize])).is_some());
    // the same values (to rounding), on both sides of the select
    for inputs in [[2.0, 3.0, 0.5], [5.0, 0.0, 7.0]] {
        let want: Vec<f64> = g.eval(&inputs, &outs);
        let got: Vec<f64> = l.eval(&inputs, &new);
        for (w, v) in want.iter().zip(&got) {
            assert!(
                w == v || (w - v).abs() <= 4.0 * f64::EPSILON * w.abs(),
                "{w} {v}"
            );
        }
    }
}
