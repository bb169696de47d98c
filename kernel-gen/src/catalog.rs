//! The catalogue of generated kernels: for every registered Green's function, the
//! self and pair kernels of all nine blocks, in the orthonormal strain basis and in
//! Cartesian form. [`generate`] returns every generated file's path and contents;
//! `cargo xtask gen` writes them, `--check` compares.

use crate::emit::{self, Float, KernelFn};
use crate::green::{self, Green, Visitor};
use crate::operators::{Basis, BLOCKS};
use crate::scene::{trace, Interaction, KernelSpec, Path};
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
    /// `(height expression, fluid above)` of each boundary plane.
    boundaries: Vec<(TokenStream, bool)>,
    file: GeneratedFile,
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
    let mut pair_arms = Vec::new();
    let mut equal_arms = Vec::new();
    let mut self_arms = Vec::new();
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
            pair_arms.push(quote!(Confinement::#v { #(#fields),* } => #m::#fpair(xa, xb, aa, ab, eta, #(#fields),*)));
            equal_arms.push(quote!(Confinement::#v { #(#fields),* } => #m::#fequal(xa, xb, a, eta, #(#fields),*)));
            self_arms.push(
                quote!(Confinement::#v { #(#fields),* } => #m::#fself(x, a, eta, #(#fields),*)),
            );
        }
        names.push(name);
    }
    quote! {
        use crate::blocks::Grand;

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

            /// The boundary planes: `(height, fluid is above it)`.
            pub fn boundaries(&self) -> Vec<(f64, bool)> {
                match *self {
                    #(#bound_arms),*
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

struct Collect {
    families: Vec<Family>,
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
}

/// The functions generated for every family.
pub fn variants() -> Vec<Variant> {
    let spec = |interaction, equal_radii| KernelSpec {
        interaction,
        basis: Basis::Orthonormal,
        equal_radii,
        blocks: BLOCKS.to_vec(),
        path: Path::Structured,
    };
    vec![
        Variant {
            suffix: "self",
            spec: spec(Interaction::SelfTerm, false),
            what: "self",
        },
        Variant {
            suffix: "pair",
            spec: spec(Interaction::Pair, false),
            what: "pair",
        },
        Variant {
            suffix: "pair_equal",
            spec: spec(Interaction::Pair, true),
            what: "pair, equal radii",
        },
    ]
}

/// Generate the kernels of one Green's function as one file.
pub fn family<G: Green>(g: &G) -> GeneratedFile {
    let mut items = TokenStream::new();
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
        let count = traced.graph.op_count(&traced.output_ids());
        op_counts.push((name.clone(), count.total()));
        items.extend(emit::function(&KernelFn {
            name,
            doc,
            ret: "Grand".into(),
            traced: &traced,
            float: Float::F64,
        }));
    }
    let module_doc = vec![
        format!("Kernels for {}.", g.title()),
        String::new(),
        "Generated: see the header comment.".into(),
    ];
    let items = quote! {
        use crate::blocks::Grand;
        #items
    };
    GeneratedFile {
        name: format!("{}.rs", g.name()),
        contents: emit::file(&module_doc, items),
        op_counts,
    }
}

impl Visitor for Collect {
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
        self.families.push(Family {
            name: g.name(),
            title: g.title(),
            params: g.params(),
            boundaries,
            file: family(g),
        });
    }
}

/// Every generated file, including `mod.rs`.
pub fn generate() -> Vec<GeneratedFile> {
    let mut c = Collect {
        families: Vec::new(),
    };
    green::for_each(&mut c);
    let mods: Vec<TokenStream> = c
        .families
        .iter()
        .map(|f| {
            let n = ident(f.name);
            let d = format!(" Kernels of the `{}` family.", f.name);
            quote!(#[doc = #d] pub mod #n;)
        })
        .collect();
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
    files.extend(c.families.into_iter().map(|f| f.file));
    files
}
