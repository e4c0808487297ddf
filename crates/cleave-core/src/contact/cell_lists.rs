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
/// over its own cells. The items are first spread to the slabs in chunks, on every thread:
/// each chunk works out its items' spans once and lists them by slab (a counting sort, each
/// slab's ascending), so a slab reads only the items that reach it, chunk after chunk, and the
/// work grows with the items, not with items times slabs. (Atomic counts and places, then a
/// sort of each cell, cost more than the serial sort on two threads.)
fn fill_par(
    cells: Cells,
    len: usize,
    item: impl Fn(usize) -> u32 + Sync,
    span: impl Fn(u32) -> ([usize; 3], [usize; 3]) + Sync,
    start: &mut [u32],
    items: &mut Vec<u32>,
) {
    let plane = cells.dims[0] * cells.dims[1];
    let nz = cells.dims[2];
    let slabs = (SLABS_PER_THREAD * rayon::current_num_threads()).min(nz);
    // slab s: the planes z0(s)..z0(s + 1)
    let z0 = |s: usize| s * nz / slabs;
    let slab_of: Vec<u32> = (0..slabs)
        .flat_map(|s| std::iter::repeat_n(s as u32, z0(s + 1) - z0(s)))
        .collect();
    let chunks: Vec<Spread> = (0..len.div_ceil(ITEM_CHUNK))
        .into_par_iter()
        .map(|c| {
            let range = c * ITEM_CHUNK..len.min((c + 1) * ITEM_CHUNK);
            Spread::of(range, &item, &span, &slab_of, slabs)
        })
        .collect();
    // a slab's items, chunk after chunk, ascending, or the other way
    let reaching = |s: usize| chunks.iter().flat_map(move |c| c.items_of(s));
    let reaching_rev = |s: usize| chunks.iter().rev().flat_map(move |c| c.items_of(s).rev());
    // each slab counts its cells' items in its part of `start` (summed up to the end of each
    // cell, as in the serial sort), and returns its number of entries
    let mut parts = split_at(&mut start[..nz * plane], (1..slabs).map(|s| z0(s) * plane));
    let totals: Vec<u32> = parts
        .par_iter_mut()
        .enumerate()
        .map(|(s, part)| {
            let base = z0(s) * plane;
            for (_, lo, hi) in reaching(s) {
                cells.each(clip((lo, hi), z0(s), z0(s + 1)), |c| part[c - base] += 1);
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
            for (q, lo, hi) in reaching_rev(s) {
                cells.each(clip((lo, hi), z0(s), z0(s + 1)), |c| {
                    let at = &mut part[c - base];
                    *at -= 1;
                    out[*at as usize] = q;
                });
            }
            for c in part.iter_mut() {
                *c += offsets[s];
            }
        });
    start[nz * plane] = total;
}

/// A chunk of the items spread to the slabs ([`fill_par`]): each item's number and span (its
/// lowest and highest cell), and the places of those that reach each slab (`at[s]..at[s + 1]`
/// of `refs`, ascending).
struct Spread {
    spans: Vec<(u32, [u32; 3], [u32; 3])>,
    at: Vec<u32>,
    refs: Vec<u32>,
}

impl Spread {
    /// Items `item(k)` for k in `range` spread to the `slabs` slabs (`slab_of` each plane).
    fn of(
        range: std::ops::Range<usize>,
        item: impl Fn(usize) -> u32,
        span: impl Fn(u32) -> ([usize; 3], [usize; 3]),
        slab_of: &[u32],
        slabs: usize,
    ) -> Self {
        let spans: Vec<(u32, [u32; 3], [u32; 3])> = range
            .map(|k| {
                let q = item(k);
                let (lo, hi) = span(q);
                (q, lo.map(|v| v as u32), hi.map(|v| v as u32))
            })
            .collect();
        let reach = |(_, lo, hi): &(u32, [u32; 3], [u32; 3])| {
            slab_of[lo[2] as usize] as usize..=slab_of[hi[2] as usize] as usize
        };
        let mut at = vec![0u32; slabs + 1];
        for sp in &spans {
            for s in reach(sp) {
                at[s + 1] += 1;
            }
        }
        for s in 0..slabs {
            at[s + 1] += at[s];
        }
        let mut next = at.clone();
        let mut refs = vec![0u32; at[slabs] as usize];
        for (i, sp) in spans.iter().enumerate() {
            for s in reach(sp) {
                refs[next[s] as usize] = i as u32;
                next[s] += 1;
            }
        }
        Spread { spans, at, refs }
    }

    /// The items of this chunk that reach slab `s`, ascending: each one's number and span.
    fn items_of(
        &self,
        s: usize,
    ) -> impl DoubleEndedIterator<Item = (u32, [usize; 3], [usize; 3])> + '_ {
        self.refs[self.at[s] as usize..self.at[s + 1] as usize]
            .iter()
            .map(|&i| {
                let (q, lo, hi) = self.spans[i as usize];
                (q, lo.map(|v| v as usize), hi.map(|v| v as usize))
            })
    }
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

    /// `fill_par` itself (below the item threshold too) against the serial sort: tall spans
    /// reaching many or all slabs, planes many more than slabs, empty spans (lo > hi), and
    /// lengths 0, 1 and around multiples of ITEM_CHUNK, on 2 to 16 threads.
    #[test]
    fn fill_par_edge_cases() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = move |m: usize| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % m as u64) as usize
        };
        for dims in [[3, 2, 100], [1, 1, 37], [5, 4, 3], [1, 1, 1], [2, 3, 16]] {
            let cells = Cells { dims };
            let n = 3 * ITEM_CHUNK + 5;
            let spans: Vec<([usize; 3], [usize; 3])> = (0..2 * n)
                .map(|k| {
                    let lo: [usize; 3] = std::array::from_fn(|d| rnd(dims[d]));
                    let mut hi: [usize; 3] = std::array::from_fn(|d| {
                        let w = if d == 2 { rnd(dims[2] + 1) } else { rnd(2) };
                        (lo[d] + w).min(dims[d] - 1)
                    });
                    match k % 17 {
                        0 => hi[2] = dims[2] - 1,            // to the top
                        1 if lo[2] > 0 => hi[2] = lo[2] - 1, // empty in z
                        2 if lo[0] > 0 => hi[0] = lo[0] - 1, // empty in x
                        _ => {}
                    }
                    let lo = if k % 23 == 0 { [lo[0], lo[1], 0] } else { lo };
                    (lo, hi)
                })
                .collect();
            let span = |q: u32| spans[q as usize];
            for threads in [2, 3, 4, 5, 7, 8, 16] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                for len in [
                    0,
                    1,
                    2,
                    ITEM_CHUNK - 1,
                    ITEM_CHUNK,
                    ITEM_CHUNK + 1,
                    2 * ITEM_CHUNK,
                    n,
                ] {
                    // a selection of the items, ascending
                    let pick = |k: usize| (k + k / 3) as u32;
                    let len = len.min(n);
                    let (mut s1, mut i1) = (vec![], vec![]);
                    fill_serial_for_test(cells, len, pick, span, &mut s1, &mut i1);
                    let (mut s2, mut i2) = (vec![0u32; cells.count() + 1], vec![7u32; 3]);
                    pool.install(|| fill_par(cells, len, pick, span, &mut s2, &mut i2));
                    assert_eq!(s1, s2, "starts {dims:?} {threads} {len}");
                    assert_eq!(i1, i2, "items {dims:?} {threads} {len}");
                }
            }
        }
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
