//! A side wall (`x1 = s`, fluid at `x1 > s`) in the solver: its grand mobility and its
//! resistance with lubrication are those of the wall `x3 = 0` turned (the sphere-wall
//! lubrication taken along the side wall's normal), and spheres outside its fluid or
//! cutting it are refused with typed errors.
//!
//! The reference is the wall's system in its own frame (the spheres at `R^T (x - s e1)`,
//! `R` the rotation taking `e3` to `e1`), turned back by `Q = diag(R, R, Q5)` on every
//! sphere (`stokesian::mobility::rotation::on_system`): the wall's kernels and its
//! horizontal lubrication path, none of the side wall's code.

use kernels::{Boundary, Condition};
use nalgebra::DMatrix;
use stokesian::mobility::rotation::{on_system, taking_e3_to};
use stokesian::{Confinement, InputError, Lubrication, Moments, Particle, System};

const SIDE: f64 = 0.25;
const SIDE_WALL: Confinement = Confinement::SideWall { side: SIDE };
const ETA: f64 = 1.3;

/// The side-wall system of `spheres` and the wall system of the same spheres turned to
/// the wall `x3 = 0`, with the rotation `R` (row-major) taking `e3` to `e1`.
fn side_and_wall(spheres: &[Particle]) -> (System, System, [[f64; 3]; 3]) {
    let r = taking_e3_to([1.0, 0.0, 0.0]);
    let turned = spheres
        .iter()
        .map(|p| {
            let d = [p.x[0] - SIDE, p.x[1], p.x[2]];
            Particle {
                x: std::array::from_fn(|j| (0..3).map(|i| r[i][j] * d[i]).sum()),
                a: p.a,
            }
        })
        .collect();
    let side = System::new(SIDE_WALL, ETA, spheres.to_vec(), false).unwrap();
    let wall = System::new(Confinement::Wall { height: 0.0 }, ETA, turned, false).unwrap();
    (side, wall, r)
}

/// `||got - want|| / ||want||` (Frobenius).
fn rel(got: &DMatrix<f64>, want: &DMatrix<f64>) -> f64 {
    (got - want).norm() / want.norm()
}

/// The FTS grand mobility of two unequal spheres near the side wall (one at gap
/// `0.05 a` from it), at negative and positive `x3` (nothing is measured from `x3 = 0`
/// but the wall's reference), equals the wall system's turned back. Tolerance 1e-14 of
/// the whole: each block differs by at most 1e-12 of its own norm
/// (`physics::rotated_planes`, where the largest blocks differ by ~1e-15), and the
/// largest blocks, which set the norm, by a few roundings of `Q5` and of the sums of
/// `Q M Q^T` (4e-16 measured).
#[test]
fn the_mobility_is_the_walls_turned() {
    let spheres = [
        Particle {
            x: [SIDE + 1.05, 0.2, -3.0],
            a: 1.0,
        },
        Particle {
            x: [SIDE + 2.4, 1.9, 0.7],
            a: 0.7,
        },
    ];
    let (side, wall, r) = side_and_wall(&spheres);
    let q = on_system(&r, Moments::FTS, spheres.len());
    let got = side.mobility(Moments::FTS);
    let want = &q * wall.mobility(Moments::FTS) * q.transpose();
    let d = rel(&got, &want);
    println!("FTS mobility: side wall vs the wall turned {d:.1e}");
    assert!(d < 1e-14, "{d:e}");
}

/// The resistance with lubrication (`Lubrication::default()`, FT and FTS) of a sphere at
/// gap `eps = 0.01` from the side wall, a second at gap `0.02` from it (both
/// corrections: sphere-wall and two-sphere), and a smaller one further out, equals the
/// wall system's turned back. Tolerance 1e-13 of the whole: the far-field mobilities
/// differ by ~1e-15 of their norm (above), which the inverse amplifies by the
/// mobility's condition number (17 at FT and 32 at FTS here, printed); every
/// lubrication term is the same function of the same gaps (the side wall's gap
/// `x1 - s` is computed as the reference's `x3'`), turned by `Q`. The corrections must
/// matter: the normal resistance of the first sphere is more than ten times its
/// far-field value.
#[test]
fn the_lubricated_resistance_is_the_walls_turned() {
    let a = 1.0;
    let spheres = [
        Particle {
            x: [SIDE + 1.01 * a, -0.4, -2.0],
            a,
        },
        Particle {
            x: [SIDE + 1.01 * a, -0.4 + 2.02 * a, -2.0],
            a,
        },
        Particle {
            x: [SIDE + 3.0, 1.0, 1.5],
            a: 0.6,
        },
    ];
    let (side, wall, r) = side_and_wall(&spheres);
    let lub = Lubrication::default();
    for moments in [Moments::FT, Moments::FTS] {
        let q = on_system(&r, moments, spheres.len());
        let got = side.resistance(moments, &lub).unwrap();
        let want = &q * wall.resistance(moments, &lub).unwrap() * q.transpose();
        let d = rel(&got, &want);
        let far = side.resistance(moments, &Lubrication::none()).unwrap();
        let eig = side.mobility(moments).symmetric_eigenvalues();
        let condition = eig.max() / eig.min();
        println!(
            "{moments:?} resistance: side wall vs the wall turned {d:.1e}, condition of M {condition:.1e}"
        );
        assert!(d < 1e-13, "{moments:?}: {d:e}");
        // the normal translation of the first sphere is index 0 (U_x of particle 0)
        assert!(
            got[(0, 0)] > 10.0 * far[(0, 0)],
            "{moments:?}: lubrication missing: {} vs far field {}",
            got[(0, 0)],
            far[(0, 0)]
        );
    }
}

/// A centre on the wall's side of the plane `x1 = s`, or on it, is outside the fluid; a
/// sphere whose centre is nearer the plane than its radius cuts it: each a typed error
/// naming the particle, its signed distance along `e1` and the side wall's boundary,
/// whatever `x3` (here negative).
#[test]
fn spheres_beyond_or_cutting_the_side_wall_are_refused() {
    let boundary = Boundary {
        normal: [1.0, 0.0, 0.0],
        offset: SIDE,
        condition: Condition::NoSlip,
        exact: true,
    };
    assert_eq!(SIDE_WALL.boundaries(), [boundary]);
    let good = Particle {
        x: [SIDE + 2.0, 0.0, -5.0],
        a: 1.0,
    };
    let err = |p: Particle, allow_overlap: bool| {
        System::new(SIDE_WALL, ETA, vec![good, p], allow_overlap).unwrap_err()
    };
    for (x1, distance) in [(SIDE - 0.5, -0.5), (SIDE, 0.0)] {
        let p = Particle {
            x: [x1, 3.0, -5.0],
            a: 0.2,
        };
        // outside the fluid even where overlaps are allowed
        for allow in [false, true] {
            assert_eq!(
                err(p, allow),
                InputError::OutsideFluid {
                    index: 1,
                    distance,
                    boundary
                }
            );
        }
    }
    let cutting = Particle {
        x: [SIDE + 0.5, 3.0, -5.0],
        a: 1.0,
    };
    let e = err(cutting, false);
    assert_eq!(
        e,
        InputError::OverlapsBoundary {
            index: 1,
            a: 1.0,
            distance: 0.5,
            boundary
        }
    );
    assert_eq!(
        e.to_string(),
        "particle 1: sphere of radius 1 overlaps the boundary, no slip at x1 = 0.25 \
         (fluid where x1 > 0.25) (centre-to-boundary distance 0.5)"
    );
    // a sphere clear of the side wall by a hair is accepted, at any x3
    let clear = Particle {
        x: [SIDE + 1.0 + 1e-12, 3.0, -5.0],
        a: 1.0,
    };
    assert!(System::new(SIDE_WALL, ETA, vec![good, clear], false).is_ok());
}
