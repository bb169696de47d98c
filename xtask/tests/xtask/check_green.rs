use anyhow::Result;
use std::path::PathBuf;
use xtask::check_green::*;

fn args(s: &str) -> Result<Args> {
    parse(&s.split_whitespace().collect::<Vec<_>>())
}

#[test]
fn arguments() {
    let file = |f: &str, n: Option<&str>| Args::File {
        file: PathBuf::from(f),
        name: n.map(String::from),
    };
    assert_eq!(args("a/b.rs").unwrap(), file("a/b.rs", None));
    assert_eq!(args("b.rs --name c").unwrap(), file("b.rs", Some("c")));
    assert_eq!(args("--name c b.rs").unwrap(), file("b.rs", Some("c")));
    assert_eq!(
        args("--registered wall").unwrap(),
        Args::Registered("wall".into())
    );
    for (bad, why) in [
        ("", "no file given"),
        ("b.txt", "not a Rust file"),
        ("a.rs b.rs", "more than one file"),
        ("b.rs --name", "--name needs a value"),
        ("b.rs --name --registered", "--name needs a value"),
        ("b.rs --name c --name d", "--name is given twice"),
        ("b.rs --nme c", "unknown option --nme"),
        ("b.rs --registered wall", "--registered takes no file"),
        ("--registered wall --name c", "--registered takes no file"),
    ] {
        let e = args(bad).unwrap_err().to_string();
        assert!(e.contains(why), "{bad:?}: {e}");
        assert!(e.contains("usage: cargo xtask check-green"), "{bad:?}: {e}");
    }
}

#[test]
fn the_side_wall_file_is_found_and_registered() {
    let root = xtask::root();
    let source = std::fs::read_to_string(root.join(GREEN_DIR).join("side_wall.rs")).unwrap();
    let found = analyze(&source).unwrap();
    assert_eq!(
        found,
        Found {
            ty: "SideWall".into(),
            name: Some("side_wall".into())
        }
    );
    let mod_rs = std::fs::read_to_string(root.join(GREEN_DIR).join("mod.rs")).unwrap();
    let new = register(&mod_rs, "other", "Other").unwrap();
    let added: Vec<&str> = new
        .lines()
        .filter(|l| !mod_rs.lines().any(|m| m == *l))
        .collect();
    assert_eq!(added, ["pub mod other;", "    v.visit(&other::Other);"]);
    // the visit line is the last statement of `for_each`
    let visit = new.find("    v.visit(&other::Other);\n}").unwrap();
    assert!(new[..visit].rfind("pub fn for_each<").unwrap() < visit);
}

#[test]
fn files_that_cannot_be_registered_are_refused() {
    for (source, why) in [
        ("pub struct A; impl Green for A {", "does not parse as Rust"),
        ("pub struct A;", "has 0 `impl Green for T`"),
        (
            "pub struct A; pub struct B; impl Green for A {} impl Green for B {}",
            "has 2 `impl Green for T`",
        ),
        (
            "pub struct A { x: f64 } impl Green for A {}",
            "a unit struct",
        ),
        ("impl Green for A {}", "a unit struct"),
        (
            "pub struct A; impl Green for &'static A {}",
            "a struct of the file",
        ),
    ] {
        let e = analyze(source).unwrap_err().to_string();
        assert!(e.contains(why), "{source}: {e}");
    }
    let found = analyze(
        "pub struct A; impl super::Green for A { fn name(&self) -> &'static str { \"a\" } }",
    )
    .unwrap();
    assert_eq!(found.name.as_deref(), Some("a"));
}

/// The generator's declaration check refuses a mirror or boundary whose normal is
/// not a unit vector, naming it.
#[test]
fn a_non_unit_normal_is_refused() {
    use kernel_gen::number::scalar::Scalar;
    use kernel_gen::physics::green::{
        check, Boundary, Condition, DeclarationError, Green, ImageTerm, Mat3, Plane,
    };
    /// A wall whose mirror and boundary normal is `N`.
    struct Tilted<const N: usize>;
    const NORMALS: [[f64; 3]; 3] = [[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 1.0, 1.0]];
    impl<const N: usize> Green for Tilted<N> {
        fn name(&self) -> &'static str {
            "tilted"
        }
        fn title(&self) -> &'static str {
            "a wall"
        }
        fn params(&self) -> &'static [kernel_gen::physics::green::Param] {
            &[]
        }
        fn reflected<S: Scalar>(&self, _x: &[S; 3], _y: &[S; 3], _p: &[S]) -> Mat3<S> {
            std::array::from_fn(|_| std::array::from_fn(|_| S::cst(0.0)))
        }
        fn image_terms(&self) -> Option<Vec<ImageTerm>> {
            // the free-surface image's `-J_33(R)` entry alone: its plane is all
            // that is checked
            Some(vec![ImageTerm {
                out: (2, 2),
                coef: -1.0,
                weight: 0,
                plane: 0,
                h_power: 0,
                d: [0; 3],
                j: (2, 2),
            }])
        }
        fn mirrors<S: Scalar>(&self, _p: &[S]) -> Vec<Plane<S>> {
            vec![Plane {
                normal: NORMALS[N],
                offset: S::cst(0.0),
            }]
        }
        fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<Boundary<S>> {
            vec![Boundary {
                plane: self.mirrors(p).remove(0),
                condition: Condition::NoSlip,
                exact: true,
            }]
        }
    }
    check(&Tilted::<0>).unwrap();
    check(&Tilted::<1>).unwrap();
    let e = check(&Tilted::<2>).unwrap_err();
    assert!(
        matches!(&e, DeclarationError::NotUnit { what, length, .. } if what == "mirror 0" && (length - 2f64.sqrt()).abs() < 1e-15),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("`tilted`: mirror 0 has the normal [0.0, 1.0, 1.0]"),
        "{e}"
    );
}
