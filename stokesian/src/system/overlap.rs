//! Overlapping spheres: what [`Overlap`] asks for, and with [`Overlap::Rpy`] the pairs
//! that take the Rotne-Prager-Yamakawa overlap forms and the damping of spheres that cut
//! a boundary ([`Rpy`]); the typed error of what the overlap forms do not cover
//! ([`OverlapError`]).
//!
//! Pairs: the generated correction kernels `kernels::overlap_f` and
//! `kernels::overlap_ft` (overlap form minus far form, zero at contact) are added to the
//! blocks of the overlapping pairs only, in a scalar pass after the lane tiles
//! (`mobility::assembly`, `mobility::tiled`): the far form is the free-space part of
//! every pair kernel, so a pair's block becomes the overlap form plus the confinement's
//! image terms. The corrections are divergence-free over either centre (the RPY tensor
//! and the far form both are: surface averages of the Stokeslet, whose curl parts
//! `k(r) [r/r]_x` have zero divergence too), so the Brownian drift of the generated
//! divergence kernels stays exact.
//!
//! Boundaries (Usabiaga et al., J. Chem. Phys. 146, 134104 (2017), Appendix 1, as
//! libMobility's NBody solver does for a wall): a sphere whose centre is at a distance
//! `0 < d < a` from a boundary is evaluated with its centre moved out along the normal
//! to `d = a`, and every block of its rows and columns (self and pair, direct and
//! image) is multiplied by `b_i = clamp(d / a, 0, 1)`: the mobility is `B M(clamped) B`,
//! `B = diag(b_i)`, symmetric positive definite whenever `M` at the clamped centres is.
//! With several boundaries each is clamped in turn and `b_i` is the product over the
//! boundaries: one boundary's factor where only one is cut (the wall's damping), a
//! smooth factor where two are (the minimum has a kink where the distances cross), and
//! still `B M B`. A sphere that cannot be moved clear of every boundary (a slit
//! narrower than its diameter) is refused. The divergence of the damped mobility is not
//! available from the kernels: the Euler-Maruyama drift is refused while a sphere is
//! damped ([`OverlapError::Boundary`]); Fixman's midpoint scheme, which needs no
//! divergence, is not.

use super::input::Particle;
use super::Moments;
use kernels::Confinement;
use thiserror::Error;

/// What to do with spheres that overlap each other or cut a boundary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Overlap {
    /// Refuse them ([`crate::InputError::Overlap`], [`crate::InputError::OverlapsBoundary`]).
    #[default]
    Refuse,
    /// Accept them and evaluate the far forms anyway (not positive definite where
    /// spheres overlap).
    Far,
    /// Accept them: overlapping pairs take the Rotne-Prager-Yamakawa overlap forms and
    /// spheres cutting a boundary are damped (module docs); symmetric positive definite.
    /// F and FT only.
    Rpy,
}

/// `false` is [`Overlap::Refuse`], `true` is [`Overlap::Far`] (what `allow_overlap`
/// meant).
impl From<bool> for Overlap {
    fn from(allow: bool) -> Overlap {
        if allow {
            Overlap::Far
        } else {
            Overlap::Refuse
        }
    }
}

/// What the RPY overlap forms do not cover, asked of a system with [`Overlap::Rpy`].
#[derive(Debug, Error, PartialEq, Eq)]
pub enum OverlapError {
    /// Two spheres overlap, and `what` has no overlap form.
    #[error("particles {first} and {second} overlap: the RPY overlap forms cover forces and torques (F, FT) only, not {what}")]
    Pair {
        /// First particle.
        first: usize,
        /// Second particle.
        second: usize,
        /// What was asked for.
        what: &'static str,
    },
    /// A sphere cuts a boundary, and `what` has no damped form.
    #[error("particle {index} cuts a boundary: the damped mobility covers forces and torques (F, FT) without Brownian drift only, not {what}")]
    Boundary {
        /// Particle index.
        index: usize,
        /// What was asked for.
        what: &'static str,
    },
}

/// What [`Overlap::Rpy`] changes in a system where something overlaps.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Rpy {
    /// The overlapping pairs `(i, j)`, `i < j`, sorted, at the evaluated centres.
    pub pairs: Vec<(usize, usize)>,
    /// The damping of spheres cutting a boundary, if any does.
    pub damping: Option<Damping>,
}

/// Spheres cutting a boundary: the centres the kernels see and the factors `b_i`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Damping {
    /// The particles with each centre moved clear of every boundary.
    pub at: Vec<Particle>,
    /// `b_i`: the product over the boundaries of `clamp(d / a, 0, 1)`.
    pub b: Vec<f64>,
}

impl Damping {
    /// The damping of `particles` (every centre inside the fluid), if any sphere cuts a
    /// boundary; `Err(index)` for a sphere that cannot be moved clear of every
    /// boundary at once.
    pub fn of(conf: &Confinement, particles: &[Particle]) -> Result<Option<Damping>, usize> {
        let planes = conf.boundaries();
        let mut at = particles.to_vec();
        let mut b = vec![1.0; particles.len()];
        let mut any = false;
        for (i, p) in at.iter_mut().enumerate() {
            for plane in &planes {
                let d = plane.distance(p.x);
                if d < p.a {
                    any = true;
                    b[i] *= (d / p.a).clamp(0.0, 1.0);
                    let up = p.a - d;
                    for (x, n) in p.x.iter_mut().zip(plane.normal) {
                        *x += up * n;
                    }
                }
            }
            // clear of every plane, to the rounding of the moves
            if planes.iter().any(|q| q.distance(p.x) < p.a * (1.0 - 1e-12)) {
                return Err(i);
            }
        }
        Ok(any.then_some(Damping { at, b }))
    }
}

impl Rpy {
    /// The error for `what` if this system overlaps anything.
    pub fn refuse(&self, what: &'static str) -> Result<(), OverlapError> {
        if let Some(&(first, second)) = self.pairs.first() {
            return Err(OverlapError::Pair {
                first,
                second,
                what,
            });
        }
        self.refuse_damping(what)
    }

    /// The error for `what` if a sphere is damped.
    pub fn refuse_damping(&self, what: &'static str) -> Result<(), OverlapError> {
        match self
            .damping
            .as_ref()
            .and_then(|d| d.b.iter().position(|&b| b < 1.0))
        {
            Some(index) => Err(OverlapError::Boundary { index, what }),
            None => Ok(()),
        }
    }
}

/// The RPY correction `M^{ab}` (overlap form minus far form) truncated to `moments` (F
/// or FT), row-major `K x K` in grand order into `out`.
pub(crate) fn correction(moments: Moments, eta: f64, p: &Particle, q: &Particle, out: &mut [f64]) {
    match moments {
        Moments::F => {
            let c = kernels::overlap_f(p.x, q.x, p.a, q.a, eta);
            for i in 0..3 {
                out[3 * i..3 * i + 3].copy_from_slice(&c.uf[i]);
            }
        }
        Moments::FT => {
            let m = kernels::overlap_ft(p.x, q.x, p.a, q.a, eta).matrix();
            for i in 0..6 {
                out[6 * i..6 * i + 6].copy_from_slice(&m[i]);
            }
        }
        Moments::FTS => unreachable!("refused before: no overlap form with stresslets"),
    }
}
