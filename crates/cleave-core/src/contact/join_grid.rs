//! The faces and nodes that joined a pass's sides since its last full build, in a uniform grid
//! that takes each one as it joins: an incremental search adds those of its step, and no
//! search sorts them all again (a bucket grid made again at every incremental search cost
//! 0.34 ms a search on the breaking 160,000-element ball, on one thread whatever the threads).
//!
//! Cells of size `h` (the full build's smallest level's, so a face box spans about 2 to 3
//! cells a side) are kept in an open-addressing table keyed by their integer coordinates; each
//! cell lists its items (faces or nodes, numbered from the first that joined) in the order
//! they joined, in one array of linked entries. A face box spanning more than [`SPAN`] cells
//! along an axis, or not finite, goes to a list every query reads. Queries give the same
//! items as a look at every item: the faces whose box holds a point (each box is in every
//! cell it overlaps, so in the point's), the nodes inside a box (each node in its cell). Their
//! order is the joining order within a cell, which no result depends on (a node's nearest face
//! is the same whatever order its candidates are tested in). Plain integer arithmetic on the
//! cells: the same lists on every machine and number of threads.

use super::search::{Aabb, SearchBox};
use crate::math::Vec3;

/// A face box spanning more cells than this along an axis goes to the list every query reads.
const SPAN: i64 = 4;

/// No entry or cell.
const NONE: u32 = u32::MAX;

/// Items that joined since the last full build, by cell (module docs).
#[derive(Clone, Debug, Default)]
pub(super) struct JoinGrid {
    /// The cell size (0 until [`JoinGrid::reset`]; then the items are all in the wide list).
    h: f64,
    faces: Cells,
    nodes: Cells,
    /// Faces whose box spans too many cells, or is not finite: every query reads them.
    wide: Vec<u32>,
}

/// One kind of item by cell: the table of cells (key, first and last entry), the entries
/// (item, next entry of its cell), and how many items were added.
#[derive(Clone, Debug, Default)]
struct Cells {
    table: Vec<([i64; 3], u32, u32)>,
    used: usize,
    entries: Vec<(u32, u32)>,
    added: usize,
}

impl Cells {
    fn clear(&mut self) {
        self.table.clear();
        self.used = 0;
        self.entries.clear();
        self.added = 0;
    }

    /// The slot of cell `key` in the table (where it is, or where it would go).
    fn slot(&self, key: [i64; 3]) -> usize {
        let mask = self.table.len() - 1;
        let mut h = (key[0] as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (key[1] as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            ^ (key[2] as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
        h ^= h >> 29;
        let mut s = h as usize & mask;
        while self.table[s].1 != NONE && self.table[s].0 != key {
            s = (s + 1) & mask;
        }
        s
    }

    /// Append `item` to cell `key`'s list.
    fn push(&mut self, key: [i64; 3], item: u32) {
        if 2 * (self.used + 1) > self.table.len() {
            self.grow();
        }
        let e = self.entries.len() as u32;
        self.entries.push((item, NONE));
        let s = self.slot(key);
        let cell = &mut self.table[s];
        if cell.1 == NONE {
            *cell = (key, e, e);
            self.used += 1;
        } else {
            self.entries[cell.2 as usize].1 = e;
            cell.2 = e;
        }
    }

    /// A table twice as large (at least 64 slots), the cells placed again.
    fn grow(&mut self) {
        let old = std::mem::take(&mut self.table);
        self.table = vec![([0; 3], NONE, NONE); (2 * old.len()).max(64)];
        for cell in old.into_iter().filter(|c| c.1 != NONE) {
            let s = self.slot(cell.0);
            self.table[s] = cell;
        }
    }

    /// The items of cell `key`, in the order they were added.
    fn items(&self, key: [i64; 3]) -> impl Iterator<Item = u32> + '_ {
        let first = if self.table.is_empty() {
            NONE
        } else {
            self.table[self.slot(key)].1
        };
        std::iter::successors((first != NONE).then_some(first), |&e| {
            let next = self.entries[e as usize].1;
            (next != NONE).then_some(next)
        })
        .map(|e| self.entries[e as usize].0)
    }
}

/// A cell size `h`, or 0 (no cells) when it is not a positive finite one.
fn usable(h: f64) -> f64 {
    if h.is_finite() && h > 0.0 {
        h
    } else {
        0.0
    }
}

impl JoinGrid {
    /// Empty, with cells of size `h` (none fit: every face to the wide list, every node found
    /// by a look at each).
    pub fn reset(&mut self, h: f64) {
        self.h = usable(h);
        self.faces.clear();
        self.nodes.clear();
        self.wide.clear();
    }

    /// Cells of size `h` from now on: when they are not (a grid read from a restart file,
    /// which keeps none), emptied, so that the next additions add every item.
    pub fn keep_cells(&mut self, h: f64) {
        let h = usable(h);
        if self.h != h {
            self.reset(h);
        }
    }

    /// The cell of coordinates `p`, `None` beyond the range of the cells' integers (or with
    /// no cell size).
    fn cell(&self, p: Vec3) -> Option<[i64; 3]> {
        if self.h == 0.0 {
            return None;
        }
        let c = p.map(|v| (v / self.h).floor());
        c.iter()
            .all(|v| v.abs() < 1e15)
            .then(|| c.map(|v| v as i64))
    }

    /// The faces that joined, `boxes[k]` being face k's (from the first that joined): those
    /// not yet added are added (`boxes` only grows between resets).
    pub fn add_faces<B: SearchBox>(&mut self, boxes: &[B]) {
        for (k, b) in boxes.iter().enumerate().skip(self.faces.added) {
            let k = k as u32;
            match (self.cell(b.lo()), self.cell(b.hi())) {
                (Some(lo), Some(hi)) if (0..3).all(|d| hi[d] - lo[d] < SPAN) => {
                    for i in lo[0]..=hi[0] {
                        for j in lo[1]..=hi[1] {
                            for l in lo[2]..=hi[2] {
                                self.faces.push([i, j, l], k);
                            }
                        }
                    }
                }
                _ => self.wide.push(k),
            }
        }
        self.faces.added = boxes.len();
    }

    /// The nodes that joined, `n` of them, node q at `point(q)`: those not yet added are
    /// added (the count only grows between resets; a node's point does not change).
    pub fn add_nodes(&mut self, n: usize, point: impl Fn(u32) -> Vec3) {
        for q in self.nodes.added..n {
            let q = q as u32;
            match self.cell(point(q)) {
                Some(c) => self.nodes.push(c, q),
                // (no cell size, or beyond the cells: read by every box query)
                None => self.nodes.push([i64::MIN; 3], q),
            }
        }
        self.nodes.added = self.nodes.added.max(n);
    }

    /// `push` each face whose box (`boxes`, as added) holds `p` and that `keep` keeps.
    pub fn faces_at<B: SearchBox>(
        &self,
        p: Vec3,
        boxes: &[B],
        keep: impl Fn(u32) -> bool,
        mut push: impl FnMut(u32),
    ) {
        let cell = self.cell(p).map(|c| self.faces.items(c));
        for f in cell.into_iter().flatten().chain(self.wide.iter().copied()) {
            if boxes[f as usize].holds(p) && keep(f) {
                push(f);
            }
        }
    }

    /// The nodes inside box `b` (node q at `pos(q)`), appended to `out`.
    pub fn points_in(&self, b: &Aabb, pos: impl Fn(u32) -> Vec3, out: &mut Vec<u32>) {
        let mut inside = |q: u32| {
            if b.contains(pos(q)) {
                out.push(q);
            }
        };
        // the nodes with no cell, then the cells the box overlaps, or every node
        self.nodes.items([i64::MIN; 3]).for_each(&mut inside);
        match (self.cell(b.min), self.cell(b.max)) {
            (Some(lo), Some(hi)) if (0..3).all(|d| hi[d] - lo[d] < 2 * SPAN) => {
                for i in lo[0]..=hi[0] {
                    for j in lo[1]..=hi[1] {
                        for l in lo[2]..=hi[2] {
                            self.nodes.items([i, j, l]).for_each(&mut inside);
                        }
                    }
                }
            }
            _ => {
                for &(c, ..) in self.nodes.table.iter().filter(|c| c.1 != NONE) {
                    if c != [i64::MIN; 3] {
                        self.nodes.items(c).for_each(&mut inside);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random boxes and points added in batches: every query gives the items a look at each
    /// gives (as sets), with boxes of every size (some spanning many cells, one not finite)
    /// and query boxes small and large.
    #[test]
    fn queries_give_what_a_look_at_each_gives() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut boxes = vec![];
        let mut points: Vec<Vec3> = vec![];
        let mut g = JoinGrid::default();
        g.reset(0.3);
        for batch in 0..6 {
            for k in 0..150 {
                let c: Vec3 = std::array::from_fn(|_| 10.0 * rnd() - 5.0);
                let r = if k % 31 == 0 { 3.0 } else { 0.4 * rnd() };
                boxes.push(Aabb {
                    min: c.map(|v| v - r),
                    max: c.map(|v| v + r),
                });
                points.push(std::array::from_fn(|_| 10.0 * rnd() - 5.0));
            }
            if batch == 2 {
                boxes.push(Aabb {
                    min: [f64::NEG_INFINITY; 3],
                    max: [f64::INFINITY; 3],
                });
            }
            g.add_faces(&boxes);
            g.add_nodes(points.len(), |q| points[q as usize]);
            for _ in 0..200 {
                let p: Vec3 = std::array::from_fn(|_| 11.0 * rnd() - 5.5);
                let mut found = vec![];
                g.faces_at(p, &boxes, |f| f % 7 != 3, |f| found.push(f));
                found.sort_unstable();
                let all: Vec<u32> = (0..boxes.len() as u32)
                    .filter(|&f| boxes[f as usize].contains(p) && f % 7 != 3)
                    .collect();
                assert_eq!(found, all);
                let r = if rnd() < 0.1 { 4.0 } else { 0.5 * rnd() };
                let b = Aabb {
                    min: p.map(|v| v - r),
                    max: p.map(|v| v + r),
                };
                let mut inside = vec![];
                g.points_in(&b, |q| points[q as usize], &mut inside);
                inside.sort_unstable();
                let all: Vec<u32> = (0..points.len() as u32)
                    .filter(|&q| b.contains(points[q as usize]))
                    .collect();
                assert_eq!(inside, all);
            }
        }
        // without a cell size: every face wide, every node looked at
        g.reset(f64::NAN);
        g.add_faces(&boxes[..40]);
        g.add_nodes(40, |q| points[q as usize]);
        let mut found = vec![];
        g.faces_at(points[3], &boxes, |_| true, |f| found.push(f));
        let all: Vec<u32> = (0..40)
            .filter(|&f| boxes[f as usize].contains(points[3]))
            .collect();
        assert_eq!(found, all);
    }
}
