use kernel_gen::graph::{Id, Op, Trace};

#[test]
fn squares_are_shared_where_they_are_live() {
    let t = Trace::begin();
    let a = t.input("a");
    let x = t.input("x");
    let square = a * a;
    let cube_x = a * (a * x); // a (a x): one product fewer as (a a) x
    let g = t.finish();
    let outs = [square.0, cube_x.0];
    let (h, map) = g.squares_shared(&g.live(&outs));
    let new: Vec<Id> = outs.iter().map(|&o| map[o as usize]).collect();
    assert_eq!(g.op_count(&outs).mul, 3);
    assert_eq!(h.op_count(&new).mul, 2);
    // the square not wanted: nothing changes
    let (k, only) = g.squares_shared(&g.live(&outs[1..]));
    let kept = k.find(Op::Mul(only[a.0 as usize], only[a.0 as usize]));
    assert!(kept.is_none_or(|aa| !k.live(&[only[cube_x.0 as usize]])[aa as usize]));
    for inputs in [[1.3, -0.7], [3e-3, 250.0]] {
        let want: Vec<f64> = g.eval(&inputs, &outs);
        let got: Vec<f64> = h.eval(&inputs, &new);
        for (w, v) in want.iter().zip(&got) {
            // two roundings of products either way
            approx::assert_relative_eq!(*w, *v, max_relative = 4.0 * f64::EPSILON);
        }
    }
}
