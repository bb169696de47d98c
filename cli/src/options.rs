//! Checks of single option values (finite, positive, comma-separated components) and
//! how numbers are shown in messages.

use crate::error::CliError;

/// A number as Rust prints it (shortest round trip), in exponent form when it is very
/// large or very small (`1e-301`, not three hundred zeros): the library's, so that the
/// command's messages and the boundaries' descriptions agree.
pub use kernels::readable as num;

/// A positive finite option value.
pub fn positive(option: &'static str, value: f64, what: &str) -> Result<(), CliError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CliError::BadOption {
            option,
            value: num(value),
            reason: format!("{what} must be a positive finite number"),
        })
    }
}

/// The help of `--pair-tolerance` (`resistance`, `velocity --lubrication`, `brownian
/// --lubrication`).
pub const PAIR_TOLERANCE_HELP: &str = "Lubrication: keep the exact two-sphere correction \
    of every pair where it may exceed TOL (its largest entry, lengths in units of the larger \
    radius, over the smaller sphere's drag 6 pi eta a), switched off smoothly beyond; 0 \
    corrects every pair, inf none. 1e-3 reaches s' = 2r/(a1 + a2) = 9.3 at FT (5.6 at \
    FTS), the default 1e-6 reaches 52.3 (17.6).";

/// `--pair-tolerance` where it needs `--lubrication` (`velocity`, `brownian`; flattened
/// into their arguments).
#[derive(clap::Args, Debug)]
pub struct PairToleranceArg {
    #[arg(
        long,
        value_name = "TOL",
        help = PAIR_TOLERANCE_HELP,
        requires = "lubrication",
        allow_hyphen_values = true
    )]
    pub pair_tolerance: Option<f64>,
}

/// The lubrication settings of `--pair-tolerance` (the library's default without it).
pub fn lubrication(pair_tolerance: Option<f64>) -> Result<stokesian::Lubrication, CliError> {
    let lub = stokesian::Lubrication::default();
    let Some(tol) = pair_tolerance else {
        return Ok(lub);
    };
    if tol >= 0.0 {
        Ok(lub.with_pair_tolerance(tol))
    } else {
        Err(CliError::BadOption {
            option: "--pair-tolerance",
            value: num(tol),
            reason: "the pair tolerance must be a number >= 0 (0: every pair corrected; \
                     inf: none)"
                .to_string(),
        })
    }
}

/// A finite option value.
pub fn finite(option: &'static str, value: f64) -> Result<(), CliError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(CliError::BadOption {
            option,
            value: num(value),
            reason: "must be a finite number".to_string(),
        })
    }
}

/// Comma-separated finite numbers given to `option`.
pub fn parse_components(option: &'static str, text: &str) -> Result<Vec<f64>, CliError> {
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
