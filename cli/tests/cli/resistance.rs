//! `stokesian resistance` and lubrication (`velocity --lubrication`,
//! `--pair-tolerance`): Eq. 19's resistance equals the library's bit for bit.

use crate::common::*;
use std::fs;
use std::path::Path;
use stokesian::Moments;

/// `resistance` writes Eq. 19's FT and FTS resistance (equal to the library's, bit for
/// bit) and `velocity --lubrication` solves its force-torque rows (`E_inf = 0`); F has no
/// lubrication and refuses with a clear message.
#[test]
fn resistance_and_lubricated_velocity() {
    use stokesian::{Confinement, Lubrication, Moments, Particle, System};
    let dir = std::env::temp_dir().join(format!("stokesian-lub-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("p.csv");
    std::fs::write(&csv, "x,y,z,radius\n0,0,1.001,1\n2.0005,0,1.001,1\n").unwrap();
    let forces = dir.join("f.csv");
    std::fs::write(&forces, "fx,fy,fz,tx,ty,tz\n0,0,-1,0,0,0\n0.5,0,0,0,0,0\n").unwrap();
    let f = [0.0, 0.0, -1.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let bin = env!("CARGO_BIN_EXE_stokesian");
    let run_ok = |args: &[&std::ffi::OsStr]| {
        let o = std::process::Command::new(bin).args(args).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        o
    };
    let ps = vec![
        Particle {
            x: [0.0, 0.0, 1.001],
            a: 1.0,
        },
        Particle {
            x: [2.0005, 0.0, 1.001],
            a: 1.0,
        },
    ];
    let s = System::new(Confinement::Wall { height: 0.0 }, 1.0, ps, false).unwrap();
    for (moments, name) in [(Moments::FT, "FT"), (Moments::FTS, "FTS")] {
        let system: [&std::ffi::OsStr; 7] = [
            "--confinement".as_ref(),
            "wall".as_ref(),
            "--moments".as_ref(),
            name.as_ref(),
            "--particles".as_ref(),
            csv.as_os_str(),
            "--out".as_ref(),
        ];
        let r_out = dir.join(format!("R-{name}.json"));
        let mut args = vec!["resistance".as_ref()];
        args.extend_from_slice(&system);
        args.push(r_out.as_os_str());
        run_ok(&args);
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&r_out).unwrap()).unwrap();
        let r = s.resistance(moments, &Lubrication::default()).unwrap();
        assert_eq!(r.nrows(), 2 * moments.per_particle());
        for i in 0..r.nrows() {
            for j in 0..r.ncols() {
                assert_eq!(v["matrix"][i][j].as_f64().unwrap(), r[(i, j)]);
            }
        }
        let u_out = dir.join(format!("U-{name}.csv"));
        let mut args = vec!["velocity".as_ref(), "--lubrication".as_ref()];
        args.extend_from_slice(&["--forces".as_ref(), forces.as_os_str()]);
        args.extend_from_slice(&system);
        args.push(u_out.as_os_str());
        let o = run_ok(&args);
        assert!(String::from_utf8_lossy(&o.stderr).contains("condition estimate of R"));
        let rows: Vec<Vec<f64>> = std::fs::read_to_string(&u_out)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        // R_{FL, U Omega} u = f, checked with the library's matrix
        let u = nalgebra::DVector::from_fn(12, |k, _| rows[(k % 6) / 3][3 * (k / 6) + k % 3]);
        let ru = r.view((0, 0), (12, 12)) * u;
        for k in 0..12 {
            assert!(
                (ru[k] - f[k]).abs() < 1e-9,
                "{name} row {k}: {} vs {}",
                ru[k],
                f[k]
            );
        }
    }
    // F has no lubrication
    let forces_f = dir.join("f3.csv");
    std::fs::write(&forces_f, "fx,fy,fz\n0,0,-1\n0.5,0,0\n").unwrap();
    let o = std::process::Command::new(bin)
        .args([
            "velocity",
            "--confinement",
            "wall",
            "--moments",
            "F",
            "--lubrication",
        ])
        .arg("--particles")
        .arg(&csv)
        .arg("--forces")
        .arg(&forces_f)
        .arg("--out")
        .arg(dir.join("U3.csv"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("use FT or FTS"));
    assert!(!dir.join("U3.csv").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--pair-tolerance` reaches the library: `resistance` equals
/// `System::resistance` with that tolerance bit for bit (0: every pair corrected; inf:
/// none, which differs where the spheres are close); a negative or NaN tolerance, the
/// option on `mobility`, or on `velocity` without `--lubrication` fail with a message.
#[test]
fn pair_tolerance_option() {
    use stokesian::Lubrication;
    let dir = Dir::new("pair-tolerance");
    let p = dir.file("particles.csv", PARTICLES);
    let resistance = |tol: &str, out: &Path| {
        let mut args = vec!["resistance"];
        args.extend(SYSTEM_ARGS);
        let out = s(out);
        args.extend(["--moments", "FT", "--particles", s(&p), "--out", out]);
        args.extend(["--pair-tolerance", tol]);
        run(&args)
    };
    let mut got = Vec::new();
    for (tol, value) in [("0", 0.0), ("1e-3", 1e-3), ("inf", f64::INFINITY)] {
        let out = dir.path(&format!("R-{tol}.npy"));
        assert_ok(&resistance(tol, &out));
        let lub = Lubrication::default().with_pair_tolerance(value);
        let want = system(WALL).resistance(Moments::FT, &lub).unwrap();
        let m = read_npy(&out);
        assert_bit_equal(&m, &want, &format!("--pair-tolerance {tol}"));
        got.push(m);
    }
    // the closest pair (s' = 2.56) is corrected at 1e-3 (out to s' = 9.3), not at inf;
    // the relative change is of the order of the correction there (about 1e-2)
    assert!((&got[1] - &got[2]).norm() > 1e-3 * got[2].norm());
    for tol in ["0", "1e-3", "inf"] {
        fs::remove_file(dir.path(&format!("R-{tol}.npy"))).unwrap();
    }
    for tol in ["-1", "nan"] {
        let o = resistance(tol, &dir.path("R.npy"));
        assert_fails(
            &o,
            &[
                "--pair-tolerance",
                "the pair tolerance must be a number >= 0",
            ],
            &dir,
            &["particles.csv"],
        );
    }
    let o = mobility_fails(&dir, PARTICLES, &["--pair-tolerance", "1e-3"]);
    assert_fails(
        &o,
        &["--pair-tolerance does not apply to `mobility`"],
        &dir,
        &["particles.csv"],
    );
    let f = dir.file("forces.csv", FORCES);
    let out = dir.path("U.csv");
    let mut args = vec!["velocity"];
    args.extend(SYSTEM_ARGS);
    args.extend(["--moments", "FT", "--particles", s(&p), "--forces", s(&f)]);
    args.extend(["--out", s(&out), "--pair-tolerance", "1e-3"]);
    assert_fails(
        &run(&args),
        &["--lubrication"],
        &dir,
        &["forces.csv", "particles.csv"],
    );
}

/// `resistance` writes `.npy`, `.csv` (one row per line, no header) and `.json` with the
/// same numbers, bit for bit; another extension is refused before any work.
#[test]
fn resistance_in_every_format() {
    use stokesian::Lubrication;
    let dir = Dir::new("resistance-formats");
    let p = dir.file("particles.csv", PARTICLES);
    let resistance = |out: &Path| {
        let mut args = vec!["resistance"];
        args.extend(SYSTEM_ARGS);
        args.extend(["--moments", "FT", "--particles", s(&p), "--out", s(out)]);
        run(&args)
    };
    let want = system(WALL)
        .resistance(Moments::FT, &Lubrication::default())
        .unwrap();
    for name in ["R.npy", "R.csv", "R.json"] {
        assert_ok(&resistance(&dir.path(name)));
    }
    assert_bit_equal(&read_npy(&dir.path("R.npy")), &want, "npy");
    assert_bit_equal(&read_csv_matrix(&dir.path("R.csv")), &want, "csv");
    assert_bit_equal(&read_json(&dir.path("R.json")).1, &want, "json");
    for name in ["R.npy", "R.csv", "R.json"] {
        fs::remove_file(dir.path(name)).unwrap();
    }
    assert_fails(
        &resistance(&dir.path("R.txt")),
        &["R.txt: the file name must end in .npy, .csv or .json"],
        &dir,
        &["particles.csv"],
    );
}
