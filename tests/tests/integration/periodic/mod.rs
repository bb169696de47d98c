//! Triply periodic boxes ([`stokesian::periodic`]): the Ewald sums against Hasimoto's
//! periodic self mobility and against the windowed sum over replicas of the open RPY
//! mobility (`ewald`); the split parameter changes nothing; the system's matrices,
//! products and refusals (`system`). Boxes periodic along a wall: the Ewald sums against
//! the brute-force sum over shells of the open wall's images, and the system (`wall`).

mod ewald;
mod system;
mod wall;
