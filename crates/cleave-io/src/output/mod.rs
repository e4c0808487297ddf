//! Result writers: CSV histories, summary JSON, ParaView VTU/VTP/PVD, PNG plots.
//!
//! Every writer here takes plain slices and structs, never solver types, so each can be tested
//! without a run and the solver decides what to write and when.
//!
//! | module | writes |
//! |---|---|
//! | [`csv`] | comma-separated histories (`glstat.csv`, `nodout.csv`, ...): one header line, then rows of numbers in shortest round-trip precision |
//! | [`vtk`] | ParaView XML files: `.vtu` (hexahedra), `.vtp` (quadrilateral polygons), `.pvd` (time collection); binary data is raw, appended, little endian, with UInt64 block headers |
//! | [`summary`] | `summary.json`, pretty-printed; non-finite numbers become `null` |
//! | [`mem`] | the process's peak resident memory (VmHWM) |
//! | [`plot`] | PNG line plots, two-axis plots and histograms, with a bundled font (no system fonts needed) |

pub mod csv;
pub mod mem;
mod number;
pub mod plot;
pub mod summary;
pub mod vtk;

pub use self::csv::{CsvWriter, Field};
pub use self::mem::peak_rss_mb;
pub use self::plot::{plot_histogram, plot_lines, plot_two_axes, PlotError};
pub use self::summary::Summary;
pub use self::vtk::{write_vtp_quads, write_vtu, DataArray, PvdWriter};
