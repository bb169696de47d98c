//! The derivative paths: where the derivatives `d_x^alpha d_y^beta G_ij` that the
//! operators ask for come from. All are [`Derivatives`] sources over any scalar.
//!
//! - [`Structured`]: the Stokeslet depends on `r = x - y` only, so `d_x = d_r`,
//!   `d_y = -d_r`; and the image follows Eq. 10. Every image term is
//!   `f(y3 - H) g(R)` with `R = x - y'`, `y' = y - 2 (y3 - H) e3`; so `d_x = d_R`,
//!   `d_{y_k} g = -P_kk d_{R_k} g`, and the explicit factor `(y3 - H)^p` is
//!   differentiated by Leibniz's rule in `y3`:
//!   `d_{y3}^n [h^p g] = sum_s C(n, s) p!/(p-s)! h^(p-s) d_{R3}^(n-s) g`.
//!   Every derivative of `J` is one of the scalar potentials `r` and `1/r`
//!   (`J_ab = (delta_ab lap - d_a d_b) r`, `lap r = 2/r`, `lap 1/r = 0`), so one jet of
//!   each potential per centre, in three variables about the unit vector `R/|R|`,
//!   serves every term; and a block entry is collected as a linear combination of
//!   those derivatives before it is built. (Writing `J` through `1/r` alone,
//!   `J_ab = delta_ab/r - R_a d_b(1/r)`, needs one order less but the factors `R_a`
//!   cost more than they save: measured 9698 vs 8941 flops for the wall FTS pair.)
//!   Where the image cancels the Stokeslet as the source touches its plane
//!   ([`Green::cancelling_image`], the wall), each free-space atom is rewritten
//!   `d^nu phi(r) = d^nu phi(R) - d^nu [phi(R) - phi(r)]`: the first part joins the
//!   image's atoms at `R` with exactly summed coefficients (the orders that cancel in
//!   exact arithmetic cancel there, as small-integer sums), and the difference is one
//!   more jet per potential, evaluated without cancellation from
//!   `|R|^2 - |r|^2 = 4 h f` (`h = y3 - H`, `f = x3 - H`):
//!   `|R| - |r| = 4 h f / (|R| + |r|)`, `1/|R| - 1/|r| = -(|R| - |r|)/(|R| |r|)`, as jets
//!   in `x`. The direct sum of `J(r)` and `-J(R)` instead loses `rho^2/(h f)` at lateral
//!   distance `rho`; what the rewrite leaves is the cancellation between the image's
//!   terms of order `h`, about `rho / f` (stiff cases: `tests/tests/integration/generated/stiff_cases.rs`).
//!   [`Structured::direct_sum`] keeps the plain sum (the stiff cases' reference).
//!   With `explicit_height = false` the `s > 0` terms are dropped: the image is
//!   differentiated as a function of `x - y'` only, the error the paper attributes to
//!   Bossis, Meunier & Sherwood (Sec. III A). It exists to demonstrate that error.
//! - [`GenericJets`]: the whole `G(x, y)` expanded in all six coordinates; needs no
//!   structure, so it serves any Green's function and cross-checks the other two.
//!
//! The structured path lives in `atoms` (the potentials' derivatives a Stokeslet
//! derivative reduces to), `structured` (the centres, the jets, Eq. 10 and the exact
//! difference) and `collection` (how atoms become arithmetic); the generic path in
//! `generic`.
//!
//! [`Derivatives`]: crate::physics::operators::Derivatives
//! [`Green::cancelling_image`]: crate::physics::green::Green::cancelling_image

mod atoms;
mod collection;
mod generic;
mod structured;

pub use atoms::{Atom, Potential};
pub use generic::{GenericJets, Part};
pub use structured::Structured;

/// How [`Structured`] turns atoms into arithmetic: the generator traces each kernel in
/// every way and keeps the cheapest ([`crate::kernel::trace`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Collection {
    /// The atoms' values combined one by one (the jets' coefficients as the jet rules
    /// compute them); kernels with many blocks share atoms between entries this way.
    Atoms,
    /// The atoms of one centre, potential, order and radius-and-height factor
    /// collected as one polynomial in the unit vector, evaluated by Horner's rule.
    Centres,
    /// Everything of one block entry at one centre collected as one polynomial in the
    /// unit vector `e` and the dimensionless `h/|R|`, `a_a^2/|R|^2`, `a_b^2/|R|^2`,
    /// times one power of `1/|R|` (each term of an entry has the entry's dimension), by
    /// Horner's rule; the differences `phi(R) - phi(r)` of a cancelling image as in
    /// `Centres`.
    Entries,
    /// As `Entries`, each polynomial taken in the cheapest of its forms on the unit
    /// sphere `|e| = 1` ([`Poly::on_unit_sphere`]): fewer monomials per entry, though
    /// entries in different forms may share fewer subexpressions.
    ///
    /// [`Poly::on_unit_sphere`]: crate::number::poly::Poly::on_unit_sphere
    EntriesOnSphere,
}

/// Which free-space terms [`Structured`] rewrites, near a cancelling image, as the image
/// plus an exactly evaluated difference (the generator traces both and keeps the
/// cheaper kernel, [`crate::kernel::trace`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Differences {
    /// Every term.
    All,
    /// The terms without Faxen factors only. A Faxen term `a^2 lap d^nu J` is smaller
    /// than the leading term of its block by `a^2/rho^2` at lateral distance `rho`,
    /// and the plain sum of it and its image loses `eps rho^2/(h_a h_b)` of itself, so
    /// `eps a^2/(h_a h_b)` of the block: at most `eps a/h` of the other sphere, since
    /// every centre is at least a radius above the plane (measured in the stiff cases,
    /// `tests/tests/integration/generated/stiff_cases.rs`).
    Leading,
}

/// How [`Structured`] builds a kernel's arithmetic.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Form {
    /// How atoms become arithmetic.
    pub collect: Collection,
    /// Which terms take the exact difference near a cancelling image.
    pub differences: Differences,
}

impl Form {
    /// `collect`, every term through the exact difference.
    pub fn collecting(collect: Collection) -> Form {
        Form {
            collect,
            differences: Differences::All,
        }
    }
}
