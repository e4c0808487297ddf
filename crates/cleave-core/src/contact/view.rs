//! What another stepper reads of the contact definitions to run the same contact (the GPU's,
//! cleave-gpu `contact.rs`): the passes, each side's faces and nodes in the order their forces
//! are scattered, the faces whose normals make each node's, and the pair stiffness; and where
//! it puts the resultants it computed, for `rcforc.csv`.
//!
//! It describes the surfaces as they are now. A stepper that runs a model whose surfaces change
//! (faces joining when interfaces fail or elements erode) hands the changes to the host's
//! [`ContactSet`] ([`ContactSet::activate_cracks`], [`ContactSet::erode`],
//! [`ContactSet::closures_stepped`]), brings its bookkeeping up to date
//! ([`ContactSet::settle`]: the chains of closed cracks, the coincident sets' leads) and reads
//! the surfaces again. With coincident copies only the sets' leads are checked, each with the
//! normal of its set's faces ([`Contact::frame_of_lead`]), against faces that hold no copy
//! chained to it ([`Contact::chain_label`]); closed cracks push through their node pairs
//! ([`Contact::closed_cracks`]).

use super::surface::FaceId;
use super::{Contact, ContactForce, ContactSet, NONE};

/// Values of a closed crack's state between steps ([`ClosedCrack::state`]): the tangential
/// force on each b_k (12), the mid-surface normal (3), each pair's normal force magnitude (4),
/// and 1 while it is tight (closure.rs `Closure`).
pub const CLOSURE_STATE: usize = 20;

/// A closed crack as another stepper runs it (closure.rs `Closure::step`).
#[derive(Clone, Debug, PartialEq)]
pub struct ClosedCrack {
    pub faces: [FaceId; 2],
    /// A's nodes in its outward order, and each one's partner on B.
    pub a: [u32; 4],
    pub b: [u32; 4],
    /// Penalty per pair.
    pub k: f64,
    pub state: [f64; CLOSURE_STATE],
}

impl Contact {
    /// The passes of each step, (node side, face side) each, in the order they run: single
    /// surface one, surface to surface two (slave nodes on master faces, then the reverse).
    pub fn pass_sides(&self) -> Vec<(usize, usize)> {
        (self.passes.iter())
            .map(|p| (p.node_side, p.face_side))
            .collect()
    }

    /// The nodes of side `side` (model numbers), in the side's own order (not the scatter
    /// order: [`Self::leads_in_scatter_order`]).
    pub fn side_nodes(&self, side: usize) -> &[u32] {
        &self.sides[side].nodes
    }

    /// The leads of side `side`'s coincident sets (every node when the model is not split) in
    /// the order their forces are scattered; valid after a [`ContactSet::settle`].
    pub fn leads_in_scatter_order(&self, side: usize) -> Vec<u32> {
        let s = &self.sides[side];
        let lead = |i: usize| s.group.get(i).is_none_or(|&g| g == i as u32);
        let mut by_rank: Vec<(u32, u32)> = (s.nodes.iter().zip(&s.rank).enumerate())
            .filter(|&(i, _)| lead(i))
            .map(|(_, (&n, &r))| (r, n))
            .collect();
        by_rank.sort_unstable();
        by_rank.into_iter().map(|(_, n)| n).collect()
    }

    /// The faces of side `side` that shape the surface of lead `n` (its normal sums theirs, in
    /// this order), appended to `out`: those of its coincident set's members along the member
    /// chain, or of the node alone when untied, each node's faces that have not eroded (mod.rs
    /// `Side::frame`).
    pub fn frame_of_lead(&self, side: usize, n: u32, out: &mut Vec<u32>) {
        let s = &self.sides[side];
        // (loops, not an extend of a flat_map: no size hint, and this runs for every lead
        // whenever the GPU's tables are made)
        let mut put = |k: u32| {
            for f in s.node_faces.of(k) {
                if s.faces[f as usize].depth > 0.0 {
                    out.push(f);
                }
            }
        };
        match s.local.get(n as usize) {
            Some(&i) if (i as usize) < s.group.len() => s.members(i).for_each(put),
            Some(&i) if i != NONE => put(i),
            _ => {}
        }
    }

    /// The lead of model node `n`'s coincident set on side `side` (`n` when untied or before a
    /// [`ContactSet::settle`]); `None` when `n` is not on the side.
    pub fn lead_of(&self, side: usize, n: u32) -> Option<u32> {
        let s = &self.sides[side];
        match s.local.get(n as usize) {
            Some(&i) if i != NONE => Some(match s.group.get(i as usize) {
                Some(&g) if g != NONE => s.nodes[g as usize],
                _ => n,
            }),
            _ => None,
        }
    }

    /// Lead `n` and the other members of its coincident set on side `side`, along the member
    /// chain (the lead, then by descending model number; mod.rs `Side::next`), appended to
    /// `out`.
    pub fn members_of_lead(&self, side: usize, n: u32, out: &mut Vec<u32>) {
        let s = &self.sides[side];
        match s.local.get(n as usize) {
            Some(&i) if (i as usize) < s.group.len() => {
                out.extend(s.members(i).map(|k| s.nodes[k as usize]))
            }
            _ => out.push(n),
        }
    }

    /// The search margin: [`MARGIN_FRACTION`](super::MARGIN_FRACTION) times the mean
    /// sqrt(area) of the definition's faces when it was made (module docs, Search), m.
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// The label of model node `n`'s chain: nodes with one label are tied or chained through
    /// closed cracks, and a node is not checked against a face that holds a node of its label
    /// (closure.rs `Chains::held`); `n` itself when the model is not split.
    pub fn chain_label(&self, n: u32) -> u32 {
        match self.chains.label.get(n as usize) {
            Some(&l) if self.chains.is_split() => l,
            _ => n,
        }
    }

    /// The closed cracks, in the order they closed (the order their forces are scattered).
    pub fn closed_cracks(&self) -> Vec<ClosedCrack> {
        (self.closures.iter())
            .map(|c| {
                let mut state = [0.0; CLOSURE_STATE];
                for k in 0..4 {
                    state[3 * k..3 * k + 3].copy_from_slice(&c.ft[k]);
                    state[15 + k] = c.fn_mag[k];
                }
                state[12..15].copy_from_slice(&c.n);
                state[19] = f64::from(u8::from(c.tight));
                ClosedCrack {
                    faces: c.faces,
                    a: c.a,
                    b: c.b,
                    k: c.k,
                    state,
                }
            })
            .collect()
    }
}

impl ContactSet<'_> {
    /// Bring each definition's bookkeeping up to the ties `tie` (the coincident set of each
    /// node, or empty), as a step's search would before its checks: the chains of closed
    /// cracks relabelled, the leads of the coincident sets found again. For a stepper that runs
    /// the checks itself: what the CPU's searches keep for their next call (faces pending a
    /// search, nodes whose normal changed) is dropped.
    pub fn settle(&mut self, tie: &[u32]) {
        self.settle_where(tie, false);
    }

    /// [`Self::settle`] where the ties changed since the last settle only as the CPU's step
    /// knows them to (at a split, whose failed interfaces' faces were activated,
    /// [`ContactSet::activate_cracks`]; not at all at a crack's release or an erosion): only the
    /// copies of the nodes of the faces activated since are regrouped, as the CPU's step
    /// regroups them (mod.rs `Contact::regroup_pending`), not every node.
    pub fn settle_pending(&mut self, tie: &[u32]) {
        self.settle_where(tie, true);
    }

    fn settle_where(&mut self, tie: &[u32], split: bool) {
        for c in &mut self.contacts {
            c.chains.refresh(tie);
            if split {
                c.regroup_pending(tie, &self.table.model().conn);
            } else {
                c.regroup(tie);
            }
            c.pending.clear();
            for side in &mut c.sides {
                side.renewed.clear();
            }
        }
    }

    /// Definition `def`'s closed cracks as another stepper stepped them: each one's state
    /// ([`CLOSURE_STATE`] values, in [`Contact::closed_cracks`] order) and whether it was
    /// released; the released ones leave, as the CPU's step lets them (mod.rs `Contact::compute`; call
    /// [`Self::settle`] after). Nothing is left pending for a search (the other stepper searches
    /// every step). Errors when the counts do not match.
    pub fn closures_stepped(
        &mut self,
        def: usize,
        states: &[f64],
        released: &[bool],
    ) -> Result<(), String> {
        let c = (self.contacts.get_mut(def)).ok_or_else(|| format!("no contact {def}"))?;
        let n = c.closures.len();
        if states.len() != CLOSURE_STATE * n || released.len() != n {
            return Err(format!(
                "contact {}: {n} closed cracks, {} states and {} flags given",
                c.id,
                states.len() / CLOSURE_STATE,
                released.len()
            ));
        }
        let mut flags = Vec::with_capacity(n);
        for ((cl, s), &r) in (c.closures.iter_mut())
            .zip(states.chunks_exact(CLOSURE_STATE))
            .zip(released)
        {
            let tight = s[19] != 0.0;
            flags.push(u32::from(r) | u32::from(tight != cl.tight) << 1);
            for k in 0..4 {
                cl.ft[k].copy_from_slice(&s[3 * k..3 * k + 3]);
                cl.fn_mag[k] = s[15 + k];
            }
            cl.n.copy_from_slice(&s[12..15]);
            cl.tight = tight;
        }
        c.settle_closures(&flags);
        // (a stepper that searches every step leaves nothing for a later search)
        c.pending.clear();
        Ok(())
    }

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
