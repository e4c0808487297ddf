use super::common::{appended_block, attribute, f64s, scratch, Box2};
use cleave_io::output::{write_vtp_quads, write_vtu, DataArray, PvdWriter};
use std::io::ErrorKind;

/// The box written as a .vtu into memory.
pub fn box_vtu(b: &Box2) -> Vec<u8> {
    let mut out = Vec::new();
    write_vtu(
        &mut out,
        &b.points,
        &b.hexes,
        &[("displacement", DataArray::Vector(&b.displacement))],
        &[
            ("part", DataArray::Int(&b.part)),
            ("von_mises", DataArray::Scalar(&b.mises)),
            ("stress", DataArray::SymTensor(&b.stress)),
        ],
    )
    .unwrap();
    out
}

fn header(file: &[u8]) -> String {
    let end = file.windows(5).position(|w| w == b"raw\">").unwrap();
    String::from_utf8(file[..end].to_vec()).unwrap()
}

#[test]
fn vtu_declares_counts_and_format() {
    let b = Box2::new();
    let file = box_vtu(&b);
    let xml = header(&file);
    assert_eq!(attribute(&xml, "<VTKFile", "type"), "UnstructuredGrid");
    assert_eq!(attribute(&xml, "<VTKFile", "byte_order"), "LittleEndian");
    assert_eq!(attribute(&xml, "<VTKFile", "header_type"), "UInt64");
    assert_eq!(attribute(&xml, "<Piece", "NumberOfPoints"), "27");
    assert_eq!(attribute(&xml, "<Piece", "NumberOfCells"), "8");
    assert!(file.ends_with(b"\n  </AppendedData>\n</VTKFile>\n"));
}

#[test]
fn vtu_appended_arrays_decode_to_the_exact_values() {
    let b = Box2::new();
    let file = box_vtu(&b);
    let points = f64s(appended_block(&file, "Points"));
    assert_eq!(points, b.points.concat());
    let stress = f64s(appended_block(&file, "stress"));
    assert_eq!(stress, b.stress.concat());
    let mises = f64s(appended_block(&file, "von_mises"));
    assert_eq!(mises, b.mises);
    let xml = header(&file);
    assert_eq!(
        attribute(
            &xml,
            "<DataArray type=\"Float64\" Name=\"stress\"",
            "NumberOfComponents"
        ),
        "6"
    );
    assert_eq!(
        attribute(
            &xml,
            "<DataArray type=\"Float64\" Name=\"stress\"",
            "ComponentName5"
        ),
        "XZ"
    );
}

#[test]
fn vtu_rejects_inconsistent_input() {
    let b = Box2::new();
    let mut out = Vec::new();
    let short = [1.0; 7];
    let e = write_vtu(
        &mut out,
        &b.points,
        &b.hexes,
        &[],
        &[("m", DataArray::Scalar(&short))],
    )
    .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidInput);
    let e = write_vtu(&mut out, &b.points[..26], &b.hexes, &[], &[]).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidInput);
    let twice = [
        ("m", DataArray::Scalar(&b.mises)),
        ("m", DataArray::Int(&b.part)),
    ];
    let e = write_vtu(&mut out, &b.points, &b.hexes, &[], &twice).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidInput);
    assert!(out.is_empty(), "nothing is written before the checks pass");
}

#[test]
fn vtp_with_quads_and_without() {
    let points = [
        [0.0, 0.0, 0.5],
        [1.0, 0.0, 0.5],
        [1.0, 1.0, 0.5],
        [0.0, 1.0, 0.5],
        [2.0, 0.0, 0.5],
        [2.0, 1.0, 0.5],
    ];
    let quads = [[0, 1, 2, 3], [1, 4, 5, 2]];
    let area = [1.0, 1.0];
    let mut file = Vec::new();
    write_vtp_quads(
        &mut file,
        &points,
        &quads,
        &[("area", DataArray::Scalar(&area))],
    )
    .unwrap();
    let xml = header(&file);
    assert_eq!(attribute(&xml, "<VTKFile", "type"), "PolyData");
    assert_eq!(attribute(&xml, "<Piece", "NumberOfPoints"), "6");
    assert_eq!(attribute(&xml, "<Piece", "NumberOfPolys"), "2");
    assert_eq!(f64s(appended_block(&file, "Points")), points.concat());

    let mut empty = Vec::new();
    write_vtp_quads(&mut empty, &[], &[], &[("area", DataArray::Scalar(&[]))]).unwrap();
    let xml = header(&empty);
    assert_eq!(attribute(&xml, "<Piece", "NumberOfPoints"), "0");
    assert_eq!(attribute(&xml, "<Piece", "NumberOfPolys"), "0");
    assert!(f64s(appended_block(&empty, "Points")).is_empty());

    let e = write_vtp_quads(&mut Vec::new(), &points, &[[0, 1, 2, 6]], &[]).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidInput);
}

#[test]
fn pvd_is_rewritten_after_each_add() {
    let path = scratch("pvd_rust").join("results.pvd");
    let mut pvd = PvdWriter::new(&path);
    pvd.add(0.0, "states/state_0000.vtu").unwrap();
    let first = std::fs::read_to_string(&path).unwrap();
    assert_eq!(first.matches("<DataSet ").count(), 1);
    pvd.add(2.5e-5, "states/state_0001.vtu").unwrap();
    let xml = std::fs::read_to_string(&path).unwrap();
    assert_eq!(attribute(&xml, "<VTKFile", "type"), "Collection");
    assert_eq!(xml.matches("<DataSet ").count(), 2);
    let second = &xml[xml.rfind("<DataSet ").unwrap()..];
    assert_eq!(
        attribute(second, "<DataSet", "timestep")
            .parse::<f64>()
            .unwrap(),
        2.5e-5
    );
    assert_eq!(
        attribute(second, "<DataSet", "file"),
        "states/state_0001.vtu"
    );
    assert!(xml.trim_end().ends_with("</Collection>\n</VTKFile>"));
    assert!(pvd.add(f64::NAN, "x.vtu").is_err());
    assert_eq!(pvd.entries().len(), 2);
}
