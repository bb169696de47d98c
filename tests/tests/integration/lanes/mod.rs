//! The lane kernels and the tiled product built on them: lanes equal the scalar kernels on
//! every instruction set, the tiled product equals the dense matrix whatever the number of
//! threads, and the single-precision product with the change of units it rests on.

mod layout;
mod scalar;
mod single_precision;
mod tiled_product;
