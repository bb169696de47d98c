//! The scalar kernel: one `let` per live node, the exchange of roles and the far
//! branch as early returns, in `f64` or `f32`.

use super::tokens::{doc_attrs, ident, input_expr, literal, nest, param};
use super::KernelFn;
use crate::graph::{Graph, Id, Op};
use crate::kernel::BlockOut;
use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;
use std::str::FromStr;

/// Statements for the live nodes `want` that are not yet named, in topological order;
/// names them `t{next}`, `t{next+1}`, ...
fn statements(
    g: &Graph,
    want: &[bool],
    name: &mut [Option<TokenStream>],
    next: &mut usize,
    ty: &TokenStream,
) -> Vec<TokenStream> {
    let mut stmts = Vec::new();
    for id in 0..g.len() {
        if !want[id] || name[id].is_some() {
            continue;
        }
        let op = g.op(id as Id);
        let v = |a: &Id| name[*a as usize].clone().expect("operand named before use");
        let rhs = match op {
            Op::Input(i) => {
                name[id] = Some(input_expr(g, i));
                continue;
            }
            Op::Const(b) => {
                name[id] = Some(literal(f64::from_bits(b)));
                continue;
            }
            Op::Add(a, b) => {
                let (a, b) = (v(&a), v(&b));
                quote!(#a + #b)
            }
            Op::Sub(a, b) => {
                let (a, b) = (v(&a), v(&b));
                quote!(#a - #b)
            }
            Op::Mul(a, b) => {
                let (a, b) = (v(&a), v(&b));
                quote!(#a * #b)
            }
            Op::Div(a, b) => {
                let (a, b) = (v(&a), v(&b));
                quote!(#a / #b)
            }
            Op::Neg(a) => {
                let a = v(&a);
                quote!(-#a)
            }
            Op::Sqrt(a) => {
                let a = v(&a);
                quote!(#a.sqrt())
            }
            Op::Rsqrt(a) => {
                let a = v(&a);
                quote!(1.0 / #a.sqrt())
            }
            Op::Powi(a, n) => {
                let a = v(&a);
                let n = Literal::i32_unsuffixed(n);
                quote!(#a.powi(#n))
            }
            Op::Select(l, r, a, b) => {
                let (l, r, a, b) = (v(&l), v(&r), v(&a), v(&b));
                quote!(if #l > #r { #a } else { #b })
            }
        };
        let t = ident(&format!("t{next}"));
        *next += 1;
        stmts.push(quote!(let #t: #ty = #rhs;));
        name[id] = Some(quote!(#t));
    }
    stmts
}

/// The struct literal fields of a set of outputs.
fn fields(outputs: &[BlockOut], name: &[Option<TokenStream>]) -> Vec<TokenStream> {
    outputs
        .iter()
        .map(|b| {
            let f = ident(&b.name);
            let vals: Vec<TokenStream> = b
                .ids
                .iter()
                .map(|id| name[*id as usize].clone().expect("output is live"))
                .collect();
            let arr = nest(&vals, &b.shape);
            quote!(#f: #arr)
        })
        .collect()
}

/// Emit one kernel function. The nodes of the conditions first; with an exchange of
/// roles ([`crate::kernel::Swap`]), `if lhs > rhs { return` the kernel called with the
/// particles exchanged, its outputs transposed `}`; with a far branch,
/// `if lhs > rhs { far branch; return }`; then the direct sum. Each branch computes
/// only what it needs.
pub fn function(k: &KernelFn) -> TokenStream {
    let g = &k.traced.graph;
    let outputs = k.traced.output_ids();
    let far_ids = k.traced.far_ids();
    let cond: Vec<Id> = k
        .traced
        .swap
        .iter()
        .flat_map(|w| [w.cond.0, w.cond.1])
        .chain(k.traced.far.iter().flat_map(|f| f.condition_ids()))
        .collect();
    let near_all: Vec<Id> = outputs.iter().chain(&cond).copied().collect();
    let far_all: Vec<Id> = far_ids.iter().chain(&cond).copied().collect();
    let live_cond = g.live(&cond);
    let live_near = g.live(&near_all);
    let live_far = g.live(&far_all);
    let live: Vec<bool> = live_near
        .iter()
        .zip(&live_far)
        .map(|(a, b)| *a || *b)
        .collect();
    let count = g.op_count(&near_all);
    let ty = k.float.ty();

    // Dense names for live interior nodes: t0, t1, ... in topological order.
    let mut name: Vec<Option<TokenStream>> = vec![None; g.len()];
    let mut next = 0usize;
    let pre = statements(g, &live_cond, &mut name, &mut next, &ty);
    let far_branch = k.traced.far.as_ref().map(|f| {
        let mut far_name = name.clone();
        let mut far_next = next;
        let stmts = statements(g, &live_far, &mut far_name, &mut far_next, &ty);
        let fs = fields(&f.outputs, &far_name);
        let tests: Vec<TokenStream> = f
            .conds
            .iter()
            .map(|&(l, r)| {
                let l = name[l as usize].clone().expect("condition named");
                let r = name[r as usize].clone().expect("condition named");
                quote!(#l > #r)
            })
            .collect();
        (tests, stmts, fs)
    });
    let stmts = statements(g, &live_near, &mut name, &mut next, &ty);

    // Arguments; those the kernel does not read are bound to `_` so the signature stays
    // uniform across a family.
    let mut params = Vec::new();
    let mut unused = Vec::new();
    for a in &k.traced.args {
        let n = ident(&a.name);
        let used = (0..g.len()).any(|id| {
            live[id]
                && matches!(g.op(id as Id), Op::Input(i)
                    if g.input_names()[i as usize] == a.name
                        || g.input_names()[i as usize].starts_with(&format!("{}[", a.name)))
        });
        if !used {
            unused.push(quote!(let _ = #n;));
        }
        params.push(param(a, &ty));
    }

    let fields = fields(&k.traced.outputs, &name);
    let ctor = TokenStream::from_str(&k.ctor).expect("constructor");
    let fname = ident(&k.name);
    let swap_code = match &k.traced.swap {
        None => quote!(),
        Some(w) => {
            let l = name[w.cond.0 as usize].clone().expect("condition named");
            let r = name[w.cond.1 as usize].clone().expect("condition named");
            let call_args: Vec<Ident> = w
                .args
                .iter()
                .map(|&j| ident(&k.traced.args[j].name))
                .collect();
            // every entry of the exchanged evaluation, in output order
            let entries: Vec<TokenStream> = k
                .traced
                .outputs
                .iter()
                .flat_map(|b| {
                    let f = ident(&b.name);
                    (0..b.ids.len()).map(move |p| {
                        let mut idx = Vec::new();
                        let mut rest = p;
                        for (d, _) in b.shape.iter().enumerate() {
                            let inner: usize = b.shape[d + 1..].iter().product();
                            idx.push(Literal::usize_unsuffixed(rest / inner));
                            rest %= inner;
                        }
                        quote!(exchanged.#f #([#idx])*)
                    })
                })
                .collect();
            let mut at = 0;
            let swapped_fields: Vec<TokenStream> = k
                .traced
                .outputs
                .iter()
                .map(|b| {
                    let f = ident(&b.name);
                    let vals: Vec<TokenStream> = w.outputs[at..at + b.ids.len()]
                        .iter()
                        .map(|&q| entries[q].clone())
                        .collect();
                    at += b.ids.len();
                    let arr = nest(&vals, &b.shape);
                    quote!(#f: #arr)
                })
                .collect();
            quote! {
                if #l > #r {
                    let exchanged = #fname(#(#call_args),*);
                    return #ctor { #(#swapped_fields),* };
                }
            }
        }
    };
    let far_code = match far_branch {
        None => quote!(),
        Some((tests, far_stmts, far_fields)) => quote! {
            if #(#tests)&&* {
                #(#far_stmts)*
                return #ctor { #(#far_fields),* };
            }
        },
    };

    let mut doc = k.doc.clone();
    doc.push(String::new());
    doc.push("# Arguments".into());
    for a in &k.traced.args {
        doc.push(format!("- `{}`: {}", a.name, a.doc));
    }
    doc.push(String::new());
    doc.push(format!(
        "Operation count (after dead-code elimination): {count}."
    ));
    if let Some(f) = &k.traced.far {
        let far_count = g.op_count(&far_all);
        doc.push(format!("{}: {far_count}.", f.doc));
    }
    if k.traced.swap.is_some() {
        doc.push(
            "Where particle b is higher above the wall than particle a, the kernel is \
             evaluated with the particles exchanged and its result transposed (the \
             mobility is symmetric): the direct sum then keeps its accuracy at any ratio \
             of the heights (kernel_gen::kernel::Swap)."
                .into(),
        );
    }
    let doc_attrs = doc_attrs(&doc);
    let ret = TokenStream::from_str(&k.ret).expect("return type");
    quote! {
        #(#doc_attrs)*
        #[inline]
        pub fn #fname(#(#params),*) -> #ret {
            #(#unused)*
            #(#pre)*
            #swap_code
            #far_code
            #(#stmts)*
            #ctor { #(#fields),* }
        }
    }
}
