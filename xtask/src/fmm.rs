//! `cargo xtask fmm [--quick]`: time the fast product (`stokesian::fmm`) and measure its
//! error and memory for monolayers of 10^3 to 10^6 spheres (the example
//! `stokesian/examples/fmm_timing.rs`, one process per row, so that each row's peak
//! memory is its own), and rewrite the table between `<!-- fmm:begin -->` and
//! `<!-- fmm:end -->` in docs/fmm.md; then one Brownian step with the fast product and
//! Lanczos noise (the example's `brownian`) for 10^3 to 10^5 spheres, the table between
//! `<!-- fmm-brownian:begin -->` and `<!-- fmm-brownian:end -->`. `--quick`: up to 10^4
//! spheres, marked provisional. No number in these tables is written by hand.

use anyhow::{bail, Context, Result};
use kernels::lanes::Isa;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const BEGIN: &str = "<!-- fmm:begin -->";
const END: &str = "<!-- fmm:end -->";
const BROWNIAN_BEGIN: &str = "<!-- fmm-brownian:begin -->";
const BROWNIAN_END: &str = "<!-- fmm-brownian:end -->";
const FILE: &str = "docs/fmm.md";

/// The tolerance of every row.
const EPS: &str = "1e-6";

/// (confinement, truncation) of the rows.
const CASES: [(&str, &str); 3] = [("wall", "F"), ("wall", "FT"), ("free", "F")];

/// The direct product is timed up to this size.
const DIRECT_UP_TO: usize = 10_000;

/// One row's `result` line as `key -> value`: the example run with `N EPS moments conf`
/// and `extra`.
fn measure(
    binary: &Path,
    n: usize,
    conf: &str,
    moments: &str,
    extra: &[&str],
) -> Result<BTreeMap<String, String>> {
    let mut cmd = Command::new(binary);
    cmd.args([n.to_string().as_str(), EPS, moments, conf]);
    cmd.args(extra);
    let out = cmd
        .output()
        .with_context(|| format!("running {}", binary.display()))?;
    if !out.status.success() {
        bail!(
            "{} {n} {EPS} {moments} {conf} failed: {}",
            binary.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("result "))
        .context("the example printed no `result` line")?;
    Ok(line
        .split_whitespace()
        .skip(1)
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect())
}

/// `cargo xtask fmm [--quick]`.
pub fn run(root: &Path, quick: bool) -> Result<()> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    crate::run(
        Command::new(cargo)
            .args([
                "build",
                "--release",
                "-p",
                "stokesian",
                "--example",
                "fmm_timing",
            ])
            .current_dir(root),
    )?;
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let binary = target.join("release/examples/fmm_timing");
    let sizes: &[usize] = if quick {
        &[1_000, 10_000]
    } else {
        &[1_000, 10_000, 100_000, 1_000_000]
    };
    let command = if quick {
        "cargo xtask fmm --quick"
    } else {
        "cargo xtask fmm"
    };
    let mut s = format!(
        "Written by `{command}` on {} ({}; lanes: {}; release build). A monolayer of unit \
         spheres (area fraction 0.3, heights 1.5 to 5 radii), random moments, the tolerance \
         `eps = {EPS}` and the parameters `FastProduct::new` chooses for it. Times: the \
         median of five products below 10^5 spheres, else one; the error is the relative \
         2-norm error against the direct sum, over every target up to 2x10^4 spheres, else \
         over 1000 random targets; memory: the process's peak resident set.\n",
        crate::report::today(),
        crate::bench::machine(),
        Isa::best().name()
    );
    if quick {
        s.push_str("**Provisional**: up to 10^4 spheres only; `cargo xtask fmm` runs them all.\n");
    }
    s.push_str(
        "\n| confinement, truncation | N | fast product | direct product | error (targets) | \
         peak memory | tree / upward / across / downward / leaves |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for (conf, moments) in CASES {
        for &n in sizes {
            let direct: &[&str] = if n <= DIRECT_UP_TO { &["direct"] } else { &[] };
            let r = measure(&binary, n, conf, moments, direct)?;
            let get = |k: &str| r.get(k).cloned().unwrap_or_else(|| "-".into());
            let seconds = |k: &str| match r.get(k).and_then(|v| v.parse::<f64>().ok()) {
                Some(t) => format!("{t:.3} s"),
                None => "-".into(),
            };
            let label = match conf {
                "free" => format!("free space, {moments}"),
                _ => format!("wall, {moments}"),
            };
            s.push_str(&format!(
                "| {label} | {n} | {} | {} | {} ({}) | {} MiB | {} / {} / {} / {} / {} |\n",
                seconds("time"),
                seconds("direct"),
                get("error"),
                get("targets"),
                get("peak_mib"),
                seconds("tree"),
                seconds("upward"),
                seconds("across"),
                seconds("downward"),
                seconds("leaves"),
            ));
            println!("measured {label}, N = {n}");
        }
    }
    crate::bench::rewrite_between(&root.join(FILE), BEGIN, END, &s)?;
    println!("wrote the table of {FILE}");
    print!("{s}");
    let mut b = format!(
        "Written by `{command}` on {} ({}; lanes: {}; release build). One Euler-Maruyama \
         step (`stokesian brownian --lanczos 1e-4 --fmm {EPS}`: the same monolayer above a \
         wall, gravity, `kT = 1`, `dt = 1e-3`): the Lanczos iteration's products, `M F` and \
         the drift, from the positions to the displaced system; the drift alone timed \
         apart.\n\n| N | step | Lanczos iterations | drift | peak memory |\n|---|---|---|---|---|\n",
        crate::report::today(),
        crate::bench::machine(),
        Isa::best().name()
    );
    let sizes = &sizes[..sizes.len().min(3)];
    for &n in sizes {
        let r = measure(&binary, n, "wall", "F", &["brownian"])?;
        let get = |k: &str| r.get(k).cloned().unwrap_or_else(|| "-".into());
        b.push_str(&format!(
            "| {n} | {} s | {} | {} s | {} MiB |\n",
            get("step"),
            get("lanczos"),
            get("drift"),
            get("peak_mib")
        ));
        println!("measured a Brownian step, N = {n}");
    }
    crate::bench::rewrite_between(&root.join(FILE), BROWNIAN_BEGIN, BROWNIAN_END, &b)?;
    print!("{b}");
    Ok(())
}
