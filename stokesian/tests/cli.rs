//! End-to-end tests of the `stokesian` command: outputs equal the library to full
//! precision, and every bad input gets a clear message, a non-zero exit status and no
//! output file.

use nalgebra::{DMatrix, DVector};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use stokesian::{Confinement, Moments, Particle, System};

/// A fresh directory under the system's temporary directory, removed on drop.
struct Dir(PathBuf);

impl Dir {
    fn new(name: &str) -> Dir {
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let k = COUNT.fetch_add(1, Ordering::SeqCst);
        let path =
            std::env::temp_dir().join(format!("stokesian-cli-{}-{k}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&path);
        fs::create_dir_all(&path).expect("create temporary directory");
        Dir(path)
    }

    fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        fs::write(&p, text).expect("write input file");
        p
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// File names in the directory, sorted.
    fn listing(&self) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(&self.0)
            .expect("read temporary directory")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stokesian"))
        .args(args)
        .output()
        .expect("run the stokesian binary")
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_ok(o: &Output) {
    assert!(o.status.success(), "command failed: {}", stderr(o));
}

/// The command failed, its message contains every `needle`, and the directory holds
/// exactly the input files (no output, no temporary file).
fn assert_fails(o: &Output, needles: &[&str], dir: &Dir, inputs: &[&str]) {
    assert!(!o.status.success(), "command must fail");
    assert_ne!(o.status.code(), Some(101), "the command panicked");
    let msg = stderr(o);
    assert!(!msg.contains("panicked"), "the command panicked: {msg}");
    for n in needles {
        assert!(msg.contains(n), "stderr {msg:?} does not contain {n:?}");
    }
    let mut expected: Vec<String> = inputs.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(dir.listing(), expected, "files left behind");
}

/// Three spheres of unequal radii above a wall at z = 0.25.
const PARTICLES: &str = "x,y,z,radius\n0,0,1.5,1\n2.5,0.5,1.75,1\n-0.5,2.75,2.5,1.2\n";
const FORCES: &str =
    "fx,fy,fz,tx,ty,tz\n1,0.5,-0.25,0,0.1,0\n0,1,0.3,-0.2,0,1\n-0.4,0,-1,1,0.5,0\n";

fn particles() -> Vec<Particle> {
    vec![
        Particle {
            x: [0.0, 0.0, 1.5],
            a: 1.0,
        },
        Particle {
            x: [2.5, 0.5, 1.75],
            a: 1.0,
        },
        Particle {
            x: [-0.5, 2.75, 2.5],
            a: 1.2,
        },
    ]
}

fn forces() -> [[f64; 6]; 3] {
    [
        [1.0, 0.5, -0.25, 0.0, 0.1, 0.0],
        [0.0, 1.0, 0.3, -0.2, 0.0, 1.0],
        [-0.4, 0.0, -1.0, 1.0, 0.5, 0.0],
    ]
}

const ETA: f64 = 0.7;
const WALL: Confinement = Confinement::Wall { height: 0.25 };

fn system(conf: Confinement) -> System {
    System::new(conf, ETA, particles(), false).expect("valid system")
}

fn moments_name(m: Moments) -> &'static str {
    match m {
        Moments::F => "F",
        Moments::FT => "FT",
        Moments::FTS => "FTS",
    }
}

/// Parse an NPY v1.0 file of little-endian float64, C or Fortran order.
fn read_npy(path: &Path) -> DMatrix<f64> {
    let bytes = fs::read(path).expect("read npy");
    assert_eq!(&bytes[..6], b"\x93NUMPY", "magic");
    assert_eq!(&bytes[6..8], &[1, 0], "version 1.0");
    let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!(
        (10 + hlen) % 64,
        0,
        "header padded to a multiple of 64 bytes"
    );
    let header = std::str::from_utf8(&bytes[10..10 + hlen]).expect("ascii header");
    assert!(header.ends_with('\n'), "header ends with a newline");
    assert!(header.contains("'descr': '<f8'"), "{header}");
    let fortran = header.contains("'fortran_order': True");
    assert!(
        fortran || header.contains("'fortran_order': False"),
        "{header}"
    );
    let shape = header
        .split("'shape': (")
        .nth(1)
        .and_then(|t| t.split(')').next())
        .expect("shape");
    let dims: Vec<usize> = shape
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().expect("shape entry"))
        .collect();
    assert_eq!(dims.len(), 2, "2-D array");
    let (r, c) = (dims[0], dims[1]);
    let data = &bytes[10 + hlen..];
    assert_eq!(data.len(), 8 * r * c, "data length");
    let values: Vec<f64> = data
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect();
    if fortran {
        DMatrix::from_column_slice(r, c, &values)
    } else {
        DMatrix::from_row_slice(r, c, &values)
    }
}

fn read_json(path: &Path) -> (serde_json::Value, DMatrix<f64>) {
    let text = fs::read_to_string(path).expect("read json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let rows = v["matrix"].as_array().expect("matrix is an array");
    let r = rows.len();
    let mut values = Vec::new();
    for row in rows {
        let row = row.as_array().expect("row is an array");
        assert_eq!(row.len(), r, "square matrix");
        values.extend(row.iter().map(|x| x.as_f64().expect("number")));
    }
    (v.clone(), DMatrix::from_row_slice(r, r, &values))
}

fn assert_bit_equal(got: &DMatrix<f64>, want: &DMatrix<f64>, what: &str) {
    assert_eq!(got.shape(), want.shape(), "{what}: shape");
    for (i, (g, w)) in got.iter().zip(want.iter()).enumerate() {
        assert_eq!(
            g.to_bits(),
            w.to_bits(),
            "{what}: entry {i}: {g:?} != {w:?}"
        );
    }
}

fn read_csv(path: &Path, header: &str) -> Vec<Vec<f64>> {
    let text = fs::read_to_string(path).expect("read csv");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(header));
    lines
        .map(|l| l.split(',').map(|f| f.parse().expect("number")).collect())
        .collect()
}

/// Moment-major forces (and torques) for `k` = 3 or 6 columns.
fn force_vector(k: usize) -> Vec<f64> {
    let f = forces();
    let n = f.len();
    let mut x = vec![0.0; k * n];
    for a in 0..n {
        for i in 0..3 {
            x[3 * a + i] = f[a][i];
            if k == 6 {
                x[3 * n + 3 * a + i] = f[a][3 + i];
            }
        }
    }
    x
}

/// CLI velocities back in moment-major order.
fn velocity_vector(rows: &[Vec<f64>]) -> Vec<f64> {
    let n = rows.len();
    let k = rows[0].len();
    let mut u = vec![0.0; k * n];
    for (a, r) in rows.iter().enumerate() {
        for i in 0..3 {
            u[3 * a + i] = r[i];
            if k == 6 {
                u[3 * n + 3 * a + i] = r[3 + i];
            }
        }
    }
    u
}

fn rel_err(got: &[f64], want: &[f64]) -> f64 {
    let d = got
        .iter()
        .zip(want)
        .map(|(g, w)| (g - w).abs())
        .fold(0.0, f64::max);
    d / want.iter().map(|w| w.abs()).fold(0.0, f64::max)
}

const SYSTEM_ARGS: [&str; 6] = [
    "--confinement",
    "wall",
    "--boundary-height",
    "0.25",
    "--viscosity",
    "0.7",
];

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
    ];
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

/// Run `mobility` on a particles file with `extra` options; the output would be M.npy.
fn mobility_fails(dir: &Dir, particles: &str, extra: &[&str]) -> Output {
    let p = dir.file("particles.csv", particles);
    let out = dir.path("M.npy");
    let mut args = vec![
        "mobility",
        "--confinement",
        "wall",
        "--moments",
        "FTS",
        "--particles",
        s(&p),
        "--out",
        s(&out),
    ];
    args.extend(extra);
    run(&args)
}

#[test]
fn missing_particles_file() {
    let dir = Dir::new("missing");
    let out = dir.path("M.npy");
    let p = dir.path("nowhere.csv");
    let o = run(&[
        "mobility",
        "--confinement",
        "wall",
        "--moments",
        "F",
        "--particles",
        s(&p),
        "--out",
        s(&out),
    ]);
    assert_fails(
        &o,
        &["cannot read particles file", "nowhere.csv"],
        &dir,
        &[],
    );
}

#[test]
fn bad_header() {
    let dir = Dir::new("header");
    let o = mobility_fails(&dir, "x,y,radius\n0,0,2\n", &[]);
    assert_fails(
        &o,
        &[
            "particles.csv line 1: the header must name the columns x,y,z,radius",
            "found x,y,radius: missing z",
        ],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn wrong_number_of_fields() {
    let dir = Dir::new("fields");
    let o = mobility_fails(&dir, "x,y,z,radius\n0,0,2,1\n5,0,2\n", &[]);
    assert_fails(
        &o,
        &["particles.csv line 3: expected 4 comma-separated fields (x,y,z,radius), found 3"],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn non_numeric_field() {
    let dir = Dir::new("nonnumeric");
    let o = mobility_fails(&dir, "x,y,z,radius\n0,0,2,1\n5,abc,2,1\n", &[]);
    assert_fails(
        &o,
        &["particles.csv line 3: y = \"abc\" is not a number"],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn nan_coordinate() {
    let dir = Dir::new("nan");
    let o = mobility_fails(&dir, "x,y,z,radius\n0,0,2,1\n5,0,NaN,1\n", &[]);
    assert_fails(
        &o,
        &["particles.csv line 3 (particle 1): coordinate z is NaN, not a finite number"],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn negative_radius() {
    let dir = Dir::new("radius");
    let o = mobility_fails(&dir, "x,y,z,radius\n0,0,2,1\n5,0,2,-1\n", &[]);
    assert_fails(
        &o,
        &["particles.csv line 3 (particle 1): radius -1 must be a positive finite number"],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn comment_lines_keep_line_numbers_right() {
    let dir = Dir::new("comments");
    let o = mobility_fails(
        &dir,
        "# spheres\nx,y,z,radius\n0,0,2,1\n\n# the bad one\n5,0,2,0\n",
        &[],
    );
    assert_fails(
        &o,
        &["particles.csv line 6 (particle 1): radius 0 must be a positive finite number"],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn zero_viscosity() {
    let dir = Dir::new("viscosity");
    let o = mobility_fails(&dir, PARTICLES, &["--viscosity", "0"]);
    assert_fails(
        &o,
        &["--viscosity 0: must be a positive finite number"],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn centre_below_wall() {
    let dir = Dir::new("below");
    let o = mobility_fails(
        &dir,
        "x,y,z,radius\n0,0,2,1\n5,0,-1,0.5\n",
        &["--boundary-height", "-0.5"],
    );
    assert_fails(
        &o,
        &["particles.csv line 3 (particle 1): centre z = -1 is not inside the fluid (boundary at z = -0.5)"],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn sphere_overlapping_the_wall_and_allow_overlap() {
    let dir = Dir::new("wall-overlap");
    let text = "x,y,z,radius\n0,0,2,1\n5,0,0.5,1\n";
    let o = mobility_fails(&dir, text, &[]);
    assert_fails(
        &o,
        &[
            "particles.csv line 3 (particle 1): sphere of radius 1 overlaps the boundary at z = 0",
            "--allow-overlap",
        ],
        &dir,
        &["particles.csv"],
    );
    let o = mobility_fails(&dir, text, &["--allow-overlap"]);
    assert_ok(&o);
    assert_eq!(read_npy(&dir.path("M.npy")).shape(), (22, 22));
}

#[test]
fn overlapping_spheres_and_allow_overlap() {
    let dir = Dir::new("overlap");
    let text = "x,y,z,radius\n0,0,2,1\n1.5,0,2,1\n";
    let o = mobility_fails(&dir, text, &[]);
    assert_fails(
        &o,
        &["particles.csv lines 2 and 3 (particles 0 and 1): spheres overlap: centre distance 1.5 < sum of radii 2"],
        &dir,
        &["particles.csv"],
    );
    let o = mobility_fails(&dir, text, &["--allow-overlap"]);
    assert_ok(&o);
    let m = read_npy(&dir.path("M.npy"));
    let conf = Confinement::Wall { height: 0.0 };
    let ps = vec![
        Particle {
            x: [0.0, 0.0, 2.0],
            a: 1.0,
        },
        Particle {
            x: [1.5, 0.0, 2.0],
            a: 1.0,
        },
    ];
    let want = System::new(conf, 1.0, ps, true)
        .expect("overlap allowed")
        .mobility(Moments::FTS);
    assert_bit_equal(&m, &want, "overlapping pair");
}

#[test]
fn missing_lambda_for_interface() {
    let dir = Dir::new("lambda");
    let p = dir.file("particles.csv", PARTICLES);
    let out = dir.path("M.json");
    let o = run(&[
        "mobility",
        "--confinement",
        "interface",
        "--moments",
        "F",
        "--particles",
        s(&p),
        "--out",
        s(&out),
    ]);
    assert_fails(
        &o,
        &["--confinement interface needs --lambda"],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn missing_gap_for_slit() {
    let dir = Dir::new("gap");
    let p = dir.file("particles.csv", PARTICLES);
    let out = dir.path("M.json");
    let o = run(&[
        "mobility",
        "--confinement",
        "slit",
        "--moments",
        "F",
        "--particles",
        s(&p),
        "--out",
        s(&out),
    ]);
    assert_fails(
        &o,
        &["--confinement slit needs --gap"],
        &dir,
        &["particles.csv"],
    );
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

#[test]
fn bad_output_name_is_rejected_before_any_work() {
    let dir = Dir::new("outname");
    let o = {
        let p = dir.file("particles.csv", PARTICLES);
        let out = dir.path("M.txt");
        run(&[
            "mobility",
            "--confinement",
            "wall",
            "--moments",
            "F",
            "--particles",
            s(&p),
            "--out",
            s(&out),
        ])
    };
    assert_fails(
        &o,
        &["M.txt: the file name must end in .npy or .json"],
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

// ---------------------------------------------------------------------------------
// `stokesian brownian`

/// Two unit spheres above a wall at z = 0.25 (gaps 0.75 and 1.25 radii, 3 apart).
const BD_PARTICLES: &str = "x,y,z,radius\n0,0,2,1\n3,0.5,2.5,1\n";
const BD_STEPS: usize = 50;
const BD_DT: f64 = 0.01;
const BD_KT: f64 = 1.5;

fn bd_particles() -> Vec<Particle> {
    vec![
        Particle {
            x: [0.0, 0.0, 2.0],
            a: 1.0,
        },
        Particle {
            x: [3.0, 0.5, 2.5],
            a: 1.0,
        },
    ]
}

/// The command line of the short run (with `seed` and `out`).
fn bd_args<'a>(particles: &'a str, seed: &'a str, out: &'a str) -> Vec<&'a str> {
    let mut a = vec!["brownian"];
    a.extend_from_slice(&SYSTEM_ARGS);
    a.extend_from_slice(&[
        "--particles",
        particles,
        "--steps",
        "50",
        "--dt",
        "0.01",
        "--kt",
        "1.5",
        "--weight",
        "0.5",
        "--repulsion-strength",
        "2",
        "--debye-length",
        "0.3",
        "--seed",
        seed,
        "--out",
        out,
    ]);
    a
}

/// The same run through the library: positions (N x 3 per frame) of every step, and
/// the number of rejected (redrawn) steps.
fn bd_library(seed: u64, dt: f64) -> (Vec<Vec<[f64; 3]>>, usize) {
    bd_library_with(seed, dt, None)
}

/// [`bd_library`] with or without lubrication.
fn bd_library_with(
    seed: u64,
    dt: f64,
    lubrication: Option<stokesian::LubricatedDynamics>,
) -> (Vec<Vec<[f64; 3]>>, usize) {
    use rand::SeedableRng;
    let bd = stokesian::Brownian {
        noise: stokesian::Noise::Cholesky,
        hydrodynamics: true,
        lubrication,
        moments: Moments::F,
        scheme: stokesian::Scheme::EulerMaruyama,
        kt: BD_KT,
        dt,
        drift: true,
        forces: stokesian::ExternalForces {
            weight: 0.5,
            strength: 2.0,
            debye: 0.3,
            trap: 0.0,
            torque: [0.0; 3],
        },
    };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut sys = System::new(WALL, ETA, bd_particles(), false).expect("valid system");
    let positions = |s: &System| s.particles().iter().map(|p| p.x).collect::<Vec<_>>();
    let mut frames = vec![positions(&sys)];
    let mut rejections = 0;
    for step in 1..=BD_STEPS {
        sys = loop {
            match sys.brownian_step(&bd, &mut rng, step) {
                Ok(next) => break next.system,
                Err(stokesian::BrownianError::Invalid { .. }) => rejections += 1,
                Err(e) => panic!("{e}"),
            }
        };
        frames.push(positions(&sys));
    }
    (frames, rejections)
}

/// Frames of a trajectory CSV, checking the step, time and particle columns.
fn read_trajectory_csv(path: &Path, n: usize, dt: f64) -> Vec<Vec<[f64; 3]>> {
    let text = fs::read_to_string(path).expect("read trajectory");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("step,time,particle,x,y,z"));
    let mut frames: Vec<Vec<[f64; 3]>> = Vec::new();
    for (k, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 6, "line {}: {line}", k + 2);
        let (frame, a) = (k / n, k % n);
        let step: usize = f[0].parse().expect("step");
        assert_eq!(step, frame, "step column");
        let time: f64 = f[1].parse().expect("time");
        assert_eq!(time.to_bits(), (step as f64 * dt).to_bits(), "time column");
        assert_eq!(
            f[2].parse::<usize>().expect("particle"),
            a,
            "particle column"
        );
        let x = [3, 4, 5].map(|i| f[i].parse::<f64>().expect("coordinate"));
        if a == 0 {
            frames.push(Vec::new());
        }
        frames[frame].push(x);
    }
    frames
}

/// An NPY trajectory: its shape and values (C order).
fn read_npy_3d(path: &Path) -> ([usize; 3], Vec<f64>) {
    let bytes = fs::read(path).expect("read npy");
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00", "magic and version 1.0");
    let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!((10 + hlen) % 64, 0, "header padded to 64 bytes");
    let header = std::str::from_utf8(&bytes[10..10 + hlen]).expect("ascii header");
    assert!(header.ends_with('\n'));
    assert!(header.contains("'descr': '<f8'"), "{header}");
    let fortran = header.contains("'fortran_order': True");
    assert!(
        fortran || header.contains("'fortran_order': False"),
        "{header}"
    );
    let shape = header
        .split("'shape': (")
        .nth(1)
        .and_then(|t| t.split(')').next())
        .expect("shape");
    let dims: Vec<usize> = shape
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().expect("shape entry"))
        .collect();
    assert_eq!(dims.len(), 3, "3-D array: {header}");
    let data = &bytes[10 + hlen..];
    assert_eq!(data.len(), 8 * dims[0] * dims[1] * dims[2], "data length");
    let values = data
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect();
    ([dims[0], dims[1], dims[2]], values)
}

fn assert_frames_bit_equal(got: &[Vec<[f64; 3]>], want: &[Vec<[f64; 3]>]) {
    assert_eq!(got.len(), want.len(), "number of frames");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.len(), w.len(), "frame {k}: particles");
        for (a, (gx, wx)) in g.iter().zip(w).enumerate() {
            for i in 0..3 {
                assert_eq!(
                    gx[i].to_bits(),
                    wx[i].to_bits(),
                    "frame {k} particle {a} axis {i}: {:?} != {:?}",
                    gx[i],
                    wx[i]
                );
            }
        }
    }
}

#[test]
fn brownian_csv_equals_the_library_bit_for_bit() {
    let dir = Dir::new("bd-csv");
    let p = dir.file("particles.csv", BD_PARTICLES);
    let out = dir.path("traj.csv");
    let o = run(&bd_args(s(&p), "7", s(&out)));
    assert_ok(&o);
    let got = read_trajectory_csv(&out, 2, BD_DT);
    let (want, _rejections) = bd_library(7, BD_DT);
    assert_eq!(got.len(), BD_STEPS + 1, "frames 0..=50");
    assert_frames_bit_equal(&got, &want);
    // the spheres moved, and stayed in the fluid
    assert_ne!(got[BD_STEPS][0], got[0][0]);
    assert!(got.iter().flatten().all(|x| x[2] > 1.25));
    assert_eq!(dir.listing(), ["particles.csv", "traj.csv"]);

    // --every 7: steps 0, 7, ..., 49 of the same trajectory
    let every = dir.path("every.csv");
    let mut args = bd_args(s(&p), "7", s(&every));
    args.extend_from_slice(&["--every", "7"]);
    assert_ok(&run(&args));
    let text = fs::read_to_string(&every).expect("read");
    let steps: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    let expected: Vec<String> = (0..=7)
        .flat_map(|k| [(7 * k).to_string(), (7 * k).to_string()])
        .collect();
    assert_eq!(steps, expected);
    let sparse: Vec<Vec<[f64; 3]>> = (0..=7).map(|k| want[7 * k].clone()).collect();
    let mut got_sparse: Vec<Vec<[f64; 3]>> = Vec::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let x = [3, 4, 5].map(|i| f[i].parse::<f64>().expect("coordinate"));
        if f[2] == "0" {
            got_sparse.push(Vec::new());
        }
        got_sparse.last_mut().expect("frame").push(x);
    }
    assert_frames_bit_equal(&got_sparse, &sparse);
}

/// `--lubrication`: the same trajectory as the library's lubricated dynamics (the pair
/// starts within the pair lubrication range), different from the far-field run, and
/// the `.npy` loads with the shape of the frames.
#[test]
fn brownian_lubrication_equals_the_library_bit_for_bit() {
    let dir = Dir::new("bd-lub");
    let p = dir.file("particles.csv", BD_PARTICLES);
    let out = dir.path("traj.csv");
    let mut args = bd_args(s(&p), "5", s(&out));
    args.push("--lubrication");
    assert_ok(&run(&args));
    let got = read_trajectory_csv(&out, 2, BD_DT);
    let lub = stokesian::LubricatedDynamics {
        lubrication: stokesian::Lubrication::default(),
        rfd_step: 1e-3,
    };
    let (want, _) = bd_library_with(5, BD_DT, Some(lub));
    assert_frames_bit_equal(&got, &want);
    let (far, _) = bd_library(5, BD_DT);
    assert_ne!(got[BD_STEPS], far[BD_STEPS]);
    let npy = dir.path("traj.npy");
    let mut args = bd_args(s(&p), "5", s(&npy));
    args.push("--lubrication");
    assert_ok(&run(&args));
    let (shape, values) = read_npy_3d(&npy);
    assert_eq!(shape, [BD_STEPS + 1, 2, 3]);
    let flat: Vec<f64> = want.iter().flatten().flatten().copied().collect();
    assert!(values
        .iter()
        .zip(&flat)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
}

#[test]
fn brownian_no_drift_differs_and_rejected_steps_are_redrawn_as_in_the_library() {
    let dir = Dir::new("bd-nodrift");
    let p = dir.file("particles.csv", BD_PARTICLES);
    let with = dir.path("with.csv");
    let without = dir.path("without.csv");
    assert_ok(&run(&bd_args(s(&p), "3", s(&with))));
    let mut args = bd_args(s(&p), "3", s(&without));
    args.push("--no-drift");
    assert_ok(&run(&args));
    let a = read_trajectory_csv(&with, 2, BD_DT);
    let b = read_trajectory_csv(&without, 2, BD_DT);
    assert_eq!(a[0], b[0]);
    assert_ne!(a[1], b[1], "the drift changes the first step");

    // dt = 0.5 near the wall: some steps are rejected and redrawn (the same rng draws
    // new noise), exactly as in the library
    let (want, rejections) = bd_library(7, 0.5);
    assert!(rejections > 0 && rejections <= 5, "{rejections} rejections");
    let big = dir.path("big.csv");
    let mut args = bd_args(s(&p), "7", s(&big));
    let dt = args.iter().position(|a| *a == "--dt").expect("--dt") + 1;
    args[dt] = "0.5";
    args.extend_from_slice(&["--max-rejections", "5"]);
    assert_ok(&run(&args));
    assert_frames_bit_equal(&read_trajectory_csv(&big, 2, 0.5), &want);
    fs::remove_file(&big).expect("remove");

    // allowing none fails, with a clear message and no output
    let k = args.len() - 1;
    args[k] = "0";
    assert_fails(
        &run(&args),
        &["rejected steps", "--max-rejections 0", "smaller --dt"],
        &dir,
        &["particles.csv", "with.csv", "without.csv"],
    );
}

#[test]
fn brownian_npy_has_shape_frames_n_3_and_equals_the_csv() {
    let dir = Dir::new("bd-npy");
    let p = dir.file("particles.csv", BD_PARTICLES);
    let csv = dir.path("traj.csv");
    let npy = dir.path("traj.npy");
    assert_ok(&run(&bd_args(s(&p), "7", s(&csv))));
    assert_ok(&run(&bd_args(s(&p), "7", s(&npy))));
    let frames = read_trajectory_csv(&csv, 2, BD_DT);
    let (shape, values) = read_npy_3d(&npy);
    assert_eq!(shape, [BD_STEPS + 1, 2, 3]);
    let from_csv: Vec<f64> = frames.iter().flatten().flatten().copied().collect();
    assert_eq!(values.len(), from_csv.len());
    for (k, (v, c)) in values.iter().zip(&from_csv).enumerate() {
        assert_eq!(v.to_bits(), c.to_bits(), "entry {k}: {v:?} != {c:?}");
    }
}

#[test]
fn brownian_same_seed_same_file_different_seed_different_file() {
    let dir = Dir::new("bd-seed");
    let p = dir.file("particles.csv", BD_PARTICLES);
    let read = |name: &str, seed: &str| {
        let out = dir.path(name);
        assert_ok(&run(&bd_args(s(&p), seed, s(&out))));
        fs::read(&out).expect("read output")
    };
    let a = read("a.csv", "11");
    let b = read("b.csv", "11");
    let c = read("c.csv", "12");
    assert_eq!(a, b, "same seed, same file");
    assert_ne!(a, c, "different seeds, different trajectories");
    let an = read("a.npy", "11");
    let bn = read("b.npy", "11");
    let cn = read("c.npy", "12");
    assert_eq!(an, bn);
    assert_ne!(an, cn);
}

#[test]
fn brownian_bad_inputs_fail_without_output() {
    let dir = Dir::new("bd-bad");
    let p = dir.file("particles.csv", BD_PARTICLES);
    let out = dir.path("traj.csv");
    let inputs = ["particles.csv"];
    let with = |option: &str, value: &str| {
        let mut args = bd_args(s(&p), "7", s(&out));
        let k = args.iter().position(|a| *a == option).expect("option") + 1;
        args[k] = value;
        run(&args)
    };

    // missing --dt (clap's usage error)
    let mut args = bd_args(s(&p), "7", s(&out));
    let k = args.iter().position(|a| *a == "--dt").expect("--dt");
    args.drain(k..k + 2);
    assert_fails(&run(&args), &["--dt"], &dir, &inputs);

    for dt in ["0", "-0.01", "nan", "inf"] {
        assert_fails(
            &with("--dt", dt),
            &["--dt", "time step must be a positive finite number"],
            &dir,
            &inputs,
        );
    }
    for kt in ["0", "-1"] {
        assert_fails(
            &with("--kt", kt),
            &["--kt", "kT must be a positive finite number"],
            &dir,
            &inputs,
        );
    }
    assert_fails(
        &with("--debye-length", "0"),
        &["--debye-length", "positive"],
        &dir,
        &inputs,
    );

    // options that do not fit together, or are out of range
    let extra = |more: &[&'static str], needles: &[&str]| {
        let mut args = bd_args(s(&p), "7", s(&out));
        args.extend_from_slice(more);
        assert_fails(&run(&args), needles, &dir, &inputs);
    };
    extra(
        &["--moments", "FTS"],
        &["--moments FTS", "F level", "FT level"],
    );
    extra(
        &["--torque", "0,1,0"],
        &["--torque does not apply", "--moments F"],
    );
    extra(
        &["--moments", "FT", "--torque", "0,1"],
        &["--torque 0,1", "needs 3 components"],
    );
    extra(
        &["--moments", "FT", "--torque", "0,x,1"],
        &["--torque", "component 2", "not a number"],
    );
    extra(
        &["--scheme", "fixman", "--lanczos", "1e-6"],
        &["--lanczos does not apply", "--scheme fixman"],
    );
    extra(
        &["--scheme", "fixman", "--no-drift"],
        &["--no-drift does not apply", "--scheme fixman"],
    );
    extra(&["--lanczos", "0"], &["--lanczos", "positive"]);
    extra(
        &["--lubrication", "--lanczos", "1e-6"],
        &["--lanczos does not apply", "--lubrication"],
    );
    extra(
        &["--lubrication", "--scheme", "fixman"],
        &["--scheme fixman does not apply", "--lubrication"],
    );
    extra(&["--rfd-step", "1e-4"], &["--lubrication"]);
    extra(
        &["--lubrication", "--rfd-step", "0"],
        &["--rfd-step", "positive"],
    );
    extra(&["--trap", "-1"], &["--trap", ">= 0"]);

    // a sphere cutting the wall at z = 0.25 (line 3, particle 1)
    let q = dir.file("cut.csv", "x,y,z,radius\n0,0,2,1\n3,0,1,1\n");
    assert_fails(
        &run(&bd_args(s(&q), "7", s(&out))),
        &[
            "cut.csv line 3 (particle 1)",
            "overlaps the boundary at z = 0.25",
        ],
        &dir,
        &["cut.csv", "particles.csv"],
    );

    // wrong output extension: rejected before any work
    let bad = dir.path("traj.txt");
    assert_fails(
        &run(&bd_args(s(&p), "7", s(&bad))),
        &[".csv or .npy"],
        &dir,
        &["cut.csv", "particles.csv"],
    );

    // --scene is exclusive with --confinement and --moments (clap's usage error), and a
    // scene file that cannot be used is an error naming it
    let scene = dir.file(
        "scene.toml",
        "name = \"x\"\nconfinement = \"wall\"\nmoments = \"FT\"\n",
    );
    let bad_scene = dir.file("bad.toml", "confinement = \"wal\"\nmoments = \"FT\"\n");
    let all_inputs = ["bad.toml", "cut.csv", "particles.csv", "scene.toml"];
    let mut args = bd_args(s(&p), "7", s(&out));
    args.extend_from_slice(&["--scene", s(&scene)]);
    assert_fails(
        &run(&args),
        &["--scene", "cannot be used with"],
        &dir,
        &all_inputs,
    );
    let mut args = bd_args(s(&p), "7", s(&out));
    args.drain(1..3); // --confinement wall
    args.extend_from_slice(&["--scene", s(&bad_scene)]);
    assert_fails(
        &run(&args),
        &["scene file", "bad.toml", "unknown confinement `wal`"],
        &dir,
        &all_inputs,
    );
}

/// The FT run through the library: per frame and particle `x, y, z, qw, qx, qy, qz`.
fn bd_library_ft(seed: u64, scheme: stokesian::Scheme, noise: stokesian::Noise) -> Vec<f64> {
    use rand::SeedableRng;
    let bd = stokesian::Brownian {
        noise,
        hydrodynamics: true,
        lubrication: None,
        moments: Moments::FT,
        scheme,
        kt: BD_KT,
        dt: BD_DT,
        drift: true,
        forces: stokesian::ExternalForces {
            weight: 0.5,
            strength: 2.0,
            debye: 0.3,
            trap: 0.0,
            torque: [0.0, 1.0, 0.0],
        },
    };
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut sys = System::new(WALL, ETA, bd_particles(), false).expect("valid system");
    let mut q = vec![[1.0, 0.0, 0.0, 0.0]; sys.len()];
    let mut out = Vec::new();
    let mut record = |s: &System, q: &[[f64; 4]]| {
        for (p, q) in s.particles().iter().zip(q) {
            out.extend_from_slice(&p.x);
            out.extend_from_slice(q);
        }
    };
    record(&sys, &q);
    for step in 1..=BD_STEPS {
        sys = loop {
            match sys.brownian_step(&bd, &mut rng, step) {
                Ok(next) => {
                    for (q, theta) in q.iter_mut().zip(&next.rotation) {
                        *q = stokesian::rotate(*q, *theta);
                    }
                    break next.system;
                }
                Err(stokesian::BrownianError::Invalid { .. }) => {}
                Err(e) => panic!("{e}"),
            }
        };
        record(&sys, &q);
    }
    out
}

/// FT Brownian dynamics from the command line (torques, Fixman's scheme, Lanczos noise,
/// the truncation from a scene file) writes exactly the library's trajectory: CSV with
/// the orientation quaternion after the position, NPY of shape (frames, N, 7).
#[test]
fn brownian_ft_equals_the_library_bit_for_bit() {
    use stokesian::{Noise, Scheme};
    let dir = Dir::new("bd-ft");
    let p = dir.file("particles.csv", BD_PARTICLES);
    let scene = dir.file(
        "wall_ft.toml",
        "name = \"wall_ft\"\nconfinement = \"wall\"\nmoments = \"FT\"\n",
    );
    let cases: [(&str, &[&str], Scheme, Noise); 3] = [
        ("em.csv", &[], Scheme::EulerMaruyama, Noise::Cholesky),
        (
            "fixman.npy",
            &["--scheme", "fixman"],
            Scheme::FixmanMidpoint,
            Noise::Cholesky,
        ),
        (
            "lanczos.csv",
            &["--lanczos", "1e-8"],
            Scheme::EulerMaruyama,
            Noise::Lanczos { tol: 1e-8 },
        ),
    ];
    for (name, options, scheme, noise) in cases {
        let out = dir.path(name);
        let mut args = bd_args(s(&p), "3", s(&out));
        args.drain(1..3); // --confinement wall: from the scene instead
        args.extend_from_slice(&["--scene", s(&scene), "--torque", "0,1,0"]);
        args.extend_from_slice(options);
        let o = run(&args);
        assert_ok(&o);
        if name.starts_with("lanczos") {
            assert!(
                stderr(&o).contains("Lanczos square root to 1e-8")
                    && stderr(&o).contains("iterations per step"),
                "{}",
                stderr(&o)
            );
        }
        let want = bd_library_ft(3, scheme, noise);
        let got: Vec<f64> = if name.ends_with(".npy") {
            let (shape, values) = read_npy_3d(&out);
            assert_eq!(shape, [BD_STEPS + 1, 2, 7]);
            values
        } else {
            let text = fs::read_to_string(&out).expect("read trajectory");
            let mut lines = text.lines();
            assert_eq!(lines.next(), Some("step,time,particle,x,y,z,qw,qx,qy,qz"));
            lines
                .flat_map(|l| {
                    l.split(',')
                        .skip(3)
                        .map(|v| v.parse::<f64>().expect("number"))
                })
                .collect()
        };
        assert_eq!(got.len(), want.len(), "{name}: values");
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(
                g.to_bits(),
                w.to_bits(),
                "{name}: value {k}: {g:?} != {w:?}"
            );
        }
        // the spheres rotated (mostly about y, the torque's axis) and stayed unit
        let last = &got[got.len() - 7..];
        let norm: f64 = last[3..].iter().map(|v| v * v).sum();
        assert!((norm - 1.0).abs() < 1e-12, "{name}: |q|^2 = {norm}");
        assert!(last[3] < 0.9999, "{name}: no rotation: {last:?}");
    }
}

/// `stokesian doublet` writes the CSV with the header (one row per grid point,
/// each row equal to the library's `doublet` at that point), the contour plot as PNG and
/// SVG beside it, and prints the maximum; bad grids fail without output.
#[test]
fn doublet_writes_csv_and_plots_and_rejects_bad_grids() {
    let dir = Dir::new("doublet");
    let out = dir.path("d.csv");
    let args = [
        "doublet",
        "--out",
        s(&out),
        "--r-points",
        "4",
        "--h-points",
        "3",
        "--r-max",
        "3",
        "--h-max",
        "2",
    ];
    let o = run(&args);
    assert_ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("maximum rate with lubrication"), "{stdout}");
    let text = fs::read_to_string(&out).expect("csv");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("r,h,rate_resistance,rate_farfield,tension_resistance,tension_farfield")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 12);
    let lub = stokesian::Lubrication::default();
    for row in &rows {
        let p = stokesian::doublet::doublet(row[0], row[1], &lub).expect("doublet");
        let want = [
            p.r,
            p.h,
            p.rate_resistance,
            p.rate_farfield,
            p.tension_resistance,
            p.tension_farfield,
        ];
        for (g, w) in row.iter().zip(want) {
            assert_eq!(g.to_bits(), w.to_bits(), "{row:?}");
        }
    }
    assert_eq!(rows[0][0], 2.0001);
    assert_eq!(rows[11][0], 3.0);
    let png = fs::read(dir.path("d.png")).expect("png");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let svg = fs::read_to_string(dir.path("d.svg")).expect("svg");
    assert!(svg.contains("<svg"));
    assert_eq!(dir.listing(), ["d.csv", "d.png", "d.svg"]);

    let bad = dir.path("bad.csv");
    for (option, value, needle) in [
        ("--r-min", "2", "must be above 2"),
        ("--h-min", "0.5", "must be above 1"),
        ("--r-points", "1", "at least 2"),
        ("--h-max", "1.00001", "above the minimum"),
    ] {
        let o = run(&["doublet", "--out", s(&bad), option, value]);
        assert_fails(&o, &[option, needle], &dir, &["d.csv", "d.png", "d.svg"]);
    }
}

/// A `.npy` file of float64 (or, with `single`, float32) `rows`, C or Fortran order.
fn write_npy_rows(path: &Path, rows: &[Vec<f64>], fortran: bool, single: bool) {
    let (r, c) = (rows.len(), rows[0].len());
    let at = |k: usize| {
        if fortran {
            rows[k % r][k / r]
        } else {
            rows[k / c][k % c]
        }
    };
    if single {
        write_npy_values(path, &[r, c], fortran, (0..r * c).map(|k| at(k) as f32));
    } else {
        write_npy_values(path, &[r, c], fortran, (0..r * c).map(at));
    }
}

/// A `.npy` file of `values` (of any type npyz writes) of this `shape`.
fn write_npy_values<T: npyz::AutoSerialize>(
    path: &Path,
    shape: &[usize],
    fortran: bool,
    values: impl IntoIterator<Item = T>,
) {
    use npyz::WriterBuilder;
    let order = if fortran {
        npyz::Order::Fortran
    } else {
        npyz::Order::C
    };
    let shape: Vec<u64> = shape.iter().map(|&d| d as u64).collect();
    let file = fs::File::create(path).expect("create npy");
    let mut w = npyz::WriteOptions::<T>::new()
        .default_dtype()
        .shape(&shape)
        .order(order)
        .writer(std::io::BufWriter::new(file))
        .begin_nd()
        .expect("npy header");
    w.extend(values).expect("npy data");
    w.finish().expect("npy complete");
}

/// `velocity --moments FTS` and `mobility --moments FTS` on `particles` (and `forces`)
/// with `extra` options: the bytes of U.csv and M.npy, and stderr.
fn outputs(
    dir: &Dir,
    particles: &Path,
    forces: &Path,
    extra: &[&str],
) -> (Vec<u8>, Vec<u8>, String) {
    let (u, m) = (dir.path("U.csv"), dir.path("M.npy"));
    let mut err = String::new();
    for command in [
        vec!["velocity", "--forces", s(forces), "--out", s(&u)],
        vec!["mobility", "--out", s(&m)],
    ] {
        let mut args = command;
        args.extend(["--moments", "FTS", "--particles", s(particles)]);
        args.extend(SYSTEM_ARGS);
        args.extend(extra);
        let o = run(&args);
        assert_ok(&o);
        err += &stderr(&o);
    }
    let read = |p: &Path| {
        let b = fs::read(p).expect("output");
        fs::remove_file(p).expect("remove output");
        b
    };
    (read(&u), read(&m), err)
}

/// Reordered and extra columns, CRLF, a byte-order mark, quoted numbers and `.npy` (C
/// and Fortran order) give the canonical CSV's outputs byte for byte; unknown columns
/// are named once per file on stderr.
#[test]
fn every_input_format_gives_the_canonical_outputs_bit_for_bit() {
    let dir = Dir::new("formats");
    let p = dir.file("particles.csv", PARTICLES);
    let f = dir.file("forces.csv", FORCES);
    let (want_u, want_m, quiet) = outputs(&dir, &p, &f, &[]);
    assert!(!quiet.contains("ignoring"), "{quiet}");
    let ps: Vec<Vec<f64>> = particles()
        .iter()
        .map(|q| vec![q.x[0], q.x[1], q.x[2], q.a])
        .collect();
    let fs_: Vec<Vec<f64>> = forces().iter().map(|r| r.to_vec()).collect();
    let variants: Vec<(&str, String, String)> = vec![
        (
            "reordered",
            "radius,z,y,x\n1,1.5,0,0\n1,1.75,0.5,2.5\n1.2,2.5,2.75,-0.5\n".into(),
            "tz,ty,tx,fz,fy,fx\n0,0.1,0,-0.25,0.5,1\n1,0,-0.2,0.3,1,0\n0,0.5,1,-1,0,-0.4\n".into(),
        ),
        (
            "extra columns",
            "id,x,y,z,radius,kind\n1,0,0,1.5,1,a\n2,2.5,0.5,1.75,1,b\n3,-0.5,2.75,2.5,1.2,c\n".into(),
            format!("particle,{}", FORCES.replace('\n', "\nP,").trim_end_matches("P,")),
        ),
        ("crlf", PARTICLES.replace('\n', "\r\n"), FORCES.replace('\n', "\r\n")),
        ("bom", format!("\u{feff}{PARTICLES}"), format!("\u{feff}{FORCES}")),
        (
            "quoted, spaced, commented",
            "# spheres\n\"x\", \"y\" ,\"z\",\"radius\"\n\"0\",\"0\",\"1.5\",\"1\"\n\n 2.5 , 0.5 , 1.75 , 1 \n\"-0.5\",2.75,\"2.5\",1.2\n".into(),
            FORCES.replace(',', " , "),
        ),
    ];
    for (what, pt, ft) in variants {
        let p = dir.file("p.csv", &pt);
        let f = dir.file("f.csv", &ft);
        let (u, m, err) = outputs(&dir, &p, &f, &[]);
        assert!(u == want_u, "{what}: velocities differ");
        assert!(m == want_m, "{what}: mobility differs");
        if what == "extra columns" {
            // twice: once for velocity's particles file, once for mobility's
            assert_eq!(
                err.matches("p.csv: ignoring columns id, kind").count(),
                2,
                "{err}"
            );
            assert_eq!(
                err.matches("f.csv: ignoring column particle").count(),
                1,
                "{err}"
            );
        } else {
            assert!(!err.contains("ignoring"), "{what}: {err}");
        }
    }
    for fortran in [false, true] {
        let p = dir.path("p.npy");
        let f = dir.path("f.npy");
        write_npy_rows(&p, &ps, fortran, false);
        write_npy_rows(&f, &fs_, fortran, false);
        let (u, m, _) = outputs(&dir, &p, &f, &[]);
        assert!(u == want_u && m == want_m, "npy, fortran {fortran}");
    }
    // centres only, with --radius: the two unit spheres
    let unit = "x,y,z,radius\n0,0,1.5,1\n2.5,0.5,1.75,1\n";
    let fu = dir.file(
        "fu.csv",
        &FORCES.lines().take(3).collect::<Vec<_>>().join("\n"),
    );
    let (want_u, want_m, _) = outputs(&dir, &dir.file("unit.csv", unit), &fu, &[]);
    let centres = dir.path("c.npy");
    write_npy_rows(
        &centres,
        &ps[..2].iter().map(|r| r[..3].to_vec()).collect::<Vec<_>>(),
        false,
        false,
    );
    let (u, m, _) = outputs(&dir, &centres, &fu, &["--radius", "1"]);
    assert!(u == want_u && m == want_m, "npy (N, 3) with --radius");
    let c = dir.file("c.csv", "z,x,y\n1.5,0,0\n1.75,2.5,0.5\n");
    let (u, m, _) = outputs(&dir, &c, &fu, &["--radius", "1"]);
    assert!(u == want_u && m == want_m, "csv x,y,z with --radius");
    // float32: the same as the CSV of the numbers rounded to single precision
    let rounded: Vec<Vec<f64>> = ps
        .iter()
        .map(|r| r.iter().map(|&v| f64::from(v as f32)).collect())
        .collect();
    let mut text = String::from("x,y,z,radius\n");
    for r in &rounded {
        text.push_str(&format!("{:?},{:?},{:?},{:?}\n", r[0], r[1], r[2], r[3]));
    }
    let (want_u, want_m, _) = outputs(&dir, &dir.file("r.csv", &text), &f, &[]);
    let p32 = dir.path("p32.npy");
    write_npy_rows(&p32, &ps, true, true);
    let (u, m, _) = outputs(&dir, &p32, &f, &[]);
    assert!(u == want_u && m == want_m, "float32 npy");
}

#[test]
fn bad_tables_and_npy_files_are_named() {
    let dir = Dir::new("bad-tables");
    let f = dir.file("forces.csv", FORCES);
    let o = mobility_fails(&dir, "x,y,z,radius,id\n0,0,2,1,a\n", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    fs::remove_file(dir.path("M.npy")).expect("output");
    let o = mobility_fails(&dir, "radius,x,z\n1,0,2\n", &[]);
    assert_fails(
        &o,
        &["particles.csv line 1", "missing y"],
        &dir,
        &["forces.csv", "particles.csv"],
    );
    let o = mobility_fails(&dir, PARTICLES, &["--radius", "1"]);
    assert_fails(
        &o,
        &["column radius conflicts with --radius"],
        &dir,
        &["forces.csv", "particles.csv"],
    );
    let o = mobility_fails(&dir, PARTICLES, &["--radius", "-1"]);
    assert_fails(
        &o,
        &["--radius -1: the radius must be a positive finite number"],
        &dir,
        &["forces.csv", "particles.csv"],
    );
    // npy: a dtype, a shape, a row
    let p = dir.path("p.npy");
    let out = dir.path("M.npy");
    let mobility = |extra: &[&str]| {
        let mut args = vec![
            "mobility",
            "--confinement",
            "wall",
            "--moments",
            "F",
            "--particles",
            s(&p),
            "--out",
            s(&out),
        ];
        args.extend(extra);
        run(&args)
    };
    write_npy_rows(&p, &[vec![0.0, 0.0, 2.0]], false, false);
    assert_fails(&mobility(&[]), &["p.npy: shape (1, 3): expected a 2-D float64 or float32 array of shape (N, 4), columns x, y, z, radius"], &dir, &["forces.csv", "p.npy", "particles.csv"]);
    write_npy_rows(
        &p,
        &[vec![0.0, 0.0, 2.0, 1.0], vec![0.0, 5.0, f64::NAN, 1.0]],
        true,
        false,
    );
    assert_fails(
        &mobility(&[]),
        &["p.npy row 1 (particle 1): coordinate z is NaN"],
        &dir,
        &["forces.csv", "p.npy", "particles.csv"],
    );
    write_npy_values(&p, &[1, 4], false, [0i32, 0, 2, 1]);
    assert_fails(
        &mobility(&[]),
        &["p.npy: dtype '<i4': expected a 2-D float64 or float32 array"],
        &dir,
        &["forces.csv", "p.npy", "particles.csv"],
    );
    // forces: torques at F, a missing column, a wrong width
    dir.file("particles.csv", PARTICLES);
    let u = dir.path("U.csv");
    let velocity = |moments: &str, forces: &Path| {
        let pp = dir.path("particles.csv");
        run(&[
            "velocity",
            "--confinement",
            "wall",
            "--moments",
            moments,
            "--particles",
            s(&pp),
            "--forces",
            s(forces),
            "--out",
            s(&u),
        ])
    };
    let inputs = ["forces.csv", "p.npy", "particles.csv"];
    assert_fails(
        &velocity("F", &f),
        &[
            "forces.csv line 1",
            "columns tx, ty, tz give torques, which need --moments FT or FTS",
        ],
        &dir,
        &inputs,
    );
    dir.file("forces.csv", "fx,fy,tx,ty,tz\n");
    assert_fails(
        &velocity("FT", &f),
        &["forces.csv line 1", "missing fz"],
        &dir,
        &inputs,
    );
    write_npy_rows(
        &p,
        &forces().iter().map(|r| r[..3].to_vec()).collect::<Vec<_>>(),
        false,
        false,
    );
    assert_fails(
        &velocity("FT", &p),
        &["p.npy: shape (3, 3): expected a 2-D float64 or float32 array of shape (N, 6)"],
        &dir,
        &inputs,
    );
}

/// A unit-scale mistake names the scale, not overlaps; a scene file's TOML error its
/// line and column.
#[test]
fn causes_are_named_right() {
    let dir = Dir::new("causes");
    let o = mobility_fails(&dir, "x,y,z,radius\n0,0,3e-301,1e-301\n", &[]);
    assert_fails(
        &o,
        &[
            "particles.csv line 2 (particle 0): radius 1e-301 with viscosity 1",
            "other units",
        ],
        &dir,
        &["particles.csv"],
    );
    assert!(!stderr(&o).contains("allow-overlap"), "{}", stderr(&o));
    // valid spheres whose pair kernels leave double precision (the wall's lateral far
    // field, an expansion in powers of 1/rho; the near kernels, collected in
    // dimensionless variables, stay finite at these scales): the scale is named
    let tiny = "x,y,z,radius\n0,0,2e-70,1e-70\n1e-60,0,2e-70,1e-70\n";
    let p = dir.file("particles.csv", tiny);
    let out = dir.path("M.npy");
    let o = run(&[
        "mobility",
        "--confinement",
        "wall",
        "--moments",
        "FTS",
        "--particles",
        s(&p),
        "--out",
        s(&out),
    ]);
    assert_fails(
        &o,
        &[
            "the mobility has entries that are not finite numbers: the lengths (from 1.000e-70",
            "other units",
        ],
        &dir,
        &["particles.csv"],
    );
    assert!(!stderr(&o).contains("allow-overlap"), "{}", stderr(&o));
    // accepted overlaps are suspected only where there are some
    let o = run(&[
        "mobility",
        "--confinement",
        "wall",
        "--moments",
        "FTS",
        "--particles",
        s(&p),
        "--out",
        s(&out),
        "--allow-overlap",
    ]);
    assert_fails(
        &o,
        &["not finite numbers: the lengths (from 1.000e-70"],
        &dir,
        &["particles.csv"],
    );
    assert!(!stderr(&o).contains("overlap"), "{}", stderr(&o));
    let scene = dir.file("scene.toml", "name = \"s\"\nconfinement = wall\n");
    let p = dir.path("particles.csv");
    let out = dir.path("M.npy");
    let o = run(&[
        "mobility",
        "--scene",
        s(&scene),
        "--particles",
        s(&p),
        "--out",
        s(&out),
    ]);
    assert_fails(
        &o,
        &["scene file", "scene.toml", "line 2, column 15"],
        &dir,
        &["particles.csv", "scene.toml"],
    );
}

/// Numbers (and a few non-numbers) as a user might type them, from the corners of
/// double precision.
fn nasty_text() -> impl proptest::strategy::Strategy<Value = String> {
    use proptest::prelude::*;
    prop_oneof![
        proptest::sample::select(vec![
            "NaN",
            "inf",
            "-inf",
            "0",
            "-0",
            "5e-324",
            "1e-310",
            "1e-301",
            "1e-120",
            "1e120",
            "1e308",
            "-1e308",
            "1.7976931348623157e308",
            "2.2250738585072014e-308",
            "abc",
            "",
        ])
        .prop_map(str::to_string),
        (-3.0..3.0f64).prop_map(|v| format!("{v:?}")),
        (0.5..4.0f64).prop_map(|v| format!("{v:?}")),
        proptest::num::f64::ANY.prop_map(|v| format!("{v:?}")),
    ]
}

/// The command's outcome on these inputs: success with a complete, finite matrix, or
/// failure with a message and no output; never a panic.
fn assert_clean_outcome(o: &Output, dir: &Dir, out: &Path, inputs: &[&str]) {
    let msg = stderr(o);
    assert!(!msg.contains("panicked"), "the command panicked: {msg}");
    assert_ne!(o.status.code(), Some(101), "the command panicked: {msg}");
    if o.status.success() {
        let m = read_npy(out);
        assert!(m.iter().all(|v| v.is_finite()), "non-finite output written");
    } else {
        assert!(msg.contains("error"), "no message: {msg:?}");
        let mut want: Vec<String> = inputs.iter().map(|s| s.to_string()).collect();
        want.sort();
        assert_eq!(dir.listing(), want, "files left behind: {msg}");
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 128, ..Default::default() })]

    /// Any numbers as coordinates, radii, viscosity, boundary height, lambda and gap.
    #[test]
    fn any_numbers_exit_cleanly(
        conf in proptest::sample::select(vec!["free", "wall", "free-surface", "interface", "slit"]),
        values in proptest::collection::vec(nasty_text(), 8..=12),
        height in proptest::option::of(nasty_text()),
        parameter in nasty_text(),
        viscosity in nasty_text(),
        allow_overlap in proptest::bool::ANY,
    ) {
        let dir = Dir::new("nasty");
        let mut text = String::from("x,y,z,radius\n");
        for row in values.chunks(4) {
            text.push_str(&row.join(","));
            text.push('\n');
        }
        let p = dir.file("particles.csv", &text);
        let out = dir.path("M.npy");
        let viscosity = format!("--viscosity={viscosity}");
        let mut args = vec!["mobility", "--moments", "F", "--confinement", conf, "--particles", s(&p), "--out", s(&out), &viscosity];
        let height = height.map(|h| format!("--boundary-height={h}"));
        if let (Some(h), true) = (&height, conf != "free") {
            args.push(h);
        }
        let parameter = match conf {
            "interface" => Some(format!("--lambda={parameter}")),
            "slit" => Some(format!("--gap={parameter}")),
            _ => None,
        };
        args.extend(parameter.as_deref());
        if allow_overlap {
            args.push("--allow-overlap");
        }
        let o = run(&args);
        assert_clean_outcome(&o, &dir, &out, &["particles.csv"]);
    }

    /// Any bytes as the particles file (CSV or `.npy`) and as the forces file.
    #[test]
    fn any_bytes_as_input_files_exit_cleanly(
        bytes in proptest::collection::vec(proptest::num::u8::ANY, 0..300),
        prefix in proptest::sample::select(vec![
            b"".to_vec(),
            b"x,y,z,radius\n".to_vec(),
            b"fx,fy,fz\n".to_vec(),
            b"\x93NUMPY\x01\x00".to_vec(),
        ]),
        npy in proptest::bool::ANY,
    ) {
        let dir = Dir::new("bytes");
        let mut data = prefix;
        data.extend(&bytes);
        let name = if npy { "particles.npy" } else { "particles.csv" };
        let p = dir.path(name);
        fs::write(&p, &data).expect("write particles");
        let out = dir.path("M.npy");
        let o = run(&["mobility", "--moments", "F", "--confinement", "free", "--particles", s(&p), "--out", s(&out)]);
        assert_clean_outcome(&o, &dir, &out, &[name]);
        fs::remove_file(&p).expect("remove particles");
        dir.file("particles.csv", "x,y,z,radius\n0,0,0,1\n3,0,0,1\n");
        let f = dir.path(if npy { "forces.npy" } else { "forces.csv" });
        fs::write(&f, &data).expect("write forces");
        let u = dir.path("U.csv");
        let pp = dir.path("particles.csv");
        let o = run(&["velocity", "--moments", "F", "--confinement", "free", "--particles", s(&pp), "--forces", s(&f), "--out", s(&u)]);
        proptest::prop_assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
        if !o.status.success() {
            proptest::prop_assert!(!u.exists(), "output left behind");
        }
    }
}

/// The nastiest command lines found: each fails with its cause named (and no output),
/// or succeeds with a finite matrix.
#[test]
fn corpus_of_nasty_command_lines() {
    let dir = Dir::new("corpus");
    let out = dir.path("M.npy");
    let failures: [(&str, &[&str], &str); 8] = [
        (
            "0,0,2,1",
            &["--confinement", "wall", "--viscosity", "5e-324"],
            "particles.csv line 2 (particle 0): radius 1 with viscosity 5e-324: 1/(viscosity a^3)",
        ),
        (
            "0,0,1e308,1",
            &["--confinement", "wall", "--boundary-height", "1e308"],
            "particles.csv line 2 (particle 0): centre z = 1e308 is not inside the fluid (boundary at z = 1e308)",
        ),
        (
            "0,0,2,1",
            &["--confinement", "slit", "--gap", "inf"],
            "--gap inf: the slit width must be a positive finite number",
        ),
        (
            "0,0,2,1",
            &["--confinement", "interface", "--lambda", "NaN"],
            "--lambda NaN: the viscosity ratio must be a non-negative finite number",
        ),
        (
            "0,0,1.5,1",
            &["--confinement", "slit", "--gap", "1e-300"],
            "centre z = 1.5 is not inside the fluid (boundary at z = 1e-300)",
        ),
        (
            "-1e308,0,2,1\n1e308,0,2,1",
            &["--confinement", "wall"],
            "the mobility has entries that are not finite numbers: the lengths (from 1.000e0, the smallest radius, to inf",
        ),
        (
            "0,0,2,1\n0,0,2,1",
            &["--confinement", "wall", "--allow-overlap"],
            "particles.csv lines 2 and 3 (particles 0 and 1): the two spheres have the same centre",
        ),
        (
            "0,0,1e-300,1",
            &["--confinement", "wall", "--allow-overlap"],
            "particles.csv line 2 (particle 0): sphere of radius 1 overlaps the boundary at z = 0 (centre-to-boundary distance 1e-300 < radius; --allow-overlap accepts this)), where the kernels are not meaningful",
        ),
    ];
    for (rows, options, message) in failures {
        let p = dir.file("particles.csv", &format!("x,y,z,radius\n{rows}\n"));
        let mut args = vec![
            "mobility",
            "--moments",
            "F",
            "--particles",
            s(&p),
            "--out",
            s(&out),
        ];
        args.extend(options);
        let o = run(&args);
        assert_fails(&o, &[message], &dir, &["particles.csv"]);
        if !options.contains(&"--allow-overlap") {
            assert!(!stderr(&o).contains("overlap"), "{}", stderr(&o));
        }
    }
    let successes: [(&str, &[&str]); 3] = [
        (
            "0,0,1e308,1",
            &["--confinement", "wall", "--boundary-height", "-1e308"],
        ),
        (
            "0,0,2,1",
            &["--confinement", "interface", "--lambda", "1e308"],
        ),
        (
            "0,0,2e100,1e100\n1e101,0,2e100,1e100",
            &["--confinement", "wall"],
        ),
    ];
    for (rows, options) in successes {
        let p = dir.file("particles.csv", &format!("x,y,z,radius\n{rows}\n"));
        let mut args = vec![
            "mobility",
            "--moments",
            "F",
            "--particles",
            s(&p),
            "--out",
            s(&out),
        ];
        args.extend(options);
        assert_ok(&run(&args));
        assert!(
            read_npy(&out).iter().all(|v| v.is_finite()),
            "{rows} {options:?}"
        );
        fs::remove_file(&out).expect("remove output");
    }
}
