//! The LS-DYNA keyword deck reader: lexing, field decoding, and building a `Model`.
