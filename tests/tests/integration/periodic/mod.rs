//! Triply periodic boxes ([`stokesian::periodic`]): the Ewald sums against Hasimoto's
//! periodic self mobility and against the windowed sum over replicas of the open RPY
//! mobility (`ewald`); the split parameter changes nothing; the system's matrices,
//! products and refusals (`system`); the resistance with lubrication over every image
//! (`lubrication`).

mod ewald;
mod lubrication;
mod system;
