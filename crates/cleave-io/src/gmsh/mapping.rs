//! Gmsh's linear solids in cleave's 8-node LS-DYNA connectivity, their volume, and the node
//! permutation that turns an inverted one the right way out.
//!
//! Node orders (Gmsh reference manual, "Node ordering"; LS-DYNA Keyword Manual,
//! `*ELEMENT_SOLID`):
//!
//! - hexahedron (type 5): Gmsh's 0-3 are the bottom face, 4-7 the top one, 4 above 0: the same
//!   as LS-DYNA's N1..N8, taken as they are.
//! - tetrahedron (type 4) `a b c d` -> `a b c d d d d d` (LS-DYNA's tetrahedron, N4 repeated).
//! - prism (type 6): Gmsh's `a b c` is the bottom triangle, `d e f` the top one, edges a-d, b-e,
//!   c-f. LS-DYNA's pentahedron is `N1 N2 N3 N4 N5 N5 N6 N6`: the hexahedron with nodes 5 = 6
//!   and 7 = 8, whose faces are the triangles (1, 2, 5) and (4, 3, 6) and the quadrangles
//!   1234, 2365 and 4156. The prism goes to `a c f d b b e e`: triangles (a, c, b) and
//!   (d, f, e), quadrangles a-c-f-d, c-f-e-b and d-a-b-e. The other assignment that fits the
//!   pattern, `a b e d c c f f`, is the mirror image: a prism Gmsh writes with positive volume
//!   has a negative one there (the test `prism_mapping_keeps_the_volume_positive` computes both).
//!
//! A Gmsh element is positively oriented when its (a, b, c, d) or, for a hexahedron, its
//! trilinear map has a positive Jacobian; Gmsh writes them so, but a file from elsewhere may
//! not. An element whose mapped volume is negative is turned by a permutation that mirrors it
//! (tetrahedron: b <-> c; hexahedron: bottom <-> top; prism: bottom triangle <-> top) and
//! counted; one with zero or non-finite volume is an error.
//!
//! Volume: the hexahedron's and the prism's is the exact volume of the trilinear map of their
//! 8-node form (`cleave_core::element::hex8::volume`, 2x2x2 Gauss points; the collapsed
//! prism's map covers the prism with its bilinear side faces once). The tetrahedron's is
//! `((b - a) x (c - a)) . (d - a) / 6`: the trilinear map of `a b c d d d d d` is not the
//! tetrahedron (its bottom face is the bilinear patch through a, b, c, d, which cuts the
//! tetrahedron in two equal halves) and `hex8::volume` of it is half the tetrahedron's volume
//! (`tet_form_has_half_the_volume_in_the_hexahedron_map` below): a solver must treat that
//! form as a tetrahedron, not as a hexahedron.

use cleave_core::element::hex8;
use cleave_core::math::{cross, dot, sub, Vec3};

/// The kind of a solid element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SolidKind {
    /// 4-node tetrahedron (Gmsh type 4).
    Tet4,
    /// 8-node hexahedron (Gmsh type 5).
    Hex8,
    /// 6-node prism (Gmsh type 6).
    Prism6,
}

impl SolidKind {
    /// The kind of Gmsh element type `number`, if it is a linear solid cleave reads.
    pub fn of_gmsh(number: i64) -> Option<Self> {
        match number {
            4 => Some(Self::Tet4),
            5 => Some(Self::Hex8),
            6 => Some(Self::Prism6),
            _ => None,
        }
    }

    /// The Gmsh element type number.
    pub fn gmsh_type(self) -> i64 {
        match self {
            Self::Tet4 => 4,
            Self::Hex8 => 5,
            Self::Prism6 => 6,
        }
    }

    /// Short name: `tet4`, `hex8`, `prism6`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Tet4 => "tet4",
            Self::Hex8 => "hex8",
            Self::Prism6 => "prism6",
        }
    }

    /// Nodes of the Gmsh element.
    pub fn nodes(self) -> usize {
        match self {
            Self::Tet4 => 4,
            Self::Hex8 => 8,
            Self::Prism6 => 6,
        }
    }
}

/// The 8-node LS-DYNA connectivity of a Gmsh element of `kind` with nodes `g` (which holds
/// `kind.nodes()` values; missing ones read as 0, which callers never pass).
pub fn to_dyna<T: Copy + Default>(kind: SolidKind, g: &[T]) -> [T; 8] {
    let n = |k: usize| g.get(k).copied().unwrap_or_default();
    match kind {
        SolidKind::Hex8 => [n(0), n(1), n(2), n(3), n(4), n(5), n(6), n(7)],
        SolidKind::Tet4 => [n(0), n(1), n(2), n(3), n(3), n(3), n(3), n(3)],
        SolidKind::Prism6 => [n(0), n(2), n(5), n(3), n(1), n(1), n(4), n(4)],
    }
}

/// Mirrors a Gmsh element in place (its volume changes sign).
pub fn mirror<T>(kind: SolidKind, g: &mut [T]) {
    match kind {
        SolidKind::Tet4 if g.len() >= 3 => g.swap(1, 2),
        SolidKind::Hex8 if g.len() >= 8 => {
            for k in 0..4 {
                g.swap(k, k + 4);
            }
        }
        SolidKind::Prism6 if g.len() >= 6 => {
            for k in 0..3 {
                g.swap(k, k + 3);
            }
        }
        _ => {}
    }
}

/// The volume of a solid of `kind` from the coordinates of its 8-node form (signed: negative
/// when the element is inside out).
pub fn volume(kind: SolidKind, x: &[Vec3; 8]) -> f64 {
    match kind {
        SolidKind::Tet4 => dot(cross(sub(x[1], x[0]), sub(x[2], x[0])), sub(x[3], x[0])) / 6.0,
        SolidKind::Hex8 | SolidKind::Prism6 => hex8::volume(x),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn coords(kind: SolidKind, g: &[Vec3]) -> [Vec3; 8] {
        to_dyna(kind, g)
    }

    const PRISM: [Vec3; 6] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.1, 0.2, 1.0],
        [1.1, 0.2, 1.0],
        [0.1, 1.2, 1.0],
    ];

    #[test]
    fn prism_mapping_keeps_the_volume_positive() {
        // a sheared prism of base area 1/2 and height 1, positive in Gmsh's sense
        let v = volume(SolidKind::Prism6, &coords(SolidKind::Prism6, &PRISM));
        assert!((v - 0.5).abs() < 1e-15, "{v}");
        // the mirrored assignment a b e d c c f f of the same prism is inside out
        let [a, b, c, d, e, f] = PRISM;
        assert!((hex8::volume(&[a, b, e, d, c, c, f, f]) + 0.5).abs() < 1e-15);
        // its corner Jacobians, where the collapsed edge is not, are positive
        let j = hex8::corner_jacobians(&coords(SolidKind::Prism6, &PRISM));
        assert!(j[..4].iter().all(|&j| j > 0.0), "{j:?}");
    }

    #[test]
    fn tet_form_has_half_the_volume_in_the_hexahedron_map() {
        let t = [
            [0.1, 0.0, 0.0],
            [1.0, 0.2, 0.0],
            [0.3, 1.0, 0.1],
            [0.2, 0.3, 1.0],
        ];
        let x = coords(SolidKind::Tet4, &t);
        let v = volume(SolidKind::Tet4, &x);
        assert!(v > 0.0);
        assert!((hex8::volume(&x) - v / 2.0).abs() < 1e-15 * v.abs().max(1.0));
    }

    #[test]
    fn mirror_flips_the_sign() {
        let mut p = PRISM;
        mirror(SolidKind::Prism6, &mut p);
        let v = volume(SolidKind::Prism6, &coords(SolidKind::Prism6, &p));
        assert!((v + 0.5).abs() < 1e-15);
        let mut t = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        assert!((volume(SolidKind::Tet4, &coords(SolidKind::Tet4, &t)) - 1.0 / 6.0).abs() < 1e-15);
        mirror(SolidKind::Tet4, &mut t);
        assert!((volume(SolidKind::Tet4, &coords(SolidKind::Tet4, &t)) + 1.0 / 6.0).abs() < 1e-15);
        let mut h: Vec<Vec3> = hex8::CORNERS.to_vec();
        assert!((volume(SolidKind::Hex8, &coords(SolidKind::Hex8, &h)) - 8.0).abs() < 1e-12);
        mirror(SolidKind::Hex8, &mut h);
        assert!((volume(SolidKind::Hex8, &coords(SolidKind::Hex8, &h)) + 8.0).abs() < 1e-12);
    }
}
