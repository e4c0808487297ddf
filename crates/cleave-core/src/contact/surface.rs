//! Contact surfaces: the exterior faces of a hexahedral mesh, the faces each side of a contact
//! definition starts with, and the penalty stiffness of every element face.
//!
//! A face is named by its element and its local face number, `(element, 0..6)` in the order of
//! [`FACES`] (outward normal by the right-hand rule). Its 4 nodes are read from the connectivity
//! the solver runs on, which for separation groups is the *split* connectivity (8 nodes of its
//! own per element). Which faces are exterior is decided on the *deck* connectivity, where two
//! elements that touch share their nodes: a face is exterior when no other element has the same
//! 4 nodes.

use rayon::prelude::*;
use std::collections::HashMap;

use crate::element::hex8::{quad_area, volume, FACES};
use crate::element::shape::{face_corners, face_key};
use crate::math::Vec3;
use crate::model::{ContactSurface, Model, PenaltyRule};

/// A face: element index and local face number (0..6, [`FACES`] order).
pub type FaceId = (u32, u8);

/// Largest penetration, as a fraction of the thickness V/A of the face's element, at which a
/// node still counts as in contact with the face. Deeper nodes are ignored, so a face does not
/// grab the nodes on the far side of its own element or of a thin body. LS-DYNA's old-style
/// contacts default to the same limit for solids (PENMAX 0.4).
pub const DEPTH_FRACTION: f64 = 0.4;

/// The 4 nodes of local face `face` of an element with connectivity `c`, outward order (a
/// triangle of a wedge or tetrahedron as `N1 N2 N3 N3`, [`face_corners`]).
#[inline]
pub fn face_nodes(c: &[u32; 8], face: u8) -> [u32; 4] {
    face_corners(c, face as usize).map(|k| c[k])
}

/// The faces of the elements accepted by `elem_filter` that no other element of `conn` shares
/// (same nodes in any order, [`face_key`]), sorted by (element, face).
///
/// Exterior is decided over the whole mesh, not over the filtered elements: a face between two
/// parts that share their nodes is inside the body, bonded, and never a contact surface.
/// Deterministic: faces are keyed by their sorted node quadruple and sorted, no hashing.
pub fn exterior_faces(conn: &[[u32; 8]], elem_filter: impl Fn(u32) -> bool) -> Vec<FaceId> {
    let mut keyed: Vec<([u32; 4], u32, u8)> = Vec::with_capacity(6 * conn.len());
    for (e, c) in conn.iter().enumerate() {
        for f in 0..6u8 {
            // a triangle keyed by its 3 nodes; collapsed to an edge or a point: no face
            if let Some(key) = face_key(face_nodes(c, f)) {
                keyed.push((key, e as u32, f));
            }
        }
    }
    keyed.sort_unstable();
    let mut out = Vec::new();
    let mut i = 0;
    while i < keyed.len() {
        let mut j = i + 1;
        while j < keyed.len() && keyed[j].0 == keyed[i].0 {
            j += 1;
        }
        if j - i == 1 && elem_filter(keyed[i].1) {
            out.push((keyed[i].1, keyed[i].2));
        }
        i = j;
    }
    out.sort_unstable();
    out
}

/// Penalty stiffness and depth limit of the faces of a model's elements, at the reference
/// geometry, worked out when asked (when a face joins a surface) from the model it borrows and
/// the elements' volumes (kept: 8 bytes an element, against a hexahedron's volume worked out
/// again four times for each interface that fails).
///
/// LS-DYNA theory manual, penalty method (SOFT = 0) for a face of a solid element:
/// `k = SLSFAC * K * A^2 / V`, with K the bulk modulus of the element's material (rigid
/// materials too, from their E and PR), A the face area and V the element volume.
/// The depth limit is [`DEPTH_FRACTION`] `* V / A`. A degenerate face or element gets 0 for
/// both.
///
/// A pair's spring is the smaller of the face's stiffness and the node's
/// ([`FaceTable::pair_stiffness`]), as LS-DYNA's default `*CONTROL_CONTACT` PENOPT = 1 ("minimum of
/// master segment and slave node"); PENOPT = 2 takes the face's alone. The node's stiffness is that
/// of the stiffest element face holding its deck node, in the deck mesh
/// ([`FaceTable::node_stiffness`]): the copies of a split model have their deck node's, so until an
/// interface fails a split model has the springs of the same mesh unsplit. The minimum keeps a
/// light node off a stiff face's spring: a copy of a small ball element against the big faces of a
/// rigid plate gets its own element's stiffness, so the springs are stable at a step set by each
/// node's own mass and faces ([`super::ContactSet::stable_dt`]), not by the lightest node against
/// the stiffest face of the model.
#[derive(Clone, Debug)]
pub struct FaceTable<'m> {
    model: &'m Model,
    /// Mean of sqrt(A) over all faces: a length scale for the search margin.
    pub mean_size: f64,
    /// The deck node of each solved node of a split model (`None`: not split).
    origin: Option<&'m [u32]>,
    /// Stiffness of each deck node: the largest `k` of the element faces holding it. Kept per
    /// deck node, not per solved node: the 20,000-element ball's 160,072 solved nodes would
    /// take 1.28 MB for the 21,343 values.
    deck_k: Vec<f64>,
    /// The reference volume of each element.
    volume: Vec<f64>,
}

impl<'m> FaceTable<'m> {
    /// For the elements of `model` (connectivity `model.conn`, coordinates `model.x0`);
    /// `origin[i]` is the deck node of solved node i in a split model, `None` when the model
    /// is not split.
    pub fn new(model: &'m Model, origin: Option<&'m [u32]>) -> Self {
        let (mut sum, mut faces) = (0.0, 0usize);
        for c in &model.conn {
            for corners in FACES.iter() {
                if face_key(corners.map(|a| c[a])).is_none() {
                    continue; // a wedge's or tetrahedron's collapsed face
                }
                let p = corners.map(|a| model.x0[c[a] as usize]);
                sum += quad_area(p[0], p[1], p[2], p[3]).sqrt();
                faces += 1;
            }
        }
        let mean_size = if faces > 0 { sum / faces as f64 } else { 0.0 };
        let volume = (model.conn.par_iter())
            .with_min_len(1024)
            .map(|c| volume(&c.map(|n| model.x0[n as usize])))
            .collect();
        let mut t = Self {
            model,
            mean_size,
            origin,
            deck_k: Vec::new(),
            volume,
        };
        t.deck_k = t.deck_stiffnesses();
        t
    }

    /// The deck node of solved node `n`.
    #[inline]
    fn deck(&self, n: u32) -> usize {
        self.origin.map_or(n, |o| o[n as usize]) as usize
    }

    /// [`FaceTable::node_stiffness`] of every deck node.
    fn deck_stiffnesses(&self) -> Vec<f64> {
        let nn = self.model.num_nodes();
        let deck = |n: u32| self.deck(n);
        let n_deck = (0..nn as u32).map(|n| deck(n) + 1).max().unwrap_or(0);
        let mut k_deck = vec![0.0f64; n_deck];
        for (e, c) in self.model.conn.iter().enumerate() {
            let xe: [Vec3; 8] = std::array::from_fn(|a| self.model.x0[c[a] as usize]);
            let v = self.volume[e];
            for (f, corners) in FACES.iter().enumerate() {
                let p = corners.map(|a| xe[a]);
                let k = self.stiffness_of(e, quad_area(p[0], p[1], p[2], p[3]), v);
                for n in face_nodes(c, f as u8) {
                    let d = &mut k_deck[deck(n)];
                    *d = d.max(k);
                }
            }
        }
        k_deck
    }

    /// The model the faces are of.
    pub fn model(&self) -> &'m Model {
        self.model
    }

    /// Area of face `f` of element `e` and the element's volume.
    fn geometry(&self, (e, f): FaceId) -> (f64, f64) {
        let c = &self.model.conn[e as usize];
        let p = FACES[f as usize].map(|a| self.model.x0[c[a] as usize]);
        (quad_area(p[0], p[1], p[2], p[3]), self.volume[e as usize])
    }

    /// Penalty stiffness of a face (force per length).
    pub fn stiffness(&self, id: FaceId) -> f64 {
        let (area, v) = self.geometry(id);
        self.stiffness_of(id.0 as usize, area, v)
    }

    /// Penalty stiffness and depth limit of a face, from one pass over its element.
    pub fn stiffness_and_depth(&self, id: FaceId) -> (f64, f64) {
        let (area, v) = self.geometry(id);
        (self.stiffness_of(id.0 as usize, area, v), depth_of(area, v))
    }

    /// `SLSFAC K A^2 / V` of a face of area `area` of element `e` of volume `v` (0 when
    /// degenerate).
    fn stiffness_of(&self, e: usize, area: f64, v: f64) -> f64 {
        if v > 0.0 && area > 0.0 {
            let bulk = self.model.element_material(e).bulk_modulus();
            self.model.control.slsfac * bulk * area * area / v
        } else {
            0.0
        }
    }

    /// Stiffness of solved node `n`: the largest [`FaceTable::stiffness`] of the element faces
    /// holding its deck node (all elements, deck mesh).
    #[inline]
    pub fn node_stiffness(&self, n: u32) -> f64 {
        self.deck_k[self.deck(n)]
    }

    /// The spring of node `n` against a face of stiffness `k_face`: the smaller of the two
    /// (PENOPT 1, the default), or the face's (PENOPT 2).
    #[inline]
    pub fn pair_stiffness(&self, k_face: f64, n: u32) -> f64 {
        match self.model.control.penalty {
            PenaltyRule::Smaller => k_face.min(self.node_stiffness(n)),
            PenaltyRule::Face => k_face,
        }
    }

    /// Largest penetration that still counts as contact with a face.
    pub fn depth(&self, id: FaceId) -> f64 {
        let (area, v) = self.geometry(id);
        depth_of(area, v)
    }
}

/// `DEPTH_FRACTION V / A` (0 when degenerate).
fn depth_of(area: f64, v: f64) -> f64 {
    if v > 0.0 && area > 0.0 {
        DEPTH_FRACTION * v / area
    } else {
        0.0
    }
}

/// Which parts a side covers (`covered[p]`), for adding the faces of failed interfaces; a
/// segment-set side covers none (its faces are the listed segments, nothing joins it).
pub fn covered_parts(model: &Model, side: &ContactSurface) -> Vec<bool> {
    let mut covered = vec![false; model.parts.len()];
    match side {
        ContactSurface::All => covered.iter_mut().for_each(|c| *c = true),
        ContactSurface::Part(p) => covered[*p] = true,
        ContactSurface::PartSet(s) => {
            for &p in &model.part_sets[*s].parts {
                covered[p] = true;
            }
        }
        ContactSurface::SegmentSet(_) => {}
    }
    covered
}

/// The faces a side starts with: the exterior faces (`exterior`, from [`exterior_faces`] on the
/// deck connectivity) of the elements of the covered parts, or for a segment set the element
/// faces its segments are ([`match_segments`]). Sorted by (element, face).
pub fn side_faces(
    model: &Model,
    deck_conn: &[[u32; 8]],
    origin: Option<&[u32]>,
    exterior: &[FaceId],
    side: &ContactSurface,
) -> Result<Vec<FaceId>, String> {
    if let ContactSurface::SegmentSet(s) = side {
        return match_segments(model, deck_conn, origin, *s);
    }
    let covered = covered_parts(model, side);
    Ok(exterior
        .iter()
        .copied()
        .filter(|&(e, _)| covered[model.elem_part[e as usize] as usize])
        .collect())
}

/// The element faces of segment set `set` (index into `model.segment_sets`), sorted, without
/// repeats.
///
/// A segment is matched by its 4 (deck) nodes in any order. A face shared by two elements is
/// given to the element whose outward face order runs the same way round as the segment (a
/// cyclic shift of it), else to the first element. Segment nodes of a split model are solved
/// nodes; `origin` maps them (and the split connectivity) back to deck nodes (`None`: the model
/// is not split). A segment that is no element face (a triangle, a typo) is an error naming the
/// set and the segment's deck node ids.
pub fn match_segments(
    model: &Model,
    deck_conn: &[[u32; 8]],
    origin: Option<&[u32]>,
    set: usize,
) -> Result<Vec<FaceId>, String> {
    let deck = |n: u32| origin.map_or(n, |o| o[n as usize]);
    let mut by_key: HashMap<[u32; 4], Vec<FaceId>> = HashMap::new();
    for (e, c) in deck_conn.iter().enumerate() {
        for f in 0..6u8 {
            if let Some(key) = face_key(face_nodes(c, f)) {
                by_key.entry(key).or_default().push((e as u32, f));
            }
        }
    }
    let s = &model.segment_sets[set];
    let mut out = Vec::with_capacity(s.segments.len());
    for seg in &s.segments {
        let nodes = seg.map(deck);
        let Some(cands) = face_key(nodes).and_then(|key| by_key.get(&key)) else {
            let ids: Vec<String> = seg
                .iter()
                .map(|&n| model.node_ids[n as usize].to_string())
                .collect();
            return Err(format!(
                "segment set {}: segment {} is not a face of any solid element",
                s.id,
                ids.join(" ")
            ));
        };
        let same_way = |&(e, f): &FaceId| {
            let fnodes = face_nodes(&deck_conn[e as usize], f);
            (0..4).any(|r| (0..4).all(|k| fnodes[(k + r) % 4] == nodes[k]))
        };
        out.push(cands.iter().copied().find(same_way).unwrap_or(cands[0]));
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::hex8::quad_normal_area;
    use crate::math::{dot, sub};
    use crate::mesh::{box_model, BoxMesh};
    use crate::model::{Material, MaterialKind, SegmentSet};

    fn mat() -> Material {
        Material {
            id: 1,
            density: 1000.0,
            young: 3e9,
            poisson: 0.25,
            kind: MaterialKind::Elastic,
        }
    }

    /// An a x b x c box has 2(ab + bc + ca) exterior faces, each on the box boundary with its
    /// normal pointing out of the box.
    #[test]
    fn box_exterior_face_count_and_orientation() {
        for (n, l) in [([3, 4, 5], [3.0, 4.0, 5.0]), ([1, 1, 1], [1.0, 2.0, 3.0])] {
            let mesh = BoxMesh::new(n, l);
            let faces = exterior_faces(&mesh.conn, |_| true);
            let [a, b, c] = n;
            assert_eq!(faces.len(), 2 * (a * b + b * c + c * a), "{n:?}");
            let centre = [l[0] / 2.0, l[1] / 2.0, l[2] / 2.0];
            for &(e, f) in &faces {
                let p = face_nodes(&mesh.conn[e as usize], f).map(|i| mesh.x[i as usize]);
                let (nrm, _) = quad_normal_area(p[0], p[1], p[2], p[3]);
                let mid = [0, 1, 2].map(|d| 0.25 * (p[0][d] + p[1][d] + p[2][d] + p[3][d]));
                // on the boundary: one coordinate at 0 or l
                let on = (0..3).any(|d| mid[d].abs() < 1e-12 || (mid[d] - l[d]).abs() < 1e-12);
                assert!(on, "face {e}/{f} is not on the boundary");
                assert!(
                    dot(nrm, sub(mid, centre)) > 0.0,
                    "face {e}/{f} points inward"
                );
            }
        }
        // 3x4x5 = 94 faces: pinned by the formula above
        assert_eq!(
            exterior_faces(&BoxMesh::new([3, 4, 5], [1.0; 3]).conn, |_| true).len(),
            94
        );
    }

    /// Filtering by element keeps whole-mesh exteriority: the filter picks, it does not re-decide.
    #[test]
    fn filter_keeps_only_exterior_faces_of_chosen_elements() {
        let mesh = BoxMesh::new([2, 1, 1], [2.0, 1.0, 1.0]);
        let faces = exterior_faces(&mesh.conn, |e| e == 0);
        // element 0 has 5 exterior faces; its face towards element 1 is shared
        assert_eq!(faces.len(), 5);
        assert!(faces.iter().all(|&(e, _)| e == 0));
    }

    /// k = SLSFAC K A^2 / V and depth 0.4 V/A on a 2 x 1 x 0.5 single element.
    #[test]
    fn stiffness_of_a_face() {
        let m = box_model([1, 1, 1], [2.0, 1.0, 0.5], mat(), 1.0);
        let t = FaceTable::new(&m, None);
        let k_bulk = 3e9 / (3.0 * (1.0 - 0.5)); // 2e9
        let v = 1.0;
        // face 0 (bottom, z = 0): A = 2
        let want = 0.1 * k_bulk * 4.0 / v;
        assert!((t.stiffness((0, 0)) - want).abs() <= 1e-12 * want);
        assert!((t.depth((0, 0)) - 0.4 * 0.5).abs() < 1e-15);
        // face 2 (y = 0): A = 2 x 0.5 = 1
        assert!((t.stiffness((0, 2)) - 0.1 * k_bulk).abs() <= 1e-12 * k_bulk);
    }

    /// A segment matches the element face with the same nodes, whatever their order; a segment
    /// that is no face is an error naming the set.
    #[test]
    fn segments_match_faces() {
        let mut m = box_model([2, 1, 1], [2.0, 1.0, 1.0], mat(), 1.0);
        let top0 = face_nodes(&m.conn[0], 1);
        let shared = face_nodes(&m.conn[1], 5); // element 1's face towards element 0
        m.segment_sets.push(SegmentSet {
            id: 7,
            segments: vec![[top0[2], top0[3], top0[0], top0[1]], shared],
        });
        let conn = m.conn.clone();
        let faces = match_segments(&m, &conn, None, 0).unwrap();
        assert_eq!(faces, vec![(0, 1), (1, 5)]);
        m.segment_sets[0].segments.push([0, 1, 2, 2]);
        let err = match_segments(&m, &conn, None, 0).unwrap_err();
        assert!(
            err.contains("segment set 7") && err.contains("1 2 3 3"),
            "{err}"
        );
    }
}
