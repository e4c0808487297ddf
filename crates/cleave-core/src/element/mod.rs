//! The 8-node hexahedron: geometry ([`hex8`]) and the one-point force kernel with
//! Flanagan-Belytschko hourglass control ([`kernel`]); the colours of element chunks that let
//! the element pass add its forces into the nodes on all cores ([`colouring`]).

pub mod colouring;
pub mod hex8;
pub mod kernel;
