//! The catalogue of generated kernels. For every registered Green's function: the self
//! and pair kernels of all nine blocks (a family file). For every scene (`scenes/`):
//! only the blocks its truncation needs, and, if asked, the fused pair products. In
//! `mod.rs`: the `Confinement` enum and the entry points that dispatch on it, using a
//! scene's kernels where one exists and the family's otherwise. In `single.rs`
//! ([`SINGLE`]): the FTS self and pair kernels of every family in single precision, behind
//! the `kernels` crate's feature `f32`. [`generate`] returns every file; `cargo xtask gen`
//! writes them, `--check` compares.

use crate::emit::{self, Float, KernelFn};
use crate::green::{self, Green, Visitor};
use crate::operators::{Basis, BLOCKS};
use crate::scene::{trace, Interaction, KernelSpec, Moments, Path, Radii, Scene, Traced};
use proc_macro2::TokenStream;
use quote::quote;

/// One generated file: path relative to `kernels/src/generated/`, and contents.
pub struct GeneratedFile {
    /// File name, e.g. `wall.rs`.
    pub name: String,
    /// Contents.
    pub contents: String,
    /// Per-function operation counts, for the report: (function, total flops).
    pub op_counts: Vec<(String, usize)>,
}

struct Family {
    name: &'static str,
    title: &'static str,
    params: &'static [&'static str],
    /// The dimension of each parameter.
    dimensions: Vec<green::Dimension>,
    /// `(height expression, fluid above)` of each boundary plane.
    boundaries: Vec<(TokenStream, bool)>,
    /// Whether its pair kernels exchange the particles' roles by height
    /// ([`crate::scene::Swap`], where the Green's function has a cancelling image).
    exchanges: bool,
    file: GeneratedFile,
    /// Its single-precision self and pair kernels (items of [`SINGLE`]).
    single: TokenStream,
    /// Scenes of this confinement that serve the dispatch: `(moments, scene name)` of
    /// those with unequal radii and both outputs.
    serving: Vec<(Moments, String)>,
    scene_files: Vec<GeneratedFile>,
}

fn camel(snake: &str) -> String {
    snake
        .split('_')
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map(|f| f.to_ascii_uppercase().to_string() + c.as_str())
                .unwrap_or_default()
        })
        .collect()
}

fn ident(s: &str) -> proc_macro2::Ident {
    proc_macro2::Ident::new(s, proc_macro2::Span::call_site())
}

/// The `Confinement` enum, one variant per family with its run-time parameters as
/// fields, and the dispatching entry points `pair`, `pair_equal`, `self_mobility`.
fn dispatch(families: &[Family]) -> TokenStream {
    let mut variants = Vec::new();
    let mut names = Vec::new();
    let mut name_arms = Vec::new();
    let mut from_arms = Vec::new();
    let mut param_arms = Vec::new();
    let mut bound_arms = Vec::new();
    let mut unit_arms = Vec::new();
    let mut pair_arms = Vec::new();
    let mut equal_arms = Vec::new();
    let mut self_arms = Vec::new();
    let mut div_pair_arms = Vec::new();
    let mut div_lane_arms = Vec::new();
    let mut div_ordered_arms = Vec::new();
    let mut pair_lane_arms = Vec::new();
    let mut exchange_arms = Vec::new();
    let mut div_self_arms = Vec::new();
    let mut truncated: Vec<Vec<TokenStream>> = Vec::new();
    for f in families {
        let v = ident(&camel(f.name));
        let m = ident(f.name);
        let name = f.name;
        let doc = format!(" {}", f.title);
        let fields: Vec<proc_macro2::Ident> = f.params.iter().map(|p| ident(p)).collect();
        let field_docs: Vec<String> = f
            .params
            .iter()
            .map(|p| format!(" {}", green::param_doc(p)))
            .collect();
        let idx: Vec<usize> = (0..f.params.len()).collect();
        let nparams = f.params.len();
        let (fpair, fequal, fself) = (
            ident(&format!("{}_pair", f.name)),
            ident(&format!("{}_pair_equal", f.name)),
            ident(&format!("{}_self", f.name)),
        );
        let pname: Vec<&str> = f.params.to_vec();
        let bounds: Vec<TokenStream> = f
            .boundaries
            .iter()
            .map(|(h, above)| quote!((#h, #above)))
            .collect();
        if fields.is_empty() {
            variants.push(quote!(#[doc = #doc] #v));
            name_arms.push(quote!(Confinement::#v => #name));
            from_arms.push(quote!(#name if params.is_empty() => Some(Confinement::#v)));
            param_arms.push(quote!(Confinement::#v => vec![]));
            bound_arms.push(quote!(Confinement::#v => vec![#(#bounds),*]));
            unit_arms.push(quote!(Confinement::#v => Confinement::#v));
            pair_arms.push(quote!(Confinement::#v => #m::#fpair(xa, xb, aa, ab, eta)));
            equal_arms.push(quote!(Confinement::#v => #m::#fequal(xa, xb, a, eta)));
            self_arms.push(quote!(Confinement::#v => #m::#fself(x, a, eta)));
        } else {
            variants.push(quote!(#[doc = #doc] #v { #(#[doc = #field_docs] #fields: f64),* }));
            name_arms.push(quote!(Confinement::#v { .. } => #name));
            from_arms.push(quote!(#name if params.len() == #nparams => Some(Confinement::#v { #(#fields: params[#idx]),* })));
            param_arms
                .push(quote!(Confinement::#v { #(#fields),* } => vec![#((#pname, #fields)),*]));
            bound_arms.push(quote!(Confinement::#v { #(#fields),* } => {
                let _ = (#(#fields,)*);
                vec![#(#bounds),*]
            }));
            let scaled: Vec<TokenStream> = fields
                .iter()
                .zip(&f.dimensions)
                .map(|(p, d)| match d {
                    green::Dimension::Height => quote!(#p: (#p - origin) / unit),
                    green::Dimension::Length => quote!(#p: #p / unit),
                    green::Dimension::Number => quote!(#p),
                })
                .collect();
            unit_arms
                .push(quote!(Confinement::#v { #(#fields),* } => Confinement::#v { #(#scaled),* }));
            pair_arms.push(quote!(Confinement::#v { #(#fields),* } => #m::#fpair(xa, xb, aa, ab, eta, #(#fields),*)));
            equal_arms.push(quote!(Confinement::#v { #(#fields),* } => #m::#fequal(xa, xb, a, eta, #(#fields),*)));
            self_arms.push(
                quote!(Confinement::#v { #(#fields),* } => #m::#fself(x, a, eta, #(#fields),*)),
            );
        }
        names.push(name);
        let pattern = if fields.is_empty() {
            quote!(Confinement::#v)
        } else {
            quote!(Confinement::#v { #(#fields),* })
        };
        let (fdp, fds) = (
            ident(&format!("{}_pair_divergence", f.name)),
            ident(&format!("{}_self_divergence", f.name)),
        );
        div_pair_arms.push(quote!(#pattern => #m::#fdp(xa, xb, aa, ab, eta, #(#fields),*)));
        let fdpl = ident(&format!("{}_pair_divergence_lanes", f.name));
        div_lane_arms.push(
            quote!(#pattern => #m::#fdpl(xa, xb, aa, ab, L::splat(eta), #(L::splat(#fields)),*)),
        );
        let fdpo = ident(&format!("{}_pair_divergence_lanes_ordered", f.name));
        div_ordered_arms.push(
            quote!(#pattern => #m::#fdpo(xa, xb, aa, ab, L::splat(eta), #(L::splat(#fields)),*)),
        );
        let fpo = ident(&format!("{}_pair_lanes_ordered", f.name));
        pair_lane_arms.push(
            quote!(#pattern => #m::#fpo(xa, xb, aa, ab, L::splat(eta), #(L::splat(#fields)),*)),
        );
        let exchanges = f.exchanges;
        let any = if fields.is_empty() {
            quote!(Confinement::#v)
        } else {
            quote!(Confinement::#v { .. })
        };
        exchange_arms.push(quote!(#any => #exchanges));
        div_self_arms.push(quote!(#pattern => #m::#fds(x, a, eta, #(#fields),*)));
        truncated.push(truncated_arms(f, &pattern, &m, &fields));
    }
    let mut truncated_fns = Vec::new();
    for (k, moments) in [Moments::F, Moments::FT].into_iter().enumerate() {
        let lo = moments.lower();
        let ty = ident(blocks_type(moments));
        let n = moments.per_particle();
        let (fpair, fself, fprod) = (
            ident(&format!("pair_{lo}")),
            ident(&format!("self_{lo}")),
            ident(&format!("product_{lo}")),
        );
        let arm = |i: usize| -> Vec<TokenStream> {
            truncated.iter().map(|t| t[6 * k + i].clone()).collect()
        };
        let (arms_pair, arms_self, arms_prod) = (arm(0), arm(1), arm(2));
        let (arms_lanes, arms_ordered, arms_blocks) = (arm(3), arm(4), arm(5));
        let fblocks = ident(&format!("pair_{lo}_lanes_ordered"));
        let nn = n * n;
        let flat = format!("{}_FLAT", moments_label(moments));
        let d_blocks = format!(
            " The lane twin of [`pair_{lo}`] without the exchange of roles, for pairs in \
             which `b` is no higher than `a` where [`Confinement::exchanges_by_height`] \
             (elsewhere any order): `L::WIDTH` pairs at once (unequal-radius kernels at any \
             radii), the {nn} entries of [`{ty}`]'s fields in their order \
             ([`crate::blocks::{flat}`]); the scene's lane kernel, or the FTS lane kernel \
             truncated for a confinement without one.",
            ty = blocks_type(moments)
        );
        let flanes = ident(&format!("product_{lo}_lanes"));
        let fordered = ident(&format!("product_{lo}_lanes_ordered"));
        let n2 = 2 * n;
        let d_lanes = format!(
            " The lane twin of [`product_{lo}`]: `L::WIDTH` pairs at once, returning `a` then \
             `b` (`{n2}` lanes); the scene's lane kernel, or the scalar product lane by lane for \
             a confinement without one."
        );
        let d_ordered = format!(
            " [`product_{lo}_lanes`] without the exchange of roles: for pairs in which `b` is \
             no higher than `a` ([`Confinement::exchanges_by_height`]; there the same values as \
             the exchanging kernel)."
        );
        let upper = moments_label(moments);
        let d_pair =
            format!(" The {upper} blocks of `M^{{ab}}` (equal-radius kernels when `aa == ab`).");
        let d_self = format!(" The {upper} blocks of `M^{{aa}}` (Eq. 17).");
        let d_prod =
            format!(" The fused pair product for {upper}: `a = M^{{ab}} vb`, `b = M^{{ba}} va`.");
        truncated_fns.push(quote! {
            #[doc = #d_pair]
            pub fn #fpair(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64) -> #ty {
                match *conf { #(#arms_pair),* }
            }
            #[doc = #d_self]
            pub fn #fself(conf: &Confinement, eta: f64, x: [f64; 3], a: f64) -> #ty {
                match *conf { #(#arms_self),* }
            }
            #[doc = #d_prod]
            pub fn #fprod(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64, va: [f64; #n], vb: [f64; #n]) -> Product<#n> {
                match *conf { #(#arms_prod),* }
            }
            #[doc = #d_lanes]
            #[inline(always)]
            pub fn #flanes<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L, va: [L; #n], vb: [L; #n]) -> [L; #n2] {
                match *conf { #(#arms_lanes),* }
            }
            #[doc = #d_ordered]
            #[inline(always)]
            pub fn #fordered<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L, va: [L; #n], vb: [L; #n]) -> [L; #n2] {
                match *conf { #(#arms_ordered),* }
            }
            #[doc = #d_blocks]
            #[inline(always)]
            pub fn #fblocks<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L) -> [L; #nn] {
                match *conf { #(#arms_blocks),* }
            }
        });
    }
    quote! {
        use crate::blocks::{BlocksF, BlocksFT, Drift, Grand, Product};

        #(#truncated_fns)*

        /// The Brownian drift of a pair: `a` = the divergence of `M^{ab}` over the
        /// position of `b` (`sum_j d/dxb_j M_{ij}`, rows U then Omega, force columns),
        /// `b` = that of `M^{ba}` over the position of `a`.
        pub fn pair_divergence(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64) -> Product<6> {
            match *conf { #(#div_pair_arms),* }
        }

        /// The lane twin of [`pair_divergence`]: `L::WIDTH` pairs at once, `a` then `b`.
        #[inline(always)]
        pub fn pair_divergence_lanes<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L) -> [L; 12] {
            match *conf { #(#div_lane_arms),* }
        }

        /// [`pair_divergence_lanes`] without the exchange of roles: for pairs in which `b`
        /// is no higher than `a` ([`Confinement::exchanges_by_height`]).
        #[inline(always)]
        pub fn pair_divergence_lanes_ordered<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L) -> [L; 12] {
            match *conf { #(#div_ordered_arms),* }
        }

        /// The lane twin of [`pair`] without the exchange of roles: `L::WIDTH` pairs at
        /// once, for pairs in which `b` is no higher than `a` where
        /// [`Confinement::exchanges_by_height`] (elsewhere any order); the 121 entries of
        /// [`Grand`]'s fields in their order (see [`crate::blocks::grand_lanes_product`]).
        #[inline(always)]
        pub fn pair_lanes_ordered<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L) -> [L; 121] {
            match *conf { #(#pair_lane_arms),* }
        }

        /// The Brownian drift of one particle's self mobility: `sum_j d/dx_j M^{aa}_{ij}`,
        /// rows U then Omega, force columns.
        pub fn self_divergence(conf: &Confinement, eta: f64, x: [f64; 3], a: f64) -> Drift<6> {
            match *conf { #(#div_self_arms),* }
        }

        /// The confinement and its run-time parameters, one variant per registered
        /// Green's function. Boundaries are planes `x3 = const` ([`Confinement::boundaries`]).
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum Confinement {
            #(#variants),*
        }

        impl Confinement {
            /// Names of all confinements, as in [`Confinement::name`].
            pub const NAMES: &'static [&'static str] = &[#(#names),*];

            /// The family name (`wall`, `free_surface`, ...).
            pub fn name(&self) -> &'static str {
                match *self {
                    #(#name_arms),*
                }
            }

            /// The confinement called `name` with run-time parameters `params` in the
            /// order of [`Confinement::params`]; `None` for an unknown name or the wrong
            /// number of parameters.
            pub fn from_name(name: &str, params: &[f64]) -> Option<Confinement> {
                match name {
                    #(#from_arms,)*
                    _ => None,
                }
            }

            /// The run-time parameters, named.
            pub fn params(&self) -> Vec<(&'static str, f64)> {
                match *self {
                    #(#param_arms),*
                }
            }

            /// Whether the pair kernels exchange the particles' roles where `b` is higher
            /// (larger `x3`) than `a`, keeping the accuracy of the direct sum
            /// (`M^{ab} = (M^{ba})^T`, evaluated with the lower particle as the source).
            /// The `*_lanes_ordered` kernels skip that exchange: a caller that orders the
            /// particles by `x3`, highest first, and passes the earlier one as `a` gets
            /// the same values with fewer operations.
            pub fn exchanges_by_height(&self) -> bool {
                match *self {
                    #(#exchange_arms),*
                }
            }

            /// The boundary planes: `(height, fluid is above it)`.
            pub fn boundaries(&self) -> Vec<(f64, bool)> {
                match *self {
                    #(#bound_arms),*
                }
            }

            /// The same confinement with lengths measured in units of `unit` and
            /// heights from `x3 = origin`: a height `h` becomes `(h - origin) / unit`, a
            /// length `l / unit`; pure numbers stay. With the viscosity as the unit of
            /// viscosity, a mobility block coupling a moment of length dimension `p`
            /// (force 0; torque, stresslet 1) to a response of dimension `q` (velocity 0;
            /// rotation, strain 1) becomes `eta unit^(1 + p + q)` times itself.
            pub fn in_units(&self, origin: f64, unit: f64) -> Confinement {
                let _ = (origin, unit);
                match *self {
                    #(#unit_arms),*
                }
            }
        }

        /// `M^{ab}` for two distinct particles: the response of particle `a` (centre
        /// `xa`, radius `aa`) to the force, torque and stresslet of particle `b`.
        pub fn pair(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64) -> Grand {
            match *conf {
                #(#pair_arms),*
            }
        }

        /// `M^{ab}` for two distinct particles of the same radius `a`.
        pub fn pair_equal(conf: &Confinement, eta: f64, xa: [f64; 3], xb: [f64; 3], a: f64) -> Grand {
            match *conf {
                #(#equal_arms),*
            }
        }

        /// `M^{aa}`: the isolated sphere plus its reflected field (Eq. 17).
        pub fn self_mobility(conf: &Confinement, eta: f64, x: [f64; 3], a: f64) -> Grand {
            match *conf {
                #(#self_arms),*
            }
        }
    }
}

struct Collect<'a> {
    families: Vec<Family>,
    scenes: &'a [Scene],
}

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
    use crate::operators::{Moment, Response};
    let spec = |interaction, equal_radii| KernelSpec {
        interaction,
        basis: Basis::Orthonormal,
        equal_radii,
        blocks: BLOCKS.to_vec(),
        path: Path::Structured,
        product: false,
        divergence: false,
    };
    let divergence = |interaction, blocks: Vec<(Response, Moment)>| KernelSpec {
        blocks,
        divergence: true,
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
            spec: divergence(Interaction::SelfTerm, vec![uf, of]),
            what: "self, divergence over the position of the particle (Brownian drift): a = [sum_j d/dx_j M_UF,ij, sum_j d/dx_j M_OmegaF,ij]",
            ret: ("Drift<6>", "Drift::<6>"),
        },
        Variant {
            suffix: "pair_divergence",
            spec: divergence(Interaction::Pair, vec![uf, ul, of]),
            what: "pair, divergence over the source position (Brownian drift): a = [sum_j d/dxb_j M^ab_UF,ij, sum_j d/dxb_j M^ab_OmegaF,ij], b the same for M^ba over xa",
            ret: ("Product<6>", "Product::<6>"),
        },
    ]
}

/// The operation counts of a traced kernel for the report: the direct sum (with the
/// switch condition, where there is one) and the lateral far-field branch.
fn counts(name: &str, traced: &Traced) -> Vec<(String, usize)> {
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
fn family_and_single<G: Green>(g: &G) -> (GeneratedFile, TokenStream) {
    let mut items = TokenStream::new();
    let mut single = TokenStream::new();
    let mut op_counts = Vec::new();
    for v in variants() {
        let traced = trace(g, &v.spec);
        let name = format!("{}_{}", g.name(), v.suffix);
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
            format!("Grand mobility blocks, {what}: {}.", g.title()),
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
        format!("Kernels for {}.", g.title()),
        String::new(),
        "Generated: see the header comment.".into(),
    ];
    let items = quote! {
        use crate::blocks::{Drift, Grand, Product};
        #items
    };
    let file = GeneratedFile {
        name: format!("{}.rs", g.name()),
        contents: emit::file(&module_doc, items),
        op_counts,
    };
    (file, single)
}

/// Name of the file of single-precision kernels, which the `kernels` crate compiles
/// only with its cargo feature `f32` (as `kernels::single`).
pub const SINGLE: &str = "single.rs";

/// `single.rs`: the FTS self and pair kernels of every family in `f32` (the same traces
/// as the `f64` kernels, emitted with [`Float::F32`]), returning `Grand32`.
fn single_file(items: Vec<TokenStream>) -> GeneratedFile {
    let fields: Vec<TokenStream> = BLOCKS
        .iter()
        .map(|&(r, m)| {
            let f = ident(&crate::operators::block_name(r, m));
            let (rows, cols) = (
                crate::operators::response_dim(r, Basis::Orthonormal),
                crate::operators::moment_dim(m, Basis::Orthonormal),
            );
            let d = format!(" Block `{}`, {rows}x{cols}, row-major.", f);
            quote!(#[doc = #d] pub #f: [[f32; #cols]; #rows])
        })
        .collect();
    let module_doc = vec![
        "Single-precision (f32) FTS self and pair kernels of every family, for accuracy and speed comparisons (`cargo xtask report`).".to_string(),
        String::new(),
        "Compiled only with the cargo feature `f32` of the kernels crate. Regenerate with `cargo xtask gen`.".to_string(),
    ];
    let body = quote! {
        /// The nine blocks of [`crate::Grand`] in single precision (same layout and basis).
        #[derive(Clone, Copy, Debug, PartialEq, Default)]
        pub struct Grand32 { #(#fields),* }
        #(#items)*
    };
    GeneratedFile {
        name: SINGLE.into(),
        contents: emit::file(&module_doc, body),
        op_counts: Vec::new(),
    }
}

impl Visitor for Collect<'_> {
    fn visit<G: Green>(&mut self, g: &G) {
        // The boundary heights as expressions of the parameters, traced and inlined.
        let t = crate::expr::Trace::begin();
        let p: Vec<crate::expr::Ex> = g.params().iter().map(|n| t.input(n)).collect();
        let b: Vec<(crate::expr::Id, bool)> = g
            .boundaries(&p)
            .into_iter()
            .map(|(h, up)| (h.0, up))
            .collect();
        let graph = t.finish();
        let boundaries = b
            .into_iter()
            .map(|(id, up)| (emit::inline(&graph, id), up))
            .collect();
        let mine: Vec<&Scene> = self
            .scenes
            .iter()
            .filter(|s| s.confinement == g.name())
            .collect();
        let mut serving: Vec<(Moments, String)> = Vec::new();
        for s in &mine {
            let serves =
                s.radii == Radii::Unequal && s.dense && s.product && s.moments != Moments::FTS;
            if serves && !serving.iter().any(|(m, _)| *m == s.moments) {
                serving.push((s.moments, s.name.clone()));
            }
        }
        let (file, single) = family_and_single(g);
        self.families.push(Family {
            name: g.name(),
            title: g.title(),
            params: g.params(),
            dimensions: g.params().iter().map(|p| g.dimension(p)).collect(),
            exchanges: g.cancelling_image().is_some(),
            boundaries,
            file,
            single,
            serving,
            scene_files: mine.iter().map(|s| scene_file(g, s, false)).collect(),
        });
    }
}

/// Every generated file, including `mod.rs`.
pub fn generate(scenes: &[Scene]) -> Vec<GeneratedFile> {
    let mut c = Collect {
        families: Vec::new(),
        scenes,
    };
    green::for_each(&mut c);
    let mut mods: Vec<TokenStream> = Vec::new();
    for f in &c.families {
        let n = ident(f.name);
        let d = format!(" Kernels of the `{}` family.", f.name);
        mods.push(quote!(#[doc = #d] pub mod #n;));
        for sf in &f.scene_files {
            let m = ident(sf.name.trim_end_matches(".rs"));
            let d = format!(
                " Kernels of the scene `{}` (`scenes/`).",
                sf.name.trim_start_matches("scene_").trim_end_matches(".rs")
            );
            mods.push(quote!(#[doc = #d] pub mod #m;));
        }
    }
    let dispatch = dispatch(&c.families);
    let module_doc = vec![
        "Generated kernels, one module per Green's function.".to_string(),
        String::new(),
        "Regenerate with `cargo xtask gen`.".to_string(),
    ];
    let mut files = vec![GeneratedFile {
        name: "mod.rs".into(),
        contents: emit::file(&module_doc, quote!(#(#mods)* #dispatch)),
        op_counts: Vec::new(),
    }];
    let mut single = Vec::new();
    for f in c.families {
        files.push(f.file);
        files.extend(f.scene_files);
        single.push(f.single);
    }
    files.push(single_file(single));
    files
}

/// The kernels' return type for a truncation.
fn blocks_type(m: Moments) -> &'static str {
    match m {
        Moments::F => "BlocksF",
        Moments::FT => "BlocksFT",
        Moments::FTS => "Grand",
    }
}

fn moments_label(m: Moments) -> &'static str {
    match m {
        Moments::F => "F",
        Moments::FT => "FT",
        Moments::FTS => "FTS",
    }
}

/// Match arms of the truncated entry points for one family, in the order
/// `[pair_f, self_f, product_f, product_f_lanes, product_f_lanes_ordered,
/// pair_f_lanes_ordered, pair_ft, ...]`: a serving scene's kernels when the family has
/// one, else the family's FTS kernels, truncated (for the product's lanes, the scalar
/// product lane by lane).
fn truncated_arms(
    f: &Family,
    pattern: &TokenStream,
    family_mod: &proc_macro2::Ident,
    fields: &[proc_macro2::Ident],
) -> Vec<TokenStream> {
    let mut arms = Vec::new();
    for moments in [Moments::F, Moments::FT] {
        let ty = ident(blocks_type(moments));
        let scene = f
            .serving
            .iter()
            .find(|(m, _)| *m == moments)
            .map(|(_, n)| n.clone());
        match scene {
            Some(name) => {
                let m = ident(&format!("scene_{name}"));
                let (p, pe, s, pp, ppe) = (
                    ident(&format!("{name}_pair")),
                    ident(&format!("{name}_pair_equal")),
                    ident(&format!("{name}_self")),
                    ident(&format!("{name}_pair_product")),
                    ident(&format!("{name}_pair_equal_product")),
                );
                arms.push(quote!(#pattern => if aa == ab { #m::#pe(xa, xb, aa, eta, #(#fields),*) } else { #m::#p(xa, xb, aa, ab, eta, #(#fields),*) }));
                arms.push(quote!(#pattern => #m::#s(x, a, eta, #(#fields),*)));
                arms.push(quote!(#pattern => if aa == ab { #m::#ppe(xa, xb, aa, eta, #(#fields,)* va, vb) } else { #m::#pp(xa, xb, aa, ab, eta, #(#fields,)* va, vb) }));
                for suffix in ["lanes", "lanes_ordered"] {
                    let ppl = ident(&format!("{name}_pair_product_{suffix}"));
                    arms.push(quote!(#pattern => #m::#ppl(xa, xb, aa, ab, L::splat(eta), #(L::splat(#fields),)* va, vb)));
                }
                let pl = ident(&format!("{name}_pair_lanes_ordered"));
                arms.push(quote!(#pattern => #m::#pl(xa, xb, aa, ab, L::splat(eta), #(L::splat(#fields)),*)));
            }
            None => {
                let (p, pe, s) = (
                    ident(&format!("{}_pair", f.name)),
                    ident(&format!("{}_pair_equal", f.name)),
                    ident(&format!("{}_self", f.name)),
                );
                let fm = family_mod;
                let pair = quote!(if aa == ab { #fm::#pe(xa, xb, aa, eta, #(#fields),*) } else { #fm::#p(xa, xb, aa, ab, eta, #(#fields),*) });
                arms.push(quote!(#pattern => #ty::from(&#pair)));
                arms.push(quote!(#pattern => #ty::from(&#fm::#s(x, a, eta, #(#fields),*))));
                arms.push(quote!(#pattern => #ty::from(&#pair).product(va, vb)));
                let fprod = ident(&format!("product_{}", moments.lower()));
                let n = moments.per_particle();
                let by_lane = quote!(#pattern => {
                    let _ = (#(#fields,)*);
                    let (a, b) = crate::blocks::lane_by_lane(|xa, aa, xb, ab, va, vb| #fprod(conf, eta, xa, aa, xb, ab, va, vb), xa, aa, xb, ab, va, vb);
                    std::array::from_fn(|i| if i < #n { a[i] } else { b[i - #n] })
                });
                arms.push(by_lane.clone());
                arms.push(by_lane);
                let fpo = ident(&format!("{}_pair_lanes_ordered", f.name));
                let at = ident(&format!("{}_FLAT", moments_label(moments)));
                arms.push(quote!(#pattern => crate::blocks::truncate_lanes(#fm::#fpo(xa, xb, aa, ab, L::splat(eta), #(L::splat(#fields)),*), &crate::blocks::#at)));
            }
        }
    }
    arms
}

/// The kernels of one scene as one file (`scene_<name>.rs`). With `standalone`, the
/// return types are defined in the file (for `cargo xtask gen --scene FILE --out`),
/// otherwise they come from the kernels crate.
pub fn scene_file<G: Green>(g: &G, scene: &Scene, standalone: bool) -> GeneratedFile {
    let mut items = TokenStream::new();
    let mut op_counts = Vec::new();
    let mut kinds: Vec<(&str, Interaction, bool, bool)> =
        vec![("self", Interaction::SelfTerm, false, false)];
    if scene.dense {
        if scene.radii == Radii::Unequal {
            kinds.push(("pair", Interaction::Pair, false, false));
        }
        kinds.push(("pair_equal", Interaction::Pair, true, false));
    }
    if scene.product {
        if scene.radii == Radii::Unequal {
            kinds.push(("pair_product", Interaction::Pair, false, true));
        }
        kinds.push(("pair_equal_product", Interaction::Pair, true, true));
    }
    let ty = blocks_type(scene.moments);
    let n = scene.moments.per_particle();
    // (type name, its fields with their shapes), for standalone definitions
    type Fields = Vec<(String, Vec<usize>)>;
    let mut types: Vec<(String, Fields)> = Vec::new();
    for (suffix, interaction, equal, product) in kinds {
        let spec = KernelSpec {
            interaction,
            basis: Basis::Orthonormal,
            equal_radii: equal,
            blocks: scene.moments.blocks(),
            path: Path::Structured,
            product,
            divergence: false,
        };
        let traced: Traced = trace(g, &spec);
        let name = format!("{}_{suffix}", scene.name);
        let (ret, ctor) = if product {
            (format!("Product<{n}>"), format!("Product::<{n}>"))
        } else {
            (ty.to_string(), ty.to_string())
        };
        let shape_fields = traced
            .outputs
            .iter()
            .map(|b| (b.name.clone(), b.shape.clone()))
            .collect();
        let tyname = if product {
            "Product".to_string()
        } else {
            ty.to_string()
        };
        if !types.iter().any(|(t, _)| *t == tyname) {
            types.push((tyname, shape_fields));
        }
        let what = if product {
            format!(
                "the fused pair product a = M^{{ab}} vb, b = M^{{ba}} va, {} moments",
                moments_label(scene.moments)
            )
        } else {
            format!("the {} blocks", moments_label(scene.moments))
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
        if !equal && !standalone {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::green::wall::Wall;

    /// A standalone scene module defines its own return types and parses as Rust;
    /// an F-only scene has no torque, rotation or stresslet code at all.
    #[test]
    fn standalone_scene_is_self_contained_and_pruned() {
        let text = "name = \"w\"\nconfinement = \"wall\"\nmoments = \"F\"\nradii = \"equal\"\noutputs = [\"dense\", \"product\"]\n";
        let scene = Scene::parse("w.toml", text, &["wall"]).unwrap();
        let f = scene_file(&Wall, &scene, true);
        let parsed: syn::File = syn::parse_str(&f.contents).expect("valid Rust");
        let structs: Vec<String> = parsed
            .items
            .iter()
            .filter_map(|i| match i {
                syn::Item::Struct(s) => Some(s.ident.to_string()),
                _ => None,
            })
            .collect();
        assert_eq!(structs, ["BlocksF", "Product"]);
        assert!(!f.contents.contains("crate::"));
        for absent in ["ul:", "of:", "os:", "es:"] {
            assert!(!f.contents.contains(absent), "{absent} in an F-only scene");
        }
        let names: Vec<&str> = f.op_counts.iter().map(|(n, _)| n.as_str()).collect();
        // the wall's pair kernels also have a lateral far-field branch (`farfield`),
        // its self kernels a closed-form branch (`self_image`)
        assert_eq!(
            names,
            [
                "w_self",
                "w_self (closed form)",
                "w_pair_equal",
                "w_pair_equal (far field)",
                "w_pair_equal_product",
                "w_pair_equal_product (far field)"
            ]
        );
    }
}
