//! Element shapes in the 8-node connectivity every element is stored with.
//!
//! LS-DYNA writes tetrahedra and wedges in `*ELEMENT_SOLID` as degenerate hexahedra:
//! tetrahedron `N1 N2 N3 N4 N4 N4 N4 N4`, pentahedron (wedge) `N1 N2 N3 N4 N5 N5 N6 N6`
//! (Keyword Manual, *ELEMENT_SOLID). cleave stores them as 8 corners too, in the layout
//! whose six hexahedron faces ([`super::hex8::FACES`]) are the element's true faces, each
//! triangle as a quadrilateral with its last corner repeated (LS-DYNA's `N1 N2 N3 N3`
//! segment), and the faces collapsed to an edge or a point left over:
//!
//! - hexahedron: 8 distinct corners;
//! - wedge `N1 N2 N3 N4 N5 N5 N6 N6` as LS-DYNA writes it: quadrilaterals 1-4-3-2, 2-3-6-5,
//!   4-1-5-6 and triangles 1-2-5, 3-4-6 (top face collapsed to the edge 5-6);
//! - tetrahedron `N1 N2 N3 N3 N4 N4 N4 N4` (the deck's `N1 N2 N3 N4 N4 N4 N4 N4` is
//!   reordered by [`canonical`]): triangles 1-3-2, 1-2-4, 2-3-4, 3-1-4.
//!
//! A positive volume means, for the tetrahedron, N4 on the side of N1 N2 N3 that the
//! right-hand rule points to; for all shapes, outward face normals in [`super::hex8::FACES`]
//! order. Which formulation runs on which shape is [`Shape`]'s doc.

/// The shape of an element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Shape {
    /// 8-node hexahedron: the one-point hexahedron with hourglass control
    /// ([`super::kernel::hex8_step`]).
    Hex,
    /// 6-node wedge: the same one-point hexahedron on the degenerate corners, as LS-DYNA's
    /// ELFORM 1 runs it (a linear field is still reproduced exactly: the hexahedron's
    /// isoparametric map of the degenerate corners is the wedge's).
    Wedge,
    /// 4-node tetrahedron: the constant-strain tetrahedron ([`super::tet4::tet4_step`]),
    /// LS-DYNA's ELFORM 10, whatever the section says (LS-DYNA's `*CONTROL_SOLID` ESORT = 1:
    /// the one-point hexahedron on a collapsed tetrahedron is poor, and LS-DYNA's manual
    /// advises against it).
    Tet,
}

impl Shape {
    /// Number of distinct nodes.
    pub fn nodes(self) -> usize {
        match self {
            Shape::Hex => 8,
            Shape::Wedge => 6,
            Shape::Tet => 4,
        }
    }

    /// The name users know it by.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Hex => "hexahedron",
            Shape::Wedge => "wedge",
            Shape::Tet => "tetrahedron",
        }
    }

    /// The plural of [`Self::name`].
    pub fn plural(self) -> &'static str {
        match self {
            Shape::Hex => "hexahedra",
            Shape::Wedge => "wedges",
            Shape::Tet => "tetrahedra",
        }
    }

    /// The corners (indices into the 8) that hold the distinct nodes, in order.
    pub fn corners(self) -> &'static [usize] {
        match self {
            Shape::Hex => &[0, 1, 2, 3, 4, 5, 6, 7],
            Shape::Wedge => &[0, 1, 2, 3, 4, 6],
            Shape::Tet => &[0, 1, 2, 4],
        }
    }
}

/// The shape of a stored connectivity (the layouts of the module docs), `None` for any other
/// pattern of repeated nodes.
pub fn shape_of(c: &[u32; 8]) -> Option<Shape> {
    let distinct = |idx: &[usize]| {
        idx.iter()
            .enumerate()
            .all(|(i, &a)| idx[i + 1..].iter().all(|&b| c[a] != c[b]))
    };
    if distinct(&[0, 1, 2, 3, 4, 5, 6, 7]) {
        Some(Shape::Hex)
    } else if c[4] == c[5] && c[6] == c[7] && distinct(&[0, 1, 2, 3, 4, 6]) {
        Some(Shape::Wedge)
    } else if c[2] == c[3]
        && c[4] == c[5]
        && c[4] == c[6]
        && c[4] == c[7]
        && distinct(&[0, 1, 2, 4])
    {
        Some(Shape::Tet)
    } else {
        None
    }
}

/// The stored connectivity and shape of an `*ELEMENT_SOLID` card's 8 nodes: hexahedra and
/// wedges as written; a tetrahedron `N1 N2 N3 N4 N4 N4 N4 N4` (or the older
/// `N1 N2 N3 N3 N4 N4 N4 N4`) as `N1 N2 N3 N3 N4 N4 N4 N4`. Any other repetition is an error
/// saying what is accepted.
pub fn canonical(n: [u32; 8]) -> Result<([u32; 8], Shape), String> {
    let tet = n[3] == n[4] && n[4] == n[5] && n[5] == n[6] && n[6] == n[7];
    let stored = if tet && n[3] != n[2] {
        [n[0], n[1], n[2], n[2], n[3], n[3], n[3], n[3]]
    } else {
        n
    };
    shape_of(&stored).map(|s| (stored, s)).ok_or_else(|| {
        "repeated nodes in a pattern cleave does not take: a solid is a hexahedron (8 distinct \
         nodes), a wedge N1 N2 N3 N4 N5 N5 N6 N6 or a tetrahedron N1 N2 N3 N4 N4 N4 N4 N4"
            .to_string()
    })
}

/// The distinct nodes of a face's 4 corners, sorted, padded with `u32::MAX`: the key two
/// elements' faces share when they are the same face (a triangle keyed by its 3 nodes,
/// whichever corner the element repeats). Faces with fewer than 3 distinct nodes (collapsed
/// to an edge or a point) give `None`.
pub fn face_key(nodes: [u32; 4]) -> Option<[u32; 4]> {
    let mut k = nodes;
    k.sort_unstable();
    let mut out = [u32::MAX; 4];
    let mut m = 0;
    for (i, &n) in k.iter().enumerate() {
        if i == 0 || n != k[i - 1] {
            out[m] = n;
            m += 1;
        }
    }
    (m >= 3).then_some(out)
}

/// The corners of face `f` ([`super::hex8::FACES`] order, outward) of an element with stored
/// connectivity `c`, turned round (a cyclic shift, so still outward) so that a triangle's
/// repeated corner comes last: LS-DYNA's triangular segment `N1 N2 N3 N3`. A quadrilateral
/// and a collapsed face are returned as they are.
#[inline]
pub fn face_corners(c: &[u32; 8], f: usize) -> [usize; 4] {
    let fc = super::hex8::FACES[f];
    let same = |i: usize| c[fc[i]] == c[fc[(i + 1) % 4]];
    match (0..4).filter(|&i| same(i)).count() {
        1 => {
            let i = (0..4).find(|&i| same(i)).unwrap_or(2);
            std::array::from_fn(|k| fc[(k + i + 2) % 4])
        }
        _ => fc,
    }
}

/// Number of distinct points of a face's 4 nodes as [`face_corners`] orders them: 3 for a
/// triangle (last node repeated), else 4.
#[inline]
pub fn face_points(nodes: &[u32; 4]) -> usize {
    if nodes[3] == nodes[2] {
        3
    } else {
        4
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::hex8::FACES;

    #[test]
    fn shapes_are_recognised_and_tets_reordered() {
        assert_eq!(shape_of(&[0, 1, 2, 3, 4, 5, 6, 7]), Some(Shape::Hex));
        assert_eq!(shape_of(&[0, 1, 2, 3, 4, 4, 5, 5]), Some(Shape::Wedge));
        let (c, s) = canonical([0, 1, 2, 3, 3, 3, 3, 3]).unwrap();
        assert_eq!((c, s), ([0, 1, 2, 2, 3, 3, 3, 3], Shape::Tet));
        assert_eq!(canonical(c).unwrap(), (c, Shape::Tet));
        // a pyramid and a wedge with a repeated base node are refused
        assert!(canonical([0, 1, 2, 3, 4, 4, 4, 4]).is_err());
        assert!(canonical([0, 0, 2, 3, 4, 4, 5, 5]).is_err());
        assert!(canonical([0, 1, 2, 3, 4, 5, 6, 6]).is_err());
    }

    #[test]
    fn faces_of_each_shape() {
        let faces = |c: [u32; 8]| -> Vec<[u32; 4]> {
            FACES
                .iter()
                .filter_map(|f| face_key(f.map(|k| c[k])))
                .collect()
        };
        let tet = faces([0, 1, 2, 2, 3, 3, 3, 3]);
        assert_eq!(tet.len(), 4);
        let wedge = faces([0, 1, 2, 3, 4, 4, 5, 5]);
        assert_eq!(wedge.len(), 5);
        let tris = wedge.iter().filter(|k| k[3] == u32::MAX).count();
        assert_eq!(tris, 2);
        // triangles come with their repeated corner last
        for c in [[0, 1, 2, 2, 3, 3, 3, 3], [0, 1, 2, 3, 4, 4, 5, 5]] {
            for f in 0..6 {
                let n = face_corners(&c, f).map(|k| c[k]);
                if face_key(n).is_some_and(|k| k[3] == u32::MAX) {
                    assert_eq!(n[2], n[3], "{c:?} face {f}: {n:?}");
                    assert_eq!(face_points(&n), 3);
                }
            }
        }
        // every node triple of the tetrahedron is a face
        let mut want = vec![[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]];
        let mut got: Vec<[u32; 3]> = tet.iter().map(|k| [k[0], k[1], k[2]]).collect();
        want.sort_unstable();
        got.sort_unstable();
        assert_eq!(got, want);
    }
}
