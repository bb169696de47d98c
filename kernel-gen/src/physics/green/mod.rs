//! Green's functions of Stokes flow: the free-space Stokeslet (Eq. 4) and the
//! reflected fields of confinements (Eqs. 5, 21, 22 and the two-wall superposition).
//!
//! Every Green's function is in units of `1/(8 pi eta)`: `G = J + J^w` with
//! `J_ij(r) = delta_ij / r + r_i r_j / r^3`, `r = x - y`. A confinement is one file
//! implementing [`Green`]: its reflected field `J^w(x, y)` written as ordinary Rust
//! generic over the scalar (this is what the generic six-variable path
//! differentiates), and optionally its image structure ([`ImageTerm`]s, each of the
//! form `c w (y3 - H)^p d^gamma J_ab(R)`, `R = x - y'`), which the structured path
//! differentiates by the chain rules of Eq. 10. Register it in [`for_each`] (a
//! confinement) or [`for_each_building_block`] (a part of a sum, such as the real part of
//! an Ewald split); the generator refuses a declaration that fails [`check`] (non-unit
//! normals and the like).

pub mod ewald;
pub mod ewald_wall;
pub mod free;
pub mod free_surface;
pub mod interface;
pub mod side_wall;
pub mod slit;
pub mod turned;
pub mod wall;

mod declaration;

pub use declaration::{check, check_registry, is_identifier, DeclarationError, UNIT_TOLERANCE};

use crate::number::scalar::Scalar;

/// A 3x3 matrix of scalars, row-major.
pub type Mat3<S> = [[S; 3]; 3];

/// Kronecker delta as a scalar.
fn delta<S: Scalar>(i: usize, j: usize) -> S {
    S::cst(if i == j { 1.0 } else { 0.0 })
}

/// The Stokeslet `J_ij(r) = delta_ij / r + r_i r_j / r^3` (Eq. 4 times 8 pi eta).
pub fn stokeslet<S: Scalar>(r: &[S; 3]) -> Mat3<S> {
    let r2 =
        r[0].clone() * r[0].clone() + r[1].clone() * r[1].clone() + r[2].clone() * r[2].clone();
    let inv_r = r2.sqrt().recip();
    let inv_r3 = inv_r.clone() * inv_r.clone() * inv_r.clone();
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            delta::<S>(i, j) * inv_r.clone() + r[i].clone() * r[j].clone() * inv_r3.clone()
        })
    })
}

/// `d_k J_ij(r) = (delta_ik r_j + delta_jk r_i - delta_ij r_k) / r^3 - 3 r_i r_j r_k / r^5`,
/// indexed `[k][i][j]`.
pub fn stokeslet_gradient<S: Scalar>(r: &[S; 3]) -> [Mat3<S>; 3] {
    let r2 =
        r[0].clone() * r[0].clone() + r[1].clone() * r[1].clone() + r[2].clone() * r[2].clone();
    let inv_r = r2.sqrt().recip();
    let inv_r3 = inv_r.clone() * inv_r.clone() * inv_r.clone();
    let inv_r5 = inv_r3.clone() * inv_r.clone() * inv_r.clone();
    std::array::from_fn(|k| {
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (delta::<S>(i, k) * r[j].clone() + delta::<S>(j, k) * r[i].clone()
                    - delta::<S>(i, j) * r[k].clone())
                    * inv_r3.clone()
                    - S::cst(3.0) * r[i].clone() * r[j].clone() * r[k].clone() * inv_r5.clone()
            })
        })
    })
}

/// `lap J_ij(r) = 2 delta_ij / r^3 - 6 r_i r_j / r^5` (the source doublet).
pub fn stokeslet_laplacian<S: Scalar>(r: &[S; 3]) -> Mat3<S> {
    let r2 =
        r[0].clone() * r[0].clone() + r[1].clone() * r[1].clone() + r[2].clone() * r[2].clone();
    let inv_r = r2.sqrt().recip();
    let inv_r3 = inv_r.clone() * inv_r.clone() * inv_r.clone();
    let inv_r5 = inv_r3.clone() * inv_r.clone() * inv_r.clone();
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            S::cst(2.0) * delta::<S>(i, j) * inv_r3.clone()
                - S::cst(6.0) * r[i].clone() * r[j].clone() * inv_r5.clone()
        })
    })
}

/// One term of a reflected field with image structure, written in the own frame of
/// its mirror plane ([`Plane::frame`]: rows `t1, t2, n`, so that the plane is
/// `x3' = offset` there):
/// `J^w'_{out} += coef * weight[w] * (y3' - offset)^h_power * d'^d J_{j}(R')`,
/// `R' = x' - y*'`, `y*' = y' - 2 (y3' - offset) e3`. In the world frame that is the
/// reflection `y* = y - 2 (n.y - offset) n` with weights in `n.y - offset` and
/// `J^w = Q^T J^w' Q`. Derivatives of such a term with respect to the source follow
/// Eq. 10 in the plane's frame; a mirror normal to `e3` has `Q = I`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageTerm {
    /// Component `(i, l)` of `J^w'` (the plane's frame) that this term adds to.
    pub out: (usize, usize),
    /// Numerical coefficient.
    pub coef: f64,
    /// Index into [`Green::weights`] (a run-time factor such as `lambda / (1 + lambda)`).
    pub weight: usize,
    /// Index into [`Green::mirrors`] (the mirror plane).
    pub plane: usize,
    /// Power `p` of the explicit factor `(y3' - offset) = n.y - offset`.
    pub h_power: u8,
    /// Derivative multi-index `gamma` of the Stokeslet with respect to `R'`.
    pub d: [u8; 3],
    /// Stokeslet component `(a, b)` (the plane's frame).
    pub j: (usize, usize),
}

/// A plane `n . x = offset`: the unit normal `n` is fixed when the kernels are
/// generated, the offset is an expression of the run-time parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane<S> {
    /// Unit normal.
    pub normal: [f64; 3],
    /// `n . x` on the plane.
    pub offset: S,
}

/// `e3`, the normal of the planes `x3 = const`.
pub const E3: [f64; 3] = [0.0, 0.0, 1.0];

impl<S: Scalar> Plane<S> {
    /// The plane `x3 = offset`.
    pub fn horizontal(offset: S) -> Plane<S> {
        Plane { normal: E3, offset }
    }

    /// The signed distance `n . x - offset` of `x` from the plane.
    pub fn distance(&self, x: &[S; 3]) -> S {
        dot(&self.normal, x) - self.offset.clone()
    }

    /// The plane's own frame: the rows `t1, t2, n` of a rotation `Q` ([`frame`]).
    pub fn frame(&self) -> Mat3<f64> {
        frame(self.normal)
    }
}

/// `n . x`, skipping the zero components of `n` and multiplying by none of `+-1`
/// (so `e3 . x` is the node `x3` itself).
pub fn dot<S: Scalar>(n: &[f64; 3], x: &[S; 3]) -> S {
    let mut acc: Option<S> = None;
    for (c, v) in n.iter().zip(x) {
        let term = if *c == 0.0 {
            continue;
        } else if *c == 1.0 {
            v.clone()
        } else if *c == -1.0 {
            -v.clone()
        } else {
            S::cst(*c) * v.clone()
        };
        acc = Some(match acc {
            None => term,
            Some(a) => a + term,
        });
    }
    acc.unwrap_or_else(|| S::cst(0.0))
}

/// `Q v`: a vector in the frame whose rows are `q`.
pub fn rotate<S: Scalar>(q: &Mat3<f64>, v: &[S; 3]) -> [S; 3] {
    std::array::from_fn(|k| dot(&q[k], v))
}

/// The right-handed orthonormal frame with third axis `n`, as the rows `t1, t2, n`
/// of a rotation: `t1` is the coordinate axis least aligned with `n` (the first of
/// equals) made orthogonal to it, `t2 = n x t1`. For `n = e3` it is the identity; for
/// `n = e1` the rows are `e2, e3, e1`.
pub fn frame(n: [f64; 3]) -> Mat3<f64> {
    let k = (0..3)
        .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .expect("three axes");
    let mut t1 = [0.0; 3];
    t1[k] = 1.0;
    let c = n[k];
    for (t, m) in t1.iter_mut().zip(&n) {
        *t -= c * m;
    }
    let norm = (t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]).sqrt();
    let t1 = t1.map(|v| clean(v / norm));
    let t2 = [
        clean(n[1] * t1[2] - n[2] * t1[1]),
        clean(n[2] * t1[0] - n[0] * t1[2]),
        clean(n[0] * t1[1] - n[1] * t1[0]),
    ];
    [t1, t2, n]
}

/// `-0` and round-off below `1e-15` as `0`, so that an axis-aligned frame has exact
/// entries.
pub(crate) fn clean(v: f64) -> f64 {
    if v.abs() < 1e-15 {
        0.0
    } else {
        v
    }
}

/// `Q^T f(Q x, Q y) Q`: a reflected field written in the frame `q` (rows `t1, t2, n`),
/// in the world frame. With [`Plane::frame`], a reflection written for the plane
/// `x3 = offset` (Blake's image, `wall::blake`) serves a plane of normal `n`.
pub fn in_frame<S: Scalar>(
    q: &Mat3<f64>,
    x: &[S; 3],
    y: &[S; 3],
    f: impl Fn(&[S; 3], &[S; 3]) -> Mat3<S>,
) -> Mat3<S> {
    let m = f(&rotate(q, x), &rotate(q, y));
    // (Q^T M Q)_ij = sum_ab Q_ai M_ab Q_bj
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let col: [S; 3] = std::array::from_fn(|a| {
                let row: [S; 3] = std::array::from_fn(|b| m[a][b].clone());
                dot(&[q[0][j], q[1][j], q[2][j]], &row)
            });
            dot(&[q[0][i], q[1][i], q[2][i]], &col)
        })
    })
}

/// What a boundary imposes on the flow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Condition {
    /// No slip: `G(x, y) = 0` for `x` on the plane. Spheres near it take the
    /// sphere-wall lubrication along its normal.
    NoSlip,
    /// A flat free surface: no penetration `n . G = 0` and no tangential stress
    /// `d_n (t . G) = 0` on the plane (Eq. 21).
    FreeSurface,
    /// A flat interface with a second liquid: no penetration `n . G = 0` on the plane
    /// (the tangential conditions couple to the other liquid, Eq. 22).
    Interface,
}

/// A plane that confines the fluid: the fluid is where `n . x > offset` (the normal
/// points into the fluid).
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary<S> {
    /// The plane, its normal into the fluid.
    pub plane: Plane<S>,
    /// What it imposes.
    pub condition: Condition,
    /// Whether the Green's function satisfies the condition exactly (the slit's
    /// superposition of two walls satisfies neither wall's no slip exactly, and says
    /// so); the checks demand an exact condition to round-off and measure the others.
    pub exact: bool,
}

impl<S> Boundary<S> {
    /// A boundary whose condition `G` satisfies exactly (the single plane of a wall,
    /// a free surface, an interface).
    pub fn exact(plane: Plane<S>, condition: Condition) -> Boundary<S> {
        Boundary {
            plane,
            condition,
            exact: true,
        }
    }
}

/// How a run-time parameter changes when lengths are measured in another unit from
/// another origin of `x3` (`Confinement::in_units`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Dimension {
    /// A position along the unit direction `d` (a plane's offset `d . x`):
    /// `(p - d . (origin e3)) / unit`.
    Position([f64; 3]),
    /// A distance: `p / unit`.
    Length,
    /// A pure number (a viscosity ratio): unchanged.
    Number,
}

/// A named run-time parameter of a Green's function, declared once: kernel argument,
/// field of the `Confinement` variant, command-line `--param NAME=VALUE`, Python
/// `params={NAME: VALUE}`, and the checks' sample value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    /// Name (a Rust identifier: kernel argument and enum field).
    pub name: &'static str,
    /// What it is, one line (documentation everywhere it appears).
    pub doc: &'static str,
    /// How it scales with the unit of length.
    pub dimension: Dimension,
    /// The value a user gets without giving it (command line, Python); `None` for a
    /// parameter that must be given.
    pub default: Option<f64>,
    /// A typical value away from the default, for the checks (a non-zero position,
    /// a ratio other than 1), so that a parameter mixed up with another shows.
    pub example: f64,
}

impl Param {
    /// The position of the plane `x3 = height`.
    pub const HEIGHT: Param = Param {
        name: "height",
        doc: "height H of the boundary plane x3 = H (the fluid is x3 > H)",
        dimension: Dimension::Position(E3),
        default: Some(0.0),
        example: 0.3,
    };
}

/// A Green's function of Stokes flow in a confinement: `G = J + J^w`.
pub trait Green {
    /// Identifier used in generated names (`wall` -> `wall_pair`).
    fn name(&self) -> &'static str;
    /// One line for the generated documentation.
    fn title(&self) -> &'static str;
    /// Run-time parameters, in order (kernel arguments after the viscosity).
    fn params(&self) -> &'static [Param];
    /// The reflected field `J^w(x, y)` in units of `1/(8 pi eta)`, as ordinary Rust.
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S>;
    /// The full Green's function `G = J + J^w` (pair interactions). Its own closed form
    /// where the sum would cancel: a screened Green's function, whose `J^w` tends to `-J`
    /// at large distance ([`ewald`]).
    fn full<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
        let r: [S; 3] = std::array::from_fn(|k| x[k].clone() - y[k].clone());
        let j = stokeslet(&r);
        let w = self.reflected(x, y, p);
        std::array::from_fn(|i| std::array::from_fn(|l| j[i][l].clone() + w[i][l].clone()))
    }
    /// Whether `G` depends on `x - y` only (no boundary): the generic path then expands
    /// it in the three components of `r = x - y`, with `d_y = -d_x`
    /// ([`crate::physics::derivatives::GenericJets`]).
    fn translation_invariant(&self) -> bool {
        false
    }
    /// The image structure of [`Green::reflected`] for the Eq. 10 path, if it has one.
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        None
    }
    /// The mirror planes of the image terms, from the run-time parameters.
    fn mirrors<S: Scalar>(&self, _p: &[S]) -> Vec<Plane<S>> {
        Vec::new()
    }
    /// The planes that confine the fluid, each with its condition: overlap checks,
    /// lubrication, Brownian dynamics and the boundary-condition checks use these.
    fn boundaries<S: Scalar>(&self, _p: &[S]) -> Vec<Boundary<S>> {
        Vec::new()
    }
    /// Run-time weights of image terms, from the run-time parameters.
    fn weights<S: Scalar>(&self, _p: &[S]) -> Vec<S> {
        vec![S::cst(1.0)]
    }
    /// The image `(plane, weight)` that cancels the Stokeslet where the source touches
    /// its plane (`J^w = -J` there, weight exactly 1: a no-slip plane), if any. The
    /// structured path then writes `J(r) = J(R) - [J(R) - J(r)]` and evaluates the
    /// bracket without cancellation ([`crate::physics::derivatives::Structured`]).
    fn cancelling_image(&self) -> Option<(usize, usize)> {
        None
    }
    /// The radial potential of a kernel other than the Stokeslet: `lap^m phi` as a
    /// function of `s = r.r`, where the free term and every image term
    /// ([`Green::image_terms`]) are made of `J = (delta lap - d d) phi` in place of the
    /// Stokeslet's `phi = r` (`None`, the default: the Stokeslet). The structured path
    /// runs it on jets in `s` for the radial coefficients of its atoms
    /// ([`crate::physics::derivatives::Potential::Radial`]). Each Laplacian is a radial
    /// function again (`lap f(s) = 4 s f'' + 6 f'`), declared in closed form: where it is
    /// small (screened, entire) the recurrence would be a cancellation of large terms.
    /// `phi` has the dimension of a length, `lap^m phi` that of `length^(1 - 2m)`. Only
    /// pair kernels take it; self kernels, whose free part is the reflected field at
    /// `r = 0`, take the generic path.
    fn radial<S: Scalar>(&self, _m: u8, _s: &S, _p: &[S]) -> Option<S> {
        None
    }
    /// Whether `G` is invariant under rotations about the common normal `n` of its
    /// mirror planes (`e3` without mirrors) and translations along them (all boundaries
    /// are planes normal to `n`): pair kernels are then traced in the canonical frame of
    /// [`crate::physics::frame`], where the lateral separation lies along the plane's
    /// first axis (for `n` other than `e3`, in the planes' own frame: [`turned`]). A
    /// Green's function that does not say so is traced as it is.
    fn axisymmetric(&self) -> bool {
        false
    }
    /// Highest derivative order of `J` that one image term carries (the jets of the
    /// structured path need this many orders on top of the operators' own).
    fn image_extra_order(&self) -> usize {
        self.image_terms()
            .map(|t| {
                t.iter()
                    .map(|t| t.d.iter().map(|&e| e as usize).sum::<usize>())
                    .max()
                    .unwrap_or(0)
            })
            .unwrap_or(0)
    }
}

/// Whether `g` declares a radial potential other than the Stokeslet's ([`Green::radial`]).
pub fn is_radial<G: Green>(g: &G) -> bool {
    g.radial(0, &1.0f64, &examples(g)).is_some()
}

/// The example values of a Green's function's parameters ([`Param::example`]).
pub fn examples<G: Green>(g: &G) -> Vec<f64> {
    g.params().iter().map(|p| p.example).collect()
}

/// Something that is handed every registered Green's function in turn (the trait has
/// generic methods, so the registry visits instead of returning trait objects).
pub trait Visitor {
    /// Called once per registered Green's function.
    fn visit<G: Green>(&mut self, g: &G);
}

/// The registry: every confinement for which kernels are generated and checked.
pub fn for_each<V: Visitor>(v: &mut V) {
    v.visit(&free::Free);
    v.visit(&wall::Wall);
    v.visit(&free_surface::FreeSurface);
    v.visit(&interface::Interface);
    v.visit(&slit::Slit);
    v.visit(&side_wall::SideWall);
}

/// The building blocks: Green's functions that are parts of a sum the solver forms (the
/// real part of an Ewald split, summed over periodic images), not confinements of their
/// own. Only the kernels of their scenes (`scenes/`) are generated: no family file, no
/// `Confinement` variant, so the solver, the command line and Python do not offer them.
/// Their declarations are checked with the registry's ([`check_registry`]: one name
/// space).
pub fn for_each_building_block<V: Visitor>(v: &mut V) {
    v.visit(&ewald::EwaldReal);
    v.visit(&ewald_wall::EwaldWall);
}

/// The full Green's function `J(x - y) + J^w(x, y)`, units of `1/(8 pi eta)`
/// ([`Green::full`]).
pub fn full<G: Green, S: Scalar>(g: &G, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
    g.full(x, y, p)
}
