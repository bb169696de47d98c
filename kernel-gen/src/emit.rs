//! Emission of traced kernels as flat Rust: one `let` per live node of the expression
//! graph, in topological order, built with `quote` and formatted by `prettyplease`.
//! No loops, no heap, no jets at run time. Output is deterministic: node order is
//! creation order, constants print in Rust's shortest round-trip form.

use crate::expr::{Graph, Id, Op};
use crate::scene::{ArgKind, BlockOut, Traced};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;
use std::str::FromStr;

/// The floating-point type a kernel is emitted in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Float {
    /// Double precision.
    F64,
    /// Single precision (constants are rounded to f32 by the compiler).
    F32,
}

impl Float {
    fn ty(self) -> TokenStream {
        match self {
            Float::F64 => quote!(f64),
            Float::F32 => quote!(f32),
        }
    }
}

/// A kernel function ready to print.
pub struct KernelFn<'a> {
    /// Function name.
    pub name: String,
    /// Documentation paragraphs (inputs and outputs are appended automatically).
    pub doc: Vec<String>,
    /// Return type: a struct with one field per output block.
    pub ret: String,
    /// The struct's constructor path (the return type without generic arguments, with
    /// turbofish if needed, e.g. `Product::<3>`).
    pub ctor: String,
    /// The traced kernel.
    pub traced: &'a Traced,
    /// Floating-point type.
    pub float: Float,
}

fn ident(s: &str) -> Ident {
    Ident::new(s, Span::call_site())
}

fn literal(c: f64) -> TokenStream {
    let s = format!("{:?}", c.abs());
    let lit = Literal::from_str(&s).expect("float literal");
    if c < 0.0 || (c == 0.0 && c.is_sign_negative()) {
        quote!((-#lit))
    } else {
        quote!(#lit)
    }
}

/// Input `k`'s Rust expression, e.g. `xa[0]` or `eta`.
fn input_expr(g: &Graph, k: u32) -> TokenStream {
    let name = &g.input_names()[k as usize];
    TokenStream::from_str(name).expect("input name is a Rust expression")
}

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

/// A kernel parameter `name: type` with the shape of its argument, in the float or
/// lane type `ty`.
fn param(a: &crate::scene::Arg, ty: &TokenStream) -> TokenStream {
    let n = ident(&a.name);
    match a.kind {
        ArgKind::Point => quote!(#n: [#ty; 3]),
        ArgKind::Scalar => quote!(#n: #ty),
        ArgKind::Vector(len) => quote!(#n: [#ty; #len]),
    }
}

/// Documentation paragraphs as `#[doc]` attributes.
fn doc_attrs(doc: &[String]) -> Vec<TokenStream> {
    doc.iter()
        .map(|d| {
            let d = format!(" {d}");
            quote!(#[doc = #d])
        })
        .collect()
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
/// roles ([`crate::scene::Swap`]), `if lhs > rhs { return` the kernel called with the
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
             of the heights (kernel_gen::scene::Swap)."
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

/// Fused multiply-adds of the lane kernels: for each `+` or `-` node, an operand that
/// is a product used only by sums (fused into `mul_add`, `mul_sub` or `neg_mul_add`),
/// as `(node, operand)`; and for each fused product, whether it is fused (so it is not
/// emitted on its own). A product is fused only if every one of its uses takes it
/// fused: used by `k` sums, it then costs `k` multiply-adds instead of a product and `k`
/// sums (each sum rounds the exact product once, as a single fused use always did).
pub struct Fusion {
    /// `fused_into[n] = Some(m)`: node `n` (`+`/`-`) takes the product `m` fused.
    pub fused_into: Vec<Option<Id>>,
    /// `fused[m]`: product `m` is emitted only inside its users (or a sum, only inside
    /// its negation).
    pub fused: Vec<bool>,
    /// `negated[n]`: node `n` is `-(x y + c)` of a sum used only there with its product
    /// fused, emitted as one `neg_mul_sub` (the sum is `fused`).
    pub negated: Vec<bool>,
}

impl Fusion {
    /// The fusions among the nodes `live`, of which `named` (outputs, conditions) are
    /// used by name.
    pub fn of(g: &Graph, live: &[bool], named: &[Id]) -> Fusion {
        // uses of each node, and uses as an operand of a sum
        let (mut uses, mut in_sums) = (vec![0u32; g.len()], vec![0u32; g.len()]);
        for id in 0..g.len() {
            if !live[id] {
                continue;
            }
            let op = g.op(id as Id);
            let sum = matches!(op, Op::Add(..) | Op::Sub(..));
            for a in op.operands() {
                uses[a as usize] += 1;
                in_sums[a as usize] += u32::from(sum);
            }
        }
        for &n in named {
            uses[n as usize] += 1;
        }
        let candidate =
            |x: Id| matches!(g.op(x), Op::Mul(..)) && uses[x as usize] == in_sums[x as usize];
        let mut fused_into = vec![None; g.len()];
        let mut taken = vec![0u32; g.len()];
        for id in 0..g.len() {
            if !live[id] {
                continue;
            }
            if let Op::Add(a, b) | Op::Sub(a, b) = g.op(id as Id) {
                // a product used once first: it is fused whatever the others do
                let pick = [a, b]
                    .into_iter()
                    .filter(|&x| candidate(x))
                    .min_by_key(|&x| uses[x as usize] != 1);
                if let Some(m) = pick {
                    fused_into[id] = Some(m);
                    taken[m as usize] += 1;
                }
            }
        }
        // a product some use does not take fused (`x + x`, or a sum fusing its other
        // operand) is emitted on its own, and every sum then uses its value; such a
        // sum may fuse its other operand if that is a product used once
        let mut fused: Vec<bool> = (0..g.len())
            .map(|m| taken[m] > 0 && taken[m] == uses[m])
            .collect();
        for id in 0..g.len() {
            let Some(m) = fused_into[id] else { continue };
            if fused[m as usize] {
                continue;
            }
            fused_into[id] = None;
            if let Op::Add(a, b) | Op::Sub(a, b) = g.op(id as Id) {
                let other = if m == a { b } else { a };
                if matches!(g.op(other), Op::Mul(..))
                    && uses[other as usize] == 1
                    && !fused[other as usize]
                {
                    fused_into[id] = Some(other);
                    fused[other as usize] = true;
                }
            }
        }
        // a negated multiply-add, `-(x y + c)`, is one instruction too
        let mut negated = vec![false; g.len()];
        for id in 0..g.len() {
            if !live[id] {
                continue;
            }
            if let Op::Neg(s) = g.op(id as Id) {
                let s = s as usize;
                if matches!(g.op(s as Id), Op::Add(..)) && fused_into[s].is_some() && uses[s] == 1 {
                    negated[id] = true;
                    fused[s] = true;
                }
            }
        }
        Fusion {
            fused_into,
            fused,
            negated,
        }
    }

    /// How many products are fused among the nodes `want` (each saves one operation).
    pub fn count(&self, want: &[bool]) -> usize {
        self.fused
            .iter()
            .zip(want)
            .filter(|(f, w)| **f && **w)
            .count()
    }
}

/// Groups of reciprocals `1/x` among the nodes `want` (not yet named) that share one
/// division (Montgomery's trick): `p_i = x_1 ... x_i`, `q = 1/p_k`, then
/// `1/x_i = q_i p_(i-1)`, `q_(i-1) = q_i x_i`. A reciprocal joins the first group none of
/// whose members its argument depends on. A division costs the latency and the
/// throughput of about 16 multiplications in the vector units; the trick trades
/// `k - 1` of them for `3 (k - 1)` multiplications, at the price of about two ulps.
fn reciprocal_groups(g: &Graph, want: &[bool], name: &[Option<TokenStream>]) -> Vec<Vec<Id>> {
    let recips: Vec<Id> = (0..g.len() as Id)
        .filter(|&id| want[id as usize] && name[id as usize].is_none())
        .filter(|&id| matches!(g.op(id), Op::Div(a, _) if g.as_const(a) == Some(1.0)))
        .collect();
    if recips.len() < 2 || recips.len() > 128 {
        return Vec::new();
    }
    // dep[n]: which reciprocals node n depends on (bit k for recips[k])
    let mut dep = vec![0u128; g.len()];
    for id in 0..g.len() {
        let mut m = g
            .op(id as Id)
            .operands()
            .iter()
            .fold(0u128, |m, &a| m | dep[a as usize]);
        if let Some(k) = recips.iter().position(|&r| r == id as Id) {
            m |= 1 << k;
        }
        dep[id] = m;
    }
    let mut groups: Vec<(u128, Vec<Id>)> = Vec::new();
    for (k, &r) in recips.iter().enumerate() {
        let Op::Div(_, x) = g.op(r) else {
            unreachable!("reciprocals are divisions")
        };
        match groups
            .iter_mut()
            .find(|(mask, _)| dep[x as usize] & mask == 0)
        {
            Some((mask, members)) => {
                *mask |= 1 << k;
                members.push(r);
            }
            None => groups.push((1 << k, vec![r])),
        }
    }
    groups
        .into_iter()
        .map(|(_, m)| m)
        .filter(|m| m.len() > 1)
        .collect()
}

/// Statements of a lane kernel (generic lane type `L`, crate `lanes`) for the nodes
/// `want` not yet named: as [`statements`], with constants broadcast, comparisons as
/// per-lane blends, the products of [`Fusion`] fused into their sums, and the
/// reciprocals of [`reciprocal_groups`] sharing one division. Emitted depth first
/// (a group of reciprocals after the arguments of all its members).
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

/// The lane twin of a kernel: the same trace evaluated on `L::WIDTH` pairs at once
/// (generic over `lanes::Lane`), branch-free per lane. The exchange of roles
/// ([`crate::scene::Swap`]) becomes a per-lane exchange of the arguments and of the
/// outputs; the far branch is computed where any lane needs it and blended per lane
/// (the direct sum likewise where any lane needs it); multiply-adds are fused
/// ([`Fusion`]) and reciprocals share divisions ([`reciprocal_groups`]). Arguments are arrays of lanes in the scalar kernel's order; the
/// outputs come back flattened, in the order of the scalar kernel's fields.
/// Returns the function and its operation count (a fused multiply-add counts once).
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
    fn of(t: &crate::scene::Traced, g: &Graph, map: &[Id]) -> LaneParts {
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

/// A small expression of the graph inlined as one Rust expression (for the handful of
/// nodes in, e.g., a boundary height such as `height + gap`).
pub fn inline(g: &Graph, id: Id) -> TokenStream {
    let v = |a: Id| inline(g, a);
    match g.op(id) {
        Op::Input(i) => input_expr(g, i),
        Op::Const(b) => literal(f64::from_bits(b)),
        Op::Add(a, b) => {
            let (a, b) = (v(a), v(b));
            quote!((#a + #b))
        }
        Op::Sub(a, b) => {
            let (a, b) = (v(a), v(b));
            quote!((#a - #b))
        }
        Op::Mul(a, b) => {
            let (a, b) = (v(a), v(b));
            quote!((#a * #b))
        }
        Op::Div(a, b) => {
            let (a, b) = (v(a), v(b));
            quote!((#a / #b))
        }
        Op::Neg(a) => {
            let a = v(a);
            quote!((-#a))
        }
        Op::Sqrt(a) => {
            let a = v(a);
            quote!(#a.sqrt())
        }
        Op::Rsqrt(a) => {
            let a = v(a);
            quote!((1.0 / #a.sqrt()))
        }
        Op::Powi(a, n) => {
            let a = v(a);
            let n = Literal::i32_unsuffixed(n);
            quote!(#a.powi(#n))
        }
        Op::Select(l, r, a, b) => {
            let (l, r, a, b) = (v(l), v(r), v(a), v(b));
            quote!((if #l > #r { #a } else { #b }))
        }
    }
}

/// Nested array literal of `vals` (row-major) with the given shape.
fn nest(vals: &[TokenStream], shape: &[usize]) -> TokenStream {
    if shape.len() <= 1 {
        return quote!([#(#vals),*]);
    }
    let inner: usize = shape[1..].iter().product();
    let parts: Vec<TokenStream> = vals.chunks(inner).map(|c| nest(c, &shape[1..])).collect();
    quote!([#(#parts),*])
}

/// A whole generated file: the header that marks it generated, then `items`.
pub fn file(module_doc: &[String], items: TokenStream) -> String {
    let docs: Vec<TokenStream> = module_doc
        .iter()
        .map(|d| {
            let d = format!(" {d}");
            quote!(#![doc = #d])
        })
        .collect();
    let ts = quote! {
        #(#docs)*
        #items
    };
    let parsed: syn::File = syn::parse2(ts).expect("emitted tokens parse as a Rust file");
    let body = prettyplease::unparse(&parsed);
    format!(
        "// @generated by `cargo xtask gen` from kernel-gen. Do not edit by hand: edit the\n\
         // generator and regenerate; `cargo xtask gen --check` fails when this file is stale.\n\n{body}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_round_trip() {
        for c in [1.0 / 3.0, -2.5, 1e-300, 6.02e23, 0.1] {
            let s = literal(c).to_string().replace([' ', '(', ')'], "");
            let back: f64 = s.parse().unwrap();
            assert_eq!(back, c, "{s}");
        }
    }

    #[test]
    fn a_negated_multiply_add_is_one_operation() {
        use crate::expr::Trace;
        let t = Trace::begin();
        let (x, y, z) = (t.input("x"), t.input("y"), t.input("z"));
        let s = x * y + z;
        let n = -s;
        let g = t.finish();
        let f = Fusion::of(&g, &g.live(&[n.0]), &[n.0]);
        assert!(f.negated[n.0 as usize], "-(x y + z) is one neg_mul_sub");
        assert!(f.fused[s.0 as usize], "and the sum is not emitted");
        assert_eq!(
            f.count(&g.live(&[n.0])),
            2,
            "of three operations, two saved"
        );
        // a sum that is an output itself is kept, and its negation with it
        let both = [n.0, s.0];
        let f = Fusion::of(&g, &g.live(&both), &both);
        assert!(!f.negated[n.0 as usize] && !f.fused[s.0 as usize]);
    }
}
