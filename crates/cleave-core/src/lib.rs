//! cleave-core: the numerical core of cleave, an explicit finite-element code for transient
//! dynamics of solids (8-node hexahedra, one-point integration, central differences).
//!
//! The data falls in three kinds (see `shared/design/architecture.md`):
//! - [`model::Model`]: what never changes during a run (mesh, materials, loads, controls);
//! - [`state::State`]: what a step changes (time, positions, velocities, stresses, energies);
//! - scratch buffers inside the solver, never saved.
//!
//! Deck ids appear only in the model's id tables and in messages; everything else uses dense
//! internal indices (`u32` for nodes and elements, `usize` for parts, materials, curves).
//!
//! The module docs explain the algorithms down to private helpers and link to them: read them
//! with `cargo doc --document-private-items` (CI builds them so, warnings denied).

// NOTE: the links to private items resolve in the private docs, which are the ones to read
#![allow(rustdoc::private_intra_doc_links)]

pub mod awake;
pub mod contact;
pub mod curve;
pub mod element;
pub mod erosion;
pub mod error;
pub mod loads;
pub mod material;
pub mod math;
pub mod mesh;
pub mod model;
pub mod node_values;
pub mod per_node;
pub mod rigid;
pub mod separation;
pub mod setup;
pub mod solver;
pub mod state;
pub mod tied;
pub mod topology;
