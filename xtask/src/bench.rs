//! `cargo xtask bench [--quick]`: run the criterion benchmarks of the solver that the
//! performance table reports (`benches/benches/mobility.rs`, filtered to the rows
//! below), read criterion's estimates (`target/criterion/**/new/estimates.json`, the
//! median of each benchmark) and rewrite the table between the markers
//! `<!-- bench:begin -->` and `<!-- bench:end -->` in `README.md` and
//! `docs/performance.md`, with the machine (processor, cores, the instruction set the
//! `lanes` crate detects), the date and the command. No number in that table is
//! written by hand.
//!
//! `--quick` passes criterion's own `--quick` (each benchmark only until its estimate
//! is stable to 5%, without warm-up): a check that the command works, marked
//! provisional in the table it writes.

use anyhow::{bail, Context, Result};
use kernels::lanes::Isa;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::SystemTime;

/// The marker lines that enclose the generated table.
/// The line before the performance table in the files it is written into.
pub const BEGIN: &str = "<!-- bench:begin -->";
/// The line after the performance table.
pub const END: &str = "<!-- bench:end -->";

/// The files whose table is rewritten, relative to the workspace root.
const FILES: [&str; 2] = ["README.md", "docs/performance.md"];

/// The fused pair products timed per pair: (row label, confinement, truncation).
const PAIR_ROWS: [(&str, &str, &str); 6] = [
    ("wall, F", "wall", "F"),
    ("wall, FT", "wall", "FT"),
    ("wall, FTS", "wall", "FTS"),
    ("free space, F", "free", "F"),
    ("free space, FT", "free", "FT"),
    ("free space, FTS", "free", "FTS"),
];

/// Whole operations: (row label, criterion id).
pub const OPERATION_ROWS: [(&str, &str); 6] = [
    (
        "`M x` near a wall, F, N = 10^4 (`System::apply`)",
        "wall product M x/F/10000",
    ),
    (
        "`M x` near a wall, FT, N = 10^4",
        "wall product M x/FT/10000",
    ),
    (
        "`M x` near a wall, FTS, N = 1000",
        "wall product M x/FTS/1000",
    ),
    (
        "dense FTS mobility near a wall, N = 1000 (11000 x 11000, huge pages)",
        "wall dense FTS assembly/LargeMatrix/1000",
    ),
    (
        "the 22 two-sphere functions of a pair, near contact (per pair)",
        "two-sphere functions of a pair/near, all 22",
    ),
    (
        "the 22 two-sphere functions of a pair, `s' >= 3` (per pair)",
        "two-sphere functions of a pair/far, all 22",
    ),
];

/// The three criterion ids of a per-pair row: scalar kernel, `f64` lanes, `f32` lanes.
fn pair_ids(conf: &str, level: &str, isa: Isa) -> [String; 3] {
    let group = "pair product lanes";
    let isa = isa.name();
    [
        format!("{group}/{level} scalar kernel/{conf}"),
        format!("{group}/{level} lanes {isa}/{conf}"),
        format!("{group}/{level} lanes {isa} f32/{conf}"),
    ]
}

/// Every criterion id the table reads.
pub fn all_ids(isa: Isa) -> Vec<String> {
    let pairs = PAIR_ROWS
        .iter()
        .flat_map(|&(_, conf, level)| pair_ids(conf, level, isa));
    let ops = OPERATION_ROWS.iter().map(|&(_, id)| id.to_string());
    pairs.chain(ops).collect()
}

/// `s` with the regular expression's special characters escaped.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        if r"\.+*?()|[]{}^$#&-~".contains(c) {
            out.push('\\');
        }
        out.push(c);
    }
    out
}

/// A criterion result: the median time of one iteration, and the elements it processed.
struct Estimate {
    median_ns: f64,
    elements: u64,
}

/// Every benchmark under `dir` (criterion's output) measured after `since`, by id.
fn read_estimates(
    dir: &Path,
    since: SystemTime,
) -> Result<std::collections::BTreeMap<String, Estimate>> {
    let mut found = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let path = e?.path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let in_new = path.parent().and_then(Path::file_name) == Some("new".as_ref());
            if !in_new || path.file_name() != Some("benchmark.json".as_ref()) {
                continue;
            }
            let estimates = path.with_file_name("estimates.json");
            if std::fs::metadata(&estimates)?.modified()? < since {
                continue; // an earlier run's
            }
            let json = |p: &Path| -> Result<serde_json::Value> {
                let text = std::fs::read_to_string(p)
                    .with_context(|| format!("reading {}", p.display()))?;
                serde_json::from_str(&text).with_context(|| format!("parsing {}", p.display()))
            };
            let id = json(&path)?;
            let est = json(&estimates)?;
            let full_id = id["full_id"]
                .as_str()
                .with_context(|| format!("no full_id in {}", path.display()))?;
            let median_ns = est["median"]["point_estimate"]
                .as_f64()
                .with_context(|| format!("no median in {}", estimates.display()))?;
            let elements = id["throughput"]["Elements"].as_u64().unwrap_or(1);
            found.insert(
                full_id.to_string(),
                Estimate {
                    median_ns,
                    elements,
                },
            );
        }
    }
    Ok(found)
}

/// A time in nanoseconds with three significant digits and its unit.
pub fn format_time(ns: f64) -> String {
    let (value, unit) = if ns < 1e3 {
        (ns, "ns")
    } else if ns < 1e6 {
        (ns / 1e3, "us")
    } else if ns < 1e9 {
        (ns / 1e6, "ms")
    } else {
        (ns / 1e9, "s")
    };
    let decimals = if value < 10.0 {
        2
    } else if value < 100.0 {
        1
    } else {
        0
    };
    format!("{value:.decimals$} {unit}")
}

/// The processor, its logical cores and the compiler.
pub fn machine() -> String {
    use crate::report::{cpu_model, logical_cpus, rustc_version};
    format!(
        "{}, {} cores, {}",
        cpu_model(),
        logical_cpus(),
        rustc_version()
    )
}

/// The Markdown between the markers.
fn table(
    estimates: &std::collections::BTreeMap<String, Estimate>,
    isa: Isa,
    quick: bool,
) -> Result<String> {
    let time = |id: &str| -> Result<String> {
        let e = estimates
            .get(id)
            .with_context(|| format!("criterion wrote no estimate for `{id}`"))?;
        Ok(format_time(e.median_ns / e.elements as f64))
    };
    let command = if quick {
        "cargo xtask bench --quick"
    } else {
        "cargo xtask bench"
    };
    let mut s = String::new();
    s.push_str(&format!(
        "Written by `{command}` on {} ({}; lanes: {}; release build, criterion medians).\n",
        crate::report::today(),
        machine(),
        isa.name()
    ));
    if quick {
        s.push_str(
            "**Provisional**: a quick run (criterion's `--quick`, no warm-up); \
             `cargo xtask bench` measures in full.\n",
        );
    }
    let name = isa.name();
    s.push_str(&format!(
        "\n| fused pair product, per pair (1024 pairs near a wall) | scalar kernel | \
         lanes, `f64`, {name} | lanes, `f32`, {name} |\n|---|---|---|---|\n"
    ));
    for &(label, conf, level) in &PAIR_ROWS {
        let [scalar, double, single] = pair_ids(conf, level, isa);
        s.push_str(&format!(
            "| {label} | {} | {} | {} |\n",
            time(&scalar)?,
            time(&double)?,
            time(&single)?
        ));
    }
    // rayon's pool: RAYON_NUM_THREADS, else one thread per logical processor
    let threads = std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|t| t.parse::<usize>().ok())
        .filter(|&t| t > 0)
        .unwrap_or_else(crate::report::logical_cpus);
    s.push_str(&format!(
        "\n| operation (unit spheres, 5% volume fraction, {threads} threads) | time |\n|---|---|\n"
    ));
    for &(label, id) in &OPERATION_ROWS {
        s.push_str(&format!("| {label} | {} |\n", time(id)?));
    }
    Ok(s)
}

/// Replace what lies between the markers of `path` by `body`.
pub fn rewrite(path: &Path, body: &str) -> Result<()> {
    rewrite_between(path, BEGIN, END, body)
}

/// Replace what lies between the lines `begin` and `end` of `path` by `body`.
pub fn rewrite_between(path: &Path, begin: &str, end: &str, body: &str) -> Result<()> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let (Some(b), Some(e)) = (text.find(begin), text.find(end)) else {
        bail!("{} has no `{begin}` ... `{end}` markers", path.display());
    };
    if e < b {
        bail!("{}: `{end}` comes before `{begin}`", path.display());
    }
    let out = format!("{}{begin}\n{body}{}", &text[..b], &text[e..]);
    std::fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

/// `cargo xtask bench [--quick]`.
pub fn run(root: &Path, quick: bool) -> Result<()> {
    let isa = Isa::best();
    let filter = format!(
        "^({})$",
        all_ids(isa)
            .iter()
            .map(|id| escape(id))
            .collect::<Vec<_>>()
            .join("|")
    );
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let since = SystemTime::now();
    let mut bench = Command::new(cargo);
    bench
        .args([
            "bench",
            "-p",
            "stokesian-benches",
            "--bench",
            "mobility",
            "--",
        ])
        .args(quick.then_some("--quick"))
        .arg(&filter)
        .current_dir(root);
    crate::run(&mut bench)?;
    let estimates = read_estimates(&target.join("criterion"), since)?;
    let body = table(&estimates, isa, quick)?;
    for file in FILES {
        rewrite(&root.join(file), &body)?;
        println!("wrote the table of {file}");
    }
    print!("{body}");
    Ok(())
}
