//! Coincident node sets: the copies of a deck node tied together by intact interfaces (and
//! permanent bonds). Each step every set shares one acceleration (the paper's equations 1-4):
//! a = sum f_i / sum m_i.
//!
//! Storage: all members in one array, each set a contiguous ascending range. A set's
//! *representative* is its smallest member, read off the set ([`CoincidentSets::rep`]; a node
//! in no set is its own), and each node knows its set's *slot* ([`CoincidentSets::slots`]): the
//! solver keeps one entry per slot, not per node, for the sum of the forces on the set and its
//! mass (and for its position and velocity, [`crate::node_values`]), adds every force on a member
//! straight into its slot and gives the set one acceleration, `a = f_slot / sum m`
//! ([`CoincidentSets::masses`]), so the sums over a set come out in a fixed order (the element
//! pass's colours, then the cohesive and contact forces in their own fixed order) and no pass
//! gathers the members. When interfaces fail, only the sets that hold their nodes are
//! recomputed (connected components through the faces still tying them), and the pieces are
//! written back in place: no set is rebuilt from scratch, nothing grows but the list of set
//! ranges and the slots (the piece of the old representative keeps the set's slot, the others
//! get new ones). A piece is a subset of the set it came from, so a node's representative is
//! always a copy of the same deck node, a member of the node's set at the start, and so are
//! the members of a slot (what keeps the element pass's writes race-free, [`crate::solver`]).
//!
//! On the 20,000-element ball (`cleave bench ball --elements 20000 --end-time 20e-6`) the
//! 160,072 copies start in 21,343 slots and end in 34,816 after 12,532 failures.

use super::split::{FaceKind, SharedFace};
use crate::topology::UnionFind;
use rayon::prelude::*;

/// Sets a task of the parallel labelling takes at least (a set's search is short).
const SETS_PER_TASK: usize = 16;

const NONE: u32 = u32::MAX;

/// The coincident node sets of a split model.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub struct CoincidentSets {
    members: Vec<u32>,
    /// (start, len) of each set in `members`; a set with len < 2 is dead.
    ranges: Vec<(u32, u32)>,
    /// Set of each node, or NONE.
    node_set: Vec<u32>,
    /// The element of each node that some face holds (`NONE`: in no face; `SHARED`: a node
    /// that faces of several elements hold, outside every group). A node's faces are among
    /// its element's. (A node outside the groups may have elements that no face of the table
    /// holds it in: faces between two such elements are not in the table.)
    node_elem: Vec<u32>,
    /// The shared faces of each element (`NONE` padding).
    elem_faces: Vec<[u32; 6]>,
    /// (node, face) for the `SHARED` nodes, sorted.
    shared_adj: Vec<(u32, u32)>,
    /// Scratch for splitting ([`Self::split_after_failure`]): the sets to split, whether each
    /// set is listed, each listed set's piece labels (per position in the set, the sets one
    /// after the other) and piece count, and a piece's members.
    #[serde(skip)]
    todo: Vec<u32>,
    #[serde(skip)]
    listed: Vec<bool>,
    #[serde(skip)]
    label: Vec<u32>,
    #[serde(skip)]
    pieces: Vec<u32>,
    #[serde(skip)]
    piece: Vec<u32>,
    /// Slot of each node: the index of its set's entry in the solver's per-set arrays (sum of
    /// forces, mass), one per set and per node in no set, numbered in the order of their
    /// representatives; a set that splits keeps its slot for the piece of its representative,
    /// and the other pieces get new slots, numbered on ([`Self::num_slots`]).
    slot: Vec<u32>,
    num_slots: u32,
    /// (start, len) in `members` of each piece the last [`Self::split_after_failure`] wrote, in
    /// the order written.
    changed: Vec<(u32, u32)>,
    /// (new slot, slot it split from) of each piece the last [`Self::split_after_failure`]
    /// gave a slot, in the order numbered.
    born: Vec<(u32, u32)>,
}

const SHARED: u32 = u32::MAX - 1;

/// Whether face `f` ties its nodes: bonds always, interfaces while intact.
#[inline]
fn ties(faces: &[SharedFace], intact: &[bool], f: usize) -> bool {
    faces[f].kind == FaceKind::Bond || intact[f]
}

impl CoincidentSets {
    /// Sets of `num_nodes` nodes tied by `faces`; `intact[f]` for the interface faces
    /// (bonds are always tied; `intact` has one entry per face).
    pub fn build(num_nodes: usize, faces: &[SharedFace], intact: &[bool]) -> Self {
        let mut uf = UnionFind::new(num_nodes);
        let mut node_elem = vec![NONE; num_nodes];
        let ne = faces
            .iter()
            .map(|f| f.elems[0].max(f.elems[1]) as usize + 1)
            .max()
            .unwrap_or(0);
        let mut elem_faces = vec![[NONE; 6]; ne];
        for (f, face) in faces.iter().enumerate() {
            for side in 0..2 {
                let e = face.elems[side];
                let slot = elem_faces[e as usize]
                    .iter_mut()
                    .find(|x| **x == NONE)
                    .expect("a hexahedron shares at most 6 faces");
                *slot = f as u32;
                for k in 0..4 {
                    let n = face.nodes[4 * side + k] as usize;
                    node_elem[n] = match node_elem[n] {
                        NONE => e,
                        x if x == e => e,
                        _ => SHARED,
                    };
                }
            }
            if ties(faces, intact, f) {
                for k in 0..4 {
                    uf.union(face.nodes[k], face.nodes[4 + k]);
                }
            }
        }
        let mut shared_adj: Vec<(u32, u32)> = Vec::new();
        for (f, face) in faces.iter().enumerate() {
            for &n in &face.nodes {
                if node_elem[n as usize] == SHARED {
                    shared_adj.push((n, f as u32));
                }
            }
        }
        shared_adj.sort_unstable();
        // group nodes by root; roots are smallest members, so sets come out ordered by their
        // smallest member with ascending members
        let mut count = vec![0u32; num_nodes];
        for i in 0..num_nodes as u32 {
            count[uf.find(i) as usize] += 1;
        }
        let mut node_set = vec![NONE; num_nodes];
        let mut ranges = Vec::new();
        let mut members = Vec::new();
        let mut root_set = vec![NONE; num_nodes];
        let mut next = Vec::new();
        for i in 0..num_nodes as u32 {
            let r = uf.find(i) as usize;
            if count[r] < 2 {
                continue;
            }
            if root_set[r] == NONE {
                root_set[r] = ranges.len() as u32;
                ranges.push((members.len() as u32, count[r]));
                members.resize(members.len() + count[r] as usize, 0);
                next.push(0u32);
            }
            let s = root_set[r] as usize;
            members[(ranges[s].0 + next[s]) as usize] = i;
            next[s] += 1;
            node_set[i as usize] = s as u32;
        }
        // a slot for each representative, in node order (a representative is its set's
        // smallest member: its slot is numbered before any other member asks for it)
        let mut slot = vec![NONE; num_nodes];
        let mut num_slots = 0u32;
        for i in 0..num_nodes {
            let r = match node_set[i] {
                NONE => i,
                s => members[ranges[s as usize].0 as usize] as usize,
            };
            if r == i {
                slot[i] = num_slots;
                num_slots += 1;
            } else {
                slot[i] = slot[r];
            }
        }
        Self {
            members,
            ranges,
            node_set,
            node_elem,
            elem_faces,
            shared_adj,
            todo: Vec::new(),
            listed: Vec::new(),
            label: Vec::new(),
            pieces: Vec::new(),
            piece: Vec::new(),
            slot,
            num_slots,
            changed: Vec::new(),
            born: Vec::new(),
        }
    }

    /// The live sets, each as its ascending member list.
    pub fn sets(&self) -> impl Iterator<Item = &[u32]> {
        self.ranges
            .iter()
            .filter(|r| r.1 >= 2)
            .map(|&(s, l)| &self.members[s as usize..(s + l) as usize])
    }

    /// The set of each node (`u32::MAX`: in no set); two nodes are tied when their entries are
    /// equal and not `u32::MAX`. This is the `tie` argument of
    /// [`crate::contact::ContactSet::compute`].
    pub fn node_sets(&self) -> &[u32] {
        &self.node_set
    }

    /// The representative of node `n`: the smallest member of its set, or the node itself
    /// when it is in no set. Always a member of the node's set as [`Self::build`] made it.
    pub fn rep(&self, n: u32) -> u32 {
        self.set_of(n).map_or(n, |set| set[0])
    }

    /// The slot of each node ([`Self::num_slots`] of them): two nodes share one exactly when
    /// they are tied (one set). The solver keeps each set's sum of forces and its mass there.
    pub fn slots(&self) -> &[u32] {
        &self.slot
    }

    /// Number of slots: the sets and the nodes in no set.
    pub fn num_slots(&self) -> usize {
        self.num_slots as usize
    }

    /// The mass of each slot's set, `sum m` over its members in ascending order (a node in no
    /// set: its own mass), into `out` (resized to [`Self::num_slots`]).
    pub fn masses(&self, mass: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.resize(self.num_slots(), 0.0);
        for (i, &m) in mass.iter().enumerate() {
            if self.node_set[i] == NONE {
                out[self.slot[i] as usize] = m;
            }
        }
        for set in self.sets() {
            self.weigh(set, mass, out);
        }
    }

    /// [`Self::masses`] again for the slots of the sets the last
    /// [`Self::split_after_failure`] changed (`out` held the masses before it; the new slots
    /// are added).
    pub fn reweigh_changed(&self, mass: &[f64], out: &mut Vec<f64>) {
        out.resize(self.num_slots(), 0.0);
        for &(st, l) in &self.changed {
            self.weigh(&self.members[st as usize..(st + l) as usize], mass, out);
        }
    }

    /// The slots the last [`Self::split_after_failure`] made, each with the slot of the set it
    /// split from (a slot of before the call: each set splits once, into its final pieces), in
    /// the order numbered (`num_slots` before it, then on). Members of a new slot sat at one
    /// point with those of its source, with its velocity: the solver copies both across.
    pub fn born(&self) -> &[(u32, u32)] {
        &self.born
    }

    /// The nodes whose set (and so representative and set mass) the last
    /// [`Self::split_after_failure`] changed, each once (the pieces are disjoint).
    pub fn changed_nodes(&self) -> impl Iterator<Item = u32> + '_ {
        self.changed
            .iter()
            .flat_map(|&(st, l)| &self.members[st as usize..(st + l) as usize])
            .copied()
    }

    /// The set holding node `n`, if any.
    pub fn set_of(&self, n: u32) -> Option<&[u32]> {
        let s = self.node_set[n as usize];
        (s != NONE).then(|| {
            let (st, l) = self.ranges[s as usize];
            &self.members[st as usize..(st + l) as usize]
        })
    }

    /// The one element whose node `n` is, if `n` is a node of a group element in some face.
    pub fn owner(&self, n: u32) -> Option<u32> {
        let e = self.node_elem[n as usize];
        (e != NONE && e != SHARED).then_some(e)
    }

    /// The slot of `set` (ascending members) gets the set's mass, summed in that order.
    fn weigh(&self, set: &[u32], mass: &[f64], out: &mut [f64]) {
        let total = set.iter().fold(0.0, |t, &n| t + mass[n as usize]);
        out[self.slot[set[0] as usize] as usize] = total;
    }

    /// The faces holding node `n`, into `out`.
    fn faces_of(&self, n: u32, faces: &[SharedFace], out: &mut Vec<u32>) {
        out.clear();
        match self.node_elem[n as usize] {
            NONE => {}
            SHARED => {
                let at = self.shared_adj.partition_point(|p| p.0 < n);
                out.extend(
                    self.shared_adj[at..]
                        .iter()
                        .take_while(|p| p.0 == n)
                        .map(|p| p.1),
                );
            }
            e => out.extend(
                self.elem_faces[e as usize]
                    .iter()
                    .copied()
                    .filter(|&f| f != NONE && faces[f as usize].nodes.contains(&n)),
            ),
        }
    }

    /// Re-split the sets holding the nodes of `failed` faces (whose `intact` entry is already
    /// false) into the components still tied together.
    ///
    /// Each set is split once, after every tie of the step is gone, so its pieces are final:
    /// the sets are listed in the order their nodes come in `failed` (which numbers the new
    /// pieces, as splitting them one face after the other would), their components labelled
    /// in parallel (each set read-only, its labels in its own span), and the pieces written
    /// back in that order. O(members of the sets split), the same on any number of threads.
    pub fn split_after_failure(&mut self, faces: &[SharedFace], intact: &[bool], failed: &[usize]) {
        self.changed.clear();
        self.born.clear();
        let mut todo = std::mem::take(&mut self.todo);
        todo.clear();
        self.listed.resize(self.ranges.len(), false);
        for &f in failed {
            for &n in &faces[f].nodes {
                let s = self.node_set[n as usize];
                if s != NONE && !self.listed[s as usize] {
                    self.listed[s as usize] = true;
                    todo.push(s);
                }
            }
        }
        let mut label = std::mem::take(&mut self.label);
        let mut pieces = std::mem::take(&mut self.pieces);
        label.clear();
        label.resize(
            todo.iter()
                .map(|&s| self.ranges[s as usize].1 as usize)
                .sum(),
            NONE,
        );
        pieces.clear();
        pieces.resize(todo.len(), 0);
        let mut spans = Vec::with_capacity(todo.len());
        let mut rest = label.as_mut_slice();
        for &s in &todo {
            let (span, tail) = rest.split_at_mut(self.ranges[s as usize].1 as usize);
            spans.push(span);
            rest = tail;
        }
        let this = &*self;
        spans
            .into_par_iter()
            .zip(todo.par_iter())
            .zip(pieces.par_iter_mut())
            .with_min_len(SETS_PER_TASK)
            .for_each_init(
                || (Vec::new(), Vec::new()),
                |(stack, incident), ((span, &s), count)| {
                    *count = this.label_pieces(s as usize, faces, intact, span, stack, incident);
                },
            );
        let mut at = 0;
        for (&s, &count) in todo.iter().zip(&pieces) {
            let len = self.ranges[s as usize].1 as usize;
            if count > 1 {
                self.write_pieces(s as usize, &label[at..at + len], count);
            }
            at += len;
            self.listed[s as usize] = false;
        }
        self.todo = todo;
        self.label = label;
        self.pieces = pieces;
    }

    /// The components of set `s` still tied together: `label[k]` the piece of its k-th
    /// member (`label` all NONE on entry), by a search through the tying faces seeded in
    /// ascending member order; returns the number of pieces.
    fn label_pieces(
        &self,
        s: usize,
        faces: &[SharedFace],
        intact: &[bool],
        label: &mut [u32],
        stack: &mut Vec<u32>,
        incident: &mut Vec<u32>,
    ) -> u32 {
        let (start, len) = self.ranges[s];
        let range = start as usize..(start + len) as usize;
        let mut pieces = 0u32;
        for seed_at in 0..len as usize {
            if label[seed_at] != NONE {
                continue;
            }
            label[seed_at] = pieces;
            stack.push(self.members[start as usize + seed_at]);
            while let Some(n) = stack.pop() {
                self.faces_of(n, faces, incident);
                for &f in incident.iter() {
                    let f = f as usize;
                    if !ties(faces, intact, f) {
                        continue;
                    }
                    let face = &faces[f];
                    let k = face
                        .nodes
                        .iter()
                        .position(|&m| m == n)
                        .expect("adjacent face holds the node");
                    let partner = face.nodes[(k + 4) % 8];
                    if self.node_set[partner as usize] != s as u32 {
                        continue;
                    }
                    // (members are ascending: binary search)
                    let at = self.members[range.clone()]
                        .binary_search(&partner)
                        .expect("a set member");
                    if label[at] == NONE {
                        label[at] = pieces;
                        stack.push(partner);
                    }
                }
            }
            pieces += 1;
        }
        pieces
    }

    /// Write the `pieces` pieces of set `s` (`label`: [`Self::label_pieces`]) back
    /// contiguously, each ascending, in order of their smallest member: the first keeps the
    /// set's number and slot, the others get new ones.
    fn write_pieces(&mut self, s: usize, label: &[u32], pieces: u32) {
        let (start, len) = self.ranges[s];
        let range = start as usize..(start + len) as usize;
        self.piece.clear();
        for p in 0..pieces {
            self.piece.extend(
                self.members[range.clone()]
                    .iter()
                    .zip(label)
                    .filter(|&(_, &l)| l == p)
                    .map(|(&n, _)| n),
            );
        }
        let old_slot = self.slot[self.members[start as usize] as usize];
        self.members[range].copy_from_slice(&self.piece);
        let mut at = start;
        for p in 0..pieces {
            let size = label.iter().filter(|&&l| l == p).count() as u32;
            let id = if p == 0 {
                s as u32
            } else {
                self.ranges.len() as u32
            };
            if p == 0 {
                self.ranges[s] = (at, size);
            } else {
                self.ranges.push((at, size));
            }
            let first = self.members[at as usize];
            // the first piece holds the old representative and keeps the slot
            let slot = if p == 0 {
                self.slot[first as usize]
            } else {
                self.num_slots += 1;
                self.born.push((self.num_slots - 1, old_slot));
                self.num_slots - 1
            };
            for &n in &self.members[at as usize..(at + size) as usize] {
                self.node_set[n as usize] = if size >= 2 { id } else { NONE };
                self.slot[n as usize] = slot;
            }
            self.changed.push((at, size));
            at += size;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_model;
    use crate::model::{Material, MaterialKind, SeparationDef};
    use crate::separation::split::split_model;

    /// A block of n x n x n unit elements, every interface able to fail.
    fn split_block_of(n: usize) -> crate::separation::split::SplitModel {
        let mat = Material {
            id: 1,
            density: 1000.0,
            young: 1e9,
            poisson: 0.25,
            kind: MaterialKind::Elastic,
        };
        let l = n as f64;
        let mut m = box_model([n, n, n], [l, l, l], mat, 1.0);
        m.separations.push(SeparationDef {
            material: 0,
            model: 1,
            sigmax: 1e6,
            beta: 1.0,
            gc: 0.0,
            bond: 1,
            strength: Default::default(),
        });
        split_model(&m)
    }

    /// The 12 interfaces around the block's centre, in a scrambled order.
    const FAILURE_ORDER: [usize; 12] = [5, 0, 11, 3, 8, 1, 10, 6, 2, 9, 4, 7];

    /// The split 2 x 2 x 2 block with every interface intact, and its sets.
    fn split_block_with_sets() -> (
        crate::separation::split::SplitModel,
        Vec<bool>,
        CoincidentSets,
    ) {
        let sm = split_block_of(2);
        let intact = vec![true; sm.faces.len()];
        let cs = CoincidentSets::build(sm.model.num_nodes(), &sm.faces, &intact);
        (sm, intact, cs)
    }

    /// Partition of all nodes into sets, computed from scratch (independent of the splitting).
    fn partition(s: &CoincidentSets) -> Vec<Vec<u32>> {
        let mut v: Vec<Vec<u32>> = s.sets().map(|x| x.to_vec()).collect();
        v.sort();
        v
    }

    /// The 2x2x2 block: 12 edge-midpoint sets of 2, 6 face-centre sets of 4, the centre set of 8.
    #[test]
    fn intact_block_sets() {
        let sm = split_block_of(2);
        let intact = vec![true; sm.faces.len()];
        let cs = CoincidentSets::build(sm.model.num_nodes(), &sm.faces, &intact);
        let mut sizes: Vec<usize> = cs.sets().map(|s| s.len()).collect();
        sizes.sort();
        assert_eq!(sizes, [vec![2; 12], vec![4; 6], vec![8]].concat());
        for set in cs.sets() {
            let x = sm.model.x0[set[0] as usize];
            assert!(
                set.iter().all(|&n| sm.model.x0[n as usize] == x),
                "members coincide"
            );
            assert!(set.windows(2).all(|w| w[0] < w[1]), "members ascending");
        }
    }

    /// The node shared by 8 elements at the block's centre: fail the 12 interfaces one by one
    /// (in a scrambled order); after each failure the incrementally split sets equal the sets
    /// built from scratch from the faces still intact, and the centre's copies are partitioned
    /// exactly as the remaining faces connect them.
    #[test]
    fn sets_split_exactly_as_the_intact_faces_say() {
        let (sm, mut intact, mut cs) = split_block_with_sets();
        let n = sm.model.num_nodes();
        let centre: Vec<u32> = (0..n as u32)
            .filter(|&i| sm.model.x0[i as usize] == [1.0, 1.0, 1.0])
            .collect();
        assert_eq!(centre.len(), 8);
        for (step, &f) in FAILURE_ORDER.iter().enumerate() {
            intact[f] = false;
            cs.split_after_failure(&sm.faces, &intact, &[f]);
            let fresh = CoincidentSets::build(n, &sm.faces, &intact);
            assert_eq!(
                partition(&cs),
                partition(&fresh),
                "after {} failures",
                step + 1
            );
            // centre copies: components of the graph whose edges are intact faces' centre pairs
            let mut uf = UnionFind::new(n);
            for (g, face) in sm.faces.iter().enumerate() {
                if intact[g] {
                    for k in 0..4 {
                        uf.union(face.nodes[k], face.nodes[4 + k]);
                    }
                }
            }
            for &a in &centre {
                for &b in &centre {
                    let together = cs.set_of(a).is_some_and(|s| s.contains(&b));
                    assert_eq!(
                        together || a == b,
                        uf.find(a) == uf.find(b),
                        "nodes {a} {b} after {} failures",
                        step + 1
                    );
                }
            }
        }
        assert_eq!(cs.sets().count(), 0, "all faces failed: every node is free");
    }

    /// Representatives, slots and set masses after each of the 12 failures around the block's
    /// centre (scrambled order): the representatives and each node's set mass equal those of
    /// the sets built from scratch from the faces still intact, bit for bit; two nodes share
    /// a slot exactly when they share a set, a slot is never reused for another set, and the
    /// first piece of a split set keeps its slot; every node's representative stays a member
    /// of its first set (the element pass's colours rely on it); and the nodes reported
    /// changed are all those whose representative, slot or set mass changed.
    /// The representative of every node.
    fn reps(cs: &CoincidentSets) -> Vec<u32> {
        (0..cs.slots().len() as u32).map(|n| cs.rep(n)).collect()
    }

    #[test]
    fn reps_slots_and_masses_follow_the_splits() {
        let (sm, mut intact, mut cs) = split_block_with_sets();
        let n = sm.model.num_nodes();
        let mass: Vec<f64> = (0..n).map(|i| 1.0 + (i % 5) as f64 * 0.37).collect();
        let first = reps(&cs);
        let mut kept = Vec::new();
        cs.masses(&mass, &mut kept);
        assert_eq!(kept.len(), cs.num_slots());
        for set in cs.sets() {
            let total: f64 = set.iter().map(|&m| mass[m as usize]).sum();
            for &m in set {
                assert_eq!(cs.rep(m), set[0]);
                let s = cs.slots()[m as usize] as usize;
                assert!((kept[s] - total).abs() <= 1e-12 * total);
            }
        }
        // node of each slot's set at the start (a slot stays with a piece of its first set)
        let owner_of_slot = |cs: &CoincidentSets| -> Vec<u32> {
            let mut o = vec![u32::MAX; cs.num_slots()];
            for i in 0..n {
                let s = cs.slots()[i] as usize;
                if o[s] == u32::MAX {
                    o[s] = i as u32;
                }
            }
            o
        };
        for (step, &failed) in FAILURE_ORDER.iter().enumerate() {
            let (reps_before, slots_before) = (reps(&cs), cs.slots().to_vec());
            let set_mass_before: Vec<f64> =
                (0..n).map(|i| kept[slots_before[i] as usize]).collect();
            let slots_count = cs.num_slots();
            intact[failed] = false;
            cs.split_after_failure(&sm.faces, &intact, &[failed]);
            cs.reweigh_changed(&mass, &mut kept);
            assert_eq!(kept.len(), cs.num_slots());
            let fresh = CoincidentSets::build(n, &sm.faces, &intact);
            let mut fresh_masses = Vec::new();
            fresh.masses(&mass, &mut fresh_masses);
            assert_eq!(reps(&cs), reps(&fresh), "after {} failures", step + 1);
            assert_eq!(cs.num_slots(), fresh.num_slots(), "one slot per set");
            let changed: Vec<u32> = cs.changed_nodes().collect();
            let owners = owner_of_slot(&cs);
            for i in 0..n {
                let (s, fs) = (cs.slots()[i] as usize, fresh.slots()[i] as usize);
                assert_eq!(
                    kept[s],
                    fresh_masses[fs],
                    "node {i} after {} failures",
                    step + 1
                );
                // same slot <=> same set: the slot's first node is tied to i (or is i)
                let o = owners[s];
                assert!(
                    o == i as u32 || cs.set_of(o).is_some_and(|set| set.contains(&(i as u32))),
                    "node {i} shares slot {s} with untied node {o}"
                );
                // a slot kept is the old one of the node's set's representative; new ones
                // are numbered on
                let r = cs.rep(i as u32) as usize;
                assert!(s == slots_before[r] as usize || s >= slots_count);
                assert_eq!(first[r], first[i], "node {i}: its rep left its first set");
                if cs.rep(i as u32) != reps_before[i]
                    || s != slots_before[i] as usize
                    || kept[s] != set_mass_before[i]
                {
                    assert!(changed.contains(&(i as u32)), "node {i} not reported");
                }
            }
            assert!(!changed.is_empty(), "each failure splits a set");
        }
        let own: Vec<f64> = (0..n).map(|i| kept[cs.slots()[i] as usize]).collect();
        assert_eq!(own, mass, "all faces failed: each node its own mass");
        assert_eq!(cs.num_slots(), n, "all faces failed: a slot per node");
    }

    /// Many interfaces failing in one step, on a 4 x 4 x 4 block (every other interface, so
    /// more sets split at once than a task of the parallel labelling takes): the sets are
    /// those built from scratch from the faces still intact, with their masses; each split
    /// set's new slots are numbered in the order its nodes first come in the failed list;
    /// and the result, slots and members included, is the same on 1 and on 4 threads.
    #[test]
    fn many_failures_in_one_step_split_alike_on_any_thread_count() {
        let sm = split_block_of(4);
        let n = sm.model.num_nodes();
        let mass: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64 * 0.29).collect();
        // every other interface, in a scrambled order
        let mut failed: Vec<usize> = (0..sm.faces.len()).filter(|f| f % 2 == 0).collect();
        failed.sort_by_key(|&f| (f * 37) % 101);
        let mut intact = vec![true; sm.faces.len()];
        for &f in &failed {
            intact[f] = false;
        }
        let run = |threads: usize| {
            let mut cs = CoincidentSets::build(n, &sm.faces, &vec![true; sm.faces.len()]);
            let mut kept = Vec::new();
            cs.masses(&mass, &mut kept);
            let before = cs.clone();
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| cs.split_after_failure(&sm.faces, &intact, &failed));
            cs.reweigh_changed(&mass, &mut kept);
            (before, cs, kept)
        };
        let (before, cs, kept) = run(1);
        // more sets split than a task of the labelling takes
        let split = (before.sets())
            .filter(|set| set.iter().any(|&m| cs.set_of(m) != Some(*set)))
            .count();
        assert!(split > 2 * SETS_PER_TASK, "{split} sets split");
        // the splitting face by face of before (one call per face, with the final ties: a
        // set splits at the first face that holds one of its nodes, later calls find it
        // whole): the same arrays and the same new slots in the same order
        let mut by_face = before.clone();
        let mut born = Vec::new();
        for &f in &failed {
            by_face.split_after_failure(&sm.faces, &intact, &[f]);
            born.extend_from_slice(by_face.born());
        }
        assert_eq!(born, cs.born());
        assert_eq!(by_face.members, cs.members);
        assert_eq!(by_face.ranges, cs.ranges);
        assert_eq!(by_face.node_set, cs.node_set);
        assert_eq!(by_face.slot, cs.slot);
        assert_eq!(by_face.num_slots, cs.num_slots);
        let fresh = CoincidentSets::build(n, &sm.faces, &intact);
        let mut fresh_masses = Vec::new();
        fresh.masses(&mass, &mut fresh_masses);
        assert_eq!(partition(&cs), partition(&fresh));
        assert_eq!(reps(&cs), reps(&fresh));
        for i in 0..n {
            let (s, fs) = (cs.slots()[i] as usize, fresh.slots()[i] as usize);
            assert_eq!(kept[s], fresh_masses[fs], "node {i}");
        }
        // new slots in the order the sets they split from first come in `failed`
        let mut first_seen = vec![usize::MAX; before.num_slots()];
        for (k, &f) in failed.iter().enumerate() {
            for &node in &sm.faces[f].nodes {
                let slot = before.slots()[node as usize] as usize;
                first_seen[slot] = first_seen[slot].min(k);
            }
        }
        let order: Vec<usize> = (cs.born().iter())
            .map(|&(_, from)| first_seen[from as usize])
            .collect();
        assert!(order.windows(2).all(|w| w[0] <= w[1]), "{order:?}");
        let (_, cs4, kept4) = run(4);
        assert_eq!(cs4.slots(), cs.slots());
        assert_eq!(cs4.born(), cs.born());
        assert_eq!(cs4.members, cs.members);
        assert_eq!(cs4.ranges, cs.ranges);
        assert_eq!(kept4, kept);
    }
}
