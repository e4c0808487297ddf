//! The VTK files read back by independent readers: meshio 5.3 and VTK's Python package.

use super::common::{scratch, Box2};
use super::vtk::box_vtu;
use cleave_io::output::{write_vtp_quads, DataArray, PvdWriter};
use serde_json::Value;
use std::io::Write;
use std::path::Path;
use std::process::Command;

/// Whether `python3` can import `module`; prints a visible SKIPPED line to stderr when it cannot.
fn python_has(module: &str, test: &str) -> bool {
    let ok = Command::new("python3")
        .args(["-c", &format!("import {module}")])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        // Written to the stderr handle directly: the test harness captures `eprintln!`.
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED {test}: python3 with {module} not available"
        );
    }
    ok
}

/// Runs a Python `script` with `args`; returns the JSON it prints on its last line.
fn run_python(script: &str, args: &[&Path]) -> Value {
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("python3 runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "python failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(stdout.lines().last().unwrap_or("")).expect("JSON from python")
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

const MESHIO_VTU: &str = r#"
import json, sys, meshio
m = meshio.read(sys.argv[1])
print(json.dumps({
    "points": len(m.points),
    "blocks": [[c.type, len(c.data)] for c in m.cells],
    "first_cell": m.cells[0].data[0].tolist(),
    "point13": m.points[13].tolist(),
    "disp13": m.point_data["displacement"][13].tolist(),
    "stress_shape": list(m.cell_data["stress"][0].shape),
    "stress7": m.cell_data["stress"][0][7].tolist(),
    "mises": m.cell_data["von_mises"][0].tolist(),
    "part": m.cell_data["part"][0].tolist(),
}))
"#;

#[test]
fn meshio_reads_the_vtu() {
    if !python_has("meshio", "meshio_reads_the_vtu") {
        return;
    }
    let b = Box2::new();
    let path = scratch("meshio_vtu").join("box.vtu");
    std::fs::write(&path, box_vtu(&b)).unwrap();
    let r = run_python(MESHIO_VTU, &[&path]);
    assert_eq!(r["points"], 27);
    assert_eq!(r["blocks"], serde_json::json!([["hexahedron", 8]]));
    assert_eq!(r["first_cell"], serde_json::json!(b.hexes[0]));
    let p13: Vec<f64> = r["point13"].as_array().unwrap().iter().map(f).collect();
    assert_eq!(p13, b.points[13]);
    let d13: Vec<f64> = r["disp13"].as_array().unwrap().iter().map(f).collect();
    assert_eq!(d13, b.displacement[13]);
    assert_eq!(r["stress_shape"], serde_json::json!([8, 6]));
    let s7: Vec<f64> = r["stress7"].as_array().unwrap().iter().map(f).collect();
    assert_eq!(s7, b.stress[7]);
    let mises: Vec<f64> = r["mises"].as_array().unwrap().iter().map(f).collect();
    assert_eq!(mises, b.mises);
    assert_eq!(r["part"], serde_json::json!(b.part));
}

const MESHIO_PVD: &str = r#"
import json, os, sys, meshio
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == "VTKFile" and root.get("type") == "Collection"
sets = root.find("Collection").findall("DataSet")
folder = os.path.dirname(sys.argv[1])
out = []
for d in sets:
    m = meshio.read(os.path.join(folder, d.get("file")))
    out.append([float(d.get("timestep")), len(m.points), sum(len(c.data) for c in m.cells)])
print(json.dumps(out))
"#;

#[test]
fn meshio_reads_every_state_of_the_pvd() {
    if !python_has("meshio", "meshio_reads_every_state_of_the_pvd") {
        return;
    }
    let b = Box2::new();
    let dir = scratch("meshio_pvd");
    std::fs::create_dir(dir.join("states")).unwrap();
    let mut pvd = PvdWriter::new(dir.join("results.pvd"));
    for (k, t) in [0.0, 1.25e-4].into_iter().enumerate() {
        let file = format!("states/state_{k:04}.vtu");
        std::fs::write(dir.join(&file), box_vtu(&b)).unwrap();
        pvd.add(t, &file).unwrap();
    }
    let r = run_python(MESHIO_PVD, &[&dir.join("results.pvd")]);
    assert_eq!(r, serde_json::json!([[0.0, 27, 8], [1.25e-4, 27, 8]]));
}

const VTK_READ: &str = r#"
import json, sys, vtk
errors = []
def read(path, reader):
    reader.AddObserver("ErrorEvent", lambda o, e: errors.append(path))
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        errors.append(path)
    return reader.GetOutput()
g = read(sys.argv[1], vtk.vtkXMLUnstructuredGridReader())
size = vtk.vtkCellSizeFilter()
size.SetInputData(g)
size.Update()
vol = size.GetOutput().GetCellData().GetArray("Volume")
stress = g.GetCellData().GetArray("stress")
p = read(sys.argv[2], vtk.vtkXMLPolyDataReader())
e = read(sys.argv[3], vtk.vtkXMLPolyDataReader())
print(json.dumps({
    "errors": errors,
    "points": g.GetNumberOfPoints(),
    "cells": g.GetNumberOfCells(),
    "types": sorted(set(g.GetCellType(i) for i in range(g.GetNumberOfCells()))),
    "volumes": [vol.GetValue(i) for i in range(vol.GetNumberOfTuples())],
    "stress_components": stress.GetNumberOfComponents(),
    "stress7": list(stress.GetTuple(7)),
    "stress_names": [stress.GetComponentName(i) for i in range(6)],
    "disp13": list(g.GetPointData().GetArray("displacement").GetTuple(13)),
    "vtp_points": p.GetNumberOfPoints(),
    "vtp_polys": p.GetNumberOfPolys(),
    "vtp_area": [p.GetCellData().GetArray("area").GetValue(i) for i in range(2)],
    "vtp_cell1": [p.GetCell(1).GetPointId(k) for k in range(4)],
    "empty_points": e.GetNumberOfPoints(),
    "empty_polys": e.GetNumberOfPolys(),
}))
"#;

#[test]
fn vtk_reads_the_vtu_and_vtp_files() {
    if !python_has("vtk", "vtk_reads_the_vtu_and_vtp_files") {
        return;
    }
    let b = Box2::new();
    let dir = scratch("vtk_python");
    let (vtu, vtp, empty) = (
        dir.join("box.vtu"),
        dir.join("crack.vtp"),
        dir.join("none.vtp"),
    );
    std::fs::write(&vtu, box_vtu(&b)).unwrap();
    let points = [
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [2.0, 0.0, 1.0],
        [2.0, 1.0, 1.0],
    ];
    let mut file = Vec::new();
    write_vtp_quads(
        &mut file,
        &points,
        &[[0, 1, 2, 3], [1, 4, 5, 2]],
        &[("area", DataArray::Scalar(&[1.0, 2.0]))],
    )
    .unwrap();
    std::fs::write(&vtp, file).unwrap();
    let mut file = Vec::new();
    write_vtp_quads(&mut file, &[], &[], &[("area", DataArray::Scalar(&[]))]).unwrap();
    std::fs::write(&empty, file).unwrap();

    let r = run_python(VTK_READ, &[&vtu, &vtp, &empty]);
    assert_eq!(r["errors"], serde_json::json!([]));
    assert_eq!(r["points"], 27);
    assert_eq!(r["cells"], 8);
    assert_eq!(r["types"], serde_json::json!([12]));
    // Unit cubes: any node-order mistake would change or negate a volume.
    for v in r["volumes"].as_array().unwrap() {
        assert!((f(v) - 1.0).abs() < 1e-12, "hexahedron volume {v}");
    }
    assert_eq!(r["stress_components"], 6);
    assert_eq!(
        r["stress_names"],
        serde_json::json!(["XX", "YY", "ZZ", "XY", "YZ", "XZ"])
    );
    let s7: Vec<f64> = r["stress7"].as_array().unwrap().iter().map(f).collect();
    assert_eq!(s7, b.stress[7]);
    let d13: Vec<f64> = r["disp13"].as_array().unwrap().iter().map(f).collect();
    assert_eq!(d13, b.displacement[13]);
    assert_eq!(r["vtp_points"], 6);
    assert_eq!(r["vtp_polys"], 2);
    assert_eq!(r["vtp_area"], serde_json::json!([1.0, 2.0]));
    assert_eq!(r["vtp_cell1"], serde_json::json!([1, 4, 5, 2]));
    assert_eq!(r["empty_points"], 0);
    assert_eq!(r["empty_polys"], 0);
}

/// A grid of one hexahedron, one wedge and one tetrahedron (cleave's stored layouts) read by
/// meshio: the cell types and counts, and each cell's volume computed by the reader's side
/// (numpy, from the points in the order meshio gives them: meshio turns VTK's wedge into its
/// own order, Gmsh's, whose triangle 0-1-2 points to 3-4-5) equal the exact volumes, all
/// positive: 1 for the unit cube, 1/2 for the half cube, 1/6 for the corner tetrahedron.
const MESHIO_SHAPES: &str = r#"
import json, sys, meshio, numpy as np
m = meshio.read(sys.argv[1])
p = m.points
def tet(a, b, c, d):
    return float(np.dot(np.cross(p[b] - p[a], p[c] - p[a]), p[d] - p[a]) / 6)
vol = {}
for blk in m.cells:
    c = blk.data[0]
    if blk.type == "tetra":
        vol["tetra"] = tet(*c)
    elif blk.type == "wedge":
        # 3 tetrahedra of the prism a b c / d e f (Gmsh order)
        a, b, cc, d, e, f = c
        vol["wedge"] = tet(a, b, cc, d) + tet(b, cc, d, e) + tet(cc, d, e, f)
    elif blk.type == "hexahedron":
        vol["hexahedron"] = len(c)
print(json.dumps({"blocks": [[b.type, len(b.data)] for b in m.cells], "vol": vol}))
"#;

#[test]
fn meshio_reads_tetrahedra_and_wedges() {
    if !python_has("meshio", "meshio_reads_tetrahedra_and_wedges") {
        return;
    }
    // unit cube 0..7 (LS-DYNA order) and, beside it at x = 1..2, the half cube as a wedge
    // (triangles on y = 0 and y = 1) and a corner tetrahedron at x = 2..3
    let mut points = Vec::new();
    for x0 in [0.0, 1.0, 2.0] {
        for [x, y, z] in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ] {
            points.push([x + x0, y, z]);
        }
    }
    let hex = [0, 1, 2, 3, 4, 5, 6, 7];
    // wedge N1..N6 = cube corners 0 1 2 3 5 6 (triangles 0-1-5 on y = 0 and 3-2-6 on y = 1)
    let w = |k: u32| 8 + k;
    let wedge = [w(0), w(1), w(2), w(3), w(5), w(5), w(6), w(6)];
    // tetrahedron N1 N2 N3 N4 = corners 0 1 3 4, stored N1 N2 N3 N3 N4 N4 N4 N4
    let t = |k: u32| 16 + k;
    let tet = [t(0), t(1), t(3), t(3), t(4), t(4), t(4), t(4)];
    let path = scratch("meshio_shapes").join("shapes.vtu");
    let mut bytes = Vec::new();
    cleave_io::output::write_vtu(&mut bytes, &points, &[hex, wedge, tet], &[], &[]).unwrap();
    std::fs::write(&path, bytes).unwrap();
    let r = run_python(MESHIO_SHAPES, &[&path]);
    let blocks = r["blocks"].as_array().unwrap();
    assert_eq!(blocks.len(), 3, "{r}");
    assert!((f(&r["vol"]["wedge"]) - 0.5).abs() < 1e-14, "{r}");
    assert!((f(&r["vol"]["tetra"]) - 1.0 / 6.0).abs() < 1e-14, "{r}");
    assert_eq!(r["vol"]["hexahedron"], 8);
}
