//! Section d, scene pruning: for every scene in `scenes/*.toml`, the operation count of
//! each generated kernel (as `cargo xtask gen` reports it, from
//! `kernel_gen::catalog::scene_file`) and its measured time per call, through the
//! `kernels` crate's dispatch (`pair_f`, `product_f`, `pair_ft`, `product_ft`, ...)
//! where the scene serves it, or through the scene's generated module directly; and the
//! FTS pair lane kernels of every family (`kernels::pair_lanes_ordered`), per pair.

use super::sample::{self, Case, Kind};
use super::table::{self, Table};
use super::timing::ns_per_eval;
use super::{Ctx, Section};
use anyhow::Result;
use kernel_gen::catalog::{Moments, Radii, Scene};
use kernel_gen::physics::green::{Green, Visitor};
use kernels::generated::scene_wall_f_monolayer as monolayer;
use kernels::Confinement;
use std::fmt::Write as _;
use std::hint::black_box;

const ETA: f64 = 1.0;

/// The moments of `a` and `b` in the timed products (the first 3 or 6 at F and FT).
const VA: [f64; 11] = [0.3, -0.7, 0.2, 0.5, 0.1, -0.4, 0.9, -0.2, 0.6, 0.05, -0.3];
const VB: [f64; 11] = [-0.5, 0.4, 0.8, -0.1, 0.7, 0.2, -0.6, 0.3, 0.15, -0.8, 0.45];

/// Operation counts of a scene's kernels: `(kernel, flops, far-field flops)`.
fn op_counts(scene: &Scene) -> Vec<(String, usize, Option<usize>)> {
    let counts = kernel_gen::catalog::scene_file_of(scene, false)
        .map(|f| f.op_counts)
        .unwrap_or_default();
    let mut out: Vec<(String, usize, Option<usize>)> = Vec::new();
    for (name, n) in counts {
        match name.strip_suffix(" (far field)") {
            Some(base) => {
                if let Some(row) = out.iter_mut().find(|r| r.0 == base) {
                    row.2 = Some(n);
                }
            }
            None => out.push((name, n, None)),
        }
    }
    out
}

/// Whether the scene is the one the dispatch uses for its confinement and truncation
/// (as `kernel_gen::catalog` decides: the first scene in file order with unequal radii,
/// both outputs, F or FT).
fn serves(scene: &Scene, all: &[Scene]) -> bool {
    let ok =
        |s: &Scene| s.radii == Radii::Unequal && s.dense && s.product && s.moments != Moments::FTS;
    ok(scene)
        && all
            .iter()
            .find(|s| s.confinement == scene.confinement && s.moments == scene.moments && ok(s))
            .is_some_and(|s| s.name == scene.name)
}

/// Time one kernel of a scene (its suffix: `self`, `pair`, `pair_equal`,
/// `pair_product`, `pair_equal_product`) over `cases`; `None` if there is no way to
/// call it from here.
fn time_kernel(
    ctx: &Ctx,
    scene: &Scene,
    serving: bool,
    suffix: &str,
    cases: &[(Confinement, Case)],
) -> Option<f64> {
    let t = ctx.cfg.min_time;
    let n = cases.len();
    let (va, vb) = (VA, VB);
    let (v3a, v3b): ([f64; 3], [f64; 3]) = (
        std::array::from_fn(|k| va[k]),
        std::array::from_fn(|k| vb[k]),
    );
    let (v6a, v6b): ([f64; 6], [f64; 6]) = (
        std::array::from_fn(|k| va[k]),
        std::array::from_fn(|k| vb[k]),
    );
    let equal = suffix.contains("equal");
    let ab = |c: &Case| if equal { c.aa } else { c.ab };
    macro_rules! time {
        ($f:expr) => {
            Some(ns_per_eval(t, n, || {
                for (conf, c) in cases {
                    let c = black_box(c);
                    black_box($f(conf, c));
                }
            }))
        };
    }
    if serving {
        return match (scene.moments, suffix) {
            (Moments::F, "self") => {
                time!(|conf: &Confinement, c: &Case| kernels::self_f(conf, ETA, c.xa, c.aa))
            }
            (Moments::F, "pair" | "pair_equal") => {
                time!(|conf: &Confinement, c: &Case| kernels::pair_f(
                    conf,
                    ETA,
                    c.xa,
                    c.aa,
                    c.xb,
                    ab(c)
                ))
            }
            (Moments::F, _) => time!(|conf: &Confinement, c: &Case| {
                kernels::product_f(conf, ETA, c.xa, c.aa, c.xb, ab(c), v3a, v3b)
            }),
            (Moments::FT, "self") => {
                time!(|conf: &Confinement, c: &Case| kernels::self_ft(conf, ETA, c.xa, c.aa))
            }
            (Moments::FT, "pair" | "pair_equal") => {
                time!(|conf: &Confinement, c: &Case| kernels::pair_ft(
                    conf,
                    ETA,
                    c.xa,
                    c.aa,
                    c.xb,
                    ab(c)
                ))
            }
            (Moments::FT, _) => time!(|conf: &Confinement, c: &Case| {
                kernels::product_ft(conf, ETA, c.xa, c.aa, c.xb, ab(c), v6a, v6b)
            }),
            _ => None,
        };
    }
    // scenes the dispatch does not use: their generated modules, one line per scene
    let height = |conf: &Confinement| conf.params().first().map_or(0.0, |p| p.1);
    match (scene.name.as_str(), suffix) {
        ("wall_f_monolayer", "self") => time!(|conf: &Confinement, c: &Case| {
            monolayer::wall_f_monolayer_self(c.xa, c.aa, ETA, height(conf))
        }),
        ("wall_f_monolayer", "pair_equal_product") => time!(|conf: &Confinement, c: &Case| {
            monolayer::wall_f_monolayer_pair_equal_product(
                c.xa,
                c.xb,
                c.aa,
                ETA,
                height(conf),
                v3a,
                v3b,
            )
        }),
        _ => None,
    }
}

/// Spheres of the tiled products that time the lane kernels ([`lane_ns`]).
const SPHERES: usize = 256;

/// Nanoseconds per pair of the lane kernels of a truncation as the solver runs them: the
/// tiled product `System::apply_with` (the generated `kernels::product_f_lanes_ordered`,
/// `product_ft_lanes_ordered`, or `pair_lanes_ordered` times the moments at FTS) on the
/// widest instruction set, in double precision and on one thread, of [`SPHERES`] spheres
/// of radii 0.4 to 1.2 placed at random in the confinement `name` (its sample
/// parameters); the time of a product divided by its `N (N - 1)/2` pairs (the `N` self
/// terms included in the time). The solver's own instantiation of the lane kernels: the
/// report compiles none of its own.
fn lane_ns(ctx: &Ctx, moments: Moments, name: &str) -> Result<f64> {
    use rand::SeedableRng;
    let conf = integration_tests::all_confinements()
        .into_iter()
        .find(|(n, _)| *n == name)
        .map(|(_, c)| c)
        .ok_or_else(|| anyhow::anyhow!("no confinement {name}"))?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7100);
    let ps = integration_tests::random_spheres(&mut rng, &conf, SPHERES, (0.4, 1.2), 0.05, 40.0);
    let system = stokesian::System::new(conf, ETA, ps, false)?;
    let moments = match moments {
        Moments::F => stokesian::Moments::F,
        Moments::FT => stokesian::Moments::FT,
        Moments::FTS => stokesian::Moments::FTS,
    };
    let k = moments.per_particle();
    let x: Vec<f64> = (0..SPHERES * k).map(|i| VA[(i / SPHERES) % 11]).collect();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let pairs = SPHERES * (SPHERES - 1) / 2;
    Ok(one.install(|| {
        ns_per_eval(ctx.cfg.min_time, pairs, || {
            black_box(system.apply_with(
                moments,
                black_box(&x),
                stokesian::Isa::best(),
                stokesian::Precision::Double,
            ));
        })
    }))
}

/// Section d.
pub fn section(ctx: &Ctx) -> Result<Section> {
    // the confinements' scenes: a building block's (`ewald_real`) has no `Confinement`
    // to sample cases in
    let scenes: Vec<Scene> = crate::scenes()?
        .into_iter()
        .filter(|s| Confinement::NAMES.contains(&s.confinement.as_str()))
        .collect();
    ctx.progress.inc_length(scenes.len() as u64);
    let mut t = Table::new(&[
        "scene",
        "confinement",
        "moments",
        "kernel",
        "flops",
        "flops (lateral far field)",
        "time per call",
        "through",
    ]);
    let mut untimed = Vec::new();
    for (k, scene) in scenes.iter().enumerate() {
        ctx.progress
            .set_message(format!("scene pruning: {}", scene.name));
        let serving = serves(scene, &scenes);
        for (name, flops, far) in op_counts(scene) {
            let suffix = name
                .strip_prefix(&format!("{}_", scene.name))
                .unwrap_or(&name)
                .to_string();
            let kind = if suffix == "self" {
                Kind::Single
            } else if suffix.contains("equal") {
                Kind::PairEqual
            } else {
                Kind::Pair
            };
            let cases: Vec<(Confinement, Case)> =
                sample::cases(&scene.confinement, kind, ctx.cfg.cases, 7000 + k as u64)
                    .into_iter()
                    .map(|c| (c.confinement(&scene.confinement), c))
                    .collect();
            let ns = match (suffix.ends_with("_lanes (fma)"), serving) {
                (true, true) => Some(lane_ns(ctx, scene.moments, &scene.confinement)?),
                (true, false) => None,
                (false, _) => time_kernel(ctx, scene, serving, &suffix, &cases),
            };
            if ns.is_none() {
                untimed.push(name.clone());
            }
            t.row(vec![
                scene.name.clone(),
                scene.confinement.clone(),
                format!("{:?}", scene.moments),
                name.clone(),
                flops.to_string(),
                far.map_or("-".into(), |f| f.to_string()),
                ns.map_or("not timed".into(), table::time_ns),
                if ns.is_none() {
                    "-".into()
                } else if suffix.ends_with("_lanes (fma)") {
                    format!(
                        "System::apply, kernels::product_{}_lanes_ordered, {} (time per pair)",
                        scene.moments.lower(),
                        kernels::lanes::Isa::best().name()
                    )
                } else if serving {
                    format!("kernels::{}_{}", moments_fn(&suffix), scene.moments.lower())
                } else {
                    "generated module".into()
                },
            ]);
        }
        ctx.progress.inc(1);
    }
    let mut body = String::new();
    writeln!(
        body,
        "For every scene in `scenes/*.toml` ({} scenes): the operation count of each generated kernel after pruning and \
         dead-code elimination, as `cargo xtask gen` prints it (`kernel_gen::catalog::scene_file`; for wall pair kernels also \
         the lateral far-field branch, taken beyond rho > 100 (h_a + h_b), not in this sample), and the measured time per call \
         over {} configurations of the scene's confinement (sampling as in section a; equal-radius kernels with one radius), \
         product kernels with fixed moment vectors. Kernels of scenes that serve the dispatch are called through it \
         (`kernels::pair_f`, `product_f`, `self_f` and the FT counterparts; equal radii select the equal-radius kernel), \
         the others through their generated module. The lane kernels (`..._lanes (fma)`: a fused multiply-add counts once, \
         divisors of square roots become reciprocal square roots, the other reciprocals share divisions) are timed per pair as the solver runs \
         them: the tiled product `System::apply_with` (their twins without the exchange of roles, `..._lanes_ordered`) on the widest instruction \
         set of this processor, in double precision, on one thread, of {} spheres of radii 0.4 to 1.2 in the confinement, the time of a product \
         divided by its pairs.\n",
        scenes.len(),
        ctx.cfg.cases,
        SPHERES
    )?;
    body.push_str(&t.markdown());
    if !untimed.is_empty() {
        writeln!(
            body,
            "\nNot timed (no entry point for them in xtask/src/report/scenes.rs yet): {}.",
            untimed.join(", ")
        )?;
    }
    body.push_str(&family_lanes(ctx)?);
    Ok(Section {
        title: "d. Scene pruning".into(),
        body,
    })
}

/// The FTS pair lane kernels of every family (`kernels::pair_lanes_ordered` times the
/// moments, as the tiled FTS product and the dense assembly call them): operation count
/// as `cargo xtask gen` prints it, and time per pair on the widest instruction set.
fn family_lanes(ctx: &Ctx) -> Result<String> {
    struct Counts(Vec<(String, usize)>);
    impl Visitor for Counts {
        fn visit<G: Green>(&mut self, g: &G) {
            let name = format!("{}_pair_lanes (fma)", g.name());
            let file = kernel_gen::catalog::family(g);
            if let Some(&(_, n)) = file.op_counts.iter().find(|(k, _)| *k == name) {
                self.0.push((g.name().to_string(), n));
            }
        }
    }
    let mut counts = Counts(Vec::new());
    kernel_gen::physics::green::for_each(&mut counts);
    let mut t = Table::new(&["family", "kernel", "flops", "time per pair"]);
    for (family, flops) in &counts.0 {
        let ns = lane_ns(ctx, Moments::FTS, family)?;
        t.row(vec![
            family.clone(),
            format!("{family}_pair_lanes (fma)"),
            flops.to_string(),
            table::time_ns(ns),
        ]);
    }
    let mut out = String::new();
    writeln!(
        out,
        "\nThe FTS pair lane kernels of every family (`kernels::pair_lanes_ordered`, the lane twin \
         of the FTS pair blocks, times the moments by `kernels::grand_lanes_product`: what the \
         tiled FTS product calls), timed per pair as above: the tiled FTS product of {} spheres \
         in the family's confinement on {} lanes, one thread:\n",
        SPHERES,
        kernels::lanes::Isa::best().name()
    )?;
    out.push_str(&t.markdown());
    Ok(out)
}

fn moments_fn(suffix: &str) -> &'static str {
    if suffix == "self" {
        "self"
    } else if suffix.contains("product") {
        "product"
    } else {
        "pair"
    }
}
