//! Validation of particles, viscosity and confinement parameters, and the overlapping
//! pairs (one neighbour search for the check and for the RPY overlap forms).

use super::overlap::{Damping, Overlap, Rpy};
use kernels::{Boundary, Confinement, Dimension};
use thiserror::Error;

/// A sphere: centre and radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle {
    /// Centre `[x1, x2, x3]`.
    pub x: [f64; 3],
    /// Radius.
    pub a: f64,
}

/// Why an input cannot be used. Particles are numbered from 0 in input order.
#[derive(Debug, Error, PartialEq)]
pub enum InputError {
    /// No particles were given.
    #[error("no particles given")]
    Empty,
    /// A coordinate is NaN or infinite.
    #[error("particle {index}: coordinate {axis} is {value}, not a finite number")]
    NonFinitePosition {
        /// Particle index.
        index: usize,
        /// Axis name (`x`, `y`, `z`).
        axis: char,
        /// The value.
        value: f64,
    },
    /// The radius is not a positive finite number.
    #[error("particle {index}: radius {value} must be a positive finite number")]
    BadRadius {
        /// Particle index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// The viscosity is not a positive finite number.
    #[error("viscosity {0} must be a positive finite number")]
    BadViscosity(f64),
    /// A confinement parameter is out of range.
    #[error("{name} = {value}: {why}")]
    BadParameter {
        /// Parameter name.
        name: &'static str,
        /// The value.
        value: f64,
        /// What it must be.
        why: &'static str,
    },
    /// The length scale is outside the range where `1 / (eta a^3)`, the scale of the
    /// rotation and strain mobilities, and its inverse are normal double-precision
    /// numbers: the kernels' results would overflow or vanish.
    #[error("particle {index}: radius {a:?} with viscosity {eta:?}: 1/(viscosity a^3) is outside the range of double precision; express lengths and viscosity in other units so that radii and viscosity are nearer 1")]
    Unrepresentable {
        /// Particle index.
        index: usize,
        /// Radius.
        a: f64,
        /// Viscosity.
        eta: f64,
    },
    /// The centre is at or beyond a boundary.
    #[error(
        "particle {index}: centre is not inside the fluid: signed distance {distance} from the boundary, {boundary}"
    )]
    OutsideFluid {
        /// Particle index.
        index: usize,
        /// Its signed distance from the boundary (positive in the fluid).
        distance: f64,
        /// The boundary it crosses.
        boundary: Boundary,
    },
    /// The sphere cuts a boundary: distance from centre to boundary below its radius.
    #[error("particle {index}: sphere of radius {a} overlaps the boundary, {boundary} (centre-to-boundary distance {distance})")]
    OverlapsBoundary {
        /// Particle index.
        index: usize,
        /// Radius.
        a: f64,
        /// Distance from centre to boundary.
        distance: f64,
        /// The boundary.
        boundary: Boundary,
    },
    /// Two spheres overlap.
    #[error(
        "particles {first} and {second} overlap: centre distance {distance} < sum of radii {sum}"
    )]
    Overlap {
        /// First particle.
        first: usize,
        /// Second particle.
        second: usize,
        /// Centre distance.
        distance: f64,
        /// Sum of radii.
        sum: f64,
    },
    /// Two spheres have the same centre: the pair kernels are undefined, overlaps
    /// allowed or not.
    #[error("particles {first} and {second} have the same centre; the mobility is undefined")]
    SameCentre {
        /// First particle.
        first: usize,
        /// Second particle.
        second: usize,
    },
}

/// The confinement's parameters checked by their declared dimension (a length
/// positive, a pure number, such as a viscosity ratio, non-negative, a position
/// finite), and its boundary planes.
fn planes(conf: &Confinement) -> Result<Vec<Boundary>, InputError> {
    for (p, (name, value)) in conf.declaration().params.iter().zip(conf.params()) {
        let (ok, why) = match p.dimension {
            Dimension::Number => (
                value >= 0.0 && value.is_finite(),
                "a ratio must be a non-negative finite number",
            ),
            Dimension::Length => (
                value > 0.0 && value.is_finite(),
                "a length must be a positive finite number",
            ),
            Dimension::Position(_) => (value.is_finite(), "must be a finite number"),
        };
        if !ok {
            return Err(InputError::BadParameter { name, value, why });
        }
    }
    Ok(conf.boundaries())
}

/// Check everything the kernels assume: finite positions, positive radii and
/// viscosity at a representable length scale, centres inside the fluid, spheres clear
/// of the boundaries and of each other (unless `overlap` accepts them), and no two
/// centres the same.
pub fn validate(
    conf: &Confinement,
    eta: f64,
    particles: &[Particle],
    overlap: impl Into<Overlap>,
) -> Result<(), InputError> {
    prepare(conf, eta, particles, overlap.into()).map(|_| ())
}

/// [`validate`], and with [`Overlap::Rpy`] what it changes where something overlaps:
/// the overlapping pairs and the damping, found at the centres the kernels see (moved
/// clear of the boundaries), which must be distinct too.
pub(crate) fn prepare(
    conf: &Confinement,
    eta: f64,
    particles: &[Particle],
    overlap: Overlap,
) -> Result<Option<Rpy>, InputError> {
    if particles.is_empty() {
        return Err(InputError::Empty);
    }
    if !(eta > 0.0 && eta.is_finite()) {
        return Err(InputError::BadViscosity(eta));
    }
    let planes = planes(conf)?;
    for (index, p) in particles.iter().enumerate() {
        for (k, &value) in p.x.iter().enumerate() {
            if !value.is_finite() {
                let axis = ['x', 'y', 'z'][k];
                return Err(InputError::NonFinitePosition { index, axis, value });
            }
        }
        if !(p.a > 0.0 && p.a.is_finite()) {
            return Err(InputError::BadRadius { index, value: p.a });
        }
        let scale = eta * p.a * p.a * p.a;
        if !(scale.is_normal() && scale.recip().is_normal()) {
            return Err(InputError::Unrepresentable { index, a: p.a, eta });
        }
        for &boundary in &planes {
            let distance = boundary.distance(p.x);
            if distance <= 0.0 {
                return Err(InputError::OutsideFluid {
                    index,
                    distance,
                    boundary,
                });
            }
            if distance < p.a && overlap == Overlap::Refuse {
                return Err(InputError::OverlapsBoundary {
                    index,
                    a: p.a,
                    distance,
                    boundary,
                });
            }
        }
    }
    if overlap == Overlap::Refuse {
        if let Some(&(i, j)) = overlapping_pairs(particles).first() {
            let (p, q) = (&particles[i], &particles[j]);
            let d2: f64 = (0..3).map(|k| (p.x[k] - q.x[k]).powi(2)).sum();
            return Err(InputError::Overlap {
                first: i,
                second: j,
                distance: d2.sqrt(),
                sum: p.a + q.a,
            });
        }
    }
    if let Some((first, second)) = first_same_centre(particles) {
        return Err(InputError::SameCentre { first, second });
    }
    if overlap != Overlap::Rpy {
        return Ok(None);
    }
    let damping = Damping::of(conf, particles).map_err(|index| {
        let p = &particles[index];
        // the boundary it cannot be moved clear of: the nearest
        let (distance, boundary) = planes
            .iter()
            .map(|b| (b.distance(p.x), *b))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .expect("a sphere is damped only near a boundary");
        InputError::OverlapsBoundary {
            index,
            a: p.a,
            distance,
            boundary,
        }
    })?;
    let at = damping.as_ref().map_or(particles, |d| &d.at[..]);
    if let Some((first, second)) = first_same_centre(at) {
        return Err(InputError::SameCentre { first, second });
    }
    let pairs = overlapping_pairs(at);
    Ok((damping.is_some() || !pairs.is_empty()).then_some(Rpy { pairs, damping }))
}

/// The first pair `(i, j)`, `i < j`, of spheres with the same centre, if any (sorted by
/// centre, such pairs are neighbours: `O(N log N)`).
fn first_same_centre(particles: &[Particle]) -> Option<(usize, usize)> {
    let mut order: Vec<usize> = (0..particles.len()).collect();
    // adding zero makes -0 and +0 the same key, as they are the same point
    let key = |i: usize| particles[i].x.map(|v| v + 0.0);
    order.sort_by(|&i, &j| {
        let (p, q) = (key(i), key(j));
        (0..3)
            .map(|k| p[k].total_cmp(&q[k]))
            .find(|o| o.is_ne())
            .unwrap_or(i.cmp(&j))
    });
    order
        .windows(2)
        .filter(|w| key(w[0]) == key(w[1]))
        .map(|w| (w[0].min(w[1]), w[0].max(w[1])))
        .min()
}

/// Every overlapping pair `(i, j)`, `i < j`, in index order (the first is the one
/// [`InputError::Overlap`] names). Sweep along `x1`: only spheres whose centres are
/// closer than `a_i + max a` in `x1` can overlap, so sorted by `x1` each sphere is
/// compared with its few neighbours (`O(N log N)` plus the pairs for a suspension, where
/// all pairs would be `O(N^2)`).
pub(crate) fn overlapping_pairs(particles: &[Particle]) -> Vec<(usize, usize)> {
    let amax = particles.iter().map(|p| p.a).fold(0.0, f64::max);
    let mut order: Vec<usize> = (0..particles.len()).collect();
    order.sort_by(|&i, &j| particles[i].x[0].total_cmp(&particles[j].x[0]));
    let mut pairs = Vec::new();
    for (s, &i) in order.iter().enumerate() {
        let p = &particles[i];
        for &j in &order[s + 1..] {
            let q = &particles[j];
            if q.x[0] - p.x[0] >= p.a + amax {
                break;
            }
            let d2: f64 = (0..3).map(|k| (p.x[k] - q.x[k]).powi(2)).sum();
            let sum = p.a + q.a;
            if d2 < sum * sum {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}
