//! Input formats: the numeric tables of `--particles` and `--forces`, read from CSV
//! through the `csv` crate (columns found by header name in any order; quoted fields,
//! CRLF, a UTF-8 byte-order mark, spaces around fields, blank lines and `#` comments
//! accepted) or from NumPy `.npy` through `npyz` (a 2-D float64 or float32 array, C or
//! Fortran order, either byte order).

use crate::error::CliError;
use crate::output::has_extension;
use npyz::{DType, NpyFile, NpyHeader, Order, TypeChar};
use std::fs;
use std::path::Path;

/// What a table must hold.
pub struct Columns {
    /// What the file describes, for messages (`particles`, `forces`).
    pub what: &'static str,
    /// The columns read, in the order of [`Table::rows`].
    pub required: &'static [&'static str],
    /// Known columns that do not apply here (an error, explained by `refused_why`).
    pub refused: &'static [&'static str],
    /// Why the `refused` columns do not apply, and what to do.
    pub refused_why: &'static str,
    /// What a row is, shown with a header or shape error.
    pub hint: &'static str,
}

/// Where rows were found: CSV lines (from 1, the header included) or `.npy` rows (from
/// 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Locus {
    /// A CSV line.
    Line,
    /// A `.npy` row.
    Row,
}

/// A numeric table: the values of the required columns, row by row, and where each row
/// was found.
#[derive(Debug)]
pub struct Table {
    /// The file, as given.
    pub path: String,
    /// One row per data line, the values in the order of [`Columns::required`].
    pub rows: Vec<Vec<f64>>,
    /// The line (CSV) or row (`.npy`) of each row.
    pub places: Vec<usize>,
    /// Lines or rows.
    pub locus: Locus,
}

impl Table {
    /// Where row `i` is: `line 7` or `row 5`.
    pub fn place(&self, i: usize) -> String {
        match self.locus {
            Locus::Line => format!("line {}", self.places[i]),
            Locus::Row => format!("row {}", self.places[i]),
        }
    }

    /// Where rows `i` and `j` are: `lines 2 and 3` or `rows 0 and 1`.
    pub fn places(&self, i: usize, j: usize) -> String {
        let unit = match self.locus {
            Locus::Line => "lines",
            Locus::Row => "rows",
        };
        format!("{unit} {} and {}", self.places[i], self.places[j])
    }
}

/// The NPY magic string.
const NPY_MAGIC: &[u8] = b"\x93NUMPY";

/// Read `path` as `.npy` (by its extension or its magic string) or as CSV. Unknown CSV
/// columns are reported once on stderr.
pub fn read(path: &Path, columns: &Columns) -> Result<Table, CliError> {
    let shown = path.display().to_string();
    let bytes = fs::read(path).map_err(|source| CliError::Read {
        what: columns.what,
        path: shown.clone(),
        source,
    })?;
    let npy = has_extension(path, "npy") || bytes.starts_with(NPY_MAGIC);
    if npy {
        read_npy(shown, &bytes, columns)
    } else {
        let (table, ignored) = read_csv(shown, &bytes, columns)?;
        if !ignored.is_empty() {
            eprintln!(
                "stokesian: note: {}: ignoring column{} {} (not used for {})",
                table.path,
                if ignored.len() == 1 { "" } else { "s" },
                ignored.join(", "),
                columns.what
            );
        }
        Ok(table)
    }
}

/// Parse CSV `bytes`; returns the table and the names of the columns ignored.
pub fn read_csv(
    path: String,
    bytes: &[u8],
    columns: &Columns,
) -> Result<(Table, Vec<String>), CliError> {
    let text = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(text);
    let expected = columns.required.join(",");
    // the header: its line, its field count and text, and the field of each column
    let mut header: Option<(usize, usize, String, Vec<usize>)> = None;
    let mut ignored = Vec::new();
    let mut rows = Vec::new();
    let mut places = Vec::new();
    let mut record = csv::ByteRecord::new();
    let (mut newlines, mut counted) = (0, 0);
    loop {
        match reader.read_byte_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            // from a byte slice with flexible records the reader has nothing to fail on;
            // should it ever, say where
            Err(e) => {
                return Err(CliError::Format {
                    path,
                    reason: format!("not a readable CSV file: {e}"),
                })
            }
        }
        // The record's line. csv's position is where this read began, before the
        // comment and empty lines it skipped (and its line count misses comment lines):
        // skip them here too, then count the newlines since the previous record.
        let mut start = record
            .position()
            .map_or(0, |p| p.byte() as usize)
            .min(text.len());
        while start < text.len() && matches!(text[start], b'#' | b'\n' | b'\r') {
            start = text[start..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(text.len(), |k| start + k + 1);
        }
        let start = start.max(counted);
        newlines += text[counted..start].iter().filter(|&&b| b == b'\n').count();
        counted = start;
        let line = 1 + newlines;
        let blank = record.iter().all(|f| f.is_empty());
        if blank || record.get(0).is_some_and(|f| f.starts_with(b"#")) {
            continue;
        }
        // csv recognises quotes at the start of a field only: a quoted field after a
        // space (`x, "y"`) keeps its quotes, removed here
        let fields: Vec<String> = record
            .iter()
            .map(|f| {
                let f = String::from_utf8_lossy(f);
                let unquoted = f.strip_prefix('"').and_then(|g| g.strip_suffix('"'));
                unquoted.map_or(f.as_ref(), str::trim).to_string()
            })
            .collect();
        let Some((_, count, found, at)) = &header else {
            let at = match_header(&fields, columns).map_err(|problem| CliError::Header {
                path: path.clone(),
                line,
                expected: expected.clone(),
                found: fields.join(","),
                problem,
                hint: columns.hint,
            })?;
            ignored = fields
                .iter()
                .enumerate()
                .filter(|(k, _)| !at.contains(k))
                .map(|(_, f)| f.clone())
                .collect();
            header = Some((line, fields.len(), fields.join(","), at));
            continue;
        };
        if fields.len() != *count {
            return Err(CliError::FieldCount {
                path,
                line,
                expected: *count,
                columns: found.clone(),
                found: fields.len(),
            });
        }
        let mut row = Vec::with_capacity(at.len());
        for (&k, column) in at.iter().zip(columns.required) {
            let field = &fields[k];
            match field.parse::<f64>() {
                Ok(v) => row.push(v),
                Err(_) => {
                    return Err(CliError::NotANumber {
                        path,
                        line,
                        column: (*column).to_string(),
                        field: field.clone(),
                    })
                }
            }
        }
        rows.push(row);
        places.push(line);
    }
    if header.is_none() {
        return Err(CliError::NoHeader { path, expected });
    }
    let table = Table {
        path,
        rows,
        places,
        locus: Locus::Line,
    };
    Ok((table, ignored))
}

/// The field of each required column in a header (names compared without regard to
/// case), or what is wrong with it.
fn match_header(fields: &[String], columns: &Columns) -> Result<Vec<usize>, String> {
    let find = |name: &str| -> Vec<usize> {
        (0..fields.len())
            .filter(|&k| fields[k].eq_ignore_ascii_case(name))
            .collect()
    };
    let refused: Vec<&str> = columns
        .refused
        .iter()
        .copied()
        .filter(|c| !find(c).is_empty())
        .collect();
    if !refused.is_empty() {
        return Err(format!(
            "column{} {} {}",
            if refused.len() == 1 { "" } else { "s" },
            refused.join(", "),
            columns.refused_why
        ));
    }
    let mut at = Vec::with_capacity(columns.required.len());
    let mut missing = Vec::new();
    for name in columns.required {
        match find(name)[..] {
            [k] => at.push(k),
            [] => missing.push(*name),
            _ => return Err(format!("the column {name} appears more than once")),
        }
    }
    if missing.is_empty() {
        Ok(at)
    } else {
        Err(format!("missing {}", missing.join(", ")))
    }
}

/// Parse `.npy` `bytes`: a 2-D float array with one column per required column.
pub fn read_npy(path: String, bytes: &[u8], columns: &Columns) -> Result<Table, CliError> {
    let bad = |reason: String| CliError::Format {
        path: path.clone(),
        reason,
    };
    let mut data = bytes;
    let header = NpyHeader::from_reader(&mut data)
        .map_err(|e| bad(format!("not a readable NumPy .npy file: {e}")))?;
    let want = columns.required.len();
    let expected = format!(
        "a 2-D float64 or float32 array of shape (N, {want}), columns {}{}",
        columns.required.join(", "),
        columns.hint
    );
    let (rows, cols) = match header.shape() {
        &[r, c] if c == want as u64 => (r, c),
        shape => {
            let dims: Vec<String> = shape.iter().map(u64::to_string).collect();
            let mut reason = format!("shape ({}): expected {expected}", dims.join(", "));
            if shape.len() == 2 && !columns.refused.is_empty() {
                reason.push_str(&format!(
                    " ({} {})",
                    columns.refused.join(", "),
                    columns.refused_why
                ));
            }
            return Err(bad(reason));
        }
    };
    let dtype = header.dtype();
    let size = match &dtype {
        DType::Plain(t) if t.type_char() == TypeChar::Float => t.size_field(),
        _ => 0,
    };
    if size != 4 && size != 8 {
        return Err(bad(format!("dtype {}: expected {expected}", dtype.descr())));
    }
    // the shape from the header against the bytes present, before anything is allocated
    let needed = rows
        .checked_mul(cols)
        .and_then(|n| n.checked_mul(size))
        .filter(|&n| n <= data.len() as u64)
        .ok_or_else(|| {
            bad(format!(
                "truncated: shape ({rows}, {cols}) of {size}-byte numbers needs more than \
                 the {} bytes of data present",
                data.len()
            ))
        })?;
    let file = NpyFile::with_header(header, &data[..needed as usize]);
    let order = file.order();
    let values: Vec<f64> = if size == 8 {
        file.into_vec::<f64>()
    } else {
        file.into_vec::<f32>()
            .map(|v| v.into_iter().map(f64::from).collect())
    }
    .map_err(|e| bad(format!("cannot read the data: {e}")))?;
    let (rows, cols) = (rows as usize, cols as usize);
    let at = |i: usize, j: usize| match order {
        Order::C => values[i * cols + j],
        Order::Fortran => values[j * rows + i],
    };
    Ok(Table {
        path,
        rows: (0..rows)
            .map(|i| (0..cols).map(|j| at(i, j)).collect())
            .collect(),
        places: (0..rows).collect(),
        locus: Locus::Row,
    })
}

#[cfg(test)]
#[path = "table_tests.rs"]
mod tests;
