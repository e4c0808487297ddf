//! The 8-node hexahedron: geometry ([`hex8`]) and the one-point force kernel with
//! Flanagan-Belytschko hourglass control ([`kernel`]).

pub mod hex8;
pub mod kernel;
