//! `stokesian`: the grand mobility of spheres in Stokes flow near a wall, a free
//! surface, a liquid-liquid interface or in a slit, and the velocities of force- and
//! torque-given spheres, from the command line.
//!
//! The subcommands share the description of the system (`--confinement`, `--moments`,
//! `--particles`, `--viscosity`, `--boundary-height`, `--lambda`, `--gap`,
//! `--allow-overlap`):
//!
//! - `stokesian mobility ... --out M.npy|M.json` writes the dense grand mobility;
//! - `stokesian velocity ... --forces forces.csv --out U.csv` writes velocities (and
//!   rotation rates) of spheres in a quiescent fluid, solving for the stresslets with
//!   `--moments FTS`;
//! - `stokesian brownian ... --steps N --dt DT --out traj.csv|traj.npy` integrates
//!   overdamped Brownian dynamics with hydrodynamic interactions (`--moments` F, the
//!   default, or FT with orientations; Euler-Maruyama or `--scheme fixman`; Cholesky or
//!   `--lanczos TOL` noise).
//!
//! `--scene scene.toml` may replace `--confinement` and `--moments` (the scene's
//! confinement and truncation).
//!
//! Every input error is a [`CliError`] naming the file, the line and the particle;
//! output is written to a temporary file in the output's directory and renamed on
//! success, so no partial output file is ever left behind.

use clap::{Args, Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use nalgebra::DMatrix;
use std::fs::{self, File};
use std::io::{self, BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;
use stokesian::{Brownian, BrownianError, Confinement, ExternalForces, InputError, Moments};
use stokesian::{Particle, System};
use thiserror::Error;

mod plot;

/// The layout string of the JSON output and the help text.
const LAYOUT: &str = "moment-major: U(3N), Omega(3N), E(5N, orthonormal basis B1..B5); \
                      particle-major within a moment";

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
    The boundary is the plane z = --boundary-height (default 0) and the fluid that holds
    the spheres is above it (z > boundary-height).
      free           unbounded fluid; no boundary (do not give --boundary-height).
      wall           rigid no-slip plane wall (Blake's image system).
      free-surface   flat, undeformable free surface (e.g. a flat air-water interface):
                     no flow through it and no shear stress on it.
      interface      flat, undeformable liquid-liquid interface; --lambda is the
                     viscosity of the liquid below the interface divided by the viscosity
                     of the liquid that holds the spheres (0: free surface; large: wall).
      slit           two parallel no-slip walls at z = boundary-height and
                     z = boundary-height + --gap, by superposing the single-wall images.
                     An approximation: accurate for wide slits, and not positive definite
                     near a wall of a narrow slit (use gap >= ~12 radii for a single sphere,
                     ~50 radii for touching pairs near a wall).

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
    particles.csv  header x,y,z,radius, then one sphere per line (particle 0 on line 2).
    forces.csv     header fx,fy,fz (F) or fx,fy,fz,tx,ty,tz (FT, FTS), one line per
                   particle, in the order of particles.csv.
    Blank lines and lines starting with # are ignored. Error messages give the line.
    Overlapping spheres (centre distance < sum of radii) and spheres cutting the boundary
    are errors unless --allow-overlap is given.
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
    /// Write the dense grand mobility matrix (.npy or .json).
    #[command(
        long_about = "Write the dense grand mobility matrix of the spheres in --particles.\n\n\
        .npy: a float64 2-D array in Fortran order (numpy.load). .json: {\"layout\": ..., \
        \"moments\": ..., \"n\": number of particles, \"dimension\": rows, \"matrix\": \
        [[row 0], [row 1], ...]}, every number printed to full round-trip precision.",
        after_long_help = LONG_HELP
    )]
    Mobility(MobilityArgs),
    /// Velocities (and rotation rates) of spheres with given forces (and torques).
    #[command(
        long_about = "Velocities (and rotation rates) of force- and torque-given spheres \
        in a quiescent fluid, written to --out as CSV with columns ux,uy,uz (F) or \
        ux,uy,uz,wx,wy,wz (FT, FTS), one line per particle.\n\n\
        F and FT: U = M F without forming M (matrix-free). FTS: the stresslets S are \
        solved for so that the strain rate imposed on the spheres is zero, or --strain: \
        from the strain rows of the grand mobility, -E_inf = M_EF F + M_EL L + M_ES S.",
        after_long_help = LONG_HELP
    )]
    Velocity(VelocityArgs),
    /// Write the grand resistance with lubrication, Eq. 19 (FT or FTS).
    #[command(
        long_about = "Write the FT or FTS grand resistance with lubrication (Swan & Brady \
        Eq. 19): R = M^-1 + R^P + R^W - (R^P,inf + R^W,inf), rows (F, L[, S]), columns \
        (U, Omega[, -E_inf]), same layout and formats as `mobility`. Near-contact two-sphere \
        terms (equal spheres, gap < 0.1 a, near-contact forms) and the exact sphere-wall \
        resistance (no-slip walls, gap < 1 a, bispherical series) are added to the inverse \
        of the far-field mobility, and their own far-field parts subtracted; at FTS these \
        corrections act on the force-torque blocks and the stresslet blocks keep the \
        far-field inverse.",
        after_long_help = LONG_HELP
    )]
    Resistance(MobilityArgs),
    /// Overdamped Brownian dynamics with hydrodynamic interactions (F or FT): trajectory.
    #[command(long_about = BROWNIAN_ABOUT, after_long_help = LONG_HELP)]
    Brownian(BrownianArgs),
    /// The co-rotating doublet above a wall (Swan & Brady Sec. III B, Figs. 2-3).
    #[command(long_about = DOUBLET_ABOUT)]
    Doublet(DoubletArgs),
}

const DOUBLET_ABOUT: &str = "\
The co-rotating doublet of Swan & Brady (Sec. III B, Figs. 2-3): two equal spheres
(radius a) at height h above a no-slip wall, centres r apart, with equal and opposite
torques T along their line of centres and otherwise force- and torque-free (FTS, no
imposed flow). Near the wall they translate in opposite directions and the doublet turns
about its centre. On a grid of r in [--r-min, --r-max] and h in [--h-min, --h-max]
(geometric in the gaps r/a - 2 and h/a - 1), for the resistance with lubrication
(Eq. 19) and for the far-field mobility alone, it computes the rotation rate
8 pi eta a^3 Omega / T and the tension tau a / T a wire joining the spheres must carry
to keep r fixed (positive: pulling them together).

Writes --out (CSV: r,h,rate_resistance,rate_farfield,tension_resistance,
tension_farfield; r and h over a) and, beside it with the same stem, a filled contour
plot of the rate with lubrication (.png and .svg); prints the maximum rate and where it
is (the grid maximum refined by a pattern search).";

/// `doublet`: the grid and the output.
#[derive(Args, Debug)]
struct DoubletArgs {
    /// Output CSV; the contour plot is written beside it as .png and .svg.
    #[arg(long, value_name = "doublet.csv")]
    out: PathBuf,
    /// Smallest separation r/a (> 2).
    #[arg(long, default_value_t = 2.0001)]
    r_min: f64,
    /// Largest separation r/a.
    #[arg(long, default_value_t = 6.0)]
    r_max: f64,
    /// Smallest height h/a (> 1).
    #[arg(long, default_value_t = 1.0001)]
    h_min: f64,
    /// Largest height h/a.
    #[arg(long, default_value_t = 4.0)]
    h_max: f64,
    /// Grid points in r (>= 2).
    #[arg(long, default_value_t = 61)]
    r_points: usize,
    /// Grid points in h (>= 2).
    #[arg(long, default_value_t = 61)]
    h_points: usize,
}

const BROWNIAN_ABOUT: &str = "\
Overdamped Brownian dynamics of spheres with hydrodynamic interactions, near the
boundary given by --confinement (or --scene). One Euler-Maruyama step of length --dt is

    x(t + dt) = x + (M F + kT div M) dt + sqrt(2 kT dt) B W,    M = B B^T,

with M the grand mobility at the current positions, F the external forces
(--weight, --repulsion-strength, --debye-length, --trap), W independent standard normal
numbers and B the Cholesky factor of M (or, with --lanczos TOL, M^(1/2) W from the
Lanczos iteration on matrix-free products, for large N). --moments F (the default)
moves the centres of torque-free spheres (M is 3N x 3N); --moments FT also rotates them
(M is 6N x 6N; --torque applies a torque to every sphere) and writes each sphere's
orientation as a unit quaternion. FTS is not implemented.

--scheme fixman uses Fixman's midpoint scheme instead:

    x* = x + (dt/2) M F + sqrt(kT dt/2) B W,
    x(t + dt) = x + dt M* F* + sqrt(2 kT dt) M* B^-T W,

with M*, F* at the midpoint x*: the drift comes from the second mobility (no divergence
kernels), the deterministic part is second order; two factorisations per step.

THE DRIFT kT div M
    Near a wall the mobility depends on position (a sphere moves more slowly the closer
    it is), and the Ito equation above needs the drift kT div M (the divergence of the
    mobility with respect to the positions) for the Boltzmann distribution exp(-U/kT)
    to be the stationary one. It pushes spheres away from a wall. --no-drift leaves it
    out: this is WRONG near a boundary (the spheres then accumulate where they move
    slowly, sampling exp(-U/kT)/mobility) and exists only to compare against; in
    unbounded fluid (--confinement free) the drift is zero anyway.

UNITS
    Consistent units, as for the other commands: with lengths in m, viscosity in Pa s,
    --kt in J (k_B T = 4.11e-21 J at 298 K) and forces in N, --dt is in s. Dimensionless
    choice: radius a = 1, viscosity 1, --kt 1; time is then in units of
    eta a^3/kT = a^2/(6 pi D_0), with D_0 = kT/(6 pi eta a) the Stokes-Einstein
    diffusion coefficient far from any boundary.

REJECTED STEPS
    A step that would put a sphere into a boundary or into another sphere is rejected
    and redrawn with new random numbers (same positions, same time). This biases the
    dynamics slightly; many rejections mean --dt is too large for the forces near
    contact. The run fails after more than --max-rejections rejections in total.

OUTPUT
    Frames at steps 0, K, 2K, ... (K = --every; the last step only if it is a multiple
    of K). .csv: header step,time,particle,x,y,z (FT: then qw,qx,qy,qz, the orientation
    quaternion, identity at step 0) and one line per particle per frame, every number
    printed to full round-trip precision (time = step * dt). .npy: float64 array of
    shape (frames, N, 3), or (frames, N, 7) at FT (x, y, z, qw, qx, qy, qz), C order
    (numpy.load). The random numbers come from
    ChaCha8 seeded with --seed: the same inputs and seed give the same file on every
    machine.";

/// The system: confinement, truncation, particles, viscosity.
#[derive(Args, Debug)]
struct SystemArgs {
    /// The boundary: free (none), wall, free-surface, interface (needs --lambda) or slit
    /// (needs --gap).
    #[arg(long, value_enum, required_unless_present = "scene")]
    confinement: Option<ConfinementArg>,
    /// Truncation of the multipole expansion: F, FT or FTS.
    #[arg(
        long,
        value_enum,
        ignore_case = true,
        required_unless_present = "scene"
    )]
    moments: Option<MomentsArg>,
    /// A scene file (scenes/*.toml) giving the confinement and the truncation instead of
    /// --confinement and --moments (its other keys concern the generated kernels).
    #[arg(long, value_name = "scene.toml", conflicts_with_all = ["confinement", "moments"])]
    scene: Option<PathBuf>,
    /// CSV file with header x,y,z,radius and one sphere per line.
    #[arg(long, value_name = "particles.csv")]
    particles: PathBuf,
    /// Viscosity of the fluid that holds the spheres.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    viscosity: f64,
    /// Height of the boundary plane z = H [default: 0; not for free].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    boundary_height: Option<f64>,
    /// Interface only: viscosity ratio (liquid below / liquid holding the spheres), >= 0.
    #[arg(long, value_name = "L", allow_negative_numbers = true)]
    lambda: Option<f64>,
    /// Slit only: distance from the lower wall to the upper wall (> 0).
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    gap: Option<f64>,
    /// Accept spheres that overlap each other or cut a boundary (normally an error).
    #[arg(long)]
    allow_overlap: bool,
}

#[derive(Args, Debug)]
struct MobilityArgs {
    #[command(flatten)]
    system: SystemArgs,
    /// Output file: .npy (NumPy float64 array) or .json.
    #[arg(long, value_name = "M.npy|M.json")]
    out: PathBuf,
    /// Check that the matrix is symmetric and positive definite (Cholesky) before
    /// writing it; report on stderr, and fail without writing if it is not.
    #[arg(long)]
    check: bool,
}

#[derive(Args, Debug)]
struct VelocityArgs {
    #[command(flatten)]
    system: SystemArgs,
    /// CSV file of forces (fx,fy,fz) and, for FT and FTS, torques (tx,ty,tz) exerted by
    /// each particle on the fluid, in the order of --particles.
    #[arg(long, value_name = "forces.csv")]
    forces: PathBuf,
    /// FTS only: uniform imposed rate of strain E_inf (symmetric, traceless), either 9
    /// comma-separated Cartesian components row-major E11,E12,E13,E21,E22,E23,E31,E32,E33,
    /// or 5 components in the orthonormal basis B1..B5 (E_m = B_m : E). The 9 components must
    /// be symmetric and traceless to 1e-9 of the largest. Default: zero. The output is then
    /// relative to the ambient flow at each centre (U - U_inf, Omega - Omega_inf).
    #[arg(long, value_name = "E11,E12,...,E33", allow_hyphen_values = true)]
    strain: Option<String>,
    /// FT and FTS: include lubrication (Eq. 19) and solve R U = F by Cholesky; the condition
    /// estimate of R is reported on stderr, and the run fails if it exceeds 1e14.
    #[arg(long)]
    lubrication: bool,
    /// Output CSV file: ux,uy,uz (F) or ux,uy,uz,wx,wy,wz (FT, FTS).
    #[arg(long, value_name = "U.csv")]
    out: PathBuf,
}

/// `brownian`: the system (`--moments` defaults to F), the integration and the external
/// forces.
#[derive(Args, Debug)]
#[command(mut_arg("moments", |a| a
    .required(false)
    .required_unless_present(clap::builder::Resettable::Reset)
    .default_value("F")
    .help("Truncation: F (positions of torque-free spheres) or FT (positions and \
           orientations; external torques allowed); FTS is not implemented for \
           Brownian dynamics")))]
struct BrownianArgs {
    #[command(flatten)]
    system: SystemArgs,
    /// Number of time steps.
    #[arg(long, value_name = "N")]
    steps: usize,
    /// Time step, in the time unit of the other inputs (> 0). Spheres should move much
    /// less than their distance to a boundary or to each other in one step:
    /// sqrt(2 D dt) << gap, with D = kT/(6 pi viscosity radius).
    #[arg(long, value_name = "DT", allow_negative_numbers = true)]
    dt: f64,
    /// Thermal energy k_B T, in energy units (force x length; 4.11e-21 J at 298 K), > 0.
    #[arg(
        long,
        value_name = "KT",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    kt: f64,
    /// Seed of the random numbers (ChaCha8): the same seed gives the same trajectory.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Buoyant weight of each sphere (gravity minus buoyancy), a force -weight e_z, in
    /// force units. The gravitational length is kT/weight.
    #[arg(
        long,
        value_name = "W",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    weight: f64,
    /// Repulsion from each boundary plane (e.g. screened electrostatics), in force units:
    /// strength * exp(-h / debye-length) along the plane's normal into the fluid, with
    /// h = (centre-to-plane distance) - radius the surface-to-plane gap. Not for free.
    #[arg(
        long,
        value_name = "S",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    repulsion_strength: f64,
    /// Decay length of the boundary repulsion (Debye screening length), in length
    /// units (> 0).
    #[arg(
        long,
        value_name = "L",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    debye_length: f64,
    /// FT only: the torque on every sphere, tx,ty,tz in torque units (e.g. a magnetic
    /// field spinning colloidal rollers).
    #[arg(long, value_name = "TX,TY,TZ", allow_hyphen_values = true)]
    torque: Option<String>,
    /// Stiffness of a harmonic trap pulling every sphere towards the axis x = y = 0
    /// (force -K (x, y, 0)), in force per length units (>= 0).
    #[arg(
        long,
        value_name = "K",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    trap: f64,
    /// The time integrator: euler-maruyama (the generated drift kT div M, one mobility
    /// per step) or fixman (midpoint scheme: the drift from a second mobility at a
    /// random midpoint; the deterministic part second order).
    #[arg(long, value_enum, default_value = "euler-maruyama")]
    scheme: SchemeArg,
    /// Form M^(1/2) W by the Lanczos iteration from matrix-free products, to this
    /// relative tolerance (e.g. 1e-6), instead of the dense Cholesky factor: for large
    /// N. Not with --scheme fixman.
    #[arg(long, value_name = "TOL")]
    lanczos: Option<f64>,
    /// Leave out the drift kT div M. WRONG near a boundary (wrong equilibrium
    /// distribution); for comparison only. Only with --scheme euler-maruyama.
    #[arg(long)]
    no_drift: bool,
    /// Lubricated Brownian dynamics (Brownian Stokesian dynamics): velocities, noise
    /// and drift from the resistance with lubrication of Eq. 19 (as `stokesian
    /// resistance`), R^-1 F + kT div R^-1 + sqrt(2 kT / dt) L^-T W with R = L L^T, the
    /// drift by a random finite difference. F (torque-free spheres) or FT; Cholesky
    /// noise and --scheme euler-maruyama only. Each step factors three resistances.
    #[arg(long)]
    lubrication: bool,
    /// The random finite difference's step with --lubrication, in units of each
    /// sphere's radius; keep it below the smallest gap over the radius.
    #[arg(
        long,
        value_name = "DELTA",
        default_value_t = 1e-3,
        requires = "lubrication"
    )]
    rfd_step: f64,
    /// Write every K-th step (step 0 always).
    #[arg(long, value_name = "K", default_value_t = 1)]
    every: usize,
    /// Fail after more than M rejected (redrawn) steps in total.
    #[arg(long, value_name = "M", default_value_t = 1000)]
    max_rejections: usize,
    /// Output trajectory: .csv (step,time,particle,x,y,z, and qw,qx,qy,qz at FT) or
    /// .npy (frames x N x 3, or frames x N x 7 at FT).
    #[arg(long, value_name = "traj.csv|traj.npy")]
    out: PathBuf,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum SchemeArg {
    /// Euler-Maruyama with the generated drift.
    EulerMaruyama,
    /// Fixman's midpoint scheme.
    Fixman,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ConfinementArg {
    /// Unbounded fluid.
    Free,
    /// No-slip plane wall at z = H.
    Wall,
    /// Flat free surface at z = H.
    #[value(alias = "free_surface")]
    FreeSurface,
    /// Flat liquid-liquid interface at z = H, viscosity ratio --lambda.
    Interface,
    /// Two no-slip walls at z = H and z = H + --gap.
    Slit,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum MomentsArg {
    /// Forces only.
    #[value(name = "F")]
    F,
    /// Forces and torques.
    #[value(name = "FT")]
    Ft,
    /// Forces, torques and stresslets.
    #[value(name = "FTS")]
    Fts,
}

impl SystemArgs {
    /// With `--scene`, read the confinement and the truncation from the scene file (clap
    /// has already made `--scene` exclusive with `--confinement` and `--moments`, and
    /// required one or the other).
    fn resolve_scene(&mut self) -> Result<(), CliError> {
        let Some(path) = &self.scene else {
            return Ok(());
        };
        let shown = path.display().to_string();
        let text = fs::read_to_string(path).map_err(|source| CliError::Read {
            what: "scene",
            path: shown.clone(),
            source,
        })?;
        let bad = |reason: String| CliError::Scene {
            path: shown.clone(),
            reason,
        };
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| bad(e.to_string()))?;
        const KEYS: [&str; 6] = [
            "name",
            "confinement",
            "moments",
            "radii",
            "outputs",
            "description",
        ];
        if let Some(key) = table.keys().find(|k| !KEYS.contains(&k.as_str())) {
            return Err(bad(format!(
                "unknown key `{key}` (a scene has {})",
                KEYS.join(", ")
            )));
        }
        let string = |key: &str| match table.get(key) {
            Some(toml::Value::String(v)) => Ok(v.clone()),
            Some(_) => Err(bad(format!("`{key}` must be a string"))),
            None => Err(bad(format!("`{key}` is missing"))),
        };
        let c = string("confinement")?;
        self.confinement = Some(
            ConfinementArg::from_str(&c, true)
                .map_err(|_| bad(format!("unknown confinement `{c}`")))?,
        );
        let m = string("moments")?;
        self.moments = Some(
            MomentsArg::from_str(&m, true)
                .map_err(|_| bad(format!("unknown moments `{m}` (F, FT or FTS)")))?,
        );
        Ok(())
    }

    /// The confinement kind (given, or read by [`SystemArgs::resolve_scene`]).
    fn kind(&self) -> ConfinementArg {
        self.confinement
            .expect("clap requires --confinement or --scene, and resolve_scene reads the scene")
    }

    /// The truncation (given, or read by [`SystemArgs::resolve_scene`]).
    fn truncation(&self) -> MomentsArg {
        self.moments
            .expect("clap requires --moments or --scene, and resolve_scene reads the scene")
    }
}

impl MomentsArg {
    fn moments(self) -> Moments {
        match self {
            MomentsArg::F => Moments::F,
            MomentsArg::Ft => Moments::FT,
            MomentsArg::Fts => Moments::FTS,
        }
    }

    fn name(self) -> &'static str {
        match self {
            MomentsArg::F => "F",
            MomentsArg::Ft => "FT",
            MomentsArg::Fts => "FTS",
        }
    }
}

/// Everything that can go wrong, each with a message that names the file, the line and
/// the particle where there is one. Line numbers count from 1 (the header).
#[derive(Debug, Error)]
enum CliError {
    /// The resistance could not be formed.
    #[error("{0}")]
    Resistance(#[from] stokesian::ResistanceError),
    /// The resistance is too ill-conditioned to solve.
    #[error("the resistance with lubrication is too ill-conditioned to solve (condition estimate {0:e} > 1e14); nothing written")]
    IllConditioned(f64),
    /// `--check` found the matrix not symmetric positive definite.
    #[error("the {moments} matrix is not symmetric positive definite: |M - M^T|/|M| = {asymmetry:e}, Cholesky {cholesky}; nothing written")]
    NotSpd {
        moments: &'static str,
        asymmetry: f64,
        cholesky: &'static str,
    },
    /// A file cannot be read.
    #[error("cannot read {what} file {path}: {source}")]
    Read {
        what: &'static str,
        path: String,
        source: io::Error,
    },
    /// A CSV file has no header line.
    #[error("{path}: the file is empty; the first line must be the header {expected}")]
    NoHeader { path: String, expected: String },
    /// A CSV file's header is not the expected one.
    #[error("{path} line {line}: header must be {expected}, found {found}{hint}")]
    Header {
        path: String,
        line: usize,
        expected: String,
        found: String,
        hint: &'static str,
    },
    /// A data line has the wrong number of fields.
    #[error(
        "{path} line {line}: expected {expected} comma-separated fields ({columns}), found {found}"
    )]
    FieldCount {
        path: String,
        line: usize,
        expected: usize,
        columns: String,
        found: usize,
    },
    /// A field is not a number.
    #[error("{path} line {line}: {column} = {field:?} is not a number")]
    NotANumber {
        path: String,
        line: usize,
        column: String,
        field: String,
    },
    /// The particles file has a header and no particles.
    #[error("{path}: no particles (the file has a header but no data lines)")]
    NoParticles { path: String },
    /// A particle is invalid: coordinates, radius, position relative to a boundary.
    #[error("{path} line {line} (particle {index}): {reason}")]
    Particle {
        path: String,
        line: usize,
        index: usize,
        reason: String,
    },
    /// Two spheres overlap.
    #[error("{path} lines {line_a} and {line_b} (particles {a} and {b}): {reason}")]
    Pair {
        path: String,
        line_a: usize,
        line_b: usize,
        a: usize,
        b: usize,
        reason: String,
    },
    /// A command-line value is out of range.
    #[error("{option} {value}: {reason}")]
    BadOption {
        option: &'static str,
        value: String,
        reason: String,
    },
    /// A confinement needs an option that was not given.
    #[error("--confinement {confinement} needs {option} ({what})")]
    MissingOption {
        confinement: &'static str,
        option: &'static str,
        what: &'static str,
    },
    /// An option was given that the confinement or truncation does not use.
    #[error("{option} does not apply to {context}")]
    Inapplicable {
        option: &'static str,
        context: String,
    },
    /// The forces file and the particles file disagree in length.
    #[error("{forces}: {rows} rows of forces for the {n} particles of {particles}; give one row per particle, in the same order")]
    RowCount {
        forces: String,
        rows: usize,
        particles: String,
        n: usize,
    },
    /// The output path cannot be used.
    #[error("--out {path}: {reason}")]
    BadOut { path: String, reason: String },
    /// Writing the output failed.
    #[error("cannot write {path}: {source}")]
    Write { path: String, source: io::Error },
    /// The result is not a finite number (overlapping spheres accepted with
    /// --allow-overlap can make the kernels meaningless).
    #[error("{0}")]
    Numerical(String),
    /// Brownian dynamics rejected too many steps.
    #[error("{rejections} rejected steps, more than --max-rejections {max}: the last, at step {step}, {reason}. The time step is too large for the forces and distances near contact: use a smaller --dt (or raise --max-rejections)")]
    TooManyRejections {
        rejections: usize,
        max: usize,
        step: usize,
        reason: String,
    },
    /// A scene file is not usable.
    #[error("scene file {path}: {reason}")]
    Scene { path: String, reason: String },
    /// The doublet study failed.
    #[error("{0}; nothing written")]
    Doublet(#[from] stokesian::doublet::DoubletError),
    /// A plot could not be drawn.
    #[error("cannot draw {path}: {reason}")]
    Plot { path: String, reason: String },
    /// Brownian dynamics failed for another reason.
    #[error("{0}; nothing written")]
    Brownian(BrownianError),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Mobility(mut args) => args
            .system
            .resolve_scene()
            .and_then(|()| run_mobility(&args)),
        Command::Velocity(mut args) => args
            .system
            .resolve_scene()
            .and_then(|()| run_velocity(&args)),
        Command::Resistance(mut args) => args
            .system
            .resolve_scene()
            .and_then(|()| run_resistance(&args)),
        Command::Brownian(mut args) => args
            .system
            .resolve_scene()
            .and_then(|()| run_brownian(&args)),
        Command::Doublet(args) => run_doublet(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stokesian: error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// A numeric CSV table with the line number of each data row.
struct Table {
    path: String,
    rows: Vec<Vec<f64>>,
    lines: Vec<usize>,
}

/// Read a CSV file whose header names exactly `columns` (case-insensitive, spaces and
/// double quotes around names ignored) and whose data are numbers.
fn read_table(
    what: &'static str,
    path: &Path,
    columns: &[&str],
    hint: &'static str,
) -> Result<Table, CliError> {
    let shown = path.display().to_string();
    let text = fs::read_to_string(path).map_err(|source| CliError::Read {
        what,
        path: shown.clone(),
        source,
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let expected = columns.join(",");
    let mut header_seen = false;
    let mut rows = Vec::new();
    let mut lines = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let trimmed = raw.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = trimmed
            .split(',')
            .map(|f| {
                let f = f.trim();
                f.strip_prefix('"')
                    .and_then(|g| g.strip_suffix('"'))
                    .unwrap_or(f)
                    .trim()
            })
            .collect();
        if !header_seen {
            let ok = fields.len() == columns.len()
                && fields
                    .iter()
                    .zip(columns)
                    .all(|(f, c)| f.eq_ignore_ascii_case(c));
            if !ok {
                return Err(CliError::Header {
                    path: shown,
                    line,
                    expected,
                    found: fields.join(","),
                    hint,
                });
            }
            header_seen = true;
            continue;
        }
        if fields.len() != columns.len() {
            return Err(CliError::FieldCount {
                path: shown,
                line,
                expected: columns.len(),
                columns: expected,
                found: fields.len(),
            });
        }
        let mut row = Vec::with_capacity(columns.len());
        for (f, c) in fields.iter().zip(columns) {
            match f.parse::<f64>() {
                Ok(v) => row.push(v),
                Err(_) => {
                    return Err(CliError::NotANumber {
                        path: shown,
                        line,
                        column: (*c).to_string(),
                        field: (*f).to_string(),
                    })
                }
            }
        }
        rows.push(row);
        lines.push(line);
    }
    if !header_seen {
        return Err(CliError::NoHeader {
            path: shown,
            expected,
        });
    }
    Ok(Table {
        path: shown,
        rows,
        lines,
    })
}

/// The validated system and where its particles came from.
struct Setup {
    system: System,
    table: Table,
    moments: MomentsArg,
}

fn particle_error(table: &Table, index: usize, reason: String) -> CliError {
    CliError::Particle {
        path: table.path.clone(),
        line: table.lines[index],
        index,
        reason,
    }
}

/// The confinement from the command line, with a clear error for a missing or
/// inapplicable parameter.
fn confinement(args: &SystemArgs) -> Result<Confinement, CliError> {
    let (name, shown) = match args.kind() {
        ConfinementArg::Free => ("free", "free"),
        ConfinementArg::Wall => ("wall", "wall"),
        ConfinementArg::FreeSurface => ("free_surface", "free-surface"),
        ConfinementArg::Interface => ("interface", "interface"),
        ConfinementArg::Slit => ("slit", "slit"),
    };
    let inapplicable = |option: &'static str| CliError::Inapplicable {
        option,
        context: format!("--confinement {shown}"),
    };
    if args.lambda.is_some() && args.kind() != ConfinementArg::Interface {
        return Err(inapplicable("--lambda"));
    }
    if args.gap.is_some() && args.kind() != ConfinementArg::Slit {
        return Err(inapplicable("--gap"));
    }
    let height = args.boundary_height.unwrap_or(0.0);
    let params: Vec<f64> = match args.kind() {
        ConfinementArg::Free => {
            if args.boundary_height.is_some() {
                return Err(inapplicable("--boundary-height"));
            }
            vec![]
        }
        ConfinementArg::Wall | ConfinementArg::FreeSurface => vec![height],
        ConfinementArg::Interface => {
            let lambda = args.lambda.ok_or(CliError::MissingOption {
                confinement: shown,
                option: "--lambda",
                what: "the viscosity ratio of the liquid below the interface to the liquid \
                       holding the spheres",
            })?;
            vec![height, lambda]
        }
        ConfinementArg::Slit => {
            let gap = args.gap.ok_or(CliError::MissingOption {
                confinement: shown,
                option: "--gap",
                what: "the distance from the lower wall to the upper wall",
            })?;
            vec![height, gap]
        }
    };
    Confinement::from_name(name, &params).ok_or_else(|| CliError::BadOption {
        option: "--confinement",
        value: shown.to_string(),
        reason: "not a confinement the kernels know".to_string(),
    })
}

/// Map the library's 0-based particle errors to file lines and option names.
fn input_error(e: InputError, table: &Table) -> CliError {
    let pair = |a: usize, b: usize, reason: String| CliError::Pair {
        path: table.path.clone(),
        line_a: table.lines[a],
        line_b: table.lines[b],
        a,
        b,
        reason,
    };
    #[allow(unreachable_patterns)]
    match e {
        InputError::Empty => CliError::NoParticles {
            path: table.path.clone(),
        },
        InputError::NonFinitePosition { index, axis, value } => particle_error(
            table,
            index,
            format!("coordinate {axis} is {value}, not a finite number"),
        ),
        InputError::BadRadius { index, value } => particle_error(
            table,
            index,
            format!("radius {value} must be a positive finite number"),
        ),
        InputError::BadViscosity(value) => CliError::BadOption {
            option: "--viscosity",
            value: value.to_string(),
            reason: "must be a positive finite number".to_string(),
        },
        InputError::BadParameter { name, value, why } => CliError::BadOption {
            option: match name {
                "lambda" => "--lambda",
                "gap" => "--gap",
                "height" => "--boundary-height",
                _ => "confinement parameter",
            },
            value: value.to_string(),
            reason: why.to_string(),
        },
        InputError::OutsideFluid { index, z, boundary } => particle_error(
            table,
            index,
            format!("centre z = {z} is not inside the fluid (boundary at z = {boundary})"),
        ),
        InputError::OverlapsBoundary {
            index,
            a,
            distance,
            boundary,
        } => particle_error(
            table,
            index,
            format!(
                "sphere of radius {a} overlaps the boundary at z = {boundary} \
                 (centre-to-boundary distance {distance} < radius; \
                 --allow-overlap accepts this)"
            ),
        ),
        InputError::Overlap {
            first,
            second,
            distance,
            sum,
        } => pair(
            first,
            second,
            format!(
                "spheres overlap: centre distance {distance} < sum of radii {sum} \
                 (--allow-overlap accepts this)"
            ),
        ),
        other => CliError::Numerical(other.to_string()),
    }
}

/// Read and validate the particles; the spinner shows progress on a terminal.
fn setup(args: &SystemArgs) -> Result<Setup, CliError> {
    let conf = confinement(args)?;
    let table = read_table(
        "particles",
        &args.particles,
        &["x", "y", "z", "radius"],
        " (one sphere per line: centre x,y,z and radius)",
    )?;
    if table.rows.is_empty() {
        return Err(CliError::NoParticles { path: table.path });
    }
    let particles: Vec<Particle> = table
        .rows
        .iter()
        .map(|r| Particle {
            x: [r[0], r[1], r[2]],
            a: r[3],
        })
        .collect();
    let system = System::new(conf, args.viscosity, particles, args.allow_overlap)
        .map_err(|e| input_error(e, &table))?;
    // Even with --allow-overlap, coincident centres make the pair kernels undefined.
    let ps = system.particles();
    for i in 0..ps.len() {
        for j in i + 1..ps.len() {
            if ps[i].x == ps[j].x {
                return Err(CliError::Pair {
                    path: table.path.clone(),
                    line_a: table.lines[i],
                    line_b: table.lines[j],
                    a: i,
                    b: j,
                    reason: "the two spheres have the same centre; the mobility is undefined \
                             even with --allow-overlap"
                        .to_string(),
                });
            }
        }
    }
    Ok(Setup {
        system,
        table,
        moments: args.truncation(),
    })
}

/// Check the output path before any work: a file name in an existing directory.
fn check_out(out: &Path, extensions: &[&str]) -> Result<(), CliError> {
    let shown = out.display().to_string();
    let bad = |reason: String| CliError::BadOut {
        path: shown.clone(),
        reason,
    };
    if out.file_name().is_none() {
        return Err(bad("not a file name".to_string()));
    }
    if out.is_dir() {
        return Err(bad("is a directory".to_string()));
    }
    let dir = parent_dir(out);
    if !dir.is_dir() {
        return Err(bad(format!(
            "the directory {} does not exist",
            dir.display()
        )));
    }
    if !extensions.is_empty() {
        let ext = out
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        if !extensions.iter().any(|e| Some(e.to_string()) == ext) {
            let list: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
            return Err(bad(format!(
                "the file name must end in {}",
                list.join(" or ")
            )));
        }
    }
    Ok(())
}

fn parent_dir(out: &Path) -> PathBuf {
    match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Write through a temporary file in the output's directory, renamed onto `out` only
/// when everything was written; on failure the temporary file is removed.
fn write_atomically(
    out: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), CliError> {
    let shown = out.display().to_string();
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = parent_dir(out).join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| -> io::Result<()> {
        let file = File::options().write(true).create_new(true).open(&tmp)?;
        let mut w = BufWriter::new(file);
        write(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, out)
    })();
    result.map_err(|source| {
        let _ = fs::remove_file(&tmp);
        CliError::Write {
            path: shown,
            source,
        }
    })
}

/// A spinner on stderr, drawn only when stderr is a terminal.
fn spinner() -> ProgressBar {
    let pb = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
        .unwrap_or_else(|_| ProgressStyle::default_spinner());
    pb.set_style(style);
    pb.enable_steady_tick(Duration::from_millis(100));
    pb
}

/// Turn the spinner into a bar over `len` rows.
fn rows_bar(pb: &ProgressBar, len: u64, message: String) {
    let style = ProgressStyle::with_template("{msg} {wide_bar} {pos}/{len} rows [{elapsed}]")
        .unwrap_or_else(|_| ProgressStyle::default_bar());
    pb.set_style(style);
    pb.set_length(len);
    pb.set_position(0);
    pb.set_message(message);
}

/// Say what was written, on a terminal only (scripts get silence).
fn report(message: String) {
    if io::stderr().is_terminal() {
        eprintln!("{message}");
    }
}

fn check_finite(values: &[f64], what: &str) -> Result<(), CliError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(CliError::Numerical(format!(
            "the {what} has entries that are not finite numbers \
             (spheres accepted with --allow-overlap too close together?)"
        )))
    }
}

fn run_mobility(args: &MobilityArgs) -> Result<(), CliError> {
    run_matrix(args, false)
}

fn run_resistance(args: &MobilityArgs) -> Result<(), CliError> {
    run_matrix(args, true)
}

/// `mobility` and `resistance`: assemble, optionally check, and write the matrix.
fn run_matrix(args: &MobilityArgs, resistance: bool) -> Result<(), CliError> {
    check_out(&args.out, &["npy", "json"])?;
    let json = args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let pb = &spinner();
    pb.set_message("reading particles");
    let setup = setup(&args.system);
    let setup = match setup {
        Ok(s) => s,
        Err(e) => {
            pb.finish_and_clear();
            return Err(e);
        }
    };
    let n = setup.system.len();
    let moments = setup.moments;
    let dim = moments.moments().per_particle() * n;
    let what = if resistance { "resistance" } else { "mobility" };
    pb.set_message(format!(
        "assembling the {dim} x {dim} {} grand {what} of {n} spheres",
        moments.name()
    ));
    let m = if resistance {
        match setup
            .system
            .resistance(moments.moments(), &stokesian::Lubrication::default())
        {
            Ok(m) => m,
            Err(e) => {
                pb.finish_and_clear();
                return Err(e.into());
            }
        }
    } else {
        setup.system.mobility(moments.moments())
    };
    if args.check {
        pb.set_message("checking symmetry and positive definiteness (Cholesky)");
        let c = stokesian::check_spd(&m);
        let cholesky = if c.positive_definite {
            "succeeds"
        } else {
            "fails"
        };
        if !c.passed() {
            pb.finish_and_clear();
            return Err(CliError::NotSpd {
                moments: moments.name(),
                asymmetry: c.asymmetry,
                cholesky,
            });
        }
        eprintln!(
            "check: |M - M^T|/|M| = {:e}; Cholesky {cholesky}: symmetric positive definite",
            c.asymmetry
        );
    }
    let result = check_finite(m.as_slice(), "mobility").and_then(|()| {
        rows_bar(
            pb,
            m.nrows() as u64,
            format!("writing {}", args.out.display()),
        );
        write_atomically(&args.out, |w| {
            if json {
                write_json(w, &m, n, moments.name(), pb)
            } else {
                write_npy(w, &m, pb)
            }
        })
    });
    pb.finish_and_clear();
    result?;
    report(format!(
        "wrote {}: {dim} x {dim} {} grand {what} of {n} spheres",
        args.out.display(),
        moments.name()
    ));
    Ok(())
}

/// NPY format version 1.0: magic, version, little-endian header length, a Python dict
/// literal padded with spaces to a multiple of 64 bytes (newline included), then the
/// data.
fn write_npy(w: &mut impl Write, m: &DMatrix<f64>, pb: &ProgressBar) -> io::Result<()> {
    let (rows, cols) = m.shape();
    // nalgebra stores columns contiguously: written as they are, in Fortran order
    write_npy_header(w, &[rows, cols], true)?;
    let mut bytes = Vec::with_capacity(8 * rows);
    for col in m.as_slice().chunks_exact(rows) {
        bytes.clear();
        bytes.extend(col.iter().flat_map(|v| v.to_le_bytes()));
        w.write_all(&bytes)?;
        pb.inc(1);
    }
    Ok(())
}

/// The NPY v1.0 preamble of a little-endian float64 array of any `shape`, in C order
/// (last index fastest) or Fortran order (first index fastest).
fn write_npy_header(w: &mut impl Write, shape: &[usize], fortran: bool) -> io::Result<()> {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    // a 1-tuple needs its trailing comma
    let tuple = if dims.len() == 1 {
        format!("{},", dims[0])
    } else {
        dims.join(", ")
    };
    let order = if fortran { "True" } else { "False" };
    let mut header = format!("{{'descr': '<f8', 'fortran_order': {order}, 'shape': ({tuple}), }}");
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    header.push('\n');
    let len = u16::try_from(header.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidData, "NPY header too long"))?;
    w.write_all(b"\x93NUMPY\x01\x00")?;
    w.write_all(&len.to_le_bytes())?;
    w.write_all(header.as_bytes())
}

/// JSON with every number in Rust's shortest round-trip form (valid JSON for finite
/// numbers, which `check_finite` guarantees).
fn write_json(
    w: &mut impl Write,
    m: &DMatrix<f64>,
    n: usize,
    moments: &str,
    pb: &ProgressBar,
) -> io::Result<()> {
    let (rows, cols) = m.shape();
    writeln!(w, "{{")?;
    writeln!(w, "  \"layout\": \"{LAYOUT}\",")?;
    writeln!(w, "  \"moments\": \"{moments}\",")?;
    writeln!(w, "  \"n\": {n},")?;
    writeln!(w, "  \"dimension\": {rows},")?;
    writeln!(w, "  \"matrix\": [")?;
    for i in 0..rows {
        write!(w, "    [")?;
        for j in 0..cols {
            if j > 0 {
                write!(w, ", ")?;
            }
            write!(w, "{:?}", m[(i, j)])?;
        }
        writeln!(w, "]{}", if i + 1 < rows { "," } else { "" })?;
        pb.inc(1);
    }
    writeln!(w, "  ]")?;
    writeln!(w, "}}")
}

/// Comma-separated finite numbers given to `option`.
fn parse_components(option: &'static str, text: &str) -> Result<Vec<f64>, CliError> {
    let bad = |reason: String| CliError::BadOption {
        option,
        value: text.to_string(),
        reason,
    };
    let mut values = Vec::new();
    for (k, f) in text.split(',').enumerate() {
        let f = f.trim();
        let v: f64 = f
            .parse()
            .map_err(|_| bad(format!("component {} ({f:?}) is not a number", k + 1)))?;
        if !v.is_finite() {
            return Err(bad(format!(
                "component {} is {v}, not a finite number",
                k + 1
            )));
        }
        values.push(v);
    }
    Ok(values)
}

/// A uniform rate of strain in the 5-component orthonormal basis, `E_m = B_m : E`.
fn parse_strain(text: &str) -> Result<[f64; 5], CliError> {
    let bad = |reason: String| CliError::BadOption {
        option: "--strain",
        value: text.to_string(),
        reason,
    };
    let values = parse_components("--strain", text)?;
    match values.len() {
        5 => {
            let mut e = [0.0; 5];
            e.copy_from_slice(&values);
            Ok(e)
        }
        9 => {
            let e = |i: usize, j: usize| values[3 * i + j];
            let scale = values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let tol = 1e-9 * scale;
            for (i, j) in [(0, 1), (0, 2), (1, 2)] {
                if (e(i, j) - e(j, i)).abs() > tol {
                    return Err(bad(format!(
                        "not symmetric: E{}{} = {} but E{}{} = {}",
                        i + 1,
                        j + 1,
                        e(i, j),
                        j + 1,
                        i + 1,
                        e(j, i)
                    )));
                }
            }
            let trace = e(0, 0) + e(1, 1) + e(2, 2);
            if trace.abs() > tol {
                return Err(bad(format!(
                    "not traceless: E11 + E22 + E33 = {trace} (an incompressible flow has \
                     a traceless rate of strain)"
                )));
            }
            let mut out = [0.0; 5];
            for (m, b) in kernels::STRAIN_BASIS.iter().enumerate() {
                out[m] = (0..3)
                    .flat_map(|i| (0..3).map(move |j| (i, j)))
                    .map(|(i, j)| b[i][j] * e(i, j))
                    .sum();
            }
            Ok(out)
        }
        k => Err(bad(format!(
            "expected 9 comma-separated Cartesian components E11,E12,E13,E21,E22,E23,E31,\
             E32,E33 (row-major) or 5 components in the orthonormal basis B1..B5, found {k}"
        ))),
    }
}

fn run_velocity(args: &VelocityArgs) -> Result<(), CliError> {
    check_out(&args.out, &[])?;
    let moments = args.system.truncation();
    let strain = match (&args.strain, moments) {
        (None, _) => [0.0; 5],
        (Some(s), MomentsArg::Fts) => parse_strain(s)?,
        (Some(_), m) => {
            return Err(CliError::Inapplicable {
                option: "--strain",
                context: format!(
                    "--moments {}: without stresslets the spheres follow a uniform strain \
                     and U - U_inf does not depend on it (use --moments FTS)",
                    m.name()
                ),
            })
        }
    };
    let pb = spinner();
    pb.set_message("reading input");
    let result = velocity(args, moments, strain, &pb);
    pb.finish_and_clear();
    let (n, what) = result?;
    report(format!(
        "wrote {}: {what} of {n} spheres ({})",
        args.out.display(),
        moments.name()
    ));
    Ok(())
}

fn velocity(
    args: &VelocityArgs,
    moments: MomentsArg,
    strain: [f64; 5],
    pb: &ProgressBar,
) -> Result<(usize, &'static str), CliError> {
    let setup = setup(&args.system)?;
    let n = setup.system.len();
    let torques = moments != MomentsArg::F;
    let (columns, hint): (&[&str], &'static str) = if torques {
        (
            &["fx", "fy", "fz", "tx", "ty", "tz"],
            " (force and torque on the fluid, one particle per line)",
        )
    } else {
        (
            &["fx", "fy", "fz"],
            " (force on the fluid, one particle per line; torques need --moments FT or FTS)",
        )
    };
    let forces = read_table("forces", &args.forces, columns, hint)?;
    if forces.rows.len() != n {
        return Err(CliError::RowCount {
            forces: forces.path,
            rows: forces.rows.len(),
            particles: setup.table.path,
            n,
        });
    }
    for (index, row) in forces.rows.iter().enumerate() {
        for (v, c) in row.iter().zip(columns) {
            if !v.is_finite() {
                return Err(particle_error(
                    &forces,
                    index,
                    format!("{c} = {v} is not a finite number"),
                ));
            }
        }
    }
    // moment-major: all forces, then all torques
    let k = if torques { 6 } else { 3 };
    let mut x = vec![0.0; k * n];
    for (a, row) in forces.rows.iter().enumerate() {
        for i in 0..3 {
            x[3 * a + i] = row[i];
            if torques {
                x[3 * n + 3 * a + i] = row[3 + i];
            }
        }
    }
    let u = match moments {
        MomentsArg::Ft | MomentsArg::Fts if args.lubrication => {
            pb.set_message(format!(
                "forming the {} resistance with lubrication of {n} spheres",
                moments.name()
            ));
            let r = setup
                .system
                .resistance(moments.moments(), &stokesian::Lubrication::default())?;
            pb.set_message("solving R U = F (Cholesky)");
            let (u, cond) = if moments == MomentsArg::Fts {
                stokesian::solve_resistance_fts(&r, &x, &strain)?
            } else {
                stokesian::solve_resistance(&r, &x)?
            };
            pb.suspend(|| eprintln!("stokesian: condition estimate of R: {cond:e}"));
            if cond.is_nan() || cond > 1e14 {
                return Err(CliError::IllConditioned(cond));
            }
            u
        }
        MomentsArg::F if args.lubrication => {
            return Err(CliError::Inapplicable {
                option: "--lubrication",
                context: "--moments F: lubrication needs torques and rotations (use FT or FTS)"
                    .to_string(),
            })
        }
        MomentsArg::F | MomentsArg::Ft => {
            pb.set_message(format!(
                "computing velocities of {n} spheres (matrix-free, {} pairs)",
                n * (n + 1) / 2
            ));
            setup.system.apply(moments.moments(), &x)
        }
        MomentsArg::Fts => {
            let dim = 11 * n;
            pb.set_message(format!(
                "assembling the {dim} x {dim} FTS grand mobility of {n} spheres"
            ));
            let m = setup.system.mobility(Moments::FTS);
            check_finite(m.as_slice(), "mobility")?;
            pb.set_message("solving for the stresslets");
            let (u, cholesky) = stokesian::solve_fts(&m, &x, &strain).map_err(|reason| {
                CliError::Numerical(format!(
                    "{reason} (spheres accepted with --allow-overlap, or a narrow slit?)"
                ))
            })?;
            if !cholesky {
                pb.suspend(|| {
                    eprintln!(
                        "stokesian: warning: the stresslet block M_ES is not positive \
                         definite (spheres accepted with --allow-overlap, or a narrow slit?); \
                         solved by LU"
                    )
                });
            }
            u
        }
    };
    check_finite(&u, "velocity")?;
    pb.set_message(format!("writing {}", args.out.display()));
    write_atomically(&args.out, |w| {
        writeln!(
            w,
            "{}",
            if torques {
                "ux,uy,uz,wx,wy,wz"
            } else {
                "ux,uy,uz"
            }
        )?;
        for a in 0..n {
            let mut fields: Vec<String> = (0..3).map(|i| format!("{:?}", u[3 * a + i])).collect();
            if torques {
                fields.extend((0..3).map(|i| format!("{:?}", u[3 * n + 3 * a + i])));
            }
            writeln!(w, "{}", fields.join(","))?;
        }
        Ok(())
    })?;
    Ok((
        n,
        if torques {
            "velocities and rotation rates"
        } else {
            "velocities"
        },
    ))
}

/// A bar over the `len` time steps.
fn steps_bar(pb: &ProgressBar, len: u64, message: String) {
    let style = ProgressStyle::with_template(
        "{msg} {wide_bar} {pos}/{len} steps [{elapsed}, {per_sec}, eta {eta}]",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    pb.set_style(style);
    pb.set_length(len);
    pb.set_position(0);
    pb.set_message(message);
}

/// A positive finite option value.
fn positive(option: &'static str, value: f64, what: &str) -> Result<(), CliError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CliError::BadOption {
            option,
            value: value.to_string(),
            reason: format!("{what} must be a positive finite number"),
        })
    }
}

/// A finite option value.
fn finite(option: &'static str, value: f64) -> Result<(), CliError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(CliError::BadOption {
            option,
            value: value.to_string(),
            reason: "must be a finite number".to_string(),
        })
    }
}

fn run_brownian(args: &BrownianArgs) -> Result<(), CliError> {
    check_out(&args.out, &["csv", "npy"])?;
    let npy = args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("npy"));
    let moments = args.system.truncation();
    if moments == MomentsArg::Fts {
        return Err(CliError::BadOption {
            option: "--moments",
            value: "FTS".to_string(),
            reason: "Brownian dynamics is implemented at the F level (positions of \
                     torque-free spheres) and the FT level (positions and orientations); \
                     give --moments F or FT"
                .to_string(),
        });
    }
    let torque = match &args.torque {
        None => [0.0; 3],
        Some(_) if moments != MomentsArg::Ft => {
            return Err(CliError::Inapplicable {
                option: "--torque",
                context: "--moments F (torques need --moments FT)".to_string(),
            })
        }
        Some(text) => <[f64; 3]>::try_from(parse_components("--torque", text)?).map_err(|v| {
            CliError::BadOption {
                option: "--torque",
                value: text.clone(),
                reason: format!("needs 3 components tx,ty,tz, found {}", v.len()),
            }
        })?,
    };
    let scheme = match args.scheme {
        SchemeArg::EulerMaruyama => stokesian::Scheme::EulerMaruyama,
        SchemeArg::Fixman => stokesian::Scheme::FixmanMidpoint,
    };
    if scheme == stokesian::Scheme::FixmanMidpoint {
        if args.lanczos.is_some() {
            return Err(CliError::Inapplicable {
                option: "--lanczos",
                context: "--scheme fixman (it needs the Cholesky factor)".to_string(),
            });
        }
        if args.no_drift {
            return Err(CliError::Inapplicable {
                option: "--no-drift",
                context: "--scheme fixman (its drift comes from the midpoint, it cannot \
                          be switched off)"
                    .to_string(),
            });
        }
    }
    let lubrication = if args.lubrication {
        if args.lanczos.is_some() {
            return Err(CliError::Inapplicable {
                option: "--lanczos",
                context: "--lubrication (the noise comes from the Cholesky factor of the \
                          resistance)"
                    .to_string(),
            });
        }
        if scheme == stokesian::Scheme::FixmanMidpoint {
            return Err(CliError::Inapplicable {
                option: "--scheme fixman",
                context: "--lubrication (its drift comes from a random finite difference; \
                          use --scheme euler-maruyama)"
                    .to_string(),
            });
        }
        positive(
            "--rfd-step",
            args.rfd_step,
            "the random finite difference's step",
        )?;
        Some(stokesian::LubricatedDynamics {
            lubrication: stokesian::Lubrication::default(),
            rfd_step: args.rfd_step,
        })
    } else {
        None
    };
    let noise = match args.lanczos {
        None => stokesian::Noise::Cholesky,
        Some(tol) => {
            positive("--lanczos", tol, "the relative tolerance")?;
            stokesian::Noise::Lanczos { tol }
        }
    };
    finite("--trap", args.trap)?;
    if args.trap < 0.0 {
        return Err(CliError::BadOption {
            option: "--trap",
            value: format!("{}", args.trap),
            reason: "the trap stiffness must be >= 0".to_string(),
        });
    }
    positive("--dt", args.dt, "the time step")?;
    positive("--kt", args.kt, "the thermal energy kT")?;
    positive("--debye-length", args.debye_length, "the decay length")?;
    finite("--weight", args.weight)?;
    finite("--repulsion-strength", args.repulsion_strength)?;
    if args.every == 0 {
        return Err(CliError::BadOption {
            option: "--every",
            value: "0".to_string(),
            reason: "must be at least 1 (write every K-th step)".to_string(),
        });
    }
    if args.repulsion_strength != 0.0 && args.system.kind() == ConfinementArg::Free {
        return Err(CliError::Inapplicable {
            option: "--repulsion-strength",
            context: "--confinement free (there is no boundary to repel from)".to_string(),
        });
    }
    let pb = &spinner();
    pb.set_message("reading particles");
    let setup = match setup(&args.system) {
        Ok(s) => s,
        Err(e) => {
            pb.finish_and_clear();
            return Err(e);
        }
    };
    let n = setup.system.len();
    let bd = Brownian {
        noise,
        hydrodynamics: true,
        moments: moments.moments(),
        scheme,
        kt: args.kt,
        dt: args.dt,
        drift: !args.no_drift,
        lubrication,
        forces: ExternalForces {
            weight: args.weight,
            strength: args.repulsion_strength,
            debye: args.debye_length,
            trap: args.trap,
            torque,
        },
    };
    steps_bar(
        pb,
        args.steps as u64,
        format!("Brownian dynamics of {n} spheres"),
    );
    let mut tally = Tally::default();
    let mut failure = None;
    let result = write_atomically(&args.out, |w| {
        match simulate(w, setup.system, &bd, args, npy, pb, &mut tally) {
            Ok(()) => Ok(()),
            Err(e) => {
                failure = Some(e);
                Err(io::Error::other("Brownian dynamics failed"))
            }
        }
    });
    pb.finish_and_clear();
    if let Some(e) = failure {
        return Err(e);
    }
    result?;
    if let Some(tol) = args.lanczos {
        eprintln!(
            "stokesian: Lanczos square root to {tol:e}: {:.1} iterations per step on average, \
             at most {}",
            tally.lanczos_sum as f64 / args.steps.max(1) as f64,
            tally.lanczos_max
        );
    }
    report(format!(
        "wrote {}: {} steps of {n} spheres (dt {:?}), {} frames, {} rejected steps redrawn",
        args.out.display(),
        args.steps,
        args.dt,
        args.steps / args.every + 1,
        tally.rejections,
    ));
    Ok(())
}

/// What a Brownian run counts: rejected (redrawn) steps and Lanczos iterations.
#[derive(Default)]
struct Tally {
    rejections: usize,
    lanczos_sum: usize,
    lanczos_max: usize,
}

/// Integrate and write the frames (step 0 and every `--every`-th step) to `w`.
fn simulate(
    w: &mut impl Write,
    system: System,
    bd: &Brownian,
    args: &BrownianArgs,
    npy: bool,
    pb: &ProgressBar,
    tally: &mut Tally,
) -> Result<(), CliError> {
    let io_error = |source: io::Error| CliError::Write {
        path: args.out.display().to_string(),
        source,
    };
    let n = system.len();
    let frames = args.steps / args.every + 1;
    // FT: each sphere's orientation (a unit quaternion) is written too
    let ft = bd.moments == Moments::FT;
    if npy {
        write_npy_header(w, &[frames, n, if ft { 7 } else { 3 }], false).map_err(io_error)?;
    } else if ft {
        writeln!(w, "step,time,particle,x,y,z,qw,qx,qy,qz").map_err(io_error)?;
    } else {
        writeln!(w, "step,time,particle,x,y,z").map_err(io_error)?;
    }
    let frame = |w: &mut dyn Write,
                 step: usize,
                 system: &System,
                 orientation: &[[f64; 4]]|
     -> io::Result<()> {
        let time = step as f64 * bd.dt;
        for (a, p) in system.particles().iter().enumerate() {
            let q: &[f64] = if ft { &orientation[a] } else { &[] };
            if npy {
                for x in p.x.iter().chain(q) {
                    w.write_all(&x.to_le_bytes())?;
                }
            } else {
                write!(
                    w,
                    "{step},{time:?},{a},{:?},{:?},{:?}",
                    p.x[0], p.x[1], p.x[2]
                )?;
                for v in q {
                    write!(w, ",{v:?}")?;
                }
                writeln!(w)?;
            }
        }
        Ok(())
    };
    // the library's run (seeded ChaCha8, invalid steps redrawn); the first write error
    // stops the writing and is reported after the run
    let run = stokesian::Run {
        steps: args.steps,
        every: args.every,
        seed: args.seed,
        max_rejections: args.max_rejections,
    };
    let mut written: io::Result<()> = Ok(());
    let result = system.brownian_run(bd, &run, |step, system, orientation| {
        if written.is_ok() {
            written = frame(&mut *w, step, system, orientation);
        }
        pb.set_position(step as u64);
    });
    let t = match result {
        Ok(t) => t,
        Err(BrownianError::TooManyRejections {
            rejections,
            max,
            step,
            source,
        }) => {
            return Err(CliError::TooManyRejections {
                rejections,
                max,
                step,
                reason: source.to_string(),
            })
        }
        Err(e) => return Err(CliError::Brownian(e)),
    };
    written.map_err(io_error)?;
    *tally = Tally {
        rejections: t.rejections,
        lanczos_sum: t.lanczos_sum,
        lanczos_max: t.lanczos_max,
    };
    Ok(())
}

/// Geometric grid from `lo` to `hi` (both > 0), `n >= 2` points.
fn geometric(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| lo * (hi / lo).powf(k as f64 / (n - 1) as f64))
        .collect()
}

fn run_doublet(args: &DoubletArgs) -> Result<(), CliError> {
    use rayon::prelude::*;
    use stokesian::doublet::{doublet, DoubletPoint};
    check_out(&args.out, &["csv"])?;
    for (option, value, floor) in [
        ("--r-min", args.r_min, 2.0),
        ("--r-max", args.r_max, 2.0),
        ("--h-min", args.h_min, 1.0),
        ("--h-max", args.h_max, 1.0),
    ] {
        finite(option, value)?;
        if value <= floor {
            return Err(CliError::BadOption {
                option,
                value: format!("{value}"),
                reason: format!(
                    "must be above {floor} (touching {})",
                    if floor == 2.0 { "spheres" } else { "the wall" }
                ),
            });
        }
    }
    for (option, lo, hi) in [
        ("--r-max", args.r_min, args.r_max),
        ("--h-max", args.h_min, args.h_max),
    ] {
        if hi <= lo {
            return Err(CliError::BadOption {
                option,
                value: format!("{hi}"),
                reason: format!("must be above the minimum {lo}"),
            });
        }
    }
    for (option, n) in [("--r-points", args.r_points), ("--h-points", args.h_points)] {
        if n < 2 {
            return Err(CliError::BadOption {
                option,
                value: n.to_string(),
                reason: "needs at least 2 points".to_string(),
            });
        }
    }
    let gaps_r = geometric(args.r_min - 2.0, args.r_max - 2.0, args.r_points);
    let gaps_h = geometric(args.h_min - 1.0, args.h_max - 1.0, args.h_points);
    let lub = stokesian::Lubrication::default();
    let pb = ProgressBar::with_draw_target(
        Some((gaps_r.len() * gaps_h.len()) as u64),
        ProgressDrawTarget::stderr(),
    );
    pb.set_style(
        ProgressStyle::with_template(
            "doublet {wide_bar} {pos}/{len} points [{elapsed}, eta {eta}]",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let points: Vec<DoubletPoint> = gaps_r
        .par_iter()
        .flat_map_iter(|&gr| gaps_h.iter().map(move |&gh| (gr, gh)))
        .map(|(gr, gh)| {
            let p = doublet(2.0 + gr, 1.0 + gh, &lub);
            pb.inc(1);
            p
        })
        .collect::<Result<_, _>>()
        .inspect_err(|_| pb.finish_and_clear())?;
    pb.finish_and_clear();
    // the maximum rate with lubrication: grid maximum, refined by a pattern search in
    // (ln(r - 2), ln(h - 1)) with steps halved down to 1e-6 of the grid spacing
    let best = points
        .iter()
        .max_by(|p, q| p.rate_resistance.total_cmp(&q.rate_resistance))
        .copied()
        .ok_or_else(|| CliError::Numerical("empty grid".to_string()))?;
    let rate = |u: f64, v: f64| -> Result<f64, CliError> {
        let (r, h) = (2.0 + u.exp(), 1.0 + v.exp());
        if r > args.r_max || h > args.h_max || r < args.r_min || h < args.h_min {
            return Ok(f64::NEG_INFINITY);
        }
        Ok(doublet(r, h, &lub)?.rate_resistance)
    };
    let (mut u, mut v, mut top) = (
        (best.r - 2.0).ln(),
        (best.h - 1.0).ln(),
        best.rate_resistance,
    );
    let (mut du, mut dv) = ((gaps_r[1] / gaps_r[0]).ln(), (gaps_h[1] / gaps_h[0]).ln());
    let stop = 1e-6 * du.min(dv);
    while du.max(dv) > stop {
        let mut moved = false;
        for (su, sv) in [(du, 0.0), (-du, 0.0), (0.0, dv), (0.0, -dv)] {
            let value = rate(u + su, v + sv)?;
            if value > top {
                (u, v, top, moved) = (u + su, v + sv, value, true);
            }
        }
        if !moved {
            du *= 0.5;
            dv *= 0.5;
        }
    }
    let (r_top, h_top) = (2.0 + u.exp(), 1.0 + v.exp());
    write_atomically(&args.out, |w| {
        writeln!(
            w,
            "r,h,rate_resistance,rate_farfield,tension_resistance,tension_farfield"
        )?;
        for p in &points {
            writeln!(
                w,
                "{:?},{:?},{:?},{:?},{:?},{:?}",
                p.r,
                p.h,
                p.rate_resistance,
                p.rate_farfield,
                p.tension_resistance,
                p.tension_farfield
            )?;
        }
        Ok(())
    })?;
    let rates: Vec<Vec<f64>> = points
        .chunks(gaps_h.len())
        .map(|c| c.iter().map(|p| p.rate_resistance).collect())
        .collect();
    let field = plot::Field {
        x: &gaps_r,
        y: &gaps_h,
        z: &rates,
        x_label: "r/a - 2",
        y_label: "h/a - 1",
        title: "doublet rotation rate 8 pi eta a^3 Omega / T (Eq. 19)",
        mark: (r_top - 2.0, h_top - 1.0),
    };
    let mut written = vec![args.out.display().to_string()];
    for ext in ["png", "svg"] {
        let path = args.out.with_extension(ext);
        let shown = path.display().to_string();
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp = parent_dir(&path).join(format!(".{name}.{}.tmp.{ext}", std::process::id()));
        plot::filled_contours(&tmp, &field, 16)
            .and_then(|()| fs::rename(&tmp, &path).map_err(|e| e.to_string()))
            .map_err(|reason| {
                let _ = fs::remove_file(&tmp);
                CliError::Plot {
                    path: shown.clone(),
                    reason,
                }
            })?;
        written.push(shown);
    }
    let (worst_t_res, worst_t_far) = points.iter().fold((0.0f64, 0.0f64), |(a, b), p| {
        (
            a.max(p.tension_resistance.abs()),
            b.max(p.tension_farfield.abs()),
        )
    });
    println!(
        "maximum rate with lubrication 8 pi eta a^3 Omega / T = {top:.6} at r = {r_top:.6} a, \
         h = {h_top:.6} a (grid maximum {:.6} at r = {:.6} a, h = {:.6} a)",
        best.rate_resistance, best.r, best.h
    );
    println!(
        "largest |tension| a / T: {worst_t_res:.3e} with lubrication, {worst_t_far:.3e} far field"
    );
    println!("wrote {}", written.join(", "));
    Ok(())
}
