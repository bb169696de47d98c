//! The tasks behind `cargo xtask` (the command is `src/main.rs`): the size budget of
//! generated files ([`budget`]), trying a Green's function ([`check_green`]), the report
//! ([`report`]), the performance table ([`bench`]) and the sphere-plane limit of two
//! spheres ([`wall_limit`]). A library so that its tests (`tests/`) link what `cargo
//! xtask` compiled instead of compiling it again: the report instantiates the lane
//! kernels of every confinement.

use anyhow::{bail, Context, Result};
use kernel_gen::catalog::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

pub mod bench;
pub mod budget;
pub mod check_green;
pub mod fmm;
pub mod report;
pub mod wall_limit;

/// The workspace's root directory (the parent of `xtask/`).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace root")
        .to_path_buf()
}

/// Names of the registered Green's functions: the confinements, then the building blocks
/// (which scenes may name too).
pub fn registered() -> Vec<&'static str> {
    struct Names(Vec<&'static str>);
    impl kernel_gen::physics::green::Visitor for Names {
        fn visit<G: kernel_gen::physics::green::Green>(&mut self, g: &G) {
            self.0.push(g.name());
        }
    }
    let mut n = Names(Vec::new());
    kernel_gen::physics::green::for_each(&mut n);
    kernel_gen::physics::green::for_each_building_block(&mut n);
    n.0
}

/// Run `cmd`, failing with its name if it fails.
pub fn run(cmd: &mut Command) -> Result<()> {
    let status = cmd
        .status()
        .with_context(|| format!("cannot start {cmd:?}"))?;
    if !status.success() {
        bail!("{cmd:?} failed ({status})");
    }
    Ok(())
}

/// The scene of the file at `path`, parsed against the registered confinements.
pub fn read_scene(path: &Path) -> Result<Scene> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading scene {}", path.display()))?;
    Ok(Scene::parse(
        &path.display().to_string(),
        &text,
        &registered(),
    )?)
}

/// Every scene in `scenes/`, in file-name order.
pub fn scenes() -> Result<Vec<Scene>> {
    let dir = root().join("scenes");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .map(|e| e.map(|e| e.path()))
        .collect::<std::io::Result<_>>()?;
    paths.retain(|p| p.extension().is_some_and(|e| e == "toml"));
    paths.sort();
    paths.iter().map(|p| read_scene(p)).collect()
}
