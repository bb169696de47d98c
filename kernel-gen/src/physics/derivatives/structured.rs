//! The structured path: the Stokeslet in `r = x - y`, each image term in `R = x - y'`
//! by the chain rules of Eq. 10, every derivative of `J` an [`Atom`] (a derivative of a
//! potential at one centre), the potentials' jets about the unit vector of each
//! centre, and, near a cancelling image, the exactly evaluated difference
//! `phi(R) - phi(r)`.

use super::atoms::{binomial, factorial, stokeslet_atoms, Atom, Factor, Potential};
use super::{Collection, Differences, Form};
use crate::number::dd::Dd;
use crate::number::jet::{Jet, Layout};
use crate::number::poly::Poly;
use crate::number::scalar::Scalar;
use crate::physics::green::{rotate, Green, ImageTerm, Mat3, Plane};
use crate::physics::operators::{Deriv, Derivatives, Term};
use std::collections::{BTreeMap, HashMap};
use std::sync::{Arc, Mutex, OnceLock};

/// The structured path: free-space Stokeslet in `r`, image terms by Eq. 10 in `R`,
/// every derivative of `J` reduced to derivatives of the potentials `r` and `1/r`.
///
/// Each block entry is collected as a linear combination of [`Atom`]s with `f64`
/// coefficients, grouped by radius factors and `weight * h^q`, before a single
/// arithmetic node is built ([`Derivatives::combine`]); the jets of the potentials
/// (power rule on `s = R.R`) supply the atoms.
pub struct Structured<S> {
    /// Expansion centres: `[r, R_0, R_1, ...]` (`r` only if the free part is included),
    /// each in its own frame ([`Structured::frames`]).
    pub(super) centres: Vec<[S; 3]>,
    /// The frame of each centre (rows of a rotation `Q`, `None` for the identity): a
    /// mirror's own frame ([`Plane::frame`]) for its image centre, the cancelling
    /// mirror's for `r` (so that the two share their atoms), the identity otherwise.
    pub(super) frames: Vec<Option<Mat3<f64>>>,
    pub(super) include_free: bool,
    pub(super) terms: Vec<ImageTerm>,
    pub(super) heights: Vec<S>,
    /// `n . x - offset` per plane.
    pub(super) field_heights: Vec<S>,
    /// The image `(plane, weight)` that absorbs the free-space atoms, with the
    /// difference evaluated apart (see the module documentation).
    pub(super) cancel: Option<(usize, usize)>,
    pub(super) weights: Vec<S>,
    pub(super) explicit_height: bool,
    pub(super) degree: usize,
    pub(super) jets: HashMap<(usize, Potential), Jet<S>>,
    /// The jets of the potentials about a symbolic unit vector ([`Poly`]), per potential.
    pub(super) poly_jets: HashMap<Potential, Jet<Poly>>,
    /// The potential of the kernel `J = (delta lap - d d) phi`: `r`, or
    /// [`Potential::Radial`]`(0)` for a Green's function that declares one.
    pub(super) phi: Potential,
    /// The radial coefficients of a declared radial potential, per centre and Laplacian
    /// `m` ([`Structured::radial`]).
    pub(super) radial: HashMap<(usize, u8), Vec<S>>,
    /// The powers `u^j`, `j = 0..=degree`, of `u = |e + d|^2 - 1 = 2 e.d + d.d` as jets
    /// in `d` about the symbolic unit vector `e`, built on first use.
    pub(super) u_powers: Vec<Jet<Poly>>,
    /// How atoms become arithmetic.
    pub(super) collect: Collection,
    /// Which terms take the exact difference near a cancelling image.
    pub(super) differences: Differences,
    pub(super) units: HashMap<usize, (S, S, [S; 3])>,
    /// A factor of every derivative ([`Structured::scaled`]).
    pub(super) multiplier: Option<S>,
    /// The interned [`Symbolic`] of this instance, once [`Derivatives::combine`] asked.
    symbolic: Option<usize>,
}

/// A block entry's atoms, grouped by the powers of `a_a^2` and `a_b^2` and the factor
/// ([`Derivatives::combine`]).
pub(super) type Groups = BTreeMap<(u8, u8, Factor), BTreeMap<Atom, f64>>;

/// Everything but the terms that [`Structured::atoms`] and [`Structured::absorb_free`]
/// read: with a block entry's terms it fixes the entry's [`Groups`], which depend on no
/// value of the arithmetic (positions, radii, parameters). The `f64`s by their bits.
#[derive(PartialEq, Eq, Hash)]
struct Symbolic {
    phi: Potential,
    include_free: bool,
    explicit_height: bool,
    planes: usize,
    centres: usize,
    cancel: Option<(usize, usize)>,
    differences: Differences,
    frames: Vec<Option<[[u64; 3]; 3]>>,
    terms: Vec<TermBits>,
}

/// An image term by its fields `(out, coef, weight, plane, h_power, d, j)`, the
/// coefficient by its bits.
type TermBits = (
    (usize, usize),
    u64,
    usize,
    usize,
    u8,
    [u8; 3],
    (usize, usize),
);

/// A block entry's terms: `(coef, pa, pb, d)`, the coefficient by its bits.
type TermsKey = Vec<(u64, u8, u8, Deriv)>;

/// The groups of every entry combined so far, per interned [`Symbolic`]: the same
/// entries recur for every configuration a kernel is evaluated at (the double-double
/// references of the tests and the report) and in the scenes that share a family's
/// kernels. Pure memoisation: the groups, and so the arithmetic, are the same.
struct Memo {
    symbolic: HashMap<Symbolic, usize>,
    groups: HashMap<(usize, TermsKey), Arc<Groups>>,
}

fn memo() -> &'static Mutex<Memo> {
    static MEMO: OnceLock<Mutex<Memo>> = OnceLock::new();
    MEMO.get_or_init(|| {
        Mutex::new(Memo {
            symbolic: HashMap::new(),
            groups: HashMap::new(),
        })
    })
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
        let mirrors = g.mirrors(p);
        let cancel = g.cancelling_image().filter(|_| include_free);
        let free_frame = cancel.map_or(crate::physics::green::E3, |(k, _)| mirrors[k].normal);
        let mut s = Self::with_terms(
            terms,
            x,
            y,
            mirrors,
            g.weights(p),
            degree,
            include_free,
            explicit_height,
        );
        s.frames[0] = frame_of(free_frame);
        if let Some(q) = &s.frames[0] {
            let r: [S; 3] = std::array::from_fn(|k| x[k].clone() - y[k].clone());
            s.centres[0] = rotate(q, &r);
        }
        s.cancel = cancel;
        if crate::physics::green::is_radial(g) {
            s.phi = Potential::kernel(true);
            s.radial = s.radial_coefficients(g, p);
        }
        s
    }

    /// The radial coefficients `b_{m,j}` of `lap^m phi` ([`Green::radial`]) at every
    /// centre: about the unit vector `e = R/|R|`, with `s = |R|^2` and `u = |e + d|^2 - 1
    /// = 2 e.d + d.d`, `lap^m phi(|R| (e + d)) = |R|^(1 - 2m) sum_j b_{m,j} u^j`, so
    /// `b_{m,j}` is the coefficient of `u^j` in the univariate jet of `lap^m phi(s (1 + u))`
    /// (the Green's function's own `sqrt`, `erfc`, `exp` on jets), times `|R|^(2m - 1)`.
    /// For a homogeneous potential `|R|^p` the `b_j` are the binomial coefficients
    /// `C(p/2, j)`, which the polynomial jets of [`Structured::poly_jet`] fold in; here
    /// they are run-time values, so every atom is `sum_j b_{m,j} P_{nu,j}(e)` with
    /// `P_{nu,j}` the universal polynomial of `d^nu u^j` ([`Structured::u_powers`]).
    /// Laplacians up to `m = degree / 2`, each to degree `degree - 2m` (an atom of
    /// `lap^m phi` has order at most that); what no kernel uses is dead code.
    fn radial_coefficients<G: Green>(&mut self, g: &G, p: &[S]) -> HashMap<(usize, u8), Vec<S>> {
        let first = if self.include_free { 0 } else { 1 };
        let pj: Vec<Jet<S>> = p.iter().map(|v| Jet::constant(v.clone())).collect();
        let mut out = HashMap::new();
        for centre in first..self.centres.len() {
            let (norm, inv, _) = self.unit(centre);
            let c = &self.centres[centre];
            let s0 = c[0].clone() * c[0].clone()
                + c[1].clone() * c[1].clone()
                + c[2].clone() * c[2].clone();
            for m in 0..=(self.degree / 2) as u8 {
                let degree = self.degree - 2 * m as usize;
                let l = Layout::get(1, degree);
                let u = Jet::variable(&l, 0, S::cst(0.0));
                let x = Jet::constant(s0.clone()) + Jet::constant(s0.clone()) * u;
                let f = g
                    .radial(m, &x, &pj)
                    .expect("a radial potential declares every Laplacian");
                // |R|^(2m - 1)
                let scale = match m {
                    0 => inv.clone(),
                    _ => (1..2 * m - 1).fold(norm.clone(), |a, _| a * norm.clone()),
                };
                let b = (0..=degree)
                    .map(|j| scale.clone() * f.coeff(&[j as u8]))
                    .collect();
                out.insert((centre, m), b);
            }
        }
        out
    }

    /// The plain direct sum of the Stokeslet and its image, without the rewrite into
    /// an exactly evaluated difference: the reference of the stiff cases.
    pub fn direct_sum(mut self) -> Self {
        self.cancel = None;
        self.symbolic = None;
        self
    }

    /// Every derivative times `m` (the kernels' `1/(8 pi eta)`): `m` multiplies the
    /// powers of `1/|R|` (`Structured::inv_norm_pow`), one of which ends every term,
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
        self.symbolic = None;
        self
    }

    /// The interned id of what, besides the terms, fixes the groups ([`Symbolic`]).
    fn symbolic_id(&mut self) -> usize {
        if let Some(id) = self.symbolic {
            return id;
        }
        let bits = |q: &Mat3<f64>| q.map(|row| row.map(f64::to_bits));
        let key = Symbolic {
            phi: self.phi,
            include_free: self.include_free,
            explicit_height: self.explicit_height,
            planes: self.heights.len(),
            centres: self.centres.len(),
            cancel: self.cancel,
            differences: self.differences,
            frames: self.frames.iter().map(|f| f.as_ref().map(bits)).collect(),
            terms: (self.terms.iter())
                .map(|t| {
                    let ImageTerm {
                        out,
                        coef,
                        weight,
                        plane,
                        h_power,
                        d,
                        j,
                    } = *t;
                    (out, coef.to_bits(), weight, plane, h_power, d, j)
                })
                .collect(),
        };
        let mut m = memo().lock().expect("the memo's lock is not poisoned");
        let next = m.symbolic.len();
        let id = *m.symbolic.entry(key).or_insert(next);
        self.symbolic = Some(id);
        id
    }

    /// A block entry's groups, built from its terms ([`Structured::atoms`],
    /// [`Structured::absorb_free`]) or taken from the memo.
    fn groups(&mut self, terms: &[Term]) -> Arc<Groups> {
        let key = (
            self.symbolic_id(),
            terms
                .iter()
                .map(|t| (t.coef.to_bits(), t.pa, t.pb, t.d))
                .collect::<TermsKey>(),
        );
        if let Some(g) = memo()
            .lock()
            .expect("the memo's lock is not poisoned")
            .groups
            .get(&key)
        {
            return g.clone();
        }
        let mut groups = Groups::new();
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
        let groups = Arc::new(groups);
        memo()
            .lock()
            .expect("the memo's lock is not poisoned")
            .groups
            .insert(key, groups.clone());
        groups
    }

    /// As [`Structured::new`], from the image terms, the mirror planes and the
    /// weights themselves (a subset of a Green's function's terms), with jets of
    /// degree `degree`; the free-space centre `r` in the world frame.
    #[allow(clippy::too_many_arguments)]
    pub fn with_terms(
        terms: Vec<ImageTerm>,
        x: &[S; 3],
        y: &[S; 3],
        planes: Vec<Plane<S>>,
        weights: Vec<S>,
        degree: usize,
        include_free: bool,
        explicit_height: bool,
    ) -> Self {
        let r: [S; 3] = std::array::from_fn(|k| x[k].clone() - y[k].clone());
        let mut centres = vec![r.clone()];
        let mut frames = vec![None];
        let mut heights = Vec::new();
        let mut field_heights = Vec::new();
        for plane in planes {
            // in the plane's frame the mirror is `x3' = offset` (Eq. 10 as written)
            field_heights.push(plane.distance(x));
            let h = plane.distance(y);
            let q = frame_of(plane.normal);
            let rq = match &q {
                Some(q) => rotate(q, &r),
                None => r.clone(),
            };
            let [r0, r1, r2] = rq;
            centres.push([r0, r1, r2 + S::cst(2.0) * h.clone()]);
            frames.push(q);
            heights.push(h);
        }
        Structured {
            centres,
            frames,
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
            phi: Potential::R,
            radial: HashMap::new(),
            u_powers: Vec::new(),
            collect: Collection::Centres,
            differences: Differences::All,
            units: HashMap::new(),
            multiplier: None,
            symbolic: None,
        }
    }

    /// `|c|`, `1/|c|` and the unit vector `e = c/|c|` of a centre.
    pub(super) fn unit(&mut self, centre: usize) -> (S, S, [S; 3]) {
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
    pub(super) fn jet(&mut self, centre: usize, pot: Potential) -> &Jet<S> {
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
                Potential::Radial(_) => unreachable!("radial atoms take `radial_value`"),
            }
        })
    }

    /// `u^j`, `j = 0..=degree`, with `u = 2 e.d + d.d`, as jets in `d` whose
    /// coefficients are polynomials in the symbolic unit vector `e`: `d^nu u^j` is the
    /// polynomial `P_{nu,j}(e)` of the radial atoms ([`Structured::radial_coefficients`]),
    /// zero unless `j <= |nu| <= 2j`.
    pub(super) fn u_powers(&mut self) -> &[Jet<Poly>] {
        if self.u_powers.is_empty() {
            let l = Layout::get(3, self.degree);
            let d: [Jet<Poly>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, Poly::cst(0.0)));
            let mut u = Jet::cst(0.0);
            for k in 0..3 {
                u = u
                    + Jet::constant(Poly::cst(2.0) * Poly::var(k)) * d[k].clone()
                    + d[k].clone() * d[k].clone();
            }
            let mut power = Jet::cst(1.0);
            for _ in 0..=self.degree {
                self.u_powers.push(power.clone());
                power = power * u.clone();
            }
        }
        &self.u_powers
    }

    /// `sum_j b_{m,j} (sum_atoms c d^nu u^j)(e)`: atoms `(nu, c)` of `lap^m phi` at one
    /// centre, without the factor `|R|^(1 - 2m - n)` ([`Structured::radial_coefficients`]);
    /// `None` if nothing survives.
    pub(super) fn radial_value(
        &mut self,
        centre: usize,
        m: u8,
        atoms: &[([u8; 3], f64)],
    ) -> Option<S> {
        let polys: Vec<Poly> = self
            .u_powers()
            .iter()
            .map(|power| {
                let mut p = Poly::default();
                for (nu, c) in atoms {
                    p.add_scaled(&power.derivative(nu), Dd::new(*c));
                }
                p
            })
            .collect();
        let (_, _, e) = self.unit(centre);
        let b = self.radial[&(centre, m)].clone();
        let mut acc: Option<S> = None;
        for (p, bj) in polys.iter().zip(&b) {
            if p.is_empty() {
                continue;
            }
            let v = p.eval(&e);
            if v.is_known_zero() {
                continue;
            }
            let v = bj.clone() * v;
            acc = Some(match acc {
                None => v,
                Some(a) => a + v,
            });
        }
        acc
    }

    /// The jet of a potential about the symbolic unit vector `e`: every coefficient a
    /// polynomial in `e` ([`crate::number::poly`]), the same for every centre.
    pub(super) fn poly_jet(&mut self, pot: Potential) -> &Jet<Poly> {
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
                Potential::Radial(_) => unreachable!("radial atoms take `u_powers`"),
            }
        })
    }

    /// The plane `t` of a difference centre `1 + n + t`.
    pub(super) fn difference_plane(&self, centre: usize) -> Option<usize> {
        centre.checked_sub(self.centres.len())
    }

    /// The centre whose `|R|` scales an atom: a difference is scaled as its image.
    pub(super) fn scaling_centre(&self, centre: usize) -> usize {
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
    pub(super) fn difference_jet(&mut self, t: usize, pot: Potential) -> Jet<S> {
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
            Potential::Radial(_) => unreachable!("no cancelling image with a radial potential"),
        }
    }

    /// Where the image cancels the Stokeslet, move every free-space atom (or those
    /// without Faxen factors, [`Differences::Leading`]) to the image centre and its
    /// difference: `c d^nu phi(r) = c d^nu phi(R) - c d^nu [phi(R) - phi(r)]`, into the
    /// image's group of factor `weight * h^0` (weight exactly 1).
    pub(super) fn absorb_free(&self, groups: &mut BTreeMap<(u8, u8, Factor), BTreeMap<Atom, f64>>) {
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
    pub(super) fn atom_at_unit(&mut self, a: &Atom) -> S {
        if let Potential::Radial(m) = a.pot {
            return self
                .radial_value(a.centre, m, &[(a.nu, 1.0)])
                .unwrap_or_else(|| S::cst(0.0));
        }
        self.jet(a.centre, a.pot).derivative(&a.nu)
    }

    /// `|R|^(-k)` by repeated products of `1/|R|` (or of `|R|` for `k < 0`), shared;
    /// times the multiplier ([`Structured::scaled`]), if any.
    pub(super) fn inv_norm_pow(&mut self, centre: usize, k: i32) -> S {
        let (norm, inv, _) = self.unit(centre);
        let base = if k >= 0 { inv } else { norm };
        let mut v = self.multiplier.clone().unwrap_or_else(|| S::cst(1.0));
        for _ in 0..k.unsigned_abs() {
            v = v * base.clone();
        }
        v
    }

    pub(super) fn factor_value(&self, f: &Factor) -> S {
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

    /// `d` as `sum factor * coef * atom`: each centre's part in its own frame
    /// ([`in_frame`]).
    pub(super) fn atoms(&self, d: &Deriv, out: &mut BTreeMap<(Factor, Atom), f64>, scale: f64) {
        let phi = self.phi;
        let mut push = |f: Factor, centre: usize, mu: [u8; 3], a: usize, b: usize, c: f64| {
            for ((pot, nu), k) in stokeslet_atoms(phi, a, b, mu, c) {
                *out.entry((f, Atom { centre, pot, nu })).or_insert(0.0) += k;
            }
        };
        if self.include_free {
            for (c, d) in in_frame(&self.frames[0], d) {
                // d_x = d_r, d_y = -d_r
                let mu = [d.dx[0] + d.dy[0], d.dx[1] + d.dy[1], d.dx[2] + d.dy[2]];
                let sign = if d.dy.iter().map(|&e| e as u32).sum::<u32>() % 2 == 1 {
                    -1.0
                } else {
                    1.0
                };
                push(Factor::Free, 0, mu, d.i, d.j, scale * c * sign);
            }
        }
        // Eq. 10 in the plane's frame: d_x = d_R; d_{y_k} = -P_kk d_{R_k} on g(R);
        // Leibniz in y3 on h^p.
        for plane in 0..self.heights.len() {
            for (c, d) in in_frame(&self.frames[1 + plane], d) {
                let sign_y = if (d.dy[0] + d.dy[1]) % 2 == 1 {
                    -1.0
                } else {
                    1.0
                };
                let n3 = d.dy[2] as usize;
                for t in self
                    .terms
                    .iter()
                    .filter(|t| t.plane == plane && t.out == (d.i, d.j))
                {
                    let p = t.h_power as usize;
                    let smax = if self.explicit_height { n3.min(p) } else { 0 };
                    for s in 0..=smax {
                        let mut mu = [0u8; 3];
                        for k in 0..3 {
                            mu[k] = t.d[k] + d.dx[k] + d.dy[k];
                        }
                        mu[2] -= s as u8;
                        let k = scale * c * sign_y * t.coef * binomial(n3, s) * factorial(p)
                            / factorial(p - s);
                        let f = Factor::Image {
                            plane: t.plane,
                            weight: t.weight,
                            q: (p - s) as u8,
                        };
                        push(f, 1 + t.plane, mu, t.j.0, t.j.1, k);
                    }
                }
            }
        }
    }
}

/// The frame of a mirror of normal `n`, `None` for `e3` (the identity).
fn frame_of(n: [f64; 3]) -> Option<Mat3<f64>> {
    (n != crate::physics::green::E3).then(|| crate::physics::green::frame(n))
}

/// A derivative of `G` in the world frame as derivatives in the frame `q` (rows
/// `t1, t2, n`): `G_ij = sum Q_i'i Q_j'j G'_i'j'` and `d_{x_k} = sum_m Q_mk d_{x'_m}`
/// (likewise in `y`), multiplied out. The identity gives `d` itself, coefficient 1.
fn in_frame(q: &Option<Mat3<f64>>, d: &Deriv) -> Vec<(f64, Deriv)> {
    let Some(q) = q else {
        return vec![(1.0, *d)];
    };
    // the monomials of prod_k (sum_m Q_mk d'_m)^alpha_k
    let expand = |alpha: [u8; 3]| -> BTreeMap<[u8; 3], f64> {
        let mut m = BTreeMap::from([([0u8; 3], 1.0)]);
        for (k, &n) in alpha.iter().enumerate() {
            for _ in 0..n {
                let mut next = BTreeMap::new();
                for (mono, c) in &m {
                    for (axis, row) in q.iter().enumerate() {
                        if row[k] != 0.0 {
                            let mut e = *mono;
                            e[axis] += 1;
                            *next.entry(e).or_insert(0.0) += c * row[k];
                        }
                    }
                }
                m = next;
            }
        }
        m
    };
    let (ex, ey) = (expand(d.dx), expand(d.dy));
    let mut out = Vec::new();
    for (i, qi) in q.iter().enumerate() {
        for (j, qj) in q.iter().enumerate() {
            let c = qi[d.i] * qj[d.j];
            if c == 0.0 {
                continue;
            }
            for (dx, cx) in &ex {
                for (dy, cy) in &ey {
                    let k = c * cx * cy;
                    if k != 0.0 {
                        out.push((
                            k,
                            Deriv {
                                i,
                                j,
                                dx: *dx,
                                dy: *dy,
                            },
                        ));
                    }
                }
            }
        }
    }
    out
}

impl<S: Scalar> Derivatives<S> for Structured<S> {
    fn get(&mut self, d: &Deriv) -> S {
        // one term, without radius factors
        let term = Term {
            coef: 1.0,
            pa: 0,
            pb: 0,
            d: *d,
        };
        let groups = self.groups(&[term]);
        let one = S::cst(1.0);
        self.evaluate(&groups, &one, &one)
    }

    fn combine(&mut self, terms: &[Term], aa2: &S, ab2: &S) -> S {
        let groups = self.groups(terms);
        if matches!(
            self.collect,
            Collection::Entries | Collection::EntriesOnSphere
        ) {
            self.evaluate_entries(&groups, aa2, ab2)
        } else {
            self.evaluate(&groups, aa2, ab2)
        }
    }
}
