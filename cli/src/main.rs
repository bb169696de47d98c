//! `stokesian`: the grand mobility of spheres in Stokes flow near a wall, a free
//! surface, a liquid-liquid interface or in a slit, and the velocities of force- and
//! torque-given spheres, from the command line: argument parsing (clap) and dispatch to
//! one module per subcommand.
//!
//! The subcommands share the description of the system (`--confinement` and
//! `--moments` or `--scene`, `--param NAME=VALUE` and its aliases `--boundary-height`,
//! `--lambda`, `--gap`, `--particles`, `--viscosity`, `--overlap` (and its alias
//! `--allow-overlap`)):
//!
//! - `stokesian mobility ... --out M.npy|M.csv|M.json` writes the dense grand mobility, and
//!   `stokesian resistance` the resistance with lubrication;
//! - `stokesian velocity ... --forces forces.csv --out U.csv|U.npy` writes velocities (and
//!   rotation rates) of force- and torque-given spheres;
//! - `stokesian brownian ... --steps N --dt DT --out traj.csv|traj.npy` integrates
//!   overdamped Brownian dynamics with hydrodynamic interactions;
//! - `stokesian doublet --out doublet.csv|doublet.npy` studies the co-rotating doublet;
//! - `stokesian confinements` lists the confinements the kernels declare, their
//!   parameters and boundaries.
//!
//! Every output's format is chosen by the extension of `--out` among those the
//! subcommand writes (`output::check_out`); any other extension is refused before any
//! work.
//!
//! | module | owns |
//! |---|---|
//! | `system` | the shared system arguments, their validation, the causes of non-finite results |
//! | `options` | checks of single option values, numbers in messages |
//! | `table` | input formats: CSV with named columns, `.npy` |
//! | `output` | output formats (`.npy`, JSON, CSV) chosen by the extension, atomic writes, progress on stderr |
//! | `error` | [`CliError`](error::CliError), every failure with its message |
//! | `matrix` | `mobility` and `resistance` |
//! | `velocity` | `velocity` |
//! | `brownian` | `brownian` |
//! | `doublet` | `doublet` |
//! | `confinements` | `confinements`: the declared confinements listed |
//! | `plot` | the doublet's contour plot (plotters) |
//!
//! Every input error names the file, the line (or row) and the particle; output is
//! written to a temporary file in the output's directory and renamed on success, so no
//! partial output file is ever left behind.

mod brownian;
mod confinements;
mod doublet;
mod error;
mod matrix;
mod options;
mod output;
mod plot;
mod system;
mod table;
mod velocity;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

const ABOUT: &str = "Grand mobility of spheres in Stokes flow near walls and interfaces \
(Swan & Brady, Phys. Fluids 19, 113306, 2007); velocities of force- and torque-given spheres; \
the resistance with lubrication; Brownian dynamics.";

const LONG_HELP: &str = "\
UNITS
    Any consistent set of units; SI is the usual choice: positions and radii in m,
    viscosity in Pa s, forces in N, torques in N m, strain rates in 1/s. Velocities come
    out in m/s, rotation rates in rad/s, and the mobility in the matching units
    (U/F in m/(N s), and so on).

SIGN CONVENTION
    Forces, torques and stresslets are those the particles exert ON THE FLUID. With no
    particle inertia these equal the external forces and torques acting on the particles
    (gravity minus buoyancy, optical traps, magnetic torques, ...): a sphere that sinks
    under gravity has fz = -(buoyant weight) < 0. The mobility maps (F, L, S) to
    (U - U_inf, Omega - Omega_inf, -E_inf) and is symmetric positive definite (except
    near a wall of a narrow slit, below).

GEOMETRY AND CONFINEMENTS
    --confinement NAME chooses the Green's function (--help lists the names; a hyphen
    may stand for each underscore, as in free-surface) and --param NAME=VALUE, repeated,
    its parameters; those not given take their defaults. `stokesian confinements` lists
    every confinement with its parameters (default or required, what each is) and its
    boundary planes. --boundary-height H, --lambda L and --gap G stand for
    --param height=H, lambda=L and gap=G; giving one of them and the same --param, or
    one the confinement does not have, is an error.
    The slit's boundaries hold only approximately (it superposes the single-wall
    images): accurate for wide slits, and not positive definite near a wall of a narrow
    slit (use gap >= ~12 radii for a single sphere, ~50 radii for touching pairs near a
    wall).

MOMENTS
    F    point forces: velocities of the centres (3N unknowns).
    FT   forces and torques: velocities and rotation rates (6N).
    FTS  adds the stresslets, with which rigid spheres resist the local strain of the
         flow (11N); more accurate near other spheres and near boundaries.

MATRIX LAYOUT
    Rows and columns are ordered moment-major, particle-major within a moment (the order
    of Swan & Brady's Eq. 1): all U (3N: U1x, U1y, U1z, U2x, ...), then all Omega (3N),
    then all E (5N). F keeps only the U rows and F columns, FT the U and Omega rows and
    F and L columns. Strain and stresslet use 5 components in the orthonormal basis
        B1 = (e1e2 + e2e1)/sqrt2,  B2 = (e1e3 + e3e1)/sqrt2,  B3 = (e2e3 + e3e2)/sqrt2,
        B4 = (e1e1 - e2e2)/sqrt2,  B5 = (2e3e3 - e1e1 - e2e2)/sqrt6,
    with E_m = B_m : E (so that the matrix is symmetric).

FILES
    particles      CSV with a header naming the columns x,y,z,radius, then one sphere
                   per line (particle 0 on the first data line); or .npy, a float64 or
                   float32 array of shape (N, 4), C or Fortran order. With --radius A:
                   columns x,y,z, or shape (N, 3).
    forces         CSV with columns fx,fy,fz (F) or fx,fy,fz,tx,ty,tz (FT, FTS), one
                   line per particle in the order of the particles; or .npy of shape
                   (N, 3) or (N, 6).
    CSV columns may come in any order and names ignore case; other columns (an id, a
    type) are ignored and named once on stderr. Fields may be quoted and surrounded by
    spaces; CRLF line ends and a UTF-8 byte-order mark are accepted; blank lines and
    lines starting with # are skipped. Error messages give the line (CSV, from 1, the
    header included) or the row (.npy, from 0).
    Overlapping spheres (centre distance < sum of radii) and spheres cutting the boundary
    are errors unless --overlap rpy (the Rotne-Prager-Yamakawa overlap forms, F and FT)
    or --overlap far (--allow-overlap: the far forms anyway) is given.
    The output is written to a temporary file next to --out and renamed when complete:
    on any error no output file is created (an existing one is left as it was).";

/// Grand mobility matrices and velocities of spheres in Stokes flow near walls and
/// interfaces.
#[derive(Parser, Debug)]
#[command(name = "stokesian", version, about = ABOUT, after_long_help = LONG_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Write the dense grand mobility matrix (.npy, .csv or .json).
    #[command(
        long_about = "Write the dense grand mobility matrix of the spheres in --particles.\n\n\
        .npy: a float64 2-D array in Fortran order (numpy.load). .csv: one matrix row \
        per line, no header, every number printed to full round-trip precision. .json: {\"layout\": ..., \
        \"moments\": ..., \"n\": number of particles, \"dimension\": rows, \"matrix\": \
        [[row 0], [row 1], ...]}, every number printed to full round-trip precision.",
        after_long_help = LONG_HELP
    )]
    Mobility(matrix::MatrixArgs),
    /// Velocities (and rotation rates) of spheres with given forces (and torques).
    #[command(
        long_about = "Velocities (and rotation rates) of force- and torque-given spheres \
        in a quiescent fluid, written to --out as CSV with columns ux,uy,uz (F) or \
        ux,uy,uz,wx,wy,wz (FT, FTS), one line per particle, or as .npy, a float64 array \
        of shape (N, 3) or (N, 6) with the same columns.\n\n\
        F and FT: U = M F without forming M (matrix-free). FTS: the stresslets S are \
        solved for so that the strain rate imposed on the spheres is zero, or --strain: \
        from the strain rows of the grand mobility, -E_inf = M_EF F + M_EL L + M_ES S.",
        after_long_help = LONG_HELP
    )]
    Velocity(velocity::VelocityArgs),
    /// Write the grand resistance with lubrication, Eq. 19 (FT or FTS).
    #[command(
        long_about = "Write the FT or FTS grand resistance with lubrication (Swan & Brady \
        Eq. 19): R = M^-1 + R^P + R^W - (R^P,inf + R^W,inf), rows (F, L[, S]), columns \
        (U, Omega[, -E_inf]), same layout and formats as `mobility`. The exact two-sphere \
        resistance (any size ratio from 1e-2 to 1e2, generated tables of the twin-multipole series, to contact) of \
        every pair whose correction may exceed 1e-6 of the smaller sphere's drag (switched \
        off smoothly beyond; --pair-tolerance), the exact sphere-wall resistance (no-slip \
        walls, every height up to 1000 radii) and the exact resistance near a free \
        surface (the sphere and its mirror image) are added to the inverse of the far-field mobility, and their own \
        far-field parts subtracted. At FTS the pair and free-surface corrections cover \
        every block; a no-slip wall's only the force-torque blocks (its stresslet blocks \
        keep the far-field inverse).",
        after_long_help = LONG_HELP
    )]
    Resistance(matrix::MatrixArgs),
    /// Overdamped Brownian dynamics with hydrodynamic interactions (F or FT): trajectory.
    #[command(long_about = brownian::ABOUT, after_long_help = LONG_HELP)]
    Brownian(brownian::BrownianArgs),
    /// The co-rotating doublet above a wall (Swan & Brady Sec. III B, Figs. 2-3).
    #[command(long_about = doublet::ABOUT)]
    Doublet(doublet::DoubletArgs),
    /// List the confinements: names, parameters (defaults, what they are), boundaries.
    #[command(long_about = confinements::ABOUT)]
    Confinements(confinements::ConfinementsArgs),
}

/// Parse the command line, run the subcommand, and report an error on stderr.
fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::Mobility(mut args) => args
            .system
            .resolve_scene()
            .and_then(|()| matrix::run(&args, false)),
        Command::Resistance(mut args) => args
            .system
            .resolve_scene()
            .and_then(|()| matrix::run(&args, true)),
        Command::Velocity(mut args) => args
            .system
            .resolve_scene()
            .and_then(|()| velocity::run(&args)),
        Command::Brownian(mut args) => args
            .system
            .resolve_scene()
            .and_then(|()| brownian::run(&args)),
        Command::Doublet(args) => doublet::run(&args),
        Command::Confinements(args) => confinements::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stokesian: error: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    /// clap's own consistency checks of the definitions (run in debug builds only when
    /// the command parses its arguments; here in every build).
    #[test]
    fn the_command_line_definition_is_consistent() {
        use clap::CommandFactory;
        super::Cli::command().debug_assert();
    }
}
