//! The reflected self term (Eq. 17) in closed form: at the sphere's own centre the
//! lateral distance is 0, and the reflected field of each mirror plane depends on one
//! length, the height `h_k` of the centre over that plane.
//!
//! The direct sum of the structured path adds derivatives of the image terms that
//! cancel: a block entry's terms of order `h^d` can cancel to order `a^2 h^(d-2)`
//! (the rotation-translation couplings of a wall or slit lose `(h/a)^2`: 3.8e-8 at
//! `h/a = 1e4`). The rule here is the lateral far field's ([`crate::physics::farfield`]) at
//! `rho = 0`, where the expansion is finite:
//!
//! 1. Homogeneity. The contribution of one plane `k` and one run-time weight `w` to a
//!    block entry is `w sum_{pa, pb} C a_a^(2 pa) a_b^(2 pb) |h_k|^(d - 2 pa - 2 pb)`,
//!    `d = -1 - n_x - n_y` the block's degree ([`crate::physics::farfield::degree`]), `pa`,
//!    `pb` in {0, 1} (each Faxén operator is `1 + c a^2 lap`): exact, not truncated.
//! 2. Double-double coefficients. `C` is the same entry traced by the same structured
//!    path (Eq. 10) with that plane's terms only, at unit height on the fluid side of
//!    the plane (`x = y = (0, 0, s_k)`, the plane at 0, `s_k = +1` where the fluid is
//!    above the plane, `-1` below), with the operators' exact coefficients
//!    ([`operators::exact_block`]) and their normalisations in double-double. What
//!    cancels exactly comes out below 1e-24 of the largest coefficient and is dropped.
//! 3. The branch. The closed form holds wherever the centre is on the fluid side of
//!    every plane (`s_k h_k > 0`: it is written with `|h_k| = s_k h_k`); the kernel
//!    takes it there and the direct sum elsewhere (centres beyond a plane, which the
//!    solver rejects), so it is the direct sum's value, without its cancellation, on
//!    every valid input.
//!
//! It applies to every Green's function with image structure (all but free space);
//! the isolated sphere ([`operators::isolated`]) is added as in the direct sum.

use crate::number::dd::Dd;
use crate::number::scalar::Scalar;
use crate::physics::derivatives::Structured;
use crate::physics::farfield::degree;
use crate::physics::green::{Green, Plane};
use crate::physics::operators::{self, isolated, Basis, Derivatives, Moment, Response, Term};
use std::collections::BTreeMap;

/// Coefficients below this fraction of the largest of the kernel are round-off of
/// exact zeros: with exact operator coefficients, cancelling terms (all of size about
/// 1 at unit height and radius) leave about 1e-32; the ones that survive are ratios
/// of small integers, above [`SMALLEST`] ([`expansion`] checks the gap).
const ZERO: f64 = 1e-24;

/// Smallest ratio to the largest coefficient a non-zero coefficient may have.
const SMALLEST: f64 = 1e-10;

/// One monomial of a self block entry: `w_weight * c * a^(2 (pa + pb)) |h_plane|^e`,
/// `e = d - 2 (pa + pb)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mono {
    /// Mirror plane.
    pub plane: usize,
    /// Run-time weight.
    pub weight: usize,
    /// Power of `a_a^2`.
    pub pa: u8,
    /// Power of `a_b^2`.
    pub pb: u8,
    /// Coefficient (units of `1/(8 pi eta)`).
    pub c: f64,
}

/// The closed form of every block: per block, per entry (row-major), its monomials.
#[derive(Debug)]
pub struct SelfImage {
    /// `blocks[k][entry]`.
    pub blocks: Vec<Vec<Vec<Mono>>>,
    /// `s_k`: +1 where the fluid is above plane `k`, -1 where it is below.
    pub sides: Vec<f64>,
}

/// The closed form of the reflected self term of `blocks` for `g`, or `None` without
/// image structure or mirror planes, or for a radial potential ([`Green::radial`]: not
/// homogeneous).
pub fn expansion<G: Green>(
    g: &G,
    blocks: &[(Response, Moment)],
    basis: Basis,
    order: usize,
) -> Option<SelfImage> {
    let terms = g.image_terms()?;
    if crate::physics::green::is_radial(g) {
        return None;
    }
    let zeros = vec![0.0f64; g.params().len()];
    let bounds = g.boundaries(&zeros);
    let mirrors = g.mirrors(&zeros);
    let nplanes = mirrors.len();
    if terms.is_empty() || nplanes == 0 || bounds.len() != nplanes {
        return None;
    }
    // the fluid's side of each mirror: that of the boundary it is, in order
    let mut sides = Vec::new();
    for (m, b) in mirrors.iter().zip(&bounds) {
        let c: f64 = (0..3).map(|k| m.normal[k] * b.plane.normal[k]).sum();
        if (c.abs() - 1.0).abs() > 1e-15 {
            return None;
        }
        sides.push(c.signum());
    }
    let nweights = g.weights(&zeros).len();
    let degree_jet = order + g.image_extra_order() + 2;
    let one = Dd::new(1.0);
    let mut out: Vec<Vec<Vec<Mono>>> = blocks
        .iter()
        .map(|&(r, m)| {
            let n = operators::response_dim(r, basis) * operators::moment_dim(m, basis);
            vec![Vec::new(); n]
        })
        .collect();
    let mut largest: f64 = 0.0;
    for plane in 0..nplanes {
        for weight in 0..nweights {
            let sub: Vec<_> = terms
                .iter()
                .filter(|t| t.plane == plane && t.weight == weight)
                .copied()
                .collect();
            if sub.is_empty() {
                continue;
            }
            // unit distance on the fluid's side of a mirror through the origin
            let x = mirrors[plane].normal.map(|n| Dd::new(n * sides[plane]));
            let through_origin = mirrors
                .iter()
                .map(|m| Plane {
                    normal: m.normal,
                    offset: Dd::new(0.0),
                })
                .collect();
            let mut src = Structured::with_terms(
                sub,
                &x,
                &x,
                through_origin,
                vec![one; nweights],
                degree_jet,
                false,
                true,
            );
            for (k, &(r, m)) in blocks.iter().enumerate() {
                let blk = operators::exact_block(r, m, basis);
                let mut e = 0;
                for (row, norms) in blk.entries.iter().zip(&blk.norm) {
                    for (entry, &n) in row.iter().zip(norms) {
                        let mut groups: BTreeMap<(u8, u8), Vec<Term>> = BTreeMap::new();
                        for t in entry {
                            groups.entry((t.pa, t.pb)).or_default().push(*t);
                        }
                        for ((pa, pb), ts) in groups {
                            let mut f = crate::physics::farfield::dd_norm(n);
                            if pa == 1 {
                                f = f * crate::physics::operators::faxen_factor::<Dd>(blk.fa);
                            }
                            if pb == 1 {
                                f = f * crate::physics::operators::faxen_factor::<Dd>(blk.fb);
                            }
                            let c = (f * src.combine(&ts, &one, &one)).to_f64();
                            largest = largest.max(c.abs());
                            out[k][e].push(Mono {
                                plane,
                                weight,
                                pa,
                                pb,
                                c,
                            });
                        }
                        e += 1;
                    }
                }
            }
        }
    }
    for entry in out.iter_mut().flatten() {
        for mo in entry.iter() {
            assert!(
                mo.c.abs() <= ZERO * largest || mo.c.abs() >= SMALLEST * largest,
                "{}: self coefficient {:e} is neither round-off nor of the size of the \
                 largest, {largest:e}",
                g.name(),
                mo.c
            );
        }
        entry.retain(|mo| mo.c.abs() > ZERO * largest);
    }
    Some(SelfImage { blocks: out, sides })
}

/// The closed-form branch of a self kernel: the switch conditions `(lhs, rhs)` (the
/// branch is taken where every `lhs > rhs`: `s_k h_k > 0`) and every entry of every
/// block (row-major, units of `1/(8 pi eta)`, the isolated sphere included).
pub fn blocks<S: Scalar, G: Green>(
    si: &SelfImage,
    g: &G,
    blocks: &[(Response, Moment)],
    basis: Basis,
    x: &[S; 3],
    a: &S,
    params: &[S],
) -> (Vec<(S, S)>, Vec<Vec<S>>) {
    let planes = g.mirrors(params);
    let weights = g.weights(params);
    let mut conds = Vec::new();
    let mut inv = Vec::new();
    for (k, plane) in planes.into_iter().enumerate() {
        let h = plane.distance(x);
        let habs = if si.sides[k] > 0.0 { h } else { -h };
        conds.push((habs.clone(), S::cst(0.0)));
        inv.push(habs.recip());
    }
    let a2 = a.clone() * a.clone();
    // inv[k]^n, built on first use
    let mut powers: BTreeMap<(usize, i32), S> = BTreeMap::new();
    let mut pow = |k: usize, n: i32| -> S {
        if let Some(v) = powers.get(&(k, n)) {
            return v.clone();
        }
        let mut v = inv[k].clone();
        for _ in 1..n {
            v = v * inv[k].clone();
        }
        powers.insert((k, n), v.clone());
        v
    };
    let mut out = Vec::new();
    for (b, &(r, m)) in blocks.iter().enumerate() {
        let iso = isolated(r, m, basis, a);
        let d = degree(r, m);
        let nc = operators::moment_dim(m, basis);
        let mut vals = Vec::new();
        for (e, monos) in si.blocks[b].iter().enumerate() {
            // grouped by (weight, radius powers), then by plane: w (a^2)^p sum_k c h_k^e
            let mut groups: BTreeMap<(usize, u8), Option<S>> = BTreeMap::new();
            for mo in monos {
                let p = mo.pa + mo.pb;
                let n = -(d - 2 * p as i32);
                let v = S::cst(mo.c) * pow(mo.plane, n);
                let g = groups.entry((mo.weight, p)).or_insert(None);
                *g = Some(match g.take() {
                    None => v,
                    Some(acc) => acc + v,
                });
            }
            let mut acc = iso[e / nc][e % nc].clone();
            for ((w, p), v) in groups {
                let mut v = v.expect("non-empty group");
                for _ in 0..p {
                    v = a2.clone() * v;
                }
                if weights.len() > 1 || !is_one(&weights[w]) {
                    v = weights[w].clone() * v;
                }
                acc = acc + v;
            }
            vals.push(acc);
        }
        out.push(vals);
    }
    (conds, out)
}

fn is_one<S: Scalar>(s: &S) -> bool {
    // a weight folded to the constant 1 (the wall, the slit): its product is skipped
    (s.clone() - S::cst(1.0)).is_known_zero()
}
