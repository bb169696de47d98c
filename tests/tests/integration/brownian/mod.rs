//! Brownian dynamics, validated statistically with fixed seeds: near a wall with the
//! far-field mobility, and with lubrication (Brownian Stokesian dynamics).

mod dynamics;
mod lubricated;
mod settings;
