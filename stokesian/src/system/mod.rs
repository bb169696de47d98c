//! The validated system of spheres and its core: [`System`] (spheres in a confinement,
//! validated once on construction, so that every method is infallible), the truncation
//! [`Moments`], the arithmetic [`Precision`] of the matrix-free product, the moment-major
//! layout of Eq. 1, the validation of the input ([`input`]), and what is done with
//! overlapping spheres ([`overlap`]).
//!
//! `System`'s methods live with the subsystem they belong to:
//!
//! | methods | module |
//! |---|---|
//! | `with_fmm`, `fmm`, `apply_fmm`, `apply_fast` (the fast product) | [`crate::fmm`] |
//! | `new`, `with_precision`, `precision`, `particles`, `confinement`, `viscosity`, `len`, `is_empty`, `overlap`, `check_overlap`, `check_drift`, `sqrt_apply` | here |
//! | `periodic`, `periodic_box` (a periodic box) | [`crate::periodic`] |
//! | `block`, `mobility`, `mobility_into` (the dense grand mobility) | [`crate::mobility::assembly`] |
//! | `apply`, `apply_with` (the matrix-free product) | [`crate::mobility::tiled`] |
//! | `velocities` (the mobility problem) | [`crate::mobility::velocity`] |
//! | `resistance` (Eq. 19) | [`crate::resistance::lubrication`] |
//! | `brownian_run`, `brownian_step`, `brownian_increment`, `external_forces`, `divergence`, `divergence_at`, `lubricated_divergence` | [`crate::dynamics::brownian`] |

pub mod input;
pub mod overlap;

use crate::periodic::Periodic;
use input::{prepare, InputError, Particle};
use kernels::Confinement;
use overlap::{Overlap, OverlapError, Rpy};

/// Below this many particles the pair loops run on the calling thread: handing a few
/// pairs to the thread pool costs more than computing them (it dominated Brownian
/// steps of two spheres).
pub(crate) const PARALLEL_MIN: usize = 32;

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

/// The arithmetic of the matrix-free product ([`System::apply_with`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Precision {
    /// `f64` lanes: the kernels' full accuracy (about 1e-15 per pair).
    #[default]
    Double,
    /// `f32` lanes, twice as many pairs per instruction, in units where the largest
    /// radius, the viscosity and the largest moment are 1 (so any units of the input
    /// work); every total is still summed in `f64`. About 1e-7 of the product's norm
    /// (at most 2e-6 in the tests). The F and FT products: FTS products, and systems of
    /// 2^24 particles or more, run in double precision (the tiles count particles in the
    /// lanes' precision; `f32` lanes of the FTS kernels, the largest, were a large part
    /// of the solver's build, for stresslets that are usually wanted to more than seven
    /// digits).
    Single,
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
    pub(crate) fn parts(self) -> &'static [(usize, usize)] {
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
    precision: Precision,
    overlap: Overlap,
    /// With [`Overlap::Rpy`], where something overlaps: the pairs and the damping.
    rpy: Option<Rpy>,
    /// The periodic box, if any ([`System::periodic`]).
    periodic: Option<Periodic>,
    /// The fast product's parameters, if [`System::apply`] takes it
    /// ([`System::with_fmm`]).
    fast: Option<crate::FastProduct>,
    /// In a periodic box with the fast product: the box's split at the fast product's
    /// tolerance, whose own fast product [`System::apply`] then takes.
    fast_periodic: Option<Periodic>,
}

impl System {
    /// Validate and build. Overlapping spheres (with each other or a boundary) are
    /// errors, evaluated with the far forms or with the RPY overlap forms as `overlap`
    /// says ([`Overlap`]; `false` and `true` are [`Overlap::Refuse`] and
    /// [`Overlap::Far`]).
    pub fn new(
        confinement: Confinement,
        viscosity: f64,
        particles: Vec<Particle>,
        overlap: impl Into<Overlap>,
    ) -> Result<System, InputError> {
        let overlap = overlap.into();
        let rpy = prepare(&confinement, viscosity, &particles, overlap)?;
        Ok(System {
            confinement,
            viscosity,
            particles,
            precision: Precision::Double,
            overlap,
            rpy,
            periodic: None,
            fast: None,
            fast_periodic: None,
        })
    }

    /// What is done with overlapping spheres.
    pub fn overlap(&self) -> Overlap {
        self.overlap
    }

    /// Whether the mobility at `moments` is available as [`Overlap::Rpy`] asks: not
    /// with the stresslets (FTS) where spheres overlap or cut a boundary. The dense
    /// matrix, its blocks and the product panic where this is an error; the velocities,
    /// resistances and Brownian dynamics return it.
    pub fn check_overlap(&self, moments: Moments) -> Result<(), OverlapError> {
        match (&self.rpy, moments) {
            (Some(rpy), Moments::FTS) => rpy.refuse("the stresslets (FTS)"),
            _ => Ok(()),
        }
    }

    /// Whether [`System::divergence_at`] is this system's Brownian drift: always, except
    /// where [`Overlap::Rpy`] damps a sphere cut by two boundaries that are not
    /// perpendicular (no registered confinement has such boundaries; [`overlap`]).
    pub fn check_drift(&self) -> Result<(), OverlapError> {
        match self.rpy.as_ref().and_then(|r| r.damping.as_ref()) {
            Some(d) => match d.oblique() {
                Some(index) => Err(OverlapError::Boundary {
                    index,
                    what: "the Brownian drift (div M) of a sphere cut by two boundaries that are not perpendicular",
                }),
                None => Ok(()),
            },
            None => Ok(()),
        }
    }

    /// The periodic box and its split, if any.
    pub(crate) fn periodic_ref(&self) -> Option<&Periodic> {
        self.periodic.as_ref()
    }

    pub(crate) fn set_periodic(&mut self, p: Option<Periodic>) {
        self.periodic = p;
        self.sync_fast_periodic();
    }

    /// With [`Overlap::Rpy`], where something overlaps: the pairs and the damping.
    pub(crate) fn rpy(&self) -> Option<&Rpy> {
        self.rpy.as_ref()
    }

    /// A square-root factor `S` of the mobility at `moments` (F or FT; `S S^T = M`)
    /// applied to `w`, by Lanczos to relative tolerance `tol` (iterations returned):
    /// `M^{1/2} w`, except where [`Overlap::Rpy`] damps a sphere cutting a boundary, where
    /// it is `B M_c^{1/2} w` with `M_c` the mobility at the clamped centres (undamped):
    /// also a factor of `B M_c B`, and Lanczos converges on the well-conditioned `M_c`
    /// rather than on `B M_c B`, whose eigenvalues go to zero with the factors `b_i`
    /// (where the noise, whitened by `M^{-1/2}`, would carry the Lanczos error divided by
    /// `b_i`). Panics where [`System::check_overlap`] fails.
    pub fn sqrt_apply(
        &self,
        moments: Moments,
        w: &[f64],
        tol: f64,
    ) -> Result<(Vec<f64>, usize), crate::LanczosError> {
        let damped = self
            .rpy
            .as_ref()
            .and_then(|r| r.damping.as_ref().map(|d| (r, d)));
        let Some((rpy, d)) = damped else {
            return crate::lanczos_sqrt(|x| self.apply(moments, x), w, tol, w.len());
        };
        let clamped = System {
            particles: d.at.clone(),
            rpy: Some(Rpy {
                pairs: rpy.pairs.clone(),
                damping: None,
            }),
            ..self.clone()
        };
        let (mut y, k) = crate::lanczos_sqrt(|x| clamped.apply(moments, x), w, tol, w.len())?;
        let n = self.len();
        let parts = moments.parts();
        for (a, b) in d.b.iter().enumerate() {
            for i in 0..moments.per_particle() {
                y[global(parts, n, a, i)] *= b;
            }
        }
        Ok((y, k))
    }

    /// The particles as the kernels see them: with the damping of [`Overlap::Rpy`],
    /// centres moved clear of the boundaries.
    pub(crate) fn evaluated(&self) -> &[Particle] {
        match self.rpy.as_ref().and_then(|r| r.damping.as_ref()) {
            Some(d) => &d.at,
            None => &self.particles,
        }
    }

    /// Panics where [`System::check_overlap`] fails.
    pub(crate) fn assert_overlap(&self, moments: Moments) {
        if let Err(e) = self.check_overlap(moments) {
            panic!("{e} (System::check_overlap)");
        }
    }

    /// The same system with the matrix-free product [`System::apply`] (and with it the
    /// far-field F and FT velocities, [`System::velocities`]) in `precision`. Dense
    /// matrices, resistances and Brownian dynamics stay in double precision.
    pub fn with_precision(mut self, precision: Precision) -> System {
        self.precision = precision;
        self
    }

    /// The fast product's parameters ([`System::with_fmm`]).
    pub(crate) fn fast(&self) -> Option<crate::FastProduct> {
        self.fast
    }

    pub(crate) fn set_fast(&mut self, fast: Option<crate::FastProduct>) {
        self.fast = fast;
        self.sync_fast_periodic();
    }

    /// The periodic box's split at the fast product's tolerance, if both are set.
    pub(crate) fn fast_periodic(&self) -> Option<&Periodic> {
        self.fast_periodic.as_ref()
    }

    fn sync_fast_periodic(&mut self) {
        self.fast_periodic = match (&self.periodic, self.fast) {
            (Some(p), Some(f)) => Some(p.at_tolerance(&self.confinement, f.eps)),
            _ => None,
        };
    }

    /// The precision of [`System::apply`].
    pub fn precision(&self) -> Precision {
        self.precision
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
}

/// `(particle, component in grand order)` of index `c` in the moment-major layout (the
/// inverse of [`global`]).
pub(crate) fn component_of(parts: &[(usize, usize)], n: usize, c: usize) -> (usize, usize) {
    let mut moff = 0;
    for &(o, d) in parts {
        if c < moff + d * n {
            return ((c - moff) / d, o + (c - moff) % d);
        }
        moff += d * n;
    }
    unreachable!("index {c} beyond the kept moments")
}

/// Index in the moment-major layout of component `i` (grand order within the kept
/// moments) of particle `a`.
pub(crate) fn global(parts: &[(usize, usize)], n: usize, a: usize, i: usize) -> usize {
    let mut moff = 0;
    for &(o, d) in parts {
        if i < o + d {
            return moff + a * d + (i - o);
        }
        moff += d * n;
    }
    unreachable!("component {i} beyond the kept moments")
}
