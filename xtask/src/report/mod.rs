//! `cargo xtask report`: measures the kernels and the solver and writes `report/REPORT.md`
//! with its plots (PNG and SVG), from scratch each run.
//!
//! This module owns the orchestration: the run's [`Config`] (sample sizes, timing
//! budget, output directory), the list of [`SECTIONS`] (each one function from the
//! shared [`Ctx`] to a [`Section`]: adding a section is one function and one line), the
//! header (machine, date) and the writing of the file. The sections live in
//! [`numerics`] (a: kernel accuracy and cost per variant), [`physics`] (b: truncation
//! levels against exact results), [`scenes`] (d: pruned scene kernels), [`brownian`] (e:
//! lubricated Brownian dynamics at equilibrium), [`periodic`] (f: Brownian dynamics
//! above a periodic wall) and [`fast`] (g: Brownian dynamics with the fast product); the
//! shared
//! pieces in [`boltzmann`] (runs with and without the drift against Boltzmann's heights,
//! sections f and g), [`sample`] (seeded configurations), [`timing`] (the timing loop),
//! [`table`] (markdown tables and number formatting) and [`plot`] (log-log scatter
//! plots).

pub mod boltzmann;
pub mod brownian;
pub mod closed;
pub mod fast;
pub mod numerics;
pub mod periodic;
pub mod physics;
pub mod plot;
pub mod sample;
pub mod scenes;
pub mod stiff;
pub mod table;
pub mod timing;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// What a run measures and where it writes.
#[derive(Clone, Debug)]
pub struct Config {
    /// Output directory (deleted and recreated).
    pub out: PathBuf,
    /// Configurations per kernel family and interaction for the fast variants (section a).
    pub cases: usize,
    /// Configurations for the slow variants (run-time jets, finite differences).
    pub slow_cases: usize,
    /// Minimum wall time of one timing measurement.
    pub min_time: Duration,
    /// Heights of the sphere-wall sweep and gaps of the two-sphere sweep (section b).
    pub sweep: usize,
    /// Brownian steps of each run of section e.
    pub brownian_steps: usize,
    /// Brownian steps of each run of section f (a step sums the periodic lattice).
    pub periodic_brownian_steps: usize,
    /// Spheres along each side of section g's lattice.
    pub fast_brownian_side: usize,
    /// Brownian steps of each run of section g (each step several fast products).
    pub fast_brownian_steps: usize,
    /// The confinements of the stiff cases (section c), all of them if `None`.
    pub stiff_only: Option<&'static str>,
    /// Draw a progress bar.
    pub progress: bool,
    /// Run the sections concurrently, one thread each (the reduced run of the test,
    /// whose timings are not read); the full report runs them one after the other so
    /// that no section's timings share the processor with another's.
    pub concurrent: bool,
}

impl Config {
    /// The full report, written to `report/` in the workspace.
    pub fn full(out: PathBuf) -> Config {
        Config {
            out,
            cases: 200,
            slow_cases: 20,
            min_time: Duration::from_millis(150),
            sweep: 12,
            brownian_steps: 1_200_000,
            periodic_brownian_steps: 1_200_000,
            fast_brownian_side: 16,
            fast_brownian_steps: 6_000,
            stiff_only: None,
            progress: true,
            concurrent: false,
        }
    }

    /// A reduced run (a few configurations, short timings) for the test.
    pub fn quick(out: PathBuf) -> Config {
        Config {
            out,
            cases: 4,
            slow_cases: 1,
            min_time: Duration::from_millis(2),
            sweep: 3,
            brownian_steps: 4_000,
            periodic_brownian_steps: 400,
            fast_brownian_side: 4,
            fast_brownian_steps: 30,
            // the wall alone: every confinement's stiff cases are the integration
            // test `generated::stiff_cases`, the same measurement
            stiff_only: Some("wall"),
            progress: false,
            concurrent: true,
        }
    }
}

/// What the sections share: the configuration, the progress bar, the output directory.
pub struct Ctx {
    /// The run's configuration.
    pub cfg: Config,
    /// Progress over all sections (sections add their own units of work).
    pub progress: ProgressBar,
}

impl Ctx {
    /// Path of an output file in the report directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.cfg.out.join(name)
    }
}

/// One section of the report: a title and its markdown body (tables, the sentence of
/// what was measured, links to plots written by the section itself).
pub struct Section {
    /// Heading.
    pub title: String,
    /// Markdown body.
    pub body: String,
}

/// A section: a function from the shared context to its text.
pub type SectionFn = fn(&Ctx) -> Result<Section>;

/// The sections of the report, in order.
pub const SECTIONS: &[SectionFn] = &[
    numerics::section,
    physics::section,
    stiff::section,
    scenes::section,
    brownian::section,
    periodic::section,
    fast::section,
];

/// Run the whole report into `cfg.out` (deleted and recreated) and return the path of
/// `REPORT.md`.
pub fn run(cfg: Config) -> Result<PathBuf> {
    let t0 = Instant::now();
    if cfg.out.exists() {
        std::fs::remove_dir_all(&cfg.out)
            .with_context(|| format!("removing {}", cfg.out.display()))?;
    }
    std::fs::create_dir_all(&cfg.out).with_context(|| format!("creating {}", cfg.out.display()))?;
    let progress = if cfg.progress {
        let pb = ProgressBar::new(0);
        pb.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
                .expect("valid template")
                .progress_chars("=> "),
        );
        pb
    } else {
        ProgressBar::hidden()
    };
    let ctx = Ctx { cfg, progress };
    let sections: Vec<Section> = if ctx.cfg.concurrent {
        std::thread::scope(|s| {
            let running: Vec<_> = SECTIONS.iter().map(|f| s.spawn(|| f(&ctx))).collect();
            running
                .into_iter()
                .map(|h| h.join().expect("a report section panicked"))
                .collect::<Result<_>>()
        })?
    } else {
        SECTIONS.iter().map(|f| f(&ctx)).collect::<Result<_>>()?
    };
    ctx.progress.finish_and_clear();
    let elapsed = t0.elapsed();
    let text = document(&sections, elapsed)?;
    let path = ctx.path("REPORT.md");
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}

/// The whole markdown document: header, table of contents, sections.
fn document(sections: &[Section], elapsed: Duration) -> Result<String> {
    let mut s = String::new();
    writeln!(s, "# Kernel and solver report\n")?;
    writeln!(
        s,
        "Written by `cargo xtask report` (xtask/src/report/) on {}; every number below was measured by that run. \
         Machine: {}, {} logical cores ({} available to the process); {}. \
         The run took {:.0} s of wall time.\n",
        today(),
        cpu_model(),
        logical_cpus(),
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        rustc_version(),
        elapsed.as_secs_f64()
    )?;
    // the load the timings were taken under (this run itself keeps one core busy)
    let load = std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|t| t.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "unknown".to_string());
    writeln!(
        s,
        "Timing throughout: a plain loop over a fixed set of inputs, one warm-up pass, then \
         repeated passes until at least a minimum wall time has elapsed, inputs and outputs \
         passed through `std::hint::black_box`; single-threaded; the figure is wall time per \
         evaluation. Load average over the last minute when the report was written: {load} \
         (the run itself accounts for about 1); under other load, timings carry noise of \
         10-20%.\n"
    )?;
    for sec in sections {
        let anchor: String = sec
            .title
            .to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-')
            .map(|c| if c == ' ' { '-' } else { c })
            .collect();
        writeln!(s, "- [{}](#{anchor})", sec.title)?;
    }
    writeln!(s)?;
    for sec in sections {
        writeln!(s, "## {}\n\n{}", sec.title, sec.body.trim_end())?;
        writeln!(s)?;
    }
    Ok(s)
}

/// The CPU model from `/proc/cpuinfo`.
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU (no /proc/cpuinfo)".into())
}

/// Logical CPUs listed in `/proc/cpuinfo`.
pub fn logical_cpus() -> usize {
    std::fs::read_to_string("/proc/cpuinfo")
        .map(|t| t.lines().filter(|l| l.starts_with("processor")).count())
        .unwrap_or(0)
}

/// `rustc --version`, as the report and the benchmark table name the compiler.
pub fn rustc_version() -> String {
    std::process::Command::new("rustc")
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|| "rustc version unknown".into())
}

/// Today's date (UTC), `YYYY-MM-DD`, from the system clock (civil-from-days).
pub fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let z = secs.div_euclid(86_400) + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}")
}
