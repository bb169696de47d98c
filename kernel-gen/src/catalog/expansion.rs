//! `potential.rs`: what a fast multipole method needs of each confinement. Its far field
//! as derivative sources of the potential `|r|` ([`crate::physics::potential`]) for the
//! forces and for forces and torques, its mirrors (the image points' planes) and the
//! weights of its image terms as functions of its parameters, and the radial
//! derivatives of the potential.

use super::dispatch::{camel, vector};
use super::Family;
use crate::emit::ident;
use crate::number::dd::Dd;
use crate::number::jet::{Jet, Layout};
use crate::number::scalar::Scalar;
use crate::physics::potential::{NoExpansion, PotentialSource};
use proc_macro2::{Literal, TokenStream};
use quote::quote;

/// The highest derivative of the potential [`RADIAL`] serves: the expansions' order plus
/// the highest derivative of a source and of the field point's functional.
pub const MAX_DERIVATIVE: usize = 32;

/// A family's expansion, from its Green's function (`Collect::visit`).
pub(super) struct Expansion {
    /// The sources of the forces, of forces and torques, and of the divergence over the
    /// source's position, or why there are none.
    pub sources: Result<[Vec<PotentialSource>; 3], NoExpansion>,
    /// Each mirror: its normal and its offset as an expression of the parameters.
    pub mirrors: Vec<([f64; 3], TokenStream)>,
    /// The weights of the image terms as expressions of the parameters.
    pub weights: Vec<TokenStream>,
}

/// `d^n/ds^n s^(1/2)` at `s = 1`, `n = 0..=MAX_DERIVATIVE`: with them the derivatives of
/// `|r| = s^(1/2)` at any `s` are `c_n s^(1/2 - n)` (the potential is homogeneous).
/// Taken from a jet of `sqrt` in double-double.
fn radial() -> Vec<f64> {
    let layout = Layout::get(1, MAX_DERIVATIVE);
    let s = Jet::variable(&layout, 0, Dd::new(1.0));
    let r = s.sqrt();
    (0..=MAX_DERIVATIVE)
        .map(|n| r.derivative(&[n as u8]).to_f64())
        .collect()
}

fn source_literal(s: &PotentialSource) -> TokenStream {
    let (channel, moment, point) = (s.channel, s.moment, s.point);
    let weight = s.weight.unwrap_or(0);
    let (h_power, a2) = (s.h_power, s.a2);
    let [d0, d1, d2] = s.d;
    let coef = Literal::f64_suffixed(s.coef);
    quote!(s(#channel, #moment, #point, #weight, #h_power, #a2, [#d0, #d1, #d2], #coef))
}

/// The file `potential.rs`.
pub(super) fn potential_file(families: &[Family]) -> TokenStream {
    let mut tables = Vec::new();
    let mut source_arms = Vec::new();
    let mut divergence_arms = Vec::new();
    let mut mirror_arms = Vec::new();
    let mut weight_arms = Vec::new();
    for f in families {
        let v = ident(&camel(f.name));
        let fields: Vec<proc_macro2::Ident> = f.params.iter().map(|p| ident(p.name)).collect();
        let pattern = if fields.is_empty() {
            quote!(Confinement::#v)
        } else {
            quote!(Confinement::#v { #(#fields),* })
        };
        let any = if fields.is_empty() {
            quote!(Confinement::#v)
        } else {
            quote!(Confinement::#v { .. })
        };
        let e = &f.expansion;
        match &e.sources {
            Ok([forces, torques, divergence]) => {
                let upper = f.name.to_uppercase();
                let (nf, nt) = (ident(&format!("{upper}_F")), ident(&format!("{upper}_FT")));
                let nd = ident(&format!("{upper}_DIVERGENCE"));
                let (lf, lt, ld) = (forces.len(), torques.len(), divergence.len());
                let dd = format!(
                    " The far field of the divergence of `{}`'s mobility over the source's position (unit sources).",
                    f.name
                );
                let sd = divergence.iter().map(source_literal);
                let (df, dt) = (
                    format!(" The far field of `{}`'s forces.", f.name),
                    format!(" The far field of `{}`'s forces and torques.", f.name),
                );
                let (sf, st) = (
                    forces.iter().map(source_literal),
                    torques.iter().map(source_literal),
                );
                tables.push(quote! {
                    #[doc = #df]
                    static #nf: [S; #lf] = [#(#sf),*];
                    #[doc = #dt]
                    static #nt: [S; #lt] = [#(#st),*];
                    #[doc = #dd]
                    static #nd: [S; #ld] = [#(#sd),*];
                });
                source_arms.push(quote!(#any => Ok(if torques { &#nt } else { &#nf })));
                divergence_arms.push(quote!(#any => Ok(&#nd)));
            }
            Err(why) => {
                let why = ident(match why {
                    NoExpansion::NoImageTerms => "NoImageTerms",
                    NoExpansion::OtherPotential => "OtherPotential",
                });
                source_arms.push(quote!(#any => Err(crate::expansion::NoExpansion::#why)));
                divergence_arms.push(quote!(#any => Err(crate::expansion::NoExpansion::#why)));
            }
        }
        let mirrors = e.mirrors.iter().map(|(n, offset)| {
            let n = vector(*n);
            quote!(crate::expansion::Mirror { normal: #n, offset: #offset })
        });
        let weights = &e.weights;
        let bind = quote!(let _ = (#(#fields,)*););
        mirror_arms.push(quote!(#pattern => { #bind vec![#(#mirrors),*] }));
        weight_arms.push(quote!(#pattern => { #bind vec![#(#weights),*] }));
    }
    let radial = radial().into_iter().map(Literal::f64_suffixed);
    let len = MAX_DERIVATIVE + 1;
    quote! {
        use super::Confinement;
        use crate::expansion::PotentialSource as S;

        /// A row of the tables: `channel, moment, point, weight, h_power, a2, d, coef`.
        #[allow(clippy::too_many_arguments)]
        const fn s(channel: usize, moment: usize, point: usize, weight: usize, h_power: u8, a2: u8, d: [u8; 3], coef: f64) -> S {
            S { channel, moment, point, weight, h_power, a2, d, coef }
        }

        /// `d^n/ds^n s^(1/2)` at `s = 1`: the derivatives of the potential `|r| = s^(1/2)`
        /// are `RADIAL[n] s^(1/2 - n)`.
        pub static RADIAL: [f64; #len] = [#(#radial),*];

        #(#tables)*

        impl Confinement {
            /// The far field as derivative sources of the potential `|r|`
            /// ([`crate::expansion`]): of the forces, or (`torques`) of forces and torques.
            pub fn potential_sources(&self, torques: bool) -> Result<&'static [S], crate::expansion::NoExpansion> {
                let _ = torques;
                match *self {
                    #(#source_arms),*
                }
            }

            /// The far field of the divergence of the mobility over the source's position
            /// (`sum_l d M_kl / d y_l`, the Brownian drift's pair terms) as derivative
            /// sources of `|r|` ([`crate::expansion`]), every row `moment = 0`: a unit
            /// source.
            pub fn divergence_sources(&self) -> Result<&'static [S], crate::expansion::NoExpansion> {
                match *self {
                    #(#divergence_arms),*
                }
            }

            /// The mirrors of the image points, in the order of
            /// [`crate::expansion::PotentialSource::point`] (`point = 1 + k`).
            pub fn mirrors(&self) -> Vec<crate::expansion::Mirror> {
                match *self {
                    #(#mirror_arms),*
                }
            }

            /// The weights of the image terms
            /// ([`crate::expansion::PotentialSource::weight`]).
            pub fn image_weights(&self) -> Vec<f64> {
                match *self {
                    #(#weight_arms),*
                }
            }
        }
    }
}
