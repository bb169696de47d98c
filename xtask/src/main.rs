//! `cargo xtask gen [--check]`: regenerate the committed kernels in
//! `kernels/src/generated/` from the registry and the scenes in `scenes/`, or (with
//! `--check`) fail when they are stale. `cargo xtask gen --scene FILE [--out PATH]`:
//! generate one scene as a standalone module; every file within the size budget
//! ([`budget`](mod@budget)). `cargo xtask check-green FILE.rs`: try a Green's function that
//! is not registered, in a scratch copy ([`check_green`]). `cargo xtask report`: check that the
//! committed kernels are up to date, then measure and write `report/` ([`report`]).
//! `cargo xtask test`: every test, Rust and Python ([`test`](fn@test)). `cargo xtask bench`: the
//! performance table of README.md and docs/performance.md ([`bench`](mod@bench)).

use anyhow::{bail, Context, Result};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use xtask::{bench, budget, check_green, fmm, read_scene, report, root, run, scenes, wall_limit};

fn usage() -> &'static str {
    "usage: cargo xtask gen [--check] | cargo xtask gen --scene FILE [--out PATH] | cargo xtask report [--quick]\n\
     | cargo xtask check-green FILE.rs [--name NAME] | cargo xtask check-green --registered NAME\n\
     | cargo xtask test | cargo xtask bench [--quick] | cargo xtask fmm [--quick] | cargo xtask wall-limit [--truncation N]\n\
     \n\
     gen                       regenerate kernels/src/generated/ from kernel-gen and scenes/*.toml; prints each\n\
                               kernel's operations and bytes, and writes nothing if a file is over the size budget\n\
     gen --check               exit non-zero if the committed kernels differ from what the generator produces\n\
     gen --scene FILE          generate only what the scene FILE needs, as a standalone module\n\
                               (default output: target/scenes/<name>.rs)\n\
     check-green FILE.rs       try a Green's function that is not registered (one `impl Green for T`, T a unit\n\
                               struct) in a scratch copy under target/check-green/: registered as module NAME (default:\n\
                               the file's stem), generated, built (time and peak memory), measured and tested\n\
     check-green --registered NAME  measure a registered Green's function: boundary residuals, incompressibility,\n\
                               structured against generic derivatives\n\
     report                    check the committed kernels (as gen --check), then measure them and the solver and\n\
                               write report/REPORT.md with its plots (deleted and recreated); --quick: a reduced sample\n\
     test                      every test: cargo test --workspace --release, then the Python module built into\n\
                               target/python-venv (maturin, numpy, pytest from PyPI) and its pytest tests\n\
     bench                     run the benchmarks of the performance table (cargo bench -p stokesian-benches) and rewrite\n\
                               that table in README.md and docs/performance.md; --quick: short, provisional runs\n\
     fmm                       time the fast multipole product and measure its error and memory for monolayers of\n\
                               10^3 to 10^6 spheres (wall F and FT, free space F) and rewrite its table in docs/fmm.md;\n\
                               --quick: up to 10^4 spheres, provisional\n\
     wall-limit [--truncation N]  the sphere-plane functions as the two-sphere limit of a large second sphere\n\
                               (coefficients built to N terms, default 400; a table in Markdown on stdout)"
}

/// `cargo xtask gen --scene FILE [--out PATH]`.
fn gen_scene(file: &Path, out: Option<&Path>) -> Result<()> {
    let scene = read_scene(file)?;
    kernel_gen::physics::green::check_registry()?;
    let f = kernel_gen::catalog::scene_file_of(&scene, true)
        .expect("the scene's confinement is registered (checked on parse)");
    print!("{}", budget::table(std::slice::from_ref(&f)));
    budget::check(std::slice::from_ref(&f), budget::FILE_BUDGET)?;
    let path = match out {
        Some(p) => p.to_path_buf(),
        None => root().join("target/scenes").join(&f.name),
    };
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(&path, &f.contents).with_context(|| format!("writing {}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn gen(check: bool) -> Result<()> {
    let scenes = scenes()?;
    let start = Instant::now();
    // The kernels, the sphere-wall tables and the two-sphere coefficients are
    // independent: made concurrently, each timed on its own.
    let timed = |f: fn() -> Vec<u8>| {
        let t = Instant::now();
        (f(), t.elapsed())
    };
    let (
        (files, elapsed),
        (wall_tables, t_wall),
        (coefficients, t_pair),
        (far, t_far),
        (near, t_near),
    ) = std::thread::scope(|scope| {
        let wall =
            scope.spawn(|| timed(|| resistance_functions::generate::wall_tables().into_bytes()));
        let pair = scope.spawn(|| timed(resistance_functions::generate::two_sphere_coefficients));
        let far = scope.spawn(|| timed(resistance_functions::generate::two_sphere_far));
        let near = scope.spawn(|| timed(resistance_functions::generate::two_sphere_near));
        let t = Instant::now();
        let files = kernel_gen::catalog::generate(&scenes);
        let kernels = (files, t.elapsed());
        let join = |h: std::thread::ScopedJoinHandle<'_, _>| {
            h.join().expect("the table generators do not panic")
        };
        (kernels, join(wall), join(pair), join(far), join(near))
    });
    let files = files?;
    print!("{}", budget::table(&files));
    budget::check(&files, budget::FILE_BUDGET)?;
    let dir = root().join("kernels/src/generated");
    let mut stale = Vec::new();
    for f in &files {
        let path = dir.join(&f.name);
        let old = std::fs::read_to_string(&path).ok();
        if old.as_deref() != Some(f.contents.as_str()) {
            stale.push(f.name.clone());
            if !check {
                std::fs::create_dir_all(&dir)?;
                std::fs::write(&path, &f.contents)
                    .with_context(|| format!("writing {}", path.display()))?;
            }
        }
    }
    // Files in the generated directory that the generator no longer produces.
    if let Ok(rd) = std::fs::read_dir(&dir) {
        for e in rd {
            let name = e?.file_name().to_string_lossy().into_owned();
            if !files.iter().any(|f| f.name == name) {
                stale.push(format!("{name} (not produced by the generator)"));
                if !check {
                    std::fs::remove_file(dir.join(&name))?;
                }
            }
        }
    }
    // the exact resistance tables of the solver, from its series
    for (name, bytes) in [
        (
            "resistance-functions/src/generated/wall_tables.rs",
            wall_tables,
        ),
        (
            "resistance-functions/src/generated/two_sphere_coefficients.bin",
            coefficients,
        ),
        ("resistance-functions/src/generated/two_sphere_far.bin", far),
        (
            "resistance-functions/src/generated/two_sphere_near.bin",
            near,
        ),
    ] {
        let path = root().join(name);
        if std::fs::read(&path).ok().as_deref() != Some(bytes.as_slice()) {
            stale.push(name.into());
            if !check {
                std::fs::write(&path, &bytes)
                    .with_context(|| format!("writing {}", path.display()))?;
            }
        }
    }
    println!(
        "generated {} files in {:.2} s, the sphere-wall tables in {:.2} s, the two-sphere \
         recurrence coefficients in {:.2} s and the two-sphere tables in {:.2} s (far) and \
         {:.2} s (near), concurrently: {:.2} s in all",
        files.len(),
        elapsed.as_secs_f64(),
        t_wall.as_secs_f64(),
        t_pair.as_secs_f64(),
        t_far.as_secs_f64(),
        t_near.as_secs_f64(),
        start.elapsed().as_secs_f64()
    );
    if check {
        if !stale.is_empty() {
            bail!(
                "the committed kernels are stale: {} differ from what the generator produces.\n\
                 Run `cargo xtask gen` and commit kernels/src/generated/ and \
                 resistance-functions/src/generated/.",
                stale.join(", ")
            );
        }
        println!("kernels/src/generated/ is up to date");
    } else if stale.is_empty() {
        println!("kernels/src/generated/ was already up to date");
    } else {
        println!("rewrote {}", stale.join(", "));
    }
    Ok(())
}

/// `cargo xtask report [--quick]`.
fn run_report(quick: bool) -> Result<()> {
    gen(true)?;
    let out = root().join("report");
    let cfg = if quick {
        report::Config::quick(out)
    } else {
        report::Config::full(out)
    };
    let t0 = Instant::now();
    let path = report::run(cfg)?;
    println!(
        "wrote {} in {:.1} s",
        path.display(),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Crates of the solver that the Python build must find compiled by `cargo test`.
const SHARED: &[&str] = &[
    "faer ",
    "nalgebra ",
    "kernels ",
    "lanes ",
    "resistance-functions ",
    "stokesian ",
];

/// `cargo xtask test`: `cargo test --workspace --release`; then a virtual environment in
/// `target/python-venv` (created once) with maturin, numpy and pytest from PyPI, the
/// module `python/` built into it by `maturin develop --release` in the workspace's own
/// target directory and release profile (so the solver's crates compiled by the cargo
/// tests are reused: a warning names any that is compiled again), and its pytest tests,
/// given the command-line binary those tests compare with. The packages are installed
/// while cargo compiles and runs the tests (the one waits on the network, the other on
/// the processor).
fn test() -> Result<()> {
    let root = root();
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let venv = target.join("python-venv");
    let python = venv.join("bin").join("python");
    let packages = {
        let (venv, python) = (venv.clone(), python.clone());
        std::thread::spawn(move || -> Result<f64> {
            let t0 = Instant::now();
            if !python.exists() {
                let system = std::env::var_os("PYTHON").unwrap_or_else(|| "python3".into());
                run(Command::new(system).arg("-m").arg("venv").arg(&venv))?;
            }
            run(Command::new(&python).args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
                "maturin>=1.9,<2",
                "numpy",
                "pytest",
                // an array library besides NumPy (pure Python, the array API's
                // reference): NBody's arrays of any kind through DLPack
                "array-api-strict",
            ]))?;
            Ok(t0.elapsed().as_secs_f64())
        })
    };
    let tests = run(Command::new(&cargo)
        .args(["test", "--workspace", "--release"])
        .current_dir(&root));
    let packages = packages
        .join()
        .map_err(|_| anyhow::anyhow!("installing the Python packages panicked"))?;
    tests?;
    let installed = packages?;
    let t0 = Instant::now();
    let path = std::env::join_paths(std::iter::once(venv.join("bin")).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))?;
    let mut build = Command::new(venv.join("bin").join("maturin"));
    build
        .args(["develop", "--release", "--manifest-path"])
        .arg(root.join("python/Cargo.toml"))
        .env("CARGO_TARGET_DIR", &target)
        .env("VIRTUAL_ENV", &venv)
        .env("PATH", &path)
        .stderr(Stdio::piped());
    let mut child = build
        .spawn()
        .with_context(|| format!("cannot start {build:?}"))?;
    let mut recompiled = Vec::new();
    if let Some(err) = child.stderr.take() {
        for line in BufReader::new(err).lines() {
            let line = line?;
            eprintln!("{line}");
            if let Some(name) = line.trim_start().strip_prefix("Compiling ") {
                if SHARED.iter().any(|s| name.starts_with(s)) {
                    recompiled.push(name.to_string());
                }
            }
        }
    }
    let status = child.wait()?;
    if !status.success() {
        bail!("{build:?} failed ({status})");
    }
    if !recompiled.is_empty() {
        eprintln!(
            "xtask test: warning: the Python build compiled {} again: the features of \
             python/Cargo.toml and of the workspace have drifted apart (see the comments in \
             python/Cargo.toml and tests/Cargo.toml)",
            recompiled.join(", ")
        );
    }
    // printed before pytest, whose summary line (with its own time) closes the run
    println!(
        "xtask test: the Python environment took {installed:.1} s (beside the cargo tests), \
         the module {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    run(Command::new(&python)
        .args(["-m", "pytest", "-q"])
        .arg(root.join("python/tests"))
        .env("STOKESIAN_CLI", target.join("release").join("stokesian"))
        .current_dir(&root))
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .as_slice()
    {
        ["gen"] => gen(false),
        ["gen", "--check"] => gen(true),
        ["gen", "--scene", file] => gen_scene(Path::new(file), None),
        ["gen", "--scene", file, "--out", out] => gen_scene(Path::new(file), Some(Path::new(out))),
        ["report"] => run_report(false),
        ["report", "--quick"] => run_report(true),
        ["test"] => test(),
        ["bench"] => bench::run(&root(), false),
        ["bench", "--quick"] => bench::run(&root(), true),
        ["fmm"] => fmm::run(&root(), false),
        ["fmm", "--quick"] => fmm::run(&root(), true),
        ["wall-limit", rest @ ..] => wall_limit::run(rest),
        ["check-green", rest @ ..] => check_green::run(&root(), rest),
        ["help"] | ["--help"] | ["-h"] | [] => {
            println!("{}", usage());
            Ok(())
        }
        _ => bail!("unknown arguments {args:?}\n{}", usage()),
    }
}
