use kernel_gen::physics::derivatives::{GenericJets, Part, Structured};

/// The largest difference between the structured path and the generic jets over every
/// derivative `d_x^alpha d_y^beta G_ij` of each order up to `order`, and the largest
/// generic derivative of that order, at `(x, y)` (pair: `J + J^w`), in double-double:
/// `(order, difference, scale)` per order. The tests' check of a Green's function's
/// image terms and potential against its closed form.
pub fn path_differences<G: kernel_gen::physics::green::Green>(
    g: &G,
    x: &[kernel_gen::number::dd::Dd; 3],
    y: &[kernel_gen::number::dd::Dd; 3],
    p: &[kernel_gen::number::dd::Dd],
    order: usize,
) -> Vec<(usize, f64, f64)> {
    use kernel_gen::physics::operators::{Deriv, Derivatives};
    let mut st = Structured::new(g, x, y, p, order, true, true);
    let mut jets = GenericJets::new(g, Part::Full, x, y, p, order);
    let l = kernel_gen::number::jet::Layout::get(6, order);
    let mut out = vec![(0, 0.0f64, 0.0f64); order + 1];
    for (n, o) in out.iter_mut().enumerate() {
        o.0 = n;
        for m in l
            .monos
            .iter()
            .filter(|m| m.iter().map(|&e| e as usize).sum::<usize>() == n)
        {
            for i in 0..3 {
                for j in 0..3 {
                    let d = Deriv {
                        i,
                        j,
                        dx: [m[0], m[1], m[2]],
                        dy: [m[3], m[4], m[5]],
                    };
                    let (a, b) = (st.get(&d), jets.get(&d));
                    o.1 = o.1.max((a - b).to_f64().abs());
                    o.2 = o.2.max(b.to_f64().abs());
                }
            }
        }
    }
    out
}
