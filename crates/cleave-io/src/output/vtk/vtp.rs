//! `.vtp`: a polygonal surface of quadrilaterals and triangles (crack surfaces).

use super::appended::{Appended, Payload};
use super::xml::{check_arrays, check_indices, vtk_file_open};
use super::DataArray;
use std::io::{self, BufWriter, Write};

/// Writes a VTK XML PolyData (`.vtp`) whose cells are quadrilateral polygons.
///
/// `quads` holds 0-based indices into `points`, in order around each face; a triangle is a
/// quadrilateral with its last point repeated (`N1 N2 N3 N3`) and is written with 3. `cell_data` arrays
/// need one tuple per quadrilateral; names must be non-empty and unique. No quads (and even no
/// points) is valid: it writes an empty surface, which ParaView opens as an empty dataset.
/// Encoding: see [the module page](super). Errors with `InvalidInput` on a length mismatch, a
/// duplicate name or an index out of range, before writing anything.
pub fn write_vtp_quads<W: Write>(
    w: &mut W,
    points: &[[f64; 3]],
    quads: &[[u32; 4]],
    cell_data: &[(&str, DataArray)],
) -> io::Result<()> {
    check_arrays(cell_data, quads.len(), "cell data")?;
    check_indices(quads, points.len(), "quadrilateral")?;

    let mut data = Appended::default();
    let mut xml = vtk_file_open("PolyData");
    xml.push_str("  <PolyData>\n");
    xml.push_str(&format!(
        "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" \
         NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
        points.len(),
        quads.len()
    ));
    xml.push_str(&data.data_section("CellData", cell_data));
    let points_tag = data.push("Points", Payload::Data(DataArray::Vector(points)));
    xml.push_str(&format!(
        "      <Points>\n        {points_tag}\n      </Points>\n"
    ));
    let mut points_of = Vec::with_capacity(4 * quads.len());
    let mut ends = Vec::with_capacity(quads.len());
    for q in quads {
        let n = if q[3] == q[2] { 3 } else { 4 };
        points_of.extend_from_slice(&q[..n]);
        ends.push(points_of.len() as i64);
    }
    let connectivity = data.push("connectivity", Payload::Indices(&points_of));
    let offsets = data.push("offsets", Payload::OffsetList(&ends));
    xml.push_str(&format!(
        "      <Polys>\n        {connectivity}\n        {offsets}\n      </Polys>\n"
    ));
    xml.push_str("    </Piece>\n  </PolyData>\n");

    let mut out = BufWriter::new(w);
    out.write_all(xml.as_bytes())?;
    data.write_section(&mut out)?;
    out.write_all(b"</VTKFile>\n")?;
    out.flush()
}
