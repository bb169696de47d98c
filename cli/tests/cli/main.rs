//! End-to-end tests of the `stokesian` command: outputs equal the library to full
//! precision, and every bad input gets a clear message, a non-zero exit status and no
//! output file.
//!
//! One test binary (each costs CI link time), one module per subcommand; `inputs` holds
//! the tests of the inputs every subcommand shares, `confinements` those of the
//! declared confinements (the listing, a confinement no code of the command names),
//! `common` the helpers.

mod brownian;
mod common;
mod confinements;
mod doublet;
mod inputs;
mod mobility;
mod resistance;
mod velocity;
