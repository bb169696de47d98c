//! The overlap correction kernels (`overlap.rs`): the RPY form of two overlapping
//! spheres minus the far RPY form ([`crate::physics::overlap`]), F and FT blocks, traced
//! once and emitted as scalar kernels. The solver adds the correction to the pair
//! kernels of any confinement for the overlapping pairs only: the far form is the
//! free-space part of every pair kernel, so the sum is the overlap form plus the images.

use super::GeneratedFile;
use crate::emit::{self, Float, KernelFn};
use crate::graph::{Ex, Trace};
use crate::kernel::{Arg, ArgKind, BlockOut, FarBranch, Traced};
use crate::number::scalar::Scalar;
use crate::physics::operators::{Moment, Response};
use crate::physics::overlap::{far, nested, overlapping, Blocks, Coefficients};
use quote::quote;

/// The blocks of `near - far`, entry by entry, scaled.
fn difference(near: &Blocks<Ex>, far: &Blocks<Ex>, scale: Ex) -> [Vec<Ex>; 4] {
    let d = |n: &[[Ex; 3]; 3], f: &[[Ex; 3]; 3]| -> Vec<Ex> {
        (0..9)
            .map(|k| scale * (n[k / 3][k % 3] - f[k / 3][k % 3]))
            .collect()
    };
    [
        d(&near.uf, &far.uf),
        d(&near.ul, &far.ul),
        d(&near.of, &far.of),
        d(&near.ol, &far.ol),
    ]
}

/// `if l > r { p } else { q }`, coefficient by coefficient.
fn select(l: Ex, r: Ex, p: Coefficients<Ex>, q: Coefficients<Ex>) -> Coefficients<Ex> {
    let s = |p: Ex, q: Ex| Ex::select_gt(l, r, p, q);
    Coefficients {
        f1: s(p.f1, q.f1),
        f2: s(p.f2, q.f2),
        k_ul: s(p.k_ul, q.k_ul),
        k_of: s(p.k_of, q.k_of),
        g1: s(p.g1, q.g1),
        g2: s(p.g2, q.g2),
    }
}

/// The correction kernel of the first `blocks` (1: F, 4: FT) of `[UF, UL, OmegaF,
/// OmegaL]`.
fn traced(blocks: usize) -> Traced {
    let t = Trace::begin();
    let mut args = Vec::new();
    let mut point = |name: &str, doc: &str| -> [Ex; 3] {
        args.push(Arg {
            name: name.into(),
            kind: ArgKind::Point,
            doc: doc.into(),
        });
        std::array::from_fn(|k| t.input(&format!("{name}[{k}]")))
    };
    let xa = point(
        "xa",
        "centre of particle a (the field particle), [x1, x2, x3]",
    );
    let xb = point("xb", "centre of particle b (the source particle)");
    let mut scalar = |name: &str, doc: &str| -> Ex {
        args.push(Arg {
            name: name.into(),
            kind: ArgKind::Scalar,
            doc: doc.into(),
        });
        t.input(name)
    };
    let aa = scalar("aa", "radius of particle a");
    let ab = scalar("ab", "radius of particle b");
    let eta = scalar("eta", "viscosity of the fluid");
    let r: [Ex; 3] = std::array::from_fn(|k| xa[k] - xb[k]);
    let r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    let len = r2.sqrt();
    let scale = Ex::cst(1.0 / (8.0 * std::f64::consts::PI)) / eta;
    let far = far(&len, &aa, &ab).blocks(&r, &len);
    let near = overlapping(&len, &aa, &ab).blocks(&r, &len);
    let inside = select(aa, ab, nested(&len, &aa, true), nested(&len, &ab, false)).blocks(&r, &len);
    let names = [
        (Response::U, Moment::F, "uf"),
        (Response::U, Moment::L, "ul"),
        (Response::Omega, Moment::F, "of"),
        (Response::Omega, Moment::L, "ol"),
    ];
    let outputs = |vals: [Vec<Ex>; 4]| -> Vec<BlockOut> {
        names
            .iter()
            .zip(vals)
            .take(blocks)
            .map(|(&(resp, m, name), v)| BlockOut {
                name: name.into(),
                block: Some((resp, m)),
                shape: vec![3, 3],
                ids: v.into_iter().map(|e| e.0).collect(),
            })
            .collect()
    };
    let main = outputs(difference(&near, &far, scale));
    let d = aa - ab;
    let branch = FarBranch {
        conds: vec![((d * d).0, r2.0)],
        outputs: outputs(difference(&inside, &far, scale)),
        doc: "Nested spheres (taken where (aa - ab)^2 > r^2: the smaller inside the larger)".into(),
        label: "nested",
    };
    let graph = t.finish();
    Traced {
        graph,
        args,
        outputs: main,
        order: 0,
        far: Some(branch),
        swap: None,
    }
}

/// The file `overlap.rs`: `overlap_f` and `overlap_ft`.
pub(super) fn overlap_file() -> GeneratedFile {
    let mut items = Vec::new();
    let mut op_counts = Vec::new();
    for (name, blocks, ret) in [("overlap_f", 1, "BlocksF"), ("overlap_ft", 4, "BlocksFT")] {
        let traced = traced(blocks);
        op_counts.extend(super::family::counts(name, &traced));
        let doc = vec![
            format!(
                "The RPY overlap correction, {} blocks: the Rotne-Prager-Yamakawa form of \
                 two overlapping spheres minus the far form (the free-space pair kernel), \
                 kernel_gen::physics::overlap.",
                if blocks == 1 { "F" } else { "FT" }
            ),
            String::new(),
            "For overlapping spheres only (r < aa + ab; it vanishes at contact): added to \
             a pair kernel of any confinement, it replaces the pair's free-space part by \
             the overlap form and keeps its image terms."
                .into(),
        ];
        items.push(emit::function(&KernelFn {
            name: name.into(),
            doc,
            ret: ret.into(),
            ctor: ret.into(),
            traced: &traced,
            float: Float::F64,
        }));
    }
    let module_doc = vec![
        "The RPY overlap corrections: overlap form minus far form of two spheres, F and FT."
            .to_string(),
        String::new(),
        "Generated: see the header comment.".to_string(),
    ];
    GeneratedFile {
        name: "overlap.rs".into(),
        contents: emit::file(
            &module_doc,
            quote!(use crate::blocks::{BlocksF, BlocksFT}; #(#items)*),
        ),
        op_counts,
    }
}
