//! `stokesian brownian`: trajectories equal the library's bit for bit (CSV and `.npy`,
//! F and FT, with lubrication, schemes and noises); bad inputs fail without output.

use crate::common::*;
use std::fs;
use std::path::Path;
use stokesian::{Moments, Particle, System};

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
    let (dims, _, values) = read_npy_values(path);
    assert_eq!(dims.len(), 3, "3-D array: {dims:?}");
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

/// An output that is neither `.csv` nor `.npy` (JSON is the matrices') is refused before
/// any work, the accepted extensions listed; the extension chooses in any case.
#[test]
fn brownian_refuses_other_extensions() {
    let dir = Dir::new("bd-out");
    let p = dir.file("particles.csv", BD_PARTICLES);
    for name in ["traj.json", "traj"] {
        let out = dir.path(name);
        assert_fails(
            &run(&bd_args(s(&p), "7", s(&out))),
            &[&format!(
                "--out {}: the file name must end in .csv or .npy",
                s(&out)
            )],
            &dir,
            &["particles.csv"],
        );
    }
    let (upper, lower) = (dir.path("a.NPY"), dir.path("b.npy"));
    assert_ok(&run(&bd_args(s(&p), "7", s(&upper))));
    assert_ok(&run(&bd_args(s(&p), "7", s(&lower))));
    assert_eq!(fs::read(&upper).unwrap(), fs::read(&lower).unwrap());
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
    extra(&["--fmm", "1e-6"], &["--lanczos"]);
    extra(
        &["--lanczos", "1e-6", "--fmm", "1e-2"],
        &["--fmm", "[1e-10, 1e-3]"],
    );
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
            "overlaps the boundary, no slip at x3 = 0.25 (fluid where x3 > 0.25)",
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
