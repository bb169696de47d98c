//! Studies of the paper built on the solver: the co-rotating doublet of Swan & Brady,
//! Sec. III B ([`doublet`]).

pub mod doublet;
