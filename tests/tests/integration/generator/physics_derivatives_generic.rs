use kernel_gen::number::jet::Layout;
use kernel_gen::physics::derivatives::{GenericJets, Part, Structured};
use kernel_gen::physics::green::wall::Wall;
use kernel_gen::physics::operators::{Deriv, Derivatives};

/// The structured Eq. 10 path and the generic six-variable path agree on every
/// derivative of Blake's image up to order 4 (f64 jets; both exact up to
/// round-off, 1e-12 relative to the largest entry covers it).
#[test]
fn structured_and_generic_paths_agree_on_blake() {
    let x = [0.3, -0.7, 1.9];
    let y = [1.1, 0.4, 2.6];
    let p = [0.25];
    let order = 4;
    let mut s = Structured::new(&Wall, &x, &y, &p, order, false, true);
    let mut g = GenericJets::new(&Wall, Part::Reflected, &x, &y, &p, order);
    let l = Layout::get(6, order);
    let mut worst: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for m in &l.monos {
        for i in 0..3 {
            for j in 0..3 {
                let d = Deriv {
                    i,
                    j,
                    dx: [m[0], m[1], m[2]],
                    dy: [m[3], m[4], m[5]],
                };
                let (a, b) = (s.get(&d), g.get(&d));
                worst = worst.max((a - b).abs());
                scale = scale.max(b.abs());
            }
        }
    }
    assert!(worst <= 1e-12 * scale, "worst {worst:e} scale {scale:e}");
}
