//! Splitting the mesh of separation groups and building the interface table.
//!
//! Node numbering of the split model: the deck's nodes that some element outside every group
//! still uses, or no element uses, keep a node (in deck order); then each group element, in element order, gets a
//! new node for each distinct corner, in corner order (8 for a hexahedron, 6 for a wedge, 4 for
//! a tetrahedron: repeated corners stay one node). Deck nodes used only by group elements have
//! no node of their own any more (as in the paper: a fully split mesh has 8 nodes per
//! hexahedron). Every solved node
//! remembers its deck node (`origin`), and copies inherit coordinates, initial velocity, single
//! point constraints, prescribed motion, node-set membership and rigid-wall membership.

use std::collections::HashMap;
use std::sync::Arc;

use super::strength;
use crate::element::hex8::{quad_area, FACES};
use crate::element::shape::{face_corners, face_key};
use crate::model::{Model, MotionTarget, PerNode};

/// Sentinel: the deck node has no solved node of its own.
const NONE: u32 = u32::MAX;

/// Whether a shared face can fail or stays bonded forever (`BOND = 0`).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceKind {
    /// May fail: a row of the interface table.
    Interface,
    /// A face between a group and another material with BOND = 0: always tied.
    Bond,
}

/// One shared face: the two elements, and the 4 + 4 coincident solved nodes, `nodes[k]` of
/// element `elems[0]` (in its outward face order) coinciding with `nodes[4 + k]` of `elems[1]`.
/// A triangle (between wedges or tetrahedra) has its last node repeated, `N1 N2 N3 N3`
/// ([`crate::element::shape::face_points`]).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, PartialEq)]
pub struct SharedFace {
    pub elems: [u32; 2],
    /// Local face number (0..6, [`FACES`]) of the face in each element.
    pub faces: [u8; 2],
    pub nodes: [u32; 8],
    /// Reference area.
    pub area0: f64,
    /// Index into `Model::separations` of the criterion that governs the face.
    pub group: u16,
    pub kind: FaceKind,
    /// Strength (Pa) of an interface, drawn once from its group's distribution
    /// ([`crate::separation::strength`]); infinite for a bond.
    pub strength: f64,
}

/// The split model and its interface table.
#[derive(Clone, Debug)]
pub struct SplitModel {
    /// The model on the split nodes (node-based data remapped to the copies).
    pub model: Model,
    /// Deck node (index into the original model) of each solved node.
    pub origin: Arc<[u32]>,
    /// Shared faces that may fail (`Interface`) followed by permanent bonds (`Bond`).
    pub faces: Vec<SharedFace>,
    /// Number of `Interface` faces (they come first in `faces`).
    pub interfaces: usize,
}

/// Split the elements of every separation group of `model` onto nodes of their own.
pub fn split_model(model: &Model) -> SplitModel {
    let ne = model.num_elements();
    let nn = model.num_nodes();
    // separation definition of each element's material, if any
    let mut mat_group = vec![NONE; model.materials.len()];
    for (g, s) in model.separations.iter().enumerate() {
        mat_group[s.material] = g as u32;
    }
    let elem_group: Vec<u32> = (0..ne)
        .map(|e| mat_group[model.parts[model.elem_part[e] as usize].material])
        .collect();

    // deck nodes still used by an element outside every group keep a node, and so do the
    // nodes of no element (free, massless: a history node, a load or wall node may name one)
    let mut keep = vec![NONE; nn];
    let mut used = vec![false; nn];
    for (e, conn) in model.conn.iter().enumerate() {
        for &n in conn {
            used[n as usize] = true;
            if elem_group[e] == NONE {
                keep[n as usize] = 0;
            }
        }
    }
    for (k, u) in keep.iter_mut().zip(&used) {
        if !u {
            *k = 0;
        }
    }
    let group_elems = elem_group.iter().filter(|&&g| g != NONE).count();
    let kept = keep.iter().filter(|&&k| k != NONE).count();
    let mut origin = Vec::with_capacity(kept + 8 * group_elems); // 8: at most
    for (n, k) in keep.iter_mut().enumerate() {
        if *k != NONE {
            *k = origin.len() as u32;
            origin.push(n as u32);
        }
    }
    let mut conn = model.conn.clone();
    for (e, c) in conn.iter_mut().enumerate() {
        if elem_group[e] == NONE {
            for n in c.iter_mut() {
                *n = keep[*n as usize];
            }
            continue;
        }
        // a node of its own for each distinct corner: a wedge's or tetrahedron's repeated
        // corners stay one node
        let deck = *c;
        for a in 0..8 {
            match deck[..a].iter().position(|&d| d == deck[a]) {
                Some(b) => c[a] = c[b],
                None => {
                    origin.push(deck[a]);
                    c[a] = (origin.len() - 1) as u32;
                }
            }
        }
    }

    // copies of each deck node (CSR), for inheriting node data
    let copies = copies_of(&origin, nn);
    let expand = |n: u32| copies.of(n).iter().copied();

    let mut m = model.clone();
    m.conn = conn;
    // the copies share their deck node's position, velocity and id
    let origin: Arc<[u32]> = origin.into();
    m.x0 = PerNode::shared(model.x0.to_vec(), origin.clone());
    m.v0 = PerNode::shared(model.v0.to_vec(), origin.clone());
    m.node_ids = PerNode::shared(model.node_ids.to_vec(), origin.clone());
    m.spcs = model
        .spcs
        .iter()
        .flat_map(|s| {
            expand(s.node).map(move |c| crate::model::Spc {
                node: c,
                dof: s.dof,
            })
        })
        .collect();
    m.spcs.sort_by_key(|s| s.node);
    m.prescribed = model
        .prescribed
        .iter()
        .flat_map(|p| {
            let targets: Vec<MotionTarget> = match p.target {
                MotionTarget::Node(n) => expand(n).map(MotionTarget::Node).collect(),
                MotionTarget::Rigid(r) => vec![MotionTarget::Rigid(r)],
                MotionTarget::NodalRigid(r) => vec![MotionTarget::NodalRigid(r)],
            };
            targets
                .into_iter()
                .map(move |t| crate::model::PrescribedMotion {
                    target: t,
                    ..p.clone()
                })
        })
        .collect();
    for s in &mut m.node_sets {
        s.nodes = s.nodes.iter().flat_map(|&n| expand(n)).collect();
    }
    // every copy of a node joined to a rigid part moves with it (nodal rigid bodies take
    // their node sets, expanded above)
    for x in &mut m.extra_nodes {
        x.nodes = x.nodes.iter().flat_map(|&n| expand(n)).collect();
    }
    for w in &mut m.rigid_walls {
        if let Some(nodes) = &mut w.nodes {
            *nodes = nodes.iter().flat_map(|&n| expand(n)).collect();
        }
    }
    for s in &mut m.segment_sets {
        // a segment keeps the first copy of each corner; contact (issue 4) rebuilds surfaces
        // from element faces, so this only keeps the set valid
        for seg in &mut s.segments {
            *seg = seg.map(|n| copies.of(n)[0]);
        }
    }
    for l in &mut m.node_loads {
        l.node = copies.of(l.node)[0];
    }
    // a segment's pressure goes to the first copy of each corner (their sets, while intact)
    for l in &mut m.pressure_loads {
        l.nodes = l.nodes.map(|n| copies.of(n)[0]);
    }
    m.output.history_nodes = model
        .output
        .history_nodes
        .iter()
        .map(|&n| copies.of(n)[0])
        .collect();

    let (faces, interfaces) = shared_faces(model, &m.conn, &elem_group);
    SplitModel {
        model: m,
        origin,
        faces,
        interfaces,
    }
}

/// Solved nodes of each deck node, ascending (CSR).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub struct Copies {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Copies {
    /// The solved nodes that are copies of deck node `n` (empty for none).
    pub fn of(&self, n: u32) -> &[u32] {
        &self.list[self.start[n as usize] as usize..self.start[n as usize + 1] as usize]
    }
}

/// Build the deck-node -> solved-nodes index from `origin`.
pub fn copies_of(origin: &[u32], deck_nodes: usize) -> Copies {
    let mut start = vec![0u32; deck_nodes + 1];
    for &o in origin {
        start[o as usize + 1] += 1;
    }
    for i in 0..deck_nodes {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut list = vec![0u32; origin.len()];
    for (i, &o) in origin.iter().enumerate() {
        list[fill[o as usize] as usize] = i as u32;
        fill[o as usize] += 1;
    }
    Copies { start, list }
}

/// Faces shared by two elements, at least one in a group, in a deterministic order (by the
/// first element, then its face number); `Interface` faces first, then `Bond`s.
fn shared_faces(
    model: &Model,
    split_conn: &[[u32; 8]],
    elem_group: &[u32],
) -> (Vec<SharedFace>, usize) {
    let mut open: HashMap<[u32; 4], (u32, u8)> = HashMap::new();
    let mut found: Vec<(u32, u8, u32, u8)> = Vec::new();
    for (e, c) in model.conn.iter().enumerate() {
        for (f, corners) in FACES.iter().enumerate() {
            // a triangle is keyed by its 3 nodes; an edge or a point is no face
            let Some(key) = face_key(corners.map(|k| c[k])) else {
                continue;
            };
            match open.remove(&key) {
                Some((ea, fa)) => found.push((ea, fa, e as u32, f as u8)),
                None => {
                    open.insert(key, (e as u32, f as u8));
                }
            }
        }
    }
    found.sort_unstable();
    // room for the bonds too (they are appended): no growth past the faces found
    let mut interfaces = Vec::with_capacity(found.len());
    let mut bonds = Vec::new();
    for (ea, fa, eb, fb) in found {
        let (ga, gb) = (elem_group[ea as usize], elem_group[eb as usize]);
        if ga == NONE && gb == NONE {
            continue;
        }
        let area0 = {
            let p = FACES[fa as usize].map(|k| model.x0[model.conn[ea as usize][k] as usize]);
            quad_area(p[0], p[1], p[2], p[3])
        };
        let ids = (model.elem_ids[ea as usize], model.elem_ids[eb as usize]);
        let (group, strength) = governing_group(model, [ga, gb], area0, ids);
        let mixed = ga == NONE || gb == NONE;
        let kind = if mixed && model.separations[group as usize].bond == 0 {
            FaceKind::Bond
        } else {
            FaceKind::Interface
        };
        let ca = &model.conn[ea as usize];
        let cb = &model.conn[eb as usize];
        let fa_c = face_corners(ca, fa as usize);
        let mut nodes = [0u32; 8];
        for k in 0..4 {
            let deck = ca[fa_c[k]];
            let kb = cb
                .iter()
                .position(|&n| n == deck)
                .expect("a shared face's corner is in both elements");
            nodes[k] = split_conn[ea as usize][fa_c[k]];
            nodes[4 + k] = split_conn[eb as usize][kb];
        }
        let face = SharedFace {
            elems: [ea, eb],
            faces: [fa, fb],
            nodes,
            area0,
            group: group as u16,
            kind,
            strength: match kind {
                FaceKind::Interface => strength,
                FaceKind::Bond => f64::INFINITY,
            },
        };
        match kind {
            FaceKind::Interface => interfaces.push(face),
            FaceKind::Bond => bonds.push(face),
        }
    }
    let n = interfaces.len();
    interfaces.extend(bonds);
    (interfaces, n)
}

/// The group that governs a face between elements of groups `g` (`NONE`: no group) with deck
/// ids `ids`, and the face's strength: the weaker of the two groups' draws, the first on a tie
/// ([`crate::separation::strength`]).
fn governing_group(model: &Model, g: [u32; 2], area0: f64, ids: (i64, i64)) -> (u32, f64) {
    let draw = |g: u32| {
        let s = &model.separations[g as usize];
        strength::draw(s.sigmax, &s.strength, area0, ids.0, ids.1)
    };
    match g {
        [a, NONE] => (a, draw(a)),
        [NONE, b] => (b, draw(b)),
        [a, b] if a == b => (a, draw(a)),
        [a, b] => {
            let (sa, sb) = (draw(a), draw(b));
            if sb < sa {
                (b, sb)
            } else {
                (a, sa)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_model;
    use crate::model::{Material, MaterialKind, Part, SeparationDef, Spc};

    fn mat(id: i64) -> Material {
        Material {
            id,
            density: 1000.0,
            young: 1e9,
            poisson: 0.25,
            kind: MaterialKind::Elastic,
        }
    }
    fn sep(material: usize, bond: i32) -> SeparationDef {
        SeparationDef {
            material,
            model: 1,
            sigmax: 1e6,
            beta: 1.0,
            gc: 0.0,
            bond,
            strength: Default::default(),
        }
    }

    /// A 2x2x2 block entirely in a group: 8 x 8 = 64 nodes, 12 internal faces, all interfaces;
    /// each face's 4 node pairs coincide in space; a constraint on a deck node reaches every copy.
    #[test]
    fn fully_split_block() {
        let mut m = box_model([2, 2, 2], [2.0, 2.0, 2.0], mat(1), 1.0);
        m.separations.push(sep(0, 1));
        m.spcs.push(Spc {
            node: 13,
            dof: [true, false, false, false, false, false],
        }); // centre node
        let s = split_model(&m);
        assert_eq!(s.model.num_nodes(), 64);
        assert_eq!((s.faces.len(), s.interfaces), (12, 12));
        for f in &s.faces {
            for k in 0..4 {
                assert_eq!(
                    s.model.x0[f.nodes[k] as usize],
                    s.model.x0[f.nodes[4 + k] as usize]
                );
            }
            assert!((f.area0 - 1.0).abs() < 1e-14);
        }
        assert_eq!(s.model.spcs.len(), 8, "the centre node has 8 copies");
        // every element has distinct nodes
        let mut seen = [false; 64];
        for c in &s.model.conn {
            for &n in c {
                assert!(!seen[n as usize]);
                seen[n as usize] = true;
            }
        }
    }

    /// Half the block in a group: the group's 4 elements get 32 nodes; the other half keeps its
    /// 18 nodes (3 x 3 x 2 layers incl. the shared plane); faces across the plane follow BOND.
    #[test]
    fn bond_decides_mixed_faces() {
        for (bond, interfaces, bonds) in [(1, 4 + 4, 0), (0, 4, 4)] {
            let mut m = box_model([2, 2, 2], [2.0, 2.0, 2.0], mat(1), 1.0);
            m.materials.push(mat(2));
            m.parts.push(Part {
                id: 2,
                title: "b".into(),
                section: 0,
                material: 1,
                hourglass: None,
            });
            for (e, c) in m.conn.clone().iter().enumerate() {
                if m.x0[c[0] as usize][2] >= 1.0 {
                    m.elem_part[e] = 1; // upper layer in material 2
                }
            }
            m.separations.push(sep(1, bond));
            let s = split_model(&m);
            assert_eq!(s.model.num_nodes(), 18 + 32);
            // upper layer: 4 faces inside the group; between layers: 4 mixed faces
            assert_eq!(s.interfaces, interfaces, "bond {bond}");
            assert_eq!(s.faces.len() - s.interfaces, bonds, "bond {bond}");
        }
    }
}
