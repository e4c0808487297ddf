//! The nodes of a pass that touch a face, stored sparsely.
//!
//! A node's contact lives from step to step: its hit (face, weights, force, engagement, |f_n|) and
//! its tangential force (the friction history), 112 bytes. On a fragmenting ball most nodes of the
//! contact surface touch nothing (the 20,000-element ball at 20 us: about 75,000 surface nodes, a
//! few thousand in contact), so these are kept only for the nodes that have them: per chunk of
//! [`Touching::chunk`] nodes (the chunks of the parallel check), a list of the chunk's touching
//! nodes in place order. A step's check walks each chunk's list of the last step while it writes
//! the new one (two lists a chunk, swapped after the step), so the chunks stay independent and
//! nothing is allocated once the lists have grown.
//!
//! The results do not depend on this storage: a node's contact reads and writes the same
//! values as with one entry per node, and the forces are scattered in the order of the
//! nodes' ranks ([`Touching::by_rank`]), as before.

use rayon::prelude::*;

use super::Hit;
use crate::math::Vec3;

/// A node's contact of the last step.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug)]
pub(super) struct Touch {
    /// Place of the node within its chunk.
    pub k: u32,
    /// Whether the hit carries a force (|f_n| > 0) this step.
    pub active: bool,
    pub hit: Hit,
    /// Tangential force (the friction history).
    pub ft: Vec3,
}

impl Touch {
    /// Whether a node with this hit and tangential force has anything to keep: an empty hit
    /// and no tangential force are the state of a node out of contact.
    fn keeps(hit: &Hit, ft: Vec3) -> bool {
        hit.face != super::NONE || ft != [0.0; 3]
    }
}

/// The touching nodes of a pass (module docs).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(super) struct Touching {
    /// Nodes per chunk.
    chunk: usize,
    /// Each chunk's touching nodes, ascending in place.
    lists: Vec<Vec<Touch>>,
    /// The lists being written by a step.
    spare: Vec<Vec<Touch>>,
    /// Scratch: (rank, chunk, index) of the active nodes; the new place of each old place.
    order: Vec<(u32, u32, u32)>,
    places: Vec<u32>,
}

impl Touching {
    /// Room for `nodes` nodes, in chunks of `chunk`; none touches.
    pub fn new(chunk: usize, nodes: usize) -> Self {
        let mut t = Self {
            chunk,
            lists: Vec::new(),
            spare: Vec::new(),
            order: Vec::new(),
            places: Vec::new(),
        };
        t.resize(nodes);
        t
    }

    /// Room for `nodes` nodes (nodes joined: they touch nothing yet).
    pub fn resize(&mut self, nodes: usize) {
        let n = nodes.div_ceil(self.chunk);
        self.lists.resize_with(n, Vec::new);
        self.spare.resize_with(n, Vec::new);
    }

    /// Number of touching nodes (with a hit or a friction history).
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.lists.iter().map(Vec::len).sum()
    }

    /// The contact of node `i` (its place), if it has one.
    pub fn get(&self, i: usize) -> Option<&Touch> {
        let list = &self.lists[i / self.chunk];
        let k = (i % self.chunk) as u32;
        list.binary_search_by_key(&k, |t| t.k)
            .ok()
            .map(|j| &list[j])
    }

    /// Give node `i` the hit and tangential force (none when empty); not active until its
    /// next check.
    pub fn set(&mut self, i: usize, hit: Hit, ft: Vec3) {
        let list = &mut self.lists[i / self.chunk];
        let k = (i % self.chunk) as u32;
        let t = Touch {
            k,
            active: false,
            hit,
            ft,
        };
        match (
            list.binary_search_by_key(&k, |t| t.k),
            Touch::keeps(&hit, ft),
        ) {
            (Ok(j), true) => list[j] = t,
            (Ok(j), false) => {
                list.remove(j);
            }
            (Err(j), true) => list.insert(j, t),
            (Err(_), false) => {}
        }
    }

    /// For a step: each chunk's list of the last step and the list to write, the chunks in
    /// order. Call [`Touching::swap`] after.
    pub fn chunks(&mut self) -> impl IndexedParallelIterator<Item = ChunkStep<'_>> {
        self.lists
            .par_iter()
            .zip(self.spare.par_iter_mut())
            .map(|(old, new)| {
                new.clear();
                ChunkStep { old, at: 0, new }
            })
    }

    /// The lists written by the step become the last step's.
    pub fn swap(&mut self) {
        std::mem::swap(&mut self.lists, &mut self.spare);
    }

    /// The active nodes (place, contact), by ascending `rank[place]`.
    pub fn by_rank<'a>(&'a mut self, rank: &[u32]) -> impl Iterator<Item = (usize, &'a Touch)> {
        self.order.clear();
        for (c, list) in self.lists.iter().enumerate() {
            for (j, t) in list.iter().enumerate().filter(|(_, t)| t.active) {
                let place = c * self.chunk + t.k as usize;
                self.order.push((rank[place], c as u32, j as u32));
            }
        }
        self.order.sort_unstable();
        let (lists, chunk) = (&self.lists, self.chunk);
        self.order.iter().map(move |&(_, c, j)| {
            let t = &lists[c as usize][j as usize];
            (c as usize * chunk + t.k as usize, t)
        })
    }

    /// The nodes moved: place k holds the node that was at `order[k].1` (as
    /// [`super::Side::permute`] applies it).
    pub fn permute(&mut self, order: &[(u64, u32)]) {
        self.places.clear();
        self.places.resize(order.len(), 0);
        for (k, &(_, old)) in order.iter().enumerate() {
            self.places[old as usize] = k as u32;
        }
        let mut moved = std::mem::take(&mut self.spare);
        for list in &mut moved {
            list.clear();
        }
        let chunk = self.chunk;
        for (c, list) in self.lists.iter().enumerate() {
            for t in list {
                let p = self.places[c * chunk + t.k as usize] as usize;
                moved[p / chunk].push(Touch {
                    k: (p % chunk) as u32,
                    ..*t
                });
            }
        }
        for list in &mut moved {
            list.sort_unstable_by_key(|t| t.k);
        }
        self.spare = std::mem::replace(&mut self.lists, moved);
    }
}

/// One chunk's step: the last step's list, read in place order, and the new one.
pub(super) struct ChunkStep<'a> {
    old: &'a [Touch],
    at: usize,
    new: &'a mut Vec<Touch>,
}

impl ChunkStep<'_> {
    /// The last step's contact of the node at place `k` of the chunk (the places must come
    /// ascending), and the new one is to be given by [`ChunkStep::put`] (a node not looked at
    /// keeps it by [`ChunkStep::keep`]).
    #[inline]
    pub fn take(&mut self, k: usize) -> Option<Touch> {
        let t = self.old.get(self.at).filter(|t| t.k as usize == k).copied();
        self.at += t.is_some() as usize;
        t
    }

    /// Keep the last step's contact of a node unchanged.
    #[inline]
    pub fn keep(&mut self, t: Touch) {
        self.new.push(t);
    }

    /// The new contact of the node at place `k` (nothing kept when empty).
    #[inline]
    pub fn put(&mut self, k: usize, hit: Hit, ft: Vec3, active: bool) {
        if Touch::keeps(&hit, ft) {
            self.new.push(Touch {
                k: k as u32,
                active,
                hit,
                ft,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(face: u32) -> Hit {
        Hit {
            face,
            ..Hit::default()
        }
    }

    #[test]
    fn set_get_and_permute_keep_each_nodes_contact() {
        let mut t = Touching::new(4, 10);
        t.set(6, hit(3), [1.0, 0.0, 0.0]);
        t.set(5, hit(2), [0.0; 3]);
        t.set(0, Hit::default(), [0.0, 2.0, 0.0]);
        t.set(9, hit(7), [0.0; 3]);
        t.set(9, Hit::default(), [0.0; 3]); // emptied: dropped
        assert_eq!(t.len(), 3);
        assert_eq!(t.get(6).map(|x| x.hit.face), Some(3));
        assert_eq!(t.get(5).map(|x| x.hit.face), Some(2));
        assert_eq!(t.get(0).map(|x| x.ft), Some([0.0, 2.0, 0.0]));
        assert!(t.get(9).is_none() && t.get(1).is_none());
        // reverse the places: place k gets the node of place 9 - k
        let order: Vec<(u64, u32)> = (0..10).map(|k| (k as u64, 9 - k as u32)).collect();
        t.permute(&order);
        assert_eq!(t.get(3).map(|x| x.hit.face), Some(3));
        assert_eq!(t.get(4).map(|x| x.hit.face), Some(2));
        assert_eq!(t.get(9).map(|x| x.ft), Some([0.0, 2.0, 0.0]));
        assert_eq!(t.len(), 3);
    }

    #[test]
    fn a_step_carries_what_it_does_not_look_at_and_scatters_by_rank() {
        let mut t = Touching::new(4, 8);
        t.set(1, hit(1), [0.0; 3]);
        t.set(2, hit(2), [0.0; 3]);
        t.set(6, hit(6), [0.0; 3]);
        let steps: Vec<_> = t.chunks().collect();
        assert_eq!(steps.len(), 2);
        for (c, mut s) in steps.into_iter().enumerate() {
            for k in 0..4 {
                match s.take(k) {
                    // place 2 is not looked at: kept; the others get an active hit
                    Some(old) if c == 0 && k == 2 => s.keep(old),
                    Some(old) => s.put(k, old.hit, old.ft, true),
                    None if c == 1 && k == 3 => s.put(k, hit(7), [0.0; 3], true),
                    None => s.put(k, Hit::default(), [0.0; 3], false),
                }
            }
        }
        t.swap();
        assert_eq!(t.len(), 4);
        assert!(t.get(2).is_some_and(|x| !x.active));
        // ranks: place 7 first, then 6, then 1
        let mut rank = vec![9u32; 8];
        (rank[7], rank[6], rank[1]) = (0, 1, 2);
        let got: Vec<usize> = t.by_rank(&rank).map(|(i, _)| i).collect();
        assert_eq!(got, vec![7, 6, 1]);
    }
}
