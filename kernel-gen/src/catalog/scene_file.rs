//! The kernels of one scene as one file.

use super::family::counts;
use super::{blocks_type, moments_label, GeneratedFile, Radii, Scene};
use crate::emit::{self, ident, Float, KernelFn};
use crate::kernel::{trace, Drift, Interaction, KernelSpec, Path, Traced};
use crate::physics::green::{self, Green, Visitor};
use crate::physics::operators::{Basis, Moment, Response};
use proc_macro2::TokenStream;
use quote::quote;

/// [`scene_file`] of the registered Green's function (a confinement or a building block)
/// the scene names, `None` if none has that name: the registry's visit made here, where
/// [`crate::catalog::generate`] instantiates the generator for every Green's function
/// with this crate's optimisation, not again in each caller.
pub fn scene_file_of(scene: &Scene, standalone: bool) -> Option<GeneratedFile> {
    struct One<'a> {
        scene: &'a Scene,
        standalone: bool,
        file: Option<GeneratedFile>,
    }
    impl Visitor for One<'_> {
        fn visit<G: Green>(&mut self, g: &G) {
            if g.name() == self.scene.confinement {
                self.file = Some(scene_file(g, self.scene, self.standalone));
            }
        }
    }
    let mut one = One {
        scene,
        standalone,
        file: None,
    };
    green::for_each(&mut one);
    green::for_each_building_block(&mut one);
    one.file
}

/// The kernels of one scene as one file (`scene_<name>.rs`). With `standalone`, the
/// return types are defined in the file (for `cargo xtask gen --scene FILE --out`),
/// otherwise they come from the kernels crate.
pub fn scene_file<G: Green>(g: &G, scene: &Scene, standalone: bool) -> GeneratedFile {
    let mut items = TokenStream::new();
    let mut op_counts = Vec::new();
    // (suffix, interaction, equal radii, fused product, drift)
    let mut kinds: Vec<(&str, Interaction, bool, bool, Option<Drift>)> = Vec::new();
    if scene.dense || scene.product {
        kinds.push(("self", Interaction::SelfTerm, false, false, None));
    }
    if scene.dense {
        if scene.radii == Radii::Unequal {
            kinds.push(("pair", Interaction::Pair, false, false, None));
        }
        kinds.push(("pair_equal", Interaction::Pair, true, false, None));
    }
    if scene.product {
        if scene.radii == Radii::Unequal {
            kinds.push(("pair_product", Interaction::Pair, false, true, None));
        }
        kinds.push(("pair_equal_product", Interaction::Pair, true, true, None));
    }
    if scene.drift {
        // a sphere and its own images: one radius
        let along = Some(Drift::Along);
        kinds.push(("self_along", Interaction::SelfTerm, true, false, along));
        let together = Some(Drift::Together);
        kinds.push(("pair_together", Interaction::Pair, true, false, together));
    }
    let ty = blocks_type(scene.moments);
    let n = scene.moments.per_particle();
    // the drift's rows: U (and Omega) over the force columns (UL for a pair's `b`)
    let drift_blocks: Vec<(Response, Moment)> = scene
        .moments
        .blocks()
        .into_iter()
        .filter(|&(r, m)| {
            matches!(
                (r, m),
                (Response::U, Moment::F) | (Response::Omega, Moment::F) | (Response::U, Moment::L)
            )
        })
        .collect();
    let drift_len = drift_blocks
        .iter()
        .filter(|&&(_, m)| m == Moment::F)
        .count()
        * 3;
    // (type name, its fields with their shapes), for standalone definitions
    type Fields = Vec<(String, Vec<usize>)>;
    let mut types: Vec<(String, Fields)> = Vec::new();
    for (suffix, interaction, equal, product, drift) in kinds {
        let spec = KernelSpec {
            interaction,
            basis: Basis::Orthonormal,
            equal_radii: equal,
            blocks: match drift {
                Some(_) => drift_blocks.clone(),
                None => scene.moments.blocks(),
            },
            path: Path::Structured,
            product,
            drift,
        };
        let traced: Traced = trace(g, &spec);
        let name = format!("{}_{suffix}", scene.name);
        let (ret, ctor) = match (product, drift, interaction) {
            (true, _, _) => (format!("Product<{n}>"), format!("Product::<{n}>")),
            (_, Some(_), Interaction::Pair) => (
                format!("Product<{drift_len}>"),
                format!("Product::<{drift_len}>"),
            ),
            (_, Some(_), Interaction::SelfTerm) => (
                format!("Drift<{drift_len}>"),
                format!("Drift::<{drift_len}>"),
            ),
            _ => (ty.to_string(), ty.to_string()),
        };
        let shape_fields = traced
            .outputs
            .iter()
            .map(|b| (b.name.clone(), b.shape.clone()))
            .collect();
        let tyname = match (product, drift, interaction) {
            (true, _, _) | (_, Some(_), Interaction::Pair) => "Product".to_string(),
            (_, Some(_), Interaction::SelfTerm) => "Drift".to_string(),
            _ => ty.to_string(),
        };
        if !types.iter().any(|(t, _)| *t == tyname) {
            types.push((tyname, shape_fields));
        }
        let what = match (product, drift) {
            (true, _) => format!(
                "the fused pair product a = M^{{ab}} vb, b = M^{{ba}} va, {} moments",
                moments_label(scene.moments)
            ),
            (_, Some(Drift::Together)) => "the derivative along a unit vector v of the column along v, both points moving together, a = [sum_jk v_j v_k d/dt M^ab_UF,ij(xa + t v, xb + t v) (and M_OmegaF)], b the same for M^ba (a sphere's drift from one of its own periodic images)".to_string(),
            (_, Some(_)) => "the derivative along a unit vector v of the column along v, the position moving, a = [sum_jk v_j v_k d/dx_k M_UF,ij (and M_OmegaF)]".to_string(),
            (false, None) => format!("the {} blocks", moments_label(scene.moments)),
        };
        let doc = vec![
            format!(
                "Scene `{}` ({}): {what}, {}.",
                scene.name,
                g.title(),
                suffix.replace('_', " ")
            ),
            String::new(),
            if scene.description.is_empty() {
                "Pruned to what the scene needs.".to_string()
            } else {
                scene.description.clone()
            },
            format!("Jets truncated at derivative order {} of G.", traced.order),
        ];
        op_counts.extend(counts(&name, &traced));
        let kf = KernelFn {
            name: name.clone(),
            doc,
            ret,
            ctor,
            traced: &traced,
            float: Float::F64,
        };
        items.extend(emit::function(&kf));
        // the lane twins of the unequal-radius product (the tiled products' kernel) and
        // blocks (the dense assembly's)
        if !equal && !standalone && drift.is_none() {
            let (f, n) = emit::lane_function(&kf);
            op_counts.push((format!("{name}_lanes (fma)"), n));
            items.extend(f);
        }
    }
    let header = if standalone {
        let defs: Vec<TokenStream> = types
            .iter()
            .map(|(t, fields)| {
                let (tname, generic) = if t == "Product" { (ident("Product"), quote!(<const K: usize>)) } else { (ident(t), quote!()) };
                let fs: Vec<TokenStream> = fields
                    .iter()
                    .map(|(f, shape)| {
                        let fi = ident(f);
                        let mut ty = quote!(f64);
                        for &d in shape.iter().rev() {
                            ty = if t == "Product" { quote!([#ty; K]) } else { quote!([#ty; #d]) };
                        }
                        let d = format!(" Block `{f}`, row-major.");
                        quote!(#[doc = #d] pub #fi: #ty)
                    })
                    .collect();
                let d = format!(" Output of the scene's kernels ({t}).");
                quote!(#[doc = #d] #[derive(Clone, Copy, Debug, PartialEq)] pub struct #tname #generic { #(#fs),* })
            })
            .collect();
        quote!(#(#defs)*)
    } else {
        let used: Vec<proc_macro2::Ident> = types.iter().map(|(t, _)| ident(t)).collect();
        quote!(use crate::blocks::{#(#used),*};)
    };
    let module_doc = vec![
        format!(
            "Kernels of scene `{}`: {}, {} moments, {} radii.",
            scene.name,
            g.title(),
            moments_label(scene.moments),
            match scene.radii {
                Radii::Equal => "equal",
                Radii::Unequal => "unequal",
            }
        ),
        String::new(),
        "Generated: see the header comment.".into(),
    ];
    GeneratedFile {
        name: format!("scene_{}.rs", scene.name),
        contents: emit::file(&module_doc, quote!(#header #items)),
        op_counts,
    }
}
