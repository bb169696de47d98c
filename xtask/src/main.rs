//! `cargo xtask gen [--check]`: regenerate the committed kernels in
//! `kernels/src/generated/`, or (with `--check`) fail when they are stale.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace root")
        .to_path_buf()
}

fn usage() -> &'static str {
    "usage: cargo xtask gen [--check]\n\
     \n\
     gen          regenerate kernels/src/generated/ from kernel-gen\n\
     gen --check  exit non-zero if the committed kernels differ from what the generator produces"
}

fn gen(check: bool) -> Result<()> {
    let t0 = Instant::now();
    let files = kernel_gen::catalog::generate();
    let elapsed = t0.elapsed();
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
    for f in &files {
        for (name, n) in &f.op_counts {
            println!("{name:<36} {n:>8} flops");
        }
    }
    println!(
        "generated {} files in {:.2} s",
        files.len(),
        elapsed.as_secs_f64()
    );
    if check {
        if !stale.is_empty() {
            bail!(
                "the committed kernels are stale: {} differ from what the generator produces.\n\
                 Run `cargo xtask gen` and commit kernels/src/generated/.",
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
        ["help"] | ["--help"] | ["-h"] | [] => {
            println!("{}", usage());
            Ok(())
        }
        _ => bail!("unknown arguments {args:?}\n{}", usage()),
    }
}
