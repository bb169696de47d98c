//! The measurements `cargo xtask check-green` makes of one registered Green's function
//! that the registry-driven integration tests do not print: the residual of the
//! condition of every declared boundary (exact or not), the divergence of `G` in the
//! field point (incompressibility), and the agreement of the structured path (Eq. 10,
//! from the image terms) with the generic six-variable jets of the Rust `reflected`.
//! All of it from the derivatives of `G` at pairs of points of the fluid drawn with a
//! fixed seed, each relative to the Stokeslet's derivatives of the same order there.

use anyhow::{bail, Result};
use kernel_gen::physics::derivatives::{GenericJets, Part, Structured};
use kernel_gen::physics::green::{examples, frame, Boundary, Condition, Green, Visitor};
use kernel_gen::physics::operators::{Deriv, Derivatives};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// An exact condition holds to this, relative to the Stokeslet's derivatives of the
/// same order: the image cancels the Stokeslet on the plane to round-off, a few ulps of
/// the sum of terms of that size (the integration tests demand the same).
const EXACT: f64 = 1e-13;

/// `div_x G` vanishes to this, relative to the Stokeslet's first derivatives: a sum of
/// three derivatives of `J + J^w`, each exact to round-off, of terms up to a hundred
/// times the scale where a source is near its image.
const DIVERGENCE: f64 = 1e-12;

/// The structured and generic paths agree to this, relative to the largest derivative
/// of the same order (up to 4): both are exact to round-off, and 1e-11 covers the
/// round-off of the generic jets' few hundred operations per high derivative (as in
/// the integration test of the two paths).
const PATHS: f64 = 1e-11;

/// Highest derivative order compared between the two paths (the kernels need up to
/// third derivatives of `G` for the FTS blocks, plus one for the Brownian drift).
const PATH_ORDER: usize = 4;

/// Pairs of points per measurement.
const PAIRS: usize = 3;

/// All multi-indices of total order `n` in three variables.
fn of_order(n: u8) -> Vec<[u8; 3]> {
    let mut v = Vec::new();
    for a in (0..=n).rev() {
        for b in (0..=n - a).rev() {
            v.push([a, b, n - a - b]);
        }
    }
    v
}

/// `order 0: r0, order 1: r1, ...`.
fn by_order(r: &[f64]) -> String {
    let v: Vec<String> = r
        .iter()
        .enumerate()
        .map(|(o, r)| format!("order {o}: {r:.1e}"))
        .collect();
    v.join(", ")
}

/// The derivatives the kernels are emitted from: the structured path if the Green's
/// function has image terms, otherwise the generic jets.
fn emitted<G: Green>(g: &G, x: &[f64; 3], y: &[f64; 3], p: &[f64]) -> Box<dyn Derivatives<f64>> {
    match g.image_terms() {
        Some(_) => Box::new(Structured::new(g, x, y, p, 5, true, true)),
        None => Box::new(GenericJets::new(g, Part::Full, x, y, p, 5)),
    }
}

/// The world-frame `d_x^dx d_y^dy G` as a matrix.
fn matrix(src: &mut dyn Derivatives<f64>, dx: [u8; 3], dy: [u8; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| src.get(&Deriv { i, j, dx, dy })))
}

/// The largest `|d_x^dx d_y^beta J|` over `|beta| = order` and `|dx| <= 1`, the
/// Stokeslet's scale at that order.
fn scale<G: Green>(g: &G, x: &[f64; 3], y: &[f64; 3], order: u8) -> f64 {
    let mut j = GenericJets::new(g, Part::Stokeslet, x, y, &[], order as usize + 1);
    let mut dxs = vec![[0u8; 3]];
    dxs.extend(of_order(1));
    let mut worst: f64 = 0.0;
    for beta in of_order(order) {
        for dx in &dxs {
            worst = matrix(&mut j, *dx, beta)
                .iter()
                .flatten()
                .fold(worst, |a, v| a.max(v.abs()));
        }
    }
    worst
}

/// The values a boundary's condition makes zero, at source derivative `beta`.
fn condition_values(src: &mut dyn Derivatives<f64>, b: &Boundary<f64>, beta: [u8; 3]) -> Vec<f64> {
    let [t1, t2, n] = frame(b.plane.normal);
    let g = matrix(src, [0; 3], beta);
    let along =
        |v: &[f64; 3], m: &[[f64; 3]; 3], j: usize| -> f64 { (0..3).map(|i| v[i] * m[i][j]).sum() };
    let mut out = Vec::new();
    match b.condition {
        Condition::NoSlip => out.extend(g.iter().flatten()),
        Condition::Interface => out.extend((0..3).map(|j| along(&n, &g, j))),
        Condition::FreeSurface => {
            out.extend((0..3).map(|j| along(&n, &g, j)));
            // the tangential stress: d_n (t . G)
            let grad: Vec<[[f64; 3]; 3]> = of_order(1)
                .into_iter()
                .map(|dx| matrix(src, dx, beta))
                .collect();
            for t in [t1, t2] {
                for j in 0..3 {
                    // of_order(1) is [e1, e2, e3]
                    out.push((0..3).map(|k| n[k] * along(&t, &grad[k], j)).sum());
                }
            }
        }
    }
    out
}

/// Points of the fluid (farther than 0.2 from every boundary) in the cube of side 6
/// about the origin, drawn with a fixed seed.
fn fluid_points(
    boundaries: &[Boundary<f64>],
    rng: &mut ChaCha8Rng,
    n: usize,
) -> Result<Vec<[f64; 3]>> {
    let mut v = Vec::new();
    for _ in 0..100_000 {
        let y: [f64; 3] = std::array::from_fn(|_| rng.gen_range(-3.0..3.0));
        if boundaries.iter().all(|b| b.plane.distance(&y) > 0.2) {
            v.push(y);
            if v.len() == n {
                return Ok(v);
            }
        }
    }
    bail!("no point of the fluid (0.2 from every boundary) in the cube |x_k| < 3: check the boundaries' normals point into the fluid")
}

struct Measure {
    name: String,
    found: bool,
    lines: Vec<String>,
    failures: Vec<String>,
}

impl Measure {
    fn run<G: Green>(&mut self, g: &G) -> Result<()> {
        let p = examples(g);
        let params: Vec<String> = g
            .params()
            .iter()
            .zip(&p)
            .map(|(d, v)| format!("{} = {v} ({:?})", d.name, d.dimension))
            .collect();
        self.lines.push(format!("`{}`: {}", g.name(), g.title()));
        if !params.is_empty() {
            self.lines
                .push(format!("at the example parameters: {}", params.join(", ")));
        }
        let boundaries = g.boundaries(&p);
        let mut rng = ChaCha8Rng::seed_from_u64(35);
        self.boundary_conditions(g, &p, &boundaries, &mut rng)?;
        let ys = fluid_points(&boundaries, &mut rng, 2 * PAIRS)?;
        let pairs: Vec<([f64; 3], [f64; 3])> = ys.chunks(2).map(|c| (c[0], c[1])).collect();
        self.incompressibility(g, &p, &pairs);
        self.paths(g, &p, &pairs);
        Ok(())
    }

    fn boundary_conditions<G: Green>(
        &mut self,
        g: &G,
        p: &[f64],
        boundaries: &[Boundary<f64>],
        rng: &mut ChaCha8Rng,
    ) -> Result<()> {
        if boundaries.is_empty() {
            self.lines.push("no boundaries".into());
            return Ok(());
        }
        self.lines.push(format!(
            "boundary conditions: the largest residual over {PAIRS} pairs (field point on the \
             plane, source in the fluid) and every source derivative of the order, relative \
             to the Stokeslet's derivatives of that order"
        ));
        for (k, b) in boundaries.iter().enumerate() {
            let [t1, t2, n] = frame(b.plane.normal);
            // sources in the fluid; field points on the plane, moved along it, that are
            // in the fluid of the other boundaries
            let mut pairs = Vec::new();
            for y in fluid_points(boundaries, rng, 100)? {
                let (s1, s2): (f64, f64) = (rng.gen_range(-2.0..2.0), rng.gen_range(-2.0..2.0));
                let d = b.plane.distance(&y);
                let x: [f64; 3] =
                    std::array::from_fn(|i| y[i] - d * n[i] + s1 * t1[i] + s2 * t2[i]);
                if boundaries.iter().all(|o| o.plane.distance(&x) >= -1e-12) {
                    pairs.push((x, y));
                    if pairs.len() == PAIRS {
                        break;
                    }
                }
            }
            if pairs.len() < PAIRS {
                bail!("boundary {k}: no point of the plane borders the fluid within |x_k| < 5");
            }
            let mut worst = [0.0f64; 4];
            for (x, y) in &pairs {
                let mut src = emitted(g, x, y, p);
                for (order, w) in worst.iter_mut().enumerate() {
                    let s = scale(g, x, y, order as u8);
                    for beta in of_order(order as u8) {
                        for v in condition_values(src.as_mut(), b, beta) {
                            *w = w.max(v.abs() / s);
                        }
                    }
                }
            }
            self.lines.push(format!(
                "  boundary {k}: {:?} on the plane {:?}.x = {} ({}): {}",
                b.condition,
                b.plane.normal,
                b.plane.offset,
                if b.exact { "exact" } else { "not exact" },
                by_order(&worst)
            ));
            if b.exact && worst.iter().any(|&w| w > EXACT) {
                self.failures.push(format!(
                    "boundary {k} is declared exact, but its {:?} condition leaves {:.1e} (more than {EXACT:e})",
                    b.condition,
                    worst.iter().fold(0.0f64, |a, &w| a.max(w))
                ));
            }
        }
        Ok(())
    }

    fn incompressibility<G: Green>(&mut self, g: &G, p: &[f64], pairs: &[([f64; 3], [f64; 3])]) {
        let mut worst: f64 = 0.0;
        for (x, y) in pairs {
            let mut src = emitted(g, x, y, p);
            for order in 0..=2u8 {
                let s = scale(g, x, y, order);
                for beta in of_order(order) {
                    let grad: Vec<[[f64; 3]; 3]> = of_order(1)
                        .into_iter()
                        .map(|dx| matrix(src.as_mut(), dx, beta))
                        .collect();
                    for j in 0..3 {
                        let div: f64 = (0..3).map(|i| grad[i][i][j]).sum();
                        worst = worst.max(div.abs() / s);
                    }
                }
            }
        }
        self.lines.push(format!(
            "incompressibility: the largest |d_xi G_ij| (and its source derivatives to order 2) \
             over {PAIRS} pairs in the fluid: {worst:.1e} of the Stokeslet's derivatives"
        ));
        if worst > DIVERGENCE {
            self.failures.push(format!(
                "G is not divergence-free in the field point: {worst:.1e} (more than {DIVERGENCE:e})"
            ));
        }
    }

    fn paths<G: Green>(&mut self, g: &G, p: &[f64], pairs: &[([f64; 3], [f64; 3])]) {
        if g.image_terms().is_none() {
            self.lines.push(
                "structured vs generic path: no image terms, the kernels come from the generic \
                 path alone"
                    .into(),
            );
            return;
        }
        // (pair: J + J^w at (x, y); self: J^w at (y, y))
        let mut worst = [[0.0f64; PATH_ORDER + 1]; 2];
        for (x, y) in pairs {
            let cases: [(Structured<f64>, GenericJets<f64>); 2] = [
                (
                    Structured::new(g, x, y, p, PATH_ORDER, true, true),
                    GenericJets::new(g, Part::Full, x, y, p, PATH_ORDER),
                ),
                (
                    Structured::new(g, y, y, p, PATH_ORDER, false, true),
                    GenericJets::new(g, Part::Reflected, y, y, p, PATH_ORDER),
                ),
            ];
            for (w, (mut s, mut j)) in worst.iter_mut().zip(cases) {
                for (order, w) in w.iter_mut().enumerate() {
                    let mut diff: f64 = 0.0;
                    let mut size: f64 = 0.0;
                    for n in 0..=order as u8 {
                        for (dx, dy) in of_order(n).into_iter().flat_map(|dx| {
                            of_order(order as u8 - n)
                                .into_iter()
                                .map(move |dy| (dx, dy))
                        }) {
                            let (a, b) = (matrix(&mut s, dx, dy), matrix(&mut j, dx, dy));
                            for (u, v) in a.iter().flatten().zip(b.iter().flatten()) {
                                diff = diff.max((u - v).abs());
                                size = size.max(v.abs());
                            }
                        }
                    }
                    *w = w.max(diff / size);
                }
            }
        }
        for (what, w) in ["pair (J + J^w)", "self (J^w at x = y)"].iter().zip(worst) {
            self.lines.push(format!(
                "structured (Eq. 10) vs generic jets, {what}, over {PAIRS} pairs: {}",
                by_order(&w)
            ));
            if w.iter().any(|&v| v > PATHS) {
                self.failures.push(format!(
                    "the image terms and `reflected` disagree ({what}): {:.1e} (more than {PATHS:e}); \
                     the kernels are emitted from the image terms",
                    w.iter().fold(0.0f64, |a, &v| a.max(v))
                ));
            }
        }
    }
}

impl Visitor for Measure {
    fn visit<G: Green>(&mut self, g: &G) {
        if g.name() != self.name {
            return;
        }
        self.found = true;
        if let Err(e) = self.run(g) {
            self.failures.push(e.to_string());
        }
    }
}

/// Measure the registered Green's function `name`; print every measurement and fail if
/// an exact condition, incompressibility or the agreement of the paths does not hold.
pub fn run(name: &str) -> Result<()> {
    let mut m = Measure {
        name: name.into(),
        found: false,
        lines: Vec::new(),
        failures: Vec::new(),
    };
    kernel_gen::physics::green::for_each(&mut m);
    if !m.found {
        bail!(
            "no registered Green's function is named `{name}` (its `name()` must return the \
             name of its module)"
        );
    }
    for l in &m.lines {
        println!("{l}");
    }
    if !m.failures.is_empty() {
        bail!("`{name}` fails:\n  {}", m.failures.join("\n  "));
    }
    Ok(())
}
