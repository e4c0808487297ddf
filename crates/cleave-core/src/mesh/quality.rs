//! Shape measures of a hexahedral mesh, to check and report what the generators make.

use super::BoxMesh;
use crate::element::hex8::{jacobian_at, max_face_area, volume, CORNERS};
use crate::math::{det, norm, sub, Vec3};

/// The 12 edges of a hexahedron (corner indices).
const EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// Extremes over the elements of a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshQuality {
    /// Shortest and longest element edge in the mesh.
    pub min_edge: f64,
    pub max_edge: f64,
    /// Largest ratio of an element's longest to its shortest edge.
    pub max_aspect: f64,
    /// Smallest scaled Jacobian: det J / (|J e1| |J e2| |J e3|) at a corner (1 for a
    /// rectangular box, 0 for a degenerate corner, negative for an inverted one).
    pub min_scaled_jacobian: f64,
    /// Smallest characteristic length V / A_max (what sets the explicit time step).
    pub min_char_length: f64,
}

/// The shape measures of `mesh`.
pub fn quality(mesh: &BoxMesh) -> MeshQuality {
    let mut q = MeshQuality {
        min_edge: f64::INFINITY,
        max_edge: 0.0,
        max_aspect: 0.0,
        min_scaled_jacobian: f64::INFINITY,
        min_char_length: f64::INFINITY,
    };
    for c in &mesh.conn {
        let xe: [Vec3; 8] = c.map(|i| mesh.x[i as usize]);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for [a, b] in EDGES {
            let l = norm(sub(xe[b], xe[a]));
            lo = lo.min(l);
            hi = hi.max(l);
        }
        q.min_edge = q.min_edge.min(lo);
        q.max_edge = q.max_edge.max(hi);
        q.max_aspect = q.max_aspect.max(hi / lo);
        for p in CORNERS {
            let j = jacobian_at(&xe, p);
            let col = |k: usize| norm([j[0][k], j[1][k], j[2][k]]);
            let s = det(&j) / (col(0) * col(1) * col(2));
            q.min_scaled_jacobian = q.min_scaled_jacobian.min(s);
        }
        q.min_char_length = q.min_char_length.min(volume(&xe) / max_face_area(&xe));
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_is_perfect() {
        let q = quality(&BoxMesh::new([2, 3, 4], [2.0, 3.0, 4.0]));
        assert!((q.min_edge - 1.0).abs() < 1e-14 && (q.max_edge - 1.0).abs() < 1e-14);
        assert!((q.max_aspect - 1.0).abs() < 1e-14);
        assert!((q.min_scaled_jacobian - 1.0).abs() < 1e-14);
        assert!((q.min_char_length - 1.0).abs() < 1e-14);
    }
}
