//! Green's functions of Stokes flow: the free-space Stokeslet (Eq. 4) and the
//! reflected fields of confinements (Eqs. 5, 21, 22 and the two-wall superposition).
//!
//! Every Green's function is in units of `1/(8 pi eta)`: `G = J + J^w` with
//! `J_ij(r) = delta_ij / r + r_i r_j / r^3`, `r = x - y`. A confinement is one file
//! implementing [`Green`]: its reflected field `J^w(x, y)` written as ordinary Rust
//! generic over the scalar (this is what the generic six-variable path
//! differentiates), and optionally its image structure ([`ImageTerm`]s, each of the
//! form `c w (y3 - H)^p d^gamma J_ab(R)`, `R = x - y'`), which the structured path
//! differentiates by the chain rules of Eq. 10. Register it in [`for_each`].

pub mod free;
pub mod free_surface;
pub mod interface;
pub mod slit;
pub mod wall;

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

/// One term of a reflected field with image structure:
/// `J^w_{out} += coef * weight[w] * (y3 - H_plane)^h_power * d^d J_{j}(R_plane)`,
/// `R_plane = x - y'`, `y' = y - 2 (y3 - H_plane) e3`. Derivatives of such a term
/// with respect to the source follow Eq. 10.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageTerm {
    /// Component `(i, l)` of `J^w` that this term adds to.
    pub out: (usize, usize),
    /// Numerical coefficient.
    pub coef: f64,
    /// Index into [`Green::weights`] (a run-time factor such as `lambda / (1 + lambda)`).
    pub weight: usize,
    /// Index into [`Green::planes`] (the mirror plane).
    pub plane: usize,
    /// Power `p` of the explicit factor `(y3 - H)`.
    pub h_power: u8,
    /// Derivative multi-index `gamma` of the Stokeslet with respect to `R`.
    pub d: [u8; 3],
    /// Stokeslet component `(a, b)`.
    pub j: (usize, usize),
}

/// What the boundary imposes, for the generic boundary-condition checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    /// Unbounded fluid.
    None,
    /// No slip: `G(x, y) = 0` for `x` on the plane.
    NoSlip,
    /// Flat free surface: no penetration `G_3j = 0` and no tangential stress
    /// `d_3 G_1j = d_3 G_2j = 0` on the plane (Eq. 21).
    FreeSurface,
}

/// A Green's function of Stokes flow in a confinement: `G = J + J^w`.
pub trait Green {
    /// Identifier used in generated names (`wall` -> `wall_pair`).
    fn name(&self) -> &'static str;
    /// One line for the generated documentation.
    fn title(&self) -> &'static str;
    /// Run-time parameters, in order, as kernel argument names (e.g. `["height"]`).
    fn params(&self) -> &'static [&'static str];
    /// The dimension of parameter `name`: by default that of the names in use
    /// ([`param_dimension`]); a Green's function with a parameter of a new name states
    /// it here (generation stops with a message otherwise).
    fn dimension(&self, name: &str) -> Dimension {
        param_dimension(name).unwrap_or_else(|| {
            panic!(
                "{}: state the dimension of the parameter `{name}` (Green::dimension)",
                self.name()
            )
        })
    }
    /// The reflected field `J^w(x, y)` in units of `1/(8 pi eta)`, as ordinary Rust.
    fn reflected<S: Scalar>(&self, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S>;
    /// The image structure of [`Green::reflected`] for the Eq. 10 path, if it has one.
    fn image_terms(&self) -> Option<Vec<ImageTerm>> {
        None
    }
    /// Heights of the mirror planes, from the run-time parameters.
    fn planes<S: Scalar>(&self, _p: &[S]) -> Vec<S> {
        Vec::new()
    }
    /// The boundary planes that confine the fluid: `(height, fluid is above)`. By
    /// default the mirror planes, with the fluid above each.
    fn boundaries<S: Scalar>(&self, p: &[S]) -> Vec<(S, bool)> {
        self.planes(p).into_iter().map(|h| (h, true)).collect()
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
    /// The boundary conditions on each mirror plane, for the generic checks.
    fn boundary(&self) -> Boundary;
    /// Whether `G` is invariant under rotations about `e3` and lateral translations
    /// (all boundaries are planes normal to `e3`): pair kernels are then traced in the
    /// canonical frame of [`crate::physics::frame`], where the lateral separation lies along
    /// `x1`. A Green's function that does not say so is traced as it is.
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

/// Documentation of a run-time parameter, by name.
pub fn param_doc(name: &str) -> &'static str {
    match name {
        "height" => "height H of the boundary plane x3 = H (the fluid is x3 > H)",
        "lambda" => "viscosity ratio lambda of the liquid beyond the interface to this one",
        "gap" => "distance from the lower wall to the upper wall",
        _ => "parameter of the Green's function",
    }
}

/// How a run-time parameter changes when lengths are measured in another unit from
/// another origin of `x3` (what [`Green::dimension`] states for each parameter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// A position on the `x3` axis: `(p - origin) / unit`.
    Height,
    /// A distance: `p / unit`.
    Length,
    /// A pure number (a viscosity ratio): unchanged.
    Number,
}

/// The dimensions of the parameter names in use (the default of
/// [`Green::dimension`]).
pub fn param_dimension(name: &str) -> Option<Dimension> {
    match name {
        "height" => Some(Dimension::Height),
        "gap" => Some(Dimension::Length),
        "lambda" => Some(Dimension::Number),
        _ => None,
    }
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
}

/// The full Green's function `J(x - y) + J^w(x, y)`, units of `1/(8 pi eta)`.
pub fn full<G: Green, S: Scalar>(g: &G, x: &[S; 3], y: &[S; 3], p: &[S]) -> Mat3<S> {
    let r: [S; 3] = std::array::from_fn(|k| x[k].clone() - y[k].clone());
    let j = stokeslet(&r);
    let w = g.reflected(x, y, p);
    std::array::from_fn(|i| std::array::from_fn(|l| j[i][l].clone() + w[i][l].clone()))
}
