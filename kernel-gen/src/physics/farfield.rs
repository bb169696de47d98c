//! The lateral far field of a pair near a plane: where the Stokeslet and its image
//! cancel, the kernel is evaluated from its Taylor expansion in the heights over the
//! lateral distance, with coefficients computed in double-double at generation time.
//!
//! Near a no-slip wall the direct sum `J(r) + J^w(x, y)` of a pair at lateral distance
//! `rho` and heights `h_a`, `h_b` has terms of order `1/rho` whose sum is of order
//! `h_a h_b / rho^3`: evaluated directly, it loses a factor `rho^2 / (h_a h_b)` to
//! cancellation (all digits at `rho/h = 1e8`). The rule here removes the cancellation
//! at generation time instead of at run time:
//!
//! 1. Homogeneity. Every block is homogeneous in the lengths: `M(l x, l a) =
//!    l^d M(x, a)` with `d = -1 - n_x - n_y`, `n_x` (`n_y`) the derivative order of the
//!    field (source) functional (0 for `U` and `F`, 1 for `Omega`, `E`, `L`, `S`;
//!    the Faxén terms `a^2 lap` keep the degree). In the frame rotated about the
//!    normal so that the lateral separation lies along `+x`,
//!    `M'(rho, h_a, h_b, a_a, a_b) = rho^d P(h_a/rho, h_b/rho, a_a^2/rho^2, a_b^2/rho^2)`.
//! 2. Taylor arithmetic. `P` is the same block, traced by the same structured path
//!    (Eq. 10), on jets in `u_a = h_a/rho`, `u_b = h_b/rho` about 0 whose coefficients
//!    are double-double numbers, at `x = (1, 0, u_a)`, `y = (0, 0, u_b)`, the plane at
//!    0. `P` is bilinear in `a_a^2`, `a_b^2` (each Faxén operator is `1 + c a^2 lap`),
//!    so the terms are grouped by their radius powers and each group is a jet. The
//!    cancelling orders come out as double-double round-off (with the `f64` coefficients of the
//!    operators, below 1e-15 of the largest coefficient of their degree) and are dropped; what remains
//!    is a polynomial whose terms are all of the size of the result.
//! 3. Rotation back. The branch's blocks are those of the canonical frame of the pair
//!    kernel ([`crate::physics::frame`]), which rotates them (or the moments and responses of a
//!    product) back to the world like the direct sum's.
//!
//! The series converges for `|h_a| + |h_b| < rho`; truncated at total degree
//! [`ORDER`] in `(u_a, u_b)` and used where `rho^2 > SWITCH^2 * 2 (h_a^2 + h_b^2)`
//! (so `(|h_a| + |h_b|)/rho < 1/SWITCH`), its truncation error relative to the leading
//! surviving term `u_a u_b` is about `(2/SWITCH)^(ORDER - 1)` (1e-14). On the other
//! side of the switch the direct sum loses at most about `eps rho^2 / (h_a h_b)`,
//! `2e-16 * 2 SWITCH^2 (h_a^2 + h_b^2) / (h_a h_b)`: 1e-11 for equal heights. Both
//! branches are tested against the double-double direct sum on both sides of the
//! switch (`tests/tests/integration/generated/stiff_cases.rs`).
//!
//! The rule applies where it is needed, decided from the coefficients: a Green's
//! function with a single mirror plane and no run-time weights (its only parameter is
//! the plane's height) for which some block's expansion has no term of degree 0 in
//! `(u_a, u_b)` (the direct sum cancels to leading order): the wall. The free surface (`J(r) +
//! J(R) P`, which does not cancel) and the confinements with run-time weights or
//! two planes keep the direct sum alone, and so does a kernel of a radial potential
//! other than the Stokeslet's (`Green::radial`: not homogeneous, so no step 1).

use crate::number::dd::Dd;
use crate::number::jet::{Jet, Layout};
use crate::number::scalar::Scalar;
use crate::physics::derivatives::Structured;
use crate::physics::green::free::Free;
use crate::physics::green::Green;
use crate::physics::operators::{self, Basis, Derivatives, Moment, Response, Term};
use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap};
use std::rc::Rc;

/// The far branch is taken where `rho > SWITCH (|h_a| + |h_b|)` (tested as
/// `rho^2 > 2 SWITCH^2 (h_a^2 + h_b^2)`, which implies it).
pub const SWITCH: f64 = 100.0;

/// Truncation degree of the expansion in `(h_a/rho, h_b/rho)`.
pub const ORDER: usize = 9;

/// Coefficients below this fraction of the largest coefficient of the free-space part
/// of their block are round-off of exact zeros. The operators' coefficients are exact
/// ([`operators::exact_block`]: dyadic rationals, the strain normalisation and the
/// Faxén factors applied in double-double outside), so the terms that cancel in exact
/// arithmetic (the Stokeslet against its image) leave about 1e-32 of the free-space
/// terms; the coefficients that do not vanish are ratios of small integers, above
/// [`SMALLEST`] of them ([`compute`] checks this gap). The scale is the free-space
/// part's, not the block's own: where a whole degree cancels, its leftovers are all
/// the block has of that degree.
const ZERO: f64 = 1e-24;

/// Smallest ratio to the free-space part's largest coefficient a non-zero coefficient
/// may have.
const SMALLEST: f64 = 1e-10;

/// One term of `P`: `c (a_a^2/rho^2)^pa (a_b^2/rho^2)^pb u_a^i u_b^j`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coef {
    /// Power of `a_a^2 / rho^2`.
    pub pa: u8,
    /// Power of `a_b^2 / rho^2`.
    pub pb: u8,
    /// Power of `u_a = h_a / rho`.
    pub i: u8,
    /// Power of `u_b = h_b / rho`.
    pub j: u8,
    /// Coefficient.
    pub c: f64,
}

/// The expansion of every block: per block, per entry (row-major, rotated frame), its
/// terms.
#[derive(Debug)]
pub struct Lateral {
    /// `blocks[k][entry]`: the terms of `P` for entry `entry` of block `k`.
    pub blocks: Vec<Vec<Vec<Coef>>>,
}

type Key = (&'static str, Vec<(Response, Moment)>, usize);

thread_local! {
    static CACHE: RefCell<HashMap<Key, Option<Rc<Lateral>>>> = RefCell::new(HashMap::new());
}

/// The lateral expansion of `blocks` for `g` (derivatives of `G` to `order`), or
/// `None` where the rule does not apply (see the module documentation). Cached per
/// thread.
pub fn lateral<G: Green>(
    g: &G,
    blocks: &[(Response, Moment)],
    basis: Basis,
    order: usize,
) -> Option<Rc<Lateral>> {
    if basis != Basis::Orthonormal
        || g.params().len() != 1
        || g.mirrors(&[0.0f64]).len() != 1
        || g.mirrors(&[0.0f64])[0].normal != crate::physics::green::E3
        || !g.axisymmetric()
        || g.image_terms().is_none()
        || crate::physics::green::is_radial(g)
        || g.weights(&[0.0f64]).len() != 1
    {
        return None;
    }
    let key = (g.name(), blocks.to_vec(), order);
    if let Some(v) = CACHE.with(|c| c.borrow().get(&key).cloned()) {
        return v;
    }
    let v = compute(g, blocks, basis, order).map(Rc::new);
    CACHE.with(|c| c.borrow_mut().insert(key, v.clone()));
    v
}

fn compute<G: Green>(
    g: &G,
    blocks: &[(Response, Moment)],
    basis: Basis,
    order: usize,
) -> Option<Lateral> {
    let l = Layout::get(2, ORDER);
    let cst = |x: f64| Jet::<Dd>::constant(Dd::new(x));
    let x = [cst(1.0), cst(0.0), Jet::variable(&l, 0, Dd::new(0.0))];
    let y = [cst(0.0), cst(0.0), Jet::variable(&l, 1, Dd::new(0.0))];
    let mut src = Structured::new(g, &x, &y, &[cst(0.0)], order, true, true);
    // the free-space part alone: the size of the terms that cancel
    let mut free = Structured::new(&Free, &x, &y, &[], order, true, true);
    let one = cst(1.0);
    let mut out = Vec::new();
    let mut cancels = false;
    for &(r, m) in blocks {
        let blk = operators::exact_block(r, m, basis);
        let mut leading: f64 = 0.0;
        let mut entries = Vec::new();
        let mut raw: Vec<Vec<(u8, u8, Jet<Dd>)>> = Vec::new();
        let mut scale: f64 = 0.0;
        for (row, norms) in blk.entries.iter().zip(&blk.norm) {
            for (entry, &n) in row.iter().zip(norms) {
                let mut groups: BTreeMap<(u8, u8), Vec<Term>> = BTreeMap::new();
                for t in entry {
                    assert!(t.pa <= 1 && t.pb <= 1, "Faxén operators are 1 + c a^2 lap");
                    groups.entry((t.pa, t.pb)).or_default().push(*t);
                }
                let mut e = Vec::new();
                for ((pa, pb), ts) in groups {
                    // the factors outside the exact coefficients, in double-double
                    let mut f = dd_norm(n);
                    if pa == 1 {
                        f = f * operators::faxen_factor::<Dd>(blk.fa);
                    }
                    if pb == 1 {
                        f = f * operators::faxen_factor::<Dd>(blk.fb);
                    }
                    let fj = Jet::constant(f);
                    let full = fj.clone() * src.combine(&ts, &one, &one);
                    let free_part = fj * free.combine(&ts, &one, &one);
                    for mono in &l.monos {
                        scale = scale.max(free_part.coeff(mono).to_f64().abs());
                    }
                    e.push((pa, pb, full));
                }
                raw.push(e);
            }
        }
        for e in &raw {
            let mut terms = Vec::new();
            for (pa, pb, j) in e {
                for mono in &l.monos {
                    let c = j.coeff(mono).to_f64();
                    assert!(
                        c.abs() <= ZERO * scale || c.abs() >= SMALLEST * scale,
                        "{}: coefficient {c:e} of {mono:?} is neither round-off nor of the \
                         size of the free-space terms, {scale:e}",
                        g.name()
                    );
                    if c.abs() > ZERO * scale {
                        if *pa == 0 && *pb == 0 && mono == &[0, 0] {
                            leading = leading.max(c.abs());
                        }
                        terms.push(Coef {
                            pa: *pa,
                            pb: *pb,
                            i: mono[0],
                            j: mono[1],
                            c,
                        });
                    }
                }
            }
            entries.push(terms);
        }
        cancels |= scale > 0.0 && leading == 0.0;
        out.push(entries);
    }
    // The rule is needed where the direct sum of some block cancels to leading order
    // (no term of degree 0 survives in it).
    cancels.then_some(Lateral { blocks: out })
}

/// A normalisation `1/sqrt(n)` ([`operators::norm`]) in double-double, from its
/// correctly rounded `f64` value: `n = round(1/v^2)` is a small integer.
pub(crate) fn dd_norm(v: f64) -> Dd {
    if v == 1.0 {
        return Dd::new(1.0);
    }
    let n = (1.0 / (v * v)).round();
    Dd::new(n).sqrt().recip()
}

/// Degree of homogeneity of a block: `-1 - n_x - n_y`.
pub fn degree(r: Response, m: Moment) -> i32 {
    let nx = if r == Response::U { 0 } else { 1 };
    let ny = if m == Moment::F { 0 } else { 1 };
    -1 - nx - ny
}

/// The far branch of a pair kernel in the canonical frame ([`crate::physics::frame`]): the
/// switch condition `(lhs, rhs)` (far where `lhs > rhs`) and every entry of every
/// block in the frame (row-major, units of `1/(8 pi eta)`), from the expansion `lat`,
/// given `rho^2`, `rho` and the particles' heights over the plane.
pub fn blocks<S: Scalar>(
    lat: &Lateral,
    blocks: &[(Response, Moment)],
    (rho2, rho): (&S, &S),
    (ha, hb): (&S, &S),
    aa: &S,
    ab: &S,
) -> ((S, S), Vec<Vec<S>>) {
    let rhs = S::cst(2.0 * SWITCH * SWITCH) * (ha.clone() * ha.clone() + hb.clone() * hb.clone());
    let cond = (rho2.clone(), rhs);
    let inv = rho.recip();
    let (ua, ub) = (ha.clone() * inv.clone(), hb.clone() * inv.clone());
    let (qa, qb) = (aa.clone() * inv.clone(), ab.clone() * inv.clone());
    let (qa2, qb2) = (qa.clone() * qa, qb.clone() * qb);
    let pow = |b: &S, n: usize| -> Vec<S> {
        let mut v = vec![S::cst(1.0)];
        for k in 1..=n {
            v.push(v[k - 1].clone() * b.clone());
        }
        v
    };
    let (pua, pwb, pinv) = (pow(&ua, ORDER), pow(&ub, ORDER), pow(&inv, 5));
    let mut out = Vec::new();
    for (k, &(r, m)) in blocks.iter().enumerate() {
        let rotated: Vec<S> = lat.blocks[k]
            .iter()
            .map(|terms| {
                let mut groups: BTreeMap<(u8, u8), Option<S>> = BTreeMap::new();
                for t in terms {
                    let v = S::cst(t.c) * (pua[t.i as usize].clone() * pwb[t.j as usize].clone());
                    let g = groups.entry((t.pa, t.pb)).or_insert(None);
                    *g = Some(match g.take() {
                        None => v,
                        Some(a) => a + v,
                    });
                }
                let mut acc = S::cst(0.0);
                for ((pa, pb), v) in groups {
                    let mut v = v.expect("non-empty group");
                    if pa == 1 {
                        v = qa2.clone() * v;
                    }
                    if pb == 1 {
                        v = qb2.clone() * v;
                    }
                    acc = acc + v;
                }
                pinv[(-degree(r, m)) as usize].clone() * acc
            })
            .collect();
        out.push(rotated);
    }
    (cond, out)
}
