//! The size budget of generated files: what `cargo xtask gen` prints of every kernel
//! (operation counts, bytes of code) and each file, and the check that refuses, before
//! anything is written, a file too large to compile.

use anyhow::{bail, Result};
use kernel_gen::catalog::GeneratedFile;
use kernel_gen::physics::green::{Green, Visitor};
use std::fmt::Write;

/// The largest generated file `cargo xtask gen` writes, in bytes (4 MiB; the largest
/// today, `wall.rs`, is 1.42 MB).
///
/// Measured with `/usr/bin/time -v` (peak resident memory of the largest process) on
/// 2 cores. The kernels are `#[inline]` or generic over the lanes, so most of their
/// machine code is made in the crates that call them: `cargo build --release -p kernels`
/// peaks at 0.69 GB (16 s), while `cargo build --release
/// -p xtask` (the kernels with `f32`, the solver, the tests' library) peaks at 2.78 GB;
/// with one family more, the corner of docs/examples/corner.rs (`corner.rs` 0.77 MB and
/// its single-precision twin 0.16 MB, through `cargo xtask check-green`), at 3.31 GB:
/// 0.57 GB per MB of generated code. A family file at the budget, with its twin (a fifth
/// of it), adds 2.9 GB: 5.7 GB, within a machine of 8 GiB (8.6 GB).
pub const FILE_BUDGET: usize = 4 << 20;

/// One line per file (its size) and, below it, one per function it defines: bytes of
/// code and the operation counts of its branches.
pub fn table(files: &[GeneratedFile]) -> String {
    let mut out = String::new();
    for f in files {
        rows(&mut out, f, &f.functions());
    }
    out
}

/// The line of file `f` and those of its `functions`, in the order given.
fn rows(out: &mut String, f: &GeneratedFile, functions: &[(&str, usize)]) {
    let _ = writeln!(out, "{:<56} {:>9} bytes", f.name, f.contents.len());
    for (name, bytes) in functions {
        // the counts of `name` and of its labelled branches, `name (label)`
        let counts: Vec<String> = f
            .op_counts
            .iter()
            .filter_map(|(k, n)| match k.strip_prefix(name)? {
                "" => Some(format!("{n} flops")),
                label => Some(format!("{n} flops {}", label.strip_prefix(' ')?)),
            })
            .collect();
        let line = format!("  {name:<54} {bytes:>9} bytes  {}", counts.join(", "));
        let _ = writeln!(out, "{}", line.trim_end());
    }
}

/// The registered Green's functions without image terms: their kernels come from the
/// generic six-variable path.
fn generic() -> Vec<&'static str> {
    struct Generic(Vec<&'static str>);
    impl Visitor for Generic {
        fn visit<G: Green>(&mut self, g: &G) {
            if g.image_terms().is_none() {
                self.0.push(g.name());
            }
        }
    }
    let mut v = Generic(Vec::new());
    kernel_gen::physics::green::for_each(&mut v);
    v.0
}

/// How many of an over-budget file's functions its message lists, largest first.
pub const LISTED: usize = 8;

/// Fails if any file is over `budget`, naming each such file and its kernels (largest
/// first, with their bytes and operation counts) and saying what to declare for the
/// structured path.
pub fn check(files: &[GeneratedFile], budget: usize) -> Result<()> {
    let over: Vec<&GeneratedFile> = files.iter().filter(|f| f.contents.len() > budget).collect();
    if over.is_empty() {
        return Ok(());
    }
    let mut msg = format!(
        "nothing was written: generated files over the budget of {budget} bytes per file \
         (FILE_BUDGET in xtask/src/budget.rs: what builds within 8 GiB):\n"
    );
    for f in over {
        let mut by_size = f.functions();
        by_size.sort_by_key(|f| std::cmp::Reverse(f.1));
        rows(&mut msg, f, &by_size[..by_size.len().min(LISTED)]);
        if by_size.len() > LISTED {
            let _ = writeln!(msg, "  ({} smaller functions)", by_size.len() - LISTED);
        }
    }
    let generic = generic();
    let declare = "`Green::image_terms` with `Green::mirrors` (each term \
                   c w (n.y - offset)^p d^gamma J_ab(R) in its mirror's own frame; \
                   docs/generator.md, \"Adding a confinement\")";
    if generic.is_empty() {
        let _ = write!(
            msg,
            "Every confinement declares its image structure, {declare}: the kernels take the \
             structured path (Eq. 10) already and are this large because of their many image \
             terms."
        );
    } else {
        let names: Vec<String> = generic.iter().map(|n| format!("`{n}`")).collect();
        let _ = write!(
            msg,
            "Without image terms ({}), kernels come from the generic six-variable path, whose \
             jets of the whole G(x, y) grow with every term of the reflected field. Declare \
             the image structure, {declare}: the structured path (Eq. 10) then \
             differentiates one Stokeslet per image term.",
            names.join(", ")
        );
    }
    bail!(msg)
}
