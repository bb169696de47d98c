//! The configurations the exact results describe, as solver systems (unit spheres,
//! viscosity 1), and the resistance functions read off their resistance matrices (Kim &
//! Karrila normalisation: A by 6 pi, B by 4 pi, C by 8 pi, the wall's functions as those of a
//! sphere and a second one of infinite radius).
//! Shared by the tests against exact results and the report.

use nalgebra::DMatrix;
use std::f64::consts::PI;
use stokesian::{Confinement, Particle, System};

/// One unit sphere with its centre at height `h` above a no-slip wall at 0.
pub fn sphere_above_wall(h: f64) -> System {
    System::new(
        crate::WALL,
        1.0,
        vec![Particle {
            x: [0.0, 0.0, h],
            a: 1.0,
        }],
        false,
    )
    .expect("a sphere above the wall")
}

/// One unit sphere with its centre at height `h` above a flat free surface at 0.
pub fn sphere_above_free_surface(h: f64) -> System {
    System::new(
        Confinement::FreeSurface { height: 0.0 },
        1.0,
        vec![Particle {
            x: [0.0, 0.0, h],
            a: 1.0,
        }],
        false,
    )
    .expect("a sphere above the free surface")
}

/// Two unit spheres in unbounded fluid at surface gap `xi`, line of centres along x.
pub fn equal_pair(xi: f64) -> System {
    System::new(
        Confinement::Free,
        1.0,
        vec![
            Particle {
                x: [0.0; 3],
                a: 1.0,
            },
            Particle {
                x: [2.0 + xi, 0.0, 0.0],
                a: 1.0,
            },
        ],
        false,
    )
    .expect("two separate spheres")
}

/// `X^A_w, Y^A_w, F^r, Y^C_w, X^C_w` of [`sphere_above_wall`] from its resistance (F:
/// 3 x 3, the rotational ones `None`; FT or FTS: the same indices for U and Omega).
/// `R_{Ly,Ux} = -6 pi eta a^2 F^r`.
pub fn wall_functions_of(r: &DMatrix<f64>) -> [Option<f64>; 5] {
    let ft = r.nrows() > 3;
    [
        Some(r[(2, 2)] / (6.0 * PI)),
        Some(r[(0, 0)] / (6.0 * PI)),
        ft.then(|| -r[(4, 0)] / (6.0 * PI)),
        ft.then(|| r[(3, 3)] / (8.0 * PI)),
        ft.then(|| r[(5, 5)] / (8.0 * PI)),
    ]
}

/// The normal translation and the rotation about the normal of
/// [`sphere_above_free_surface`] (`X^A`, `X^C`; F: the rotation `None`).
pub fn free_surface_functions_of(r: &DMatrix<f64>) -> [Option<f64>; 2] {
    let ft = r.nrows() > 3;
    [
        Some(r[(2, 2)] / (6.0 * PI)),
        ft.then(|| r[(5, 5)] / (8.0 * PI)),
    ]
}

/// `X11A, X12A, X11C, X12C, Y11A, Y12A, Y11B, Y12B, Y11C, Y12C` of [`equal_pair`] from its
/// resistance (F: 6 x 6, the rotational ones `None`). With `d = e_x`, `B_zy = -Y^B` in
/// the torque-velocity rows.
pub fn pair_functions_of(r: &DMatrix<f64>) -> [Option<f64>; 10] {
    let ft = r.nrows() > 6;
    [
        Some(r[(0, 0)] / (6.0 * PI)),
        Some(r[(0, 3)] / (6.0 * PI)),
        ft.then(|| r[(6, 6)] / (8.0 * PI)),
        ft.then(|| r[(6, 9)] / (8.0 * PI)),
        Some(r[(1, 1)] / (6.0 * PI)),
        Some(r[(1, 4)] / (6.0 * PI)),
        ft.then(|| -r[(8, 1)] / (4.0 * PI)),
        ft.then(|| -r[(8, 4)] / (4.0 * PI)),
        ft.then(|| r[(7, 7)] / (8.0 * PI)),
        ft.then(|| r[(7, 10)] / (8.0 * PI)),
    ]
}
