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
//!   terms of order `h`, about `rho / f` (stiff cases: `tests/tests/stiff_cases.rs`).
//!   [`Structured::direct_sum`] keeps the plain sum (the stiff cases' reference).
//!   With `explicit_height = false` the `s > 0` terms are dropped: the image is
//!   differentiated as a function of `x - y'` only, the error the paper attributes to
//!   Bossis, Meunier & Sherwood (Sec. III A). It exists to demonstrate that error.
//! - [`GenericJets`]: the whole `G(x, y)` expanded in all six coordinates; needs no
//!   structure, so it serves any Green's function and cross-checks the other two.

use crate::number::dd::Dd;
use crate::number::jet::{Jet, Layout};
use crate::number::poly::{Poly, VARS};
use crate::number::scalar::Scalar;
use crate::physics::green::{self, Green, ImageTerm, Mat3};
use crate::physics::operators::{Deriv, Derivatives, Term};
use std::collections::{BTreeMap, HashMap};

fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

fn binomial(n: usize, k: usize) -> f64 {
    factorial(n) / (factorial(k) * factorial(n - k))
}

/// The scalar potential a Stokeslet derivative reduces to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Potential {
    /// `r` (biharmonic: `J_ab = (delta_ab lap - d_a d_b) r`).
    R,
    /// `1/r` (harmonic; `lap r = 2/r`).
    InvR,
}

/// `d^nu phi` of a potential at one expansion centre, with `nu_3 <= 1` after reduction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Atom {
    /// 0: the free-space separation `r = x - y`; `1 + t`: `R` of mirror plane `t`;
    /// `1 + n + t` (`n` planes): the difference `phi(R) - phi(r)` for plane `t`.
    pub centre: usize,
    /// Which potential.
    pub pot: Potential,
    /// Derivative multi-index.
    pub nu: [u8; 3],
}

/// `d^nu phi` as a combination of derivatives with `nu_3 <= 1`, by
/// `d_3^2 = lap - d_1^2 - d_2^2`, `lap r = 2/r`, `lap (1/r) = 0` (away from `r = 0`).
fn reduce(pot: Potential, nu: [u8; 3], coef: f64, out: &mut BTreeMap<(Potential, [u8; 3]), f64>) {
    if nu[2] < 2 {
        *out.entry((pot, nu)).or_insert(0.0) += coef;
        return;
    }
    let base = [nu[0], nu[1], nu[2] - 2];
    if pot == Potential::R {
        reduce(Potential::InvR, base, 2.0 * coef, out);
    }
    reduce(pot, [base[0] + 2, base[1], base[2]], -coef, out);
    reduce(pot, [base[0], base[1] + 2, base[2]], -coef, out);
}

/// `d^mu J_ab = delta_ab d^mu lap r - d^(mu + e_a + e_b) r`, reduced.
fn stokeslet_atoms(
    a: usize,
    b: usize,
    mu: [u8; 3],
    coef: f64,
) -> BTreeMap<(Potential, [u8; 3]), f64> {
    let mut out = BTreeMap::new();
    if a == b {
        reduce(Potential::InvR, mu, 2.0 * coef, &mut out);
    }
    let mut nu = mu;
    nu[a] += 1;
    nu[b] += 1;
    reduce(Potential::R, nu, -coef, &mut out);
    out.retain(|_, c| *c != 0.0);
    out
}

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
    /// `tests/tests/stiff_cases.rs`).
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

/// The non-atom factor of a group of atoms: `weight * h_plane^q`, or 1 for free space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Factor {
    Free,
    Image { plane: usize, weight: usize, q: u8 },
}

/// The structured path: free-space Stokeslet in `r`, image terms by Eq. 10 in `R`,
/// every derivative of `J` reduced to derivatives of the potentials `r` and `1/r`.
///
/// Each block entry is collected as a linear combination of [`Atom`]s with `f64`
/// coefficients, grouped by radius factors and `weight * h^q`, before a single
/// arithmetic node is built ([`Derivatives::combine`]); the jets of the potentials
/// (power rule on `s = R.R`) supply the atoms.
pub struct Structured<S> {
    /// Expansion centres: `[r, R_0, R_1, ...]` (`r` only if the free part is included).
    centres: Vec<[S; 3]>,
    include_free: bool,
    terms: Vec<ImageTerm>,
    heights: Vec<S>,
    /// `x3 - H` per plane.
    field_heights: Vec<S>,
    /// The image `(plane, weight)` that absorbs the free-space atoms, with the
    /// difference evaluated apart (see the module documentation).
    cancel: Option<(usize, usize)>,
    weights: Vec<S>,
    explicit_height: bool,
    degree: usize,
    jets: HashMap<(usize, Potential), Jet<S>>,
    /// The jets of the potentials about a symbolic unit vector ([`Poly`]), per potential.
    poly_jets: HashMap<Potential, Jet<Poly>>,
    /// How atoms become arithmetic.
    collect: Collection,
    /// Which terms take the exact difference near a cancelling image.
    differences: Differences,
    units: HashMap<usize, (S, S, [S; 3])>,
    /// A factor of every derivative ([`Structured::scaled`]).
    multiplier: Option<S>,
}

impl<S: Scalar> Structured<S> {
    /// Derivatives up to total order `order` in `(x, y)` of `J + J^w` (pair,
    /// `include_free`) or of `J^w` alone (self, Eq. 17), at field point `x` and source `y`.
    pub fn new<G: Green>(
        g: &G,
        x: &[S; 3],
        y: &[S; 3],
        p: &[S],
        order: usize,
        include_free: bool,
        explicit_height: bool,
    ) -> Self {
        let terms = g
            .image_terms()
            .expect("the structured path needs a Green's function with image terms");
        let degree = order + g.image_extra_order() + 2;
        let mut s = Self::with_terms(
            terms,
            x,
            y,
            g.planes(p),
            g.weights(p),
            degree,
            include_free,
            explicit_height,
        );
        if include_free {
            s.cancel = g.cancelling_image();
        }
        s
    }

    /// The plain direct sum of the Stokeslet and its image, without the rewrite into
    /// an exactly evaluated difference: the reference of the stiff cases.
    pub fn direct_sum(mut self) -> Self {
        self.cancel = None;
        self
    }

    /// Every derivative times `m` (the kernels' `1/(8 pi eta)`): `m` multiplies the
    /// powers of `1/|R|` ([`Structured::inv_norm_pow`]), one of which ends every term,
    /// so that it enters once per centre and power (shared nodes) rather than once per
    /// block entry.
    pub fn scaled(mut self, m: S) -> Self {
        self.multiplier = Some(m);
        self
    }

    /// Build the arithmetic in form `f` (collection and differences; default
    /// [`Collection::Centres`], [`Differences::All`]).
    pub fn in_form(mut self, f: Form) -> Self {
        self.collect = f.collect;
        self.differences = f.differences;
        self
    }

    /// As [`Structured::new`], from the image terms, the planes' heights and the
    /// weights themselves (a subset of a Green's function's terms), with jets of
    /// degree `degree`.
    #[allow(clippy::too_many_arguments)]
    pub fn with_terms(
        terms: Vec<ImageTerm>,
        x: &[S; 3],
        y: &[S; 3],
        planes: Vec<S>,
        weights: Vec<S>,
        degree: usize,
        include_free: bool,
        explicit_height: bool,
    ) -> Self {
        let r: [S; 3] = std::array::from_fn(|k| x[k].clone() - y[k].clone());
        let mut centres = vec![r];
        let mut heights = Vec::new();
        let mut field_heights = Vec::new();
        for hp in planes {
            field_heights.push(x[2].clone() - hp.clone());
            let h = y[2].clone() - hp;
            centres.push([
                x[0].clone() - y[0].clone(),
                x[1].clone() - y[1].clone(),
                x[2].clone() - y[2].clone() + S::cst(2.0) * h.clone(),
            ]);
            heights.push(h);
        }
        Structured {
            centres,
            include_free,
            terms,
            heights,
            field_heights,
            cancel: None,
            weights,
            explicit_height,
            degree,
            jets: HashMap::new(),
            poly_jets: HashMap::new(),
            collect: Collection::Centres,
            differences: Differences::All,
            units: HashMap::new(),
            multiplier: None,
        }
    }

    /// `|c|`, `1/|c|` and the unit vector `e = c/|c|` of a centre.
    fn unit(&mut self, centre: usize) -> (S, S, [S; 3]) {
        if let Some(u) = self.units.get(&centre) {
            return u.clone();
        }
        let c = self.centres[centre].clone();
        let s =
            c[0].clone() * c[0].clone() + c[1].clone() * c[1].clone() + c[2].clone() * c[2].clone();
        let norm = s.sqrt();
        let inv = norm.recip();
        let e: [S; 3] = std::array::from_fn(|k| c[k].clone() * inv.clone());
        let u = (norm, inv, e);
        self.units.insert(centre, u.clone());
        u
    }

    /// Jet of a potential about the unit vector `e` of a centre, built on first use.
    /// About `e` the expansion of `s = |e + d|^2 = 1 + 2 e.d + d.d` has the constant
    /// term exactly 1, so the power rule never divides, and every coefficient is a
    /// polynomial in `e`. Homogeneity scales it back: `d^nu phi(R) = |R|^(p - n)
    /// d^nu phi(e)` for `phi = |R|^p`, `n = |nu|`.
    fn jet(&mut self, centre: usize, pot: Potential) -> &Jet<S> {
        if let Some(t) = self.difference_plane(centre) {
            if !self.jets.contains_key(&(centre, pot)) {
                let d = self.difference_jet(t, pot);
                self.jets.insert((centre, pot), d);
            }
            return &self.jets[&(centre, pot)];
        }
        let degree = self.degree;
        let (_, _, e) = self.unit(centre);
        self.jets.entry((centre, pot)).or_insert_with(|| {
            let l = Layout::get(3, degree);
            let d: [Jet<S>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, S::cst(0.0)));
            let mut s = Jet::cst(1.0);
            for k in 0..3 {
                s = s
                    + Jet::constant(S::cst(2.0) * e[k].clone()) * d[k].clone()
                    + d[k].clone() * d[k].clone();
            }
            match pot {
                Potential::R => s.powf(0.5, S::cst(1.0)),
                Potential::InvR => s.powf(-0.5, S::cst(1.0)),
            }
        })
    }

    /// The jet of a potential about the symbolic unit vector `e`: every coefficient a
    /// polynomial in `e` ([`crate::number::poly`]), the same for every centre.
    fn poly_jet(&mut self, pot: Potential) -> &Jet<Poly> {
        let degree = self.degree;
        self.poly_jets.entry(pot).or_insert_with(|| {
            let l = Layout::get(3, degree);
            let d: [Jet<Poly>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, Poly::cst(0.0)));
            let mut s = Jet::cst(1.0);
            for k in 0..3 {
                s = s
                    + Jet::constant(Poly::cst(2.0) * Poly::var(k)) * d[k].clone()
                    + d[k].clone() * d[k].clone();
            }
            match pot {
                Potential::R => s.powf(0.5, Poly::cst(1.0)),
                Potential::InvR => s.powf(-0.5, Poly::cst(1.0)),
            }
        })
    }

    /// The plane `t` of a difference centre `1 + n + t`.
    fn difference_plane(&self, centre: usize) -> Option<usize> {
        centre.checked_sub(self.centres.len())
    }

    /// The centre whose `|R|` scales an atom: a difference is scaled as its image.
    fn scaling_centre(&self, centre: usize) -> usize {
        match self.difference_plane(centre) {
            Some(t) => 1 + t,
            None => centre,
        }
    }

    /// Jet of `[phi(R + d) - phi(r + d)] / |R|^p` in `d / |R|` about 0, for plane `t`,
    /// without cancellation. With `L = |R|`, `s_R = |e_R + d|^2` (the image's own jet)
    /// and `s_r = |r/L + d|^2`, `s_R - s_r = 4 h f / L^2 + 4 (h / L) d_3` exactly, so
    /// `sqrt(s_R) - sqrt(s_r) = (s_R - s_r) / (sqrt(s_R) + sqrt(s_r))` and
    /// `1/sqrt(s_R) - 1/sqrt(s_r) = -(sqrt(s_R) - sqrt(s_r)) / (sqrt(s_R) sqrt(s_r))`.
    fn difference_jet(&mut self, t: usize, pot: Potential) -> Jet<S> {
        let big = self.jet(1 + t, Potential::R).clone();
        let (_, inv, _) = self.unit(1 + t);
        let (small_norm, _, _) = self.unit(0);
        let l = Layout::get(3, self.degree);
        let d: [Jet<S>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, S::cst(0.0)));
        let q = small_norm * inv.clone();
        let mut s = Jet::constant(q.clone() * q.clone());
        for (k, dk) in d.iter().enumerate() {
            let e = self.centres[0][k].clone() * inv.clone();
            s = s + Jet::constant(S::cst(2.0) * e) * dk.clone() + dk.clone() * dk.clone();
        }
        let small = s.powf(0.5, q);
        let h4 = S::cst(4.0) * self.heights[t].clone() * inv.clone();
        let gap = Jet::constant(h4.clone() * self.field_heights[t].clone() * inv)
            + Jet::constant(h4) * d[2].clone();
        let dr = gap / (big.clone() + small.clone());
        match pot {
            Potential::R => dr,
            Potential::InvR => -(dr / (big * small)),
        }
    }

    /// Where the image cancels the Stokeslet, move every free-space atom (or those
    /// without Faxen factors, [`Differences::Leading`]) to the image centre and its
    /// difference: `c d^nu phi(r) = c d^nu phi(R) - c d^nu [phi(R) - phi(r)]`, into the
    /// image's group of factor `weight * h^0` (weight exactly 1).
    fn absorb_free(&self, groups: &mut BTreeMap<(u8, u8, Factor), BTreeMap<Atom, f64>>) {
        let Some((plane, weight)) = self.cancel else {
            return;
        };
        let every = self.differences == Differences::All;
        let free: Vec<_> = groups
            .keys()
            .filter(|k| k.2 == Factor::Free && (every || (k.0 == 0 && k.1 == 0)))
            .copied()
            .collect();
        for key in free {
            let atoms = groups.remove(&key).expect("listed key");
            let to = (
                key.0,
                key.1,
                Factor::Image {
                    plane,
                    weight,
                    q: 0,
                },
            );
            let group = groups.entry(to).or_default();
            for (a, c) in atoms {
                debug_assert_eq!(a.centre, 0, "free-space atoms are at r");
                let at = |centre| Atom { centre, ..a };
                *group.entry(at(1 + plane)).or_insert(0.0) += c;
                *group.entry(at(self.centres.len() + plane)).or_insert(0.0) -= c;
            }
        }
    }

    /// `d^nu phi(e)`: the atom without its factor `|R|^(p - n)`.
    fn atom_at_unit(&mut self, a: &Atom) -> S {
        self.jet(a.centre, a.pot).derivative(&a.nu)
    }

    /// `|R|^(-k)` by repeated products of `1/|R|` (or of `|R|` for `k < 0`), shared;
    /// times the multiplier ([`Structured::scaled`]), if any.
    fn inv_norm_pow(&mut self, centre: usize, k: i32) -> S {
        let (norm, inv, _) = self.unit(centre);
        let base = if k >= 0 { inv } else { norm };
        let mut v = self.multiplier.clone().unwrap_or_else(|| S::cst(1.0));
        for _ in 0..k.unsigned_abs() {
            v = v * base.clone();
        }
        v
    }

    fn factor_value(&self, f: &Factor) -> S {
        match *f {
            Factor::Free => S::cst(1.0),
            Factor::Image { plane, weight, q } => {
                let mut v = self.weights[weight].clone();
                for _ in 0..q {
                    v = v * self.heights[plane].clone();
                }
                v
            }
        }
    }

    /// `d` as `sum factor * coef * atom`.
    fn atoms(&self, d: &Deriv, out: &mut BTreeMap<(Factor, Atom), f64>, scale: f64) {
        let mut push = |f: Factor, centre: usize, mu: [u8; 3], a: usize, b: usize, c: f64| {
            for ((pot, nu), k) in stokeslet_atoms(a, b, mu, c) {
                *out.entry((f, Atom { centre, pot, nu })).or_insert(0.0) += k;
            }
        };
        if self.include_free {
            // d_x = d_r, d_y = -d_r
            let mu = [d.dx[0] + d.dy[0], d.dx[1] + d.dy[1], d.dx[2] + d.dy[2]];
            let sign = if d.dy.iter().map(|&e| e as u32).sum::<u32>() % 2 == 1 {
                -1.0
            } else {
                1.0
            };
            push(Factor::Free, 0, mu, d.i, d.j, scale * sign);
        }
        // Eq. 10: d_x = d_R; d_{y_k} = -P_kk d_{R_k} on g(R); Leibniz in y3 on h^p.
        let sign_y = if (d.dy[0] + d.dy[1]) % 2 == 1 {
            -1.0
        } else {
            1.0
        };
        let n3 = d.dy[2] as usize;
        for t in self.terms.iter().filter(|t| t.out == (d.i, d.j)) {
            let p = t.h_power as usize;
            let smax = if self.explicit_height { n3.min(p) } else { 0 };
            for s in 0..=smax {
                let mut mu = [0u8; 3];
                for k in 0..3 {
                    mu[k] = t.d[k] + d.dx[k] + d.dy[k];
                }
                mu[2] -= s as u8;
                let c = scale * sign_y * t.coef * binomial(n3, s) * factorial(p) / factorial(p - s);
                let f = Factor::Image {
                    plane: t.plane,
                    weight: t.weight,
                    q: (p - s) as u8,
                };
                push(f, 1 + t.plane, mu, t.j.0, t.j.1, c);
            }
        }
    }

    /// `sum_atoms coef * value`: atoms of one centre, potential and order share the
    /// factor `|R|^(p - n)`, which multiplies their sum once. Deterministic order.
    fn linear(&mut self, atoms: &BTreeMap<Atom, f64>) -> Option<S> {
        let mut groups: BTreeMap<(usize, Potential, usize), Vec<(Atom, f64)>> = BTreeMap::new();
        for (a, &c) in atoms {
            if c != 0.0 {
                let n = a.nu.iter().map(|&k| k as usize).sum();
                groups
                    .entry((a.centre, a.pot, n))
                    .or_default()
                    .push((*a, c));
            }
        }
        let mut acc: Option<S> = None;
        for ((centre, pot, n), list) in groups {
            let sum =
                if self.collect != Collection::Atoms && self.difference_plane(centre).is_none() {
                    // one polynomial in the unit vector, evaluated by Horner's rule
                    let mut p = Poly::default();
                    for (a, c) in &list {
                        let d = self.poly_jet(pot).derivative(&a.nu);
                        p.add_scaled(&d, Dd::new(*c));
                    }
                    let (_, _, e) = self.unit(centre);
                    let v = p.eval(&e);
                    (!v.is_known_zero()).then_some(v)
                } else {
                    let mut sum: Option<S> = None;
                    for (a, c) in list {
                        let v = self.atom_at_unit(&a);
                        if v.is_known_zero() {
                            continue;
                        }
                        let v = if c == 1.0 { v } else { S::cst(c) * v };
                        sum = Some(match sum {
                            None => v,
                            Some(s) => s + v,
                        });
                    }
                    sum
                };
            let Some(sum) = sum else { continue };
            let p = match pot {
                Potential::R => 1,
                Potential::InvR => -1,
            };
            let scaling = self.scaling_centre(centre);
            let v = self.inv_norm_pow(scaling, n as i32 - p) * sum;
            acc = Some(match acc {
                None => v,
                Some(s) => s + v,
            });
        }
        acc
    }

    /// Evaluate collected atoms grouped by `(pa, pb, factor)`. Groups of one factor
    /// with the same atoms and coefficients are evaluated once, times the sum of their
    /// radius monomials: the free-space Stokeslet's Faxen Laplacians at the field point
    /// and at the source are the same derivatives (`d_y = -d_r`, two of them), so its
    /// terms come as `alpha L + beta L`, taken as `(alpha + beta) L` (one product
    /// fewer per entry, and `alpha + beta` is shared by all of them).
    fn evaluate(
        &mut self,
        groups: BTreeMap<(u8, u8, Factor), BTreeMap<Atom, f64>>,
        aa2: &S,
        ab2: &S,
    ) -> S {
        // the radius monomials of each distinct (factor, atoms), in the order of the
        // first group that has them
        type Atoms = Vec<(Atom, u64)>;
        let mut order: Vec<(Factor, Atoms)> = Vec::new();
        let mut monomials: HashMap<(Factor, Atoms), Vec<(u8, u8)>> = HashMap::new();
        for ((pa, pb, f), atoms) in groups {
            let key: Atoms = atoms
                .into_iter()
                .filter(|&(_, c)| c != 0.0)
                .map(|(a, c)| (a, c.to_bits()))
                .collect();
            let list = monomials.entry((f, key.clone())).or_default();
            if list.is_empty() {
                order.push((f, key));
            }
            list.push((pa, pb));
        }
        let mut out: Option<S> = None;
        for (f, key) in order {
            let atoms: BTreeMap<Atom, f64> =
                key.iter().map(|&(a, c)| (a, f64::from_bits(c))).collect();
            let Some(mut v) = self.linear(&atoms) else {
                continue;
            };
            if f != Factor::Free {
                v = self.factor_value(&f) * v;
            }
            // the sum of the groups' `aa2^pa ab2^pb` (a product by 1 folds away)
            let weight = monomials[&(f, key)]
                .iter()
                .map(|&(pa, pb)| {
                    let mut m = S::cst(1.0);
                    for _ in 0..pa {
                        m = aa2.clone() * m;
                    }
                    for _ in 0..pb {
                        m = ab2.clone() * m;
                    }
                    m
                })
                .reduce(|w, m| w + m)
                .expect("every key has a group");
            v = weight * v;
            out = Some(match out {
                None => v,
                Some(o) => o + v,
            });
        }
        out.unwrap_or_else(|| S::cst(0.0))
    }
}

impl<S: Scalar> Structured<S> {
    /// [`Collection::Entries`]: every atom of one entry at one centre (and weight) in
    /// one polynomial `sum c e^m t^q alpha^pa beta^pb` with `t = h |R|^-1`, `alpha =
    /// a_a^2 |R|^-2`, `beta = a_b^2 |R|^-2`, times `|R|^-k` (one `k` per entry by
    /// dimension; kept apart should another occur); the atoms of difference centres go
    /// through [`Structured::evaluate`], and so, near a cancelling image, do the
    /// free-space terms with Faxen factors that [`Differences::Leading`] leaves at `r`,
    /// whose `alpha L + beta L` is then taken once (wall FTS pair lanes 1534 -> 1459).
    fn evaluate_entries(
        &mut self,
        groups: BTreeMap<(u8, u8, Factor), BTreeMap<Atom, f64>>,
        aa2: &S,
        ab2: &S,
    ) -> S {
        let mut polys: BTreeMap<(usize, Option<usize>, i32), Poly> = BTreeMap::new();
        let mut rest: BTreeMap<(u8, u8, Factor), BTreeMap<Atom, f64>> = BTreeMap::new();
        for ((pa, pb, f), atoms) in groups {
            for (a, c) in atoms {
                if c == 0.0 {
                    continue;
                }
                if self.difference_plane(a.centre).is_some()
                    || (f == Factor::Free && (pa, pb) != (0, 0) && self.cancel.is_some())
                {
                    rest.entry((pa, pb, f)).or_default().insert(a, c);
                    continue;
                }
                let (q, weight) = match f {
                    Factor::Free => (0, None),
                    Factor::Image { plane, weight, q } => {
                        debug_assert_eq!(a.centre, 1 + plane, "image atoms sit on their plane");
                        (q, Some(weight))
                    }
                };
                let n: i32 = a.nu.iter().map(|&k| k as i32).sum();
                let p = match a.pot {
                    Potential::R => 1,
                    Potential::InvR => -1,
                };
                let k = n - p - 2 * (pa as i32 + pb as i32) - q as i32;
                let d = self.poly_jet(a.pot).derivative(&a.nu);
                let mut shift = [0u8; VARS];
                shift[3] = q;
                shift[4] = pa;
                shift[5] = pb;
                polys
                    .entry((a.centre, weight, k))
                    .or_default()
                    .add_shifted(&d, Dd::new(c), shift);
            }
        }
        let mut out: Option<S> = None;
        for ((centre, weight, k), p) in polys {
            if p.is_empty() {
                continue;
            }
            let (_, inv, e) = self.unit(centre);
            let inv2 = inv.clone() * inv.clone();
            let t = match centre.checked_sub(1) {
                Some(plane) => self.heights[plane].clone() * inv.clone(),
                None => S::cst(0.0),
            };
            let vars: [S; VARS] = [
                e[0].clone(),
                e[1].clone(),
                e[2].clone(),
                t,
                aa2.clone() * inv2.clone(),
                ab2.clone() * inv2,
            ];
            let p = if self.collect == Collection::EntriesOnSphere {
                p.on_unit_sphere(std::array::from_fn(|k| vars[k].is_known_zero()))
            } else {
                p
            };
            let mut v = p.eval_all(&vars);
            if v.is_known_zero() {
                continue;
            }
            v = self.inv_norm_pow(centre, k) * v;
            if let Some(w) = weight {
                v = self.weights[w].clone() * v;
            }
            out = Some(match out {
                None => v,
                Some(o) => o + v,
            });
        }
        if !rest.is_empty() {
            let r = self.evaluate(rest, aa2, ab2);
            out = Some(match out {
                None => r,
                Some(o) => o + r,
            });
        }
        out.unwrap_or_else(|| S::cst(0.0))
    }
}

impl<S: Scalar> Derivatives<S> for Structured<S> {
    fn get(&mut self, d: &Deriv) -> S {
        let mut m = BTreeMap::new();
        self.atoms(d, &mut m, 1.0);
        let mut groups: BTreeMap<(u8, u8, Factor), BTreeMap<Atom, f64>> = BTreeMap::new();
        for ((f, a), c) in m {
            *groups.entry((0, 0, f)).or_default().entry(a).or_insert(0.0) += c;
        }
        self.absorb_free(&mut groups);
        let one = S::cst(1.0);
        self.evaluate(groups, &one, &one)
    }

    fn combine(&mut self, terms: &[Term], aa2: &S, ab2: &S) -> S {
        let mut groups: BTreeMap<(u8, u8, Factor), BTreeMap<Atom, f64>> = BTreeMap::new();
        for t in terms {
            let mut m = BTreeMap::new();
            self.atoms(&t.d, &mut m, t.coef);
            for ((f, a), c) in m {
                *groups
                    .entry((t.pa, t.pb, f))
                    .or_default()
                    .entry(a)
                    .or_insert(0.0) += c;
            }
        }
        self.absorb_free(&mut groups);
        if matches!(
            self.collect,
            Collection::Entries | Collection::EntriesOnSphere
        ) {
            self.evaluate_entries(groups, aa2, ab2)
        } else {
            self.evaluate(groups, aa2, ab2)
        }
    }
}

/// Derivatives of any `G(x, y)` from one jet in all six coordinates.
pub struct GenericJets<S> {
    g: Mat3<Jet<S>>,
}

/// Which part of the Green's function a generic jet expands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// `J + J^w` (pair interactions).
    Full,
    /// `J^w` only (self interactions, Eq. 17).
    Reflected,
    /// `J` only.
    Stokeslet,
}

impl<S: Scalar> GenericJets<S> {
    /// Jets of the chosen part of `g` about `(x, y)`, truncated at total degree `degree`.
    pub fn new<G: Green>(
        g: &G,
        part: Part,
        x: &[S; 3],
        y: &[S; 3],
        p: &[S],
        degree: usize,
    ) -> Self {
        let l = Layout::get(6, degree);
        let xj: [Jet<S>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, x[k].clone()));
        let yj: [Jet<S>; 3] = std::array::from_fn(|k| Jet::variable(&l, 3 + k, y[k].clone()));
        let pj: Vec<Jet<S>> = p.iter().map(|v| Jet::constant(v.clone())).collect();
        let gj = match part {
            Part::Full => green::full(g, &xj, &yj, &pj),
            Part::Reflected => g.reflected(&xj, &yj, &pj),
            Part::Stokeslet => {
                let r: [Jet<S>; 3] = std::array::from_fn(|k| xj[k].clone() - yj[k].clone());
                green::stokeslet(&r)
            }
        };
        GenericJets { g: gj }
    }
}

impl<S: Scalar> Derivatives<S> for GenericJets<S> {
    fn get(&mut self, d: &Deriv) -> S {
        let m: Vec<u8> = d.dx.iter().chain(&d.dy).copied().collect();
        self.g[d.i][d.j].derivative(&m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::green::wall::Wall;
    use crate::physics::operators::{Deriv, Derivatives};

    /// The wall's UF block with both Faxen Laplacians, at a lateral distance where the
    /// Stokeslet and its image cancel to 4e-4 of either, in every form the generator
    /// traces (three collections, the exact difference for every term or for the
    /// leading ones only) against the plain direct sum in double-double: 1e-14 of the
    /// block's largest entry covers the f64 rounding of every form (the plain sum in
    /// f64 would lose about `eps rho^2/(h_a h_b)` = 1e-12 here).
    #[test]
    fn every_form_of_a_faxen_block_agrees() {
        use crate::physics::operators::{block, max_order, Basis, Moment, Response};
        let (x, y, p) = ([0.3, -0.7, 1.9], [60.1, 32.4, 1.4], [0.25]);
        let (aa2, ab2) = (0.64, 1.21);
        let order = max_order(Response::U, Moment::F);
        let terms = block(Response::U, Moment::F, Basis::Cartesian);
        let dd = |v: [f64; 3]| v.map(Dd::new);
        let mut reference =
            Structured::new(&Wall, &dd(x), &dd(y), &[Dd::new(p[0])], order, true, true)
                .direct_sum();
        let want: Vec<f64> = terms
            .iter()
            .flatten()
            .map(|t| reference.combine(t, &Dd::new(aa2), &Dd::new(ab2)).to_f64())
            .collect();
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for collect in [
            Collection::Atoms,
            Collection::Centres,
            Collection::Entries,
            Collection::EntriesOnSphere,
        ] {
            for differences in [Differences::All, Differences::Leading] {
                let form = Form {
                    collect,
                    differences,
                };
                let mut s = Structured::new(&Wall, &x, &y, &p, order, true, true).in_form(form);
                for (t, w) in terms.iter().flatten().zip(&want) {
                    let got = s.combine(t, &aa2, &ab2);
                    assert!((got - w).abs() <= 1e-14 * scale, "{form:?}: {got:e} {w:e}");
                }
            }
        }
    }

    /// The structured Eq. 10 path and the generic six-variable path agree on every
    /// derivative of Blake's image up to order 4 (f64 jets; both exact up to
    /// round-off, 1e-12 relative to the largest entry covers it).
    #[test]
    fn structured_and_generic_paths_agree_on_blake() {
        let x = [0.3, -0.7, 1.9];
        let y = [1.1, 0.4, 2.6];
        let p = [0.25];
        let order = 4;
        let mut s = Structured::new(&Wall, &x, &y, &p, order, false, true);
        let mut g = GenericJets::new(&Wall, Part::Reflected, &x, &y, &p, order);
        let l = Layout::get(6, order);
        let mut worst: f64 = 0.0;
        let mut scale: f64 = 0.0;
        for m in &l.monos {
            for i in 0..3 {
                for j in 0..3 {
                    let d = Deriv {
                        i,
                        j,
                        dx: [m[0], m[1], m[2]],
                        dy: [m[3], m[4], m[5]],
                    };
                    let (a, b) = (s.get(&d), g.get(&d));
                    worst = worst.max((a - b).abs());
                    scale = scale.max(b.abs());
                }
            }
        }
        assert!(worst <= 1e-12 * scale, "worst {worst:e} scale {scale:e}");
    }
}
