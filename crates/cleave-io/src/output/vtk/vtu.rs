//! `.vtu`: an unstructured grid of 8-node hexahedra.

use super::appended::{Appended, Payload};
use super::xml::{check_arrays, check_indices, vtk_file_open};
use super::DataArray;
use std::io::{self, BufWriter, Write};

/// VTK's cell type code for the linear hexahedron.
const VTK_HEXAHEDRON: u8 = 12;

/// Writes a VTK XML UnstructuredGrid (`.vtu`) of hexahedra (VTK_HEXAHEDRON, type 12).
///
/// `hexes` holds 0-based indices into `points`, in LS-DYNA's node order N1..N8 (bottom face
/// N1-N4 counter-clockwise seen from the top face, then N5-N8 above them), which is VTK's
/// hexahedron order. `point_data` arrays need one tuple per point, `cell_data` arrays one per
/// hexahedron; names must be non-empty and unique within each list. Encoding: see
/// [the module page](super). Errors with `InvalidInput` on a length mismatch, a duplicate name
/// or a node index out of range, before writing anything.
pub fn write_vtu<W: Write>(
    w: &mut W,
    points: &[[f64; 3]],
    hexes: &[[u32; 8]],
    point_data: &[(&str, DataArray)],
    cell_data: &[(&str, DataArray)],
) -> io::Result<()> {
    check_arrays(point_data, points.len(), "point data")?;
    check_arrays(cell_data, hexes.len(), "cell data")?;
    check_indices(hexes, points.len(), "hexahedron")?;

    let mut data = Appended::default();
    let mut xml = vtk_file_open("UnstructuredGrid");
    xml.push_str("  <UnstructuredGrid>\n");
    xml.push_str(&format!(
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
        points.len(),
        hexes.len()
    ));
    xml.push_str(&data.data_section("PointData", point_data));
    xml.push_str(&data.data_section("CellData", cell_data));
    let points_tag = data.push("Points", Payload::Data(DataArray::Vector(points)));
    xml.push_str(&format!(
        "      <Points>\n        {points_tag}\n      </Points>\n"
    ));
    let cells = [
        data.push("connectivity", Payload::Indices(hexes.as_flattened())),
        data.push(
            "offsets",
            Payload::Offsets {
                count: hexes.len(),
                stride: 8,
            },
        ),
        data.push(
            "types",
            Payload::CellTypes {
                count: hexes.len(),
                code: VTK_HEXAHEDRON,
            },
        ),
    ];
    xml.push_str("      <Cells>\n");
    for tag in cells {
        xml.push_str(&format!("        {tag}\n"));
    }
    xml.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");

    let mut out = BufWriter::new(w);
    out.write_all(xml.as_bytes())?;
    data.write_section(&mut out)?;
    out.write_all(b"</VTKFile>\n")?;
    out.flush()
}
