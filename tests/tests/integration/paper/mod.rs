//! Swan & Brady (2007) itself: the closed forms of Appendices B and C and their errata,
//! the asymmetry of Sec. III A, and the co-rotating doublet of Sec. III B.

mod appendices;
mod bossis_asymmetry;
mod corrected;
mod doublet;
