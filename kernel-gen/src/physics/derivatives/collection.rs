//! How the structured path turns atoms into arithmetic ([`Collection`]): one by one,
//! or collected into polynomials in the unit vector evaluated by Horner's rule.

use super::atoms::{Atom, Factor, Potential};
use super::structured::Groups;
use super::{Collection, Structured};
use crate::number::dd::Dd;
use crate::number::poly::{Poly, VARS};
use crate::number::scalar::Scalar;
use std::collections::{BTreeMap, HashMap};

impl<S: Scalar> Structured<S> {
    /// `sum_atoms coef * value`: atoms of one centre, potential and order share the
    /// factor `|R|^(p - n)`, which multiplies their sum once. Deterministic order.
    pub(super) fn linear(&mut self, atoms: &BTreeMap<Atom, f64>) -> Option<S> {
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
            let sum = if let (Potential::Radial(m), true) = (pot, self.collect != Collection::Atoms)
            {
                // one polynomial per radial coefficient
                let atoms: Vec<([u8; 3], f64)> = list.iter().map(|(a, c)| (a.nu, *c)).collect();
                self.radial_value(centre, m, &atoms)
            } else if self.collect != Collection::Atoms && self.difference_plane(centre).is_none() {
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
            let p = pot.dimension();
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
    pub(super) fn evaluate(&mut self, groups: &Groups, aa2: &S, ab2: &S) -> S {
        // the radius monomials of each distinct (factor, atoms), in the order of the
        // first group that has them
        type Atoms = Vec<(Atom, u64)>;
        let mut order: Vec<(Factor, Atoms)> = Vec::new();
        let mut monomials: HashMap<(Factor, Atoms), Vec<(u8, u8)>> = HashMap::new();
        for (&(pa, pb, f), atoms) in groups {
            let key: Atoms = atoms
                .iter()
                .filter(|&(_, &c)| c != 0.0)
                .map(|(&a, &c)| (a, c.to_bits()))
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

    /// [`Collection::Entries`]: every atom of one entry at one centre (and weight) in
    /// one polynomial `sum c e^m t^q alpha^pa beta^pb` with `t = h |R|^-1`, `alpha =
    /// a_a^2 |R|^-2`, `beta = a_b^2 |R|^-2`, times `|R|^-k` (one `k` per entry by
    /// dimension; kept apart should another occur); the atoms of difference centres go
    /// through [`Structured::evaluate`], and so, near a cancelling image, do the
    /// free-space terms with Faxen factors that [`Differences::Leading`](super::Differences::Leading) leaves at `r`,
    /// whose `alpha L + beta L` is then taken once (wall FTS pair lanes 1534 -> 1459).
    pub(super) fn evaluate_entries(&mut self, groups: &Groups, aa2: &S, ab2: &S) -> S {
        // per centre, weight and power of `1/|R|`: one polynomial, or for a radial
        // potential one per radial coefficient `b_{m,j}` (its key)
        type Coefficient = Option<(u8, usize)>;
        let mut polys: BTreeMap<(usize, Option<usize>, i32), BTreeMap<Coefficient, Poly>> =
            BTreeMap::new();
        let mut rest = Groups::new();
        for (&(pa, pb, f), atoms) in groups {
            for (&a, &c) in atoms {
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
                let k = n - a.pot.dimension() - 2 * (pa as i32 + pb as i32) - q as i32;
                let mut shift = [0u8; VARS];
                shift[3] = q;
                shift[4] = pa;
                shift[5] = pb;
                let entry = polys.entry((a.centre, weight, k)).or_default();
                if let Potential::Radial(m) = a.pot {
                    let powers = self.u_powers();
                    for (j, power) in powers.iter().enumerate() {
                        let d = power.derivative(&a.nu);
                        if !d.is_empty() {
                            entry.entry(Some((m, j))).or_default().add_shifted(
                                &d,
                                Dd::new(c),
                                shift,
                            );
                        }
                    }
                    continue;
                }
                let d = self.poly_jet(a.pot).derivative(&a.nu);
                entry
                    .entry(None)
                    .or_default()
                    .add_shifted(&d, Dd::new(c), shift);
            }
        }
        let mut out: Option<S> = None;
        for ((centre, weight, k), parts) in polys {
            if parts.values().all(Poly::is_empty) {
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
            let mut sum: Option<S> = None;
            for (coefficient, p) in parts {
                if p.is_empty() {
                    continue;
                }
                let p = if self.collect == Collection::EntriesOnSphere {
                    p.on_unit_sphere(std::array::from_fn(|k| vars[k].is_known_zero()))
                } else {
                    p
                };
                let mut v = p.eval_all(&vars);
                if v.is_known_zero() {
                    continue;
                }
                if let Some((m, j)) = coefficient {
                    v = self.radial[&(centre, m)][j].clone() * v;
                }
                sum = Some(match sum {
                    None => v,
                    Some(s) => s + v,
                });
            }
            let Some(mut v) = sum else { continue };
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
            let r = self.evaluate(&rest, aa2, ab2);
            out = Some(match out {
                None => r,
                Some(o) => o + r,
            });
        }
        out.unwrap_or_else(|| S::cst(0.0))
    }
}
