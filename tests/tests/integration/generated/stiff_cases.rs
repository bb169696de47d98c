//! The stiff and extreme cases (`integration_tests::stiff`, which measures them):
//! every block of every kernel the solver links, for every confinement, against a
//! double-double evaluation of the direct sum, norm-wise per block.
//!
//! Every case keeps [`TOL`] = 1e-10. Each row also records the plain direct sum
//! evaluated in `f64` (`StiffRow::direct_sum`): what the kernels would lose without
//! the generator's stable forms.
//!
//! Measured before and after the exactly evaluated Stokeslet-minus-image difference
//! and the exchange of roles (`kernel_gen::physics::derivatives::Structured`,
//! `kernel_gen::kernel::Swap`): a wall pair with very unequal heights just below the
//! switch to the lateral far field lost `eps rho^2 / (h_a h_b)`, 2.8e-9 for
//! `product_f` at heights 2 and 3000, `rho = 0.99 * switch` (the plain direct sum
//! loses 0.75 at heights 1 and 1e6); after, 5.1e-14 at any ratio of the heights up to
//! 1e8. The reference had to become exact for this: the expression graph evaluated in
//! double-double carries its `f64` constants (the jet rules' weights such as 1/3),
//! which left 3.3e-9 of the `us` block at heights 1 and 1e8 with the lower particle
//! as the field particle (the generic six-variable path, reciprocity and
//! `kernel_gen::kernel::evaluate_direct` all agree that the kernel was right there).
//!
//! Measured before and after the exact operator coefficients and the closed-form self
//! term (`cargo test --release -p integration-tests -- generated::stiff_cases
//! --nocapture`):
//!
//! - lateral (wall FTS pair, blocks other than `uf`, `rho/h = 1e8`): 9.8e-9 before,
//!   the operators' `f64` coefficients (`1/sqrt 6`, `1/6`, the jet rules' weights)
//!   leaving exact cancellations of the `1/rho^2` terms at 1e-17 of their size; about
//!   1e-15 after (`kernel_gen::physics::operators::exact_block`, `kernel_gen::physics::farfield`).
//! - height (self `ul`/`of`, wall 3.8e-8 at `h/a = 1e4`, slit 0.66 at `h/a = 1e8`):
//!   the reflected self term's `O(1/h^2)` terms cancelling to `O(a^2/h^4)`; about
//!   1e-15 after (`kernel_gen::physics::self_image`: the self term in closed form).
//!
//! Before the lateral far-field rule, wall pair kernels lost up to 0.75 (`product_f`,
//! `rho/h = 1e8`, heights 2 and 30).

use integration_tests::all_confinements;
use integration_tests::stiff::{
    block_errors, case, evaluate, stiff_cases, Kind, StiffRow, KINDS, TOL,
};
use kernel_gen::kernel::{evaluate_direct, trace};
use kernel_gen::number::dd::Dd;
use kernel_gen::physics::green::{Green, Visitor};
use std::collections::BTreeMap;

#[test]
fn generated_kernels_keep_1e_10_in_the_stiff_cases() {
    let rows = stiff_cases();
    // worst error per (case, confinement)
    let mut worst: BTreeMap<(&str, &str), (&StiffRow, f64)> = BTreeMap::new();
    for r in &rows {
        let w = worst
            .entry((r.case, r.confinement.as_str()))
            .or_insert((r, 0.0));
        if r.error.is_nan() || r.error > w.0.error {
            w.0 = r;
        }
        w.1 = w.1.max(r.direct_sum);
    }
    println!("worst norm-wise relative error per block, against double-double:");
    println!(
        "{:<13} {:<13} {:>9} {:>11}  where",
        "case", "confinement", "error", "direct sum"
    );
    for ((case, conf), (r, direct)) in &worst {
        println!(
            "{case:<13} {conf:<13} {:>9.1e} {direct:>11.1e}  {} [{}] ({:.0e})",
            r.error, r.kernel, r.block, r.parameter
        );
    }
    let failures: Vec<String> = rows
        .iter()
        .filter(|r| r.error.is_nan() || r.error > TOL)
        .map(|r| {
            format!(
                "{} {} {} [{}]: {:.1e}",
                r.case, r.confinement, r.kernel, r.block, r.error
            )
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} blocks lose more than {TOL:e}:\n{}",
        failures.len(),
        failures.join("\n")
    );
    // the cases are stiff: the plain direct sum loses far more than TOL in some (so
    // the test would catch a kernel that fell back to it)
    let plain = rows.iter().map(|r| r.direct_sum).fold(0.0, f64::max);
    assert!(plain > 1e-3, "the plain direct sum loses only {plain:e}");
}

/// Both branches of every kernel with a second branch, evaluated by the interpreter,
/// agree with the double-double direct sum, and the emitted kernel is the branch its
/// condition selects (same operations in the same order: equal up to 4 ulps, as in
/// `generated::engine`; for a twin, `kernels::turn`, up to its rotation's rounding):
///
/// - the lateral far field (wall pairs), on both sides of the switch
///   (`rho^2 = 2 SWITCH^2 (h_a^2 + h_b^2)`, from 0.3 to 3 times it): to 1e-10, so
///   continuous there to 2e-10;
/// - the closed-form self term (every confinement with images) at heights from
///   `1 + 1e-12` to 1e8 radii: the closed form to 1e-10 everywhere; the direct sum to
///   1e-10 up to `h/a = 1e2` (beyond, it loses `eps (h/a)^2`, which is why the kernel
///   does not take it there).
#[test]
fn second_branches_are_accurate_and_continuous() {
    struct Switch {
        pairs: usize,
        selfs: usize,
        worst: f64,
    }
    fn check<G: Green>(
        g: &G,
        kind: Kind,
        traced: &kernel_gen::kernel::Traced,
        c: &integration_tests::stiff::Case,
        far: bool,
        direct_tol: f64,
    ) -> f64 {
        let conf = c.confinement(g.name());
        let (got, inputs) = evaluate(kind, &conf, c);
        let dd: Vec<Dd> = inputs.iter().map(|&x| Dd::new(x)).collect();
        let want: Vec<Dd> = evaluate_direct(g, &kind.reference(), &dd);
        let inputs = kind.kernel_inputs(&inputs);
        assert_eq!(traced.takes_far(&inputs), far, "{} {}", g.name(), c.label);
        let interpreted: Vec<f64> = traced.eval(&inputs);
        if conf.served().1.is_some() {
            // a twin (`kernels::turn`): its kernel is the serving family's, the blocks
            // rotated back at run time, so it equals the trace with the rotation folded
            // in up to that rotation's rounding: each entry a sum of at most 25 products
            // (weights at most 1, two roundings each) of entries no larger than the
            // block's norm, 50 eps of it; 64 eps bounds that
            let exact: Vec<Dd> = interpreted.iter().map(|&x| Dd::new(x)).collect();
            for (block, e) in block_errors(traced, &got, &exact) {
                assert!(
                    e <= 64.0 * f64::EPSILON,
                    "{} {} [{block}]: the twin's rotation lost {e:e}",
                    kind.name(),
                    c.label
                );
            }
        } else {
            for (k, (a, b)) in got.iter().zip(&interpreted).enumerate() {
                let ulps = (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
                assert!(
                    ulps <= 4 || a == b,
                    "{} {} output {k}",
                    kind.name(),
                    c.label
                );
            }
        }
        let mut worst: f64 = 0.0;
        for (ids, tol) in [(traced.output_ids(), direct_tol), (traced.far_ids(), TOL)] {
            let branch: Vec<f64> = traced.graph.eval(&inputs, &ids);
            for (block, e) in block_errors(traced, &branch, &want) {
                assert!(
                    e <= tol,
                    "{} {} {} [{block}]: {e:e}",
                    g.name(),
                    kind.name(),
                    c.label
                );
                if tol.is_finite() {
                    worst = worst.max(e);
                }
            }
        }
        worst
    }
    impl Visitor for Switch {
        fn visit<G: Green>(&mut self, g: &G) {
            for kind in KINDS {
                let traced = trace(g, &kind.kernel_spec());
                if traced.far.is_none() {
                    continue;
                }
                if kind.is_self() {
                    for h in [1.0 + 1e-12, 1.5, 1e2, 1e4, 1e6, 1e8] {
                        let c = case(
                            "height",
                            format!("h/a={h:e}"),
                            h,
                            0.3,
                            [0.2, -0.1, 0.3 + h],
                            1.0,
                            [0.0; 3],
                            1.0,
                            1.3,
                            true,
                            false,
                        );
                        let direct = if h <= 1e2 { TOL } else { f64::INFINITY };
                        self.worst = self.worst.max(check(g, kind, &traced, &c, true, direct));
                        self.selfs += 1;
                    }
                    continue;
                }
                for (ha, hb) in [(1.5, 1.5), (1.2, 4.0), (2.0, 30.0)] {
                    for f in [0.3, 0.9, 0.99, 1.01, 1.1, 3.0] {
                        let (h2, s) = (ha * ha + hb * hb, kernel_gen::physics::farfield::SWITCH);
                        let rho = f * (2.0 * s * s * h2).sqrt();
                        let ab = if kind == Kind::PairEqualFts { 1.0 } else { 0.7 };
                        let c = case(
                            "lateral",
                            format!("f={f} h={ha},{hb}"),
                            rho / ha.min(hb),
                            0.3,
                            [0.2, -0.1, 0.3 + ha],
                            1.0,
                            [
                                0.2 + rho * 0.6f64.cos(),
                                -0.1 + rho * 0.6f64.sin(),
                                0.3 + hb,
                            ],
                            ab,
                            1.3,
                            false,
                            true,
                        );
                        self.worst = self.worst.max(check(g, kind, &traced, &c, f > 1.0, TOL));
                        self.pairs += 1;
                    }
                }
            }
        }
    }
    let mut s = Switch {
        pairs: 0,
        selfs: 0,
        worst: 0.0,
    };
    kernel_gen::physics::green::for_each(&mut s);
    println!(
        "switch: {} pair and {} self configurations, worst error of either branch {:.1e}",
        s.pairs, s.selfs, s.worst
    );
    // every kernel that should have a second branch has one, counted from the
    // declarations: the lateral far field where an image cancels the Stokeslet on its
    // plane (the pair kernels exchange roles along its normal, and the direct sum
    // cancels laterally): the FTS pair and pair_equal, F and FT pair and product
    // kernels, 3 pairs of heights, 6 distances; the closed-form self term wherever
    // there is a boundary: self_mobility, self_f, self_ft, 6 heights
    let confs = all_confinements();
    let cancelling = confs
        .iter()
        .filter(|(_, c)| c.exchange_normal().is_some())
        .count();
    let bounded = confs
        .iter()
        .filter(|(_, c)| !c.boundaries().is_empty())
        .count();
    assert!(cancelling > 0 && bounded > 0);
    assert_eq!(s.pairs, cancelling * 6 * 3 * 6);
    assert_eq!(s.selfs, bounded * 3 * 6);
}
