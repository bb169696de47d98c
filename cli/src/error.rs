//! The command's error type: every failure of a subcommand, each with a message that
//! says what is wrong and where (file, line or row, particle) and, where it helps, what
//! to do.

use std::io;
use thiserror::Error;

/// Everything that can go wrong. Places are CSV lines counted from 1 (the header
/// included) or `.npy` rows counted from 0, as NumPy indexes them.
#[derive(Debug, Error)]
pub enum CliError {
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
    /// A CSV header lacks a required column, names one twice, or names one that does
    /// not apply.
    #[error("{path} line {line}: the header must name the columns {expected} (in any order; other columns are ignored), found {found}: {problem}{hint}")]
    Header {
        path: String,
        line: usize,
        expected: String,
        found: String,
        problem: String,
        hint: &'static str,
    },
    /// A data line has another number of fields than the header.
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
    /// An input file that cannot be used: a `.npy` file that is not NPY, of another
    /// dtype or shape, or truncated.
    #[error("{path}: {reason}")]
    Format { path: String, reason: String },
    /// The particles file has a header and no particles.
    #[error("{path}: no particles (the file has a header but no data lines)")]
    NoParticles { path: String },
    /// A particle is invalid: coordinates, radius, position relative to a boundary.
    #[error("{path} {place} (particle {index}): {reason}")]
    Particle {
        path: String,
        place: String,
        index: usize,
        reason: String,
    },
    /// Two spheres overlap or share a centre.
    #[error("{path} {places} (particles {a} and {b}): {reason}")]
    Pair {
        path: String,
        places: String,
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
    /// A confinement parameter given wrongly: unknown, missing, given twice, not
    /// finite (`place`: how it was given, where that helps; `hint`: what to do).
    #[error("{place}{source}{hint}")]
    Param {
        place: String,
        source: kernels::ParamError,
        hint: String,
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
    /// The memory for the matrix could not be had.
    #[error("cannot hold the {dim} x {dim} matrix ({gib:.1} GiB): {source}; nothing written")]
    Memory {
        dim: usize,
        gib: f64,
        source: io::Error,
    },
    /// Writing the output failed.
    #[error("cannot write {path}: {source}")]
    Write { path: String, source: io::Error },
    /// The result is not a finite number, or a solve failed; the message names the
    /// cause found (see `system::Setup::non_finite`).
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
    Doublet(#[from] stokesian::studies::doublet::DoubletError),
    /// A plot could not be drawn.
    #[error("cannot draw {path}: {reason}")]
    Plot { path: String, reason: String },
    /// What the RPY overlap forms do not cover (`--overlap rpy` at FTS).
    #[error("{0}; nothing written")]
    Overlap(#[from] stokesian::OverlapError),
    /// What a periodic box cannot be or do (`--box`).
    #[error("--box: {0}; nothing written")]
    Periodic(#[from] stokesian::PeriodicError),
    /// What the fast product cannot do (`--fmm`).
    #[error("--fmm: {0}; nothing written")]
    Fmm(#[from] stokesian::FmmError),
    /// Brownian dynamics failed for another reason.
    #[error("{0}; nothing written")]
    Brownian(stokesian::BrownianError),
}
