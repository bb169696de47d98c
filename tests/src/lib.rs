//! Shared helpers for the integration tests: configurations, norms, and the mapping
//! between the generator's Green's functions and the kernels' confinements.
//!
//! The independent references live here too: [`closed_forms`] (free-space far-field
//! couplings from the literature) and [`paper`] (Appendices B and C of Swan & Brady,
//! as printed and as corrected).

pub mod closed_forms;
pub mod configurations;
pub mod exact;
pub mod paper;
pub mod statistics;
pub mod stiff;

use kernels::{Confinement, Grand};
use rand::Rng;

/// A no-slip wall at `x3 = 0`, the fluid above it: the paper's geometry.
pub const WALL: Confinement = Confinement::Wall { height: 0.0 };

/// No external force, torque or trap (Brownian motion alone).
pub const NO_FORCES: stokesian::ExternalForces = stokesian::ExternalForces {
    weight: 0.0,
    strength: 0.0,
    debye: 1.0,
    trap: 0.0,
    torque: [0.0; 3],
};

/// The confinement a generated family stands for, with parameters `p` in the
/// generator's order (`height`, then `lambda` or `gap`).
pub fn confinement(name: &str, p: &[f64]) -> Confinement {
    Confinement::from_name(name, p).unwrap_or_else(|| panic!("no confinement {name} with {p:?}"))
}

/// Sample parameters of a registered family, in the generator's order: each
/// parameter's declared example value.
pub fn sample_params(name: &str) -> Vec<f64> {
    struct Find<'a>(&'a str, Option<Vec<f64>>);
    impl kernel_gen::physics::green::Visitor for Find<'_> {
        fn visit<G: kernel_gen::physics::green::Green>(&mut self, g: &G) {
            if g.name() == self.0 {
                self.1 = Some(kernel_gen::physics::green::examples(g));
            }
        }
    }
    let mut f = Find(name, None);
    kernel_gen::physics::green::for_each(&mut f);
    f.1.unwrap_or_else(|| panic!("no registered Green's function {name}"))
}

/// Every registered confinement with sample parameters.
pub fn all_confinements() -> Vec<(&'static str, Confinement)> {
    Confinement::NAMES
        .iter()
        .map(|&n| (n, confinement(n, &sample_params(n))))
        .collect()
}

/// The lower and upper limits of the fluid in x3 (its planes `x3 = const`).
pub fn bounds(c: &Confinement) -> (f64, f64) {
    let mut lo = f64::NEG_INFINITY;
    let mut hi = f64::INFINITY;
    for b in c.boundaries().iter().filter(|b| b.is_horizontal()) {
        let h = b.offset * b.normal[2];
        if b.normal[2] > 0.0 {
            lo = lo.max(h);
        } else {
            hi = hi.min(h);
        }
    }
    (lo, hi)
}

/// All entries of the nine blocks in the generator's output order (`BLOCKS`, each
/// row-major).
pub fn flat(g: &Grand) -> Vec<f64> {
    let mut v = Vec::new();
    let mut push = |rows: &[&[f64]]| rows.iter().for_each(|r| v.extend_from_slice(r));
    push(&g.uf.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&g.ul.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&g.us.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&g.of.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&g.ol.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&g.os.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&g.ef.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&g.el.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&g.es.iter().map(|r| &r[..]).collect::<Vec<_>>());
    v
}

/// The entries of a matrix, row-major.
pub fn flat2<const N: usize, const M: usize>(m: &[[f64; N]; M]) -> Vec<f64> {
    m.iter().flatten().copied().collect()
}

/// The entries of a Cartesian tensor of rank 3, the last index fastest.
pub fn flat3(m: &[[[f64; 3]; 3]; 3]) -> Vec<f64> {
    m.iter().flatten().flatten().copied().collect()
}

/// The entries of a Cartesian tensor of rank 4, the last index fastest.
pub fn flat4(m: &[[[[f64; 3]; 3]; 3]; 3]) -> Vec<f64> {
    m.iter().flatten().flatten().flatten().copied().collect()
}

/// The nine blocks as (name, entries), so that each block can be compared on its own
/// scale (blocks carry different powers of the radius).
pub fn blocks(g: &Grand) -> Vec<(&'static str, Vec<f64>)> {
    let f = flat(g);
    let sizes = [
        ("uf", 9),
        ("ul", 9),
        ("us", 15),
        ("of", 9),
        ("ol", 9),
        ("os", 15),
        ("ef", 15),
        ("el", 15),
        ("es", 25),
    ];
    let mut out = Vec::new();
    let mut k = 0;
    for (n, s) in sizes {
        out.push((n, f[k..k + s].to_vec()));
        k += s;
    }
    out
}

/// Frobenius norm.
pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// `||a - b|| / ||b||` (Frobenius).
pub fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    norm(&d) / norm(b)
}

/// `n` non-overlapping spheres with radii in `[amin, amax]` and surface gaps at least
/// `gap_min * a` from each other and from the boundaries, in a box of side `side`
/// above the lower boundary (and below the upper one) in x3, `[0, side)` in x1 and x2.
pub fn random_spheres(
    rng: &mut impl Rng,
    conf: &Confinement,
    n: usize,
    (amin, amax): (f64, f64),
    gap_min: f64,
    side: f64,
) -> Vec<stokesian::Particle> {
    let (lo, hi) = bounds(conf);
    let base = if lo.is_finite() { lo } else { 0.0 };
    let mut ps: Vec<stokesian::Particle> = Vec::new();
    while ps.len() < n {
        let a = rng.gen_range(amin..=amax);
        let z_hi = if hi.is_finite() {
            hi - a * (1.0 + gap_min)
        } else {
            base + side
        };
        let z_lo = if lo.is_finite() {
            lo + a * (1.0 + gap_min)
        } else {
            base - side
        };
        if z_hi <= z_lo {
            continue;
        }
        let x = [
            rng.gen_range(0.0..side),
            rng.gen_range(0.0..side),
            rng.gen_range(z_lo..z_hi),
        ];
        // clear of every other sphere, and of the planes not normal to x3 (a side wall)
        let clear = ps.iter().all(|q| {
            let d: f64 = (0..3).map(|k| (x[k] - q.x[k]).powi(2)).sum::<f64>().sqrt();
            d >= (a + q.a) * (1.0 + gap_min)
        }) && conf
            .boundaries()
            .iter()
            .filter(|b| !b.is_horizontal())
            .all(|b| b.distance(x) >= a * (1.0 + gap_min));
        if clear {
            ps.push(stokesian::Particle { x, a });
        }
    }
    ps
}

/// The 22 x 22 FTS grand mobility of two unit spheres at height h, separation s along
/// x, wall at 0, eta = 1, from wall kernels traced with `path` and interpreted (not the
/// emitted kernels: `Path::Generic` gives an independent derivation, and
/// `Path::StructuredNoExplicitHeight` the asymmetric x - y' variant); per-particle
/// blocks of 11 `[U, Omega, E]` (a permutation of the moment-major layout of docs/conventions.md).
pub fn two_sphere_mobility(
    path: kernel_gen::kernel::Path,
    h: f64,
    s: f64,
) -> nalgebra::DMatrix<f64> {
    use kernel_gen::kernel::{trace, Interaction, KernelSpec};
    use kernel_gen::physics::green::wall::Wall;
    use kernel_gen::physics::operators::{Basis, BLOCKS};
    let spec = |interaction| KernelSpec {
        interaction,
        basis: Basis::Orthonormal,
        equal_radii: false,
        blocks: BLOCKS.to_vec(),
        path,
        product: false,
        divergence: false,
    };
    let self_k = trace(&Wall, &spec(Interaction::SelfTerm));
    let pair_k = trace(&Wall, &spec(Interaction::Pair));
    let x = [[0.0, 0.0, h], [s, 0.0, h]];
    let mut m = nalgebra::DMatrix::zeros(22, 22);
    let sizes = [
        (3, 3),
        (3, 3),
        (3, 5),
        (3, 3),
        (3, 3),
        (3, 5),
        (5, 3),
        (5, 3),
        (5, 5),
    ];
    let offs = [0, 3, 6];
    for a in 0..2 {
        for b in 0..2 {
            let vals: Vec<f64> = if a == b {
                let inp = [x[a][0], x[a][1], x[a][2], 1.0, 1.0, 0.0];
                self_k.graph.eval(&inp, &self_k.output_ids())
            } else {
                let inp = [
                    x[a][0], x[a][1], x[a][2], x[b][0], x[b][1], x[b][2], 1.0, 1.0, 1.0, 0.0,
                ];
                pair_k.graph.eval(&inp, &pair_k.output_ids())
            };
            let mut k = 0;
            for (blk, &(r, c)) in sizes.iter().enumerate() {
                let (r0, c0) = (offs[blk / 3], offs[blk % 3]);
                for i in 0..r {
                    for j in 0..c {
                        m[(11 * a + r0 + i, 11 * b + c0 + j)] = vals[k];
                        k += 1;
                    }
                }
            }
        }
    }
    m
}
