//! Shared fixtures: a scratch folder, a 2x2x2 box of hexahedra, and a light VTK file parser.

use std::path::PathBuf;

/// A fresh, empty scratch folder for one test.
pub fn scratch(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("cleave-io-output")
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A 2x2x2 box of unit hexahedra: 27 points (x fastest, then y, then z) and 8 cells in
/// LS-DYNA / VTK node order, with point and cell data whose values differ everywhere.
pub struct Box2 {
    pub points: Vec<[f64; 3]>,
    pub hexes: Vec<[u32; 8]>,
    pub displacement: Vec<[f64; 3]>,
    pub mises: Vec<f64>,
    pub stress: Vec<[f64; 6]>,
    pub part: Vec<i32>,
}

impl Box2 {
    pub fn new() -> Self {
        // x fastest, then y, then z: the numbering of cleave_core's structured box
        let cleave_core::mesh::BoxMesh {
            x: points,
            conn: hexes,
        } = cleave_core::mesh::BoxMesh::new([2, 2, 2], [2.0, 2.0, 2.0]);
        let displacement = points
            .iter()
            .map(|p| [0.1 * p[0], -1e-7 * p[1], 1.0 / 3.0 + p[2]])
            .collect();
        let mises = (0..8).map(|c| 1.5e8 + f64::from(c) / 7.0).collect();
        let stress = (0..8)
            .map(|c| std::array::from_fn(|k| f64::from(10 * c + k as i32) + 0.25))
            .collect();
        let part = (0..8).map(|c| 1 + c / 4).collect();
        Box2 {
            points,
            hexes,
            displacement,
            mises,
            stress,
            part,
        }
    }
}

/// The value of attribute `name` in the first tag of `xml` that starts with `tag_start`.
pub fn attribute<'a>(xml: &'a str, tag_start: &str, name: &str) -> &'a str {
    let tag = &xml[xml
        .find(tag_start)
        .unwrap_or_else(|| panic!("no {tag_start}"))..];
    let tag = &tag[..tag.find('>').unwrap()];
    let key = format!(" {name}=\"");
    let value = &tag[tag.find(&key).unwrap_or_else(|| panic!("no {name}")) + key.len()..];
    &value[..value.find('"').unwrap()]
}

/// The bytes of the appended block of the `DataArray` named `array` in a raw-appended VTK file,
/// after checking its UInt64 byte-count header.
pub fn appended_block<'a>(file: &'a [u8], array: &str) -> &'a [u8] {
    let marker = b"<AppendedData encoding=\"raw\">";
    let start = find(file, marker).expect("raw appended section") + marker.len();
    let base = start + find(&file[start..], b"_").unwrap() + 1;
    let head = String::from_utf8_lossy(&file[..start]);
    let offset: usize = attribute(
        &head,
        &format!("<DataArray type=\"Float64\" Name=\"{array}\""),
        "offset",
    )
    .parse()
    .unwrap();
    let at = base + offset;
    let len = u64::from_le_bytes(file[at..at + 8].try_into().unwrap()) as usize;
    &file[at + 8..at + 8 + len]
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Little-endian f64 values of `bytes`.
pub fn f64s(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect()
}
