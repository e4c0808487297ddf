//! The faces of each node of a contact side, in the order they joined.
//!
//! A node's normal is the sum of its faces' normals in that order ([`super::Side::frame`]),
//! read for every node a step checks. A copy of a split node lies on at most three faces (of
//! its one element) and a node of an unsplit surface mostly on four, so up to [`INLINE`] faces
//! are kept in place, 16 bytes a node, and only a node with more has a list of the rest
//! elsewhere. One `Vec` per node took 24 bytes plus a heap block of at least 32 and a pointer
//! chase on every read (about 75,000 surface nodes on the 20,000-element ball at 20 us).

use std::collections::HashMap;

const NONE: u32 = u32::MAX;

/// Faces of a node kept in place.
pub const INLINE: usize = 4;

/// The faces of each node (by its place in the side's `nodes`).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub(super) struct NodeFaces {
    /// The first faces of each node, NONE after the last.
    inline: Vec<[u32; INLINE]>,
    /// The faces after the first [`INLINE`], of the nodes that have more.
    more: HashMap<u32, Vec<u32>>,
}

impl NodeFaces {
    /// Room for `n` nodes (new nodes have no faces).
    pub fn resize(&mut self, n: usize) {
        self.inline.resize(n, [NONE; INLINE]);
    }

    /// Face `f` joins node `i` (after its faces so far).
    pub fn push(&mut self, i: u32, f: u32) {
        let slot = &mut self.inline[i as usize];
        match slot.iter_mut().find(|g| **g == NONE) {
            Some(g) => *g = f,
            None => self.more.entry(i).or_default().push(f),
        }
    }

    /// The faces of node `i`, in the order they joined.
    #[inline]
    pub fn of(&self, i: u32) -> impl Iterator<Item = u32> + '_ {
        let slot = &self.inline[i as usize];
        let more = if slot[INLINE - 1] == NONE || self.more.is_empty() {
            None
        } else {
            self.more.get(&i)
        };
        slot.iter()
            .copied()
            .take_while(|&f| f != NONE)
            .chain(more.into_iter().flatten().copied())
    }

    /// The nodes move: place k gets the node at `order[k].1` (each place once); `gather`
    /// makes the inline array so moved (`Side::permute`).
    pub fn permute(
        &mut self,
        order: &[(u64, u32)],
        gather: impl FnOnce(&[[u32; INLINE]]) -> Vec<[u32; INLINE]>,
    ) {
        self.inline = gather(&self.inline);
        if self.more.is_empty() {
            return;
        }
        let mut place = vec![0u32; order.len()];
        for (k, &(_, j)) in order.iter().enumerate() {
            place[j as usize] = k as u32;
        }
        // (a map: only looked up, so the order it is filled in reaches no result)
        self.more = (std::mem::take(&mut self.more).into_iter())
            .map(|(i, faces)| (place[i as usize], faces))
            .collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_come_back_in_order_past_the_inline_ones_and_move_with_their_nodes() {
        let mut nf = NodeFaces::default();
        nf.resize(3);
        for f in 0..7 {
            nf.push(1, 10 + f);
        }
        nf.push(2, 5);
        assert_eq!(nf.of(0).count(), 0);
        assert_eq!(nf.of(1).collect::<Vec<_>>(), (10..17).collect::<Vec<_>>());
        // place k gets the node at order[k].1: nodes 1 and 2 swap places
        let moved = |nf: &mut NodeFaces, order: &[(u64, u32)]| {
            nf.permute(order, |v| {
                order.iter().map(|&(_, j)| v[j as usize]).collect()
            })
        };
        moved(&mut nf, &[(0, 0), (0, 2), (0, 1)]);
        assert_eq!(nf.of(1).collect::<Vec<_>>(), vec![5]);
        assert_eq!(nf.of(2).collect::<Vec<_>>(), (10..17).collect::<Vec<_>>());
        // a cycle: place 0 gets node 2 (the seven faces), 1 gets 0 (none), 2 gets 1 (face 5)
        moved(&mut nf, &[(0, 2), (0, 0), (0, 1)]);
        assert_eq!(nf.of(0).count(), 7);
        assert_eq!(nf.of(1).count(), 0);
        assert_eq!(nf.of(2).collect::<Vec<_>>(), vec![5]);
        nf.resize(4);
        assert_eq!(nf.of(3).count(), 0);
    }
}
