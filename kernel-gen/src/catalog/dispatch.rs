//! The generated `mod.rs`: the `Confinement` enum, one variant per family with its
//! run-time parameters, and the entry points that dispatch on it (a serving scene's
//! kernels where one exists, the family's FTS kernels truncated otherwise).

use super::{blocks_type, moments_label, Family, Moments};
use crate::emit::ident;
use crate::physics::green;
use proc_macro2::TokenStream;
use quote::quote;

/// An `f64` literal.
fn lit(v: f64) -> proc_macro2::Literal {
    proc_macro2::Literal::f64_suffixed(v)
}

/// `[n0, n1, n2]` as tokens.
pub(super) fn vector(n: [f64; 3]) -> TokenStream {
    let [a, b, c] = n.map(lit);
    quote!([#a, #b, #c])
}

/// `d . origin` as tokens, skipping zero components (`e3 . origin` is `origin[2]`).
fn dot_origin(d: [f64; 3]) -> TokenStream {
    let terms: Vec<TokenStream> = (0..3)
        .filter(|&k| d[k] != 0.0)
        .map(|k| {
            if d[k] == 1.0 {
                quote!(origin[#k])
            } else if d[k] == -1.0 {
                quote!((-origin[#k]))
            } else {
                let c = lit(d[k]);
                quote!(#c * origin[#k])
            }
        })
        .collect();
    if terms.is_empty() {
        quote!(0.0)
    } else {
        quote!(#(#terms)+*)
    }
}

/// A parameter's declaration as a `kernels::declare::Param` literal.
fn param_decl(p: &green::Param) -> TokenStream {
    let (name, doc, example) = (p.name, p.doc, lit(p.example));
    let dimension = match p.dimension {
        green::Dimension::Position(d) => {
            let d = vector(d);
            quote!(crate::declare::Dimension::Position(#d))
        }
        green::Dimension::Length => quote!(crate::declare::Dimension::Length),
        green::Dimension::Number => quote!(crate::declare::Dimension::Number),
    };
    let default = match p.default {
        Some(v) => {
            let v = lit(v);
            quote!(Some(#v))
        }
        None => quote!(None),
    };
    quote!(crate::declare::Param { name: #name, doc: #doc, dimension: #dimension, default: #default, example: #example })
}

pub(super) fn camel(snake: &str) -> String {
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

/// The pattern of a family's arm in an entry point: its variant, or that of any twin it
/// serves, each binding its parameters under the family's names (`path` names the
/// enum).
fn serving_pattern(f: &Family, families: &[Family], path: TokenStream) -> TokenStream {
    let binding = |g: &Family| {
        let v = ident(&camel(g.name));
        if f.params.is_empty() {
            return quote!(#path::#v);
        }
        let bindings = g.params.iter().zip(f.params).map(|(own, p)| {
            let (own, p) = (ident(own.name), ident(p.name));
            if own == p {
                quote!(#p)
            } else {
                quote!(#own: #p)
            }
        });
        quote!(#path::#v { #(#bindings),* })
    };
    let twins = families
        .iter()
        .filter(|t| t.twin.as_ref().is_some_and(|t| t.of == f.name));
    let alternatives = std::iter::once(binding(f)).chain(twins.map(binding));
    quote!(#(#alternatives)|*)
}

/// The body of an entry point: the confinement that serves `conf` and the rotation into
/// its planes' frame where `conf` is a twin (`Confinement::served`), the arguments
/// `turned` (`(name, Turn method)`: `point` for points and directions, `moments` for
/// moments) into that frame, the `arms` matched on the serving confinement, and their
/// `out` back to the world by `back`. One call of each serving kernel, so that the solver
/// compiles it once for the family and its twins.
fn served(turned: &[(&str, &str)], arms: &[TokenStream], back: TokenStream) -> TokenStream {
    let names: Vec<proc_macro2::Ident> = turned.iter().map(|(n, _)| ident(n)).collect();
    let methods: Vec<proc_macro2::Ident> = turned.iter().map(|(_, m)| ident(m)).collect();
    quote! {
        let (conf, turn) = conf.served();
        let conf = &conf;
        let (#(#names,)*) = match turn {
            Some(t) => (#(t.#methods(#names),)*),
            None => (#(#names,)*),
        };
        let out = match *conf { #(#arms),* };
        match turn { Some(t) => #back, None => out }
    }
}

/// The `Confinement` enum, one variant per family with its run-time parameters as
/// fields, and the dispatching entry points `pair`, `pair_equal`, `self_mobility`.
pub(super) fn dispatch(families: &[Family]) -> TokenStream {
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
    let mut normal_arms = Vec::new();
    let mut declarations = Vec::new();
    let mut div_self_arms = Vec::new();
    let mut along_pair_arms = Vec::new();
    let mut along_self_arms = Vec::new();
    let mut truncated: Vec<Vec<TokenStream>> = Vec::new();
    let mut served_arms = Vec::new();
    let mut turns = Vec::new();
    for f in families {
        let v = ident(&camel(f.name));
        let m = ident(f.name);
        let name = f.name;
        let doc = format!(" {}", f.title);
        let fields: Vec<proc_macro2::Ident> = f.params.iter().map(|p| ident(p.name)).collect();
        let field_docs: Vec<String> = f.params.iter().map(|p| format!(" {}", p.doc)).collect();
        let decls: Vec<TokenStream> = f.params.iter().map(param_decl).collect();
        let title = f.title;
        declarations.push(quote!(crate::declare::Declaration { name: #name, title: #title, params: &[#(#decls),*] }));
        let idx: Vec<usize> = (0..f.params.len()).collect();
        let nparams = f.params.len();
        let (fpair, fequal, fself) = (
            ident(&format!("{}_pair", f.name)),
            ident(&format!("{}_pair_equal", f.name)),
            ident(&format!("{}_self", f.name)),
        );
        let pname: Vec<&str> = f.params.iter().map(|p| p.name).collect();
        let bounds: Vec<TokenStream> = f
            .boundaries
            .iter()
            .map(|b| {
                let normal = vector(b.plane.normal);
                let offset = &b.plane.offset;
                let condition = ident(match b.condition {
                    green::Condition::NoSlip => "NoSlip",
                    green::Condition::FreeSurface => "FreeSurface",
                    green::Condition::Interface => "Interface",
                });
                let exact = b.exact;
                quote!(crate::declare::Boundary { normal: #normal, offset: #offset, condition: crate::declare::Condition::#condition, exact: #exact })
            })
            .collect();
        if fields.is_empty() {
            variants.push(quote!(#[doc = #doc] #v));
            name_arms.push(quote!(Confinement::#v => #name));
            from_arms.push(quote!(#name if params.is_empty() => Some(Confinement::#v)));
            param_arms.push(quote!(Confinement::#v => vec![]));
            bound_arms.push(quote!(Confinement::#v => vec![#(#bounds),*]));
            unit_arms.push(quote!(Confinement::#v => Confinement::#v));
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
                .zip(f.params)
                .map(|(p, d)| match d.dimension {
                    green::Dimension::Position(d) => {
                        let o = dot_origin(d);
                        quote!(#p: (#p - #o) / unit)
                    }
                    green::Dimension::Length => quote!(#p: #p / unit),
                    green::Dimension::Number => quote!(#p),
                })
                .collect();
            unit_arms
                .push(quote!(Confinement::#v { #(#fields),* } => Confinement::#v { #(#scaled),* }));
        }
        names.push(name);
        let any = if fields.is_empty() {
            quote!(Confinement::#v)
        } else {
            quote!(Confinement::#v { .. })
        };
        let exchanges = f.exchanges.is_some();
        exchange_arms.push(quote!(#any => #exchanges));
        let normal = match f.exchanges {
            Some(n) => {
                let n = vector(n);
                quote!(Some(#n))
            }
            None => quote!(None),
        };
        normal_arms.push(quote!(#any => #normal));
        if let Some(t) = &f.twin {
            // a twin: served by the kernels of `t.of`, turned (kernels::turn)
            let (of, of_fields) = (
                ident(&camel(t.of)),
                t.of_params.iter().map(|p| ident(p)).collect::<Vec<_>>(),
            );
            let konst = ident(&format!("{}_TURN", f.name.to_uppercase()));
            let q = t.q.map(|r| r.map(lit));
            let q = q.map(|r| quote!([#(#r),*]));
            let q5 = t.q5.map(|r| r.map(lit));
            let q5 = q5.map(|r| quote!([#(#r),*]));
            let d = format!(
                " `{}` in the frame of its planes, where it is `{}` (kernel_gen `catalog::twin`).",
                f.name, t.of
            );
            turns.push(quote! {
                #[doc = #d]
                static #konst: crate::turn::Turn = crate::turn::Turn { q: [#(#q),*], q5: [#(#q5),*] };
            });
            let target = if fields.is_empty() {
                quote!(Confinement::#of)
            } else {
                quote!(Confinement::#of { #(#of_fields: #fields),* })
            };
            let own = if fields.is_empty() {
                quote!(Confinement::#v)
            } else {
                quote!(Confinement::#v { #(#fields),* })
            };
            served_arms.push(quote!(#own => (#target, Some(&#konst))));
            continue;
        }
        let pattern = serving_pattern(f, families, quote!(Confinement));
        pair_arms.push(quote!(#pattern => #m::#fpair(xa, xb, aa, ab, eta, #(#fields),*)));
        equal_arms.push(quote!(#pattern => #m::#fequal(xa, xb, a, eta, #(#fields),*)));
        self_arms.push(quote!(#pattern => #m::#fself(x, a, eta, #(#fields),*)));
        let (fdp, fds) = (
            ident(&format!("{}_pair_divergence", f.name)),
            ident(&format!("{}_self_divergence", f.name)),
        );
        div_pair_arms.push(quote!(#pattern => #m::#fdp(xa, xb, aa, ab, eta, #(#fields),*)));
        let (fap, fas) = (
            ident(&format!("{}_pair_along", f.name)),
            ident(&format!("{}_self_along", f.name)),
        );
        along_pair_arms.push(quote!(#pattern => #m::#fap(xa, xb, aa, ab, eta, #(#fields,)* v)));
        along_self_arms.push(quote!(#pattern => #m::#fas(x, a, eta, #(#fields,)* v)));
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
        let to_world = ident(&format!("blocks_{lo}"));
        let flat_at = ident(&format!("{}_FLAT", moments_label(moments)));
        let pts: &[(&str, &str)] = &[("xa", "point"), ("xb", "point")];
        let pts_moments: &[(&str, &str)] = &[
            ("xa", "point"),
            ("xb", "point"),
            ("va", "moments"),
            ("vb", "moments"),
        ];
        let body_pair = served(pts, &arms_pair, quote!(t.#to_world(out)));
        let self_to_world = ident(&format!("self_{lo}"));
        let body_self = served(&[("x", "point")], &arms_self, quote!(t.#self_to_world(out)));
        let body_prod = served(pts_moments, &arms_prod, quote!(t.product(out)));
        let both_len = 2 * n;
        let both = quote!(t.both::<L, #n, #both_len>(out));
        let body_lanes = served(pts_moments, &arms_lanes, both.clone());
        let body_ordered = served(pts_moments, &arms_ordered, both);
        let body_blocks = served(
            pts,
            &arms_blocks,
            quote!(t.blocks(out, &crate::blocks::#flat_at)),
        );
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
                #body_pair
            }
            #[doc = #d_self]
            pub fn #fself(conf: &Confinement, eta: f64, x: [f64; 3], a: f64) -> #ty {
                #body_self
            }
            #[doc = #d_prod]
            pub fn #fprod(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64, va: [f64; #n], vb: [f64; #n]) -> Product<#n> {
                #body_prod
            }
            #[doc = #d_lanes]
            #[inline(always)]
            pub fn #flanes<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L, va: [L; #n], vb: [L; #n]) -> [L; #n2] {
                #body_lanes
            }
            #[doc = #d_ordered]
            #[inline(always)]
            pub fn #fordered<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L, va: [L; #n], vb: [L; #n]) -> [L; #n2] {
                #body_ordered
            }
            #[doc = #d_blocks]
            #[inline(always)]
            pub fn #fblocks<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L) -> [L; #nn] {
                #body_blocks
            }
        });
    }
    let pts: &[(&str, &str)] = &[("xa", "point"), ("xb", "point")];
    let div_pair = served(pts, &div_pair_arms, quote!(t.product(out)));
    let div_lanes = served(pts, &div_lane_arms, quote!(t.both::<L, 6, 12>(out)));
    let div_ordered = served(pts, &div_ordered_arms, quote!(t.both::<L, 6, 12>(out)));
    let pair_lanes = served(
        pts,
        &pair_lane_arms,
        quote!(t.blocks(out, &crate::blocks::GRAND_FLAT)),
    );
    let div_self = served(&[("x", "point")], &div_self_arms, quote!(t.drift(out)));
    let along_pair = served(
        &[("xa", "point"), ("xb", "point"), ("v", "point")],
        &along_pair_arms,
        quote!(t.product(out)),
    );
    let along_self = served(
        &[("x", "point"), ("v", "point")],
        &along_self_arms,
        quote!(t.drift(out)),
    );
    let pair = served(pts, &pair_arms, quote!(t.grand(out)));
    let equal = served(pts, &equal_arms, quote!(t.grand(out)));
    let self_mobility = served(&[("x", "point")], &self_arms, quote!(t.self_grand(out)));
    let served_match = if served_arms.is_empty() {
        quote!((*self, None))
    } else {
        quote!(match *self { #(#served_arms,)* other => (other, None) })
    };
    quote! {
        use crate::blocks::{BlocksF, BlocksFT, Drift, Grand, Product};

        #(#turns)*

        #(#truncated_fns)*

        /// The Brownian drift of a pair: `a` = the divergence of `M^{ab}` over the
        /// position of `b` (`sum_j d/dxb_j M_{ij}`, rows U then Omega, force columns),
        /// `b` = that of `M^{ba}` over the position of `a`.
        pub fn pair_divergence(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64) -> Product<6> {
            #div_pair
        }

        /// The lane twin of [`pair_divergence`]: `L::WIDTH` pairs at once, `a` then `b`.
        #[inline(always)]
        pub fn pair_divergence_lanes<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L) -> [L; 12] {
            #div_lanes
        }

        /// [`pair_divergence_lanes`] without the exchange of roles: for pairs in which `b`
        /// is no higher than `a` ([`Confinement::exchanges_by_height`]).
        #[inline(always)]
        pub fn pair_divergence_lanes_ordered<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L) -> [L; 12] {
            #div_ordered
        }

        /// The lane twin of [`pair`] without the exchange of roles: `L::WIDTH` pairs at
        /// once, for pairs in which `b` is no higher than `a` where
        /// [`Confinement::exchanges_by_height`] (elsewhere any order); the 121 entries of
        /// [`Grand`]'s fields in their order (see [`crate::blocks::grand_lanes_product`]).
        #[inline(always)]
        pub fn pair_lanes_ordered<L: lanes::Lane>(conf: &Confinement, eta: f64, xa: [L; 3], aa: L, xb: [L; 3], ab: L) -> [L; 121] {
            #pair_lanes
        }

        /// The Brownian drift of one particle's self mobility: `sum_j d/dx_j M^{aa}_{ij}`,
        /// rows U then Omega, force columns.
        pub fn self_divergence(conf: &Confinement, eta: f64, x: [f64; 3], a: f64) -> Drift<6> {
            #div_self
        }

        /// The derivative of a pair's blocks along a unit vector `v` of their column along
        /// `v` (rows U then Omega, force columns): `a = sum_jk v_j v_k d/dxb_k M^{ab}_{ij}`,
        /// `b` that of `M^{ba}` over the position of `a`. The part of the divergence that
        /// holding the moving sphere's centre on a plane of normal `v` removes.
        pub fn pair_along(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64, v: [f64; 3]) -> Product<6> {
            #along_pair
        }

        /// [`pair_along`] for one particle's self mobility, its position moving:
        /// `sum_jk v_j v_k d/dx_k M^{aa}_{ij}`.
        pub fn self_along(conf: &Confinement, eta: f64, x: [f64; 3], a: f64, v: [f64; 3]) -> Drift<6> {
            #along_self
        }

        /// What every registered confinement declares: name, title, parameters, in the
        /// order of [`Confinement::NAMES`].
        pub static DECLARATIONS: &[crate::declare::Declaration] = &[#(#declarations),*];

        /// The confinement and its run-time parameters, one variant per registered
        /// Green's function ([`DECLARATIONS`]); its planes are [`Confinement::boundaries`].
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
            /// (farther from the cancelling plane along [`Confinement::exchange_normal`],
            /// `x3` for a wall) than `a`, keeping the accuracy of the direct sum
            /// (`M^{ab} = (M^{ba})^T`, evaluated with the lower particle as the source).
            /// The `*_lanes_ordered` kernels skip that exchange: a caller that orders the
            /// particles by `x3`, highest first, and passes the earlier one as `a` gets
            /// the same values with fewer operations.
            pub fn exchanges_by_height(&self) -> bool {
                match *self {
                    #(#exchange_arms),*
                }
            }

            /// The direction along which [`Confinement::exchanges_by_height`] compares
            /// the particles (the normal of the plane whose image cancels the
            /// Stokeslet), if the pair kernels exchange roles.
            pub fn exchange_normal(&self) -> Option<[f64; 3]> {
                match *self {
                    #(#normal_arms),*
                }
            }

            /// The confinement whose kernels serve this one, and the rotation into the
            /// frame of its planes where this one is that confinement turned (a twin,
            /// [`crate::turn`]); itself and `None` otherwise.
            pub fn served(&self) -> (Confinement, Option<&'static crate::turn::Turn>) {
                #served_match
            }

            /// Its parameters' declarations ([`DECLARATIONS`]).
            pub fn declaration(&self) -> &'static crate::declare::Declaration {
                let name = self.name();
                DECLARATIONS.iter().find(|d| d.name == name).expect("every confinement is declared")
            }

            /// The planes that confine the fluid, each with its condition.
            pub fn boundaries(&self) -> Vec<crate::declare::Boundary> {
                match *self {
                    #(#bound_arms),*
                }
            }

            /// The same confinement with lengths measured in units of `unit` and
            /// positions from `origin`: a position `p` along the direction `d`
            /// becomes `(p - d . origin) / unit`, a length `l / unit`; pure numbers
            /// stay. With the viscosity as the unit of viscosity, a mobility block
            /// coupling a moment of length dimension `p` (force 0; torque, stresslet 1)
            /// to a response of dimension `q` (velocity 0; rotation, strain 1) becomes
            /// `eta unit^(1 + p + q)` times itself.
            pub fn in_units(&self, origin: [f64; 3], unit: f64) -> Confinement {
                let _ = (origin, unit);
                match *self {
                    #(#unit_arms),*
                }
            }
        }

        /// `M^{ab}` for two distinct particles: the response of particle `a` (centre
        /// `xa`, radius `aa`) to the force, torque and stresslet of particle `b`.
        pub fn pair(conf: &Confinement, eta: f64, xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64) -> Grand {
            #pair
        }

        /// `M^{ab}` for two distinct particles of the same radius `a`.
        pub fn pair_equal(conf: &Confinement, eta: f64, xa: [f64; 3], xb: [f64; 3], a: f64) -> Grand {
            #equal
        }

        /// `M^{aa}`: the isolated sphere plus its reflected field (Eq. 17).
        pub fn self_mobility(conf: &Confinement, eta: f64, x: [f64; 3], a: f64) -> Grand {
            #self_mobility
        }
    }
}

/// The single-precision entry points of `single.rs`, dispatching on the confinement
/// (its parameters rounded to `f32`) like [`dispatch`]'s `self_mobility` and `pair`.
pub(super) fn single_dispatch(families: &[Family]) -> TokenStream {
    let mut self_arms = Vec::new();
    let mut pair_arms = Vec::new();
    for f in families.iter().filter(|f| f.twin.is_none()) {
        let fields: Vec<proc_macro2::Ident> = f.params.iter().map(|p| ident(p.name)).collect();
        let (fself, fpair) = (
            ident(&format!("{}_self", f.name)),
            ident(&format!("{}_pair", f.name)),
        );
        let pattern = serving_pattern(f, families, quote!(crate::Confinement));
        self_arms.push(quote!(#pattern => #fself(x, a, eta, #(#fields as f32),*)));
        pair_arms.push(quote!(#pattern => #fpair(xa, xb, aa, ab, eta, #(#fields as f32),*)));
    }
    let back = quote!(Grand32::from_flat(
        &t.blocks(out.flat(), &crate::blocks::GRAND_FLAT)
    ));
    let back_self = quote!(Grand32::from_flat(&crate::turn::symmetric(
        t.blocks(out.flat(), &crate::blocks::GRAND_FLAT),
        &crate::blocks::GRAND_FLAT
    )));
    let body_self = served(&[("x", "point")], &self_arms, back_self);
    let body_pair = served(&[("xa", "point"), ("xb", "point")], &pair_arms, back);
    quote! {
        /// The single-precision self kernel of a confinement (its parameters rounded to `f32`).
        pub fn self_mobility(conf: &crate::Confinement, x: [f32; 3], a: f32, eta: f32) -> Grand32 {
            #body_self
        }
        /// The single-precision pair kernel of a confinement (its parameters rounded to `f32`).
        pub fn pair(conf: &crate::Confinement, xa: [f32; 3], xb: [f32; 3], aa: f32, ab: f32, eta: f32) -> Grand32 {
            #body_pair
        }
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
