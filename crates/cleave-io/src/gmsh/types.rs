//! Gmsh's element types: number, nodes, dimension, order and name.
//!
//! The table is what Gmsh 4.15.2 itself reports (`gmsh.model.mesh.getElementProperties` for
//! every type number it knows), plus the complete high-order prisms 90, 91 and 106-110 of
//! Gmsh's `GmshDefines.h`. A reader needs a type's node count to read past its elements, so a
//! type not in this table is an error; the types cleave uses are
//! 1 (2-node line), 2 (3-node triangle), 3 (4-node quadrangle), 4 (4-node tetrahedron),
//! 5 (8-node hexahedron), 6 (6-node prism) and 15 (1-node point).

/// One element type of the MSH format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ElemType {
    /// The MSH type number.
    pub number: i64,
    /// Nodes per element.
    pub nodes: usize,
    /// Dimension: 0 point, 1 line, 2 surface, 3 volume.
    pub dim: u8,
    /// Polynomial order (0 for the 1-node types).
    pub order: u8,
    /// Gmsh's name, e.g. `Tetrahedron 10`.
    pub name: &'static str,
}

/// The type `number`, if Gmsh has it.
pub fn elem_type(number: i64) -> Option<ElemType> {
    TABLE.binary_search_by_key(&number, |t| t.0).ok().map(|k| {
        let (number, nodes, dim, order, name) = TABLE[k];
        ElemType {
            number,
            nodes,
            dim,
            order,
            name,
        }
    })
}

/// (number, nodes, dimension, order, name), sorted by number.
const TABLE: &[(i64, usize, u8, u8, &str)] = &[
    (1, 2, 1, 1, "Line 2"),
    (2, 3, 2, 1, "Triangle 3"),
    (3, 4, 2, 1, "Quadrilateral 4"),
    (4, 4, 3, 1, "Tetrahedron 4"),
    (5, 8, 3, 1, "Hexahedron 8"),
    (6, 6, 3, 1, "Prism 6"),
    (7, 5, 3, 1, "Pyramid 5"),
    (8, 3, 1, 2, "Line 3"),
    (9, 6, 2, 2, "Triangle 6"),
    (10, 9, 2, 2, "Quadrilateral 9"),
    (11, 10, 3, 2, "Tetrahedron 10"),
    (12, 27, 3, 2, "Hexahedron 27"),
    (13, 18, 3, 2, "Prism 18"),
    (14, 14, 3, 2, "Pyramid 14"),
    (15, 1, 0, 0, "Point"),
    (16, 8, 2, 2, "Quadrilateral 8"),
    (17, 20, 3, 2, "Hexahedron 20"),
    (18, 15, 3, 2, "Prism 15"),
    (19, 13, 3, 2, "Pyramid 13"),
    (20, 9, 2, 3, "Triangle 9"),
    (21, 10, 2, 3, "Triangle 10"),
    (22, 12, 2, 4, "Triangle 12"),
    (23, 15, 2, 4, "Triangle 15"),
    (24, 15, 2, 5, "Triangle 15I"),
    (25, 21, 2, 5, "Triangle 21"),
    (26, 4, 1, 3, "Line 4"),
    (27, 5, 1, 4, "Line 5"),
    (28, 6, 1, 5, "Line 6"),
    (29, 20, 3, 3, "Tetrahedron 20"),
    (30, 35, 3, 4, "Tetrahedron 35"),
    (31, 56, 3, 5, "Tetrahedron 56"),
    (32, 22, 3, 4, "Tetrahedron 22"),
    (33, 28, 3, 5, "Tetrahedron 28"),
    (36, 16, 2, 3, "Quadrilateral 16"),
    (37, 25, 2, 4, "Quadrilateral 25"),
    (38, 36, 2, 5, "Quadrilateral 36"),
    (39, 12, 2, 3, "Quadrilateral 12"),
    (40, 16, 2, 4, "Quadrilateral 16I"),
    (41, 20, 2, 5, "Quadrilateral 20"),
    (42, 28, 2, 6, "Triangle 28"),
    (43, 36, 2, 7, "Triangle 36"),
    (44, 45, 2, 8, "Triangle 45"),
    (45, 55, 2, 9, "Triangle 55"),
    (46, 66, 2, 10, "Triangle 66"),
    (47, 49, 2, 6, "Quadrilateral 49"),
    (48, 64, 2, 7, "Quadrilateral 64"),
    (49, 81, 2, 8, "Quadrilateral 81"),
    (50, 100, 2, 9, "Quadrilateral 100"),
    (51, 121, 2, 10, "Quadrilateral 121"),
    (52, 18, 2, 6, "Triangle 18"),
    (53, 21, 2, 7, "Triangle 21I"),
    (54, 24, 2, 8, "Triangle 24"),
    (55, 27, 2, 9, "Triangle 27"),
    (56, 30, 2, 10, "Triangle 30"),
    (57, 24, 2, 6, "Quadrilateral 24"),
    (58, 28, 2, 7, "Quadrilateral 28"),
    (59, 32, 2, 8, "Quadrilateral 32"),
    (60, 36, 2, 9, "Quadrilateral 36I"),
    (61, 40, 2, 10, "Quadrilateral 40"),
    (62, 7, 1, 6, "Line 7"),
    (63, 8, 1, 7, "Line 8"),
    (64, 9, 1, 8, "Line 9"),
    (65, 10, 1, 9, "Line 10"),
    (66, 11, 1, 10, "Line 11"),
    (71, 84, 3, 6, "Tetrahedron 84"),
    (72, 120, 3, 7, "Tetrahedron 120"),
    (73, 165, 3, 8, "Tetrahedron 165"),
    (74, 220, 3, 9, "Tetrahedron 220"),
    (75, 286, 3, 10, "Tetrahedron 286"),
    (79, 34, 3, 6, "Tetrahedron 34"),
    (80, 40, 3, 7, "Tetrahedron 40"),
    (81, 46, 3, 8, "Tetrahedron 46"),
    (82, 52, 3, 9, "Tetrahedron 52"),
    (83, 58, 3, 10, "Tetrahedron 58"),
    (84, 1, 1, 0, "Line 1"),
    (85, 1, 2, 0, "Triangle 1"),
    (86, 1, 2, 0, "Quadrilateral 1"),
    (87, 1, 3, 0, "Tetrahedron 1"),
    (88, 1, 3, 0, "Hexahedron 1"),
    (89, 1, 3, 0, "Prism 1"),
    (90, 40, 3, 3, "Prism 40"),
    (91, 75, 3, 4, "Prism 75"),
    (92, 64, 3, 3, "Hexahedron 64"),
    (93, 125, 3, 4, "Hexahedron 125"),
    (94, 216, 3, 5, "Hexahedron 216"),
    (95, 343, 3, 6, "Hexahedron 343"),
    (96, 512, 3, 7, "Hexahedron 512"),
    (97, 729, 3, 8, "Hexahedron 729"),
    (98, 1000, 3, 9, "Hexahedron 1000"),
    (99, 32, 3, 3, "Hexahedron 32"),
    (100, 44, 3, 4, "Hexahedron 44"),
    (101, 56, 3, 5, "Hexahedron 56"),
    (102, 68, 3, 6, "Hexahedron 68"),
    (103, 80, 3, 7, "Hexahedron 80"),
    (104, 92, 3, 8, "Hexahedron 92"),
    (105, 104, 3, 9, "Hexahedron 104"),
    (106, 126, 3, 5, "Prism 126"),
    (107, 196, 3, 6, "Prism 196"),
    (108, 288, 3, 7, "Prism 288"),
    (109, 405, 3, 8, "Prism 405"),
    (110, 550, 3, 9, "Prism 550"),
    (118, 30, 3, 3, "Pyramid 30"),
    (119, 55, 3, 4, "Pyramid 55"),
    (120, 91, 3, 5, "Pyramid 91"),
    (121, 140, 3, 6, "Pyramid 140"),
    (122, 204, 3, 7, "Pyramid 204"),
    (123, 285, 3, 8, "Pyramid 285"),
    (124, 385, 3, 9, "Pyramid 385"),
    (125, 21, 3, 3, "Pyramid 21"),
    (126, 29, 3, 4, "Pyramid 29"),
    (127, 37, 3, 5, "Pyramid 37"),
    (128, 45, 3, 6, "Pyramid 45"),
    (129, 53, 3, 7, "Pyramid 53"),
    (130, 61, 3, 8, "Pyramid 61"),
    (131, 69, 3, 9, "Pyramid 69"),
    (132, 1, 3, 0, "Pyramid 1"),
    (137, 16, 3, 3, "Tetrahedron 16"),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_sorted_and_knows_the_usual_types() {
        assert!(TABLE.windows(2).all(|w| w[0].0 < w[1].0));
        assert_eq!(elem_type(4).map(|t| (t.nodes, t.dim)), Some((4, 3)));
        assert_eq!(elem_type(6).map(|t| (t.nodes, t.dim)), Some((6, 3)));
        assert_eq!(elem_type(11).map(|t| (t.nodes, t.order)), Some((10, 2)));
        assert_eq!(elem_type(15).map(|t| (t.nodes, t.dim)), Some((1, 0)));
        assert_eq!(elem_type(0), None);
        assert_eq!(elem_type(1000), None);
    }
}
