//! `stokesian`: the grand mobility of spheres in Stokes flow near a wall, a free
//! surface, a liquid-liquid interface or in a slit, and the velocities of force- and
//! torque-given spheres, from the command line.
//!
//! The subcommands share the description of the system (`--confinement` and
//! `--moments` or `--scene`, `--particles`, `--viscosity`, `--boundary-height`,
//! `--lambda`, `--gap`, `--allow-overlap`):
//!
//! - `stokesian mobility ... --out M.npy|M.json` writes the dense grand mobility, and
//!   `stokesian resistance` the resistance with lubrication;
//! - `stokesian velocity ... --forces forces.csv --out U.csv` writes velocities (and
//!   rotation rates) of force- and torque-given spheres;
//! - `stokesian brownian ... --steps N --dt DT --out traj.csv|traj.npy` integrates
//!   overdamped Brownian dynamics with hydrodynamic interactions;
//! - `stokesian doublet --out doublet.csv` studies the co-rotating doublet.
//!
//! The command itself is the module `cli`, one file per subcommand.

use std::process::ExitCode;

mod cli;

fn main() -> ExitCode {
    cli::main()
}
