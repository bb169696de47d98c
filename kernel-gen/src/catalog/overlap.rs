//! The overlap correction kernels (`overlap.rs`): the RPY form of two overlapping
//! spheres minus the far RPY form ([`crate::physics::overlap`]), F and FT blocks, traced
//! once and emitted as scalar kernels. The solver adds the correction to the pair
//! kernels of any confinement for the overlapping pairs only: the far form is the
//! free-space part of every pair kernel, so the sum is the overlap form plus the images.

use super::GeneratedFile;
use crate::emit::{self, Float, KernelFn};
use crate::graph::{Ex, Trace};
use crate::kernel::{Arg, ArgKind, BlockOut, FarBranch, Traced};
use crate::number::jet::{Jet, Layout};
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

/// The arguments of a correction kernel: `xa`, `xb`, `aa`, `ab`, `eta`, and with
/// `along` the direction `v`.
struct Inputs {
    xa: [Ex; 3],
    xb: [Ex; 3],
    aa: Ex,
    ab: Ex,
    eta: Ex,
    v: Option<[Ex; 3]>,
}

fn inputs(t: &Trace, args: &mut Vec<Arg>, along: bool) -> Inputs {
    let mut arg = |name: &str, kind: ArgKind, doc: &str| {
        args.push(Arg {
            name: name.into(),
            kind,
            doc: doc.into(),
        })
    };
    let point =
        |name: &str| -> [Ex; 3] { std::array::from_fn(|k| t.input(&format!("{name}[{k}]"))) };
    arg(
        "xa",
        ArgKind::Point,
        "centre of particle a (the field particle), [x1, x2, x3]",
    );
    let xa = point("xa");
    arg(
        "xb",
        ArgKind::Point,
        "centre of particle b (the source particle)",
    );
    let xb = point("xb");
    arg("aa", ArgKind::Scalar, "radius of particle a");
    let aa = t.input("aa");
    arg("ab", ArgKind::Scalar, "radius of particle b");
    let ab = t.input("ab");
    arg("eta", ArgKind::Scalar, "viscosity of the fluid");
    let eta = t.input("eta");
    let v = along.then(|| {
        arg(
            "v",
            ArgKind::Point,
            "the direction of the derivative, a unit vector",
        );
        point("v")
    });
    Inputs {
        xa,
        xb,
        aa,
        ab,
        eta,
        v,
    }
}

/// The correction kernel of the first `blocks` (1: F, 4: FT) of `[UF, UL, OmegaF,
/// OmegaL]`.
fn traced(blocks: usize) -> Traced {
    let t = Trace::begin();
    let mut args = Vec::new();
    let Inputs {
        xa,
        xb,
        aa,
        ab,
        eta,
        ..
    } = inputs(&t, &mut args, false);
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

/// The derivative of the FT correction along a unit vector `v` of its column along `v`,
/// the source moving (`Drift::Along` of [`crate::kernel::Drift`], for the overlapping
/// pairs of spheres held on a boundary): `a_i = sum_j v_j d/dt C_ij(xa, xb + t v)` over
/// the force columns, rows `U` then `Omega`, by the overlap forms evaluated on jets of
/// degree 1 in `t`.
fn traced_along() -> Traced {
    let t = Trace::begin();
    let mut args = Vec::new();
    let Inputs {
        xa,
        xb,
        aa,
        ab,
        eta,
        v,
    } = inputs(&t, &mut args, true);
    let v = v.expect("declared");
    let l = Layout::get(1, 1);
    let c = |e: &Ex| Jet::constant(*e);
    let tv = Jet::variable(&l, 0, Ex::cst(0.0));
    // r = xa - (xb + t v)
    let r: [Jet<Ex>; 3] = std::array::from_fn(|k| c(&(xa[k] - xb[k])) - c(&v[k]) * tv.clone());
    let r2 =
        r[0].clone() * r[0].clone() + r[1].clone() * r[1].clone() + r[2].clone() * r[2].clone();
    let len = r2.sqrt();
    let (ja, jb) = (c(&aa), c(&ab));
    let scale = Ex::cst(1.0 / (8.0 * std::f64::consts::PI)) / eta;
    // sum_j v_j d/dt of the force columns of a block, rows U then Omega
    let along = |b: &Blocks<Jet<Ex>>| -> Vec<Ex> {
        let rows = |m: &[[Jet<Ex>; 3]; 3]| -> Vec<Ex> {
            (0..3)
                .map(|i| {
                    (0..3)
                        .map(|j| v[j] * m[i][j].derivative(&[1]))
                        .fold(Ex::cst(0.0), |acc, e| acc + e)
                })
                .collect()
        };
        let mut a = rows(&b.uf);
        a.extend(rows(&b.of));
        a
    };
    let far = along(&far(&len, &ja, &jb).blocks(&r, &len));
    let near = along(&overlapping(&len, &ja, &jb).blocks(&r, &len));
    let in_a = along(&nested(&len, &ja, true).blocks(&r, &len));
    let in_b = along(&nested(&len, &jb, false).blocks(&r, &len));
    let out = |vals: Vec<Ex>| -> Vec<BlockOut> {
        vec![BlockOut {
            name: "a".into(),
            block: None,
            shape: vec![vals.len()],
            ids: vals.into_iter().map(|e| e.0).collect(),
        }]
    };
    let main: Vec<Ex> = near
        .iter()
        .zip(&far)
        .map(|(&n, &f)| scale * (n - f))
        .collect();
    let inside: Vec<Ex> = (0..6)
        .map(|k| scale * (Ex::select_gt(aa, ab, in_a[k], in_b[k]) - far[k]))
        .collect();
    let d = aa - ab;
    let branch = FarBranch {
        conds: vec![((d * d).0, (r2.value()).0)],
        outputs: out(inside),
        doc: "Nested spheres (taken where (aa - ab)^2 > r^2: the smaller inside the larger)".into(),
        label: "nested",
    };
    let graph = t.finish();
    Traced {
        graph,
        args,
        outputs: out(main),
        order: 0,
        far: Some(branch),
        swap: None,
    }
}

/// The file `overlap.rs`: `overlap_f`, `overlap_ft` and `overlap_along`.
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
    let traced = traced_along();
    op_counts.extend(super::family::counts("overlap_along", &traced));
    items.push(emit::function(&KernelFn {
        name: "overlap_along".into(),
        doc: vec![
            "The derivative of the FT RPY overlap correction along a unit vector `v` of its \
             column along `v`, the source moving: `a = sum_jk v_j v_k d/dxb_k C_ij`, rows U \
             then Omega, force columns (kernel_gen::kernel::Drift::Along)."
                .into(),
            String::new(),
            "For overlapping spheres only (r < aa + ab), as the correction itself.".into(),
        ],
        ret: "Drift<6>".into(),
        ctor: "Drift::<6>".into(),
        traced: &traced,
        float: Float::F64,
    }));
    let module_doc = vec![
        "The RPY overlap corrections: overlap form minus far form of two spheres, F and FT, and the derivative along a direction."
            .to_string(),
        String::new(),
        "Generated: see the header comment.".to_string(),
    ];
    GeneratedFile {
        name: "overlap.rs".into(),
        contents: emit::file(
            &module_doc,
            quote!(use crate::blocks::{BlocksF, BlocksFT, Drift}; #(#items)*),
        ),
        op_counts,
    }
}
