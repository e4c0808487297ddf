//! cleave-io: the LS-DYNA keyword deck reader ([`deck`]) and the result writers ([`output`]).

pub mod deck;
pub mod output;
