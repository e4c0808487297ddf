//! Tetrahedral and wedge meshes from hexahedral ones, for tests, benchmarks and examples:
//! each hexahedron cut into 6 tetrahedra or 2 wedges without new nodes, conforming across
//! neighbours that are cut the same way.

use super::BoxMesh;
use crate::element::{self, Shape};

/// Corners of the hexahedron (LS-DYNA order) at the unit-cube vertex with bits (x, y, z).
const AT: [[usize; 2]; 4] = [[0, 4], [3, 7], [1, 5], [2, 6]];

/// The corner at (x, y, z) in {0, 1}^3.
fn corner(x: usize, y: usize, z: usize) -> usize {
    AT[2 * x + y][z]
}

impl BoxMesh {
    /// Each hexahedron cut into the 6 tetrahedra of Kuhn's (Freudenthal's) subdivision, all
    /// sharing its diagonal from corner 1 (0,0,0) to corner 7 (1,1,1) in natural coordinates:
    /// one per order in which the path along the edges crosses x, y and z. Neighbouring
    /// hexahedra cut this way share their faces' diagonals, so the mesh is conforming. Each
    /// tetrahedron is stored positive (`N1 N2 N3 N3 N4 N4 N4 N4`, [`crate::element::shape`]).
    pub fn split_tets(&self) -> BoxMesh {
        const ORDERS: [[usize; 3]; 6] = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let mut conn = Vec::with_capacity(6 * self.conn.len());
        for c in &self.conn {
            for order in ORDERS {
                let mut b = [0usize; 3];
                let mut path = [corner(0, 0, 0); 4];
                for (k, &axis) in order.iter().enumerate() {
                    b[axis] = 1;
                    path[k + 1] = corner(b[0], b[1], b[2]);
                }
                let mut t = path.map(|k| c[k]);
                if !self.positive(&[t[0], t[1], t[2], t[2], t[3], t[3], t[3], t[3]]) {
                    t.swap(1, 2);
                }
                conn.push([t[0], t[1], t[2], t[2], t[3], t[3], t[3], t[3]]);
            }
        }
        BoxMesh {
            x: self.x.clone(),
            conn,
        }
    }

    /// Each hexahedron cut into 2 wedges by the plane through its edges 1-5 and 3-7 (bits
    /// (0,y,0)-(0,y,1) ... the diagonal of its y = const faces from (0,·,0) to (1,·,1)): the
    /// triangles lie on the y = const faces, the quadrilaterals on the others and on the
    /// cut, so hexahedra and wedges cut this way meet on whole faces along x and z. Stored as
    /// LS-DYNA writes a wedge, `N1 N2 N3 N4 N5 N5 N6 N6` (triangles 1-2-5 and 4-3-6), positive.
    pub fn split_wedges(&self) -> BoxMesh {
        // the prisms a b c / d e f (triangles on y = 0 and y = 1, edges a-d, b-e, c-f)
        let prisms = [
            [(0, 0), (1, 0), (1, 1)], // (x, z) of a, b, c
            [(0, 0), (1, 1), (0, 1)],
        ];
        let mut conn = Vec::with_capacity(2 * self.conn.len());
        for c in &self.conn {
            for p in prisms {
                let lo = p.map(|(x, z)| c[corner(x, 0, z)]);
                let hi = p.map(|(x, z)| c[corner(x, 1, z)]);
                // LS-DYNA's N1..N6 = a b e d c f
                let mut w = [lo[0], lo[1], hi[1], hi[0], lo[2], lo[2], hi[2], hi[2]];
                if !self.positive(&w) {
                    w = [lo[0], lo[2], hi[2], hi[0], lo[1], lo[1], hi[1], hi[1]];
                }
                conn.push(w);
            }
        }
        BoxMesh {
            x: self.x.clone(),
            conn,
        }
    }

    fn positive(&self, c: &[u32; 8]) -> bool {
        let xe = c.map(|n| self.x[n as usize]);
        let shape = element::shape::shape_of(c).unwrap_or(Shape::Hex);
        element::first_bad_corner(shape, &xe).is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::shape::{face_key, shape_of};
    use crate::element::volume;

    /// Both cuts fill the box exactly with upright elements, and every interior face is
    /// shared by exactly two elements (conforming).
    #[test]
    fn cuts_fill_the_box_and_conform() {
        let mut m = BoxMesh::new([3, 2, 2], [3.0, 2.0, 1.0]);
        // distort the interior a little
        for p in &mut m.x {
            p[0] += 0.05 * (p[1] * 1.7).sin() * (p[2] * 2.3).cos();
        }
        for (cut, shape, per) in [
            (m.split_tets(), Shape::Tet, 6),
            (m.split_wedges(), Shape::Wedge, 2),
        ] {
            assert_eq!(cut.conn.len(), per * m.conn.len());
            let mut v = 0.0;
            let mut keys = Vec::new();
            for c in &cut.conn {
                assert_eq!(shape_of(c), Some(shape));
                let xe = c.map(|n| cut.x[n as usize]);
                assert!(element::first_bad_corner(shape, &xe).is_none());
                v += volume(shape, &xe);
                for f in crate::element::hex8::FACES {
                    keys.extend(face_key(f.map(|k| c[k])));
                }
            }
            assert!((v - 6.0).abs() < 1e-12, "{shape:?}: volume {v}");
            keys.sort_unstable();
            let mut boundary = 0;
            let mut i = 0;
            while i < keys.len() {
                let j = keys[i..].iter().take_while(|k| **k == keys[i]).count();
                assert!(j <= 2, "a face shared by {j} elements");
                boundary += usize::from(j == 1);
                i += j;
            }
            // the box's surface, 3 x 2 x 2 hexahedra: 2 (3x2 + 3x2 + 2x2) = 32 quads, as 2
            // triangles each for tetrahedra; for wedges only the 12 on y = const are cut
            let want = match shape {
                Shape::Tet => 64,
                _ => 20 + 24,
            };
            assert_eq!(boundary, want, "{shape:?}");
        }
    }
}
