//! Reading Gmsh meshes (`.msh`) and converting them to LS-DYNA keyword text.
//!
//! # The format
//!
//! MSH 4.1 and MSH 2.2 (2.0 and 2.1 read as 2.2), ASCII and binary, as the Gmsh reference
//! manual's section "MSH file format" (and, for 2.2, "MSH file format version 2") describes
//! them. A file is a list of sections `$Name` ... `$EndName`; `$MeshFormat` comes first
//! (`format`), then cleave reads `$PhysicalNames` (`names`), `$Entities` (4.1: the physical
//! groups of each geometric entity), `$Nodes` and `$Elements` (`v4`, `v2`), and skips every
//! other section by name (`sections`). Binary files keep their section names, counts (2.2) and
//! `$PhysicalNames` in ASCII; their data is `int` (4 bytes), `double` (8) and, in 4.1, `size_t`
//! of data-size bytes, in the byte order the integer 1 after the header tells (`cursor`).
//!
//! Element types read (the node counts of every Gmsh type are in `types`, so that the
//! elements cleave does not use can be read past): 4 (4-node tetrahedron), 5 (8-node
//! hexahedron) and 6 (6-node prism) as solids; 2 (3-node triangle) and 3 (4-node quadrangle)
//! as faces of physical surfaces; 1 (2-node line) and 15 (point) for the nodes of physical
//! curves and points.
//!
//! # The mapping to LS-DYNA
//!
//! - A node's tag is its NID, a 3-D element's tag its EID.
//! - A solid's part id (PID) is the tag of the physical volume it is in. One in no physical
//!   volume takes its geometric volume entity's tag (Gmsh writes such elements only when the
//!   file has no physical group, or with `Mesh.SaveAll`); if that tag is also a physical
//!   volume's, it is an error (two parts would silently merge). A solid in two physical volumes
//!   is an error: in 4.1 its entity lists two, in 2.2 Gmsh writes it twice with two element
//!   tags, which is found as two solids with the same nodes.
//! - Connectivity in cleave's 8-node LS-DYNA form (`mapping`): hexahedra as Gmsh orders them,
//!   tetrahedra `a b c d d d d d`, prisms `a c f d b b e e` (LS-DYNA's pentahedron
//!   `N1 N2 N3 N4 N5 N5 N6 N6`; `mapping` says why not `a b e d c c f f`). Every solid comes out
//!   with positive volume: one that Gmsh (or whoever wrote the file) left inside out is
//!   mirrored by a permutation of its nodes and counted ([`Mesh::reoriented`]).
//! - A physical surface becomes a `*SET_SEGMENT` with SID = its tag (a triangle as
//!   `N1 N2 N3 N3`, a quadrangle as written) and a `*SET_NODE_LIST` of its nodes with the same
//!   SID; a physical curve or point becomes a `*SET_NODE_LIST` with SID = its tag.
//! - Physical groups are numbered per dimension in Gmsh; LS-DYNA's node sets share one id
//!   space. Two groups of dimension 0 to 2 with one tag are an error that names both and asks
//!   to renumber one in Gmsh. A physical volume may share its tag with a curve or surface:
//!   one is a part id, the other a set id, and those never meet.
//! - Names (`$PhysicalNames`) title the sets (`*SET_..._TITLE`); the parts, which the including
//!   deck defines, are listed with their names in the `$` header of the keyword text.
//!
//! # What is refused
//!
//! Every error names the file and the line (ASCII) or byte offset (binary, [`At`]); nothing
//! panics on any input. Refused: a version other than 4.1 and 2.x; a truncated file, counts
//! that do not match the data, values missing or extra on a line; an element that refers to a
//! node `$Nodes` does not define; a node or element tag used twice; a 3-D element other than
//! types 4, 5, 6 (second-order ones, such as type 11, the 10-node tetrahedron, with "re-mesh
//! with order 1"; pyramids) and, in a physical group, a lower-dimensional element other than
//! types 1, 2, 3, 15; a solid with zero volume.

mod assemble;
mod cursor;
mod error;
mod format;
mod keyword;
pub mod mapping;
mod names;
mod raw;
mod sections;
pub mod types;
mod v2;
mod v4;

use std::collections::HashMap;
use std::path::Path;

pub use error::{At, MshError};
pub use keyword::{keyword_text, summary};
pub use mapping::SolidKind;
pub use raw::Version;

/// How a file was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Format {
    pub version: Version,
    pub binary: bool,
}

/// A node: its tag (the LS-DYNA NID) and coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub tag: i64,
    pub x: [f64; 3],
}

/// A solid element in cleave's 8-node LS-DYNA form.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Solid {
    /// The Gmsh element tag (the LS-DYNA EID).
    pub tag: i64,
    pub kind: SolidKind,
    /// N1..N8 as node tags (module doc: the mapping), positively oriented.
    pub nodes: [i64; 8],
    /// The part id: the physical volume tag, or the volume entity's tag outside any.
    pub part: i64,
}

/// A physical group that holds elements in the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    /// 0 point, 1 curve, 2 surface, 3 volume.
    pub dim: u8,
    /// The physical tag (a part id for a volume, a set id otherwise).
    pub tag: i64,
    /// Its `$PhysicalNames` name ("" without one).
    pub name: String,
    /// The tags of its elements' nodes, ascending, each once.
    pub nodes: Vec<i64>,
    /// A surface's faces as 4 node tags (a triangle with its third node repeated), sorted by
    /// those tags (MSH 2.2 and 4.1 files of one mesh may number its elements differently);
    /// empty for other dimensions.
    pub faces: Vec<[i64; 4]>,
    /// How many of the file's elements are in it.
    pub elements: usize,
}

/// A Gmsh mesh as cleave uses it.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub format: Format,
    /// Every node of the file, by ascending tag.
    pub nodes: Vec<Node>,
    /// Every 3-D element, by ascending tag.
    pub solids: Vec<Solid>,
    /// The physical groups that hold elements, by dimension then tag.
    pub groups: Vec<Group>,
    /// How many elements of each Gmsh type the file holds (those not used included), by type.
    pub element_counts: Vec<(i64, usize)>,
    /// Solids that were inside out as written and were mirrored.
    pub reoriented: usize,
}

impl Mesh {
    /// Coordinates by node tag.
    pub fn coords(&self) -> HashMap<i64, [f64; 3]> {
        self.nodes.iter().map(|n| (n.tag, n.x)).collect()
    }

    /// The (positive) volume of each solid, in solid order.
    pub fn volumes(&self) -> Vec<f64> {
        let x = self.coords();
        self.solids
            .iter()
            .map(|s| {
                let c = s.nodes.map(|n| x.get(&n).copied().unwrap_or_default());
                mapping::volume(s.kind, &c)
            })
            .collect()
    }
}

/// Reads the Gmsh mesh at `path`; errors name the file as given.
pub fn read_msh(path: &Path) -> Result<Mesh, MshError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| MshError::file(&file, format!("cannot read the mesh: {e}")))?;
    parse_msh(&bytes, &file)
}

/// Reads a Gmsh mesh from the bytes of a file; `file` names it in messages.
pub fn parse_msh(bytes: &[u8], file: &str) -> Result<Mesh, MshError> {
    let raw = sections::read(file, bytes)?;
    let mut c = cursor::Cursor::new(file, bytes);
    if raw.binary {
        c.set_binary(8);
    }
    assemble::assemble(raw, &c)
}
