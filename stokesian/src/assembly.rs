//! A validated system of spheres, and its grand mobility: dense, or applied to a vector
//! without forming the matrix.

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

    /// `(offset within the 11x11 grand block, dimension)` of each moment kept.
    fn parts(self) -> &'static [(usize, usize)] {
        match self {
            Moments::F => &[(0, 3)],
            Moments::FT => &[(0, 3), (3, 3)],
            Moments::FTS => &[(0, 3), (3, 3), (6, 5)],
        }
    }
}

/// Spheres in a confinement, validated once on construction, so that every method is
/// infallible.
#[derive(Clone, Debug)]
pub struct System {
    confinement: Confinement,
    viscosity: f64,
    particles: Vec<Particle>,
}

impl System {
    /// Validate and build. Overlapping spheres (with each other or a boundary) are
    /// errors unless `allow_overlap`.
    pub fn new(
        confinement: Confinement,
        viscosity: f64,
        particles: Vec<Particle>,
        allow_overlap: bool,
    ) -> Result<System, InputError> {
        validate(&confinement, viscosity, &particles, allow_overlap)?;
        Ok(System {
            confinement,
            viscosity,
            particles,
        })
    }

    /// The particles.
    pub fn particles(&self) -> &[Particle] {
        &self.particles
    }

    /// The confinement.
    pub fn confinement(&self) -> &Confinement {
        &self.confinement
    }

    /// The viscosity.
    pub fn viscosity(&self) -> f64 {
        self.viscosity
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// Never true for a validated system (it has at least one particle).
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// `M^{ab}`, using the equal-radius kernel when the radii match.
    pub fn pair_blocks(&self, a: usize, b: usize) -> Grand {
        let (p, q) = (&self.particles[a], &self.particles[b]);
        let (c, eta) = (&self.confinement, self.viscosity);
        if a == b {
            self_mobility(c, eta, p.x, p.a)
        } else if p.a == q.a {
            pair_equal(c, eta, p.x, q.x, p.a)
        } else {
            pair(c, eta, p.x, p.a, q.x, q.a)
        }
    }

    /// The dense grand mobility in the layout of Eq. 1 (moment-major: all `U`, then
    /// all `Omega`, then all `E`; particle-major within a moment). Each unordered pair
    /// is evaluated once, in parallel; `M^{ba} = (M^{ab})^T` (reciprocity).
    pub fn mobility(&self, moments: Moments) -> DMatrix<f64> {
        let n = self.len();
        let dim = moments.per_particle() * n;
        let blocks: Vec<(usize, usize, Grand)> = (0..n)
            .into_par_iter()
            .flat_map_iter(|a| (a..n).map(move |b| (a, b, self.pair_blocks(a, b))))
            .collect();
        let mut m = DMatrix::zeros(dim, dim);
        for (a, b, g) in &blocks {
            place(&mut m, n, moments, *a, *b, g);
            if a != b {
                place(&mut m, n, moments, *b, *a, &g.transposed());
            }
        }
        m
    }

    /// `M x` without forming `M`: `x` and the result in the layout of
    /// [`System::mobility`]. Parallel over particles `a`; each thread sums
    /// `M^{ab} x_b` for its rows, so no two threads write the same entry.
    pub fn apply(&self, moments: Moments, x: &[f64]) -> Vec<f64> {
        let n = self.len();
        let dim = moments.per_particle() * n;
        assert_eq!(
            x.len(),
            dim,
            "vector length must be {dim} for {n} particles"
        );
        let parts = moments.parts();
        // gather particle b's components of x into grand-block order
        let local = |b: usize| -> [f64; 11] {
            let mut v = [0.0; 11];
            let mut moff = 0;
            for &(o, d) in parts {
                for k in 0..d {
                    v[o + k] = x[moff + b * d + k];
                }
                moff += d * n;
            }
            v
        };
        let rows: Vec<[f64; 11]> = (0..n)
            .into_par_iter()
            .map(|a| {
                let mut acc = [0.0; 11];
                for b in 0..n {
                    let g = self.pair_blocks(a, b).matrix();
                    let xb = local(b);
                    for &(ro, rd) in parts {
                        for i in ro..ro + rd {
                            let mut s = 0.0;
                            for &(co, cd) in parts {
                                for j in co..co + cd {
                                    s += g[(i, j)] * xb[j];
                                }
                            }
                            acc[i] += s;
                        }
                    }
                }
                acc
            })
            .collect();
        let mut out = vec![0.0; dim];
        for (a, acc) in rows.iter().enumerate() {
            let mut moff = 0;
            for &(o, d) in parts {
                for k in 0..d {
                    out[moff + a * d + k] = acc[o + k];
                }
                moff += d * n;
            }
        }
        out
    }
}

/// Place `M^{ab}` into the moment-major matrix `m`.
fn place(m: &mut DMatrix<f64>, n: usize, moments: Moments, a: usize, b: usize, g: &Grand) {
    let full = g.matrix();
    let mut roff = 0;
    for &(ro, rd) in moments.parts() {
        let mut coff = 0;
        for &(co, cd) in moments.parts() {
            for i in 0..rd {
                for j in 0..cd {
                    m[(roff + a * rd + i, coff + b * cd + j)] = full[(ro + i, co + j)];
                }
            }
            coff += cd * n;
        }
        roff += rd * n;
    }
}

/// The dense grand mobility of `particles` (validated, no overlaps allowed); see
/// [`System::mobility`].
pub fn grand_mobility(
    conf: &Confinement,
    eta: f64,
    particles: &[Particle],
    moments: Moments,
) -> Result<DMatrix<f64>, InputError> {
    Ok(System::new(*conf, eta, particles.to_vec(), false)?.mobility(moments))
}
