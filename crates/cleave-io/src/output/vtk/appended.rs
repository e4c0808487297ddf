//! The raw appended-data section: byte layout of the arrays and their `<DataArray>` tags.
//!
//! Each block is a UInt64 little-endian byte count followed by the values, little endian.

use super::xml::escape;
use super::DataArray;
use std::io::{self, Write};

/// The values of one appended array.
pub(super) enum Payload<'a> {
    /// Point or cell data, or the point coordinates.
    Data(DataArray<'a>),
    /// Point indices (connectivity), written as Int64.
    Indices(&'a [u32]),
    /// End offsets of cells of any sizes, as Int64.
    OffsetList(&'a [i64]),
    /// One VTK cell type code per cell, as UInt8.
    CellTypes(&'a [u8]),
}

impl Payload<'_> {
    fn vtk_type(&self) -> &'static str {
        match self {
            Payload::Data(DataArray::Int(_)) => "Int32",
            Payload::Data(_) => "Float64",
            Payload::Indices(_) | Payload::OffsetList(_) => "Int64",
            Payload::CellTypes(_) => "UInt8",
        }
    }

    fn components(&self) -> usize {
        match self {
            Payload::Data(array) => array.components(),
            _ => 1,
        }
    }

    fn byte_len(&self) -> u64 {
        let bytes = match self {
            Payload::Data(DataArray::Int(v)) => 4 * v.len(),
            Payload::Data(array) => 8 * array.len() * array.components(),
            Payload::Indices(v) => 8 * v.len(),
            Payload::OffsetList(v) => 8 * v.len(),
            Payload::CellTypes(v) => v.len(),
        };
        bytes as u64
    }

    fn write_values(&self, w: &mut impl Write) -> io::Result<()> {
        match *self {
            Payload::Data(DataArray::Scalar(v)) => write_f64s(w, v),
            Payload::Data(DataArray::Vector(v)) => write_f64s(w, v.as_flattened()),
            Payload::Data(DataArray::SymTensor(v)) => write_f64s(w, v.as_flattened()),
            Payload::Data(DataArray::Int(v)) => {
                v.iter().try_for_each(|x| w.write_all(&x.to_le_bytes()))
            }
            Payload::Indices(v) => v
                .iter()
                .try_for_each(|&x| w.write_all(&i64::from(x).to_le_bytes())),
            Payload::OffsetList(v) => v.iter().try_for_each(|x| w.write_all(&x.to_le_bytes())),
            Payload::CellTypes(v) => w.write_all(v),
        }
    }
}

fn write_f64s(w: &mut impl Write, values: &[f64]) -> io::Result<()> {
    values
        .iter()
        .try_for_each(|x| w.write_all(&x.to_le_bytes()))
}

/// The arrays of one file, in the order of their blocks in the appended section.
#[derive(Default)]
pub(super) struct Appended<'a> {
    payloads: Vec<Payload<'a>>,
    next_offset: u64,
}

impl<'a> Appended<'a> {
    /// Adds an array and returns its self-closing `<DataArray .../>` tag (no indentation).
    pub(super) fn push(&mut self, name: &str, payload: Payload<'a>) -> String {
        let mut tag = format!(
            "<DataArray type=\"{}\" Name=\"{}\"",
            payload.vtk_type(),
            escape(name)
        );
        let components = payload.components();
        if components > 1 {
            tag.push_str(&format!(" NumberOfComponents=\"{components}\""));
        }
        if components == 6 {
            for (k, c) in ["XX", "YY", "ZZ", "XY", "YZ", "XZ"].iter().enumerate() {
                tag.push_str(&format!(" ComponentName{k}=\"{c}\""));
            }
        }
        tag.push_str(&format!(
            " format=\"appended\" offset=\"{}\"/>",
            self.next_offset
        ));
        self.next_offset += 8 + payload.byte_len();
        self.payloads.push(payload);
        tag
    }

    /// Writes the whole `<AppendedData>` element, from its opening tag to its closing tag.
    pub(super) fn write_section(&self, w: &mut impl Write) -> io::Result<()> {
        w.write_all(b"  <AppendedData encoding=\"raw\">\n   _")?;
        for payload in &self.payloads {
            w.write_all(&payload.byte_len().to_le_bytes())?;
            payload.write_values(w)?;
        }
        w.write_all(b"\n  </AppendedData>\n")
    }
}

impl<'a> Appended<'a> {
    /// Adds `arrays` and returns the `<PointData>` or `<CellData>` element (`element`) holding
    /// their tags, indented for a `<Piece>`; an empty string when there is no array.
    pub(super) fn data_section(
        &mut self,
        element: &str,
        arrays: &[(&str, DataArray<'a>)],
    ) -> String {
        if arrays.is_empty() {
            return String::new();
        }
        let mut xml = format!("      <{element}>\n");
        for (name, array) in arrays {
            xml.push_str("        ");
            xml.push_str(&self.push(name, Payload::Data(*array)));
            xml.push('\n');
        }
        xml.push_str(&format!("      </{element}>\n"));
        xml
    }
}
