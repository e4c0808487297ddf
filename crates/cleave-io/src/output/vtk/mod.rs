//! ParaView XML writers: `.vtu` (hexahedra), `.vtp` (quadrilateral polygons), `.pvd` (time series).
//!
//! # Encoding
//!
//! Every file is written in VTK's XML format version 1.0 with `byte_order="LittleEndian"` and
//! `header_type="UInt64"`. All numbers live in one `<AppendedData encoding="raw">` section: after
//! its `_` marker, each array is an 8-byte little-endian byte count followed by its values,
//! little endian, uncompressed; each `<DataArray format="appended" offset="...">` gives the byte
//! position of its block after the `_`. The section ends with a newline before
//! `</AppendedData>`. Raw appended data is VTK's own default: the smallest and fastest to write
//! and to read (no base64 inflation), and both ParaView (VTK's XML readers) and meshio 5.3 (which
//! recognises the raw section and decodes it) read it. The crate's tests check the files with
//! meshio and, where installed, with VTK's own Python readers.
//!
//! Types: points and float arrays `Float64`; [`DataArray::Int`] `Int32`; connectivity and offsets
//! `Int64`; cell types `UInt8`. A 1-component array has no `NumberOfComponents` attribute (so
//! readers see it as a scalar); vectors have 3 components; symmetric tensors have 6 components
//! named `XX YY ZZ XY YZ XZ`, which ParaView recognises as a symmetric tensor.

mod appended;
mod pvd;
mod vtp;
mod vtu;
mod xml;

pub use self::pvd::PvdWriter;
pub use self::vtp::write_vtp_quads;
pub use self::vtu::write_vtu;

/// One named array of point or cell data: one tuple per point or per cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DataArray<'a> {
    /// One float per entity (e.g. von Mises stress).
    Scalar(&'a [f64]),
    /// Three floats per entity (e.g. displacement, velocity).
    Vector(&'a [[f64; 3]]),
    /// A symmetric tensor per entity in LS-DYNA order xx yy zz xy yz zx, which is ParaView's
    /// symmetric tensor order (XX YY ZZ XY YZ XZ); written as 6 components.
    SymTensor(&'a [[f64; 6]]),
    /// One integer per entity (e.g. part id).
    Int(&'a [i32]),
}

impl DataArray<'_> {
    /// Number of tuples (entities) in the array.
    pub fn len(&self) -> usize {
        match self {
            DataArray::Scalar(v) => v.len(),
            DataArray::Vector(v) => v.len(),
            DataArray::SymTensor(v) => v.len(),
            DataArray::Int(v) => v.len(),
        }
    }

    /// Whether the array has no tuple.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of components per tuple: 1, 3 or 6.
    pub fn components(&self) -> usize {
        match self {
            DataArray::Scalar(_) | DataArray::Int(_) => 1,
            DataArray::Vector(_) => 3,
            DataArray::SymTensor(_) => 6,
        }
    }
}
