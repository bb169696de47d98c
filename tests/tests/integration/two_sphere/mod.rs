//! The exact two-sphere resistance functions (`stokesian::resistance::two_sphere`) against
//! independent references, and the tables generated from them.

mod exact;
mod tables;
