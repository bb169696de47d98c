//! Bad input gets a typed error with a clear message, never a panic and never a
//! partial result.

use integration_tests::{all_confinements, over, WALL};
use kernels::Dimension;
use stokesian::{
    strain_components, Confinement, InputError, Lubrication, Moments, Particle, ResistanceError,
    System, VelocityError,
};

fn p(x: [f64; 3], a: f64) -> Particle {
    Particle { x, a }
}

fn err(conf: Confinement, eta: f64, ps: &[Particle]) -> InputError {
    System::new(conf, eta, ps.to_vec(), false).expect_err("input must be rejected")
}

#[test]
fn each_bad_input_is_named() {
    let good = p([0.0, 0.0, 2.0], 1.0);
    let cases: Vec<(InputError, &str)> = vec![
        (err(WALL, 1.0, &[]), "no particles given"),
        (
            err(WALL, 1.0, &[good, p([5.0, f64::NAN, 2.0], 1.0)]),
            "particle 1: coordinate y is NaN, not a finite number",
        ),
        (
            err(WALL, 1.0, &[p([0.0, 0.0, f64::INFINITY], 1.0)]),
            "particle 0: coordinate z is inf, not a finite number",
        ),
        (
            err(WALL, 1.0, &[good, p([5.0, 0.0, 2.0], -1.0)]),
            "particle 1: radius -1 must be a positive finite number",
        ),
        (err(WALL, 1.0, &[p([0.0, 0.0, 2.0], 0.0)]), "particle 0: radius 0 must be a positive finite number"),
        (err(WALL, 0.0, &[good]), "viscosity 0 must be a positive finite number"),
        (err(WALL, f64::NAN, &[good]), "viscosity NaN must be a positive finite number"),
        (
            err(WALL, 1.0, &[p([0.0, 0.0, -0.5], 0.2)]),
            "particle 0: centre is not inside the fluid: signed distance -0.5 from the boundary, no slip at x3 = 0 (fluid where x3 > 0)",
        ),
        (
            err(WALL, 1.0, &[p([0.0, 0.0, 0.0], 0.2)]),
            "particle 0: centre is not inside the fluid: signed distance 0 from the boundary, no slip at x3 = 0 (fluid where x3 > 0)",
        ),
        (
            err(WALL, 1.0, &[p([0.0, 0.0, 0.5], 1.0)]),
            "particle 0: sphere of radius 1 overlaps the boundary, no slip at x3 = 0 (fluid where x3 > 0) (centre-to-boundary distance 0.5)",
        ),
        (
            err(WALL, 1.0, &[good, p([1.5, 0.0, 2.0], 1.0)]),
            "particles 0 and 1 overlap: centre distance 1.5 < sum of radii 2",
        ),
        (
            err(Confinement::Slit { height: 0.0, gap: 3.0 }, 1.0, &[p([0.0, 0.0, 2.5], 1.0)]),
            "particle 0: sphere of radius 1 overlaps the boundary, no slip at x3 = 3 (fluid where x3 < 3, approximately) (centre-to-boundary distance 0.5)",
        ),
    ];
    for (e, msg) in cases {
        assert_eq!(e.to_string(), msg);
    }
}

/// Every declared parameter of every confinement is checked by its dimension, the
/// others at their example values: a position must be finite, a length positive and
/// finite, a pure number (a viscosity ratio) non-negative and finite; the error names
/// the parameter.
#[test]
fn every_declared_parameter_is_checked_by_its_dimension() {
    let good = p([0.0, 0.0, 2.0], 1.0);
    let mut checked = 0;
    for decl in kernels::DECLARATIONS {
        for (k, param) in decl.params.iter().enumerate() {
            let bad: &[(f64, &str)] = match param.dimension {
                Dimension::Position(_) => &[
                    (f64::NAN, "must be a finite number"),
                    (f64::NEG_INFINITY, "must be a finite number"),
                ],
                Dimension::Length => &[
                    (-3.0, "a length must be a positive finite number"),
                    (0.0, "a length must be a positive finite number"),
                    (f64::INFINITY, "a length must be a positive finite number"),
                ],
                Dimension::Number => &[
                    (-1.0, "a ratio must be a non-negative finite number"),
                    (f64::NAN, "a ratio must be a non-negative finite number"),
                ],
            };
            for &(value, why) in bad {
                let mut values: Vec<f64> = decl.params.iter().map(|q| q.example).collect();
                values[k] = value;
                let conf = Confinement::from_name(decl.name, &values).expect("declared");
                assert_eq!(
                    err(conf, 1.0, &[good]).to_string(),
                    format!("{} = {value}: {why}", param.name),
                    "{}",
                    decl.name
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 0);
}

/// Every boundary of every confinement, whatever its normal, rejects a centre on or
/// beyond its plane and a sphere that cuts it, naming that boundary, and accepts a
/// sphere clear of it (spheres of radius 1 at heights -0.5, 0, 0.5 and 2 over the
/// plane, along its normal; the example parameters keep the other planes away).
#[test]
fn every_boundary_rejects_centres_beyond_it_and_spheres_that_cut_it() {
    let mut checked = 0;
    for (name, conf) in all_confinements() {
        for b in conf.boundaries() {
            let at = |h: f64| [p(over(Some(&b), [0.3, -0.2], h), 1.0)];
            for h in [-0.5, 0.0] {
                match err(conf, 1.0, &at(h)) {
                    InputError::OutsideFluid {
                        index: 0, boundary, ..
                    } => assert_eq!(boundary, b, "{name} at {h}"),
                    e => panic!("{name}: a centre at {h} from {b}: {e}"),
                }
            }
            match err(conf, 1.0, &at(0.5)) {
                InputError::OverlapsBoundary {
                    index: 0,
                    boundary,
                    distance,
                    ..
                } => {
                    assert_eq!(boundary, b, "{name}");
                    // the plane's offset and the height rounded in placing the centre
                    assert!((distance - 0.5).abs() < 1e-12, "{name}: {distance}");
                }
                e => panic!("{name}: a sphere cutting {b}: {e}"),
            }
            System::new(conf, 1.0, at(2.0).to_vec(), false)
                .unwrap_or_else(|e| panic!("{name}: a sphere clear of {b}: {e}"));
            checked += 1;
        }
    }
    // every boundary the dispatch declares
    let declared: usize = all_confinements()
        .iter()
        .map(|(_, c)| c.boundaries().len())
        .sum();
    assert!(declared > 0);
    assert_eq!(checked, declared);
}

#[test]
fn valid_input_gives_the_full_matrix() {
    let ps = [p([0.0, 0.0, 2.0], 1.0), p([3.0, 0.0, 2.0], 0.5)];
    let m = System::new(WALL, 1.0, ps.to_vec(), false)
        .unwrap()
        .mobility(Moments::FTS);
    assert_eq!(m.shape(), (22, 22));
    let m = System::new(WALL, 1.0, ps.to_vec(), false)
        .unwrap()
        .mobility(Moments::FT);
    assert_eq!(m.shape(), (12, 12));
    let m = System::new(WALL, 1.0, ps.to_vec(), false)
        .unwrap()
        .mobility(Moments::F);
    assert_eq!(m.shape(), (6, 6));
    // layout: all U, then all Omega; M_UL^{01} = (M_OmegaF^{10})^T
    let ft = System::new(WALL, 1.0, ps.to_vec(), false)
        .unwrap()
        .mobility(Moments::FT);
    let n = 2;
    for i in 0..3 {
        for j in 0..3 {
            let ul01 = ft[(i, 3 * n + 3 + j)];
            let of10 = ft[(3 * n + 3 + j, i)];
            assert_eq!(ul01, of10);
        }
    }
}

/// The matrix-free product equals the dense matrix times the vector (same kernels,
/// different summation order: 1e-13 relative).
#[test]
fn matrix_free_product_equals_dense() {
    let ps = vec![
        p([0.0, 0.0, 2.0], 1.0),
        p([3.0, 0.5, 2.5], 0.5),
        p([-1.0, 3.0, 1.6], 1.0),
    ];
    for moments in [Moments::F, Moments::FT, Moments::FTS] {
        let s = System::new(WALL, 1.3, ps.clone(), false).unwrap();
        let m = s.mobility(moments);
        let x: Vec<f64> = (0..m.ncols()).map(|k| ((k * 7 % 5) as f64) - 1.7).collect();
        let dense = &m * nalgebra::DVector::from_column_slice(&x);
        let free = s.apply(moments, &x);
        let d: f64 = dense
            .iter()
            .zip(&free)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(d <= 1e-13 * dense.norm(), "{moments:?}: {d:e}");
    }
}

/// A number from the corners of double precision, or any at all.
fn nasty() -> impl proptest::strategy::Strategy<Value = f64> {
    use proptest::prelude::*;
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(5e-324),
        Just(1e-310),
        Just(1e-301),
        Just(f64::MIN_POSITIVE),
        Just(1e308),
        Just(-1e308),
        Just(f64::MAX),
        -4.0..4.0,
        0.5..3.0,
        any::<f64>(),
    ]
}

/// Any registered confinement with any parameters.
fn confinement() -> impl proptest::strategy::Strategy<Value = Confinement> {
    use proptest::prelude::*;
    proptest::sample::select(kernels::DECLARATIONS).prop_flat_map(|d| {
        proptest::collection::vec(nasty(), d.params.len())
            .prop_map(move |p| Confinement::from_name(d.name, &p).expect("declared"))
    })
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 2000, ..Default::default() })]

    /// Any numbers as coordinates, radii, viscosity and confinement parameters: a typed
    /// error or a valid system, never a panic; a valid system's matrix has its shape and
    /// the radii and scales the validation promises.
    #[test]
    fn system_new_never_panics(
        conf in confinement(),
        eta in nasty(),
        coords in proptest::collection::vec((nasty(), nasty(), nasty(), nasty()), 0..4),
        allow_overlap in proptest::bool::ANY,
    ) {
        let ps: Vec<Particle> = coords.iter().map(|&(x, y, z, a)| p([x, y, z], a)).collect();
        match System::new(conf, eta, ps.clone(), allow_overlap) {
            Err(e) => proptest::prop_assert!(!e.to_string().is_empty()),
            Ok(s) => {
                for q in s.particles() {
                    let scale = eta * q.a * q.a * q.a;
                    proptest::prop_assert!(q.a > 0.0 && scale.is_normal() && scale.recip().is_normal());
                    proptest::prop_assert!(q.x.iter().all(|v| v.is_finite()));
                }
                let m = s.mobility(Moments::F);
                proptest::prop_assert_eq!(m.shape(), (3 * ps.len(), 3 * ps.len()));
            }
        }
    }
}

/// The nastiest inputs found: a unit-scale mistake, scales at the edge of double
/// precision, and centres that coincide (an error even with overlaps allowed).
#[test]
fn corpus_of_extreme_inputs() {
    let unrepresentable = [
        (1e-301, 1.0),
        (1e-110, 1.0),
        (1e110, 1.0),
        (1.0, 1e-310),
        (1.0, 5e-324),
        (1e-100, 1e-20),
    ];
    for (a, eta) in unrepresentable {
        let e = System::new(WALL, eta, vec![p([0.0, 0.0, 3.0 * a], a)], false)
            .expect_err("unrepresentable scale");
        assert!(
            matches!(e, InputError::Unrepresentable { index: 0, .. }),
            "a = {a}, eta = {eta}: {e}"
        );
        assert!(e.to_string().contains("other units"), "{e}");
    }
    // the edges that are still representable
    for (a, eta) in [(1e-100, 1.0), (1e100, 1.0), (1.0, 1e300)] {
        System::new(WALL, eta, vec![p([0.0, 0.0, 3.0 * a], a)], false)
            .unwrap_or_else(|e| panic!("a = {a}, eta = {eta}: {e}"));
    }
    let same = vec![
        p([1.0, 2.0, 3.0], 1.0),
        p([5.0, 0.0, 3.0], 1.0),
        p([1.0, 2.0, 3.0], 0.5),
    ];
    for allow in [false, true] {
        let e = System::new(WALL, 1.0, same.clone(), allow).expect_err("same centre");
        let want = if allow {
            "particles 0 and 2 have the same centre; the mobility is undefined"
        } else {
            "particles 0 and 2 overlap: centre distance 0 < sum of radii 1.5"
        };
        assert_eq!(e.to_string(), want);
    }
    // -0 and +0 are the same point, whatever lies between them in sorted order
    let signed = vec![
        p([-0.0, 1.0, 3.0], 0.1),
        p([0.0, 0.0, 3.0], 0.1),
        p([0.0, 1.0, 3.0], 0.1),
    ];
    let e = System::new(WALL, 1.0, signed, true).expect_err("same centre");
    assert_eq!(
        e,
        InputError::SameCentre {
            first: 0,
            second: 2
        }
    );
}

#[test]
fn strain_components_are_the_basis_projections_and_checked() {
    // E = B_4 (e1e1 - e2e2)/sqrt2 scaled by 3: components (0, 0, 0, 3, 0)
    let r = 3.0 / 2f64.sqrt();
    let e = [[r, 0.0, 0.0], [0.0, -r, 0.0], [0.0, 0.0, 0.0]];
    let c = strain_components(&e).unwrap();
    assert!((c[3] - 3.0).abs() < 1e-15 && c.iter().enumerate().all(|(m, v)| m == 3 || *v == 0.0));
    let mut bad = e;
    bad[0][1] = 1.0;
    assert!(matches!(
        strain_components(&bad),
        Err(VelocityError::NotSymmetricTraceless(_))
    ));
    assert!(matches!(
        strain_components(&[[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]),
        Err(VelocityError::NotSymmetricTraceless(_))
    ));
}

#[test]
fn velocities_refuse_bad_input() {
    let p = |z| Particle {
        x: [0.0, 0.0, z],
        a: 1.0,
    };
    let s = System::new(
        kernels::Confinement::Wall { height: 0.0 },
        1.0,
        vec![p(2.0)],
        false,
    )
    .unwrap();
    let e0 = [0.0; 5];
    assert!(matches!(
        s.velocities(Moments::F, &[1.0; 4], &e0, None),
        Err(VelocityError::Length {
            expected: 3,
            found: 4,
            ..
        })
    ));
    assert!(matches!(
        s.velocities(Moments::F, &[1.0, f64::NAN, 0.0], &e0, None),
        Err(VelocityError::NonFinite { index: 1, .. })
    ));
    assert!(matches!(
        s.velocities(Moments::FT, &[0.0; 6], &[1.0, 0.0, 0.0, 0.0, 0.0], None),
        Err(VelocityError::StrainWithoutStresslets(Moments::FT))
    ));
    assert!(matches!(
        s.velocities(Moments::F, &[0.0; 3], &e0, Some(&Lubrication::default())),
        Err(VelocityError::Resistance(ResistanceError::Unsupported(
            Moments::F
        )))
    ));
    // F without lubrication is M x
    let u = s
        .velocities(Moments::F, &[1.0, 0.0, 0.0], &e0, None)
        .unwrap();
    assert_eq!(u.u, s.apply(Moments::F, &[1.0, 0.0, 0.0]));
}
