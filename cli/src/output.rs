//! Output formats and how they are written: the format of `--out` chosen by its
//! extension among those the subcommand declares ([`check_out`]); `.npy` (the preamble
//! by `npyz`, then the data streamed; a matrix in Fortran order column by column as
//! nalgebra stores it, never copied or transposed), JSON, CSV; every output through a
//! temporary file renamed when complete; the progress bars and the closing report on
//! stderr.

use crate::error::CliError;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use nalgebra::DMatrixView;
use npyz::{NpyWriter, Order, WriteOptions, WriterBuilder};
use std::fs::{self, File};
use std::io::{self, BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The layout string of the JSON output and the help text.
pub const LAYOUT: &str = "moment-major: U(3N), Omega(3N), E(5N, orthonormal basis B1..B5); \
                          particle-major within a moment";

/// The formats of `--out`, each named by its file extension: a subcommand declares the
/// ones it writes and [`check_out`] chooses among them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// NumPy `.npy`: little-endian float64, the shape in the header.
    Npy,
    /// CSV text, every number in shortest round-trip form.
    Csv,
    /// JSON (the matrices only).
    Json,
}

impl Format {
    /// The file extension that names the format.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Npy => "npy",
            Format::Csv => "csv",
            Format::Json => "json",
        }
    }
}

/// Check the output path before any work, a file name in an existing directory, and
/// choose its format by its extension (any case) among `accepted`; any other extension
/// is refused with the list of the accepted ones, in their order.
pub fn check_out(out: &Path, accepted: &[Format]) -> Result<Format, CliError> {
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
    if let Some(&format) = accepted.iter().find(|f| has_extension(out, f.extension())) {
        return Ok(format);
    }
    let list: Vec<String> = accepted
        .iter()
        .map(|f| format!(".{}", f.extension()))
        .collect();
    let list = match list.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => list.concat(),
    };
    Err(bad(format!("the file name must end in {list}")))
}

/// Whether `path` ends in `.ext` (any case).
pub fn has_extension(path: &Path, ext: &str) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

fn parent_dir(out: &Path) -> PathBuf {
    match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A temporary file name next to `out`, ending in `suffix`.
pub fn temporary(out: &Path, suffix: &str) -> PathBuf {
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    parent_dir(out).join(format!(".{name}.{}.tmp{suffix}", std::process::id()))
}

/// Write through a temporary file in the output's directory, renamed onto `out` only
/// when everything was written; on failure the temporary file is removed.
pub fn write_atomically(
    out: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), CliError> {
    let tmp = temporary(out, "");
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
            path: out.display().to_string(),
            source,
        }
    })
}

/// The `.npy` preamble (magic, version, the header dictionary padded to 64 bytes) of a
/// little-endian float64 array of `shape` in C order (last index fastest) or Fortran
/// order (first index fastest), as npyz writes it; the data follow through
/// [`write_f64s`]. npyz's own writer takes the data one number per call, which made
/// `mobility` of a 1 GB matrix take 3.8-4.0 s instead of 1.9-2.7 s (measured, three
/// runs each); its writer is therefore used for the preamble only and dropped before any
/// data (on drop it checks the count of numbers written and ignores the error).
pub fn write_npy_header(w: &mut impl Write, shape: &[usize], order: Order) -> io::Result<()> {
    let shape: Vec<u64> = shape.iter().map(|&d| d as u64).collect();
    let mut preamble = Vec::new();
    let writer: NpyWriter<f64, _> = WriteOptions::new()
        .default_dtype()
        .shape(&shape)
        .order(order)
        .writer(&mut preamble)
        .begin_nd()?;
    drop(writer);
    w.write_all(&preamble)
}

/// Numbers as little-endian float64, in one write. (Eight bytes appended per number:
/// collecting `flat_map(f64::to_le_bytes)` over a matrix view's columns took half the
/// `perf` samples of writing the 968 MB FTS mobility of 1000 spheres, and about 1.4 s
/// more user time.)
pub fn write_f64s(w: &mut impl Write, values: impl IntoIterator<Item = f64>) -> io::Result<()> {
    let values = values.into_iter();
    let mut bytes = Vec::with_capacity(values.size_hint().0 * 8);
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    w.write_all(&bytes)
}

/// A matrix as a 2-D `.npy` array in Fortran order: nalgebra stores columns
/// contiguously, so they are written as they are, one column per progress step.
pub fn write_npy(w: &mut impl Write, m: DMatrixView<f64>, pb: &ProgressBar) -> io::Result<()> {
    let (rows, cols) = m.shape();
    write_npy_header(w, &[rows, cols], Order::Fortran)?;
    for col in m.column_iter() {
        write_f64s(w, col.iter().copied())?;
        pb.inc(1);
    }
    Ok(())
}

/// JSON with every number in Rust's shortest round-trip form (valid JSON for finite
/// numbers, which the commands check before writing).
pub fn write_json(
    w: &mut impl Write,
    m: DMatrixView<f64>,
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

/// A matrix as CSV: one matrix row per line, no header.
pub fn write_csv_matrix(
    w: &mut impl Write,
    m: DMatrixView<f64>,
    pb: &ProgressBar,
) -> io::Result<()> {
    for row in m.row_iter() {
        write_csv_row(w, row.iter().copied())?;
        pb.inc(1);
    }
    Ok(())
}

/// A table of `rows` rows under the named `columns`, as CSV (the header, then one line
/// per row) or as `.npy` (a 2-D float64 array of shape (rows, columns) in C order: the
/// CSV's numbers in the CSV's order). `values` yields each row's numbers.
pub fn write_table<R: IntoIterator<Item = f64>>(
    w: &mut impl Write,
    format: Format,
    columns: &[&str],
    rows: usize,
    values: impl IntoIterator<Item = R>,
) -> io::Result<()> {
    match format {
        Format::Npy => {
            write_npy_header(w, &[rows, columns.len()], Order::C)?;
            values.into_iter().try_for_each(|row| write_f64s(w, row))
        }
        Format::Csv => {
            writeln!(w, "{}", columns.join(","))?;
            values.into_iter().try_for_each(|row| write_csv_row(w, row))
        }
        // the subcommands writing tables do not accept .json (`check_out`)
        Format::Json => Err(io::Error::new(
            io::ErrorKind::Unsupported,
            "a table has no JSON form",
        )),
    }
}

/// One CSV line of numbers in shortest round-trip form.
pub fn write_csv_row(w: &mut impl Write, values: impl IntoIterator<Item = f64>) -> io::Result<()> {
    let fields: Vec<String> = values.into_iter().map(|v| format!("{v:?}")).collect();
    writeln!(w, "{}", fields.join(","))
}

/// A spinner on stderr, drawn only when stderr is a terminal.
pub fn spinner() -> ProgressBar {
    let pb = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
        .unwrap_or_else(|_| ProgressStyle::default_spinner());
    pb.set_style(style);
    pb.enable_steady_tick(Duration::from_millis(100));
    pb
}

/// Turn the spinner into a bar over `len` items of `unit` (`rows`, `steps`, ...),
/// with the rate and the time left where `eta` is set.
pub fn bar(pb: &ProgressBar, len: u64, unit: &str, eta: bool, message: String) {
    let timing = if eta {
        "[{elapsed}, {per_sec}, eta {eta}]"
    } else {
        "[{elapsed}]"
    };
    let style = ProgressStyle::with_template(&format!(
        "{{msg}} {{wide_bar}} {{pos}}/{{len}} {unit} {timing}"
    ))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    pb.set_style(style);
    pb.set_length(len);
    pb.set_position(0);
    pb.set_message(message);
}

/// Say what was written, on a terminal only (scripts get silence).
pub fn report(message: String) {
    if io::stderr().is_terminal() {
        eprintln!("{message}");
    }
}
