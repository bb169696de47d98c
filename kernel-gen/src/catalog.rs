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
    file: GeneratedFile,
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
        self.families.push(Family {
            name: g.name(),
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
            let n = proc_macro2::Ident::new(f.name, proc_macro2::Span::call_site());
            let d = format!(" Kernels of the `{}` family.", f.name);
            quote!(#[doc = #d] pub mod #n;)
        })
        .collect();
    let module_doc = vec![
        "Generated kernels, one module per Green's function.".to_string(),
        String::new(),
        "Regenerate with `cargo xtask gen`.".to_string(),
    ];
    let mut files = vec![GeneratedFile {
        name: "mod.rs".into(),
        contents: emit::file(&module_doc, quote!(#(#mods)*)),
        op_counts: Vec::new(),
    }];
    files.extend(c.families.into_iter().map(|f| f.file));
    files
}
