//! Overdamped Brownian dynamics with hydrodynamic interactions (F level: positions of
//! torque-free spheres), Euler-Maruyama:
//!
//! `x(t + dt) = x + (M F + kT div M) dt + sqrt(2 kT dt) L W`,
//!
//! with `M = L L^T` the F-level grand mobility (Cholesky), `W` standard normal, and
//! `div M` the generated divergence kernels (the drift that position-dependent
//! mobility requires for the Boltzmann distribution to be stationary). External forces:
//! a uniform weight along `-z` and an exponential (screened-electrostatic) repulsion
//! from each boundary plane.

use crate::assembly::{Moments, System};
use crate::input::{InputError, Particle};
use kernels::{pair_divergence, self_divergence};
use rand::Rng;
use rand_distr::StandardNormal;
use rayon::prelude::*;
use thiserror::Error;

/// External forces on every sphere (force exerted on the fluid = external force on the
/// particle, in the mobility's convention).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExternalForces {
    /// Buoyant weight: force `-weight e_z`.
    pub weight: f64,
    /// Repulsion from each boundary, `F = strength * exp(-(d - a) / debye)` along the
    /// boundary's normal into the fluid, `d` the centre-to-boundary distance; potential
    /// `strength * debye * exp(-(d - a) / debye)`.
    pub strength: f64,
    /// Screening length of the repulsion.
    pub debye: f64,
    /// Stiffness of a harmonic trap pulling each sphere towards the axis `x = y = 0`
    /// (force `-trap (x, y, 0)`; potential `trap (x^2 + y^2) / 2`); 0 for none.
    pub trap: f64,
}

impl ExternalForces {
    /// The potential energy of one sphere of radius `a` at centre height `z` above a
    /// single lower boundary at `z0` (for tests and for the Boltzmann distribution).
    pub fn potential_above(&self, z: f64, a: f64, z0: f64) -> f64 {
        self.weight * z + self.strength * self.debye * (-((z - z0) - a) / self.debye).exp()
    }

    /// Whether any force is applied.
    fn any(&self) -> bool {
        self.weight != 0.0 || self.strength != 0.0 || self.trap != 0.0
    }
}

/// Integration settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Brownian {
    /// Thermal energy `kT`.
    pub kt: f64,
    /// Time step.
    pub dt: f64,
    /// Include the drift `kT div M` (switching it off is wrong near a boundary; the
    /// option exists to show that it matters).
    pub drift: bool,
    /// External forces.
    pub forces: ExternalForces,
    /// How the Brownian displacement `M^{1/2} W` is formed.
    pub noise: Noise,
    /// With `false`, no hydrodynamic interactions: each sphere has the isolated Stokes
    /// mobility `1/(6 pi eta a)` (no wall or pair coupling, hence no drift). For
    /// comparison: the equilibrium distribution must not depend on it.
    pub hydrodynamics: bool,
}

/// The square root of the mobility applied to the random vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Noise {
    /// Cholesky factor `L` of the dense `M` (`L W` has covariance `M`): N up to a few
    /// thousand.
    Cholesky,
    /// Lanczos `M^{1/2} W` from matrix-free products, to a relative tolerance.
    Lanczos {
        /// Relative change at which the iteration stops.
        tol: f64,
    },
}

/// Why a step cannot be taken.
#[derive(Debug, Error, PartialEq)]
pub enum BrownianError {
    /// The new configuration is invalid (a sphere crossed a boundary or another
    /// sphere): the time step is too large for the forces.
    #[error("step {step}: {source}; reduce the time step")]
    Invalid {
        /// Step number.
        step: usize,
        /// What is wrong with the new configuration.
        source: InputError,
    },
    /// The mobility lost positive definiteness (cannot happen for valid input).
    #[error("step {0}: the mobility is not positive definite")]
    NotPositiveDefinite(usize),
    /// The Lanczos square root failed.
    #[error("step {step}: {source}")]
    Lanczos {
        /// Step number.
        step: usize,
        /// Why.
        source: LanczosError,
    },
}

impl System {
    /// External forces on every sphere, `3N` (particle-major).
    pub fn external_forces(&self, f: &ExternalForces) -> Vec<f64> {
        let mut out = vec![0.0; 3 * self.len()];
        for (a, p) in self.particles().iter().enumerate() {
            if !f.any() {
                break;
            }
            out[3 * a] -= f.trap * p.x[0];
            out[3 * a + 1] -= f.trap * p.x[1];
            out[3 * a + 2] -= f.weight;
            for (plane, above) in self.confinement().boundaries() {
                let d = if above {
                    p.x[2] - plane
                } else {
                    plane - p.x[2]
                };
                let push = f.strength * (-(d - p.a) / f.debye).exp();
                out[3 * a + 2] += if above { push } else { -push };
            }
        }
        out
    }

    /// The Brownian drift `div M` at the F level (`3N`): for particle `a`,
    /// `sum_b sum_j d/dx_{b,j} M^{ab}_{ij}`, from the generated divergence kernels.
    pub fn divergence(&self) -> Vec<f64> {
        let (c, eta, ps) = (self.confinement(), self.viscosity(), self.particles());
        let n = self.len();
        // each unordered pair once; per-thread accumulators summed at the end
        let row = |mut out: Vec<f64>, a: usize| {
            let s = self_divergence(c, eta, ps[a].x, ps[a].a);
            for i in 0..3 {
                out[3 * a + i] += s.a[i];
            }
            for b in a + 1..n {
                let d = pair_divergence(c, eta, ps[a].x, ps[a].a, ps[b].x, ps[b].a);
                for i in 0..3 {
                    out[3 * a + i] += d.a[i];
                    out[3 * b + i] += d.b[i];
                }
            }
            out
        };
        if n < crate::assembly::PARALLEL_MIN {
            return (0..n).fold(vec![0.0; 3 * n], row);
        }
        (0..n)
            .into_par_iter()
            .fold(|| vec![0.0; 3 * n], row)
            .reduce(
                || vec![0.0; 3 * n],
                |mut u, v| {
                    for (p, q) in u.iter_mut().zip(&v) {
                        *p += q;
                    }
                    u
                },
            )
    }

    /// One Euler-Maruyama step; returns the system at the new positions.
    pub fn brownian_step(
        &self,
        bd: &Brownian,
        rng: &mut impl Rng,
        step: usize,
    ) -> Result<System, BrownianError> {
        let n = self.len();
        let f = self.external_forces(&bd.forces);
        let w: Vec<f64> = (0..3 * n)
            .map(|_| rng.sample::<f64, _>(StandardNormal))
            .collect();
        let scale = (2.0 * bd.kt * bd.dt).sqrt();
        let (mf, noise): (Vec<f64>, Vec<f64>) = match bd.noise {
            _ if !bd.hydrodynamics => {
                let mob: Vec<f64> = self
                    .particles()
                    .iter()
                    .flat_map(|p| [1.0 / (6.0 * std::f64::consts::PI * self.viscosity() * p.a); 3])
                    .collect();
                (
                    f.iter().zip(&mob).map(|(f, m)| m * f).collect(),
                    w.iter()
                        .zip(&mob)
                        .map(|(w, m)| (m.sqrt() * w) * scale)
                        .collect(),
                )
            }
            Noise::Cholesky => {
                let m = self.mobility(Moments::F);
                let mf = &m * nalgebra::DVector::from_column_slice(&f);
                let l = m
                    .cholesky()
                    .ok_or(BrownianError::NotPositiveDefinite(step))?
                    .l();
                let noise = l * nalgebra::DVector::from_column_slice(&w) * scale;
                (
                    mf.iter().copied().collect(),
                    noise.iter().copied().collect(),
                )
            }
            Noise::Lanczos { tol } => {
                let (y, _) = lanczos_sqrt(|x| self.apply(Moments::F, x), &w, tol, 3 * n)
                    .map_err(|source| BrownianError::Lanczos { step, source })?;
                (
                    self.apply(Moments::F, &f),
                    y.iter().map(|v| v * scale).collect(),
                )
            }
        };
        let div = if bd.drift {
            self.divergence()
        } else {
            vec![0.0; 3 * n]
        };
        let ps: Vec<Particle> = self
            .particles()
            .iter()
            .enumerate()
            .map(|(a, p)| Particle {
                x: std::array::from_fn(|i| {
                    let k = 3 * a + i;
                    p.x[i] + (mf[k] + bd.kt * div[k]) * bd.dt + noise[k]
                }),
                a: p.a,
            })
            .collect();
        System::new(*self.confinement(), self.viscosity(), ps, false)
            .map_err(|source| BrownianError::Invalid { step, source })
    }
}

/// Why a Krylov square root failed.
#[derive(Debug, Error, PartialEq)]
pub enum LanczosError {
    /// The Lanczos matrix has a non-positive eigenvalue: the operator is not positive
    /// definite.
    #[error("the operator is not positive definite (Lanczos eigenvalue {0:e})")]
    NotPositiveDefinite(f64),
    /// No convergence within the iteration limit.
    #[error(
        "Lanczos did not converge to {tol:e} in {iterations} iterations (last change {change:e})"
    )]
    NotConverged {
        /// Requested relative tolerance.
        tol: f64,
        /// Iterations done.
        iterations: usize,
        /// Relative change of the last iteration.
        change: f64,
    },
}

/// `M^{1/2} w` for a symmetric positive definite `M` known only through products
/// `apply(x) = M x`, by the Lanczos process (Chow & Saad 2014; Ando, Chow, Saad &
/// Skolnick 2012 for Brownian dynamics): with `V_k` the orthonormal Krylov basis
/// (fully reorthogonalised) and `T_k` the tridiagonal Lanczos matrix,
/// `M^{1/2} w ~ |w| V_k T_k^{1/2} e_1`. Stops when successive approximations differ
/// by less than `tol` relative; returns the result and the number of iterations.
pub fn lanczos_sqrt(
    apply: impl Fn(&[f64]) -> Vec<f64>,
    w: &[f64],
    tol: f64,
    max_iter: usize,
) -> Result<(Vec<f64>, usize), LanczosError> {
    let n = w.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let beta0 = dot(w, w).sqrt();
    if beta0 == 0.0 {
        return Ok((vec![0.0; n], 0));
    }
    let mut basis: Vec<Vec<f64>> = vec![w.iter().map(|x| x / beta0).collect()];
    let (mut alpha, mut beta): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    let mut previous: Option<Vec<f64>> = None;
    let mut change = f64::INFINITY;
    for k in 0..max_iter.min(n) {
        let mut z = apply(&basis[k]);
        let a = dot(&basis[k], &z);
        alpha.push(a);
        // full reorthogonalisation against the whole basis (twice is enough)
        for _ in 0..2 {
            for v in &basis {
                let c = dot(v, &z);
                for (zi, vi) in z.iter_mut().zip(v) {
                    *zi -= c * vi;
                }
            }
        }
        let b = dot(&z, &z).sqrt();
        // y = beta0 V T^{1/2} e1 from the eigen-decomposition of the k+1 x k+1 T
        let m = alpha.len();
        let t = nalgebra::DMatrix::from_fn(m, m, |i, j| {
            if i == j {
                alpha[i]
            } else if i + 1 == j {
                beta[i]
            } else if j + 1 == i {
                beta[j]
            } else {
                0.0
            }
        });
        let eig = t.symmetric_eigen();
        let lmin = eig.eigenvalues.min();
        if lmin <= 0.0 {
            return Err(LanczosError::NotPositiveDefinite(lmin));
        }
        let coef: Vec<f64> = (0..m)
            .map(|i| {
                (0..m)
                    .map(|j| {
                        eig.eigenvectors[(i, j)]
                            * eig.eigenvalues[j].sqrt()
                            * eig.eigenvectors[(0, j)]
                    })
                    .sum::<f64>()
                    * beta0
            })
            .collect();
        let mut y = vec![0.0; n];
        for (c, v) in coef.iter().zip(&basis) {
            for (yi, vi) in y.iter_mut().zip(v) {
                *yi += c * vi;
            }
        }
        if let Some(prev) = &previous {
            let d: f64 = y
                .iter()
                .zip(prev)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            change = d / dot(&y, &y).sqrt();
            if change < tol {
                return Ok((y, m));
            }
        }
        // an invariant subspace: the result is exact
        if b <= 1e-14 * beta0 || m == n {
            return Ok((y, m));
        }
        beta.push(b);
        basis.push(z.iter().map(|x| x / b).collect());
        previous = Some(y);
    }
    Err(LanczosError::NotConverged {
        tol,
        iterations: alpha.len(),
        change,
    })
}
