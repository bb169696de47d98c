//! A mirror of another orientation against the upright one: the side wall `x1 = side` is
//! the wall rotated, `M_side(x) = Q^T M_wall(Q x) Q` for the vector and pseudovector
//! blocks, `Q` the side wall's own frame (rows `e2, e3, e1`: it takes `e1` to `e3`).
//! The side wall's kernels are traced in that frame (kernel_gen::physics::green::turned)
//! with the points and moments turned in and the blocks turned out: this checks the turn
//! on the generated kernels, both branches, and at every distance (the physics of the
//! side wall is checked against the rotated Blake image in `physics::rotated_planes`).

use kernels::{pair, Confinement, Grand};

/// The side wall's frame: rows `e2, e3, e1`.
const Q: [[f64; 3]; 3] = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]];

fn to_wall(x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| (0..3).map(|m| Q[k][m] * x[m]).sum())
}

/// The largest difference between the side wall's UF, UL, OF, OL blocks and the wall's
/// rotated back, relative to the largest entry of those blocks.
fn difference(side: &Grand, wall: &Grand) -> f64 {
    let (mut err, mut size) = (0.0f64, 0.0f64);
    for (s, w) in [
        (&side.uf, &wall.uf),
        (&side.ul, &wall.ul),
        (&side.of, &wall.of),
        (&side.ol, &wall.ol),
    ] {
        for i in 0..3 {
            for j in 0..3 {
                let r: f64 = (0..3)
                    .map(|a| (0..3).map(|b| Q[a][i] * w[a][b] * Q[b][j]).sum::<f64>())
                    .sum();
                err = err.max((s[i][j] - r).abs());
                size = size.max(r.abs());
            }
        }
    }
    err / size
}

/// Near and far along the wall (lateral distance `rho` up to 7e4 times the heights, on
/// both sides of the switch to the lateral far field) the side wall is the turned wall to
/// rounding: 1e-15 of the largest entry (a signed permutation of inputs and outputs
/// leaves the arithmetic as it is; a few ulps of slack for the multiply-adds the
/// compiler may contract differently in two functions).
#[test]
fn side_wall_is_the_turned_wall_near_and_far() {
    let (side, wall) = (
        Confinement::SideWall { side: 0.0 },
        Confinement::Wall { height: 0.0 },
    );
    let (ha, hb) = (1.5, 2.0);
    for rho in [1e0, 1e1, 1e2, 1e3, 1e4, 1e5] {
        let xa = [ha, 0.3, 0.0];
        let xb = [hb, 0.3 + 0.6 * rho, 0.8 * rho];
        let s = pair(&side, 1.0, xa, 1.0, xb, 0.8);
        let w = pair(&wall, 1.0, to_wall(xa), 1.0, to_wall(xb), 0.8);
        let d = difference(&s, &w);
        assert!(d <= 1e-15, "rho = {rho:e}: {d:e}");
    }
}
