//! Tests of the result writers (`cleave_io::output`), each in its own file under `output/`.
//!
//! The `readers` tests check the VTK files with independent readers (Python's meshio 5.3 and,
//! where installed, VTK's own Python package); each prints `SKIPPED: ...` to stderr and passes
//! when its reader is missing.

#[path = "output/common.rs"]
mod common;
#[path = "output/csv.rs"]
mod csv;
#[path = "output/plot.rs"]
mod plot;
#[path = "output/readers.rs"]
mod readers;
#[path = "output/summary.rs"]
mod summary;
#[path = "output/vtk.rs"]
mod vtk;
