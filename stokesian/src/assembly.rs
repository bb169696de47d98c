//! Assembly of the dense grand mobility from the pair and self kernels.

use crate::input::{validate, InputError, Particle};
use kernels::{pair, pair_equal, self_mobility, Confinement, Grand};
use nalgebra::DMatrix;
use rayon::prelude::*;

/// Truncation of the multipole expansion: which moments the matrix couples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Moments {
    /// Forces to velocities (`3N x 3N`).
    F,
    /// Forces and torques to velocities and angular velocities (`6N x 6N`).
    FT,
    /// Forces, torques and stresslets to velocities, angular velocities and strains
    /// (`11N x 11N`).
    FTS,
}

impl Moments {
    /// Rows (and columns) per particle.
    pub fn per_particle(self) -> usize {
        match self {
            Moments::F => 3,
            Moments::FT => 6,
            Moments::FTS => 11,
        }
    }
}

/// Place `M^{ab}` (and nothing else) into the moment-major matrix `m`.
fn place(m: &mut DMatrix<f64>, n: usize, moments: Moments, a: usize, b: usize, g: &Grand) {
    // (offset of the moment block, dimension) for U/F, Omega/L, E/S
    let parts: &[(usize, usize)] = match moments {
        Moments::F => &[(0, 3)],
        Moments::FT => &[(0, 3), (3 * n, 3)],
        Moments::FTS => &[(0, 3), (3 * n, 3), (6 * n, 5)],
    };
    let full = g.matrix();
    let starts = [0usize, 3, 6];
    for (ri, &(roff, rd)) in parts.iter().enumerate() {
        for (ci, &(coff, cd)) in parts.iter().enumerate() {
            for i in 0..rd {
                for j in 0..cd {
                    m[(roff + a * rd + i, coff + b * cd + j)] =
                        full[(starts[ri] + i, starts[ci] + j)];
                }
            }
        }
    }
}

/// The dense grand mobility of `particles` in confinement `conf`, viscosity `eta`,
/// in the layout of Eq. 1 (see the crate documentation). Pairs are computed in
/// parallel; `M^{ba}` is the transpose of `M^{ab}` (reciprocity), so each unordered
/// pair is evaluated once. Equal radii use the equal-radius kernels.
pub fn grand_mobility(
    conf: &Confinement,
    eta: f64,
    particles: &[Particle],
    moments: Moments,
) -> Result<DMatrix<f64>, InputError> {
    validate(conf, eta, particles, false)?;
    let n = particles.len();
    let dim = moments.per_particle() * n;
    let selfs: Vec<Grand> = particles
        .par_iter()
        .map(|p| self_mobility(conf, eta, p.x, p.a))
        .collect();
    let pairs: Vec<(usize, usize, Grand)> = (0..n)
        .into_par_iter()
        .flat_map_iter(|a| {
            (a + 1..n).map(move |b| {
                let (p, q) = (&particles[a], &particles[b]);
                let g = if p.a == q.a {
                    pair_equal(conf, eta, p.x, q.x, p.a)
                } else {
                    pair(conf, eta, p.x, p.a, q.x, q.a)
                };
                (a, b, g)
            })
        })
        .collect();
    let mut m = DMatrix::zeros(dim, dim);
    for (a, g) in selfs.iter().enumerate() {
        place(&mut m, n, moments, a, a, g);
    }
    for (a, b, g) in &pairs {
        place(&mut m, n, moments, *a, *b, g);
        place(&mut m, n, moments, *b, *a, &g.transposed());
    }
    Ok(m)
}
