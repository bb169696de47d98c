//! A mirror of another orientation against the upright one: the side wall `x1 = side` is
//! the wall rotated, `M_side(x) = Q^T M_wall(Q x) Q` for the vector and pseudovector
//! blocks, `Q` the side wall's own frame (rows `e2, e3, e1`: it takes `e1` to `e3`).
//! The wall's kernels are traced in the canonical frame and carry the lateral far-field
//! branch; the side wall's are traced in the world frame from image terms rotated at
//! generation time and keep the direct sum everywhere: two independent paths.

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

/// Far along the wall (lateral distance `rho` up to 7e4 times the heights) the side wall's
/// direct sum loses only what the exact difference leaves, about `eps rho / h` (the plain
/// sum of Stokeslet and image would lose `eps rho^2 / (h_a h_b)`, 1e-6 at the largest
/// distance): the bound is 4 eps rho / h_a, and 1e-14 where that is smaller (the
/// rounding of a few hundred operations).
#[test]
fn side_wall_far_field_loses_eps_rho_over_h() {
    let (side, wall) = (
        Confinement::SideWall { side: 0.0 },
        Confinement::Wall { height: 0.0 },
    );
    let (ha, hb) = (1.5, 2.0);
    for rho in [1e1, 1e2, 1e3, 1e4, 1e5] {
        let xa = [ha, 0.3, 0.0];
        let xb = [hb, 0.3 + 0.6 * rho, 0.8 * rho];
        let s = pair(&side, 1.0, xa, 1.0, xb, 0.8);
        let w = pair(&wall, 1.0, to_wall(xa), 1.0, to_wall(xb), 0.8);
        let d = difference(&s, &w);
        let bound = (4.0 * f64::EPSILON * rho / ha).max(1e-14);
        assert!(d <= bound, "rho = {rho:e}: {d:e} > {bound:e}");
    }
}
