//! `velocity`: velocities (and rotation rates) of force- and torque-given spheres in a
//! quiescent fluid or a uniform strain: matrix-free at F and FT, the stresslets solved
//! for at FTS, or from the resistance with lubrication; written as CSV or `.npy`.

use crate::error::CliError;
use crate::options::{lubrication, parse_components, PairToleranceArg};
use crate::output::{self, check_out, write_atomically, Format};
use crate::system::{moments_default_f, particle_error, MomentsArg, Setup, SystemArgs};
use crate::table::{self, Columns};
use clap::{Args, ValueEnum};
use indicatif::ProgressBar;
use std::path::PathBuf;
use stokesian::{strain_components, Precision, VelocityError};

/// `velocity`: the system (`--moments` defaults to F, as for `brownian`), the forces and
/// the output.
#[derive(Args, Debug)]
#[command(mut_arg("moments", |a| moments_default_f(a, "Truncation of the multipole \
    expansion: F (velocities of the centres), FT (and rotation rates) or FTS (the \
    stresslets solved for)")))]
pub struct VelocityArgs {
    #[command(flatten)]
    pub system: SystemArgs,
    /// Forces (fx,fy,fz) and, for FT and FTS, torques (tx,ty,tz) exerted by each
    /// particle on the fluid, in the order of --particles: CSV with these columns (any
    /// order, other columns ignored) or .npy of shape (N, 3) or (N, 6).
    #[arg(long, value_name = "forces.csv|forces.npy")]
    pub forces: PathBuf,
    /// FTS only: uniform imposed rate of strain E_inf (symmetric, traceless), either 9
    /// comma-separated Cartesian components row-major E11,E12,E13,E21,E22,E23,E31,E32,E33,
    /// or 5 components in the orthonormal basis B1..B5 (E_m = B_m : E). The 9 components must
    /// be symmetric and traceless to 1e-9 of the largest. Default: zero. The output is then
    /// relative to the ambient flow at each centre (U - U_inf, Omega - Omega_inf).
    #[arg(long, value_name = "E11,E12,...,E33", allow_hyphen_values = true)]
    pub strain: Option<String>,
    /// FT and FTS: include lubrication (Eq. 19) and solve R U = F by Cholesky; the condition
    /// estimate of R is reported on stderr, and the run fails if it exceeds 1e14.
    #[arg(long)]
    pub lubrication: bool,
    #[command(flatten)]
    pub pair_tolerance: PairToleranceArg,
    /// Arithmetic of the matrix-free product (F and FT without --lubrication): double
    /// (f64 lanes, about 1e-15 per pair) or single (f32 lanes: twice the pairs per
    /// instruction, about 1e-7 relative to the largest velocity; any units of input).
    #[arg(long, value_enum, default_value = "double")]
    pub precision: PrecisionArg,
    /// F and FT without --lubrication: the product by the fast multipole method to the
    /// relative tolerance EPS (in [1e-10, 1e-3]) on the 2-norm of the velocities, instead
    /// of the exact O(N^2) sum (in double precision; docs/fmm.md); with --box, the box's
    /// own fast product with its lattice sums to EPS.
    #[arg(long, value_name = "EPS")]
    pub fmm: Option<f64>,
    /// Output file, its format by the extension: .csv with columns ux,uy,uz (F) or
    /// ux,uy,uz,wx,wy,wz (FT, FTS), one line per particle, or .npy (a float64 array of
    /// shape (N, 3) or (N, 6), the same columns).
    #[arg(long, value_name = "U.csv|U.npy")]
    pub out: PathBuf,
}

/// `--precision`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    /// f64 lanes.
    Double,
    /// f32 lanes.
    Single,
}

/// The forces file's columns at F, and with torques at FT and FTS.
const FORCES: Columns = Columns {
    what: "forces",
    required: &["fx", "fy", "fz"],
    refused: &["tx", "ty", "tz"],
    refused_why: "give torques, which need --moments FT or FTS",
    hint: " (force on the fluid, one particle per row)",
};
const FORCES_TORQUES: Columns = Columns {
    what: "forces",
    required: &["fx", "fy", "fz", "tx", "ty", "tz"],
    refused: &[],
    refused_why: "",
    hint: " (force and torque on the fluid, one particle per row)",
};

/// Check the options, compute and write the velocities.
pub fn run(args: &VelocityArgs) -> Result<(), CliError> {
    let format = check_out(&args.out, &[Format::Csv, Format::Npy])?;
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
    if moments == MomentsArg::F && args.lubrication {
        return Err(CliError::Inapplicable {
            option: "--lubrication",
            context: "--moments F: lubrication needs torques and rotations (use FT or FTS)"
                .to_string(),
        });
    }
    if args.precision == PrecisionArg::Single && (args.lubrication || moments == MomentsArg::Fts) {
        return Err(CliError::Inapplicable {
            option: "--precision single",
            context: "single precision is for the matrix-free product (F or FT without \
                      --lubrication); resistances and the FTS solve are in double precision"
                .to_string(),
        });
    }
    if args.fmm.is_some() && (args.lubrication || moments == MomentsArg::Fts) {
        return Err(CliError::Inapplicable {
            option: "--fmm",
            context: "the fast product is the matrix-free product (F or FT without \
                      --lubrication)"
                .to_string(),
        });
    }
    let pb = output::spinner();
    pb.set_message("reading input");
    let result = velocity(args, format, moments, strain, &pb);
    pb.finish_and_clear();
    let (n, what) = result?;
    output::report(format!(
        "wrote {}: {what} of {n} spheres ({})",
        args.out.display(),
        moments.name()
    ));
    Ok(())
}

/// Read the forces of `setup`'s particles, moment-major (all forces, then all torques).
fn read_forces(args: &VelocityArgs, setup: &Setup, torques: bool) -> Result<Vec<f64>, CliError> {
    let columns = if torques { &FORCES_TORQUES } else { &FORCES };
    let forces = table::read(&args.forces, columns)?;
    let n = setup.system.len();
    if forces.rows.len() != n {
        return Err(CliError::RowCount {
            forces: forces.path,
            rows: forces.rows.len(),
            particles: setup.table.path.clone(),
            n,
        });
    }
    for (index, row) in forces.rows.iter().enumerate() {
        if let Some((v, c)) = row
            .iter()
            .zip(columns.required)
            .find(|(v, _)| !v.is_finite())
        {
            return Err(particle_error(
                &forces,
                index,
                format!("{c} = {v} is not a finite number"),
            ));
        }
    }
    let k = columns.required.len();
    let mut x = vec![0.0; k * n];
    for (a, row) in forces.rows.iter().enumerate() {
        for i in 0..3 {
            x[3 * a + i] = row[i];
            if torques {
                x[3 * n + 3 * a + i] = row[3 + i];
            }
        }
    }
    Ok(x)
}

/// The work of [`run`], written in `format`; returns the number of spheres and what was
/// written.
fn velocity(
    args: &VelocityArgs,
    format: Format,
    moments: MomentsArg,
    strain: [f64; 5],
    pb: &ProgressBar,
) -> Result<(usize, &'static str), CliError> {
    let setup = args.system.setup()?;
    let n = setup.system.len();
    let torques = moments != MomentsArg::F;
    let x = read_forces(args, &setup, torques)?;
    let lub = lubrication(args.pair_tolerance.pair_tolerance)?;
    let lubrication = (torques && args.lubrication).then_some(&lub);
    let dim = 11 * n;
    pb.set_message(match (moments, lubrication) {
        (_, Some(_)) => format!(
            "forming the {} resistance with lubrication of {n} spheres and solving R U = F \
             (Cholesky)",
            moments.name()
        ),
        (MomentsArg::Fts, None) => format!(
            "assembling the {dim} x {dim} FTS grand mobility of {n} spheres and solving for \
             the stresslets"
        ),
        _ => match args.fmm {
            Some(eps) => {
                format!("computing velocities of {n} spheres (fast multipole method to {eps:e})")
            }
            None => format!(
                "computing velocities of {n} spheres (matrix-free, {} pairs)",
                n * (n + 1) / 2
            ),
        },
    });
    let precision = match args.precision {
        PrecisionArg::Double => Precision::Double,
        PrecisionArg::Single => Precision::Single,
    };
    let mut system = setup.system.clone().with_precision(precision);
    if let Some(eps) = args.fmm {
        system = system.with_fmm(eps)?;
    }
    // the library's call; its numerical failures get the causes only the command knows
    let v = system
        .velocities(moments.moments(), &x, &strain, lubrication)
        .map_err(|e| match e {
            VelocityError::NotFinite(what) => setup.non_finite(what),
            VelocityError::Singular(reason) => {
                CliError::Numerical(format!("{reason}: {}", setup.indefinite()))
            }
            VelocityError::IllConditioned(cond) => CliError::IllConditioned(cond),
            VelocityError::Resistance(r) => CliError::Resistance(r),
            other => CliError::Numerical(other.to_string()),
        })?;
    if let Some(cond) = v.condition {
        pb.suspend(|| eprintln!("stokesian: condition estimate of R: {cond:e}"));
    }
    if !v.stresslet_cholesky {
        pb.suspend(|| {
            eprintln!(
                "stokesian: warning: the stresslet block M_ES is not positive definite ({}); \
                 solved by LU",
                setup.indefinite()
            )
        });
    }
    let u = v.u;
    pb.set_message(format!("writing {}", args.out.display()));
    let columns: &[&str] = if torques {
        &["ux", "uy", "uz", "wx", "wy", "wz"]
    } else {
        &["ux", "uy", "uz"]
    };
    write_atomically(&args.out, |w| {
        let rows = (0..n).map(|a| {
            let rotation = if torques {
                3 * n + 3 * a..3 * n + 3 * a + 3
            } else {
                0..0
            };
            u[3 * a..3 * a + 3].iter().chain(&u[rotation]).copied()
        });
        output::write_table(w, format, columns, n, rows)
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
            let e: [[f64; 3]; 3] =
                std::array::from_fn(|i| std::array::from_fn(|j| values[3 * i + j]));
            strain_components(&e).map_err(|e| match e {
                VelocityError::NotSymmetricTraceless(detail) => bad(detail),
                other => bad(other.to_string()),
            })
        }
        k => Err(bad(format!(
            "expected 9 comma-separated Cartesian components E11,E12,E13,E21,E22,E23,E31,\
             E32,E33 (row-major) or 5 components in the orthonormal basis B1..B5, found {k}"
        ))),
    }
}
