//! The Rust example of the README, kept compiling and running here: two spheres above a
//! wall, their dense FT mobility and the same product without the matrix (`stokesian`),
//! then one pair kernel called directly (`kernels`).
//! Run with `cargo run --release -p stokesian --example quickstart`.

use kernels::{pair, Confinement};
use stokesian::{check_spd, InputError, Moments, Particle, System};

fn main() -> Result<(), InputError> {
    let wall = Confinement::Wall { height: 0.0 }; // the plane x3 = 0, fluid above it
    let spheres = vec![
        Particle {
            x: [0.0, 0.0, 1.5],
            a: 1.0,
        }, // centre, radius
        Particle {
            x: [3.0, 0.0, 2.0],
            a: 0.8,
        },
    ];
    let system = System::new(wall, 1.0, spheres, false)?; // viscosity 1; validated once
    let m = system.mobility(Moments::FT); // dense 12 x 12: all U, then all Omega
    let f = [0.0, 0.0, -1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]; // forces, torques
    let u = system.apply(Moments::FT, &f); // M f without forming M
    let ab = pair(&wall, 1.0, [0.0, 0.0, 1.5], 1.0, [3.0, 0.0, 2.0], 0.8); // 11 x 11 M^{ab}
    println!(
        "sphere 0 sinks at {:.6}, the matrix is SPD: {}",
        u[2],
        check_spd(&m).passed()
    );
    println!("U_x of sphere 0 per F_x of sphere 1: {:.6}", ab.uf[0][0]);

    // the matrix and the matrix-free product agree to round-off
    let dense = &m * nalgebra::DVector::from_column_slice(&f);
    let diff = u.iter().zip(dense.iter()).map(|(a, b)| (a - b).abs());
    assert!(diff.fold(0.0, f64::max) < 1e-14);
    let block = system.block(Moments::F, 0, 1)[(0, 0)]; // the matrix's own block, from lanes
    assert!((ab.uf[0][0] - block).abs() < 1e-13 * block.abs());
    Ok(())
}
