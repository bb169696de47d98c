//! Checks of single option values (finite, positive, comma-separated components) and
//! how numbers are shown in messages.

use super::error::CliError;

/// A number as Rust prints it (shortest round trip), in exponent form when it is very
/// large or very small (`1e-301`, not three hundred zeros).
pub fn num(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-5..1e16).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

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
