//! Emission of traced kernels as flat Rust: one `let` per live node of the expression
//! graph, in topological order, built with `quote` and formatted by `prettyplease`.
//! No loops, no heap, no jets at run time. Output is deterministic: node order is
//! creation order, constants print in Rust's shortest round-trip form.
//!
//! - `tokens`: literals, names, parameters, documentation, nested arrays, and the
//!   generated file with its header;
//! - `function`: the scalar kernel ([`function()`]), in `f64` or `f32`;
//! - `lanes`: its lane twin ([`lane_function`]), generic over `lanes::Lane`;
//! - `fusion`: the fused multiply-adds of the lane kernels ([`Fusion`]);
//! - `reciprocals`: the reciprocals of a lane kernel that share one division.

mod function;
mod fusion;
mod lanes;
mod reciprocals;
mod tokens;

pub use function::function;
pub use fusion::Fusion;
pub use lanes::lane_function;
pub(crate) use tokens::ident;
pub use tokens::{file, inline, literal};

use crate::kernel::Traced;
use proc_macro2::TokenStream;
use quote::quote;

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
