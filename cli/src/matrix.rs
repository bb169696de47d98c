//! `mobility` and `resistance`: assemble the dense grand mobility, or the grand
//! resistance with lubrication (Eq. 19), optionally check it, and write it as `.npy`,
//! CSV or JSON.

use crate::error::CliError;
use crate::options::{lubrication, PAIR_TOLERANCE_HELP};
use crate::output::{self, check_out, write_atomically, Format};
use crate::system::SystemArgs;
use clap::Args;
use nalgebra::DMatrixView;
use std::path::PathBuf;
use stokesian::linalg::LargeMatrix;

/// `mobility` and `resistance`.
#[derive(Args, Debug)]
pub struct MatrixArgs {
    #[command(flatten)]
    pub system: SystemArgs,
    /// Output file, its format by the extension: .npy (NumPy float64 array), .csv (one
    /// matrix row per line, no header) or .json.
    #[arg(long, value_name = "M.npy|M.csv|M.json")]
    pub out: PathBuf,
    /// Check that the matrix is symmetric and positive definite (Cholesky) before
    /// writing it; report on stderr, and fail without writing if it is not.
    #[arg(long)]
    pub check: bool,
    #[arg(long, value_name = "TOL", help = PAIR_TOLERANCE_HELP, allow_hyphen_values = true)]
    pub pair_tolerance: Option<f64>,
}

/// Assemble (the resistance if `resistance`), optionally check, and write the matrix.
pub fn run(args: &MatrixArgs, resistance: bool) -> Result<(), CliError> {
    let format = check_out(&args.out, &[Format::Npy, Format::Csv, Format::Json])?;
    if !resistance && args.pair_tolerance.is_some() {
        return Err(CliError::Inapplicable {
            option: "--pair-tolerance",
            context: "`mobility` (lubrication is in `resistance`)".to_string(),
        });
    }
    let lub = lubrication(args.pair_tolerance)?;
    let pb = &output::spinner();
    pb.set_message("reading particles");
    let result = assemble_and_write(args, format, resistance.then_some(&lub), pb);
    pb.finish_and_clear();
    let (dim, n, moments) = result?;
    let what = if resistance { "resistance" } else { "mobility" };
    output::report(format!(
        "wrote {}: {dim} x {dim} {moments} grand {what} of {n} spheres",
        args.out.display(),
    ));
    Ok(())
}

/// The work of [`run`] (the resistance with `lubrication` if given, else the mobility),
/// written in `format`; returns the dimension, the number of spheres and the truncation.
fn assemble_and_write(
    args: &MatrixArgs,
    format: Format,
    lubrication: Option<&stokesian::Lubrication>,
    pb: &indicatif::ProgressBar,
) -> Result<(usize, usize, &'static str), CliError> {
    let setup = args.system.setup()?;
    let n = setup.system.len();
    let moments = setup.moments;
    let dim = moments.moments().per_particle() * n;
    let what = if lubrication.is_some() {
        "resistance"
    } else {
        "mobility"
    };
    pb.set_message(format!(
        "assembling the {dim} x {dim} {} grand {what} of {n} spheres",
        moments.name()
    ));
    // the mobility in huge pages (`LargeMatrix`): at FTS, N = 1000, the 4 KiB pages of
    // an ordinary allocation took longer to map and fill than the kernels took
    let (resistance, mut mobility);
    let values: &[f64] = match lubrication {
        Some(lub) => {
            resistance = setup.system.resistance(moments.moments(), lub)?;
            resistance.as_slice()
        }
        None => {
            setup.system.check_overlap(moments.moments())?;
            mobility = LargeMatrix::zeros(dim, dim).map_err(|source| CliError::Memory {
                dim,
                gib: (dim as f64).powi(2) * 8.0 / (1u64 << 30) as f64,
                source,
            })?;
            setup
                .system
                .mobility_into(moments.moments(), mobility.as_mut_slice());
            mobility.as_slice()
        }
    };
    let m = DMatrixView::from_slice(values, dim, dim);
    setup.check_finite(values, what)?;
    if args.check {
        pb.set_message("checking symmetry and positive definiteness (Cholesky)");
        let c = stokesian::check_spd(m);
        let cholesky = if c.positive_definite {
            "succeeds"
        } else {
            "fails"
        };
        if !c.passed() {
            return Err(CliError::NotSpd {
                moments: moments.name(),
                asymmetry: c.asymmetry,
                cholesky,
            });
        }
        pb.suspend(|| {
            eprintln!(
                "check: |M - M^T|/|M| = {:e}; Cholesky {cholesky}: symmetric positive definite",
                c.asymmetry
            )
        });
    }
    output::bar(
        pb,
        m.nrows() as u64,
        "rows",
        false,
        format!("writing {}", args.out.display()),
    );
    write_atomically(&args.out, |w| match format {
        Format::Npy => output::write_npy(w, m, pb),
        Format::Csv => output::write_csv_matrix(w, m, pb),
        Format::Json => output::write_json(w, m, n, moments.name(), pb),
    })?;
    Ok((dim, n, moments.name()))
}
