//! `stokesian mobility`: the dense grand mobility as `.npy`, CSV and JSON equals the
//! library's bit for bit in every confinement; `--check`; the output's name and format.

use crate::common::*;
use std::fs;
use std::path::Path;
use stokesian::{Confinement, Moments, Overlap, Particle, System};

#[test]
fn mobility_npy_and_json_equal_the_library_bit_for_bit() {
    let dir = Dir::new("mobility");
    let p = dir.file("particles.csv", PARTICLES);
    for moments in [Moments::F, Moments::FT, Moments::FTS] {
        let want = system(WALL).mobility(moments);
        for ext in ["npy", "json"] {
            let out = dir.path(&format!("M_{}.{ext}", moments_name(moments)));
            let mut args = vec!["mobility"];
            args.extend(SYSTEM_ARGS);
            args.extend([
                "--moments",
                moments_name(moments),
                "--particles",
                s(&p),
                "--out",
                s(&out),
            ]);
            let o = run(&args);
            assert_ok(&o);
            let got = if ext == "npy" {
                read_npy(&out)
            } else {
                let (v, m) = read_json(&out);
                assert_eq!(v["n"], 3);
                assert_eq!(v["moments"], moments_name(moments));
                assert_eq!(v["dimension"], want.nrows());
                assert!(v["layout"]
                    .as_str()
                    .expect("layout string")
                    .starts_with("moment-major: U(3N), Omega(3N), E(5N"));
                m
            };
            assert_bit_equal(&got, &want, &format!("{ext} {}", moments_name(moments)));
        }
    }
    // only the outputs: no temporary files left over
    assert_eq!(dir.listing().len(), 1 + 6);
}

#[test]
fn mobility_every_confinement_matches_the_library() {
    let dir = Dir::new("confinements");
    let p = dir.file("particles.csv", PARTICLES);
    let cases: Vec<(Vec<&str>, Confinement)> = vec![
        (vec!["free"], Confinement::Free),
        (
            vec!["free-surface", "--boundary-height", "-0.5"],
            Confinement::FreeSurface { height: -0.5 },
        ),
        (
            vec!["interface", "--boundary-height", "0.1", "--lambda", "2.5"],
            Confinement::Interface {
                height: 0.1,
                lambda: 2.5,
            },
        ),
        (
            vec!["slit", "--boundary-height", "-0.5", "--gap", "60"],
            Confinement::Slit {
                height: -0.5,
                gap: 60.0,
            },
        ),
        (
            vec!["side_wall", "--param", "side=-2"],
            Confinement::SideWall { side: -2.0 },
        ),
    ];
    let mut covered: Vec<&str> = cases.iter().map(|(_, c)| c.name()).collect();
    covered.push(WALL.name()); // mobility_npy_and_json_equal_the_library_bit_for_bit
    covered.sort();
    let mut names = Confinement::NAMES.to_vec();
    names.sort();
    assert_eq!(covered, names, "a case for every registered confinement");
    for (k, (conf_args, conf)) in cases.into_iter().enumerate() {
        let out = dir.path(&format!("M{k}.npy"));
        let mut args = vec!["mobility", "--confinement"];
        args.extend(conf_args);
        args.extend([
            "--viscosity",
            "0.7",
            "--moments",
            "fts",
            "--particles",
            s(&p),
            "--out",
            s(&out),
        ]);
        let o = run(&args);
        assert_ok(&o);
        assert_bit_equal(
            &read_npy(&out),
            &system(conf).mobility(Moments::FTS),
            conf.name(),
        );
    }
}

#[test]
fn bad_output_name_is_rejected_before_any_work() {
    let dir = Dir::new("outname");
    let o = {
        let p = dir.file("particles.csv", PARTICLES);
        let out = dir.path("M.txt");
        run_mobility("wall", "F", &p, &out, &[])
    };
    assert_fails(
        &o,
        &["M.txt: the file name must end in .npy, .csv or .json"],
        &dir,
        &["particles.csv"],
    );
}

/// `--check` passes for valid input and refuses (no output) an overlapping pair whose
/// FTS matrix is indefinite (r = 1.0 a, see docs/verification.md).
#[test]
fn check_flag_reports_and_refuses_indefinite_matrices() {
    let dir = std::env::temp_dir().join(format!("stokesian-check-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("p.csv");
    std::fs::write(&csv, "x,y,z,radius\n0,0,3,1\n4,0,3,1\n").unwrap();
    let out = dir.join("M.npy");
    let run = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_stokesian"))
            .args([
                "mobility",
                "--confinement",
                "wall",
                "--moments",
                "FTS",
                "--check",
                "--particles",
            ])
            .arg(&csv)
            .arg("--out")
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };
    let ok = run(&[]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(String::from_utf8_lossy(&ok.stderr).contains("Cholesky succeeds"));
    std::fs::remove_file(&out).unwrap();
    std::fs::write(&csv, "x,y,z,radius\n0,0,3,1\n1,0,3,1\n").unwrap();
    let bad = run(&["--allow-overlap"]);
    assert!(!bad.status.success());
    let msg = String::from_utf8_lossy(&bad.stderr);
    assert!(
        msg.contains("not symmetric positive definite") && msg.contains("Cholesky fails"),
        "{msg}"
    );
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `.csv` writes the matrix one row per line (no header), the `.npy`'s numbers bit for
/// bit; the extension chooses the format in any case; no extension, or another one, is
/// refused before any work (here before the missing particles file is noticed).
#[test]
fn mobility_csv_equals_the_npy_and_other_extensions_are_refused() {
    let dir = Dir::new("mobility-formats");
    let p = dir.file("particles.csv", PARTICLES);
    let args = |particles: &Path, out: &Path| {
        let mut a = vec!["mobility"];
        a.extend(SYSTEM_ARGS);
        a.extend([
            "--moments",
            "FTS",
            "--particles",
            s(particles),
            "--out",
            s(out),
        ]);
        run(&a)
    };
    let want = system(WALL).mobility(Moments::FTS);
    for name in ["M.npy", "M.csv", "M2.CSV"] {
        assert_ok(&args(&p, &dir.path(name)));
    }
    let npy = read_npy(&dir.path("M.npy"));
    assert_bit_equal(&npy, &want, "npy");
    assert_bit_equal(&read_csv_matrix(&dir.path("M.csv")), &want, "csv");
    assert_eq!(
        fs::read(dir.path("M.csv")).unwrap(),
        fs::read(dir.path("M2.CSV")).unwrap()
    );
    for name in ["M.npy", "M.csv", "M2.CSV"] {
        fs::remove_file(dir.path(name)).unwrap();
    }
    for name in ["M.txt", "M", "M.npz"] {
        assert_fails(
            &args(&dir.path("nowhere.csv"), &dir.path(name)),
            &[&format!(
                "--out {}: the file name must end in .npy, .csv or .json",
                s(&dir.path(name))
            )],
            &dir,
            &["particles.csv"],
        );
    }
}

/// `--overlap rpy`: overlapping spheres, one of them cutting the wall, give the library's
/// RPY mobility bit for bit, symmetric positive definite (`--check`); at FTS the
/// overlap forms do not exist and the command says so; `--allow-overlap` and
/// `--overlap` together are refused.
#[test]
fn overlap_rpy_gives_the_library_matrix_and_refuses_fts() {
    let dir = Dir::new("mobility-overlap-rpy");
    let csv = dir.file("p.csv", "x,y,z,radius\n0,0,0.8,1\n1.2,0,1.5,0.7\n");
    let out = dir.path("M.npy");
    let run = |moments: &str, extra: &[&str]| {
        let mut a = vec!["mobility", "--confinement", "wall", "--moments", moments];
        a.extend(["--check", "--particles", s(&csv), "--out", s(&out)]);
        a.extend(extra);
        run(&a)
    };
    let ok = run("FT", &["--overlap", "rpy"]);
    assert_ok(&ok);
    assert!(stderr(&ok).contains("Cholesky succeeds"), "{}", stderr(&ok));
    let ps = vec![
        Particle {
            x: [0.0, 0.0, 0.8],
            a: 1.0,
        },
        Particle {
            x: [1.2, 0.0, 1.5],
            a: 0.7,
        },
    ];
    let want = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, Overlap::Rpy)
        .unwrap()
        .mobility(Moments::FT);
    assert_bit_equal(&read_npy(&out), &want, "--overlap rpy");
    std::fs::remove_file(&out).unwrap();
    let fts = run("FTS", &["--overlap", "rpy"]);
    assert_fails(
        &fts,
        &["particles 0 and 1 overlap", "not the stresslets (FTS)"],
        &dir,
        &["p.csv"],
    );
    let both = run("F", &["--overlap", "rpy", "--allow-overlap"]);
    assert!(!both.status.success());
    assert!(
        stderr(&both).contains("cannot be used with"),
        "{}",
        stderr(&both)
    );
}
