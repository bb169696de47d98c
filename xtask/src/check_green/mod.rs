//! `cargo xtask check-green FILE.rs [--name NAME]`: try a Green's function that is not
//! in the registry without touching the checkout. The workspace is mirrored into
//! `target/check-green/workspace` (the files git tracks or does not ignore; a file is
//! rewritten only when it differs, so cargo rebuilds only what changed since the last
//! run), FILE is added there as `kernel-gen/src/physics/green/NAME.rs` with its `pub mod`
//! line and its line in the registry `for_each`, and there, with its own target
//! directory `target/check-green/target` (seeded once from the checkout's release
//! build): `cargo xtask gen` (the declaration checks and the size budget apply), the
//! build of the kernels and the solver and of the integration tests, each timed with its
//! peak memory (`/usr/bin/time -v`), the measurements of [`measure`]
//! (`check-green --registered NAME`) and the integration tests that iterate the
//! registry (`generated::`, `physics::` and the lanes binary's modules: reciprocity,
//! positive definiteness, emitted against interpreted kernels, the far field, lanes and
//! units). A summary of
//! the sizes, operation counts, residuals, times and memory closes the run.
//!
//! `cargo xtask check-green --registered NAME` measures a registered Green's function.

mod measure;

use anyhow::{bail, Context, Result};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Where the Green's functions live, relative to the workspace.
pub const GREEN_DIR: &str = "kernel-gen/src/physics/green";

/// The directories `cargo xtask gen` writes: mirrored only when the scratch copy has no
/// file there yet, and from then on left to the scratch copy's own generator.
const GENERATED: [&str; 2] = [
    "kernels/src/generated/",
    "resistance-functions/src/generated/",
];

/// The modules of the integration tests (binaries `integration`, `lanes` and
/// `lanes_single`) that iterate
/// the registry.
const REGISTRY_TESTS: [&str; 6] = [
    "generated::",
    "physics::",
    "scalar::",
    "single_precision::",
    "tiled_product::",
    "layout::",
];

/// What the command line asks.
#[derive(Debug, PartialEq)]
pub enum Args {
    /// Check a Green's function file, registered under a module name.
    File {
        /// The file (`FILE.rs`).
        file: PathBuf,
        /// The module name to register it under (`--name`; default: the file's stem).
        name: Option<String>,
    },
    /// Measure a registered Green's function.
    Registered(String),
}

const USAGE: &str = "usage: cargo xtask check-green FILE.rs [--name NAME] | cargo xtask check-green --registered NAME";

/// The arguments of `cargo xtask check-green`, or an error that says what is wrong
/// followed by the usage.
pub fn parse(args: &[&str]) -> Result<Args> {
    let mut file: Option<PathBuf> = None;
    let mut name: Option<String> = None;
    let mut registered: Option<String> = None;
    let mut it = args.iter();
    while let Some(&a) = it.next() {
        let value = |it: &mut std::slice::Iter<&str>| -> Result<String> {
            match it.next() {
                Some(v) if !v.starts_with("--") => Ok(v.to_string()),
                _ => bail!("{a} needs a value\n{USAGE}"),
            }
        };
        match a {
            "--name" if name.is_none() => name = Some(value(&mut it)?),
            "--registered" if registered.is_none() => registered = Some(value(&mut it)?),
            "--name" | "--registered" => bail!("{a} is given twice\n{USAGE}"),
            _ if a.starts_with("--") => bail!("unknown option {a}\n{USAGE}"),
            _ if file.is_some() => bail!("more than one file: {a}\n{USAGE}"),
            _ if !a.ends_with(".rs") => bail!("{a} is not a Rust file (FILE.rs)\n{USAGE}"),
            _ => file = Some(PathBuf::from(a)),
        }
    }
    match (file, name, registered) {
        (Some(file), name, None) => Ok(Args::File { file, name }),
        (None, None, Some(name)) => Ok(Args::Registered(name)),
        (None, None, None) => bail!("no file given\n{USAGE}"),
        _ => bail!("--registered takes no file and no --name\n{USAGE}"),
    }
}

/// `cargo xtask check-green ARGS`.
pub fn run(root: &Path, args: &[&str]) -> Result<()> {
    match parse(args)? {
        Args::Registered(name) => measure::run(&name),
        Args::File { file, name } => check_file(root, &file, name),
    }
}

/// What the registry needs to know of a Green's function's file.
#[derive(Debug, PartialEq)]
pub struct Found {
    /// The unit struct that implements `Green`.
    pub ty: String,
    /// What its `name()` returns, if that is a string literal.
    pub name: Option<String>,
}

/// Find the one `impl Green for T` of a file, `T` a unit struct of the file.
pub fn analyze(source: &str) -> Result<Found> {
    let file: syn::File = syn::parse_file(source).map_err(|e| {
        anyhow::anyhow!("it does not parse as Rust: {e} (`rustfmt --check FILE` shows where)")
    })?;
    let mut impls = Vec::new();
    for item in &file.items {
        let syn::Item::Impl(i) = item else { continue };
        let Some((_, path, _)) = &i.trait_ else {
            continue;
        };
        if path.segments.last().is_some_and(|s| s.ident == "Green") {
            impls.push(i);
        }
    }
    let [i] = impls.as_slice() else {
        bail!(
            "it has {} `impl Green for T`; it needs exactly one",
            impls.len()
        );
    };
    let syn::Type::Path(t) = &*i.self_ty else {
        bail!("`impl Green for T` needs T to be a struct of the file");
    };
    let ty = match t.path.get_ident() {
        Some(ty) => ty.to_string(),
        None => bail!("`impl Green for T` needs T to be a struct of the file, by its name alone"),
    };
    let unit = file.items.iter().any(|item| {
        matches!(item, syn::Item::Struct(s) if s.ident == ty && matches!(s.fields, syn::Fields::Unit) && s.generics.params.is_empty())
    });
    if !unit {
        bail!(
            "the registry visits `&{ty}`: the file must declare `pub struct {ty};`, a unit struct"
        );
    }
    let name = i.items.iter().find_map(|item| {
        let syn::ImplItem::Fn(f) = item else {
            return None;
        };
        if f.sig.ident != "name" {
            return None;
        }
        match f.block.stmts.as_slice() {
            [syn::Stmt::Expr(
                syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }),
                None,
            )] => Some(s.value()),
            _ => None,
        }
    });
    Ok(Found { ty, name })
}

/// The registry's `mod.rs` with the module `module` (its Green's function the unit
/// struct `ty`) added: a `pub mod` line after the last one, a `v.visit` line at the end
/// of `for_each`.
pub fn register(mod_rs: &str, module: &str, ty: &str) -> Result<String> {
    let mut lines: Vec<String> = mod_rs.lines().map(String::from).collect();
    let last_mod = lines
        .iter()
        .rposition(|l| l.starts_with("pub mod "))
        .context("the registry's mod.rs has no `pub mod` line")?;
    lines.insert(last_mod + 1, format!("pub mod {module};"));
    let start = lines
        .iter()
        .position(|l| l.starts_with("pub fn for_each<"))
        .context("the registry's mod.rs has no `pub fn for_each<`")?;
    let end = start
        + lines[start..]
            .iter()
            .position(|l| l == "}")
            .context("`for_each` has no closing brace in column 0")?;
    lines.insert(end, format!("    v.visit(&{module}::{ty});"));
    Ok(lines.join("\n") + "\n")
}

/// Check the file, name the module, and run everything in the scratch copy.
fn check_file(root: &Path, file: &Path, name: Option<String>) -> Result<()> {
    let source =
        std::fs::read_to_string(file).with_context(|| format!("reading {}", file.display()))?;
    let name = match name {
        Some(n) => n,
        None => file
            .file_stem()
            .and_then(|s| s.to_str())
            .context("the file has no name")?
            .to_string(),
    };
    if !kernel_gen::physics::green::is_identifier(&name) {
        bail!("the module name `{name}` is not a lower-case Rust identifier: rename the file or give --name NAME");
    }
    if root.join(GREEN_DIR).join(format!("{name}.rs")).exists() {
        bail!("{GREEN_DIR}/{name}.rs exists already: rename the file or give --name NAME");
    }
    let found = analyze(&source).with_context(|| format!("{}", file.display()))?;
    if let Some(declared) = &found.name {
        if *declared != name {
            bail!(
                "{}: `name()` returns \"{declared}\", but the module is `{name}`: make them equal \
                 (or give --name {declared})",
                file.display()
            );
        }
    }
    if crate::registered().contains(&name.as_str()) {
        bail!("a Green's function named `{name}` is registered already: rename it");
    }
    let status_before = git_status(root)?;
    let t0 = Instant::now();
    let scratch = Scratch::new(root)?;
    println!(
        "check-green: {} as `{name}` (the unit struct `{}`) in {}",
        file.display(),
        found.ty,
        scratch.workspace.display()
    );
    let mod_rs = std::fs::read_to_string(root.join(GREEN_DIR).join("mod.rs"))?;
    let extra = BTreeMap::from([
        (
            format!("{GREEN_DIR}/mod.rs"),
            register(&mod_rs, &name, &found.ty)?,
        ),
        (format!("{GREEN_DIR}/{name}.rs"), source),
    ]);
    let (written, same) = scratch.mirror(&extra)?;
    println!("mirrored the workspace: {written} files written, {same} unchanged");
    let result = scratch.steps(&name, file);
    if let Ok(summary) = &result {
        println!("\n{summary}");
    }
    let status_after = git_status(root)?;
    if status_after == status_before {
        println!("the checkout is untouched (`git status` as before)");
    } else {
        println!("warning: `git status` of the checkout changed during the run:\n{status_after}");
    }
    println!("check-green took {:.0} s", t0.elapsed().as_secs_f64());
    result.map(|_| ())
}

fn git_status(root: &Path) -> Result<String> {
    let out = Command::new("git")
        .args(["status", "--porcelain"])
        .current_dir(root)
        .output()
        .context("running git status")?;
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The scratch copy of the workspace and its target directory.
struct Scratch {
    root: PathBuf,
    workspace: PathBuf,
    target: PathBuf,
    cargo: std::ffi::OsString,
}

/// A command's wall-clock time and the peak resident memory of its largest process.
struct Measured {
    status: ExitStatus,
    time: Duration,
    peak_kb: Option<u64>,
}

impl Measured {
    fn describe(&self) -> String {
        let peak = match self.peak_kb {
            Some(kb) => format!("peak memory {:.2} GB", kb as f64 * 1024.0 / 1e9),
            None => "peak memory not measured (no /usr/bin/time)".into(),
        };
        format!("{:.0} s, {peak}", self.time.as_secs_f64())
    }
}

impl Scratch {
    fn new(root: &Path) -> Result<Scratch> {
        let checkout_target = std::env::var_os("CARGO_TARGET_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|| root.join("target"));
        let dir = checkout_target.join("check-green");
        let s = Scratch {
            root: root.to_path_buf(),
            workspace: dir.join("workspace"),
            target: dir.join("target"),
            cargo: std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()),
        };
        let release = checkout_target.join("release");
        if !s.target.exists() && release.exists() {
            // the dependencies' artifacts, so that the first run compiles only the
            // workspace's own crates
            std::fs::create_dir_all(&s.target)?;
            println!(
                "seeding {} from {} (once)",
                s.target.display(),
                release.display()
            );
            crate::run(
                Command::new("cp")
                    .args(["-a", "--reflink=auto"])
                    .arg(&release)
                    .arg(s.target.join("release")),
            )?;
        }
        std::fs::create_dir_all(&s.workspace)?;
        Ok(s)
    }

    /// The files of the checkout that git tracks or does not ignore, relative paths.
    fn listed(&self) -> Result<Vec<String>> {
        let out = Command::new("git")
            .args([
                "ls-files",
                "-z",
                "--cached",
                "--others",
                "--exclude-standard",
            ])
            .current_dir(&self.root)
            .output()
            .context("running git ls-files")?;
        if !out.status.success() {
            bail!("git ls-files failed in {}", self.root.display());
        }
        Ok(String::from_utf8(out.stdout)?
            .split('\0')
            .filter(|p| !p.is_empty() && self.root.join(p).is_file())
            .map(String::from)
            .collect())
    }

    /// Make the scratch workspace the checkout's files plus `extra` (path, contents),
    /// writing only what differs and removing what the checkout no longer has. Returns
    /// the numbers of files written and unchanged.
    fn mirror(&self, extra: &BTreeMap<String, String>) -> Result<(usize, usize)> {
        let listed = self.listed()?;
        let (mut written, mut same) = (0, 0);
        for path in &listed {
            if extra.contains_key(path) {
                continue;
            }
            let to = self.workspace.join(path);
            let generated = GENERATED.iter().any(|g| path.starts_with(g));
            let from = self.root.join(path);
            let differs = if generated {
                !to.exists()
            } else {
                std::fs::read(&from).ok() != std::fs::read(&to).ok()
            };
            if differs {
                if let Some(dir) = to.parent() {
                    std::fs::create_dir_all(dir)?;
                }
                std::fs::copy(&from, &to)
                    .with_context(|| format!("copying {} to {}", from.display(), to.display()))?;
                written += 1;
            } else {
                same += 1;
            }
        }
        for (path, contents) in extra {
            let to = self.workspace.join(path);
            if std::fs::read(&to).ok().as_deref() != Some(contents.as_bytes()) {
                std::fs::write(&to, contents)
                    .with_context(|| format!("writing {}", to.display()))?;
                written += 1;
            } else {
                same += 1;
            }
        }
        // what an earlier run added or the checkout has since removed
        let keep: std::collections::BTreeSet<&str> = listed
            .iter()
            .map(String::as_str)
            .chain(extra.keys().map(String::as_str))
            .collect();
        let mut stack = vec![self.workspace.clone()];
        while let Some(dir) = stack.pop() {
            for e in std::fs::read_dir(&dir)? {
                let path = e?.path();
                let rel = path
                    .strip_prefix(&self.workspace)?
                    .to_string_lossy()
                    .into_owned();
                if path.is_dir() {
                    stack.push(path);
                } else if !keep.contains(rel.as_str())
                    && !GENERATED.iter().any(|g| rel.starts_with(g))
                {
                    std::fs::remove_file(&path)?;
                }
            }
        }
        Ok((written, same))
    }

    /// The generated files as the checkout has them (when the scratch copy's, from an
    /// earlier run, do not build).
    fn reset_generated(&self) -> Result<()> {
        for dir in GENERATED {
            let _ = std::fs::remove_dir_all(self.workspace.join(dir));
        }
        for path in self.listed()? {
            if GENERATED.iter().any(|g| path.starts_with(g)) {
                let to = self.workspace.join(&path);
                std::fs::create_dir_all(to.parent().expect("a file in a directory"))?;
                std::fs::copy(self.root.join(&path), to)?;
            }
        }
        Ok(())
    }

    /// `cargo ARGS` in the scratch workspace, with the scratch target directory.
    fn cargo(&self, args: &[&str]) -> Command {
        let mut c = Command::new(&self.cargo);
        c.args(args)
            .current_dir(&self.workspace)
            .env("CARGO_TARGET_DIR", &self.target);
        c
    }

    /// The scratch copy's `xtask` binary with `args`.
    fn xtask(&self, args: &[&str]) -> Command {
        let mut c = Command::new(self.target.join("release").join("xtask"));
        c.args(args)
            .current_dir(&self.workspace)
            .env("CARGO_TARGET_DIR", &self.target);
        c
    }

    /// Everything after the mirror; returns the summary.
    fn steps(&self, name: &str, file: &Path) -> Result<String> {
        let mut summary = vec![format!(
            "check-green summary: `{name}` ({})",
            file.display()
        )];
        step("the Green's function compiles (cargo build --release -p kernel-gen)");
        let built = measured(&mut self.cargo(&["build", "--release", "-p", "kernel-gen"]))?;
        if !built.status.success() {
            bail!(
                "{} does not compile as {GREEN_DIR}/{name}.rs (the compiler's errors above, \
                 with the scratch copy's paths)",
                file.display()
            );
        }
        step("the generator (cargo build --release -p xtask)");
        let xtask = ["build", "--release", "-p", "xtask"];
        if !measured(&mut self.cargo(&xtask))?.status.success() {
            println!("the kernels an earlier run generated do not build: back to the checkout's");
            self.reset_generated()?;
            if !measured(&mut self.cargo(&xtask))?.status.success() {
                bail!("the scratch copy's xtask does not build (the errors above)");
            }
        }
        step("cargo xtask gen (the declaration checks and the size budget)");
        let (status, gen_out) = streamed(&mut self.xtask(&["gen"]))?;
        if !status.success() {
            bail!(
                "`cargo xtask gen` refused `{name}` (its message above); nothing of the \
                 checkout was written"
            );
        }
        summary.push(format!(
            "generated files of the family (bytes of each kernel, operation counts; the budget \
             is {} bytes per file):",
            crate::budget::FILE_BUDGET
        ));
        summary.extend(family_rows(&gen_out, name));
        summary.extend(
            gen_out
                .iter()
                .filter(|l| ["mod.rs ", "single.rs "].iter().any(|f| l.starts_with(f)))
                .cloned(),
        );
        step("the kernels and the solver (cargo build --release -p xtask)");
        let build = measured(&mut self.cargo(&xtask))?;
        if !build.status.success() {
            bail!("the generated kernels of `{name}` do not build (the errors above)");
        }
        summary.push(format!(
            "build of the kernels and the solver (cargo build --release -p xtask): {}",
            build.describe()
        ));
        step("measurements (cargo xtask check-green --registered)");
        let (status, measured_out) =
            streamed(&mut self.xtask(&["check-green", "--registered", name]))?;
        summary.extend(measured_out);
        let mut failed = Vec::new();
        if !status.success() {
            failed.push("the measurements (above)".to_string());
        }
        step("the integration tests that iterate the registry");
        let tests = [
            "test",
            "--release",
            "-p",
            "integration-tests",
            "-p",
            "xtask",
            "--test",
            "integration",
            "--test",
            "lanes",
            "--test",
            "lanes_single",
        ];
        let no_run: Vec<&str> = tests.iter().copied().chain(["--no-run"]).collect();
        let build = measured(&mut self.cargo(&no_run))?;
        if !build.status.success() {
            bail!("the integration tests do not build (the errors above)");
        }
        summary.push(format!(
            "build of the integration tests: {}",
            build.describe()
        ));
        // every binary runs, whatever fails in the one before
        let run: Vec<&str> = tests
            .iter()
            .copied()
            .chain(["--no-fail-fast", "--"])
            .chain(REGISTRY_TESTS)
            .collect();
        let t = Instant::now();
        let (_, test_out) = streamed(&mut self.cargo(&run))?;
        let (passed, failing) = test_results(&test_out);
        summary.push(format!(
            "integration tests ({}): {passed} passed, {} failed in {:.0} s{}",
            REGISTRY_TESTS.join(" "),
            failing.len(),
            t.elapsed().as_secs_f64(),
            if failing.is_empty() {
                String::new()
            } else {
                format!(": {}", failing.join(", "))
            }
        ));
        if !failing.is_empty() {
            failed.push(format!("{} integration tests", failing.len()));
        }
        let summary = summary.join("\n");
        if failed.is_empty() {
            Ok(summary)
        } else {
            println!("\n{summary}");
            bail!("`{name}` fails {}", failed.join(" and "))
        }
    }
}

fn step(what: &str) {
    println!("\n== {what}");
}

/// The rows of `cargo xtask gen`'s table for the family `name`: its file and kernels.
fn family_rows(gen_out: &[String], name: &str) -> Vec<String> {
    let header = format!("{name}.rs ");
    let mut rows = Vec::new();
    let mut inside = false;
    for l in gen_out {
        if !l.starts_with(' ') {
            inside = l.starts_with(&header);
        }
        if inside {
            rows.push(l.clone());
        }
    }
    rows
}

/// Passed tests and the names of the failed ones, from libtest's output.
fn test_results(out: &[String]) -> (usize, Vec<String>) {
    let mut passed = 0;
    let mut failed = Vec::new();
    for l in out {
        if let Some(rest) = l.strip_prefix("test ") {
            if rest.ends_with(" ... ok") {
                passed += 1;
            } else if let Some(n) = rest.strip_suffix(" ... FAILED") {
                failed.push(n.to_string());
            }
        }
    }
    (passed, failed)
}

/// Run `cmd` with its output shown; its stdout lines are also returned.
fn streamed(cmd: &mut Command) -> Result<(ExitStatus, Vec<String>)> {
    let mut child = cmd
        .stdout(Stdio::piped())
        .spawn()
        .with_context(|| format!("cannot start {cmd:?}"))?;
    let mut lines = Vec::new();
    if let Some(out) = child.stdout.take() {
        for line in BufReader::new(out).lines() {
            let line = line?;
            println!("{line}");
            lines.push(line);
        }
    }
    Ok((child.wait()?, lines))
}

/// Run `cmd` under `/usr/bin/time -v` (if there is one), its output shown.
fn measured(cmd: &mut Command) -> Result<Measured> {
    let time = Path::new("/usr/bin/time");
    let t0 = Instant::now();
    if !time.exists() {
        let status = cmd
            .status()
            .with_context(|| format!("cannot start {cmd:?}"))?;
        return Ok(Measured {
            status,
            time: t0.elapsed(),
            peak_kb: None,
        });
    }
    let report = std::env::temp_dir().join(format!("check-green-time-{}", std::process::id()));
    let mut wrapped = Command::new(time);
    wrapped
        .arg("-v")
        .arg("-o")
        .arg(&report)
        .arg(cmd.get_program())
        .args(cmd.get_args());
    if let Some(dir) = cmd.get_current_dir() {
        wrapped.current_dir(dir);
    }
    for (k, v) in cmd.get_envs() {
        match v {
            Some(v) => wrapped.env(k, v),
            None => wrapped.env_remove(k),
        };
    }
    let status = wrapped
        .status()
        .with_context(|| format!("cannot start {wrapped:?}"))?;
    let text = std::fs::read_to_string(&report).unwrap_or_default();
    let _ = std::fs::remove_file(&report);
    let peak_kb = text.lines().find_map(|l| {
        l.trim()
            .strip_prefix("Maximum resident set size (kbytes):")
            .and_then(|v| v.trim().parse().ok())
    });
    Ok(Measured {
        status,
        time: t0.elapsed(),
        peak_kb,
    })
}
