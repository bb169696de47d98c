//! The stiff and extreme cases: the round-off of the generated f64 kernels, measured
//! against a double-double reference, for every confinement and every kernel the
//! solver links (FTS `pair`, `pair_equal`, `self_mobility`; the F and FT scene kernels
//! `pair_f`, `self_f`, `product_f`, `pair_ft`, `self_ft`, `product_ft`):
//!
//! - `lateral`: lateral separation over height `rho/h` from 1e2 to 1e8 (equal,
//!   different and very unequal heights, `h_b/h_a` from 1e-3 to 1e8 around the switch
//!   to the far field): near a no-slip wall the Stokeslet and its image each decay
//!   like `1/rho` but their sum like `h_a h_b / rho^3`;
//! - `gap`: gaps to the wall and between spheres down to 1e-12 a;
//! - `radius ratio`: radius ratios up to 1e3;
//! - `height`: heights from 1 to 1e8 a, where every confinement must tend to free
//!   space;
//! - `scale`: the same configurations at a = 1e-9 m with eta = 1e-3 Pa s (the others
//!   are at a = 1, eta = 1).
//!
//! The reference is the direct sum of the same kernel, evaluated straight in
//! double-double from the Green's function (`kernel_gen::kernel::evaluate_direct`, every
//! rational weight exact; not the expression graph, whose constants are `f64`): about
//! 32 significant digits, so even where the direct formula loses 16 digits to
//! cancellation (rho/h = 1e8) it keeps 16. It never uses the branches the generator
//! switches to (the lateral far field, `kernel_gen::physics::farfield`; the closed-form self
//! term, `kernel_gen::physics::self_image`) nor the exactly evaluated Stokeslet-minus-image
//! difference of the wall's direct branch (`kernel_gen::physics::derivatives::Structured`):
//! it is the plain sum ([`Kind::reference`]), so it is independent of them.
//!
//! Errors are norm-wise per block, `||K - K_ref||_F / ||K_ref||_F`: entries that
//! vanish by symmetry (e.g. `U_x F_y` for a lateral separation along x) or are small
//! beside the rest of their block carry no relative precision of their own, so an
//! entrywise relative error would be meaningless for them.

use crate::{norm, placed, with_params};
use kernel_gen::catalog::Moments;
use kernel_gen::kernel::{evaluate_direct, trace, Interaction, KernelSpec, Path, Traced};
use kernel_gen::number::dd::Dd;
use kernel_gen::physics::farfield::SWITCH;
use kernel_gen::physics::green::{Green, Visitor};
use kernel_gen::physics::operators::BLOCKS;
use kernels::{BlocksF, BlocksFT, Dimension, Grand};

/// Required accuracy, norm-wise per block.
pub const TOL: f64 = 1e-10;

/// One measured block: the worst is what a report prints.
#[derive(Clone, Debug)]
pub struct StiffRow {
    /// `lateral`, `gap`, `radius ratio`, `height` or `scale`.
    pub case: &'static str,
    /// The confinement (generated family name).
    pub confinement: String,
    /// The kernel's entry point with the configuration, e.g. `pair rho/h=1e8 h=2,30 a=1,1`.
    pub kernel: String,
    /// The block (`uf`, `ul`, ..., or `a`, `b` for the fused products).
    pub block: String,
    /// `rho/h`, `gap/a`, radius ratio, `h/a` or `a`.
    pub parameter: f64,
    /// Norm-wise relative error against the double-double direct sum.
    pub error: f64,
    /// The same for the plain direct sum evaluated in `f64` (the reference's graph,
    /// [`Kind::reference`]): what the kernel would lose without the generator's
    /// stable forms (the exactly evaluated Stokeslet-minus-image difference, the
    /// exchange of roles, the lateral far field, the closed-form self term).
    pub direct_sum: f64,
}

/// One kernel the solver links, by its public entry point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kind {
    /// FTS `self_mobility`.
    SelfFts,
    /// FTS `pair`.
    PairFts,
    /// FTS `pair_equal`.
    PairEqualFts,
    /// `self_f`.
    SelfF,
    /// `pair_f`.
    PairF,
    /// `product_f`.
    ProductF,
    /// `self_ft`.
    SelfFt,
    /// `pair_ft`.
    PairFt,
    /// `product_ft`.
    ProductFt,
}

/// Every kind, in measuring order.
pub const KINDS: [Kind; 9] = [
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
    /// The entry point's name.
    pub fn name(self) -> &'static str {
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

    /// The reference's graph: the same kernel as the plain direct sum of the Stokeslet
    /// and its image ([`Path::StructuredDirectSum`]: no exactly evaluated difference,
    /// no second branch), to be evaluated in double-double.
    pub fn reference(self) -> KernelSpec {
        KernelSpec {
            path: Path::StructuredDirectSum,
            ..self.spec()
        }
    }

    /// Whether it is a self kernel.
    pub fn is_self(self) -> bool {
        matches!(self, Kind::SelfFts | Kind::SelfF | Kind::SelfFt)
    }

    /// The spec the generated kernel of this kind is traced with: [`Kind::spec`], but
    /// `pair_equal` takes one radius (its trace may choose another form than the
    /// two-radius kernel's, so the two agree to rounding, not to the bit).
    pub fn kernel_spec(self) -> KernelSpec {
        KernelSpec {
            equal_radii: self == Kind::PairEqualFts,
            ..self.spec()
        }
    }

    /// The inputs of [`evaluate`] (two radii for every pair) as the kernel of
    /// [`Kind::kernel_spec`] takes them.
    pub fn kernel_inputs(self, inputs: &[f64]) -> Vec<f64> {
        let mut v = inputs.to_vec();
        if self == Kind::PairEqualFts {
            // xa, xb, aa, ab, eta, ...: drop ab
            v.remove(7);
        }
        v
    }

    /// The kernel with two radii for every pair kind (the unequal-radius spec serves
    /// `pair_equal` at equal radii, within rounding; [`Kind::kernel_spec`] is its own).
    pub fn spec(self) -> KernelSpec {
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
            basis: kernel_gen::physics::operators::Basis::Orthonormal,
            equal_radii: false,
            blocks: if moments == Moments::FTS {
                BLOCKS.to_vec()
            } else {
                moments.blocks()
            },
            path: Path::Structured,
            product,
            drift: None,
        }
    }
}

/// One configuration: two spheres (or one, for self kernels) relative to the first
/// boundary plane, written in its frame (`crate::frame_of`: `x3` along its normal;
/// [`Case::placed`] puts them in the world).
#[derive(Clone, Debug)]
pub struct Case {
    /// Which case: `lateral`, `gap`, `radius ratio`, `height` or `scale`.
    pub case: &'static str,
    /// Human-readable configuration.
    pub label: String,
    /// The case's parameter: `rho/h`, `gap/a`, radius ratio, `h/a` or `a`.
    pub parameter: f64,
    /// Offset of the first plane along its normal (every position parameter).
    pub plane: f64,
    /// Centre of particle a (the self kernels' particle), in the plane's frame.
    pub xa: [f64; 3],
    /// Radius of particle a.
    pub aa: f64,
    /// Centre of particle b, in the plane's frame.
    pub xb: [f64; 3],
    /// Radius of particle b.
    pub ab: f64,
    /// Viscosity.
    pub eta: f64,
    /// Every length parameter (a slit's gap: the distance between the walls).
    pub gap: f64,
    /// Whether the self kernels are evaluated (at `xa`, radius `aa`).
    pub with_self: bool,
    /// Whether the pair kernels are evaluated.
    pub with_pair: bool,
    /// Height of `xa` over its radius (self kernels).
    pub h_over_a: f64,
}

impl Case {
    /// The confinement `name` for this case, its parameters by their declared
    /// dimension: every position [`Case::plane`] (the first plane's offset), every
    /// length [`Case::gap`], every pure number its example value.
    pub fn confinement(&self, name: &str) -> kernels::Confinement {
        with_params(name, |p| match p.dimension {
            Dimension::Position(_) => self.plane,
            Dimension::Length => self.gap,
            Dimension::Number => p.example,
        })
    }

    /// The centres `(xa, xb)` in the world, for the confinement `conf`
    /// ([`crate::placed`]).
    pub fn placed(&self, conf: &kernels::Confinement) -> ([f64; 3], [f64; 3]) {
        (placed(conf, self.xa), placed(conf, self.xb))
    }
}

fn flat_grand(g: &Grand) -> Vec<f64> {
    crate::flat(g)
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
/// the graph inputs for the same call (the case placed for `conf`, and its run-time
/// parameters).
pub fn evaluate(kind: Kind, conf: &kernels::Confinement, c: &Case) -> (Vec<f64>, Vec<f64>) {
    let p: Vec<f64> = conf.params().iter().map(|v| v.1).collect();
    let (xa, xb) = c.placed(conf);
    let mut inputs: Vec<f64> = xa.to_vec();
    let got = if kind.is_self() {
        inputs.extend([c.aa, c.eta]);
        match kind {
            Kind::SelfFts => flat_grand(&kernels::self_mobility(conf, c.eta, xa, c.aa)),
            Kind::SelfF => flat_f(&kernels::self_f(conf, c.eta, xa, c.aa)),
            _ => flat_ft(&kernels::self_ft(conf, c.eta, xa, c.aa)),
        }
    } else {
        inputs.extend(xb);
        inputs.extend([c.aa, c.ab, c.eta]);
        let (aa, ab, eta) = (c.aa, c.ab, c.eta);
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
                inputs.extend(&p);
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
                inputs.extend(&p);
                inputs.extend(va.iter().chain(&vb));
                return (pr.a.iter().chain(&pr.b).copied().collect(), inputs);
            }
            _ => unreachable!(),
        }
    };
    inputs.extend(&p);
    (got, inputs)
}

/// Norm-wise relative error per output block (a block whose reference is exactly
/// zero must be exactly zero).
pub fn block_errors(traced: &Traced, got: &[f64], want: &[Dd]) -> Vec<(String, f64)> {
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

/// A case with the first plane at offset `plane` and every length parameter (the slit's
/// gap) wide enough for the spheres (at least 12 a, and three times the highest sphere
/// top above the plane: off the slit's mid-plane, where the two walls' contributions
/// to the coupling blocks cancel by symmetry and a norm-wise relative error would
/// measure nothing but that cancellation). Positions in the plane's frame.
#[allow(clippy::too_many_arguments)]
pub fn case(
    case: &'static str,
    label: String,
    parameter: f64,
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
    Case {
        case,
        label,
        parameter,
        plane,
        xa,
        aa,
        xb,
        ab,
        eta,
        gap,
        with_self,
        with_pair,
        h_over_a: (xa[2] - plane) / aa,
    }
}

/// The case of a configuration: its own, or `scale` for the copies at a = 1e-9 m.
fn which(scale: bool, case: &'static str) -> &'static str {
    if scale {
        "scale"
    } else {
        case
    }
}

/// The configurations of every case at a = 1, eta = 1, and again (case `scale`) at
/// a = 1e-9 m, eta = 1e-3 Pa s.
pub fn cases() -> Vec<Case> {
    let mut v = Vec::new();
    let (c, s) = (0.6f64.cos(), 0.6f64.sin());
    let unit = |a: f64, eta: f64, scale: bool, tag: &str, v: &mut Vec<Case>| {
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
                    which(scale, "lateral"),
                    format!("{tag}rho/h={ratio:.0e} h={ha},{hb} a={aa},{ab}"),
                    if scale { a } else { rho / (ha.min(hb) * a) },
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
        // very unequal heights (h_b/h_a = 1e-3 to 1e8, either particle lower) below and
        // just above the switch to the far field, where the plain direct sum loses
        // eps rho^2/(h_a h_b)
        for (ha, hb) in [
            (1.0, 1000.0),
            (2.0, 3000.0),
            (3000.0, 2.0),
            (1.0, 1e6),
            (1.0, 1e8),
        ] {
            let at = (2.0 * SWITCH * SWITCH * (ha * ha + hb * hb)).sqrt();
            for f in [0.3, 0.9, 0.99, 1.01] {
                let rho = f * at * a;
                v.push(case(
                    which(scale, "lateral"),
                    format!("{tag}rho={f}*switch h={ha},{hb} a=1,1"),
                    if scale { a } else { rho / (ha.min(hb) * a) },
                    plane,
                    [0.2 * a, -0.1 * a, plane + ha * a],
                    a,
                    [0.2 * a + rho * c, -0.1 * a + rho * s, plane + hb * a],
                    a,
                    eta,
                    false,
                    true,
                ));
            }
        }
    };
    let gaps = |a: f64, eta: f64, scale: bool, tag: &str, v: &mut Vec<Case>| {
        let plane = 0.3 * a;
        // b. gaps to the wall (self, and a pair side by side at the wall) and between
        // spheres (along x, along the normal, and oblique)
        for e in [3, 6, 9, 12] {
            let gap = 10f64.powi(-e);
            v.push(case(
                which(scale, "gap"),
                format!("{tag}wall gap={gap:.0e}"),
                if scale { a } else { gap },
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
                    which(scale, "gap"),
                    format!("{tag}pair gap={gap:.0e} {label}"),
                    if scale { a } else { gap },
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
    let ratios = |a: f64, eta: f64, scale: bool, tag: &str, v: &mut Vec<Case>| {
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
                    which(scale, "radius ratio"),
                    format!("{tag}ratio={k:.0e} big_first={big_first} h/a={h}"),
                    if scale { a } else { k },
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
    let heights = |a: f64, eta: f64, scale: bool, tag: &str, v: &mut Vec<Case>| {
        let plane = 0.3 * a;
        // d. heights up to 1e8 a
        for e in [0, 2, 4, 6, 8] {
            let h = 10f64.powi(e) * a;
            v.push(case(
                which(scale, "height"),
                format!("{tag}h/a={:.0e}", h / a),
                if scale { a } else { h / a },
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
    unit(1.0, 1.0, false, "", &mut v);
    gaps(1.0, 1.0, false, "", &mut v);
    ratios(1.0, 1.0, false, "", &mut v);
    heights(1.0, 1.0, false, "", &mut v);
    // the same physics at a = 1e-9 m, eta = 1e-3 Pa s
    let (a, eta) = (1e-9, 1e-3);
    unit(a, eta, true, "nm: ", &mut v);
    gaps(a, eta, true, "nm: ", &mut v);
    ratios(a, eta, true, "nm: ", &mut v);
    heights(a, eta, true, "nm: ", &mut v);
    v
}

/// Every block of every kernel the solver links, for every confinement, in every case:
/// one confinement per task of rayon's pool (the double-double references take most of
/// the time), the rows in the order of [`kernels::Confinement::NAMES`].
pub fn stiff_cases() -> Vec<StiffRow> {
    use rayon::prelude::*;
    kernels::Confinement::NAMES
        .par_iter()
        .map(|name| stiff_cases_of(&|n| n == *name))
        .collect::<Vec<_>>()
        .concat()
}

/// [`stiff_cases`] of the confinements whose name `include` accepts.
pub fn stiff_cases_of(include: &dyn Fn(&str) -> bool) -> Vec<StiffRow> {
    struct Measure<'a> {
        include: &'a dyn Fn(&str) -> bool,
        cases: Vec<Case>,
        rows: Vec<StiffRow>,
    }
    impl Visitor for Measure<'_> {
        fn visit<G: Green>(&mut self, g: &G) {
            if !(self.include)(g.name()) {
                return;
            }
            for kind in KINDS {
                let traced = trace(g, &kind.reference());
                let ids = traced.output_ids();
                for c in &self.cases {
                    if (kind.is_self() && !c.with_self) || (!kind.is_self() && !c.with_pair) {
                        continue;
                    }
                    if kind == Kind::PairEqualFts && c.aa != c.ab {
                        continue;
                    }
                    let conf = c.confinement(g.name());
                    let (got, inputs) = evaluate(kind, &conf, c);
                    let dd_inputs: Vec<Dd> = inputs.iter().map(|&x| Dd::new(x)).collect();
                    let want: Vec<Dd> = evaluate_direct(g, &kind.reference(), &dd_inputs);
                    let plain: Vec<f64> = traced.graph.eval(&inputs, &ids);
                    let before = block_errors(&traced, &plain, &want);
                    for ((block, error), (_, direct_sum)) in
                        block_errors(&traced, &got, &want).into_iter().zip(before)
                    {
                        self.rows.push(StiffRow {
                            case: c.case,
                            confinement: g.name().to_string(),
                            kernel: format!("{} {}", kind.name(), c.label),
                            block,
                            parameter: c.parameter,
                            error,
                            direct_sum,
                        });
                    }
                }
            }
        }
    }
    let mut m = Measure {
        include,
        cases: cases(),
        rows: Vec::new(),
    };
    kernel_gen::physics::green::for_each(&mut m);
    m.rows
}
