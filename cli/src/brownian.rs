//! `brownian`: overdamped Brownian dynamics with hydrodynamic interactions (F or FT;
//! Euler-Maruyama or Fixman's midpoint; Cholesky or Lanczos noise; optionally with
//! lubrication), written frame by frame as CSV or `.npy`.

use crate::error::CliError;
use crate::options::{finite, parse_components, positive, PairToleranceArg};
use crate::output::{self, check_out, write_atomically, write_npy_header, Format};
use crate::system::{moments_default_f, MomentsArg, SystemArgs};
use clap::{Args, ValueEnum};
use indicatif::ProgressBar;
use std::io::{self, Write};
use std::path::PathBuf;
use stokesian::{Brownian, BrownianError, ExternalForces, Moments, System};

pub const ABOUT: &str = "\
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

/// `brownian`: the system (`--moments` defaults to F), the integration and the external
/// forces.
#[derive(Args, Debug)]
#[command(mut_arg("moments", |a| moments_default_f(a, "Truncation: F (positions of \
    torque-free spheres) or FT (positions and orientations; external torques allowed); FTS \
    is not implemented for Brownian dynamics")))]
pub struct BrownianArgs {
    #[command(flatten)]
    pub system: SystemArgs,
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
    /// With --lanczos: the matrix-free products (the noise's and M F) by the fast
    /// multipole method to the relative tolerance EPS in [1e-10, 1e-3] (docs/fmm.md);
    /// keep TOL above EPS (the fast product is symmetric to about EPS). The drift kT
    /// div M is then each sphere's own terms, O(N): its pair terms cancel.
    #[arg(long, value_name = "EPS", requires = "lanczos")]
    fmm: Option<f64>,
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
    #[command(flatten)]
    pair_tolerance: PairToleranceArg,
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
pub enum SchemeArg {
    /// Euler-Maruyama with the generated drift.
    EulerMaruyama,
    /// Fixman's midpoint scheme.
    Fixman,
}

pub fn run(args: &BrownianArgs) -> Result<(), CliError> {
    let npy = check_out(&args.out, &[Format::Csv, Format::Npy])? == Format::Npy;
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
            lubrication: crate::options::lubrication(args.pair_tolerance.pair_tolerance)?,
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
    if args.repulsion_strength != 0.0 && args.system.confinement()?.boundaries().is_empty() {
        return Err(CliError::Inapplicable {
            option: "--repulsion-strength",
            context: format!(
                "--confinement {} (there is no boundary to repel from)",
                args.system.declaration().name
            ),
        });
    }
    let pb = &output::spinner();
    pb.set_message("reading particles");
    let setup = match args.system.setup() {
        Ok(s) => s,
        Err(e) => {
            pb.finish_and_clear();
            return Err(e);
        }
    };
    let n = setup.system.len();
    let system = match args.fmm {
        Some(eps) => match setup.system.with_fmm(eps) {
            Ok(s) => s,
            Err(e) => {
                pb.finish_and_clear();
                return Err(e.into());
            }
        },
        None => setup.system,
    };
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
    output::bar(
        pb,
        args.steps as u64,
        "steps",
        true,
        format!("Brownian dynamics of {n} spheres"),
    );
    let mut tally = Tally::default();
    let mut failure = None;
    let result = write_atomically(&args.out, |w| {
        match simulate(w, system.clone(), &bd, args, npy, pb, &mut tally) {
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
    output::report(format!(
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
    let mut frames_out = if npy {
        let shape = [frames, n, if ft { 7 } else { 3 }];
        write_npy_header(w, &shape, npyz::Order::C).map_err(io_error)?;
        Frames::Npy(w)
    } else {
        let header = if ft {
            "step,time,particle,x,y,z,qw,qx,qy,qz"
        } else {
            "step,time,particle,x,y,z"
        };
        writeln!(w, "{header}").map_err(io_error)?;
        Frames::Csv(w)
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
            written = frames_out.write(
                step,
                step as f64 * bd.dt,
                system,
                if ft { orientation } else { &[] },
            );
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

/// Where the frames go: CSV lines, or a `.npy` array of shape (frames, N, 3 or 7).
enum Frames<W: Write> {
    Csv(W),
    Npy(W),
}

impl<W: Write> Frames<W> {
    /// One frame: each sphere's centre and, at FT, its `orientation`.
    fn write(
        &mut self,
        step: usize,
        time: f64,
        system: &System,
        orientation: &[[f64; 4]],
    ) -> io::Result<()> {
        for (a, p) in system.particles().iter().enumerate() {
            let q = orientation.get(a).map_or(&[][..], |q| &q[..]);
            match self {
                Frames::Csv(w) => {
                    write!(w, "{step},{time:?},{a},")?;
                    output::write_csv_row(w, p.x.iter().chain(q).copied())?;
                }
                Frames::Npy(w) => output::write_f64s(w, p.x.iter().chain(q).copied())?,
            }
        }
        Ok(())
    }
}
