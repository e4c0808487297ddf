//! `.vtu`: an unstructured grid of hexahedra, wedges and tetrahedra.

use super::appended::{Appended, Payload};
use super::xml::{check_arrays, check_indices, vtk_file_open};
use super::DataArray;
use std::io::{self, BufWriter, Write};

use cleave_core::element::shape::{shape_of, Shape};

/// VTK's cell type codes of the linear hexahedron, wedge and tetrahedron.
const VTK_HEXAHEDRON: u8 = 12;
const VTK_WEDGE: u8 = 13;
const VTK_TETRA: u8 = 10;

/// A cell's VTK type and its points in VTK's order, from cleave's 8 stored corners
/// ([`cleave_core::element::shape`]):
/// - hexahedron: LS-DYNA's N1..N8 (bottom face N1-N4 counter-clockwise seen from the top,
///   then N5-N8 above them) is VTK's order;
/// - tetrahedron `N1 N2 N3 N3 N4 ..`: N1 N2 N3 N4 (VTK: the normal of 0-1-2 by the right-hand
///   rule points to 3, as for a positive LS-DYNA tetrahedron);
/// - wedge `N1 N2 N3 N4 N5 N5 N6 N6`, triangles 1-2-5 (outward) and 4-3-6, edges 1-4, 2-3,
///   5-6: N1 N2 N5 N4 N3 N6 (VTK: triangle 0-1-2 with its normal pointing away from 3-4-5,
///   `vtkWedge`'s documented convention).
///
/// Any other pattern is written as the hexahedron it is stored as.
fn vtk_cell(c: &[u32; 8]) -> (u8, ArrayVecU32) {
    match shape_of(c) {
        Some(Shape::Tet) => (VTK_TETRA, ArrayVecU32::new(&[c[0], c[1], c[2], c[4]])),
        Some(Shape::Wedge) => (
            VTK_WEDGE,
            ArrayVecU32::new(&[c[0], c[1], c[4], c[3], c[2], c[6]]),
        ),
        _ => (VTK_HEXAHEDRON, ArrayVecU32::new(c)),
    }
}

/// Up to 8 point indices.
struct ArrayVecU32 {
    v: [u32; 8],
    n: usize,
}

impl ArrayVecU32 {
    fn new(s: &[u32]) -> Self {
        let mut v = [0; 8];
        v[..s.len()].copy_from_slice(s);
        Self { v, n: s.len() }
    }
    fn as_slice(&self) -> &[u32] {
        &self.v[..self.n]
    }
}

/// Writes a VTK XML UnstructuredGrid (`.vtu`) of hexahedra, wedges and tetrahedra.
///
/// `hexes` holds 0-based indices into `points`, 8 per cell in cleave's stored layouts (a
/// wedge or tetrahedron as its degenerate hexahedron), written in VTK's orders (a tetrahedron N1 N2 N3 N4, a wedge N1 N2 N5 N4 N3 N6).
/// `point_data` arrays need one tuple per point, `cell_data` arrays one per cell; names must be non-empty and unique within each list. Encoding: see
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
    let mut connectivity = Vec::with_capacity(8 * hexes.len());
    let mut offsets = Vec::with_capacity(hexes.len());
    let mut types = Vec::with_capacity(hexes.len());
    for c in hexes {
        let (code, pts) = vtk_cell(c);
        connectivity.extend_from_slice(pts.as_slice());
        offsets.push(connectivity.len() as i64);
        types.push(code);
    }
    let cells = [
        data.push("connectivity", Payload::Indices(&connectivity)),
        data.push("offsets", Payload::OffsetList(&offsets)),
        data.push("types", Payload::CellTypes(&types)),
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

#[cfg(test)]
mod tests {
    use super::*;
    use cleave_core::math::{cross, dot, sub, Vec3};

    /// The orientation rules of [`vtk_cell`] on a positive tetrahedron and wedge.
    #[test]
    fn tetrahedra_and_wedges_in_vtk_order() {
        let x: [Vec3; 6] = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.0, 1.0],
            [0.5, 1.0, 1.0],
        ];
        // wedge N1..N6 = nodes 0..5 (stored 0 1 2 3 4 4 5 5), positive in cleave
        let w = [0, 1, 2, 3, 4, 4, 5, 5];
        let xs: [Vec3; 8] = w.map(|i| x[i as usize]);
        assert!(cleave_core::element::hex8::volume(&xs) > 0.0);
        let (code, p) = vtk_cell(&w);
        assert_eq!(code, VTK_WEDGE);
        let p: Vec<Vec3> = p.as_slice().iter().map(|&i| x[i as usize]).collect();
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let towards_top = sub(p[3], p[0]);
        assert!(dot(n, towards_top) < 0.0, "0-1-2 points away from 3-4-5");
        // the edges 0-3, 1-4, 2-5 are the wedge's
        for k in 0..3 {
            assert!((dot(sub(p[k + 3], p[k]), [0.0, 1.0, 0.0]) - 1.0).abs() < 1e-15);
        }
        let t = [0, 1, 3, 3, 4, 4, 4, 4];
        let (code, p) = vtk_cell(&t);
        assert_eq!(code, VTK_TETRA);
        let p: Vec<Vec3> = p.as_slice().iter().map(|&i| x[i as usize]).collect();
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        assert!(dot(n, sub(p[3], p[0])) > 0.0);
    }
}
