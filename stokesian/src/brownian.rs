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
}

impl ExternalForces {
    /// The potential energy of one sphere of radius `a` at centre height `z` above a
    /// single lower boundary at `z0` (for tests and for the Boltzmann distribution).
    pub fn potential_above(&self, z: f64, a: f64, z0: f64) -> f64 {
        self.weight * z + self.strength * self.debye * (-((z - z0) - a) / self.debye).exp()
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
}

impl System {
    /// External forces on every sphere, `3N` (particle-major).
    pub fn external_forces(&self, f: &ExternalForces) -> Vec<f64> {
        let mut out = vec![0.0; 3 * self.len()];
        for (a, p) in self.particles().iter().enumerate() {
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
        let mut out = vec![0.0; 3 * n];
        for a in 0..n {
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
        }
        out
    }

    /// One Euler-Maruyama step; returns the system at the new positions.
    pub fn brownian_step(
        &self,
        bd: &Brownian,
        rng: &mut impl Rng,
        step: usize,
    ) -> Result<System, BrownianError> {
        let n = self.len();
        let m = self.mobility(Moments::F);
        let f = self.external_forces(&bd.forces);
        let mf = &m * nalgebra::DVector::from_column_slice(&f);
        let l = m
            .cholesky()
            .ok_or(BrownianError::NotPositiveDefinite(step))?
            .l();
        let w = nalgebra::DVector::from_fn(3 * n, |_, _| rng.sample::<f64, _>(StandardNormal));
        let noise = l * w * (2.0 * bd.kt * bd.dt).sqrt();
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
