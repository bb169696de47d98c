//! Seeded random configurations of one or two spheres in each confinement, shared by
//! the sections. The sampling is described by [`DESCRIPTION`] (quoted in the report).

use kernels::{Boundary, Confinement, Dimension};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How the configurations are drawn (for the report).
pub const DESCRIPTION: &str = "Configurations are drawn from a ChaCha8 generator with a fixed seed per family. \
Parameters by their declared dimension: every position 0 (the boundary planes through the origin, e.g. the wall at x3 = 0), \
every length W log-uniform in [3, 30] times the larger radius (the slit: lower wall at 0, upper wall at W), \
every pure number log-uniform in [0.1, 10] (the interface's viscosity ratio lambda); viscosity 1. \
Radii log-uniform in [0.5, 2] (pairs: independently, or one radius for the equal-radius rows). \
Sphere a: at a gap (h - a)/a log-uniform in [1e-3, 10] from one boundary (chosen at random where there are several), \
lateral position uniform in [-1, 1]^2 along that plane's axes; in free space x3 = h. \
Sphere b (pairs): surface gap to sphere a log-uniform in [1e-3, 30] times the mean radius, \
in a uniformly random direction; configurations where a sphere comes closer than 1e-3 of its radius to a boundary are redrawn.";

/// One configuration: for self terms `xb == xa` and `ab == aa`.
#[derive(Clone, Debug)]
pub struct Case {
    /// Centre of particle a (the field particle).
    pub xa: [f64; 3],
    /// Centre of particle b (the source particle).
    pub xb: [f64; 3],
    /// Radius of a.
    pub aa: f64,
    /// Radius of b.
    pub ab: f64,
    /// Run-time parameters of the Green's function, in the generator's order.
    pub params: Vec<f64>,
}

impl Case {
    /// The confinement `family` with this case's parameters.
    pub fn confinement(&self, family: &str) -> Confinement {
        Confinement::from_name(family, &self.params).expect("a registered confinement")
    }
}

/// What to draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// One sphere (self term).
    Single,
    /// Two spheres of independent radii.
    Pair,
    /// Two spheres of one radius.
    PairEqual,
}

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    (rng.gen_range(lo.ln()..hi.ln())).exp()
}

/// Is a sphere of radius `a` at `x` at least `1e-3 a` away from every plane?
fn fits(x: [f64; 3], a: f64, boundaries: &[Boundary]) -> bool {
    let min = a * (1.0 + 1e-3);
    boundaries.iter().all(|b| b.distance(x) >= min)
}

/// `n` configurations of the registered confinement `family`, seeded by `seed`.
pub fn cases(family: &str, kind: Kind, n: usize, seed: u64) -> Vec<Case> {
    let decl = kernels::declaration(family).unwrap_or_else(|e| panic!("{e}"));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let aa = log_uniform(&mut rng, 0.5, 2.0);
        let ab = match kind {
            Kind::Single | Kind::PairEqual => aa,
            Kind::Pair => log_uniform(&mut rng, 0.5, 2.0),
        };
        let width = log_uniform(&mut rng, 3.0, 30.0) * aa.max(ab);
        let ratio = log_uniform(&mut rng, 0.1, 10.0);
        let p: Vec<f64> = decl
            .params
            .iter()
            .map(|p| match p.dimension {
                Dimension::Position(_) => 0.0,
                Dimension::Length => width,
                Dimension::Number => ratio,
            })
            .collect();
        let boundaries = Confinement::from_name(family, &p)
            .expect("a registered confinement")
            .boundaries();
        let g = log_uniform(&mut rng, 1e-3, 10.0);
        // the boundary sphere a is measured from: uniformly at random (reservoir
        // sampling, one draw per further boundary)
        let mut from = 0;
        for k in 1..boundaries.len() {
            if rng.gen_bool(1.0 / (k as f64 + 1.0)) {
                from = k;
            }
        }
        let lateral = [rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)];
        let xa = integration_tests::over(boundaries.get(from), lateral, aa * (1.0 + g));
        if !fits(xa, aa, &boundaries) {
            continue;
        }
        let xb = if kind == Kind::Single {
            xa
        } else {
            let gap = log_uniform(&mut rng, 1e-3, 30.0) * 0.5 * (aa + ab);
            let d = aa + ab + gap;
            // uniform direction on the sphere
            let z: f64 = rng.gen_range(-1.0..1.0);
            let phi: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
            let s = (1.0 - z * z).sqrt();
            let xb = [
                xa[0] + d * s * phi.cos(),
                xa[1] + d * s * phi.sin(),
                xa[2] + d * z,
            ];
            if !fits(xb, ab, &boundaries) {
                continue;
            }
            xb
        };
        out.push(Case {
            xa,
            xb,
            aa,
            ab,
            params: p,
        });
    }
    out
}
