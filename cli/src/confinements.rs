//! `confinements`: the registry of Green's functions as the kernels declare it
//! (`kernels::DECLARATIONS`), listed: each confinement's name, title and parameters
//! (default or required, what it is, its alias), and its boundary planes for stated
//! parameter values (the defaults, and each required parameter's declared example).

use crate::error::CliError;
use crate::system::ALIASES;
use clap::{Args, ValueEnum};
use kernels::{Boundary, Declaration, Param};
use std::io::Write;

pub const ABOUT: &str = "\
List every confinement the kernels know: its name (for --confinement; a hyphen may stand
for each underscore), what it is, its parameters (for --param NAME=VALUE: the default,
or \"required\", and what each is) and its boundary planes. The planes depend on the
parameters: they are shown for the defaults and, for a parameter without a default, its
example value, as the listing says.";

/// `confinements`: the format.
#[derive(Args, Debug)]
pub struct ConfinementsArgs {
    /// text (for reading) or json (an array of objects: name, title, params,
    /// boundaries_for, boundaries).
    #[arg(long, value_enum, default_value = "text")]
    format: ListFormat,
}

/// `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ListFormat {
    /// Lines for reading.
    Text,
    /// JSON.
    Json,
}

/// The values the boundaries are shown for: each parameter's default, or its example
/// where it has none.
fn shown_values(d: &Declaration) -> Vec<(&'static str, f64)> {
    d.params
        .iter()
        .map(|p| (p.name, p.default.unwrap_or(p.example)))
        .collect()
}

/// The boundaries of `d` at [`shown_values`].
fn boundaries(d: &Declaration) -> Vec<Boundary> {
    d.with(&shown_values(d))
        .expect("every declared parameter given a finite value")
        .boundaries()
}

/// The option that stands for `--param NAME=` (`--gap`), if any.
fn alias(p: &Param) -> Option<&'static str> {
    ALIASES
        .iter()
        .find(|(_, name)| *name == p.name)
        .map(|(option, _)| *option)
}

/// The listing for reading.
fn text() -> String {
    let mut out = String::new();
    for d in kernels::DECLARATIONS {
        let hyphenated = d.name.replace('_', "-");
        let also = if hyphenated != d.name {
            format!(" (or {hyphenated})")
        } else {
            String::new()
        };
        out.push_str(&format!("{}{also}\n    {}\n", d.name, d.title));
        if d.params.is_empty() {
            out.push_str("    parameters: none\n");
        } else {
            out.push_str("    parameters:\n");
            let width = d.params.iter().map(|p| p.name.len()).max().unwrap_or(0);
            for p in d.params {
                let default = match p.default {
                    Some(v) => format!("default {v}"),
                    None => "required".to_string(),
                };
                let alias = alias(p).map(|o| format!("; alias {o}")).unwrap_or_default();
                out.push_str(&format!(
                    "      {:width$}  {default}: {}{alias}\n",
                    p.name, p.doc
                ));
            }
        }
        let planes = boundaries(d);
        if planes.is_empty() {
            out.push_str("    boundaries: none\n");
        } else {
            let values: Vec<String> = shown_values(d)
                .iter()
                .map(|(name, v)| format!("{name} = {v}"))
                .collect();
            out.push_str(&format!("    boundaries (for {}):\n", values.join(", ")));
            for b in planes {
                out.push_str(&format!("      {}\n", b.describe()));
            }
        }
        out.push('\n');
    }
    out
}

/// The listing as JSON.
fn json() -> String {
    let list: Vec<serde_json::Value> = kernels::DECLARATIONS
        .iter()
        .map(|d| {
            let params: Vec<serde_json::Value> = d
                .params
                .iter()
                .map(|p| {
                    serde_json::json!({
                        "name": p.name,
                        "doc": p.doc,
                        "default": p.default,
                        "example": p.example,
                        "alias": alias(p),
                    })
                })
                .collect();
            let values: serde_json::Map<String, serde_json::Value> = shown_values(d)
                .into_iter()
                .map(|(name, v)| (name.to_string(), v.into()))
                .collect();
            let planes: Vec<serde_json::Value> = boundaries(d)
                .iter()
                .map(|b| {
                    serde_json::json!({
                        "normal": b.normal,
                        "offset": b.offset,
                        "condition": b.condition.describe(),
                        "exact": b.exact,
                        "describe": b.describe(),
                    })
                })
                .collect();
            serde_json::json!({
                "name": d.name,
                "title": d.title,
                "params": params,
                "boundaries_for": values,
                "boundaries": planes,
            })
        })
        .collect();
    let mut text = serde_json::to_string_pretty(&list).expect("JSON of strings and numbers");
    text.push('\n');
    text
}

/// Write the listing to standard output (an error, not a panic, if it is closed).
pub fn run(args: &ConfinementsArgs) -> Result<(), CliError> {
    let listing = match args.format {
        ListFormat::Text => text(),
        ListFormat::Json => json(),
    };
    std::io::stdout()
        .lock()
        .write_all(listing.as_bytes())
        .map_err(|source| CliError::Write {
            path: "standard output".to_string(),
            source,
        })
}
