//! Seeded random configurations of one or two spheres in each confinement, shared by
//! the sections. The sampling is described by [`DESCRIPTION`] (quoted in the report).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How the configurations are drawn (for the report).
pub const DESCRIPTION: &str = "Configurations are drawn from a ChaCha8 generator with a fixed seed per family. \
Boundary plane at x3 = 0 (slit: lower wall at 0, upper wall at the width W); viscosity 1. \
Radii log-uniform in [0.5, 2] (pairs: independently, or one radius for the equal-radius rows). \
Sphere a: lateral position uniform in [-1, 1]^2, gap to its nearest boundary (h - a)/a log-uniform in [1e-3, 10] \
(slit: nearest wall chosen at random). Sphere b (pairs): surface gap to sphere a log-uniform in [1e-3, 30] times the mean radius, \
in a uniformly random direction; configurations where b comes closer than 1e-3 b to a boundary are redrawn. \
Interface: viscosity ratio lambda log-uniform in [0.1, 10]; slit: W log-uniform in [3, 30] times the larger radius.";

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

/// Is a sphere of radius `a` at height `x3` at least `1e-3 a` away from every plane?
fn fits(x3: f64, a: f64, lower: Option<f64>, upper: Option<f64>) -> bool {
    let min = a * (1.0 + 1e-3);
    let above = match lower {
        Some(h) => x3 - h >= min,
        None => true,
    };
    let below = match upper {
        Some(h) => h - x3 >= min,
        None => true,
    };
    above && below
}

/// `n` configurations for the family `family` with parameters named `params`
/// (`height`, `lambda`, `gap`), seeded by `seed`.
pub fn cases(family: &str, params: &[&str], kind: Kind, n: usize, seed: u64) -> Vec<Case> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let aa = log_uniform(&mut rng, 0.5, 2.0);
        let ab = match kind {
            Kind::Single | Kind::PairEqual => aa,
            Kind::Pair => log_uniform(&mut rng, 0.5, 2.0),
        };
        let width = log_uniform(&mut rng, 3.0, 30.0) * aa.max(ab);
        let lambda = log_uniform(&mut rng, 0.1, 10.0);
        let p: Vec<f64> = params
            .iter()
            .map(|&name| match name {
                "height" => 0.0,
                "lambda" => lambda,
                "gap" => width,
                other => panic!("no sampling rule for the parameter {other}"),
            })
            .collect();
        let (lower, upper) = match family {
            "free" => (None, None),
            _ if params.contains(&"gap") => (Some(0.0), Some(width)),
            _ => (Some(0.0), None),
        };
        let g = log_uniform(&mut rng, 1e-3, 10.0);
        let from_upper = upper.is_some() && rng.gen_bool(0.5);
        let h = if from_upper {
            width - aa * (1.0 + g)
        } else {
            aa * (1.0 + g)
        };
        let xa = [rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), h];
        if !fits(h, aa, lower, upper) {
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
            if !fits(xb[2], ab, lower, upper) {
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
