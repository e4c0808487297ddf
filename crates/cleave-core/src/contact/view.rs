//! What another stepper reads of the contact definitions to run the same contact (the GPU's,
//! cleave-gpu `contact.rs`): the passes, each side's faces and nodes in the order their forces
//! are scattered, the faces whose normals make each node's, and the pair stiffness; and where
//! it puts the resultants it computed, for `rcforc.csv`.
//!
//! It describes the surfaces as they are: a stepper that takes them over must not run a model
//! whose surfaces change (faces joining when interfaces fail or elements erode), nor one with
//! coincident copies (a node's normal would be its set's).

use super::{Contact, ContactForce, ContactSet, NONE};

impl Contact {
    /// The passes of each step, (node side, face side) each, in the order they run: single
    /// surface one, surface to surface two (slave nodes on master faces, then the reverse).
    pub fn pass_sides(&self) -> Vec<(usize, usize)> {
        (self.passes.iter())
            .map(|p| (p.node_side, p.face_side))
            .collect()
    }

    /// The nodes of side `side` in the order their forces are scattered (the order they
    /// joined the side).
    pub fn nodes_in_scatter_order(&self, side: usize) -> Vec<u32> {
        let s = &self.sides[side];
        let mut by_rank: Vec<(u32, u32)> = (s.nodes.iter().zip(&s.rank))
            .map(|(&n, &r)| (r, n))
            .collect();
        by_rank.sort_unstable();
        by_rank.into_iter().map(|(_, n)| n).collect()
    }

    /// The faces of side `side` (indices into [`Contact::faces`]) that shape the surface at
    /// model node `n` (its normal sums theirs, in this order); empty when `n` is not on it.
    pub fn faces_of_node(&self, side: usize, n: u32) -> Vec<u32> {
        let s = &self.sides[side];
        match s.local.get(n as usize) {
            Some(&i) if i != NONE => (s.node_faces.of(i))
                .filter(|&f| s.faces[f as usize].depth > 0.0)
                .collect(),
            _ => Vec::new(),
        }
    }
}

impl ContactSet<'_> {
    /// Penalty stiffness of model node `n` ([`super::surface::FaceTable::node_stiffness`]).
    pub fn node_stiffness(&self, n: u32) -> f64 {
        self.table.node_stiffness(n)
    }

    /// The spring of node `n` against a face of stiffness `k_face` (PENOPT,
    /// [`super::surface::FaceTable::pair_stiffness`]).
    pub fn pair_stiffness(&self, k_face: f64, n: u32) -> f64 {
        self.table.pair_stiffness(k_face, n)
    }

    /// Each definition's resultants of the last step, as another stepper computed them (in
    /// deck order, one per definition; [`ContactSet::forces`] returns them).
    pub fn set_forces(&mut self, forces: &[ContactForce]) {
        assert_eq!(
            forces.len(),
            self.forces.len(),
            "one resultant per definition"
        );
        self.forces.copy_from_slice(forces);
    }
}
