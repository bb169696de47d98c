//! Section a, kernel numerics: for every family (the registered Green's functions) and
//! its self and pair kernels, the norm-wise relative error of each of the nine blocks
//! against a double-double reference, and the cost of one evaluation, for each way of
//! computing the blocks ([`Variant`]): the generated `f64` and `f32` kernels, the paper's
//! closed forms (wall only), the generator's structured derivative path run at run time
//! on `f64` jets, and central finite differences in `f64`.
//!
//! The reference is the traced expression graph of the kernel (the graph the emitter
//! prints, direct sum, no far-field branch) evaluated by the interpreter in
//! double-double (`kernel_gen::number::dd::Dd`).

use super::sample::{self, Case, Kind};
use super::table::{self, Table};
use super::timing::ns_per_eval;
use super::{closed, plot, Ctx, Section};
use anyhow::Result;
use kernel_gen::kernel::{trace, Interaction, KernelSpec, Traced};
use kernel_gen::number::dd::Dd;
use kernel_gen::physics::derivatives::{GenericJets, Part, Structured};
use kernel_gen::physics::green::{self, Green, Mat3, Visitor};
use kernel_gen::physics::operators::{
    self, block_name, isolated, moment_dim, response_dim, Basis, Deriv, Derivatives, Term, BLOCKS,
};
use kernels::single::{self, Grand32};
use kernels::Confinement;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::hint::black_box;

/// Viscosity of every configuration.
const ETA: f64 = 1.0;

/// Step of the `f64` central differences, relative to the distance from the source
/// point to the nearest singularity of the differenced part (the field point for pair
/// kernels, the source's image for the reflected field).
pub const FD_STEP: f64 = 1e-2;

/// How the blocks are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// The generated kernels (`kernels` crate), double precision.
    F64,
    /// The generated kernels in single precision (`kernels::single`, feature `f32`).
    F32,
    /// The paper's Appendices B and C as corrected, plus free-space closed forms (wall,
    /// equal radii only).
    Closed,
    /// The structured derivative path (Eq. 10) evaluated at run time on `f64` jets.
    Jets,
    /// Central finite differences of `G` in `f64` with the operators applied.
    Fd,
    /// The reference itself (timed only): the traced graph interpreted in double-double.
    Reference,
}

impl Variant {
    /// Name in tables and plots.
    pub fn name(self) -> &'static str {
        match self {
            Variant::F64 => "generated f64",
            Variant::F32 => "generated f32",
            Variant::Closed => "closed forms (paper)",
            Variant::Jets => "run-time jets (f64)",
            Variant::Fd => "finite differences (f64)",
            Variant::Reference => "reference (dd graph)",
        }
    }
}

/// The variants plotted, in legend order.
const PLOTTED: [Variant; 5] = [
    Variant::F64,
    Variant::F32,
    Variant::Closed,
    Variant::Jets,
    Variant::Fd,
];

/// One measured (family, term, variant).
pub struct Row {
    /// Family name.
    pub family: &'static str,
    /// Self, pair, or pair with equal radii.
    pub kind: Kind,
    /// Variant.
    pub variant: Variant,
    /// Number of configurations.
    pub cases: usize,
    /// Per block (kernel order), the relative errors over the configurations where the
    /// reference block is not zero.
    pub errors: Vec<Vec<f64>>,
    /// Per configuration, the largest block error.
    pub worst: Vec<f64>,
    /// Nanoseconds per evaluation.
    pub ns: f64,
}

impl Row {
    /// Largest error over blocks and configurations (`None` for the timed-only reference).
    pub fn max(&self) -> Option<f64> {
        table::max(&self.worst)
    }
}

fn kind_name(k: Kind) -> &'static str {
    match k {
        Kind::Single => "self",
        Kind::Pair => "pair",
        Kind::PairEqual => "pair, equal radii",
    }
}

/// `(name, entries)` of the nine blocks in kernel order.
fn block_sizes() -> Vec<(String, usize)> {
    BLOCKS
        .iter()
        .map(|&(r, m)| {
            (
                block_name(r, m),
                response_dim(r, Basis::Orthonormal) * moment_dim(m, Basis::Orthonormal),
            )
        })
        .collect()
}

/// The value of the graph input `name` (`xa[0]`, `aa`, `eta`, `height`, ...).
fn input_value(name: &str, params: &[&str], c: &Case) -> f64 {
    let index = |s: &str| -> usize {
        s.trim_end_matches(']')
            .parse()
            .unwrap_or_else(|_| panic!("input {name}"))
    };
    if let Some(k) = name.strip_prefix("xa[") {
        c.xa[index(k)]
    } else if let Some(k) = name.strip_prefix("xb[") {
        c.xb[index(k)]
    } else if let Some(k) = name.strip_prefix("x[") {
        c.xa[index(k)]
    } else {
        match name {
            "aa" | "a" => c.aa,
            "ab" => c.ab,
            "eta" => ETA,
            p => {
                let k = params
                    .iter()
                    .position(|q| *q == p)
                    .unwrap_or_else(|| panic!("unknown kernel input {p}"));
                c.params[k]
            }
        }
    }
}

/// The reference blocks: the traced graph's direct sum in double-double.
fn reference(traced: &Traced, params: &[&str], c: &Case) -> Vec<Dd> {
    let inputs: Vec<Dd> = traced
        .graph
        .input_names()
        .iter()
        .map(|n| Dd::new(input_value(n, params, c)))
        .collect();
    traced.graph.eval(&inputs, &traced.output_ids())
}

/// Per block `||v - ref|| / ||ref||` (Frobenius, difference in double-double); `None`
/// where the reference block is zero.
fn block_errors(v: &[f64], r: &[Dd], sizes: &[(String, usize)]) -> Vec<Option<f64>> {
    let mut k = 0;
    sizes
        .iter()
        .map(|(_, n)| {
            let (mut num, mut den) = (0.0, 0.0);
            for i in k..k + n {
                let d = (Dd::new(v[i]) - r[i]).to_f64();
                num += d * d;
                den += r[i].to_f64() * r[i].to_f64();
            }
            k += n;
            (den > 0.0).then(|| (num / den).sqrt())
        })
        .collect()
}

/// All entries of a single-precision grand block, widened, in kernel order.
fn flat32(g: &Grand32) -> Vec<f64> {
    let mut v = Vec::with_capacity(121);
    let mut push = |rows: Vec<&[f32]>| {
        rows.iter()
            .for_each(|r| v.extend(r.iter().map(|&x| f64::from(x))))
    };
    push(g.uf.iter().map(|r| &r[..]).collect());
    push(g.ul.iter().map(|r| &r[..]).collect());
    push(g.us.iter().map(|r| &r[..]).collect());
    push(g.of.iter().map(|r| &r[..]).collect());
    push(g.ol.iter().map(|r| &r[..]).collect());
    push(g.os.iter().map(|r| &r[..]).collect());
    push(g.ef.iter().map(|r| &r[..]).collect());
    push(g.el.iter().map(|r| &r[..]).collect());
    push(g.es.iter().map(|r| &r[..]).collect());
    v
}

fn f32x3(x: [f64; 3]) -> [f32; 3] {
    x.map(|v| v as f32)
}

/// Central finite differences of `G` (or its reflected part) in `f64`: the stencils of
/// `kernel_gen::physics::fd` (second order, tensor products), evaluated in double precision.
struct Fd64<'g, G: Green> {
    g: &'g G,
    part: Part,
    x: [f64; 3],
    y: [f64; 3],
    p: Vec<f64>,
    h: f64,
    stencils: Vec<Vec<(i32, f64)>>,
    cache: HashMap<[i32; 6], Mat3<f64>>,
}

impl<'g, G: Green> Fd64<'g, G> {
    fn new(g: &'g G, part: Part, x: [f64; 3], y: [f64; 3], p: &[f64], h: f64, order: u8) -> Self {
        Fd64 {
            g,
            part,
            x,
            y,
            p: p.to_vec(),
            h,
            stencils: (0..=order).map(kernel_gen::physics::fd::stencil).collect(),
            cache: HashMap::new(),
        }
    }

    fn eval(&mut self, off: [i32; 6]) -> Mat3<f64> {
        if let Some(v) = self.cache.get(&off) {
            return *v;
        }
        let x: [f64; 3] = std::array::from_fn(|k| self.x[k] + self.h * f64::from(off[k]));
        let y: [f64; 3] = std::array::from_fn(|k| self.y[k] + self.h * f64::from(off[3 + k]));
        let v = match self.part {
            Part::Full => green::full(self.g, &x, &y, &self.p),
            Part::Reflected => self.g.reflected(&x, &y, &self.p),
            Part::Stokeslet => {
                let r: [f64; 3] = std::array::from_fn(|k| x[k] - y[k]);
                green::stokeslet(&r)
            }
        };
        self.cache.insert(off, v);
        v
    }
}

impl<G: Green> Derivatives<f64> for Fd64<'_, G> {
    fn get(&mut self, d: &Deriv) -> f64 {
        let orders: Vec<u8> = d.dx.iter().chain(&d.dy).copied().collect();
        let st: Vec<Vec<(i32, f64)>> = orders
            .iter()
            .map(|&n| self.stencils[n as usize].clone())
            .collect();
        let mut acc = 0.0;
        let mut idx = [0usize; 6];
        loop {
            let mut w = 1.0;
            let mut off = [0i32; 6];
            for v in 0..6 {
                let (o, wv) = st[v][idx[v]];
                off[v] = o;
                w *= wv;
            }
            acc += w * self.eval(off)[d.i][d.j];
            let mut v = 0;
            loop {
                if v == 6 {
                    let n: i32 = orders.iter().map(|&e| i32::from(e)).sum();
                    return acc / self.h.powi(n);
                }
                idx[v] += 1;
                if idx[v] < st[v].len() {
                    break;
                }
                idx[v] = 0;
                v += 1;
            }
        }
    }
}

/// The operators' term lists of a kernel, computed once (static tables, not part of
/// what the run-time variants are timed on).
struct Operators {
    pair: bool,
    order: usize,
    /// Per block: rows of entries of terms.
    terms: Vec<Vec<Vec<Vec<Term>>>>,
}

impl Operators {
    fn new(spec: &KernelSpec) -> Self {
        Operators {
            pair: spec.interaction == Interaction::Pair,
            order: spec.order(),
            terms: spec
                .blocks
                .iter()
                .map(|&(r, m)| operators::block(r, m, Basis::Orthonormal))
                .collect(),
        }
    }

    /// The blocks from a source of derivatives (units of `1/(8 pi eta)` scaled last,
    /// isolated sphere added for self terms), flattened in kernel order.
    fn blocks<D: Derivatives<f64>>(&self, src: &mut D, c: &Case) -> Vec<f64> {
        let (aa2, ab2) = (c.aa * c.aa, c.ab * c.ab);
        let scale = 1.0 / (8.0 * std::f64::consts::PI) / ETA;
        let mut v = Vec::with_capacity(121);
        for (&(r, m), terms) in BLOCKS.iter().zip(&self.terms) {
            let iso = (!self.pair).then(|| isolated(r, m, Basis::Orthonormal, &c.aa));
            for (row, entries) in terms.iter().enumerate() {
                for (col, entry) in entries.iter().enumerate() {
                    let mut e = operators::apply(entry, &aa2, &ab2, src);
                    if let Some(iso) = &iso {
                        e += iso[row][col];
                    }
                    v.push(scale * e);
                }
            }
        }
        v
    }

    /// The run-time jet variant: the structured path (Eq. 10) for Green's functions
    /// with image structure, the generic six-variable jets otherwise.
    fn jets<G: Green>(&self, g: &G, c: &Case) -> Vec<f64> {
        if g.image_terms().is_some() {
            let mut s = Structured::new(g, &c.xa, &c.xb, &c.params, self.order, self.pair, true);
            self.blocks(&mut s, c)
        } else {
            let part = if self.pair {
                Part::Full
            } else {
                Part::Reflected
            };
            let mut s = GenericJets::new(g, part, &c.xa, &c.xb, &c.params, self.order);
            self.blocks(&mut s, c)
        }
    }

    /// The finite-difference variant, step [`FD_STEP`] times the distance to the
    /// nearest singularity.
    fn fd<G: Green>(&self, g: &G, conf: &Confinement, c: &Case) -> Vec<f64> {
        let mut d = f64::INFINITY;
        if self.pair {
            let r: f64 = (0..3).map(|k| (c.xa[k] - c.xb[k]).powi(2)).sum::<f64>();
            d = r.sqrt();
        }
        for b in conf.boundaries() {
            d = d.min(2.0 * b.distance(c.xb).abs());
        }
        if !d.is_finite() {
            d = c.ab;
        }
        let part = if self.pair {
            Part::Full
        } else {
            Part::Reflected
        };
        let mut s = Fd64::new(
            g,
            part,
            c.xa,
            c.xb,
            &c.params,
            FD_STEP * d,
            self.order as u8,
        );
        self.blocks(&mut s, c)
    }
}

/// Whether the paper's closed forms ([`closed`]: one or two equal spheres above a
/// no-slip wall at `x3 = 0`) describe the confinement `family` as sampled
/// ([`sample::cases`]: every position 0): its only boundary is that wall, exactly.
fn closed_forms_apply(family: &str) -> bool {
    let conf = sample::cases(family, Kind::Single, 1, 0)[0].confinement(family);
    conf.boundaries()
        == [kernels::Boundary {
            normal: [0.0, 0.0, 1.0],
            offset: 0.0,
            condition: kernels::Condition::NoSlip,
            exact: true,
        }]
}

/// The kernel spec of the catalog's family variant `suffix` (`self`, `pair`).
fn catalog_spec(suffix: &str) -> KernelSpec {
    kernel_gen::catalog::variants()
        .into_iter()
        .find(|v| v.suffix == suffix)
        .unwrap_or_else(|| panic!("the catalog has no variant {suffix}"))
        .spec
}

struct Measure<'a> {
    ctx: &'a Ctx,
    rows: Vec<Row>,
    family_index: u64,
}

impl Visitor for Measure<'_> {
    fn visit<G: Green>(&mut self, g: &G) {
        self.family_index += 1;
        let mut kinds = vec![Kind::Single, Kind::Pair];
        if closed_forms_apply(g.name()) {
            kinds.push(Kind::PairEqual);
        }
        for (k, kind) in kinds.into_iter().enumerate() {
            self.ctx.progress.set_message(format!(
                "kernel numerics: {} {}",
                g.name(),
                kind_name(kind)
            ));
            let rows = measure(self.ctx, g, kind, 1000 * self.family_index + k as u64);
            self.rows.extend(rows);
            self.ctx.progress.inc(1);
        }
    }
}

/// Every variant of one family and kind.
fn measure<G: Green>(ctx: &Ctx, g: &G, kind: Kind, seed: u64) -> Vec<Row> {
    let cfg = &ctx.cfg;
    let spec = catalog_spec(if kind == Kind::Single { "self" } else { "pair" });
    let traced = trace(g, &spec);
    let ops = Operators::new(&spec);
    let names: Vec<&str> = g.params().iter().map(|p| p.name).collect();
    let params = &names[..];
    let cases = sample::cases(g.name(), kind, cfg.cases, seed);
    let confs: Vec<Confinement> = cases.iter().map(|c| c.confinement(g.name())).collect();
    let refs: Vec<Vec<Dd>> = cases
        .iter()
        .map(|c| reference(&traced, params, c))
        .collect();
    let sizes = block_sizes();
    let slow = cfg.slow_cases.min(cases.len());
    let mut rows = Vec::new();
    let closed_applies = closed_forms_apply(g.name()) && kind != Kind::Pair;
    let variants = [
        Variant::F64,
        Variant::F32,
        Variant::Closed,
        Variant::Jets,
        Variant::Fd,
        Variant::Reference,
    ];
    for variant in variants {
        if variant == Variant::Closed && !closed_applies {
            continue;
        }
        let n = match variant {
            Variant::Jets | Variant::Fd | Variant::Reference => slow,
            _ => cases.len(),
        };
        let (cs, fs) = (&cases[..n], &confs[..n]);
        let value = |c: &Case, conf: &Confinement| -> Vec<f64> {
            match variant {
                Variant::F64 => integration_tests::flat(&match kind {
                    Kind::Single => kernels::self_mobility(conf, ETA, c.xa, c.aa),
                    Kind::Pair => kernels::pair(conf, ETA, c.xa, c.aa, c.xb, c.ab),
                    Kind::PairEqual => kernels::pair_equal(conf, ETA, c.xa, c.xb, c.aa),
                }),
                Variant::F32 => flat32(&match kind {
                    Kind::Single => {
                        single::self_mobility(conf, f32x3(c.xa), c.aa as f32, ETA as f32)
                    }
                    _ => single::pair(
                        conf,
                        f32x3(c.xa),
                        f32x3(c.xb),
                        c.aa as f32,
                        c.ab as f32,
                        ETA as f32,
                    ),
                }),
                Variant::Closed => match kind {
                    Kind::Single => closed::self_blocks(c.xa, c.aa, ETA),
                    _ => closed::pair_blocks(c.xa, c.xb, c.aa, ETA),
                },
                Variant::Jets => ops.jets(g, c),
                Variant::Fd => ops.fd(g, conf, c),
                Variant::Reference => reference(&traced, params, c)
                    .iter()
                    .map(|d| d.to_f64())
                    .collect(),
            }
        };
        // errors
        let mut errors = vec![Vec::new(); sizes.len()];
        let mut worst = Vec::new();
        if variant != Variant::Reference {
            for ((c, conf), r) in cs.iter().zip(fs).zip(&refs) {
                let e = block_errors(&value(c, conf), r, &sizes);
                let mut w: f64 = 0.0;
                for (b, e) in e.into_iter().enumerate() {
                    if let Some(e) = e {
                        errors[b].push(e);
                        w = w.max(e);
                    }
                }
                worst.push(w);
            }
        }
        // time: the generated kernels without flattening, the others as evaluated
        let ns = match variant {
            Variant::F64 => ns_per_eval(cfg.min_time, n, || {
                for (c, conf) in cs.iter().zip(fs) {
                    let c = black_box(c);
                    black_box(match kind {
                        Kind::Single => kernels::self_mobility(conf, ETA, c.xa, c.aa),
                        Kind::Pair => kernels::pair(conf, ETA, c.xa, c.aa, c.xb, c.ab),
                        Kind::PairEqual => kernels::pair_equal(conf, ETA, c.xa, c.xb, c.aa),
                    });
                }
            }),
            Variant::F32 => {
                let inputs: Vec<([f32; 3], [f32; 3], f32, f32)> = cs
                    .iter()
                    .map(|c| (f32x3(c.xa), f32x3(c.xb), c.aa as f32, c.ab as f32))
                    .collect();
                ns_per_eval(cfg.min_time, n, || {
                    for (i, conf) in inputs.iter().zip(fs) {
                        let (xa, xb, aa, ab) = *black_box(i);
                        black_box(match kind {
                            Kind::Single => single::self_mobility(conf, xa, aa, ETA as f32),
                            _ => single::pair(conf, xa, xb, aa, ab, ETA as f32),
                        });
                    }
                })
            }
            _ => ns_per_eval(cfg.min_time, n, || {
                for (c, conf) in cs.iter().zip(fs) {
                    black_box(value(black_box(c), conf));
                }
            }),
        };
        rows.push(Row {
            family: g.name(),
            kind,
            variant,
            cases: n,
            errors,
            worst,
            ns,
        });
    }
    rows
}

/// Section a.
pub fn section(ctx: &Ctx) -> Result<Section> {
    ctx.progress.inc_length(11);
    let mut m = Measure {
        ctx,
        rows: Vec::new(),
        family_index: 0,
    };
    green::for_each(&mut m);
    let rows = m.rows;
    let sizes = block_sizes();
    let cfg = &ctx.cfg;

    let mut body = String::new();
    writeln!(
        body,
        "For every family and its self and pair kernels (all nine blocks, orthonormal strain basis, dimensional), \
         the relative error of each block, **norm-wise per block**: `||B - B_ref||_F / ||B_ref||_F`, the difference taken \
         in double-double; blocks whose reference is exactly zero (e.g. UL of a free-space self term) are left out. \
         The reference is the kernel's traced expression graph (the graph the emitter prints; direct sum, \
         the lateral far-field branch is not taken in this sample) interpreted in double-double (`kernel_gen::number::dd::Dd`). \
         Sample: {} configurations per family and term for the generated kernels and the closed forms, the first {} of them \
         for the run-time jets, the finite differences and the timing of the reference. {}\n",
        cfg.cases,
        cfg.slow_cases,
        sample::DESCRIPTION
    )?;
    writeln!(
        body,
        "Variants: **generated f64** (`kernels::self_mobility`, `kernels::pair`, `kernels::pair_equal`); \
         **generated f32** (`kernels::single`, feature `f32`: the same traces emitted in single precision; inputs rounded to f32); \
         **closed forms** (wall only, self and equal radii: Appendices B and C as corrected in `integration_tests::paper::corrected`, \
         plus the isolated sphere or the free-space closed forms of `integration_tests::closed_forms`; UL, US, OS by reciprocity); \
         **run-time jets** (the generator's structured path, Eq. 10, evaluated on `f64` Taylor jets at run time, the operators' \
         term tables precomputed; the generic six-variable jets for Green's functions without image structure); \
         **finite differences** (the second-order central stencils of `kernel_gen::physics::fd`, tensor products, evaluated in `f64` with \
         step h = {FD_STEP} d, d the distance from the source point to the nearest singularity of the differenced part: \
         the field point for pairs, the source's image for the reflected field; G evaluations cached per configuration). \
         Time per evaluation is single-threaded and includes, for the run-time variants, building the jets or the stencil cache.\n"
    )?;

    // summary table
    let mut t = Table::new(&[
        "family",
        "term",
        "variant",
        "configurations",
        "max error (worst block)",
        "median error (worst block)",
        "time per evaluation",
    ]);
    for r in &rows {
        t.row(vec![
            r.family.to_string(),
            kind_name(r.kind).to_string(),
            r.variant.name().to_string(),
            r.cases.to_string(),
            if r.variant == Variant::Reference {
                "(reference)".into()
            } else {
                table::err(r.max())
            },
            if r.variant == Variant::Reference {
                "(reference)".into()
            } else {
                table::err(table::median(&r.worst))
            },
            table::time_ns(r.ns),
        ]);
    }
    writeln!(
        body,
        "Summary: per family, term and variant, the largest block error over the sample, the median over \
         configurations of the largest block error, and the time per evaluation of all nine blocks.\n"
    )?;
    body.push_str(&t.markdown());

    // per-block table
    let mut header: Vec<String> = vec!["family".into(), "term".into(), "variant".into()];
    header.extend(sizes.iter().map(|(n, _)| n.to_uppercase()));
    let mut tb = Table::new(&header);
    for r in rows.iter().filter(|r| r.variant != Variant::Reference) {
        let mut cells = vec![
            r.family.to_string(),
            kind_name(r.kind).to_string(),
            r.variant.name().to_string(),
        ];
        for e in &r.errors {
            cells.push(if e.is_empty() {
                "zero".into()
            } else {
                format!(
                    "{} / {}",
                    table::err(table::max(e)),
                    table::err(table::median(e))
                )
            });
        }
        tb.row(cells);
    }
    writeln!(
        body,
        "\nPer block: maximum / median relative error over the sample (\"zero\": the reference block vanishes identically).\n"
    )?;
    body.push_str(&tb.markdown());

    // plot
    let families: Vec<&'static str> = {
        let mut f: Vec<&'static str> = Vec::new();
        for r in &rows {
            if !f.contains(&r.family) {
                f.push(r.family);
            }
        }
        f
    };
    let floor = 1e-17;
    let points = rows
        .iter()
        .filter_map(|r| {
            let series = PLOTTED.iter().position(|&v| v == r.variant)?;
            Some(plot::Point {
                x: r.ns,
                y: r.max()?.max(floor),
                series,
                group: families.iter().position(|&f| f == r.family)?,
                filled: r.kind == Kind::Single,
            })
        })
        .collect();
    let scatter = plot::Scatter {
        title: "Kernel accuracy against cost (largest block error over the sample)".into(),
        x_label: "time per evaluation of all nine blocks [ns]".into(),
        y_label: "largest relative block error".into(),
        series: PLOTTED.iter().map(|v| v.name().to_string()).collect(),
        groups: families.iter().map(|f| f.to_string()).collect(),
        fill_legend: Some(("self".into(), "pair".into())),
        y_floor: floor,
        points,
    };
    plot::write(&cfg.out, "numerics", &scatter)?;
    writeln!(
        body,
        "\n![accuracy against cost](numerics.png)\n\n\
         [numerics.svg](numerics.svg): one point per variant (colour), family (shape) and term (filled: self, hollow: pair; \
         the closed forms' pair point is the equal-radius wall pair); errors below {floor:.0e} (exact zeros) are drawn at {floor:.0e}."
    )?;
    Ok(Section {
        title: "a. Kernel numerics".into(),
        body,
    })
}
