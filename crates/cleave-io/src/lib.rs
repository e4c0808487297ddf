//! cleave-io: the LS-DYNA keyword deck reader and the result writers.
