//! `stokesian velocity`: velocities equal the library's mobility times the forces (F,
//! FT, both precisions) and the Schur complement at FTS (with an imposed strain); the
//! forces file's errors; `.npy` output with the CSV's columns; `--moments` defaults to F.

use crate::common::*;
use nalgebra::DVector;
use std::fs;
use std::path::Path;
use std::process::Output;
use stokesian::Moments;

#[test]
fn velocity_f_and_ft_equal_mobility_times_forces() {
    let dir = Dir::new("velocity");
    let p = dir.file("particles.csv", PARTICLES);
    let f3: String = std::iter::once("fx,fy,fz".to_string())
        .chain(
            forces()
                .iter()
                .map(|r| format!("{:?},{:?},{:?}", r[0], r[1], r[2])),
        )
        .collect::<Vec<_>>()
        .join("\n");
    let f3 = dir.file("forces3.csv", &f3);
    let f6 = dir.file("forces6.csv", FORCES);
    // single precision: f32 lanes, 2e-6 of the largest velocity (as the library's
    // `tests/single_precision.rs`: 2e-6 per pair at worst)
    for (precision, tol) in [("double", 1e-14), ("single", 2e-6)] {
        for (moments, file, k, header) in [
            (Moments::F, &f3, 3, "ux,uy,uz"),
            (Moments::FT, &f6, 6, "ux,uy,uz,wx,wy,wz"),
        ] {
            let out = dir.path(&format!("U_{}_{precision}.csv", moments_name(moments)));
            let mut args = vec!["velocity"];
            args.extend(SYSTEM_ARGS);
            args.extend([
                "--moments",
                moments_name(moments),
                "--particles",
                s(&p),
                "--forces",
                s(file),
                "--precision",
                precision,
                "--out",
                s(&out),
            ]);
            let o = run(&args);
            assert_ok(&o);
            let rows = read_csv(&out, header);
            assert_eq!(rows.len(), 3);
            let got = velocity_vector(&rows);
            let m = system(WALL).mobility(moments);
            let want = &m * DVector::from_vec(force_vector(k));
            let e = rel_err(&got, want.as_slice());
            assert!(
                e <= tol,
                "{} {precision}: relative error {e:e}",
                moments_name(moments)
            );
        }
    }
    // refused where it does not apply
    let out = dir.path("U_refused.csv");
    let mut args = vec!["velocity"];
    args.extend(SYSTEM_ARGS);
    args.extend([
        "--moments",
        "FT",
        "--lubrication",
        "--precision",
        "single",
        "--particles",
        s(&p),
        "--forces",
        s(&f6),
        "--out",
        s(&out),
    ]);
    let o = run(&args);
    assert!(
        !o.status.success() && stderr(&o).contains("--precision single"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
}

/// `(U, Omega)` of an FTS system by the explicit Schur complement
/// `(M_11 - M_12 M_22^{-1} M_21) x - M_12 M_22^{-1} e_inf`, with LU.
fn schur_velocities(e_inf: [f64; 5]) -> Vec<f64> {
    let m = system(WALL).mobility(Moments::FTS);
    let n = 3;
    let m11 = m.view((0, 0), (6 * n, 6 * n)).into_owned();
    let m12 = m.view((0, 6 * n), (6 * n, 5 * n)).into_owned();
    let m21 = m.view((6 * n, 0), (5 * n, 6 * n)).into_owned();
    let m22 = m.view((6 * n, 6 * n), (5 * n, 5 * n)).into_owned();
    let lu = m22.lu();
    let m22_inv_m21 = lu.solve(&m21).expect("M_ES invertible");
    let schur = &m11 - &m12 * m22_inv_m21;
    let e = DVector::from_fn(5 * n, |i, _| e_inf[i % 5]);
    let shift = &m12 * lu.solve(&e).expect("M_ES invertible");
    let u = schur * DVector::from_vec(force_vector(6)) - shift;
    u.as_slice().to_vec()
}

fn run_fts(dir: &Dir, name: &str, extra: &[&str]) -> Vec<f64> {
    let p = dir.file("particles.csv", PARTICLES);
    let f = dir.file("forces.csv", FORCES);
    let out = dir.path(name);
    let mut args = vec!["velocity"];
    args.extend(SYSTEM_ARGS);
    args.extend([
        "--moments",
        "FTS",
        "--particles",
        s(&p),
        "--forces",
        s(&f),
        "--out",
        s(&out),
    ]);
    args.extend(extra);
    let o = run(&args);
    assert_ok(&o);
    velocity_vector(&read_csv(&out, "ux,uy,uz,wx,wy,wz"))
}

#[test]
fn velocity_fts_zero_strain_equals_schur_complement() {
    let dir = Dir::new("fts");
    let got = run_fts(&dir, "U.csv", &[]);
    let want = schur_velocities([0.0; 5]);
    let e = rel_err(&got, &want);
    assert!(e <= 1e-12, "relative error {e:e}");
    // the stresslets matter: FTS differs from FT
    let ft = system(WALL).mobility(Moments::FT) * DVector::from_vec(force_vector(6));
    assert!(rel_err(&got, ft.as_slice()) > 1e-4);
}

#[test]
fn velocity_fts_with_imposed_strain_in_both_formats() {
    let dir = Dir::new("strain");
    // uniaxial extension along z: E = diag(-1, -1, 2) / 2, plus a shear part E12
    let cart = run_fts(&dir, "U9.csv", &["--strain", "-0.5,0.3,0,0.3,-0.5,0,0,0,1"]);
    // the same in the orthonormal basis: E_m = B_m : E
    let s2 = std::f64::consts::SQRT_2;
    let b = [0.6 / s2, 0.0, 0.0, 0.0, 6f64.sqrt() / 2.0];
    let basis_arg = format!("{:?},{:?},{:?},{:?},{:?}", b[0], b[1], b[2], b[3], b[4]);
    let basis = run_fts(&dir, "U5.csv", &["--strain", &basis_arg]);
    let want = schur_velocities(b);
    assert!(
        rel_err(&cart, &want) <= 1e-12,
        "{:e}",
        rel_err(&cart, &want)
    );
    assert!(
        rel_err(&basis, &want) <= 1e-12,
        "{:e}",
        rel_err(&basis, &want)
    );
    assert!(rel_err(&want, &schur_velocities([0.0; 5])) > 1e-3);
}

#[test]
fn forces_row_count_mismatch() {
    let dir = Dir::new("rows");
    let p = dir.file("particles.csv", PARTICLES);
    let f = dir.file(
        "forces.csv",
        "fx,fy,fz,tx,ty,tz\n1,0,0,0,0,0\n0,1,0,0,0,0\n",
    );
    let out = dir.path("U.csv");
    let o = run(&[
        "velocity",
        "--confinement",
        "wall",
        "--moments",
        "FT",
        "--particles",
        s(&p),
        "--forces",
        s(&f),
        "--out",
        s(&out),
    ]);
    assert_fails(
        &o,
        &[
            "forces.csv: 2 rows of forces for the 3 particles of",
            "particles.csv",
        ],
        &dir,
        &["forces.csv", "particles.csv"],
    );
}

#[test]
fn forces_non_finite_and_bad_strain() {
    let dir = Dir::new("forces");
    let p = dir.file("particles.csv", PARTICLES);
    let f = dir.file(
        "forces.csv",
        "fx,fy,fz,tx,ty,tz\n1,0,0,0,0,0\n0,1,0,0,inf,0\n0,0,1,0,0,0\n",
    );
    let out = dir.path("U.csv");
    let base = [
        "velocity",
        "--confinement",
        "wall",
        "--moments",
        "FTS",
        "--particles",
        s(&p),
        "--forces",
        s(&f),
        "--out",
        s(&out),
    ];
    let o = run(&base);
    assert_fails(
        &o,
        &["forces.csv line 3 (particle 1): ty = inf is not a finite number"],
        &dir,
        &["forces.csv", "particles.csv"],
    );
    dir.file("forces.csv", FORCES);
    let mut args = base.to_vec();
    args.extend(["--strain", "0,1,0,0,0,0,0,0,0"]);
    assert_fails(
        &run(&args),
        &["--strain 0,1,0,0,0,0,0,0,0: not symmetric: E12 = 1 but E21 = 0"],
        &dir,
        &["forces.csv", "particles.csv"],
    );
    let mut args = base.to_vec();
    args.extend(["--strain", "1,0,0,0,1,0,0,0,1"]);
    assert_fails(
        &run(&args),
        &["not traceless"],
        &dir,
        &["forces.csv", "particles.csv"],
    );
}

/// Run `velocity` on the three spheres and `forces` with `extra` options, writing `out`.
fn velocity(dir: &Dir, forces: &str, out: &Path, extra: &[&str]) -> Output {
    let p = dir.file("particles.csv", PARTICLES);
    let f = dir.file("forces.csv", forces);
    let mut args = vec!["velocity"];
    args.extend(SYSTEM_ARGS);
    args.extend(["--particles", s(&p), "--forces", s(&f), "--out", s(out)]);
    args.extend(extra);
    run(&args)
}

/// `.npy`: a float64 array of shape (N, 3) at F, (N, 6) at FT and FTS, in C order, the
/// CSV's columns and numbers bit for bit; the extension chooses the format in any case.
#[test]
fn velocity_npy_has_the_csv_columns_bit_for_bit() {
    let dir = Dir::new("velocity-npy");
    let f3 = "fx,fy,fz\n1,0.5,-0.25\n0,1,0.3\n-0.4,0,-1\n";
    for (moments, forces, header, extension) in [
        ("F", f3, "ux,uy,uz", "npy"),
        ("FT", FORCES, "ux,uy,uz,wx,wy,wz", "NPY"),
        ("FTS", FORCES, "ux,uy,uz,wx,wy,wz", "npy"),
    ] {
        let (csv, npy) = (dir.path("U.csv"), dir.path(&format!("U.{extension}")));
        assert_ok(&velocity(&dir, forces, &csv, &["--moments", moments]));
        assert_ok(&velocity(&dir, forces, &npy, &["--moments", moments]));
        let want = read_csv(&csv, header);
        let got = read_npy(&npy);
        assert_eq!(got.shape(), (3, header.split(',').count()), "{moments}");
        let bytes = fs::read(&npy).unwrap();
        assert!(
            String::from_utf8_lossy(&bytes[..128]).contains("'fortran_order': False"),
            "{moments}: C order"
        );
        for (a, row) in want.iter().enumerate() {
            for (k, w) in row.iter().enumerate() {
                assert_eq!(got[(a, k)].to_bits(), w.to_bits(), "{moments} ({a}, {k})");
            }
        }
        fs::remove_file(&csv).unwrap();
        fs::remove_file(&npy).unwrap();
    }
}

/// Without `--moments` the truncation is F (as for `brownian`): the same bytes as
/// `--moments F`.
#[test]
fn velocity_moments_defaults_to_f() {
    let dir = Dir::new("velocity-default");
    let f3 = "fx,fy,fz\n1,0.5,-0.25\n0,1,0.3\n-0.4,0,-1\n";
    let (default, f) = (dir.path("U-default.csv"), dir.path("U-F.csv"));
    assert_ok(&velocity(&dir, f3, &default, &[]));
    assert_ok(&velocity(&dir, f3, &f, &["--moments", "F"]));
    assert_eq!(fs::read(&default).unwrap(), fs::read(&f).unwrap());
    read_csv(&default, "ux,uy,uz");
    // torques need FT or FTS, named as such
    fs::remove_file(&default).unwrap();
    fs::remove_file(&f).unwrap();
    assert_fails(
        &velocity(&dir, FORCES, &default, &[]),
        &["tx, ty, tz", "--moments FT or FTS"],
        &dir,
        &["forces.csv", "particles.csv"],
    );
}

/// An output that is neither `.csv` nor `.npy` (JSON is the matrices') is refused before
/// any work, the accepted extensions listed, and nothing is written.
#[test]
fn velocity_refuses_other_extensions() {
    let dir = Dir::new("velocity-out");
    for name in ["U.txt", "U.json", "U"] {
        let out = dir.path(name);
        assert_fails(
            &velocity(&dir, FORCES, &out, &["--moments", "FT"]),
            &[&format!(
                "--out {}: the file name must end in .csv or .npy",
                s(&out)
            )],
            &dir,
            &["forces.csv", "particles.csv"],
        );
    }
}

/// `--fmm EPS`: the library's fast product (`System::with_fmm`) bit for bit, within EPS
/// of the direct product for 400 spheres in a layer above the wall (F and FT); refused
/// with --lubrication and for a tolerance outside [1e-10, 1e-3].
#[test]
fn velocity_fmm_is_the_librarys_fast_product() {
    let dir = Dir::new("velocity_fmm");
    let n = 400;
    // a square lattice of unit spheres 3 apart, heights 1.5 to 3.5 above the wall
    let ps: Vec<stokesian::Particle> = (0..n)
        .map(|i| stokesian::Particle {
            x: [
                3.0 * (i % 20) as f64,
                3.0 * (i / 20) as f64,
                0.25 + 1.5 + (i % 7) as f64 / 3.0,
            ],
            a: 1.0,
        })
        .collect();
    let particles: String = std::iter::once("x,y,z,radius".to_string())
        .chain(
            ps.iter()
                .map(|p| format!("{:?},{:?},{:?},1.0", p.x[0], p.x[1], p.x[2])),
        )
        .collect::<Vec<_>>()
        .join("\n");
    let p = dir.file("particles.csv", &particles);
    let forces: Vec<f64> = (0..6 * n)
        .map(|k| ((k * 37 % 101) as f64 - 50.0) / 50.0)
        .collect();
    let f6: String = std::iter::once("fx,fy,fz,tx,ty,tz".to_string())
        .chain((0..n).map(|a| {
            let r: Vec<String> = (0..6).map(|c| format!("{:?}", forces[6 * a + c])).collect();
            r.join(",")
        }))
        .collect::<Vec<_>>()
        .join("\n");
    let f6 = dir.file("forces6.csv", &f6);
    let system = stokesian::System::new(WALL, ETA, ps, false).unwrap();
    for (moments, header) in [(Moments::F, "ux,uy,uz"), (Moments::FT, "ux,uy,uz,wx,wy,wz")] {
        let k = moments.per_particle();
        let out = dir.path(&format!("U_{}.csv", moments_name(moments)));
        let mut args = vec!["velocity"];
        args.extend(SYSTEM_ARGS);
        args.extend([
            "--moments",
            moments_name(moments),
            "--particles",
            s(&p),
            "--forces",
            s(&f6),
            "--fmm",
            "1e-6",
            "--out",
            s(&out),
        ]);
        if moments == Moments::F {
            // the torque columns refused at F: the forces alone
            let f3: String = std::iter::once("fx,fy,fz".to_string())
                .chain((0..n).map(|a| {
                    let r: Vec<String> =
                        (0..3).map(|c| format!("{:?}", forces[6 * a + c])).collect();
                    r.join(",")
                }))
                .collect::<Vec<_>>()
                .join("\n");
            let f3 = dir.file("forces3.csv", &f3);
            let at = args.iter().position(|a| *a == s(&f6)).unwrap();
            args[at] = s(&f3);
            assert_ok(&run(&args));
        } else {
            assert_ok(&run(&args));
        }
        let got = velocity_vector(&read_csv(&out, header));
        // the library's layout: all forces (particle-major), then all torques
        let mut x = vec![0.0; k * n];
        for part in 0..k / 3 {
            for a in 0..n {
                for comp in 0..3 {
                    x[part * 3 * n + 3 * a + comp] = forces[6 * a + 3 * part + comp];
                }
            }
        }
        let fast = system.clone().with_fmm(1e-6).unwrap().apply(moments, &x);
        assert!(
            got.iter()
                .zip(&fast)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{}: not the library's fast product",
            moments_name(moments)
        );
        let direct = system.apply(moments, &x);
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let d: Vec<f64> = got.iter().zip(&direct).map(|(a, b)| a - b).collect();
        let e = norm(&d) / norm(&direct);
        assert!(e <= 1e-6, "{}: {e:e}", moments_name(moments));
    }
    let out = dir.path("U_refused.csv");
    for (extra, needle) in [
        (
            &["--moments", "FT", "--lubrication", "--fmm", "1e-6"][..],
            "--fmm",
        ),
        (&["--moments", "FT", "--fmm", "1e-2"][..], "[1e-10, 1e-3]"),
    ] {
        let mut args = vec!["velocity"];
        args.extend(SYSTEM_ARGS);
        args.extend(["--particles", s(&p), "--forces", s(&f6), "--out", s(&out)]);
        args.extend(extra);
        let o = run(&args);
        assert!(
            !o.status.success() && stderr(&o).contains(needle),
            "{}",
            stderr(&o)
        );
        assert!(!out.exists());
    }
}
