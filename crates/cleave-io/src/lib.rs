//! cleave-io: the LS-DYNA keyword deck reader ([`deck`]), the Gmsh mesh reader ([`gmsh`]) and
//! the result writers ([`output`]).

pub mod deck;
pub mod gmsh;
pub mod output;
