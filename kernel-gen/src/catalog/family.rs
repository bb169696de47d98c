//! The kernels of one Green's function (a family file), and their single-precision
//! twins.

use super::GeneratedFile;
use crate::emit::{self, ident, Float, KernelFn};
use crate::kernel::{trace, Drift, Interaction, KernelSpec, Path, Traced};
use crate::physics::green::Green;
use crate::physics::operators::{Basis, BLOCKS};
use proc_macro2::TokenStream;
use quote::quote;

/// One generated function per family: name suffix, what it computes, and a phrase for
/// its documentation.
pub struct Variant {
    /// Suffix of the function name (`wall_` + suffix).
    pub suffix: &'static str,
    /// What to trace.
    pub spec: KernelSpec,
    /// Documentation phrase.
    pub what: &'static str,
    /// Return type and its constructor path.
    pub ret: (&'static str, &'static str),
}

/// The functions generated for every family.
pub fn variants() -> Vec<Variant> {
    use crate::physics::operators::{Moment, Response};
    let spec = |interaction, equal_radii| KernelSpec {
        interaction,
        basis: Basis::Orthonormal,
        equal_radii,
        blocks: BLOCKS.to_vec(),
        path: Path::Structured,
        product: false,
        drift: None,
    };
    let drift = |interaction, drift, blocks: Vec<(Response, Moment)>| KernelSpec {
        blocks,
        drift: Some(drift),
        ..spec(interaction, false)
    };
    let (uf, ul, of) = (
        (Response::U, Moment::F),
        (Response::U, Moment::L),
        (Response::Omega, Moment::F),
    );
    vec![
        Variant {
            suffix: "self",
            spec: spec(Interaction::SelfTerm, false),
            what: "self",
            ret: ("Grand", "Grand"),
        },
        Variant {
            suffix: "pair",
            spec: spec(Interaction::Pair, false),
            what: "pair",
            ret: ("Grand", "Grand"),
        },
        Variant {
            suffix: "pair_equal",
            spec: spec(Interaction::Pair, true),
            what: "pair, equal radii",
            ret: ("Grand", "Grand"),
        },
        Variant {
            suffix: "self_divergence",
            spec: drift(Interaction::SelfTerm, Drift::Divergence, vec![uf, of]),
            what: "self, divergence over the position of the particle (Brownian drift): a = [sum_j d/dx_j M_UF,ij, sum_j d/dx_j M_OmegaF,ij]",
            ret: ("Drift<6>", "Drift::<6>"),
        },
        Variant {
            suffix: "pair_divergence",
            spec: drift(Interaction::Pair, Drift::Divergence, vec![uf, ul, of]),
            what: "pair, divergence over the source position (Brownian drift): a = [sum_j d/dxb_j M^ab_UF,ij, sum_j d/dxb_j M^ab_OmegaF,ij], b the same for M^ba over xa",
            ret: ("Product<6>", "Product::<6>"),
        },
        Variant {
            suffix: "self_along",
            spec: drift(Interaction::SelfTerm, Drift::Along, vec![uf, of]),
            what: "self, derivative along a unit vector v of the column along v, the position of the particle moving (the drift of a sphere held on a plane of normal v): a = [sum_jk v_j v_k d/dx_k M_UF,ij, the same for M_OmegaF]",
            ret: ("Drift<6>", "Drift::<6>"),
        },
        Variant {
            suffix: "pair_along",
            spec: drift(Interaction::Pair, Drift::Along, vec![uf, ul, of]),
            what: "pair, derivative along a unit vector v of the column along v, the source position moving (the drift of a sphere held on a plane of normal v): a = [sum_jk v_j v_k d/dxb_k M^ab_UF,ij, the same for M^ab_OmegaF], b the same for M^ba over xa",
            ret: ("Product<6>", "Product::<6>"),
        },
    ]
}

/// The operation counts of a traced kernel for the report: the direct sum (with the
/// switch condition, where there is one) and the lateral far-field branch.
pub(super) fn counts(name: &str, traced: &Traced) -> Vec<(String, usize)> {
    let mut near = traced.output_ids();
    let mut far = traced.far_ids();
    if let Some(f) = &traced.far {
        near.extend(f.condition_ids());
        far.extend(f.condition_ids());
    }
    let mut v = vec![(name.to_string(), traced.graph.op_count(&near).total())];
    if let Some(f) = &traced.far {
        v.push((
            format!("{name} ({})", f.label),
            traced.graph.op_count(&far).total(),
        ));
    }
    v
}

/// Generate the kernels of one Green's function as one file.
pub fn family<G: Green>(g: &G) -> GeneratedFile {
    family_and_single(g).0
}

/// The family file, and the single-precision (`f32`) self and pair kernels of the
/// family (items of `single.rs`, [`SINGLE`]), emitted from the same traces.
pub(super) fn family_and_single<G: Green>(g: &G) -> (GeneratedFile, TokenStream) {
    family_file(g.name(), g.title(), &|spec| trace(g, spec))
}

/// The family file and single-precision kernels of the Green's function called `name`
/// and titled `title`, whose kernels `trace` traces (not generic: the emission is
/// compiled once for every Green's function).
pub(super) fn family_file(
    name: &str,
    title: &str,
    trace: &dyn Fn(&KernelSpec) -> Traced,
) -> (GeneratedFile, TokenStream) {
    let family = name;
    let mut items = TokenStream::new();
    let mut single = TokenStream::new();
    let mut op_counts = Vec::new();
    for v in variants() {
        let traced = trace(&v.spec);
        let name = format!("{}_{}", family, v.suffix);
        let what = v.what;
        let eq = match v.spec.interaction {
            Interaction::SelfTerm => "Eq. 17: the isolated sphere plus the reflected field only",
            Interaction::Pair => "Eq. 16: Faxén laws (Eqs. 12-15) applied to the multipole expansion (Eq. 8) of G = J + J^w",
        };
        let basis_doc = match v.spec.basis {
            Basis::Orthonormal => {
                "Strain and stresslet in the 5-component orthonormal basis (kernels::STRAIN_BASIS)."
            }
            Basis::Cartesian => {
                "Strain and stresslet as Cartesian index pairs, as in the paper's appendices."
            }
        };
        let doc = vec![
            format!("Grand mobility blocks, {what}: {}.", title),
            String::new(),
            format!("{eq}. Dimensional; blocks map the force, torque and stresslet exerted on the fluid to (U, Omega, -E_inf)."),
            basis_doc.to_string(),
        ];
        op_counts.extend(counts(&name, &traced));
        if matches!(v.suffix, "self" | "pair") {
            let mut doc = doc.clone();
            doc[0] = format!("Single precision: {}", doc[0]);
            single.extend(emit::function(&KernelFn {
                name: name.clone(),
                doc,
                ret: "Grand32".into(),
                ctor: "Grand32".into(),
                traced: &traced,
                float: Float::F32,
            }));
        }
        let kf = KernelFn {
            name: name.clone(),
            doc,
            ret: v.ret.0.into(),
            ctor: v.ret.1.into(),
            traced: &traced,
            float: Float::F64,
        };
        items.extend(emit::function(&kf));
        // the lane twins of the FTS pair blocks (the tiled FTS product and dense
        // assembly) and of the pair divergence (the tiled Brownian drift)
        if matches!(v.suffix, "pair" | "pair_divergence") {
            let (f, n) = emit::lane_function(&kf);
            op_counts.push((format!("{name}_lanes (fma)"), n));
            items.extend(f);
        }
    }
    let module_doc = vec![
        format!("Kernels for {}.", title),
        String::new(),
        "Generated: see the header comment.".into(),
    ];
    let items = quote! {
        use crate::blocks::{Drift, Grand, Product};
        #items
    };
    let file = GeneratedFile {
        name: format!("{}.rs", family),
        contents: emit::file(&module_doc, items),
        op_counts,
    };
    (file, single)
}

/// Name of the file of the single-precision dispatch, which the `kernels` crate compiles
/// only with its cargo feature `f32` (as `kernels::single`).
pub const SINGLE: &str = "single.rs";

/// Name of the file of single-precision kernels, compiled in the crate `kernel-bodies`
/// with its feature `f32` (as `kernel_bodies::single_kernels`, re-exported by
/// [`SINGLE`]).
pub const SINGLE_KERNELS: &str = "single_kernels.rs";

/// [`SINGLE`] (the dispatch `entry` on the confinement, and the kernels re-exported)
/// and [`SINGLE_KERNELS`]: the FTS self and pair kernels of every family in `f32`
/// (`items`: the same traces as the `f64` kernels, emitted with [`Float::F32`]),
/// returning `Grand32`.
pub(super) fn single_files(entry: TokenStream, items: Vec<TokenStream>) -> [GeneratedFile; 2] {
    let fields: Vec<TokenStream> = BLOCKS
        .iter()
        .map(|&(r, m)| {
            let f = ident(&crate::physics::operators::block_name(r, m));
            let (rows, cols) = (
                crate::physics::operators::response_dim(r, Basis::Orthonormal),
                crate::physics::operators::moment_dim(m, Basis::Orthonormal),
            );
            let d = format!(" Block `{}`, {rows}x{cols}, row-major.", f);
            quote!(#[doc = #d] pub #f: [[f32; #cols]; #rows])
        })
        .collect();
    let module_doc = vec![
        "Single-precision (f32) FTS self and pair kernels of every family, for accuracy and speed comparisons (`cargo xtask report`).".to_string(),
        String::new(),
        "Compiled only with the cargo feature `f32` of the kernel-bodies crate. Regenerate with `cargo xtask gen`.".to_string(),
    ];
    let dispatch_doc = vec![
        "Single-precision (f32) FTS self and pair kernels of every family (`kernel_bodies::single_kernels`), dispatched on the confinement.".to_string(),
        String::new(),
        "Compiled only with the cargo feature `f32` of the kernels crate. Regenerate with `cargo xtask gen`.".to_string(),
    ];
    let names: Vec<proc_macro2::Ident> = BLOCKS
        .iter()
        .map(|&(r, m)| ident(&crate::physics::operators::block_name(r, m)))
        .collect();
    let body = quote! {
        /// The nine blocks of [`crate::blocks::Grand`] in single precision (same layout and basis).
        #[derive(Clone, Copy, Debug, PartialEq, Default)]
        pub struct Grand32 { #(#fields),* }
        impl Grand32 {
            /// The fields flattened in their order, each row-major (as [`crate::blocks::Grand::flat`]).
            pub fn flat(&self) -> [f32; 121] {
                let v: Vec<f32> = [#(self.#names.iter().flatten().copied().collect::<Vec<f32>>()),*].concat();
                std::array::from_fn(|i| v[i])
            }
            /// The inverse of [`Grand32::flat`].
            pub fn from_flat(m: &[f32; 121]) -> Grand32 {
                let mut at = 0;
                let mut take = |out: &mut [f32]| {
                    out.copy_from_slice(&m[at..at + out.len()]);
                    at += out.len();
                };
                let mut g = Grand32::default();
                #(g.#names.iter_mut().for_each(|row| take(row));)*
                g
            }
        }
        #(#items)*
    };
    [
        GeneratedFile {
            name: SINGLE.into(),
            contents: emit::file(
                &dispatch_doc,
                quote!(pub use kernel_bodies::single_kernels::*; #entry),
            ),
            op_counts: Vec::new(),
        },
        GeneratedFile {
            name: SINGLE_KERNELS.into(),
            contents: emit::file(&module_doc, body),
            op_counts: Vec::new(),
        },
    ]
}
