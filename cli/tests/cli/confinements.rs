//! The confinements as the kernels declare them: `stokesian confinements` lists every
//! registered one with its parameters and boundaries (text and JSON), and a confinement
//! none of the command's code names, the side wall, works through `--confinement` and
//! `--param` in `mobility` and `velocity`, equal to the library.

use crate::common::*;
use nalgebra::DVector;
use stokesian::{Confinement, Moments, Particle, System};

/// The spheres of [`PARTICLES`] with x1 and x3 exchanged: clear of a side wall at
/// x1 = -1 (distances 2.5, 2.75 and 3.5 from it, radii 1, 1 and 1.2).
const SIDE_PARTICLES: &str = "x,y,z,radius\n1.5,0,0,1\n1.75,0.5,2.5,1\n2.5,2.75,-0.5,1.2\n";

const SIDE_WALL: Confinement = Confinement::SideWall { side: -1.0 };

fn side_system() -> System {
    let ps = particles()
        .into_iter()
        .map(|p| Particle {
            x: [p.x[2], p.x[1], p.x[0]],
            a: p.a,
        })
        .collect();
    System::new(SIDE_WALL, ETA, ps, false).expect("spheres clear of the side wall")
}

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8(o.stdout.clone()).expect("UTF-8 listing")
}

/// The text listing has a section per registered name, in the registry's order, each
/// with its title, every parameter (its default or "required", its doc) and the
/// boundaries of the confinement at the stated values.
#[test]
fn confinements_lists_every_registered_confinement() {
    let o = run(&["confinements"]);
    assert_ok(&o);
    let text = stdout(&o);
    let sections: Vec<&str> = text.split("\n\n").filter(|s| !s.is_empty()).collect();
    assert_eq!(sections.len(), Confinement::NAMES.len(), "{text}");
    for (name, section) in Confinement::NAMES.iter().zip(&sections) {
        let d = kernels::declaration(name).expect("a registered name");
        let head = section.lines().next().expect("a first line");
        assert!(
            head == *name || head.starts_with(&format!("{name} (or ")),
            "{head:?} for {name}"
        );
        assert!(section.contains(d.title), "{name}: title in {section}");
        for p in d.params {
            let line = section
                .lines()
                .find(|l| l.trim_start().starts_with(&format!("{} ", p.name)))
                .unwrap_or_else(|| panic!("{name}: no line for {}: {section}", p.name));
            assert!(line.contains(p.doc), "{line}");
            match p.default {
                Some(v) => assert!(line.contains(&format!("default {v}")), "{line}"),
                None => assert!(line.contains("required"), "{line}"),
            }
        }
        // the boundaries at the values the listing names: defaults, else examples
        let values: Vec<(&str, f64)> = d
            .params
            .iter()
            .map(|p| (p.name, p.default.unwrap_or(p.example)))
            .collect();
        let planes = d.with(&values).expect("declared values").boundaries();
        if planes.is_empty() {
            assert!(section.contains("boundaries: none"), "{section}");
        } else {
            let stated: Vec<String> = values.iter().map(|(n, v)| format!("{n} = {v}")).collect();
            assert!(
                section.contains(&format!("boundaries (for {}):", stated.join(", "))),
                "{section}"
            );
            for b in planes {
                assert!(section.contains(&b.describe()), "{name}: {b} in {section}");
            }
        }
    }
}

/// `--format json`: an array in the registry's order, each parameter's default (null
/// when required) and the boundaries at `boundaries_for`.
#[test]
fn confinements_as_json() {
    let o = run(&["confinements", "--format", "json"]);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("valid JSON");
    let list = v.as_array().expect("an array");
    let names: Vec<&str> = list
        .iter()
        .map(|c| c["name"].as_str().expect("a name"))
        .collect();
    assert_eq!(names, Confinement::NAMES);
    for c in list {
        let d = kernels::declaration(c["name"].as_str().unwrap()).unwrap();
        assert_eq!(c["title"], d.title);
        let params = c["params"].as_array().expect("params");
        assert_eq!(params.len(), d.params.len());
        let mut values = Vec::new();
        for (j, p) in params.iter().zip(d.params) {
            assert_eq!(j["name"], p.name);
            assert_eq!(j["doc"], p.doc);
            assert_eq!(j["default"].as_f64(), p.default);
            let shown = c["boundaries_for"][p.name].as_f64().expect("a value");
            assert_eq!(shown, p.default.unwrap_or(p.example));
            values.push((p.name, shown));
        }
        let planes = d.with(&values).unwrap().boundaries();
        let listed = c["boundaries"].as_array().expect("boundaries");
        assert_eq!(listed.len(), planes.len());
        for (j, b) in listed.iter().zip(&planes) {
            assert_eq!(j["describe"], b.describe());
            assert_eq!(j["offset"].as_f64(), Some(b.offset));
            let normal: Vec<f64> = j["normal"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert_eq!(normal, b.normal);
            assert_eq!(j["exact"], b.exact);
        }
    }
}

/// `mobility --confinement side_wall --param side=-1` (and its hyphenated spelling)
/// equals the library's mobility of the side wall bit for bit.
#[test]
fn side_wall_mobility_equals_the_library() {
    let dir = Dir::new("side-mobility");
    let p = dir.file("particles.csv", SIDE_PARTICLES);
    let want = side_system().mobility(Moments::FTS);
    for name in ["side_wall", "side-wall"] {
        let out = dir.path(&format!("M-{name}.npy"));
        let o = run_mobility(
            name,
            "FTS",
            &p,
            &out,
            &["--param", "side=-1", "--viscosity", "0.7"],
        );
        assert_ok(&o);
        assert_bit_equal(&read_npy(&out), &want, name);
    }
}

/// `velocity` of the side wall at F and FT: the library's velocities bit for bit, and
/// within 1e-14 of the largest velocity of the dense mobility times the forces (the
/// matrix-free product sums the same terms in another order: round-off of a few ulps).
#[test]
fn side_wall_velocity_equals_the_library() {
    let dir = Dir::new("side-velocity");
    let p = dir.file("particles.csv", SIDE_PARTICLES);
    let f6 = dir.file("forces6.csv", FORCES);
    let f3 = dir.file("forces3.csv", "fx,fy,fz\n1,0.5,-0.25\n0,1,0.3\n-0.4,0,-1\n");
    let system = side_system();
    for (moments, file, k, header) in [
        (Moments::F, &f3, 3, "ux,uy,uz"),
        (Moments::FT, &f6, 6, "ux,uy,uz,wx,wy,wz"),
    ] {
        let out = dir.path(&format!("U_{}.csv", moments_name(moments)));
        let o = run(&[
            "velocity",
            "--confinement",
            "side_wall",
            "--param",
            "side=-1",
            "--viscosity",
            "0.7",
            "--moments",
            moments_name(moments),
            "--particles",
            s(&p),
            "--forces",
            s(file),
            "--out",
            s(&out),
        ]);
        assert_ok(&o);
        let got = velocity_vector(&read_csv(&out, header));
        let x = force_vector(k);
        let want = system
            .velocities(moments, &x, &[0.0; 5], None)
            .expect("velocities")
            .u;
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(g.to_bits(), w.to_bits(), "{header}: entry {i}: {g} != {w}");
        }
        let dense = system.mobility(moments) * DVector::from_vec(x);
        let e = rel_err(&got, dense.as_slice());
        assert!(e <= 1e-14, "{header}: {e:e} from the dense product");
    }
}

/// The side wall's own errors: an alias of another confinement's parameter, a sphere
/// on the wrong side (its boundary named), an unknown parameter (the side wall's
/// listed).
#[test]
fn side_wall_errors_name_the_side_wall() {
    let dir = Dir::new("side-errors");
    let p = dir.file("particles.csv", SIDE_PARTICLES);
    let out = dir.path("M.npy");
    let with = |extra: &[&str]| run_mobility("side_wall", "F", &p, &out, extra);
    assert_fails(
        &with(&["--boundary-height", "1"]),
        &["--boundary-height does not apply to --confinement side_wall (its parameters: side)"],
        &dir,
        &["particles.csv"],
    );
    assert_fails(
        &with(&["--param", "side=2"]),
        &["particles.csv line 2 (particle 0): centre is not inside the fluid: signed distance -0.5 from the boundary, no slip at x1 = 2 (fluid where x1 > 2)"],
        &dir,
        &["particles.csv"],
    );
    assert_fails(
        &with(&["--param", "height=1"]),
        &["--param height=1: `side_wall` has no parameter `height` (its parameters: side)"],
        &dir,
        &["particles.csv"],
    );
}
