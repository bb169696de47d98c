//! A plane of any orientation is the wall `x3 = 0` turned: every one of the nine blocks of
//! the side wall's kernels (`x1 = s`, fluid at `x1 > s`) equals the wall's at the turned
//! positions, `Q M_wall(R^T (x - s e1), R^T (y - s e1)) Q^T` (the wall at `x3 = 0`, `R`
//! taking `e3` to `e1`
//! and `Q = diag(R, R, Q5)`: `stokesian::mobility::rotation`); and a plane `x3 = c`'s own
//! kernels hold on either side of it (the fluid below is the fluid above turned by `pi`
//! about `e1`), which the lubrication of the slit's upper wall relies on.
//!
//! The references are the wall's and free surface's kernels, generated for the plane
//! `x3 = const` in the world frame. The side wall (kernel-gen `green::side_wall`, its
//! image written in its own frame) is the wall's twin (kernel-gen `catalog::twin`): its
//! entry points call the wall's kernels with the points and moments turned by the
//! generator's frame `Q` (rows `e2, e3, e1`) and turn the blocks back
//! (`kernels::turn`); the reference turns them by another rotation `R` and its own
//! strain representation (`stokesian::mobility::rotation`). The side wall's own Green's
//! function is checked against its double-double direct sum in `generated::stiff_cases`.

use integration_tests::{blocks, norm};
use kernels::{pair, self_mobility, Confinement, Grand};
use nalgebra::{DMatrix, SMatrix};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use stokesian::mobility::rotation::{on_components, taking_e3_to};

/// `Q g Q^T` for a grand block `g`.
fn turned(q: &DMatrix<f64>, g: &Grand) -> Grand {
    let m = q * DMatrix::from_column_slice(11, 11, g.matrix().as_slice()) * q.transpose();
    Grand::from_matrix(&SMatrix::<f64, 11, 11>::from_column_slice(m.as_slice()))
}

/// `R^T (x - c n)`: a point near the plane `n . x = c` turned to the plane `x3 = 0`
/// (`R` takes `e3` to `n`).
fn to_plane_frame(r: &[[f64; 3]; 3], n: [f64; 3], c: f64, x: [f64; 3]) -> [f64; 3] {
    let d: [f64; 3] = std::array::from_fn(|k| x[k] - c * n[k]);
    std::array::from_fn(|j| (0..3).map(|i| r[i][j] * d[i]).sum())
}

/// The largest difference of a block, over `tol` times its norm, of `got` and `want`;
/// a block whose norm is below `1e-9` of the largest block of `want` (an entry zero by
/// symmetry at this configuration, or an image coupling decayed to nothing) is compared
/// on that scale instead, since round-off of the larger blocks reaches it.
fn worst_block(got: &Grand, want: &Grand) -> (f64, &'static str) {
    let want = blocks(want);
    let scale = want.iter().map(|(_, v)| norm(v)).fold(0.0, f64::max);
    let mut worst = (0.0f64, "");
    for ((name, x), (_, y)) in blocks(got).into_iter().zip(&want) {
        let d: Vec<f64> = x.iter().zip(y).map(|(u, v)| u - v).collect();
        let r = norm(&d) / norm(y).max(1e-9 * scale);
        if r > worst.0 {
            worst = (r, name);
        }
    }
    worst
}

/// Positions at `h` (from `h_min` to `40` radii, log-uniform) from the plane `n . x = c`
/// and lateral coordinates in `[-4, 4]`, for a radius `a`.
fn near(rng: &mut ChaCha8Rng, n: [f64; 3], c: f64, a: f64, h_min: f64) -> [f64; 3] {
    let h = a * h_min * (40.0 / h_min).powf(rng.gen_range(0.0..1.0));
    let mut x: [f64; 3] = std::array::from_fn(|_| rng.gen_range(-4.0..4.0));
    let along: f64 = (0..3).map(|k| n[k] * x[k]).sum();
    for k in 0..3 {
        x[k] += (c + h - along) * n[k];
    }
    x
}

/// Compares every block of the self and pair kernels of `conf` (whose fluid is at
/// `n . x > c`) with those of `plane` (fluid at `x3 > 0`) turned, at spheres from
/// `1.0001` radii from the plane to 40, pairs from `1e-4` of the radii's sum apart
/// (near contact) to the lateral far field, unequal radii, each pair both ways round.
/// Returns the largest block difference over its norm.
fn compare_turned(conf: &Confinement, plane: &Confinement, n: [f64; 3], c: f64) -> f64 {
    let r = taking_e3_to(n);
    let q = on_components(&r, 11);
    let eta = 0.9;
    let mut rng = ChaCha8Rng::seed_from_u64(35);
    let mut worst = 0.0f64;
    let mut check = |got: Grand, want: Grand, what: &str| {
        let (d, block) = worst_block(&got, &turned(&q, &want));
        assert!(
            d <= 1e-12,
            "{} {what}: block {block} differs by {d:e} of its norm",
            conf.name()
        );
        worst = worst.max(d);
    };
    for _ in 0..60 {
        let a = rng.gen_range(0.4..1.6);
        let x = near(&mut rng, n, c, a, 1.0001);
        let got = self_mobility(conf, eta, x, a);
        let want = self_mobility(plane, eta, to_plane_frame(&r, n, c, x), a);
        check(got, want, &format!("self at {x:?}, a = {a}"));
    }
    for trial in 0..200 {
        let (a, b) = (rng.gen_range(0.4..1.6), rng.gen_range(0.4..1.6));
        let x = near(&mut rng, n, c, a, 1.0001);
        // near contact on every other trial, anywhere else otherwise
        let y = if trial % 2 == 0 {
            let gap = (a + b) * 10f64.powf(rng.gen_range(-4.0..0.0));
            let mut dir: [f64; 3] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
            let along: f64 = (0..3).map(|k| dir[k] * n[k]).sum();
            // pointing into the fluid, so that the second sphere stays in it
            if along < 0.0 {
                for k in 0..3 {
                    dir[k] -= 2.0 * along * n[k];
                }
            }
            let len = norm(&dir);
            std::array::from_fn(|k| x[k] + (a + b + gap) * dir[k] / len)
        } else {
            let y = near(&mut rng, n, c, b, 1.0001);
            let d: f64 = (0..3).map(|k| (y[k] - x[k]).powi(2)).sum::<f64>().sqrt();
            if d < 1.01 * (a + b) {
                continue;
            }
            y
        };
        let (xt, yt) = (to_plane_frame(&r, n, c, x), to_plane_frame(&r, n, c, y));
        for ((p, pa, pt), (s, sa, st)) in [((x, a, xt), (y, b, yt)), ((y, b, yt), (x, a, xt))] {
            let got = pair(conf, eta, p, pa, s, sa);
            let want = pair(plane, eta, pt, pa, st, sa);
            check(got, want, &format!("pair {p:?} ({pa}), {s:?} ({sa})"));
        }
    }
    worst
}

/// The side wall's self and pair kernels are the wall `x3 = 0`'s turned by the rotation
/// taking `e3` to `e1`. Tolerance 1e-12 of each block's norm: the two are different
/// floating-point computations of the same exact quantity (the wall's kernels are
/// reciprocal to that tolerance, `reciprocity_every_block_every_confinement`); `R` is a
/// permutation, so the turned positions are exact but for `x1 - s`, and `Q5` adds a few
/// roundings.
#[test]
fn the_side_wall_is_the_wall_turned() {
    let side = -0.7;
    let worst = compare_turned(
        &Confinement::SideWall { side },
        &Confinement::Wall { height: 0.0 },
        [1.0, 0.0, 0.0],
        side,
    );
    println!("side wall vs the wall turned: largest block difference {worst:.1e} of its norm");
}

/// A wall's and a free surface's kernels, evaluated below their plane `x3 = c`, are
/// those above the plane `x3 = 0` turned by `pi` about `e1` (the rotation taking `e3` to
/// `-e3`), as the slit's upper wall and any boundary with normal `-e3` use them.
/// Tolerance as above; below its plane the wall's pair kernels exchange the roles of the
/// pairs they do not exchange above (they order the spheres by `x3`), so the difference
/// includes the kernels' reciprocity error, which is within the same 1e-12.
#[test]
fn a_horizontal_plane_holds_on_either_side() {
    let c = 0.4;
    for (below, above) in [
        (
            Confinement::Wall { height: c },
            Confinement::Wall { height: 0.0 },
        ),
        (
            Confinement::FreeSurface { height: c },
            Confinement::FreeSurface { height: 0.0 },
        ),
    ] {
        let worst = compare_turned(&below, &above, [0.0, 0.0, -1.0], -c);
        println!(
            "{} below vs above: largest block difference {worst:.1e} of its norm",
            below.name()
        );
    }
}

/// The side wall is served by the wall's kernels at its own offset, turned by its
/// planes' frame `Q` (rows `e2, e3, e1`), whose strain representation `Q_5` takes the
/// components of a symmetric traceless `E` to those of `Q E Q^T`: to 2e-15 absolute
/// for components below 1 (each a sum of five products; `Q_5` is computed from the
/// basis' rounded `1/sqrt 2`, `1/sqrt 6`, a few ulps off, and so is the reference).
#[test]
fn the_side_wall_is_served_by_the_wall_turned() {
    let (served, turn) = Confinement::SideWall { side: -0.7 }.served();
    assert_eq!(served, Confinement::Wall { height: -0.7 });
    let turn = turn.expect("the side wall is a twin of the wall");
    assert_eq!(turn.q, [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]);
    for (_, conf) in integration_tests::all_confinements() {
        let twin = conf.served().1.is_some();
        assert_eq!(twin, conf.name() == "side_wall", "{}", conf.name());
    }
    let basis = kernels::STRAIN_BASIS;
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..10 {
        let e: [f64; 5] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
        let m: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..5).map(|p| e[p] * basis[p][i][j]).sum())
        });
        // Q E Q^T, then its components B_p : (Q E Q^T)
        let qm: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (0..3)
                    .flat_map(|k| (0..3).map(move |l| (k, l)))
                    .map(|(k, l)| turn.q[i][k] * m[k][l] * turn.q[j][l])
                    .sum()
            })
        });
        let want: [f64; 5] = std::array::from_fn(|p| {
            (0..3)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|(i, j)| basis[p][i][j] * qm[i][j])
                .sum()
        });
        // the strain part of a grand vector (force, torque, stresslet)
        let v: [f64; 11] = std::array::from_fn(|i| if i < 6 { 0.0 } else { e[i - 6] });
        let got = turn.moments(v);
        for (g, w) in got[6..].iter().zip(&want) {
            approx::assert_abs_diff_eq!(g, w, epsilon = 2e-15);
        }
    }
}
