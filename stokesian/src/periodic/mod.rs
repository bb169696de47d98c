//! Periodic boxes: spheres in a triply periodic box of unbounded fluid, above a plane
//! no-slip wall in a box periodic along it (x and y), or between two no-slip walls (a
//! slit, with its exact Green's function) periodic along them, the mobility summed over
//! every periodic image by Ewald summation ([`ewald`], [`wall`], [`slit`]). A [`System`] is made periodic
//! by [`System::periodic`], which validates the box against the spheres; the dense
//! mobility, its blocks, the product and the velocities (F and FT) then are the periodic
//! ones, and so is Brownian dynamics: in the triply periodic box the drift is zero (each
//! part of the split is divergence-free, as the free-space kernels are); near a periodic
//! wall each sphere's drift is the height derivative of its own periodic self mobility
//! ([`wall::WallEwald::drift`]: the pairs of distinct spheres add none). A step that
//! would overlap two spheres by their nearest images is redrawn like any invalid step. The dense
//! matrix and its blocks use the direct sums; the triply periodic product is the fast
//! one ([`product`]: real space over linked cells, reciprocal space by spectral Ewald),
//! `O(N)`, and so is the product along a periodic wall ([`wall_product`]); in the slit the
//! product is the two walls' fast products less the Stokeslet's they share, plus the
//! remainder's lateral modes ([`slit_product`]: one by one in a small box, on a lateral
//! grid by FFTs in a wide one).
//!
//! The resistance with lubrication ([`System::resistance`]) adds its pair corrections
//! for every image of a sphere within the window of the correction, a sphere's own
//! images included ([`PeriodicBox::separations`], [`PeriodicBox::own_images`]): the
//! near field of a pair is the same two-body problem wherever the pair sits in the
//! lattice, and the far field of every image is already in the periodic mobility.
//!
//! The stresslets (FTS) are available in every box: the dense mobility and its blocks
//! are the direct sums of [`Ewald::grand`], [`wall::WallEwald::grand`] or
//! [`slit::SlitEwald::grand`]; the product is the fast one in the triply periodic box,
//! the direct sums near walls; the lubricated resistance takes them.
//!
//! Not available in a periodic box (typed errors, or panics of the infallible dense
//! matrix and product, as for [`crate::Overlap::Rpy`]): the harmonic trap of Brownian
//! dynamics (not a periodic force), the
//! overlap forms (overlapping spheres are refused, by their nearest images), the
//! single-precision product (the periodic product is in `f64` whatever
//! [`crate::Precision`] asks), and every confinement but free space (three lengths), the
//! wall and the slit (two lengths, walls normal to `e3`): near a free surface or an
//! interface the lattice sum diverges (their far field parallel to the plane decays like
//! `1/rho`, and nothing balances a net lateral force); a wall of another normal is
//! periodic along its normal, which is meaningless; free space with two lengths leaves a
//! net lateral force unbalanced (`1/rho` again). The periodic slit is not the open
//! slit's kernels summed (those superpose two walls' images, whose far field tends to
//! `-J`): it is the exact slit ([`slit`]).
//!
//! Positions are kept as given (unwrapped) and wrapped into the box where the kernels
//! evaluate them ([`PeriodicBox::wrap`]): every sum is over the lattice, and a sphere
//! moved by box lengths (an exact move) gives the same bits.

mod cells;
pub mod ewald;
mod fft;
mod low_modes;
mod plane_mode;
mod product;
mod real;
pub mod slit;
mod slit_product;
mod spectral;
pub mod wall;
mod wall_product;
mod wall_spectral;

use crate::system::input::Particle;
use crate::system::Moments;
use crate::System;
use ewald::Ewald;
use kernels::{BlocksFT, Condition, Confinement};
use rayon::prelude::*;
use slit::SlitEwald;
use thiserror::Error;
use wall::WallEwald;
use wall_product::Sum;

/// A periodic box: its lengths and the tolerance of its lattice sums.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicBox {
    /// The periodic lengths.
    pub lengths: BoxLengths,
    /// Relative truncation error of the lattice sums, of each block's largest pair
    /// entry.
    pub tolerance: f64,
}

/// Along which axes a box is periodic, and its lengths there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BoxLengths {
    /// `[Lx, Ly, Lz]`: triply periodic (unbounded fluid).
    Triply([f64; 3]),
    /// `[Lx, Ly]`: periodic along a wall normal to `e3` (unbounded above it), or along
    /// the walls of a slit.
    Lateral([f64; 2]),
}

impl BoxLengths {
    /// The lengths, `x` first.
    pub fn as_slice(&self) -> &[f64] {
        match self {
            BoxLengths::Triply(l) => l,
            BoxLengths::Lateral(l) => l,
        }
    }

    /// The length along axis `d` (0, 1, 2 for x, y, z), if the box is periodic along it.
    pub fn along(&self, d: usize) -> Option<f64> {
        self.as_slice().get(d).copied()
    }
}

impl PeriodicBox {
    /// The default tolerance of the lattice sums.
    pub const TOLERANCE: f64 = 1e-10;

    /// A triply periodic box of `[Lx, Ly, Lz]` at the default tolerance.
    pub fn new(lengths: [f64; 3]) -> PeriodicBox {
        PeriodicBox {
            lengths: BoxLengths::Triply(lengths),
            tolerance: PeriodicBox::TOLERANCE,
        }
    }

    /// A box periodic along a wall, `[Lx, Ly]`, at the default tolerance.
    pub fn lateral(lengths: [f64; 2]) -> PeriodicBox {
        PeriodicBox {
            lengths: BoxLengths::Lateral(lengths),
            tolerance: PeriodicBox::TOLERANCE,
        }
    }

    /// `x` brought into the box along its periodic axes, `x - L floor(x/L)` (in `[0, L)`
    /// but for rounding): every kernel evaluates the wrapped positions, so a sphere
    /// moved by box lengths (an exact move) gives the same bits.
    pub fn wrap(&self, x: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|d| {
            self.lengths
                .along(d)
                .map_or(x[d], |l| x[d] - l * (x[d] / l).floor())
        })
    }

    /// The separation `x_a - x_b` of the nearest images: each periodic component in
    /// `[-L/2, L/2]`, the others as they are.
    pub fn minimum_image(&self, xa: [f64; 3], xb: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|d| {
            let r = xa[d] - xb[d];
            self.lengths.along(d).map_or(r, |l| r - l * (r / l).round())
        })
    }

    /// The separations `x_b + n L - x_a` of the periodic images of a sphere at `xb` from
    /// a sphere at `xa` whose length is at most `reach`, over every lattice vector `n L`
    /// (along the periodic axes; `n` in a fixed order, the last component fastest).
    pub fn separations(&self, xa: [f64; 3], xb: [f64; 3], reach: f64) -> Vec<[f64; 3]> {
        self.lattice(self.minimum_image(xb, xa), reach, false)
    }

    /// The lattice vectors `n L`, `n != 0`, of length at most `reach`, one of each pair
    /// `+-n` (the first non-zero component of `n` positive): the separations of a
    /// sphere's own images, each pair of which is one pair of spheres seen from either
    /// end.
    pub fn own_images(&self, reach: f64) -> Vec<[f64; 3]> {
        self.lattice([0.0; 3], reach, true)
    }

    /// `r0 + n L` of length at most `reach`, `n` in a fixed order (with `half`, `n` in
    /// the half lattice of [`PeriodicBox::own_images`]); `n_d = 0` along an axis that is
    /// not periodic.
    fn lattice(&self, r0: [f64; 3], reach: f64, half: bool) -> Vec<[f64; 3]> {
        let l: [f64; 3] = std::array::from_fn(|d| self.lengths.along(d).unwrap_or(0.0));
        let range = |d: usize| match self.lengths.along(d) {
            Some(l) => ((-reach - r0[d]) / l).ceil() as i64..=((reach - r0[d]) / l).floor() as i64,
            None => 0..=0,
        };
        let mut out = Vec::new();
        for n1 in range(0) {
            for n2 in range(1) {
                for n3 in range(2) {
                    if half && !(n1 > 0 || (n1 == 0 && (n2 > 0 || (n2 == 0 && n3 > 0)))) {
                        continue;
                    }
                    let n = [n1, n2, n3];
                    let r: [f64; 3] = std::array::from_fn(|d| r0[d] + n[d] as f64 * l[d]);
                    if r[0] * r[0] + r[1] * r[1] + r[2] * r[2] <= reach * reach {
                        out.push(r);
                    }
                }
            }
        }
        out
    }
}

/// What a periodic box cannot be, or cannot do.
#[derive(Debug, Error, PartialEq)]
pub enum PeriodicError {
    /// A box length is not a positive finite number.
    #[error("box length {axis} = {value} must be a positive finite number")]
    BadLength {
        /// `x`, `y` or `z`.
        axis: char,
        /// The value.
        value: f64,
    },
    /// The tolerance is not in `[1e-15, 1e-2]`.
    #[error("periodic tolerance {0} must be between 1e-15 and 1e-2")]
    BadTolerance(f64),
    /// The confinement has no periodic sum here.
    #[error("a periodic box is not available {where_}: {why}")]
    Confinement {
        /// Where (near what).
        where_: &'static str,
        /// Why.
        why: &'static str,
    },
    /// A sphere overlaps its own periodic image.
    #[error("particle {index}: sphere of radius {a} overlaps its own periodic image: box length {axis} = {length} is not more than its diameter")]
    OwnImage {
        /// Particle index.
        index: usize,
        /// Radius.
        a: f64,
        /// The axis.
        axis: char,
        /// The box length along it.
        length: f64,
    },
    /// Two spheres overlap, by their nearest images.
    #[error("particles {first} and {second} overlap in the periodic box: nearest-image distance {distance} < sum of radii {sum}")]
    Overlap {
        /// First particle.
        first: usize,
        /// Second particle.
        second: usize,
        /// Nearest-image centre distance.
        distance: f64,
        /// Sum of radii.
        sum: f64,
    },
    /// A sphere cuts the wall of a box periodic along it (the overlap forms of
    /// [`crate::Overlap::Rpy`] are not available in a periodic box).
    #[error("particle {index}: sphere of radius {a} cuts the wall (its centre {distance} above it): the overlap forms are not available in a periodic box")]
    CutsWall {
        /// Particle index.
        index: usize,
        /// Radius.
        a: f64,
        /// The centre's distance from the wall.
        distance: f64,
    },
    /// What a periodic box does not provide.
    #[error("{0}: not available in a periodic box")]
    NotAvailable(&'static str),
}

/// A validated box and its Ewald split.
#[derive(Clone, Debug)]
pub(crate) struct Periodic {
    pub(crate) bx: PeriodicBox,
    pub(crate) lattice: Lattice,
}

/// The Ewald sum of a box: triply periodic, or periodic along a wall.
#[derive(Clone, Debug)]
pub(crate) enum Lattice {
    /// Unbounded fluid, periodic in `x`, `y` and `z`.
    Triply(Ewald),
    /// Above a wall, periodic in `x` and `y`.
    Wall(WallEwald),
    /// Between two walls, periodic in `x` and `y`.
    Slit(SlitEwald),
}

impl Periodic {
    /// The same box's split at the lattice tolerance `tolerance`: what
    /// [`System::with_fmm`]'s fast product takes in a periodic box (its own fast product
    /// at the fast product's tolerance, [`System::apply`]).
    pub(crate) fn at_tolerance(&self, confinement: &Confinement, tolerance: f64) -> Periodic {
        let bx = PeriodicBox {
            tolerance,
            ..self.bx
        };
        let lattice =
            lattice(confinement, &bx).expect("the box was validated with this confinement");
        Periodic { bx, lattice }
    }

    /// A sphere with its centre brought into the box ([`PeriodicBox::wrap`]).
    fn wrapped(&self, s: &Particle) -> Particle {
        Particle {
            x: self.bx.wrap(s.x),
            a: s.a,
        }
    }

    /// The FT blocks `M^{ab}` of particles `p` (field) and `q` (source), every image
    /// summed; `p == q` for the self mobility.
    pub(crate) fn blocks(&self, eta: f64, ps: &[Particle], p: usize, q: usize) -> BlocksFT {
        let (a, b) = (self.wrapped(&ps[p]), self.wrapped(&ps[q]));
        match &self.lattice {
            Lattice::Triply(e) => e.blocks(eta, &a, &b, p == q),
            Lattice::Wall(w) => w.blocks(eta, &a, &b, p == q),
            Lattice::Slit(s) => s.blocks(eta, &a, &b, p == q),
        }
    }

    /// The block `M^{pq}` truncated to `moments`, row-major: [`Periodic::blocks`] at F
    /// and FT, [`Ewald::grand`], [`wall::WallEwald::grand`] or [`slit::SlitEwald::grand`]
    /// at FTS.
    pub(crate) fn block(
        &self,
        eta: f64,
        ps: &[Particle],
        p: usize,
        q: usize,
        moments: Moments,
    ) -> Vec<f64> {
        let k = moments.per_particle();
        let m: Vec<f64> = match (&self.lattice, moments) {
            (_, Moments::FTS) => {
                let (a, b) = (self.wrapped(&ps[p]), self.wrapped(&ps[q]));
                let g = match &self.lattice {
                    Lattice::Triply(e) => e.grand(eta, &a, &b, p == q),
                    Lattice::Wall(w) => w.grand(eta, &a, &b, p == q),
                    Lattice::Slit(s) => s.grand(eta, &a, &b, p == q),
                }
                .matrix();
                return (0..k * k).map(|e| g[(e / k, e % k)]).collect();
            }
            _ => self.blocks(eta, ps, p, q).matrix().concat(),
        };
        (0..k * k).map(|e| m[(e / k) * 6 + e % k]).collect()
    }
}

/// The Ewald sum of `bx` in `confinement`, or why there is none.
fn lattice(confinement: &Confinement, bx: &PeriodicBox) -> Result<Lattice, PeriodicError> {
    let bounds = confinement.boundaries();
    let refuse = |where_, why| Err(PeriodicError::Confinement { where_, why });
    if bounds
        .iter()
        .any(|b| matches!(b.condition, Condition::FreeSurface | Condition::Interface))
    {
        return refuse(
            "near a free surface or an interface",
            "the far field parallel to the plane decays like 1/rho, nothing balances a net lateral force, and the lattice sum diverges",
        );
    }
    match (bounds.as_slice(), bx.lengths) {
        ([], BoxLengths::Triply(l)) => Ok(Lattice::Triply(Ewald::new(l, bx.tolerance, None))),
        ([], BoxLengths::Lateral(_)) => refuse(
            "in unbounded fluid with two lengths (periodic in x and y only)",
            "a net lateral force is balanced by nothing, the far field decays like 1/rho and the lattice sum diverges; give three lengths for a triply periodic box",
        ),
        ([wall], BoxLengths::Lateral(l)) if wall.normal == [0.0, 0.0, 1.0] => Ok(Lattice::Wall(
            WallEwald::new(l, wall.offset, bx.tolerance, None),
        )),
        ([_], BoxLengths::Lateral(_)) => refuse(
            "near a wall whose normal is not e3",
            "the box is periodic in x and y, and a box periodic along the wall's normal is meaningless (use the wall normal to e3)",
        ),
        ([_], BoxLengths::Triply(_)) => refuse(
            "near a wall with three lengths",
            "the box is periodic along the wall only: give two lengths, Lx and Ly",
        ),
        ([bottom, top], BoxLengths::Lateral(l))
            if bottom.normal == [0.0, 0.0, 1.0] && top.normal == [0.0, 0.0, -1.0] =>
        {
            let gap = -top.offset - bottom.offset;
            Ok(Lattice::Slit(SlitEwald::new(
                l,
                bottom.offset,
                gap,
                bx.tolerance,
                None,
            )))
        }
        ([_, _], BoxLengths::Lateral(_)) => refuse(
            "in a slit whose walls are not normal to e3",
            "the box is periodic in x and y, along the walls of a slit normal to e3 only",
        ),
        (_, _) => refuse(
            "in a slit with three lengths",
            "the box is periodic along the walls only: give two lengths, Lx and Ly",
        ),
    }
}

impl System {
    /// This system in a periodic box: triply periodic unbounded fluid (confinement free,
    /// [`PeriodicBox::new`]) or periodic along a wall or a slit's walls normal to `e3`
    /// (confinement wall or slit, [`PeriodicBox::lateral`]), spheres clear of each other's
    /// and their own images and of the walls. See
    /// [`crate::periodic`] for what is available there.
    pub fn periodic(mut self, bx: PeriodicBox) -> Result<System, PeriodicError> {
        for (d, &value) in bx.lengths.as_slice().iter().enumerate() {
            if !(value > 0.0 && value.is_finite()) {
                let axis = ['x', 'y', 'z'][d];
                return Err(PeriodicError::BadLength { axis, value });
            }
        }
        if !(1e-15..=1e-2).contains(&bx.tolerance) {
            return Err(PeriodicError::BadTolerance(bx.tolerance));
        }
        let lattice = lattice(self.confinement(), &bx)?;
        let ps = self.particles();
        for (index, p) in ps.iter().enumerate() {
            for (d, &length) in bx.lengths.as_slice().iter().enumerate() {
                if length <= 2.0 * p.a {
                    let axis = ['x', 'y', 'z'][d];
                    return Err(PeriodicError::OwnImage {
                        index,
                        a: p.a,
                        axis,
                        length,
                    });
                }
            }
        }
        // the walls' planes `x3 = z0` (fluid above) and `x3 = z0 + H` (fluid below)
        let walls: Vec<(f64, f64)> = match &lattice {
            Lattice::Wall(w) => vec![(w.height, 1.0)],
            Lattice::Slit(s) => vec![(s.bottom(), 1.0), (s.bottom() + s.gap, -1.0)],
            Lattice::Triply(_) => Vec::new(),
        };
        for (index, p) in ps.iter().enumerate() {
            for &(plane, side) in &walls {
                let distance = side * (p.x[2] - plane);
                if distance < p.a {
                    return Err(PeriodicError::CutsWall {
                        index,
                        a: p.a,
                        distance,
                    });
                }
            }
        }
        let periodic = Periodic { bx, lattice };
        for i in 0..ps.len() {
            for j in i + 1..ps.len() {
                let r = bx.minimum_image(ps[i].x, ps[j].x);
                let distance = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
                let sum = ps[i].a + ps[j].a;
                if distance < sum {
                    return Err(PeriodicError::Overlap {
                        first: i,
                        second: j,
                        distance,
                        sum,
                    });
                }
            }
        }
        self.set_periodic(Some(periodic));
        Ok(self)
    }

    /// The periodic box, if any.
    pub fn periodic_box(&self) -> Option<PeriodicBox> {
        self.periodic_ref().map(|p| p.bx)
    }

    /// The blocks `M^{ab}` truncated to `moments` (row-major), `b >= a`, row by row in
    /// order of `a`: `ROWS` rows at a time evaluated in parallel (each block on its own,
    /// so the bits do not depend on the threads), then handed to `f(a, [M^{aa},
    /// M^{a,a+1}, ...])`.
    fn block_rows(&self, p: &Periodic, moments: Moments, mut f: impl FnMut(usize, &[Vec<f64>])) {
        const ROWS: usize = 16;
        let n = self.len();
        let (ps, eta) = (self.particles(), self.viscosity());
        for start in (0..n).step_by(ROWS) {
            let rows: Vec<Vec<Vec<f64>>> = (start..(start + ROWS).min(n))
                .into_par_iter()
                .map(|a| (a..n).map(|b| p.block(eta, ps, a, b, moments)).collect())
                .collect();
            for (k, row) in rows.iter().enumerate() {
                f(start + k, row);
            }
        }
    }

    /// The periodic dense mobility, column-major into `out` (every entry written): each
    /// unordered pair once, `M^{ba} = (M^{ab})^T`.
    pub(crate) fn periodic_mobility_into(&self, p: &Periodic, moments: Moments, out: &mut [f64]) {
        let n = self.len();
        let k = moments.per_particle();
        let dim = k * n;
        let parts = moments.parts();
        let g = |a: usize, i: usize| crate::system::global(parts, n, a, i);
        self.block_rows(p, moments, |a, row| {
            for (db, m) in row.iter().enumerate() {
                let b = a + db;
                for i in 0..k {
                    for j in 0..k {
                        let (gi, gj) = (g(a, i), g(b, j));
                        out[gi + dim * gj] = m[i * k + j];
                        out[gj + dim * gi] = m[i * k + j];
                    }
                }
            }
        });
    }

    /// The periodic block `M^{ab}` truncated to `moments`, row-major.
    pub(crate) fn periodic_block(
        &self,
        p: &Periodic,
        moments: Moments,
        a: usize,
        b: usize,
    ) -> Vec<f64> {
        p.block(self.viscosity(), self.particles(), a, b, moments)
    }

    /// The periodic product `M x` from the direct sums of each pair's blocks (`O(N^2)`
    /// pairs, each over its images and wave vectors: the FTS product near periodic walls,
    /// which the fast products do not have), each unordered pair once; the bits do not
    /// depend on the threads.
    fn periodic_dense_apply(&self, p: &Periodic, moments: Moments, x: &[f64]) -> Vec<f64> {
        let n = self.len();
        let k = moments.per_particle();
        let parts = moments.parts();
        let g = |a: usize, i: usize| crate::system::global(parts, n, a, i);
        let mut y = vec![0.0; k * n];
        self.block_rows(p, moments, |a, row| {
            for (db, m) in row.iter().enumerate() {
                let b = a + db;
                for i in 0..k {
                    for j in 0..k {
                        // a self block symmetric to its truncation: its lower triangle,
                        // as the dense matrix keeps it
                        let v = if b == a {
                            m[i.max(j) * k + i.min(j)]
                        } else {
                            m[i * k + j]
                        };
                        y[g(a, i)] += v * x[g(b, j)];
                        if b != a {
                            y[g(b, j)] += v * x[g(a, i)];
                        }
                    }
                }
            }
        });
        y
    }

    /// The periodic product `M x`, moment-major, to the box's tolerance: in a triply
    /// periodic box the fast product ([`product`]: linked cells and spectral Ewald; F, FT
    /// and FTS), near a wall its twin ([`wall_product`]: linked cells, spectral Ewald with
    /// the image sources, the mode `k_par = 0` interpolated in the heights), in a slit the
    /// walls' and the remainder's ([`slit_product`]); FTS near walls by the direct sums
    /// ([`System::periodic_dense_apply`]).
    pub(crate) fn periodic_apply(&self, p: &Periodic, moments: Moments, x: &[f64]) -> Vec<f64> {
        if let (Lattice::Wall(_) | Lattice::Slit(_), Moments::FTS) = (&p.lattice, moments) {
            return self.periodic_dense_apply(p, moments, x);
        }
        let tol = p.bx.tolerance;
        let ps: Vec<Particle> = self.particles().iter().map(|s| p.wrapped(s)).collect();
        match (&p.lattice, p.bx.lengths) {
            (Lattice::Wall(w), _) => {
                wall_product::apply(w, Sum::Wall, self.viscosity(), &ps, moments, x).0
            }
            (Lattice::Triply(_), BoxLengths::Triply(lengths)) => {
                product::apply(lengths, tol, self.viscosity(), &ps, moments, x)
            }
            (Lattice::Triply(_), BoxLengths::Lateral(_)) => {
                unreachable!("a triply periodic sum has three lengths")
            }
            (Lattice::Slit(s), _) => slit_product::apply(s, self.viscosity(), &ps, moments, x),
        }
    }
}
