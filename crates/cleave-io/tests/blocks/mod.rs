//! Keyword text of a box of hexahedra, shared by the tests that write decks.

use cleave_core::mesh::BoxMesh;

/// `*NODE` and `*ELEMENT_SOLID` data lines (free format) of an `n[0] x n[1] x n[2]` box of
/// hexahedra of side `h` with its lowest corner at `origin` ([`BoxMesh`]'s grid and
/// numbering): node ids from `n0` (x fastest), element ids from `e0`, all in part `pid`.
pub fn hex_block(
    n0: usize,
    e0: usize,
    pid: usize,
    n: [usize; 3],
    h: f64,
    origin: [f64; 3],
) -> (String, String) {
    let planes = |k: usize| -> Vec<f64> { (0..=n[k]).map(|i| origin[k] + h * i as f64).collect() };
    let mesh = BoxMesh::from_coords(&planes(0), &planes(1), &planes(2));
    let nodes: String = mesh
        .x
        .iter()
        .enumerate()
        .map(|(k, p)| format!("{}, {}, {}, {}\n", n0 + k, p[0], p[1], p[2]))
        .collect();
    let elems: String = mesh
        .conn
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let ids: Vec<String> = c.iter().map(|&a| (n0 + a as usize).to_string()).collect();
            format!("{}, {pid}, {}\n", e0 + k, ids.join(", "))
        })
        .collect();
    (nodes, elems)
}
