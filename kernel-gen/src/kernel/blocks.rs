//! Every entry of a kernel's blocks, generic over the scalar: the derivative source of
//! the kernel's path, combined by the operators, normalised, scaled, plus the isolated
//! sphere for self kernels.

use super::spec::{Interaction, KernelSpec, Path};
use crate::number::scalar::Scalar;
use crate::physics::derivatives::{Form, GenericJets, Part, Structured};
use crate::physics::green::Green;
use crate::physics::operators::{self, apply, isolated};

/// The derivative source for a kernel: structured when the Green's function has image
/// structure (pair kernels only, for a radial potential), generic otherwise.
enum Source<S> {
    Structured(Structured<S>),
    Generic(GenericJets<S>),
}

impl<S: Scalar> Source<S> {
    #[allow(clippy::too_many_arguments)]
    fn new<G: Green>(
        g: &G,
        spec: &KernelSpec,
        xa: &[S; 3],
        xb: &[S; 3],
        p: &[S],
        order: usize,
        form: Form,
        scale: Option<&S>,
    ) -> Self {
        let pair = spec.interaction == Interaction::Pair;
        // a radial potential's self term has a free part, its reflected field at r = 0,
        // which the atoms about a unit vector do not reach
        let structured = pair || !crate::physics::green::is_radial(g);
        if g.image_terms().is_some() && spec.path != Path::Generic && structured {
            let explicit = spec.path != Path::StructuredNoExplicitHeight;
            let s = Structured::new(g, xa, xb, p, order, pair, explicit);
            let s = s.in_form(form);
            let s = match scale {
                Some(m) => s.scaled(m.clone()),
                None => s,
            };
            Source::Structured(if spec.path == Path::StructuredDirectSum {
                s.direct_sum()
            } else {
                s
            })
        } else {
            let part = if pair { Part::Full } else { Part::Reflected };
            Source::Generic(GenericJets::new(g, part, xa, xb, p, order))
        }
    }

    fn entry(&mut self, terms: &[operators::Term], aa2: &S, ab2: &S) -> S {
        match self {
            Source::Structured(s) => apply(terms, aa2, ab2, s),
            Source::Generic(s) => apply(terms, aa2, ab2, s),
        }
    }
}

/// Every entry of every block of `spec`, row-major, in units of `1/(8 pi eta)` (self
/// kernels include the isolated sphere), for any scalar: expression nodes for the
/// kernels, jets of expression nodes for their derivatives.
#[allow(clippy::too_many_arguments)]
pub(super) fn block_values<G: Green, S: Scalar>(
    g: &G,
    spec: &KernelSpec,
    xa: &[S; 3],
    xb: &[S; 3],
    aa: &S,
    ab: &S,
    params: &[S],
    order: usize,
    form: Form,
    scale: Option<&S>,
) -> Vec<Vec<S>> {
    let mut src = Source::new(g, spec, xa, xb, params, order, form, scale);
    // the structured derivatives carry the scale themselves (`Structured::scaled`)
    let outside = match (&src, scale) {
        (Source::Generic(_), Some(s)) => Some(s),
        _ => None,
    };
    let (aa2, ab2) = (aa.clone() * aa.clone(), ab.clone() * ab.clone());
    spec.blocks
        .iter()
        .map(|&(r, m)| {
            let blk = operators::exact_block(r, m, spec.basis);
            let iso = match spec.interaction {
                Interaction::SelfTerm => Some(isolated(r, m, spec.basis, aa)),
                Interaction::Pair => None,
            };
            // the Faxén factors multiply a^2 once per kernel (shared nodes)
            let (fa2, fb2) = (
                operators::faxen_factor::<S>(blk.fa) * aa2.clone(),
                operators::faxen_factor::<S>(blk.fb) * ab2.clone(),
            );
            let mut vals = Vec::new();
            for (row, entries) in blk.entries.iter().enumerate() {
                for (col, entry) in entries.iter().enumerate() {
                    let mut v = src.entry(entry, &fa2, &fb2);
                    let n = blk.norm[row][col];
                    if n != 1.0 {
                        v = S::cst(n) * v;
                    }
                    if let Some(s) = outside {
                        v = s.clone() * v;
                    }
                    vals.push(match (&iso, scale) {
                        (Some(iso), Some(s)) => s.clone() * iso[row][col].clone() + v,
                        (Some(iso), None) => iso[row][col].clone() + v,
                        (None, _) => v,
                    });
                }
            }
            vals
        })
        .collect()
}
