//! The candidate lists of a pass's nodes and their schedules, kept in one buffer per chunk of
//! nodes.
//!
//! Each node with candidates has a [`Sched`] and a *room* of candidates ([`super::schedule`]:
//! the list and the places of its inline hot candidates), whose size changes only at a search.
//! The schedule is kept in the buffer just before the room ([`Sched::store`]); a node without
//! candidates (a copy that is not its set's lead, a buried node) has neither. The rooms of a
//! chunk of [`super::NODE_CHUNK`] consecutive nodes lie in one buffer, each node holding its
//! room's start and size (8 bytes), instead of a schedule (32 bytes) and a list of its own (24
//! bytes, and for those with candidates a heap block with its 16-byte header and growth room):
//! on the 20,000-element ball at 50 us, 76,000 nodes on the surface of which 27,000 are leads,
//! 7.3 MB of schedules, lists and their headers for 141,000 candidates (1.1 MB).
//!
//! A full build lays each chunk out again, node after node. A search of a few nodes puts a
//! node's new room in the place of its old one when it fits and at the end of the buffer
//! otherwise; the room left behind is a *hole*, and a chunk whose holes outgrow its rooms is
//! laid out again. Where a room lies never changes what a check finds: the lists are only
//! read through their rooms.

use rayon::prelude::*;
use std::cell::RefCell;

use super::schedule::{Cand, Sched};
use super::search::trim;

/// Candidates' space of a schedule, before its room.
const UNITS: usize = Sched::UNITS;

/// Where a node's room lies in its chunk's buffer.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
struct Place {
    start: u32,
    size: u32,
}

impl Place {
    fn range(&self) -> std::ops::Range<usize> {
        self.start as usize..(self.start + self.size) as usize
    }
}

/// One chunk's rooms.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
struct Buffer {
    cands: Vec<Cand>,
    /// Candidates of the buffer in no node's room.
    holes: usize,
}

thread_local! {
    /// Scratch of a chunk's new layout and of a node's new room.
    static NEW: RefCell<Vec<Cand>> = const { RefCell::new(Vec::new()) };
}

/// The rooms of all the nodes of a pass (module docs).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(super) struct CandLists {
    chunk: usize,
    place: Vec<Place>,
    buffers: Vec<Buffer>,
}

impl CandLists {
    /// `nodes` nodes without candidates, in chunks of `chunk`.
    pub fn new(chunk: usize, nodes: usize) -> Self {
        let mut c = Self {
            chunk,
            place: Vec::new(),
            buffers: Vec::new(),
        };
        c.resize(nodes);
        c
    }

    /// Room for `nodes` nodes (new nodes have no candidates).
    pub fn resize(&mut self, nodes: usize) {
        self.place.resize(nodes, Place::default());
        self.buffers
            .resize_with(nodes.div_ceil(self.chunk), Buffer::default);
    }

    /// Node i's schedule and room (a node without candidates has the default schedule).
    pub fn get(&self, i: usize) -> (Sched, &[Cand]) {
        split(&self.buffers[i / self.chunk].cands[self.place[i].range()])
    }

    /// Every node's schedule and room, in node order.
    pub fn rooms(&self) -> impl Iterator<Item = (Sched, &[Cand])> + '_ {
        (0..self.place.len()).map(|i| self.get(i))
    }

    /// The chunk that holds node i, and i's place in it.
    pub fn chunk_of(&mut self, i: usize) -> (Chunk<'_>, usize) {
        let c = i / self.chunk;
        let end = ((c + 1) * self.chunk).min(self.place.len());
        let chunk = Chunk {
            place: &mut self.place[c * self.chunk..end],
            buffer: &mut self.buffers[c],
        };
        (chunk, i - c * self.chunk)
    }

    /// The chunks, for a pass in parallel (chunk c holds nodes `c chunk..`).
    pub fn chunks(&mut self) -> impl IndexedParallelIterator<Item = Chunk<'_>> {
        self.place
            .par_chunks_mut(self.chunk)
            .zip(self.buffers.par_iter_mut())
            .map(|(place, buffer)| Chunk { place, buffer })
    }

    /// Drop every node's candidates, keeping the buffers' room (when the nodes are put in a
    /// new order, just before a full build lists them all again: carrying the rooms over to the
    /// new places would need a second copy of them all at once, 0.9 MB at the peak of the
    /// 20,000-element ball).
    pub fn forget(&mut self) {
        self.place.fill(Place::default());
        for b in &mut self.buffers {
            b.cands.clear();
            b.holes = 0;
        }
    }
}

/// The rooms of one chunk of nodes.
pub(super) struct Chunk<'a> {
    place: &'a mut [Place],
    buffer: &'a mut Buffer,
}

impl Chunk<'_> {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.place.len()
    }

    /// `f` of node k's schedule and room (k within the chunk), which it may change (the
    /// schedule is kept again; a node without candidates gets the default schedule and an
    /// empty room, and keeps nothing).
    #[inline]
    pub fn with<R>(&mut self, k: usize, f: impl FnOnce(&mut Sched, &mut [Cand]) -> R) -> R {
        let r = self.place[k].range();
        if r.is_empty() {
            return f(&mut Sched::default(), &mut []);
        }
        let (h, room) = self.buffer.cands[r].split_at_mut(UNITS);
        let mut sched = Sched::load(h);
        let out = f(&mut sched, room);
        sched.store(h);
        out
    }

    /// New rooms for every node of the chunk, laid out in node order: `search(k, sched, room,
    /// new)` gets node k's schedule and room, appends k's new candidates to `new` and returns
    /// their schedule. The buffer keeps its capacity, grown to fit exactly when short.
    pub fn search_all(
        &mut self,
        mut search: impl FnMut(usize, Sched, &mut [Cand], &mut Vec<Cand>) -> Sched,
    ) {
        NEW.with_borrow_mut(|new| {
            new.clear();
            for k in 0..self.place.len() {
                let start = new.len();
                let r = self.place[k].range();
                let (sched, room) = split_mut(&mut self.buffer.cands[r]);
                new.extend_from_slice(&[Cand::new(0); UNITS]);
                let sched = search(k, sched, room, new);
                let size = keep(sched, new, start);
                self.place[k] = Place {
                    start: start as u32,
                    size: size as u32,
                };
            }
            self.buffer.set(new);
        });
    }

    /// A new room for node k: `search(sched, room, new)` gets its schedule and room, fills
    /// `new` (empty) with the new candidates and returns their schedule. The new room takes
    /// the old one's place when it fits, else goes at the end of the buffer (growing it by an
    /// eighth at least when short).
    pub fn search_one(
        &mut self,
        k: usize,
        search: impl FnOnce(Sched, &mut [Cand], &mut Vec<Cand>) -> Sched,
    ) {
        NEW.with_borrow_mut(|new| {
            new.clear();
            let old = self.place[k];
            let (sched, room) = split_mut(&mut self.buffer.cands[old.range()]);
            new.extend_from_slice(&[Cand::new(0); UNITS]);
            let sched = search(sched, room, new);
            keep(sched, new, 0);
            let b = &mut *self.buffer;
            let start = if new.len() <= old.size as usize {
                b.cands[old.start as usize..][..new.len()].copy_from_slice(new);
                b.holes += old.size as usize - new.len();
                old.start as usize
            } else {
                let need = b.cands.len() + new.len();
                if need > b.cands.capacity() {
                    b.cands.reserve_exact(new.len().max(b.cands.len() / 8 + 8));
                }
                let start = b.cands.len();
                b.cands.extend_from_slice(new);
                b.holes += old.size as usize;
                start
            };
            self.place[k] = Place {
                start: start as u32,
                size: new.len() as u32,
            };
            // laid out again once the holes outgrow the rooms
            if b.holes > 16 && 2 * b.holes > b.cands.len() {
                new.clear();
                for p in self.place.iter_mut() {
                    let start = new.len();
                    new.extend_from_slice(&b.cands[p.range()]);
                    p.start = start as u32;
                }
                b.set(new);
            }
        });
    }
}

/// A kept schedule and its room (none kept: the default schedule, no room).
fn split(kept: &[Cand]) -> (Sched, &[Cand]) {
    if kept.is_empty() {
        (Sched::default(), kept)
    } else {
        (Sched::load(kept), &kept[UNITS..])
    }
}

fn split_mut(kept: &mut [Cand]) -> (Sched, &mut [Cand]) {
    if kept.is_empty() {
        (Sched::default(), kept)
    } else {
        let (h, room) = kept.split_at_mut(UNITS);
        (Sched::load(h), room)
    }
}

/// The schedule kept before the candidates appended to `new` after `start + UNITS`, or
/// nothing kept when there are none; returns the size kept.
fn keep(sched: Sched, new: &mut Vec<Cand>, start: usize) -> usize {
    if new.len() == start + UNITS {
        new.truncate(start);
        0
    } else {
        sched.store(&mut new[start..start + UNITS]);
        new.len() - start
    }
}

impl Buffer {
    /// The rooms laid out in `new`, without holes. The buffer fits them exactly when short,
    /// and gives back room it has too much of ([`trim`]: a chunk's candidates come and go with
    /// the motion; on the 20,000-element ball at 50 us the buffers kept 2.4 MB for 1.7 MB of
    /// rooms without this).
    fn set(&mut self, new: &[Cand]) {
        self.cands.clear();
        if new.len() > self.cands.capacity() {
            self.cands.reserve_exact(new.len());
        }
        self.cands.extend_from_slice(new);
        trim(&mut self.cands);
        self.holes = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn faces(room: &[Cand]) -> Vec<u32> {
        room.iter().map(|c| c.face).collect()
    }

    /// A schedule of the candidates, made from them (so each room's is told apart).
    fn sched_of(room: &mut [Cand]) -> Sched {
        let mut s = Sched::default();
        s.split(room, room.len() as f64 / 2.0);
        s
    }

    /// Everything a node holds, its inline hot candidates with the list, by face.
    fn held(s: Sched, room: &[Cand]) -> Vec<u32> {
        let mut f: Vec<u32> = s.faces(room).collect();
        f.sort_unstable();
        f
    }

    /// Rooms set by whole chunks and node by node (in place, at the end, with the holes laid
    /// out again) hold exactly what each node was given last, with the schedule it was given;
    /// a node given nothing keeps nothing.
    #[test]
    fn rooms_hold_what_each_node_was_given() {
        let n = 10;
        let mut lists = CandLists::new(4, n);
        let mut want: Vec<Vec<u32>> = vec![Vec::new(); n];
        let dues = |f: u32| Cand {
            face: f,
            due: (f % 7) as f32,
        };
        // a full layout: node i gets i candidates
        for (c, mut chunk) in lists.chunks().collect::<Vec<_>>().into_iter().enumerate() {
            chunk.search_all(|k, sched, old, new| {
                assert!(old.is_empty() && sched == Sched::default());
                let start = new.len();
                new.extend((0..(c * 4 + k) as u32).map(dues));
                sched_of(&mut new[start..])
            });
        }
        for (i, w) in want.iter_mut().enumerate() {
            *w = (0..i as u32).collect();
        }
        let check = |lists: &CandLists, want: &[Vec<u32>], what: &str| {
            for (i, (sched, room)) in lists.rooms().enumerate() {
                assert_eq!(held(sched, room), want[i], "{what}: node {i}");
                assert_eq!(room.len(), want[i].len(), "{what}: node {i}");
                // the schedule kept is the one made for these candidates
                let mut all: Vec<Cand> = want[i].iter().map(|&f| dues(f)).collect();
                if !all.is_empty() {
                    assert_eq!(sched.next_due(room), sched_of(&mut all).next_due(&all));
                }
            }
        };
        check(&lists, &want, "laid out");
        // node by node: shorter (in place), longer (at the end), empty, over and over
        for round in 0..40u32 {
            let i = (round as usize * 7) % n;
            let len = ((round * 13) % 11) as usize;
            let given: Vec<u32> = (0..len as u32).map(|f| 100 * round + f).collect();
            let (mut chunk, k) = lists.chunk_of(i);
            let before = want[i].clone();
            chunk.search_one(k, |mut sched, old, new| {
                sched.gather(old);
                let mut had = faces(old);
                had.sort_unstable();
                assert_eq!(had, before);
                let start = new.len();
                new.extend(given.iter().map(|&f| dues(f)));
                sched_of(&mut new[start..])
            });
            want[i] = given;
            check(&lists, &want, &format!("round {round}"));
            // no buffer holds more holes than rooms, beyond the slack
            for b in &lists.buffers {
                assert!(b.holes <= 16 || 2 * b.holes <= b.cands.len(), "{}", b.holes);
            }
        }
        // a change through `with` is kept
        let (mut chunk, k) = lists.chunk_of(3);
        chunk.with(k, |sched, room| sched.renew(room));
        let (sched, room) = lists.get(3);
        assert!(room.is_empty() || sched.next_due(room) == f32::NEG_INFINITY);
        // forgotten: no node has candidates
        let mut forgotten = lists.clone();
        forgotten.forget();
        assert!(forgotten
            .rooms()
            .all(|(s, r)| r.is_empty() && s == Sched::default()));
        // more nodes: the new ones have no candidates
        lists.resize(n + 5);
        assert!(lists
            .rooms()
            .skip(n)
            .all(|(s, r)| r.is_empty() && s == Sched::default()));
        assert_eq!(lists.rooms().count(), n + 5);
    }
}
