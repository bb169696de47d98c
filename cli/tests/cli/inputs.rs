//! The inputs every subcommand shares (the system arguments, the particles and forces
//! files, scene files): every accepted spelling of a table gives the same outputs byte
//! for byte, every bad input a message naming its cause and no output, and no input
//! ever a panic.

use crate::common::*;
use std::fs;
use std::path::Path;
use std::process::Output;
use stokesian::{Confinement, Moments, Particle, System};

#[test]
fn missing_particles_file() {
    let dir = Dir::new("missing");
    let out = dir.path("M.npy");
    let p = dir.path("nowhere.csv");
    let o = run_mobility("wall", "F", &p, &out, &[]);
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
        &["particles.csv line 3 (particle 1): centre is not inside the fluid: signed distance -0.5 from the boundary, no slip at x3 = -0.5 (fluid where x3 > -0.5)"],
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
            "particles.csv line 3 (particle 1): sphere of radius 1 overlaps the boundary, no slip at x3 = 0 (fluid where x3 > 0): centre-to-boundary distance 0.5 < radius",
            "--overlap rpy or far",
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
    let o = run_mobility("interface", "F", &p, &out, &[]);
    assert_fails(
        &o,
        &[
            "`interface` needs the parameter `lambda`: viscosity ratio",
            "(give --param lambda=VALUE or --lambda VALUE)",
        ],
        &dir,
        &["particles.csv"],
    );
}

#[test]
fn missing_gap_for_slit() {
    let dir = Dir::new("gap");
    let p = dir.file("particles.csv", PARTICLES);
    let out = dir.path("M.json");
    let o = run_mobility("slit", "F", &p, &out, &[]);
    assert_fails(
        &o,
        &[
            "`slit` needs the parameter `gap`: distance from the lower wall to the upper wall",
            "(give --param gap=VALUE or --gap VALUE)",
        ],
        &dir,
        &["particles.csv"],
    );
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
    let mobility = |extra: &[&str]| run_mobility("wall", "F", &p, &out, extra);
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

/// `--param NAME=VALUE` and the aliases give the same bytes, in any mix and order.
#[test]
fn params_by_name_equal_the_aliases() {
    let dir = Dir::new("params");
    let p = dir.file("particles.csv", PARTICLES);
    let spellings: [&[&str]; 3] = [
        &["--boundary-height", "-0.5", "--gap", "60"],
        &["--param", "gap=60", "--param", "height=-0.5"],
        &["--param=height=-0.5", "--gap=60"],
    ];
    let mut outputs = Vec::new();
    for (k, spelling) in spellings.iter().enumerate() {
        let out = dir.path(&format!("M{k}.npy"));
        assert_ok(&run_mobility("slit", "FT", &p, &out, spelling));
        outputs.push(fs::read(&out).expect("read output"));
    }
    assert_eq!(outputs[0], outputs[1], "--param");
    assert_eq!(outputs[0], outputs[2], "mixed");
}

/// A parameter given wrongly by name is refused with a message naming it (and the
/// known ones, or what a missing one is), before any output.
#[test]
fn params_given_wrongly() {
    let dir = Dir::new("param-errors");
    let p = dir.file("particles.csv", PARTICLES);
    let out = dir.path("M.npy");
    let cases: [(&str, &[&str], &str); 10] = [
        (
            "slit",
            &["--param", "gapp=3"],
            "--param gapp=3: `slit` has no parameter `gapp` (its parameters: height, gap)",
        ),
        (
            "free",
            &["--param", "height=1"],
            "--param height=1: `free` has no parameters (got `height`)",
        ),
        (
            "slit",
            &["--gap", "60", "--param", "gap=60"],
            "the parameter `gap` is given twice (--gap 60 and --param gap=60; give it once)",
        ),
        (
            "wall",
            &["--param", "height=0", "--param", "height=1"],
            "the parameter `height` is given twice (--param height=0 and --param height=1; give it once)",
        ),
        (
            "interface",
            &["--param", "height=0.1"],
            "`interface` needs the parameter `lambda`",
        ),
        (
            "wall",
            &["--lambda", "2"],
            "--lambda does not apply to --confinement wall (its parameters: height)",
        ),
        (
            "free",
            &["--boundary-height", "0"],
            "--boundary-height does not apply to --confinement free (it has no parameters)",
        ),
        (
            "slit",
            &["--param", "gap=-1"],
            "--param gap=-1: a length must be a positive finite number",
        ),
        (
            "slit",
            &["--param", "gap"],
            "invalid value 'gap' for '--param <NAME=VALUE>': expected NAME=VALUE",
        ),
        (
            "slit",
            &["--param", "gap=wide"],
            "invalid value 'gap=wide' for '--param <NAME=VALUE>': \"wide\" is not a number",
        ),
    ];
    for (confinement, extra, message) in cases {
        let o = run_mobility(confinement, "F", &p, &out, extra);
        assert_fails(&o, &[message], &dir, &["particles.csv"]);
    }
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
    let o = run_mobility("wall", "FTS", &p, &out, &[]);
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
    let o = run_mobility("wall", "FTS", &p, &out, &["--allow-overlap"]);
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

    /// Any numbers as coordinates, radii, viscosity and the parameters of any
    /// confinement, each given by `--param` or by its alias.
    #[test]
    fn any_numbers_exit_cleanly(
        conf in proptest::sample::select(Confinement::NAMES.to_vec()),
        values in proptest::collection::vec(nasty_text(), 8..=12),
        parameters in proptest::collection::vec(proptest::option::of(nasty_text()), 2),
        by_alias in proptest::bool::ANY,
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
        let declared = kernels::declaration(conf).expect("a registered name").params;
        assert!(declared.len() <= parameters.len(), "a value for each parameter of {conf}");
        let given: Vec<String> = declared
            .iter()
            .zip(&parameters)
            .filter_map(|(param, value)| {
                let value = value.as_ref()?;
                let alias = ALIASES.iter().find(|(_, name)| *name == param.name);
                Some(match alias {
                    Some((option, _)) if by_alias => format!("{option}={value}"),
                    _ => format!("--param={}={value}", param.name),
                })
            })
            .collect();
        args.extend(given.iter().map(String::as_str));
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
            "particles.csv line 2 (particle 0): centre is not inside the fluid: signed distance 0 from the boundary, no slip at x3 = ",
        ),
        (
            "0,0,2,1",
            &["--confinement", "slit", "--gap", "inf"],
            "--gap inf: the parameter `gap` must be finite (got inf)",
        ),
        (
            "0,0,2,1",
            &["--confinement", "interface", "--lambda", "NaN"],
            "--lambda NaN: the parameter `lambda` must be finite (got NaN)",
        ),
        (
            "0,0,1.5,1",
            &["--confinement", "slit", "--gap", "1e-300"],
            "particles.csv line 2 (particle 0): centre is not inside the fluid: signed distance -1.5 from the boundary, no slip at x3 = ",
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
            "particles.csv line 2 (particle 0): sphere of radius 1 overlaps the boundary, no slip at x3 = 0 (fluid where x3 > 0): centre-to-boundary distance 1e-300 < radius (--overlap rpy or far accepts this)), where the kernels are not meaningful",
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

/// Two spheres for the periodic boxes' tests: the particle file and its particles.
const BOXED_SPHERES: &str = "x,y,z,radius\n0,0,0,1\n3,1,2,0.7\n";

fn boxed_spheres() -> Vec<Particle> {
    vec![
        Particle {
            x: [0.0, 0.0, 0.0],
            a: 1.0,
        },
        Particle {
            x: [3.0, 1.0, 2.0],
            a: 0.7,
        },
    ]
}

/// `--box LX,LY` near a wall: the library's mobility periodic along the wall, written
/// whole.
#[test]
fn a_box_periodic_along_a_wall() {
    let dir = Dir::new("box_wall");
    let text = BOXED_SPHERES;
    let p = dir.file("particles.csv", text);
    let out = dir.path("M.npy");
    let extra = ["--box", "10,11", "--boundary-height", "-5"];
    let o = run_mobility("wall", "FT", &p, &out, &extra);
    assert_ok(&o);
    let m = read_npy(&out);
    let ps = boxed_spheres();
    let want = System::new(Confinement::Wall { height: -5.0 }, 1.0, ps, false)
        .unwrap()
        .periodic(stokesian::PeriodicBox::lateral([10.0, 11.0]))
        .unwrap()
        .mobility(Moments::FT);
    assert_eq!(m.shape(), (12, 12));
    assert_eq!(m, want);
}

/// `--box LX,LY,LZ`: the library's periodic mobility, written whole; bad boxes and what
/// a box does not provide are errors that write nothing.
#[test]
fn a_periodic_box() {
    let dir = Dir::new("box");
    let text = BOXED_SPHERES;
    let p = dir.file("particles.csv", text);
    let out = dir.path("M.npy");
    let o = run_mobility("free", "FT", &p, &out, &["--box", "10,11,12"]);
    assert_ok(&o);
    let m = read_npy(&out);
    let ps = boxed_spheres();
    let want = System::new(Confinement::Free, 1.0, ps, false)
        .unwrap()
        .periodic(stokesian::PeriodicBox::new([10.0, 11.0, 12.0]))
        .unwrap()
        .mobility(Moments::FT);
    assert_eq!(m.shape(), (12, 12));
    assert_eq!(m, want);
    fs::remove_file(&out).unwrap();
    // the stresslets too, in the triply periodic box
    let o = run_mobility("free", "FTS", &p, &out, &["--box", "10,11,12"]);
    assert_ok(&o);
    let want = System::new(Confinement::Free, 1.0, boxed_spheres(), false)
        .unwrap()
        .periodic(stokesian::PeriodicBox::new([10.0, 11.0, 12.0]))
        .unwrap()
        .mobility(Moments::FTS);
    assert_eq!(read_npy(&out), want);
    fs::remove_file(&out).unwrap();
    // a periodic slit between x3 = -2 and x3 = 3: its exact Green's function
    let slit = ["--box", "10,11", "--boundary-height", "-2", "--gap", "5"];
    let periodic_slit = System::new(
        Confinement::Slit {
            height: -2.0,
            gap: 5.0,
        },
        1.0,
        boxed_spheres(),
        false,
    )
    .unwrap()
    .periodic(stokesian::PeriodicBox::lateral([10.0, 11.0]))
    .unwrap();
    // its stresslets too
    for (name, moments) in [("FT", Moments::FT), ("FTS", Moments::FTS)] {
        let o = run_mobility("slit", name, &p, &out, &slit);
        assert_ok(&o);
        assert_eq!(read_npy(&out), periodic_slit.mobility(moments));
        fs::remove_file(&out).unwrap();
    }
    for (conf, moments, b, message) in [
        (
            "free",
            "F",
            "10",
            "--box 10: needs 3 lengths lx,ly,lz (a triply periodic box) or 2 lengths lx,ly (periodic along a wall or a slit's walls), found 1",
        ),
        (
            "free",
            "F",
            "10,11",
            "--box: a periodic box is not available in unbounded fluid with two lengths",
        ),
        (
            "wall",
            "F",
            "10,11,12",
            "--box: a periodic box is not available near a wall with three lengths",
        ),
        (
            "free",
            "F",
            "10,1.5,12",
            "--box: particle 0: sphere of radius 1 overlaps its own periodic image",
        ),
        (
            "free-surface",
            "F",
            "10,11,12",
            "--box: a periodic box is not available near a free surface or an interface",
        ),
    ] {
        // the plane of the free surface below the spheres
        let mut extra = vec!["--box", b];
        if conf != "free" {
            extra.extend(["--boundary-height", "-5"]);
        }
        let o = run_mobility(conf, moments, &p, &out, &extra);
        assert_fails(&o, &[message], &dir, &["particles.csv"]);
    }
}
