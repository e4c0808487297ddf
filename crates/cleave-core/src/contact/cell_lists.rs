//! The items of each cell of a uniform grid, compressed rows, each cell's items ascending: the
//! counting sort of the contact search's grids ([`super::search`]), serial or on every thread.
//!
//! Both ways give the same arrays, bit for bit: the serial sort places the items (given
//! ascending) last to first, counting each cell's end down to its start; the parallel one does
//! the same in slabs of cells, each slab on a thread of its own over the items that reach it
//! ([`fill_par`]). So the lists do not depend on the number of threads. The parallel sort is
//! taken only where there is more than one thread and enough items: on the breaking
//! 20,000-element ball the grids of a full search were 4% of the step on one thread, all of it
//! serial.

use rayon::prelude::*;

/// Fewer items than this are sorted on one thread.
const PAR_MIN_ITEMS: usize = 8192;

/// Items a thread takes at a time.
const ITEM_CHUNK: usize = 2048;

/// Slabs of cells a thread sorts, about (the items crowd some slabs more than others).
const SLABS_PER_THREAD: usize = 2;

/// A uniform grid's cells: `dims` along x, y, z, numbered x fastest.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cells {
    pub dims: [usize; 3],
}

impl Cells {
    pub fn count(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    #[inline]
    pub fn flat(&self, c: [usize; 3]) -> usize {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    /// Call `f` with every cell of the block from cell `lo` to cell `hi` (bounds included),
    /// x fastest.
    #[inline]
    fn each(&self, (lo, hi): ([usize; 3], [usize; 3]), mut f: impl FnMut(usize)) {
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    f(self.flat([i, j, k]));
                }
            }
        }
    }
}

/// List items `item(0), .., item(len - 1)` (ascending) in every cell of the block `span(q)`
/// gives for item q (its lowest and highest cell): afterwards cell c's items are
/// `items[start[c]..start[c + 1]]`, ascending; `start` has one entry a cell and one more.
pub(super) fn fill(
    cells: Cells,
    len: usize,
    item: impl Fn(usize) -> u32 + Sync,
    span: impl Fn(u32) -> ([usize; 3], [usize; 3]) + Sync,
    start: &mut Vec<u32>,
    items: &mut Vec<u32>,
) {
    let ncell = cells.count();
    start.clear();
    start.resize(ncell + 1, 0);
    if len >= PAR_MIN_ITEMS && rayon::current_num_threads() > 1 {
        fill_par(cells, len, item, span, start, items);
    } else {
        fill_serial(cells, len, item, span, start, items);
    }
}

/// The serial counting sort: `start[c]` counts up to the end of cell c's items, and the items,
/// taken last to first, count it down to the start, so no cursor array is needed.
fn fill_serial(
    cells: Cells,
    len: usize,
    item: impl Fn(usize) -> u32,
    span: impl Fn(u32) -> ([usize; 3], [usize; 3]),
    start: &mut [u32],
    items: &mut Vec<u32>,
) {
    let mut total = 0u32;
    for k in 0..len {
        cells.each(span(item(k)), |c| {
            start[c] += 1;
            total += 1;
        });
    }
    for c in 1..start.len() {
        start[c] += start[c - 1];
    }
    items.clear();
    items.resize(total as usize, 0);
    for k in (0..len).rev() {
        let q = item(k);
        cells.each(span(q), |c| {
            start[c] -= 1;
            items[start[c] as usize] = q;
        });
    }
}

/// The same sort on every thread, without atomics: the cells are cut into slabs of whole
/// xy-planes (contiguous cell numbers, so each slab owns a contiguous part of `start` and of
/// `items`), and each slab sorts, as the serial sort does, the items whose span reaches it,
/// over its own cells. Every slab reads every item's planes (12 bytes an item, kept from one
/// pass over the items and dropped at the end: two comparisons an item, against the work of
/// the few that reach its cells), so slabs are only a few per thread. (Atomic counts and
/// places, then a sort of each cell, cost more than the serial sort on two threads.)
fn fill_par(
    cells: Cells,
    len: usize,
    item: impl Fn(usize) -> u32 + Sync,
    span: impl Fn(u32) -> ([usize; 3], [usize; 3]) + Sync,
    start: &mut [u32],
    items: &mut Vec<u32>,
) {
    let mut planes = Vec::with_capacity(len);
    planes.par_extend((0..len).into_par_iter().with_min_len(ITEM_CHUNK).map(|k| {
        let q = item(k);
        let (lo, hi) = span(q);
        Planes {
            q,
            lo: lo[2] as u32,
            hi: hi[2] as u32,
        }
    }));
    let planes: &[Planes] = &planes;
    let plane = cells.dims[0] * cells.dims[1];
    let nz = cells.dims[2];
    let slabs = (SLABS_PER_THREAD * rayon::current_num_threads()).min(nz);
    // slab s: the planes z0(s)..z0(s + 1)
    let z0 = |s: usize| s * nz / slabs;
    let reaches = |p: &&Planes, s: usize| p.hi as usize >= z0(s) && (p.lo as usize) < z0(s + 1);
    // each slab counts its cells' items in its part of `start` (summed up to the end of each
    // cell, as in the serial sort), and returns its number of entries
    let mut parts = split_at(&mut start[..nz * plane], (1..slabs).map(|s| z0(s) * plane));
    let totals: Vec<u32> = parts
        .par_iter_mut()
        .enumerate()
        .map(|(s, part)| {
            let base = z0(s) * plane;
            for p in planes.iter().filter(|p| reaches(p, s)) {
                cells.each(clip(span(p.q), z0(s), z0(s + 1)), |c| part[c - base] += 1);
            }
            let mut run = 0;
            for c in part.iter_mut() {
                run += *c;
                *c = run;
            }
            run
        })
        .collect();
    let mut offsets = Vec::with_capacity(slabs);
    let mut total = 0u32;
    for t in &totals {
        offsets.push(total);
        total += t;
    }
    items.clear();
    items.resize(total as usize, 0);
    let outs = split_at(items, offsets[1..].iter().map(|&o| o as usize));
    parts
        .par_iter_mut()
        .zip(outs)
        .enumerate()
        .for_each(|(s, (part, out))| {
            let base = z0(s) * plane;
            // the items last to first, each cell's end counted down to its start (within the
            // slab's entries), then the slab's offset added
            for p in planes.iter().rev().filter(|p| reaches(p, s)) {
                cells.each(clip(span(p.q), z0(s), z0(s + 1)), |c| {
                    let at = &mut part[c - base];
                    *at -= 1;
                    out[*at as usize] = p.q;
                });
            }
            for c in part.iter_mut() {
                *c += offsets[s];
            }
        });
    start[nz * plane] = total;
}

/// An item and its lowest and highest plane of cells, as the parallel sort keeps them.
struct Planes {
    q: u32,
    lo: u32,
    hi: u32,
}

/// The block of cells `(lo, hi)` within the planes `z0..z1` (which it reaches).
#[inline]
fn clip(
    (mut lo, mut hi): ([usize; 3], [usize; 3]),
    z0: usize,
    z1: usize,
) -> ([usize; 3], [usize; 3]) {
    lo[2] = lo[2].max(z0);
    hi[2] = hi[2].min(z1 - 1);
    (lo, hi)
}

/// `v` cut at the ascending places `at`: one part more than places.
fn split_at<T>(mut v: &mut [T], at: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut parts = Vec::new();
    let mut done = 0;
    for a in at {
        let (head, tail) = v.split_at_mut(a - done);
        parts.push(head);
        v = tail;
        done = a;
    }
    parts.push(v);
    parts
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random blocks of cells (a fixed generator): the parallel sort on three threads gives
    /// the serial sort's arrays, item for item, for a selection of the items (ascending, as
    /// the grids give them) and for all.
    #[test]
    fn parallel_sort_gives_the_serial_lists() {
        // more planes than slabs, fewer (3 threads: 6 slabs), one
        for dims in [[23, 17, 11], [9, 40, 4], [60, 50, 1]] {
            sort_both_ways(Cells { dims });
        }
    }

    fn sort_both_ways(cells: Cells) {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = |m: usize| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % m as u64) as usize
        };
        let n = 40_000;
        let spans: Vec<([usize; 3], [usize; 3])> = (0..n)
            .map(|_| {
                let lo: [usize; 3] = std::array::from_fn(|d| rnd(cells.dims[d]));
                let hi = std::array::from_fn(|d| (lo[d] + rnd(3)).min(cells.dims[d] - 1));
                (lo, hi)
            })
            .collect();
        let some: Vec<u32> = (0..n as u32).filter(|q| q % 3 != 1).collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let span = |q: u32| spans[q as usize];
        let check = |len: usize, pick: &(dyn Fn(usize) -> u32 + Sync)| {
            assert!(len >= PAR_MIN_ITEMS);
            let (mut s1, mut i1, mut s2, mut i2) = (vec![], vec![], vec![], vec![]);
            fill_serial_for_test(cells, len, pick, span, &mut s1, &mut i1);
            pool.install(|| fill(cells, len, pick, span, &mut s2, &mut i2));
            assert_eq!(s1, s2, "starts");
            assert_eq!(i1, i2, "items");
            // every cell's items ascending, and each item in every cell of its span
            for c in 0..cells.count() {
                let l = &i1[s1[c] as usize..s1[c + 1] as usize];
                assert!(l.windows(2).all(|w| w[0] < w[1]));
            }
            let listed: usize = (0..len)
                .map(|k| {
                    let (lo, hi) = span(pick(k));
                    (0..3).map(|d| hi[d] - lo[d] + 1).product::<usize>()
                })
                .sum();
            assert_eq!(i1.len(), listed);
        };
        check(some.len(), &|k| some[k]);
        check(n, &|k| k as u32);
    }

    fn fill_serial_for_test(
        cells: Cells,
        len: usize,
        item: impl Fn(usize) -> u32,
        span: impl Fn(u32) -> ([usize; 3], [usize; 3]),
        start: &mut Vec<u32>,
        items: &mut Vec<u32>,
    ) {
        start.clear();
        start.resize(cells.count() + 1, 0);
        fill_serial(cells, len, item, span, start, items);
    }
}
