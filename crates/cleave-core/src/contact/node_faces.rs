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

    /// Nodes `a` and `b` swap places.
    pub fn swap(&mut self, a: usize, b: usize) {
        self.inline.swap(a, b);
        if self.more.is_empty() {
            return;
        }
        let (a, b) = (a as u32, b as u32);
        let (ma, mb) = (self.more.remove(&a), self.more.remove(&b));
        if let Some(m) = ma {
            self.more.insert(b, m);
        }
        if let Some(m) = mb {
            self.more.insert(a, m);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_come_back_in_order_past_the_inline_ones_and_move_with_swaps() {
        let mut nf = NodeFaces::default();
        nf.resize(3);
        for f in 0..7 {
            nf.push(1, 10 + f);
        }
        nf.push(2, 5);
        assert_eq!(nf.of(0).count(), 0);
        assert_eq!(nf.of(1).collect::<Vec<_>>(), (10..17).collect::<Vec<_>>());
        nf.swap(1, 2);
        assert_eq!(nf.of(1).collect::<Vec<_>>(), vec![5]);
        assert_eq!(nf.of(2).collect::<Vec<_>>(), (10..17).collect::<Vec<_>>());
        nf.swap(0, 2);
        assert_eq!(nf.of(0).count(), 7);
        assert_eq!(nf.of(2).count(), 0);
        nf.resize(4);
        assert_eq!(nf.of(3).count(), 0);
    }
}
