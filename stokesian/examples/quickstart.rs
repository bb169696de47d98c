//! The Rust example of the README, kept compiling and running here: two spheres above a
//! wall, their dense FT mobility and the same product without the matrix (`stokesian`),
//! then one pair kernel called directly (`kernels`).
//! Run with `cargo run --release -p stokesian --example quickstart`.

use kernels::{pair, Confinement};
use stokesian::{check_spd, InputError, Moments, Particle, System};

fn main() -> Result<(), InputError> {
    // README, from here to the blank line
    let wall = Confinement::Wall { height: 0.0 }; // the plane x3 = 0, fluid above it
    let (xa, xb) = ([0.0, 0.0, 1.5], [3.0, 0.0, 2.0]); // centres; radii 1 and 0.8
    let spheres = vec![Particle { x: xa, a: 1.0 }, Particle { x: xb, a: 0.8 }];
    let system = System::new(wall, 1.0, spheres, false)?; // viscosity 1; validated once
    let m = system.mobility(Moments::FT); // dense 12 x 12: all U, then all Omega
    let f = [0.0, 0.0, -1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]; // forces, torques
    let u = system.apply(Moments::FT, &f); // M f without forming M (SIMD tiles)
    assert!(check_spd(&m).passed()); // symmetric, and its Cholesky factor exists
    let ab = pair(&wall, 1.0, xa, 1.0, xb, 0.8); // one kernel: the 11 x 11 block M^{ab}
    println!("{:.6} {:.6}", u[2], ab.uf[0][0]); // sphere a's sinking speed, U_x(a) per F_x(b)

    // the matrix and the matrix-free product agree to round-off, and the matrix holds
    // the kernel's block (evaluated there by the lane kernels). Bounds: velocities here
    // are about 0.02 (unit forces, eta = 1), so 1e-14 absolute is 5e-13 of them; the
    // lane and scalar kernels round differently, so 1e-13 relative for one entry.
    let dense = &m * nalgebra::DVector::from_column_slice(&f);
    let diff = u.iter().zip(dense.iter()).map(|(x, y)| (x - y).abs());
    assert!(diff.fold(0.0, f64::max) < 1e-14);
    let block = system.block(Moments::F, 0, 1)[(0, 0)];
    assert!((ab.uf[0][0] - block).abs() < 1e-13 * block.abs());
    Ok(())
}
