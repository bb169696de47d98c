//! The lane twin of a kernel: `L::WIDTH` pairs at once, generic over `lanes::Lane`,
//! branch-free per lane.

use super::fusion::Fusion;
use super::reciprocals::reciprocal_groups;
use super::tokens::{doc_attrs, ident, input_expr, literal, param};
use super::KernelFn;
use crate::graph::{Graph, Id, Op};
use crate::kernel::{ArgKind, Traced};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

/// Statements of a lane kernel (generic lane type `L`, crate `lanes`) for the nodes `want`
/// not yet named: as the scalar kernel's statements, with constants broadcast, comparisons
/// as per-lane blends, the products of [`Fusion`] fused into their sums, and the
/// reciprocals of [`reciprocal_groups`] sharing one division. Emitted depth first (a group
/// of reciprocals after the arguments of all its members).
fn lane_statements(
    g: &Graph,
    want: &[bool],
    fusion: &Fusion,
    name: &mut [Option<TokenStream>],
    next: &mut usize,
) -> Vec<TokenStream> {
    let groups = reciprocal_groups(g, want, name);
    let mut group_of: Vec<Option<usize>> = vec![None; g.len()];
    for (k, m) in groups.iter().enumerate() {
        for &r in m {
            group_of[r as usize] = Some(k);
        }
    }
    let mut e = LaneEmitter {
        g,
        want,
        fusion,
        groups: &groups,
        group_of: &group_of,
        name,
        next,
        stmts: Vec::new(),
    };
    for id in 0..g.len() as Id {
        e.emit(id);
    }
    e.stmts
}

struct LaneEmitter<'a> {
    g: &'a Graph,
    want: &'a [bool],
    fusion: &'a Fusion,
    groups: &'a [Vec<Id>],
    group_of: &'a [Option<usize>],
    name: &'a mut [Option<TokenStream>],
    next: &'a mut usize,
    stmts: Vec<TokenStream>,
}

impl LaneEmitter<'_> {
    fn fresh(&mut self, rhs: TokenStream) -> TokenStream {
        let t = ident(&format!("t{}", self.next));
        *self.next += 1;
        self.stmts.push(quote!(let #t: L = #rhs;));
        quote!(#t)
    }

    fn v(&self, a: Id) -> TokenStream {
        self.name[a as usize]
            .clone()
            .expect("operand named before use")
    }

    /// Emit node `id` after its operands (depth first).
    fn emit(&mut self, id: Id) {
        let i = id as usize;
        if !self.want[i] || self.name[i].is_some() || self.fusion.fused[i] {
            return;
        }
        let g = self.g;
        let op = g.op(id);
        // operands first (a fused product's operands for its sum)
        let mut operands = op.operands();
        if self.fusion.negated[i] {
            // the negated sum's operands instead of the sum
            let s = operands[0];
            operands = g.op(s).operands();
            if let Some(Op::Mul(x, y)) = self.fusion.fused_into[s as usize].map(|m| g.op(m)) {
                operands.extend([x, y]);
            }
        }
        if let Some(m) = self.fusion.fused_into[i] {
            if let Op::Mul(x, y) = g.op(m) {
                operands.extend([x, y]);
            }
        }
        if let Some(k) = self.group_of[i] {
            // every member's argument, then the shared division
            let members = self.groups[k].clone();
            let args: Vec<Id> = members
                .iter()
                .map(|&r| match g.op(r) {
                    Op::Div(_, x) => x,
                    _ => unreachable!("reciprocals are divisions"),
                })
                .collect();
            for &x in &args {
                self.emit(x);
            }
            let xs: Vec<TokenStream> = args.iter().map(|&x| self.v(x)).collect();
            let mut prefix = vec![xs[0].clone()];
            for x in &xs[1..] {
                let last = prefix.last().expect("non-empty").clone();
                prefix.push(self.fresh(quote!(#last * #x)));
            }
            let total = prefix.last().expect("non-empty").clone();
            let mut q = self.fresh(quote!(#total.recip()));
            for j in (1..members.len()).rev() {
                let (p, x) = (&prefix[j - 1], &xs[j]);
                let r = self.fresh(quote!(#q * #p));
                self.name[members[j] as usize] = Some(r);
                q = self.fresh(quote!(#q * #x));
            }
            self.name[members[0] as usize] = Some(q);
            return;
        }
        for a in operands {
            if self.fusion.fused[a as usize] {
                continue;
            }
            self.emit(a);
        }
        let factors = |me: &Self, m: Id| match g.op(m) {
            Op::Mul(x, y) => (me.v(x), me.v(y)),
            _ => unreachable!("fused nodes are products"),
        };
        let rhs = match op {
            Op::Input(k) => {
                self.name[i] = Some(input_expr(g, k));
                return;
            }
            Op::Const(b) => {
                let c = f64::from_bits(b);
                let lit = literal(c.abs());
                self.name[i] = Some(if c < 0.0 {
                    quote!(L::splat(-#lit))
                } else {
                    quote!(L::splat(#lit))
                });
                return;
            }
            Op::Add(a, b) => match self.fusion.fused_into[i] {
                Some(m) => {
                    let (x, y) = factors(self, m);
                    let other = if m == a { self.v(b) } else { self.v(a) };
                    quote!(#x.mul_add(#y, #other))
                }
                None => {
                    let (a, b) = (self.v(a), self.v(b));
                    quote!(#a + #b)
                }
            },
            Op::Sub(a, b) => match self.fusion.fused_into[i] {
                Some(m) if m == a => {
                    let (x, y) = factors(self, m);
                    let b = self.v(b);
                    quote!(#x.mul_sub(#y, #b))
                }
                Some(m) => {
                    let (x, y) = factors(self, m);
                    let a = self.v(a);
                    quote!(#x.neg_mul_add(#y, #a))
                }
                None => {
                    let (a, b) = (self.v(a), self.v(b));
                    quote!(#a - #b)
                }
            },
            Op::Mul(a, b) => {
                let (a, b) = (self.v(a), self.v(b));
                quote!(#a * #b)
            }
            Op::Div(a, b) if g.as_const(a) == Some(1.0) => {
                let b = self.v(b);
                quote!(#b.recip())
            }
            Op::Div(a, b) => {
                let (a, b) = (self.v(a), self.v(b));
                quote!(#a / #b)
            }
            Op::Neg(s) if self.fusion.negated[i] => {
                let (Op::Add(a, b), Some(m)) = (g.op(s), self.fusion.fused_into[s as usize]) else {
                    unreachable!("negated nodes are sums with a fused product")
                };
                let (x, y) = factors(self, m);
                let other = if m == a { self.v(b) } else { self.v(a) };
                quote!(#x.neg_mul_sub(#y, #other))
            }
            Op::Neg(a) => {
                let a = self.v(a);
                quote!(-#a)
            }
            // where the lane form also needs 1/sqrt(a), both come from one rsqrt
            Op::Sqrt(a) => match g.find(Op::Rsqrt(a)).filter(|&r| self.want[r as usize]) {
                Some(r) => {
                    self.emit(r);
                    let (a, r) = (self.v(a), self.v(r));
                    quote!(#a.sqrt_with(#r))
                }
                None => {
                    let a = self.v(a);
                    quote!(#a.sqrt())
                }
            },
            Op::Rsqrt(a) => {
                let a = self.v(a);
                quote!(#a.rsqrt())
            }
            Op::Powi(a, n) => {
                let a = self.v(a);
                let n = Literal::i32_unsuffixed(n);
                quote!(#a.powi(#n))
            }
            Op::Select(l, r, a, b) => {
                let (l, r, a, b) = (self.v(l), self.v(r), self.v(a), self.v(b));
                quote!(L::select(#l.gt(#r), #a, #b))
            }
        };
        let t = self.fresh(rhs);
        self.name[i] = Some(t);
    }
}

/// The lane twin of a kernel: the same trace evaluated on `L::WIDTH` pairs at once (generic
/// over `lanes::Lane`), branch-free per lane. The exchange of roles
/// ([`crate::kernel::Swap`]) becomes a per-lane exchange of the arguments and of the
/// outputs; the far branch is computed where any lane needs it and blended per lane (the
/// direct sum likewise where any lane needs it); multiply-adds are fused ([`Fusion`]) and
/// reciprocals share divisions (`reciprocal_groups`). Arguments are arrays of lanes in the
/// scalar kernel's order; the outputs come back flattened, in the order of the scalar
/// kernel's fields. Returns the function and its operation count (a fused multiply-add
/// counts once).
pub fn lane_function(k: &KernelFn) -> (TokenStream, usize) {
    let t = k.traced;
    // the lane form: reciprocal square roots in place of square roots then divisions;
    // then the powers of two carried beside the nodes (through products only, or
    // through sums too) where that takes fewer operations than computing them
    let (lane_graph, first) = t.graph.lane_form();
    let forms = [None, Some(false), Some(true)].map(|carry| {
        let (g, map) = match carry {
            None => (lane_graph.clone(), first.clone()),
            Some(through_sums) => {
                let (g, second) = lane_graph.powers_of_two_carried(through_sums);
                (g, first.iter().map(|&i| second[i as usize]).collect())
            }
        };
        let parts = LaneParts::of(t, &g, &map);
        (g, map, parts)
    });
    let (lane_graph, map, parts) = forms
        .into_iter()
        .min_by_key(|f| f.2.count)
        .expect("three forms");
    let g = &lane_graph;
    let LaneParts {
        outputs,
        far_ids,
        swap_cond,
        live_near,
        live_far,
        live_swap,
        live_cond,
        fusion,
        count,
    } = parts;
    let n_out = outputs.len();

    let mut next = 0usize;
    let params: Vec<TokenStream> = t.args.iter().map(|a| param(a, &quote!(L))).collect();
    let arg_names: Vec<Ident> = t.args.iter().map(|a| ident(&a.name)).collect();
    let fname = ident(&format!("{}_lanes", k.name));
    let ordered = ident(&format!("{}_lanes_ordered", k.name));
    // the exchange of roles: its condition on the arguments as given, the arguments
    // exchanged per lane, the kernel without exchange, its outputs exchanged back
    let exchanging = match &t.swap {
        None => None,
        Some(w) => {
            let mut name: Vec<Option<TokenStream>> = vec![None; g.len()];
            let mut next = 0usize;
            let stmts = lane_statements(g, &live_swap, &fusion, &mut name, &mut next);
            let l = name[swap_cond[0] as usize]
                .clone()
                .expect("condition named");
            let r = name[swap_cond[1] as usize]
                .clone()
                .expect("condition named");
            // only the arguments that change places
            let moved: Vec<usize> = (0..t.args.len()).filter(|&i| w.args[i] != i).collect();
            let mine: Vec<Ident> = moved.iter().map(|&i| ident(&t.args[i].name)).collect();
            let picks: Vec<TokenStream> = moved
                .iter()
                .map(|&i| {
                    let (m, th) = (ident(&t.args[i].name), ident(&t.args[w.args[i]].name));
                    match t.args[i].kind {
                        ArgKind::Scalar => quote!(L::select(swap, #th, #m)),
                        _ => quote!(lanes::select_array(swap, #th, #m)),
                    }
                })
                .collect();
            let outs: Vec<TokenStream> = w
                .outputs
                .iter()
                .enumerate()
                .map(|(i, &j)| {
                    let (i, j) = (Literal::usize_unsuffixed(i), Literal::usize_unsuffixed(j));
                    quote!(L::select(swap, out[#j], out[#i]))
                })
                .collect();
            Some(quote! {
                let swap = {
                    #(#stmts)*
                    #l.gt(#r)
                };
                let (#(#mine),*) = (#(#picks),*);
                let out = #ordered(#(#arg_names),*);
                [#(#outs),*]
            })
        }
    };
    let mut name: Vec<Option<TokenStream>> = vec![None; g.len()];
    let pre = lane_statements(g, &live_cond, &fusion, &mut name, &mut next);
    let flat = |ids: &[Id], name: &[Option<TokenStream>]| -> Vec<TokenStream> {
        ids.iter()
            .map(|id| name[*id as usize].clone().expect("output is live"))
            .collect()
    };
    let near_code = {
        let mut nm = name.clone();
        let stmts = lane_statements(g, &live_near, &fusion, &mut nm, &mut next);
        let vals = flat(&outputs, &nm);
        quote!({ #(#stmts)* [#(#vals),*] })
    };
    let body = match &t.far {
        None => quote! { let out: [L; #n_out] = #near_code; },
        Some(f) => {
            let mut nm = name.clone();
            let stmts = lane_statements(g, &live_far, &fusion, &mut nm, &mut next);
            let vals = flat(&far_ids, &nm);
            let tests: Vec<TokenStream> = f
                .conds
                .iter()
                .map(|&(l, r)| {
                    let (l, r) = (map[l as usize], map[r as usize]);
                    let l = name[l as usize].clone().expect("condition named");
                    let r = name[r as usize].clone().expect("condition named");
                    quote!(#l.gt(#r))
                })
                .collect();
            let mut mask = tests[0].clone();
            for t in &tests[1..] {
                mask = quote!(L::and(#mask, #t));
            }
            quote! {
                let far = #mask;
                let near: [L; #n_out] = if L::all(far) { [L::splat(0.0); #n_out] } else #near_code;
                let farv: [L; #n_out] = if L::any(far) { #(#stmts)* [#(#vals),*] } else { [L::splat(0.0); #n_out] };
                let out: [L; #n_out] = lanes::select_array(far, farv, near);
            }
        }
    };
    let mut doc = k.doc.clone();
    doc.push(String::new());
    doc.push(format!(
        "Lanes: `L::WIDTH` pairs at once (crate `lanes`), outputs flattened in the order \
         of `{}`'s fields. Operation count with fused multiply-adds: {count} (direct sum).",
        k.name
    ));
    let doc_attrs = doc_attrs(&doc);
    let f = match exchanging {
        None => quote! {
            #(#doc_attrs)*
            #[inline(always)]
            #[allow(unused_variables)]
            pub fn #fname<L: lanes::Lane>(#(#params),*) -> [L; #n_out] {
                #(#pre)*
                #body
                out
            }
            pub use #fname as #ordered;
        },
        Some(exchange) => {
            let d_ordered = format!(
                " [`{fname}`] without the exchange of roles: the same values in lanes \
                 where `b` is no farther than `a` from the cancelling plane; elsewhere the \
                 same tensor with the cancellation the exchange avoids. The caller orders \
                 the particles (by height, highest first) and passes the earlier one as `a`."
            );
            quote! {
                #(#doc_attrs)*
                #[inline(always)]
                #[allow(unused_variables)]
                pub fn #fname<L: lanes::Lane>(#(#params),*) -> [L; #n_out] {
                    #exchange
                }
                #[doc = #d_ordered]
                #[inline(always)]
                #[allow(unused_variables)]
                pub fn #ordered<L: lanes::Lane>(#(#params),*) -> [L; #n_out] {
                    #(#pre)*
                    #body
                    out
                }
            }
        }
    };
    (f, count)
}

/// A lane kernel traced as `t`, on its lane graph `g` (`map` takes `t.graph`'s ids to
/// `g`'s): its outputs and conditions, what each branch needs, the fused products, and
/// its operation count (the near branch with its far-field condition, a fused
/// multiply-add counted once, a group of `k` reciprocals as one division and
/// `3 (k - 1)` multiplications).
struct LaneParts {
    outputs: Vec<Id>,
    far_ids: Vec<Id>,
    swap_cond: Vec<Id>,
    live_near: Vec<bool>,
    live_far: Vec<bool>,
    live_swap: Vec<bool>,
    live_cond: Vec<bool>,
    fusion: Fusion,
    count: usize,
}

impl LaneParts {
    fn of(t: &Traced, g: &Graph, map: &[Id]) -> LaneParts {
        let m = |ids: Vec<Id>| -> Vec<Id> { ids.into_iter().map(|i| map[i as usize]).collect() };
        let outputs = m(t.output_ids());
        let far_ids = m(t.far_ids());
        let swap_cond: Vec<Id> = m(t.swap.iter().flat_map(|w| [w.cond.0, w.cond.1]).collect());
        let far_cond: Vec<Id> = m(t.far.iter().flat_map(|f| f.condition_ids()).collect());
        let near_all: Vec<Id> = outputs.iter().chain(&far_cond).copied().collect();
        let live_near = g.live(&near_all);
        let live_far = g.live(&far_ids.iter().chain(&far_cond).copied().collect::<Vec<_>>());
        let live_swap = g.live(&swap_cond);
        let live_cond = g.live(&far_cond);
        let live: Vec<bool> = (0..g.len())
            .map(|i| live_near[i] || live_far[i] || live_swap[i])
            .collect();
        let named: Vec<Id> = [&outputs, &far_ids, &swap_cond, &far_cond]
            .into_iter()
            .flatten()
            .copied()
            .collect();
        let fusion = Fusion::of(g, &live, &named);
        let batched: usize = reciprocal_groups(g, &live_near, &vec![None; g.len()])
            .iter()
            .map(|m| 2 * (m.len() - 1))
            .sum();
        let count = g.op_count(&near_all).total() - fusion.count(&live_near) + batched;
        LaneParts {
            outputs,
            far_ids,
            swap_cond,
            live_near,
            live_far,
            live_swap,
            live_cond,
            fusion,
            count,
        }
    }
}
