//! The steps of Brownian dynamics as methods of [`System`] (module docs of
//! [`crate::dynamics`]): whole runs, one step, its increment for given random numbers,
//! the drift `div M` from the generated divergence kernels, and the lubricated step with
//! its random finite difference.

use super::settings::{
    Brownian, BrownianError, ExternalForces, LubricatedDynamics, Noise, Run, RunTally, Scheme, Step,
};
use crate::linalg::{lanczos_sqrt, mul_vec, Cholesky};
use crate::mobility::tiled::LaneProduct;
use crate::periodic::PeriodicError;
use crate::system::input::{InputError, Particle};
use crate::system::overlap::Overlap;
use crate::system::{Moments, Precision, System, PARALLEL_MIN};
use rand::Rng;
use rand_distr::StandardNormal;
use rayon::prelude::*;
use std::f64::consts::PI;

/// The rotation vectors (`Omega` rows of an FT increment), or zeros at the F level.
fn rotations(increment: &[f64], moments: Moments, n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|a| match moments {
            Moments::FT => std::array::from_fn(|i| increment[3 * n + 3 * a + i]),
            _ => [0.0; 3],
        })
        .collect()
}

/// A unit quaternion `q = (w, x, y, z)` rotated by the rotation vector `theta`:
/// `exp(theta/2) q`, renormalised (the exponential is exact, the renormalisation only
/// removes round-off drift over many steps).
pub fn rotate(q: [f64; 4], theta: [f64; 3]) -> [f64; 4] {
    let angle = (theta[0] * theta[0] + theta[1] * theta[1] + theta[2] * theta[2]).sqrt();
    // sin(angle/2)/angle, with its series below 1e-4 (error below 1e-17)
    let s = if angle < 1e-4 {
        0.5 - angle * angle / 48.0
    } else {
        (0.5 * angle).sin() / angle
    };
    let r = [
        (0.5 * angle).cos(),
        s * theta[0],
        s * theta[1],
        s * theta[2],
    ];
    let p = [
        r[0] * q[0] - r[1] * q[1] - r[2] * q[2] - r[3] * q[3],
        r[0] * q[1] + r[1] * q[0] + r[2] * q[3] - r[3] * q[2],
        r[0] * q[2] - r[1] * q[3] + r[2] * q[0] + r[3] * q[1],
        r[0] * q[3] + r[1] * q[2] - r[2] * q[1] + r[3] * q[0],
    ];
    let norm = p.iter().map(|v| v * v).sum::<f64>().sqrt();
    p.map(|v| v / norm)
}

impl System {
    /// A trajectory of `run.steps` steps of `bd` from this system, the standard normal
    /// numbers drawn from ChaCha8 seeded with `run.seed`; a step whose new configuration
    /// is invalid is redrawn (up to `run.max_rejections` in total). `frame(step, system,
    /// orientations)` receives step 0 and every `run.every`-th step; the orientations are
    /// unit quaternions `(w, x, y, z)` starting at the identity (FT level; they stay the
    /// identity at the F level).
    pub fn brownian_run(
        self,
        bd: &Brownian,
        run: &Run,
        mut frame: impl FnMut(usize, &System, &[[f64; 4]]),
    ) -> Result<RunTally, BrownianError> {
        use rand::SeedableRng;
        bd.check()?;
        if run.every == 0 {
            return Err(BrownianError::BadSetting {
                name: "every",
                value: 0.0,
                why: "must be at least 1 (keep every K-th step)",
            });
        }
        let mut tally = RunTally::default();
        let mut system = self;
        let mut orientation = vec![[1.0, 0.0, 0.0, 0.0]; system.len()];
        frame(0, &system, &orientation);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(run.seed);
        for step in 1..=run.steps {
            system = loop {
                match system.brownian_step(bd, &mut rng, step) {
                    Ok(next) => {
                        for (q, theta) in orientation.iter_mut().zip(&next.rotation) {
                            *q = rotate(*q, *theta);
                        }
                        if let Some(k) = next.lanczos_iterations {
                            tally.lanczos_sum += k;
                            tally.lanczos_max = tally.lanczos_max.max(k);
                        }
                        break next.system;
                    }
                    Err(BrownianError::Invalid { step, source }) => {
                        tally.rejections += 1;
                        if tally.rejections > run.max_rejections {
                            return Err(BrownianError::TooManyRejections {
                                rejections: tally.rejections,
                                max: run.max_rejections,
                                step,
                                source,
                            });
                        }
                    }
                    Err(e) => return Err(e),
                }
            };
            if step % run.every == 0 {
                frame(step, &system, &orientation);
            }
        }
        Ok(tally)
    }

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
            for b in self.confinement().boundaries() {
                let d = b.distance(p.x);
                let push = f.strength * (-(d - p.a) / f.debye).exp();
                // along the normal, into the fluid
                for (k, &n) in b.normal.iter().enumerate() {
                    if n != 0.0 {
                        out[3 * a + k] += if n == 1.0 { push } else { n * push };
                    }
                }
            }
        }
        out
    }

    /// The Brownian drift `div M` at the F level (`3N`): for particle `a`,
    /// `sum_b sum_j d/dx_{b,j} M^{ab}_{ij}`, from the generated divergence kernels.
    pub fn divergence(&self) -> Vec<f64> {
        self.divergence_at(Moments::F)
    }

    /// `sum_b sum_j d/dx_{b,j} M^{ab}_{ij}` for the `U` and `Omega` rows (`6N`,
    /// moment-major), from the generated divergence kernels; with the damping of
    /// [`crate::Overlap::Rpy`] that of `B M(clamped) B` (`crate::system::overlap`: the
    /// divergence weighted by the factors, plus the terms of the clamping and of the
    /// factors' gradients). The overlap corrections are divergence-free.
    fn divergence_ft(&self) -> Vec<f64> {
        let n = self.len();
        let ps: Vec<([f64; 3], f64)> = self.evaluated().iter().map(|p| (p.x, p.a)).collect();
        let rpy = self.rpy();
        let damping = rpy.and_then(|r| r.damping.as_ref());
        let div = crate::mobility::tiled::Divergence {
            conf: self.confinement(),
            eta: self.viscosity(),
            weighted: damping.is_some(),
        };
        // the weights b_q, through the first moment of the (otherwise unused) vectors
        let weights: Vec<[f64; 6]> = (0..n)
            .map(|q| [damping.map_or(1.0, |d| d.b[q]), 0.0, 0.0, 0.0, 0.0, 0.0])
            .collect();
        // with the fast product, and where the far field of the pair terms cancels (the
        // confinement's divergence table is empty: the reciprocal theorem, module
        // `crate::fmm`), each sphere's own term alone: `O(N)`; otherwise each unordered
        // pair once, in tiles: the same bits with any number of threads
        let pairs_cancel = self.fmm().is_some()
            && self
                .confinement()
                .divergence_sources()
                .is_ok_and(|t| t.is_empty());
        let mut acc = if pairs_cancel {
            ps.par_iter()
                .zip(&weights)
                .map(|(&(x, a), &v)| div.diagonal(x, a, v))
                .collect()
        } else {
            crate::mobility::tiled::apply::<_, f64, 6>(
                &div,
                &ps,
                &weights,
                kernels::lanes::Isa::best(),
                n >= PARALLEL_MIN,
            )
        };
        if let (Some(rpy), Some(d)) = (rpy, damping) {
            d.drift(self.confinement(), self.viscosity(), &rpy.pairs, &mut acc);
            for (v, b) in acc.iter_mut().zip(&d.b) {
                v.iter_mut().for_each(|v| *v *= b);
            }
        }
        let mut out = vec![0.0; 6 * n];
        for (a, v) in acc.iter().enumerate() {
            for i in 0..3 {
                out[3 * a + i] = v[i];
                out[3 * n + 3 * a + i] = v[3 + i];
            }
        }
        out
    }

    /// One time step of `bd.scheme` at the level `bd.moments` (F: positions; FT:
    /// positions and rotations), with standard normal numbers drawn from `rng`; returns
    /// the system at the new positions and each sphere's rotation vector over the step
    /// (zero at the F level).
    pub fn brownian_step(
        &self,
        bd: &Brownian,
        rng: &mut impl Rng,
        step: usize,
    ) -> Result<Step, BrownianError> {
        let w: Vec<f64> = (0..bd.random_numbers(self.len()))
            .map(|_| rng.sample::<f64, _>(StandardNormal))
            .collect();
        let (increment, lanczos_iterations) = self.increment(bd, &w, step)?;
        Ok(Step {
            system: self.displaced(&increment, step)?,
            rotation: rotations(&increment, bd.moments, self.len()),
            lanczos_iterations,
        })
    }

    /// The displacement of one step for given standard normal numbers `w`
    /// ([`Brownian::random_numbers`]: `3N` at the F level, `6N` at FT, `9N` with
    /// lubrication), moment-major: translations (`3N`), then at FT the rotation
    /// vectors (`3N`). [`System::brownian_step`] draws `w` and applies this; with `w`
    /// given, the step is a deterministic function (for variance-reduced tests, or
    /// random numbers from elsewhere).
    pub fn brownian_increment(
        &self,
        bd: &Brownian,
        w: &[f64],
        step: usize,
    ) -> Result<Vec<f64>, BrownianError> {
        Ok(self.increment(bd, w, step)?.0)
    }

    /// [`System::brownian_increment`] and the number of Lanczos iterations it took (with
    /// Lanczos noise).
    fn increment(
        &self,
        bd: &Brownian,
        w: &[f64],
        step: usize,
    ) -> Result<(Vec<f64>, Option<usize>), BrownianError> {
        if self.periodic_ref().is_some() && bd.forces.trap != 0.0 {
            let what = "a harmonic trap (it pulls towards one axis, not a periodic force)";
            return Err(crate::periodic::PeriodicError::NotAvailable(what).into());
        }
        match bd.moments {
            Moments::F | Moments::FT => {}
            Moments::FTS => return Err(BrownianError::Unsupported("FTS Brownian dynamics")),
        }
        if bd.moments == Moments::F && bd.forces.torque != [0.0; 3] {
            return Err(BrownianError::Unsupported(
                "an external torque at the F level (torque-free spheres; use FT)",
            ));
        }
        let expected = bd.random_numbers(self.len());
        if w.len() != expected {
            return Err(BrownianError::RandomNumbers {
                expected,
                found: w.len(),
            });
        }
        if let Some(lub) = &bd.lubrication {
            return Ok((self.lubricated_step(bd, lub, w, step)?, None));
        }
        match bd.scheme {
            Scheme::EulerMaruyama => self.euler_maruyama(bd, w, step),
            // with a constant mobility the midpoint is Euler-Maruyama
            Scheme::FixmanMidpoint if !bd.hydrodynamics => self.euler_maruyama(bd, w, step),
            Scheme::FixmanMidpoint => Ok((self.fixman_midpoint(bd, w, step)?, None)),
        }
    }

    /// Euler-Maruyama: `dx = (M F + kT div M) dt + sqrt(2 kT dt) B W`, `B B^T = M`.
    fn euler_maruyama(
        &self,
        bd: &Brownian,
        w: &[f64],
        step: usize,
    ) -> Result<(Vec<f64>, Option<usize>), BrownianError> {
        let f = self.generalised_forces(&bd.forces, bd.moments);
        let scale = (2.0 * bd.kt * bd.dt).sqrt();
        let mut iterations = None;
        let (mf, noise): (Vec<f64>, Vec<f64>) = match bd.noise {
            _ if !bd.hydrodynamics => {
                let mob = self.stokes_mobility(bd.moments);
                (
                    f.iter().zip(&mob).map(|(f, m)| m * f).collect(),
                    w.iter()
                        .zip(&mob)
                        .map(|(w, m)| m.sqrt() * w * scale)
                        .collect(),
                )
            }
            Noise::Cholesky => {
                let m = self.mobility(bd.moments);
                let chol = Cholesky::new(&m).ok_or(BrownianError::NotPositiveDefinite(step))?;
                let noise = chol.l_mul(w).into_iter().map(|v| v * scale).collect();
                (mul_vec(&m, &f), noise)
            }
            Noise::Lanczos { tol } => {
                let (y, k) = lanczos_sqrt(
                    |x| self.apply_in(bd.moments, x, Precision::Double),
                    w,
                    tol,
                    w.len(),
                )
                .map_err(|source| BrownianError::Lanczos { step, source })?;
                iterations = Some(k);
                (
                    self.apply_in(bd.moments, &f, Precision::Double),
                    y.iter().map(|v| v * scale).collect(),
                )
            }
        };
        let div = if bd.drift && bd.hydrodynamics {
            self.check_drift()?;
            self.divergence_at(bd.moments)
        } else {
            vec![0.0; w.len()]
        };
        let dx = mf
            .iter()
            .zip(&noise)
            .zip(&div)
            .map(|((mf, noise), div)| (mf + bd.kt * div) * bd.dt + noise)
            .collect();
        Ok((dx, iterations))
    }

    /// Fixman's midpoint scheme (Fixman 1978; Delong, Balboa Usabiaga & Donev 2014):
    /// with `M^n = B B^T` (Cholesky),
    ///
    /// ```text
    /// x* = x + (dt/2) M^n F^n + sqrt(kT dt / 2) B W
    /// dx = dt M* F* + sqrt(2 kT dt) M* B^{-T} W
    /// ```
    ///
    /// The second noise term has covariance `2 kT dt M` to leading order and, because
    /// `M*` is evaluated at the randomly displaced midpoint, mean
    /// `kT dt sum_j dM_ij/dx_j + O(dt^2)`: the drift comes out of the scheme without the
    /// divergence kernels, and the deterministic part is the second-order midpoint rule.
    fn fixman_midpoint(
        &self,
        bd: &Brownian,
        w: &[f64],
        step: usize,
    ) -> Result<Vec<f64>, BrownianError> {
        if bd.noise != Noise::Cholesky {
            return Err(BrownianError::Unsupported(
                "the Fixman midpoint scheme with Lanczos noise (it needs B^-T W; use Cholesky)",
            ));
        }
        let m = self.mobility(bd.moments);
        let chol = Cholesky::new(&m).ok_or(BrownianError::NotPositiveDefinite(step))?;
        let f = self.generalised_forces(&bd.forces, bd.moments);
        let (drift_half, noise_half) = ((0.5 * bd.dt), (0.5 * bd.kt * bd.dt).sqrt());
        let half: Vec<f64> = mul_vec(&m, &f)
            .iter()
            .zip(chol.l_mul(w))
            .map(|(mf, lw)| mf * drift_half + lw * noise_half)
            .collect();
        let mid = self.displaced(&half, step)?;
        let m_mid = mid.mobility(bd.moments);
        let f_mid = mid.generalised_forces(&bd.forces, bd.moments);
        let y = chol.lt_solve(w);
        let scale = (2.0 * bd.kt * bd.dt).sqrt();
        let rhs: Vec<f64> = f_mid
            .iter()
            .zip(&y)
            .map(|(f, y)| f * bd.dt + y * scale)
            .collect();
        Ok(mul_vec(&m_mid, &rhs))
    }

    /// Brownian Stokesian dynamics ([`crate::dynamics`]): `w` is `6N` numbers for the noise,
    /// then `3N` for the random finite difference.
    fn lubricated_step(
        &self,
        bd: &Brownian,
        lub: &LubricatedDynamics,
        w: &[f64],
        step: usize,
    ) -> Result<Vec<f64>, BrownianError> {
        if !bd.hydrodynamics {
            return Err(BrownianError::Unsupported(
                "lubrication without hydrodynamic interactions",
            ));
        }
        if bd.noise != Noise::Cholesky {
            return Err(BrownianError::Unsupported(
                "lubrication with Lanczos noise (the noise is L^-T W from the Cholesky \
                 factor of the resistance)",
            ));
        }
        if bd.scheme != Scheme::EulerMaruyama {
            return Err(BrownianError::Unsupported(
                "lubrication with Fixman's scheme (the drift comes from a random finite \
                 difference; use Euler-Maruyama)",
            ));
        }
        let n = self.len();
        let (noise_w, rfd_w) = w.split_at(6 * n);
        let r = self
            .resistance(Moments::FT, &lub.lubrication)
            .map_err(|source| BrownianError::Resistance { step, source })?;
        let chol = Cholesky::new(&r).ok_or(BrownianError::NotPositiveDefinite(step))?;
        // torques are zero at the F level (checked by the caller)
        let u = chol.solve(&self.generalised_forces(&bd.forces, Moments::FT));
        let noise = chol.lt_solve(noise_w);
        let drift = if bd.drift {
            self.lubricated_divergence(lub, rfd_w, step)?
        } else {
            vec![0.0; 6 * n]
        };
        let scale = (2.0 * bd.kt * bd.dt).sqrt();
        let dx = (0..bd.moments.per_particle() * n)
            .map(|i| (u[i] + bd.kt * drift[i]) * bd.dt + scale * noise[i])
            .collect();
        Ok(dx)
    }

    /// `div R^-1` of the lubricated FT resistance (`6N`, moment-major: the translational
    /// and rotational rows, the divergence over the positions) by one random finite
    /// difference with the `3N` standard normal numbers `w` ([`crate::dynamics`]): an unbiased
    /// estimate up to `O(delta^2)`, `delta = lub.rfd_step` in units of each radius.
    /// Two resistances and their Cholesky factors at configurations displaced by
    /// `+-delta a W~ / 2`.
    pub fn lubricated_divergence(
        &self,
        lub: &LubricatedDynamics,
        w: &[f64],
        step: usize,
    ) -> Result<Vec<f64>, BrownianError> {
        let n = self.len();
        if w.len() != 3 * n {
            return Err(BrownianError::RandomNumbers {
                expected: 3 * n,
                found: w.len(),
            });
        }
        let delta = lub.rfd_step.min(0.1 * self.smallest_gap());
        let radius = |i: usize| self.particles()[i / 3].a;
        let shift: Vec<f64> = (0..3 * n).map(|i| 0.5 * delta * radius(i) * w[i]).collect();
        let v: Vec<f64> = (0..6 * n)
            .map(|i| if i < 3 * n { w[i] / radius(i) } else { 0.0 })
            .collect();
        let mobility_times_v = |sign: f64| -> Result<Vec<f64>, BrownianError> {
            let moved: Vec<f64> = shift.iter().map(|s| sign * s).collect();
            let r = self
                .displaced(&moved, step)?
                .resistance(Moments::FT, &lub.lubrication)
                .map_err(|source| BrownianError::Resistance { step, source })?;
            Ok(Cholesky::new(&r)
                .ok_or(BrownianError::NotPositiveDefinite(step))?
                .solve(&v))
        };
        let plus = mobility_times_v(1.0)?;
        let minus = mobility_times_v(-1.0)?;
        Ok(plus
            .iter()
            .zip(&minus)
            .map(|(p, m)| (p - m) / delta)
            .collect())
    }

    /// The smallest gap over the radius (the smaller of the two for a pair) of any
    /// sphere to a boundary or to another sphere (in a periodic box, to the nearest
    /// images of the others and of itself); infinite for one sphere in free space.
    fn smallest_gap(&self) -> f64 {
        let ps = self.particles();
        let mut gap = f64::INFINITY;
        for (a, p) in ps.iter().enumerate() {
            for b in self.confinement().boundaries() {
                gap = gap.min((b.distance(p.x).abs() - p.a) / p.a);
            }
            let bx = self.periodic_box();
            for q in &ps[a + 1..] {
                // in a periodic box, the nearest image
                let d = match bx {
                    Some(bx) => bx.minimum_image(p.x, q.x),
                    None => std::array::from_fn(|i| p.x[i] - q.x[i]),
                };
                let r = d.iter().map(|v| v.powi(2)).sum::<f64>().sqrt();
                gap = gap.min((r - p.a - q.a) / p.a.min(q.a));
            }
            // and its own nearest images
            for &l in bx.iter().flat_map(|bx| bx.lengths.as_slice()) {
                gap = gap.min((l - 2.0 * p.a) / p.a);
            }
        }
        gap
    }

    /// The system with every centre moved by the `U` rows of `increment` (moment-major:
    /// `3N` translations first).
    fn displaced(&self, increment: &[f64], step: usize) -> Result<System, BrownianError> {
        let ps: Vec<Particle> = self
            .particles()
            .iter()
            .enumerate()
            .map(|(a, p)| Particle {
                x: std::array::from_fn(|i| p.x[i] + increment[3 * a + i]),
                a: p.a,
            })
            .collect();
        // overlaps stay refused unless the RPY forms evaluate them
        let overlap = match self.overlap() {
            Overlap::Rpy => Overlap::Rpy,
            Overlap::Refuse | Overlap::Far => Overlap::Refuse,
        };
        let mut system = System::new(*self.confinement(), self.viscosity(), ps, overlap)
            .map_err(|source| BrownianError::Invalid { step, source })?;
        // the fast product's setting moves with the spheres ([`System::with_fmm`])
        system.set_fast(self.fast());
        // in a periodic box the positions stay unwrapped (every sum is over the lattice);
        // spheres overlapping by their nearest images are an invalid step, as in open
        // space (the box itself was validated before)
        let Some(bx) = self.periodic_box() else {
            return Ok(system);
        };
        system.periodic(bx).map_err(|e| match e {
            PeriodicError::Overlap {
                first,
                second,
                distance,
                sum,
            } => BrownianError::Invalid {
                step,
                source: InputError::Overlap {
                    first,
                    second,
                    distance,
                    sum,
                },
            },
            other => BrownianError::Periodic(other),
        })
    }

    /// External forces (and at the FT level torques), moment-major like the mobility.
    fn generalised_forces(&self, f: &ExternalForces, moments: Moments) -> Vec<f64> {
        let mut out = self.external_forces(f);
        if moments == Moments::FT {
            out.extend((0..self.len()).flat_map(|_| f.torque));
        }
        out
    }

    /// Without hydrodynamic interactions: the isolated Stokes mobilities
    /// `1/(6 pi eta a)` and `1/(8 pi eta a^3)`, moment-major.
    fn stokes_mobility(&self, moments: Moments) -> Vec<f64> {
        let eta = self.viscosity();
        let t = self
            .particles()
            .iter()
            .flat_map(|p| [1.0 / (6.0 * PI * eta * p.a); 3]);
        let r = self
            .particles()
            .iter()
            .flat_map(|p| [1.0 / (8.0 * PI * eta * p.a.powi(3)); 3]);
        match moments {
            Moments::FT => t.chain(r).collect(),
            _ => t.collect(),
        }
    }

    /// The drift `div M` (with [`crate::Overlap::Rpy`] that of the damped mobility;
    /// [`System::check_drift`] says where it is not available) at the F level (`3N`) or
    /// the FT level (`6N`, moment-major: translational then rotational rows; the columns
    /// are always the forces, since the mobility of spheres does not depend on their
    /// orientation). In a triply periodic box it is zero (every part of the Ewald split is
    /// divergence-free); near a wall in a box periodic along it, each sphere's is the
    /// height derivative of its periodic self mobility ([`crate::periodic::wall::WallEwald::drift`]).
    pub fn divergence_at(&self, moments: Moments) -> Vec<f64> {
        let n = self.len();
        if let Some(p) = self.periodic_ref() {
            let mut out = vec![0.0; moments.per_particle() * n];
            let eta = self.viscosity();
            let ps = self.particles();
            // each sphere's own images near walls; zero in a triply periodic box. The
            // kernels evaluate wrapped positions (crate::periodic)
            let own = |q: &Particle| -> [f64; 3] {
                let q = Particle {
                    x: p.bx.wrap(q.x),
                    a: q.a,
                };
                match &p.lattice {
                    crate::periodic::Lattice::Wall(w) => w.drift(eta, &q),
                    crate::periodic::Lattice::Slit(s) => s.drift(eta, &q),
                    crate::periodic::Lattice::Triply(_) => [0.0; 3],
                }
            };
            if !matches!(p.lattice, crate::periodic::Lattice::Triply(_)) {
                let drift: Vec<[f64; 3]> = ps.par_iter().map(own).collect();
                for (a, d) in drift.iter().enumerate() {
                    out[3 * a..3 * a + 3].copy_from_slice(d);
                }
            }
            return out;
        }
        let d = self.divergence_ft();
        match moments {
            Moments::FT => d,
            _ => d[..3 * n].to_vec(),
        }
    }
}
