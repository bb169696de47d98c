//! The generator's independent derivation paths agree, and the emitted kernels are the
//! expression graph the generator traced.

use integration_tests::{all_confinements, confinement, flat, placed, sample_params};
use kernel_gen::catalog::variants;
use kernel_gen::kernel::{trace, Drift, Interaction};
use kernel_gen::number::dd::Dd;
use kernel_gen::number::jet::Layout;
use kernel_gen::physics::derivatives::{GenericJets, Part, Structured};
use kernel_gen::physics::fd::FiniteDifferences;
use kernel_gen::physics::green::{free::Free, wall::Wall, Green, Visitor};
use kernel_gen::physics::operators::{Deriv, Derivatives};
use kernels::{
    pair, pair_along, pair_divergence, pair_equal, self_along, self_divergence, self_mobility,
};

/// A unit vector of no special direction, for the derivatives along a direction.
const DIRECTION: [f64; 3] = [0.48, -0.6, 0.64];

fn all_derivs(order: usize) -> Vec<Deriv> {
    let l = Layout::get(6, order);
    let mut v = Vec::new();
    for m in &l.monos {
        for i in 0..3 {
            for j in 0..3 {
                v.push(Deriv {
                    i,
                    j,
                    dx: [m[0], m[1], m[2]],
                    dy: [m[3], m[4], m[5]],
                });
            }
        }
    }
    v
}

/// Jets of the Stokeslet against central finite differences in double-double, every
/// derivative up to order 4 in (x, y). Tolerance 1e-7 relative to the largest
/// derivative of the same order: the stencils are second-order accurate with step
/// 1e-4 (truncation ~1e-8 relative), and double-double round-off is ~1e-32 / h^4 = 1e-16.
#[test]
fn stokeslet_jets_agree_with_double_double_finite_differences() {
    let x = [0.4, -0.3, 1.1];
    let y = [-0.5, 0.6, 0.2];
    let order = 4;
    let mut jets = GenericJets::new(&Free, Part::Stokeslet, &x, &y, &[], order);
    let mut fd = FiniteDifferences::new(&Free, Part::Stokeslet, x, y, &[], 1e-4);
    for n in 0..=order {
        let ds: Vec<Deriv> = all_derivs(order)
            .into_iter()
            .filter(|d| d.order() == n)
            .collect();
        let vals: Vec<(f64, f64)> = ds
            .iter()
            .map(|d| (jets.get(d), fd.get(d).to_f64()))
            .collect();
        let scale = vals.iter().map(|v| v.0.abs()).fold(0.0, f64::max);
        for (d, (j, f)) in ds.iter().zip(&vals) {
            assert!(
                (j - f).abs() <= 1e-7 * scale,
                "{d:?}: jet {j:e} vs finite difference {f:e} (scale {scale:e})"
            );
        }
    }
}

/// The structured path (jets of r and 1/r, Eq. 10 for the image, each image term in
/// its mirror's frame) and the generic six-variable jets of the whole G(x, y) agree on
/// every derivative up to order 6, for every registered Green's function (pair, and
/// self for those with a reflected field), at its example parameters with the points
/// placed relative to its first boundary. Both are exact up to round-off; 1e-11
/// relative to the largest derivative of the same order covers the round-off of
/// sixth derivatives (a few hundred operations each).
#[test]
fn structured_and_generic_six_variable_paths_agree() {
    struct Paths {
        checked: Vec<String>,
    }
    impl Visitor for Paths {
        fn visit<G: Green>(&mut self, g: &G) {
            let p = sample_params(g.name());
            let conf = confinement(g.name(), &p);
            let bounded = !conf.boundaries().is_empty();
            // x3 = 1.1 and 2.2 along the first boundary's normal
            let (x, y) = (
                placed(&conf, [0.4, -0.3, 1.1]),
                placed(&conf, [-0.5, 0.6, 2.2]),
            );
            let order = 6;
            type Pair<'a> = Box<dyn FnMut(&Deriv) -> (f64, f64) + 'a>;
            let mut cases: Vec<(&str, Pair)> = vec![("pair", {
                let mut s = Structured::new(g, &x, &y, &p, order, true, true);
                let mut j = GenericJets::new(g, Part::Full, &x, &y, &p, order);
                Box::new(move |d| (s.get(d), j.get(d)))
            })];
            if bounded {
                cases.push(("self", {
                    let mut s = Structured::new(g, &y, &y, &p, order, false, true);
                    let mut j = GenericJets::new(g, Part::Reflected, &y, &y, &p, order);
                    Box::new(move |d| (s.get(d), j.get(d)))
                }));
            }
            for (kind, mut f) in cases {
                for n in 0..=order {
                    let ds: Vec<Deriv> = all_derivs(order)
                        .into_iter()
                        .filter(|d| d.order() == n)
                        .collect();
                    let vals: Vec<(f64, f64)> = ds.iter().map(&mut f).collect();
                    let scale = vals.iter().map(|v| v.1.abs()).fold(0.0, f64::max);
                    for (d, (s, j)) in ds.iter().zip(&vals) {
                        assert!(
                            (s - j).abs() <= 1e-11 * scale,
                            "{} {kind} {d:?}: structured {s:e} vs generic {j:e} (scale {scale:e})",
                            g.name()
                        );
                    }
                }
                self.checked.push(format!("{} {kind}", g.name()));
            }
        }
    }
    let mut v = Paths { checked: vec![] };
    kernel_gen::physics::green::for_each(&mut v);
    println!("structured = generic: {}", v.checked.join(", "));
    // a pair for every confinement the dispatch lists, a self term for every bounded one
    let confs = all_confinements();
    let bounded = confs.iter().filter(|(_, c)| !c.boundaries().is_empty());
    assert_eq!(v.checked.len(), confs.len() + bounded.count());
}

/// The emitted kernels and the graph interpreter agree to a few ulps (they perform the
/// same operations in the same order; Rust does not contract to fused multiply-adds,
/// so the expected difference is zero, and 4 ulps allows for `powi`). The interpreter
/// runs the kernel as emitted (`Traced::eval`: the exchange of roles, then the branch
/// its condition selects, such as the closed-form self term wherever the centre is in
/// the fluid), with either particle of the pair the higher one.
struct EmittedVsInterpreted {
    checked: usize,
}

impl Visitor for EmittedVsInterpreted {
    fn visit<G: Green>(&mut self, g: &G) {
        let p = sample_params(g.name());
        let conf = confinement(g.name(), &p);
        // x3 = 2.3 and 1.6 along the first boundary's normal, in the fluid; either
        // particle the higher one (the wall's pair kernels exchange roles where b is)
        let (hi, lo) = (
            placed(&conf, [0.7, -0.4, 2.3]),
            placed(&conf, [-1.1, 0.9, 1.6]),
        );
        let (aa, ab, eta) = (0.8, 0.55, 1.3);
        for v in variants() {
            let traced = trace(g, &v.spec);
            for (xa, xb) in [(hi, lo), (lo, hi)] {
                let mut inputs: Vec<f64> = xa.to_vec();
                // the kernel the variant was emitted as, through the public dispatch
                let got: Vec<f64> = match (v.spec.interaction, v.spec.equal_radii, v.spec.drift) {
                    (Interaction::SelfTerm, _, None) => {
                        inputs.extend([aa, eta]);
                        flat(&self_mobility(&conf, eta, xa, aa))
                    }
                    (Interaction::SelfTerm, _, Some(Drift::Divergence)) => {
                        inputs.extend([aa, eta]);
                        self_divergence(&conf, eta, xa, aa).a.to_vec()
                    }
                    (Interaction::SelfTerm, _, Some(Drift::Along)) => {
                        inputs.extend([aa, eta]);
                        self_along(&conf, eta, xa, aa, DIRECTION).a.to_vec()
                    }
                    (_, _, Some(Drift::Together)) => {
                        unreachable!("no family kernel moves both points together (a scene's)")
                    }
                    (Interaction::Pair, true, _) => {
                        inputs.extend(xb);
                        inputs.extend([aa, eta]);
                        flat(&pair_equal(&conf, eta, xa, xb, aa))
                    }
                    (Interaction::Pair, false, None) => {
                        inputs.extend(xb);
                        inputs.extend([aa, ab, eta]);
                        flat(&pair(&conf, eta, xa, aa, xb, ab))
                    }
                    (Interaction::Pair, false, Some(Drift::Divergence)) => {
                        inputs.extend(xb);
                        inputs.extend([aa, ab, eta]);
                        let d = pair_divergence(&conf, eta, xa, aa, xb, ab);
                        d.a.iter().chain(&d.b).copied().collect()
                    }
                    (Interaction::Pair, false, Some(Drift::Along)) => {
                        inputs.extend(xb);
                        inputs.extend([aa, ab, eta]);
                        let d = pair_along(&conf, eta, xa, aa, xb, ab, DIRECTION);
                        d.a.iter().chain(&d.b).copied().collect()
                    }
                };
                inputs.extend(&p);
                if v.spec.drift == Some(Drift::Along) {
                    inputs.extend(DIRECTION);
                }
                let want: Vec<f64> = traced.eval(&inputs);
                assert_eq!(got.len(), want.len());
                for (k, (a, b)) in got.iter().zip(&want).enumerate() {
                    let ulps = (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
                    assert!(
                        ulps <= 4 || a == b,
                        "{}_{} at {xa:?}, {xb:?}, output {k}: emitted {a:e} vs interpreted {b:e} ({ulps} ulps)",
                        g.name(),
                        v.suffix
                    );
                }
            }
            self.checked += 1;
        }
    }
}

#[test]
fn emitted_kernels_equal_the_interpreted_graph() {
    let mut v = EmittedVsInterpreted { checked: 0 };
    kernel_gen::physics::green::for_each(&mut v);
    assert_eq!(v.checked, all_confinements().len() * variants().len());
}

/// The interpreter in double-double on the same graph measures the f64 kernels'
/// round-off: a sanity bound of 1e-12 relative per block at a generic configuration.
#[test]
fn wall_pair_round_off_against_double_double_interpreter() {
    let v = &variants()[1];
    assert_eq!(v.suffix, "pair");
    let traced = trace(&Wall, &v.spec);
    let inputs = [0.7, -0.4, 2.3, -1.1, 0.9, 1.6, 0.8, 0.55, 1.3, 0.3];
    let f: Vec<f64> = traced.graph.eval(&inputs, &traced.output_ids());
    let d: Vec<Dd> = traced
        .graph
        .eval(&inputs.map(Dd::new), &traced.output_ids());
    let d: Vec<f64> = d.iter().map(|x| x.to_f64()).collect();
    let e = integration_tests::rel_diff(&f, &d);
    assert!(e < 1e-12, "relative round-off {e:e}");
}
