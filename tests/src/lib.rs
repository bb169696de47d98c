//! Shared helpers for the integration tests: configurations, norms, and the mapping
//! between the generator's Green's functions and the kernels' confinements.
//!
//! The checks name no confinement and no parameter: they take the registered
//! confinements ([`all_confinements`]), choose parameters by their declared dimension
//! ([`with_params`]) and place spheres relative to the declared boundaries, whatever
//! their normals ([`frame_of`], [`placed`], [`over`], [`random_spheres`]).
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
pub const NO_FORCES: stokesian::ExternalForces = stokesian::ExternalForces::NONE;

/// The Brownian step of the fast product's tests (`stokesian brownian`'s defaults with
/// gravity): F, Euler-Maruyama with `noise` and the drift, kT = 1, dt = 1e-3, buoyant
/// weight 1 kT/a and no other force.
pub fn falling(noise: stokesian::Noise) -> stokesian::Brownian {
    stokesian::Brownian {
        kt: 1.0,
        dt: 1e-3,
        drift: true,
        forces: stokesian::ExternalForces {
            weight: 1.0,
            ..stokesian::ExternalForces::NONE
        },
        noise,
        hydrodynamics: true,
        moments: stokesian::Moments::F,
        scheme: stokesian::Scheme::EulerMaruyama,
        lubrication: None,
    }
}

/// A sedimented colloid's forces: buoyant weight 1 kT/a (the gravitational length is a),
/// a wall repulsion of 50 kT/a with screening length 0.1 a, no trap or torque (kT = 1,
/// unit spheres). Without the drift `kT div M`, Euler-Maruyama would sample `exp(-U/kT) /
/// mu_perp(h)`, whose Kolmogorov-Smirnov distance from Boltzmann's is 0.116 near an open
/// wall (computed from B1's mu_perp; 0.091 for weight 2, 0.059 for weight 5).
pub const SEDIMENTED: stokesian::ExternalForces = stokesian::ExternalForces {
    weight: 1.0,
    strength: 50.0,
    debye: 0.1,
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

/// The run-time parameters of the confinement `name`, in the generator's order, each
/// `choose(param)` (by its declared dimension: the checks name no parameter), and the
/// confinement they make.
pub fn with_params(name: &str, choose: impl FnMut(&kernels::Param) -> f64) -> Confinement {
    let decl = kernels::declaration(name).unwrap_or_else(|e| panic!("{e}"));
    confinement(name, &decl.params.iter().map(choose).collect::<Vec<_>>())
}

/// The axes `t1, t2` along a plane of normal `n`: those of its own frame
/// (`kernel_gen::physics::green::frame`) for the normal turned to its positive side, so
/// that a plane's axes do not depend on which side the fluid is (the two walls of a
/// slit share them).
fn plane_axes(n: [f64; 3]) -> [[f64; 3]; 2] {
    let k = (0..3)
        .max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
        .expect("three axes");
    let [t1, t2, _] = kernel_gen::physics::green::frame(if n[k] < 0.0 { n.map(|v| -v) } else { n });
    [t1, t2]
}

/// The frame the checks write configurations in: the rows `t1, t2, n` with `n` the
/// normal of the confinement's first boundary (into the fluid) and `t1, t2` the axes
/// along its plane ([`plane_axes`]), the identity in free space. A configuration
/// written with `x3` along that normal (heights over the plane, lateral separations
/// along `x1`, `x2`) is placed in the world by [`placed`]; for a plane `x3 = const`
/// the frame is the identity, for a plane normal to another axis a permutation, so
/// placing is exact.
pub fn frame_of(c: &Confinement) -> [[f64; 3]; 3] {
    match c.boundaries().first() {
        Some(b) => {
            let [t1, t2] = plane_axes(b.normal);
            [t1, t2, b.normal]
        }
        None => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    }
}

/// The point whose coordinates in [`frame_of`] are `local`: `Q^T local`.
pub fn placed(c: &Confinement, local: [f64; 3]) -> [f64; 3] {
    let q = frame_of(c);
    std::array::from_fn(|i| kernels::along([q[0][i], q[1][i], q[2][i]], local))
}

/// The point at height `h` over the boundary `b` (along its normal, into the fluid),
/// at `lateral` along its plane's axes ([`plane_axes`]); without a boundary, over the
/// plane `x3 = 0`.
pub fn over(b: Option<&kernels::Boundary>, lateral: [f64; 2], h: f64) -> [f64; 3] {
    let Some(b) = b else {
        return [lateral[0], lateral[1], h];
    };
    let (n, [t1, t2]) = (b.normal, plane_axes(b.normal));
    std::array::from_fn(|i| b.offset * n[i] + lateral[0] * t1[i] + lateral[1] * t2[i] + h * n[i])
}

/// The point at height `h` over the confinement's first boundary ([`over`]).
pub fn above(c: &Confinement, lateral: [f64; 2], h: f64) -> [f64; 3] {
    over(c.boundaries().first(), lateral, h)
}

/// A boundary's normal in [`frame_of`] (`Q n`).
fn local_normal(q: &[[f64; 3]; 3], b: &kernels::Boundary) -> [f64; 3] {
    std::array::from_fn(|k| kernels::along(q[k], b.normal))
}

/// Per axis of [`frame_of`], the limits `(lo, hi)` of the fluid that the boundaries
/// normal to that axis set (infinite where there is none): `(H, H + gap)` along the
/// third axis of a slit, `(s, inf)` along the third axis of a side wall `x1 = s`.
pub fn local_bounds(c: &Confinement) -> [(f64, f64); 3] {
    let q = frame_of(c);
    let mut out = [(f64::NEG_INFINITY, f64::INFINITY); 3];
    for b in c.boundaries() {
        let n = local_normal(&q, &b);
        if let Some(k) = (0..3).find(|&k| n[k].abs() == 1.0) {
            if n[k] > 0.0 {
                out[k].0 = out[k].0.max(b.offset);
            } else {
                out[k].1 = out[k].1.min(-b.offset);
            }
        }
    }
    out
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
/// `gap_min * a` from each other and from the boundaries, drawn uniformly in a box of
/// [`frame_of`]: along each axis between the boundaries normal to it (less the gap),
/// or from one of them to `side` beyond it, or where none is, `[0, side)` along the
/// first two axes and `[-side, side)` along the third. A boundary normal to none of
/// the axes is kept by redrawing.
pub fn random_spheres(
    rng: &mut impl Rng,
    conf: &Confinement,
    n: usize,
    (amin, amax): (f64, f64),
    gap_min: f64,
    side: f64,
) -> Vec<stokesian::Particle> {
    let q = frame_of(conf);
    let bounds = local_bounds(conf);
    let oblique: Vec<kernels::Boundary> = conf
        .boundaries()
        .into_iter()
        .filter(|b| local_normal(&q, b).iter().all(|v| v.abs() != 1.0))
        .collect();
    let mut ps: Vec<stokesian::Particle> = Vec::new();
    let mut misses = 0usize;
    while ps.len() < n {
        misses += 1;
        assert!(
            misses < 1_000_000,
            "{conf:?}: no room for {n} spheres of radii {amin} to {amax} in a box of {side}"
        );
        let a = rng.gen_range(amin..=amax);
        let m = a * (1.0 + gap_min);
        let range = |k: usize| match bounds[k] {
            (lo, hi) if lo.is_finite() && hi.is_finite() => (lo + m, hi - m),
            (lo, _) if lo.is_finite() => (lo + m, lo + side),
            (_, hi) if hi.is_finite() => (hi - side, hi - m),
            _ if k == 2 => (-side, side),
            _ => (0.0, side),
        };
        let ranges = [range(0), range(1), range(2)];
        if ranges.iter().any(|(lo, hi)| hi <= lo) {
            continue;
        }
        let local = ranges.map(|(lo, hi)| rng.gen_range(lo..hi));
        let x = placed(conf, local);
        if oblique.iter().any(|b| b.distance(x) < m) {
            continue;
        }
        let clear = ps.iter().all(|q| {
            let d: f64 = (0..3).map(|k| (x[k] - q.x[k]).powi(2)).sum::<f64>().sqrt();
            d >= (a + q.a) * (1.0 + gap_min)
        });
        if clear {
            ps.push(stokesian::Particle { x, a });
            misses = 0;
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
        drift: None,
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
