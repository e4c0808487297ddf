//! Contact search: which faces each node may touch, by uniform bucket grids.
//!
//! Each face is represented by its axis-aligned bounding box, inflated by how far a node may be
//! from it and still be in contact plus a motion margin (the caller decides the inflation). A
//! node's candidates are the faces whose inflated box contains it. The boxes are sorted into
//! size levels (a factor `LEVEL_RATIO` apart, from the median extent up), and each level has
//! its own grid whose cell size is half the level's largest box extent, so a box covers at most
//! 3 x 3 x 3 cells of its level; every face is listed in each cell of its level its box
//! overlaps (counting sort: linear time, and each cell lists its faces in ascending order), and
//! a node looks only at the faces listed in its own cell of each level. A separate grid lists
//! the nodes of each cell, to find the nodes inside a box (when faces join a surface). Nothing
//! compares all nodes with all faces. The number of cells is capped (a few per face or node),
//! so a domain that grows (fragments flying apart) makes the cells larger, never the memory.
//!
//! The caller rebuilds the candidate lists only when the nodes have moved far enough relative
//! to each other since the last build (see `contact::Contact`); in between, the lists are
//! reused.

use super::cell_lists::{self, Cells};
use crate::math::{f32_down, f32_up, Vec3};
use rayon::prelude::*;

/// An axis-aligned box, bounds included.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (min +inf, max -inf).
    pub fn empty() -> Self {
        Self {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        }
    }
    /// The box of some points.
    pub fn of_points(p: &[Vec3]) -> Self {
        let mut b = Self::empty();
        for q in p {
            b.include(*q);
        }
        b
    }
    /// The box of the finite ones of `n` points `point(q)`, on every thread (minima and
    /// maxima: the same box in any order, but for which zero a tie of -0 and +0 keeps).
    pub fn of_finite(n: usize, point: impl Fn(u32) -> Vec3 + Sync) -> Self {
        (0..n as u32)
            .into_par_iter()
            .with_min_len(PAR_CHUNK)
            .fold(Self::empty, |mut b, q| {
                let p = point(q);
                if p.iter().all(|v| v.is_finite()) {
                    b.include(p);
                }
                b
            })
            .reduce(Self::empty, |a, b| a.join(&b))
    }
    /// The smallest box holding both.
    pub fn join(&self, o: &Self) -> Self {
        Self {
            min: std::array::from_fn(|d| self.min[d].min(o.min[d])),
            max: std::array::from_fn(|d| self.max[d].max(o.max[d])),
        }
    }
    /// Grow the box to hold `q`.
    #[inline]
    pub fn include(&mut self, q: Vec3) {
        for (d, &v) in q.iter().enumerate() {
            self.min[d] = self.min[d].min(v);
            self.max[d] = self.max[d].max(v);
        }
    }
    /// The box grown by `r` on every side.
    #[inline]
    pub fn inflated(&self, r: f64) -> Self {
        Self {
            min: self.min.map(|v| v - r),
            max: self.max.map(|v| v + r),
        }
    }
    /// Whether `p` lies in the box (false for a NaN coordinate). The six comparisons are
    /// combined without short-circuit: no branch to mispredict in the searches' loops, where
    /// about a quarter of the boxes tested hold the node.
    #[inline]
    pub fn contains(&self, p: Vec3) -> bool {
        (self.min[0] <= p[0])
            & (p[0] <= self.max[0])
            & (self.min[1] <= p[1])
            & (p[1] <= self.max[1])
            & (self.min[2] <= p[2])
            & (p[2] <= self.max[2])
    }
    /// Largest edge length.
    #[inline]
    pub fn extent(&self) -> f64 {
        (0..3)
            .map(|d| self.max[d] - self.min[d])
            .fold(0.0, f64::max)
    }
}

/// What the grids read of a box: its corners, whether it holds a point, its largest edge.
pub trait SearchBox {
    fn lo(&self) -> Vec3;
    fn hi(&self) -> Vec3;
    fn holds(&self, p: Vec3) -> bool;
    fn size(&self) -> f64;
}

impl SearchBox for Aabb {
    #[inline]
    fn lo(&self) -> Vec3 {
        self.min
    }
    #[inline]
    fn hi(&self) -> Vec3 {
        self.max
    }
    #[inline]
    fn holds(&self, p: Vec3) -> bool {
        self.contains(p)
    }
    #[inline]
    fn size(&self) -> f64 {
        self.extent()
    }
}

/// A box kept in single precision, rounded outward so that it holds the box it was made from
/// (24 bytes instead of 48): a search box may be larger than asked, never smaller.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct Aabb32 {
    min: [f32; 3],
    max: [f32; 3],
}

impl From<Aabb> for Aabb32 {
    fn from(b: Aabb) -> Self {
        Self {
            min: b.min.map(f32_down),
            max: b.max.map(f32_up),
        }
    }
}

impl Aabb32 {
    /// The same box in double precision.
    #[inline]
    pub fn wide(&self) -> Aabb {
        Aabb {
            min: self.lo(),
            max: self.hi(),
        }
    }
}

impl SearchBox for Aabb32 {
    #[inline]
    fn lo(&self) -> Vec3 {
        self.min.map(f64::from)
    }
    #[inline]
    fn hi(&self) -> Vec3 {
        self.max.map(f64::from)
    }
    #[inline]
    fn holds(&self, p: Vec3) -> bool {
        self.wide().contains(p)
    }
    #[inline]
    fn size(&self) -> f64 {
        self.wide().extent()
    }
}

/// Candidate faces of each node, compressed rows: node `i`'s faces are
/// `list[start[i]..start[i + 1]]`, ascending.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default, PartialEq)]
pub struct Candidates {
    pub start: Vec<u32>,
    pub list: Vec<u32>,
}

impl Candidates {
    /// The candidate faces of node `i`.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.list[self.start[i] as usize..self.start[i + 1] as usize]
    }
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    fn reset(&mut self) {
        self.start.clear();
        self.start.push(0);
        self.list.clear();
    }
}

/// Give back the room of a buffer more than a quarter larger than its contents (keeping an
/// eighth): a grid's levels change size from build to build as the boxes move between them
/// (on the 20,000-element ball one level's items once took 456,576 entries and 261,540 at the
/// end, another 372,672 and 149,170), and their pages, once written, stay resident. Large
/// buffers are served by `mmap` (see the binary's `alloc_tuning`), so the shrink and a later
/// growth move pages by `mremap` rather than copying; this comes only with a full build. The
/// candidate buffers ([`super::cand_lists`]) give back their room by the same rule.
pub(super) fn trim<T>(v: &mut Vec<T>) {
    let len = v.len();
    if v.capacity() > len + len / 4 + 64 {
        v.shrink_to(len + len / 8 + 64);
    }
}

/// Levels of box sizes: a box goes to level k >= 1 when its extent is in
/// `(h0 LEVEL_RATIO^(k-1), h0 LEVEL_RATIO^k]` (h0 the median extent), to level 0 when at most h0.
const LEVEL_RATIO: f64 = 4.0;

/// Boxes larger than `h0 LEVEL_RATIO^MAX_LEVEL` (or of non-finite extent) share the last level.
const MAX_LEVEL: usize = 16;

/// Boxes or points a thread takes at a time in a build.
const PAR_CHUNK: usize = 4096;

/// Faces of a cell whose boxes are tested at a time in [`BucketGrid::faces_at`].
const BLOCK: usize = 64;

/// A level's cells are this many times smaller than its largest box: a box then covers at most
/// 3 x 3 x 3 cells, and a query looks at the faces of a cell whose boxes overlap a region
/// (1 + 1/2)^3 = 3.4 box volumes large instead of 2^3 = 8 with cells as large as the boxes.
const CELLS_PER_BOX: f64 = 2.0;

/// Bucket grids over face boxes, one per size level, and one over points; keeps its buffers
/// between builds.
///
/// A single grid with cells as large as the largest box degenerates when a few boxes are much
/// larger than the rest (a coarse rigid plate under a finely meshed ball: its faces' boxes,
/// inflated by its elements' depth, span the whole ball, and every cell then lists nearly every
/// face). So each box goes to the grid of its size level, whose cells are half as large as
/// that level's largest box; a query looks at its cell in every level. A box lies in one level and
/// is listed in every cell of it that it overlaps, so the result is exact.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub struct BucketGrid {
    levels: Vec<Level>,
    /// Levels `..used` hold this build's boxes.
    used: usize,
    points: Level,
    /// Scratch: level of each box, extents.
    level_of: Vec<u8>,
    ext: Vec<f64>,
    /// Scratch: the boxes of each level, ascending, level after level.
    #[serde(skip)]
    members: Vec<u32>,
    /// Scratch: the cell of each point (its number in the point grid).
    #[serde(skip)]
    cell_of_point: Vec<u32>,
}

/// One uniform grid: the items (box or point indices) of each cell, in ascending order.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
struct Level {
    bounds: Option<Aabb>,
    h: f64,
    dims: [usize; 3],
    /// Compressed rows: cell c's items are `items[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl BucketGrid {
    /// Candidate faces of every point: the faces `f` whose box `boxes[f]` contains `points[i]`
    /// and for which `keep(i, f)` holds (e.g. the node is not one of the face's own nodes),
    /// ascending.
    pub fn candidates<B: SearchBox + Sync>(
        &mut self,
        boxes: &[B],
        points: &[Vec3],
        keep: impl Fn(usize, u32) -> bool,
        out: &mut Candidates,
    ) {
        self.build(boxes, &[]);
        out.reset();
        for (i, &p) in points.iter().enumerate() {
            let start = out.list.len();
            self.faces_at(p, boxes, |f| keep(i, f), |f| out.list.push(f));
            out.list[start..].sort_unstable();
            out.start.push(out.list.len() as u32);
        }
    }

    /// Pass to `push` the faces `f` whose box (`boxes`, those of the build) contains `p` and
    /// for which `keep(f)` holds: ascending within each size level, level after level.
    #[inline]
    pub fn faces_at<B: SearchBox>(
        &self,
        p: Vec3,
        boxes: &[B],
        keep: impl Fn(u32) -> bool,
        mut push: impl FnMut(u32),
    ) {
        for level in &self.levels[..self.used] {
            if let Some(c) = level.cell_of(p) {
                let range = level.start[c] as usize..level.start[c + 1] as usize;
                // the faces whose box holds p are packed into a block without a branch per
                // face, then kept or not, in the same order: on the fracturing 2800 ball a
                // node's cell lists 66 faces of which 18 hold it, and the branch per face
                // made the full builds' searches a third slower
                let mut block = [0u32; BLOCK];
                for items in level.items[range].chunks(BLOCK) {
                    let mut n = 0;
                    for &f in items {
                        block[n] = f;
                        n += boxes[f as usize].holds(p) as usize;
                    }
                    for &f in &block[..n] {
                        if keep(f) {
                            push(f);
                        }
                    }
                }
            }
        }
    }

    /// Append to `out` the points of the build (indices into its `points`, whose positions
    /// `pos(q)` gives) inside box `b`, in cell order.
    pub fn points_in(&self, b: &Aabb, pos: impl Fn(u32) -> Vec3, out: &mut Vec<u32>) {
        let g = &self.points;
        let Some(bounds) = g.bounds.as_ref() else {
            return;
        };
        if g.start.is_empty()
            || (0..3).any(|d| b.max[d] < bounds.min[d] || b.min[d] > bounds.max[d])
        {
            return;
        }
        let (lo, hi) = (g.index(b.min), g.index(b.max));
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    let c = g.flat([i, j, k]);
                    let range = g.start[c] as usize..g.start[c + 1] as usize;
                    for &q in &g.items[range] {
                        if b.contains(pos(q)) {
                            out.push(q);
                        }
                    }
                }
            }
        }
    }

    /// Sort the boxes into size levels and list each in the cells of its level it overlaps;
    /// list each point in its cell of the point grid (cells about as large as the smallest
    /// level's).
    pub fn build<B: SearchBox + Sync>(&mut self, boxes: &[B], points: &[Vec3]) {
        self.build_with(boxes, points.len(), |q| points[q as usize]);
    }

    /// [`BucketGrid::build`] with the points given as `n` positions `point(q)`, so that the
    /// caller need not gather them (the nodes of a side: 1.8 MB on the 20,000-element ball).
    /// Each point is read twice, for the grid's bounds and for its cell (kept, 4 bytes a point,
    /// for the counting sort), both on every thread.
    pub fn build_with<B: SearchBox + Sync>(
        &mut self,
        boxes: &[B],
        n: usize,
        point: impl Fn(u32) -> Vec3 + Sync,
    ) {
        self.used = 0;
        self.points.clear();
        // median extent of the boxes of finite extent
        self.ext.clear();
        self.ext.par_extend(
            boxes
                .par_iter()
                .with_min_len(PAR_CHUNK)
                .map(B::size)
                .filter(|e| e.is_finite()),
        );
        let h0 = if self.ext.is_empty() {
            0.0
        } else {
            let mid = self.ext.len() / 2;
            *self.ext.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        self.level_of.clear();
        self.level_of
            .par_extend(boxes.par_iter().with_min_len(PAR_CHUNK).map(|b| {
                let e = b.size();
                (if e <= h0 {
                    0
                } else if e.is_finite() && h0 > 0.0 {
                    ((e / h0).ln() / LEVEL_RATIO.ln())
                        .ceil()
                        .clamp(1.0, MAX_LEVEL as f64) as usize
                } else {
                    MAX_LEVEL
                }) as u8
            }));
        // the boxes of each level, ascending, one level after the other
        let mut first = [0usize; MAX_LEVEL + 2];
        for &k in &self.level_of {
            first[k as usize + 1] += 1;
        }
        let counts: [usize; MAX_LEVEL + 1] = std::array::from_fn(|k| first[k + 1]);
        for k in 1..first.len() {
            first[k] += first[k - 1];
        }
        self.members.clear();
        self.members.resize(boxes.len(), 0);
        let mut at = first;
        for (f, &k) in self.level_of.iter().enumerate() {
            self.members[at[k as usize]] = f as u32;
            at[k as usize] += 1;
        }
        // levels in use, in order; an empty level is skipped
        let mut slot = [usize::MAX; MAX_LEVEL + 1];
        for (k, &n) in counts.iter().enumerate() {
            if n > 0 {
                slot[k] = self.used;
                self.used += 1;
            }
        }
        if self.levels.len() < self.used {
            self.levels.resize_with(self.used, Level::default);
        }
        // levels this build leaves unused give their room back
        for level in &mut self.levels[self.used..] {
            level.clear();
            level.items.clear();
            trim(&mut level.start);
            trim(&mut level.items);
        }
        let mut h_points = 0.0f64;
        for (k, &n) in counts.iter().enumerate() {
            if n == 0 {
                continue;
            }
            let members = &self.members[first[k]..first[k + 1]];
            // bounds and largest extent: minima and maxima, the same in any order
            let (bounds, h) = members
                .par_iter()
                .with_min_len(PAR_CHUNK)
                .fold(
                    || (Aabb::empty(), 0.0f64),
                    |(mut bounds, h), &f| {
                        let b = &boxes[f as usize];
                        bounds.include(b.lo());
                        bounds.include(b.hi());
                        (bounds, h.max(b.size()))
                    },
                )
                .reduce(
                    || (Aabb::empty(), 0.0),
                    |a, b| (a.0.join(&b.0), a.1.max(b.1)),
                );
            let level = &mut self.levels[slot[k]];
            level.size(bounds, h / CELLS_PER_BOX, (27 * n + 64) as f64);
            level.fill(
                members.len(),
                |i| members[i],
                |f| (boxes[f as usize].lo(), boxes[f as usize].hi()),
            );
            if h_points == 0.0 {
                h_points = level.h;
            }
        }
        trim(&mut self.members);
        if n == 0 {
            // no points: nothing kept of a larger build before
            self.points.items.clear();
            trim(&mut self.points.items);
            self.cell_of_point.clear();
            trim(&mut self.cell_of_point);
            return;
        }
        let bounds = Aabb::of_finite(n, &point);
        if h_points == 0.0 || !h_points.is_finite() {
            // points only: about one per cell
            h_points = bounds.extent() / (n as f64).cbrt();
        }
        self.points.size(bounds, h_points, (n + 64) as f64);
        // each point's cell worked out once, on every thread (a point is read through the
        // nodes' and the slots' numbers: one read of it, not one per pass of the sort)
        let grid = &self.points;
        self.cell_of_point.clear();
        self.cell_of_point.par_extend(
            (0..n as u32)
                .into_par_iter()
                .with_min_len(PAR_CHUNK)
                .map(|q| grid.flat(grid.index(point(q))) as u32),
        );
        let cells = &self.cell_of_point;
        let [nx, ny, _] = self.points.dims;
        self.points.fill_cells(
            n,
            |i| i as u32,
            |q| {
                let c = cells[q as usize] as usize;
                let ijk = [c % nx, (c / nx) % ny, c / (nx * ny)];
                (ijk, ijk)
            },
        );
        trim(&mut self.cell_of_point);
    }

    /// The cell size of the level of the smallest boxes (NaN without boxes).
    pub fn cell_size(&self) -> f64 {
        match self.levels[..self.used].first() {
            Some(level) => level.h,
            None => f64::NAN,
        }
    }

    /// Number of cells over all levels and the point grid.
    #[cfg(test)]
    fn cells(&self) -> usize {
        self.levels[..self.used]
            .iter()
            .chain([&self.points])
            .filter(|l| l.bounds.is_some())
            .map(|l| l.dims.iter().product::<usize>())
            .sum()
    }
}

impl Level {
    fn clear(&mut self) {
        self.bounds = None;
        self.start.clear();
    }

    /// Cells of size h over `bounds` (a point at the origin when empty), made larger until there
    /// are at most `cap` of them (and never more than 2^21 per axis).
    fn size(&mut self, mut bounds: Aabb, mut h: f64, cap: f64) {
        if !(0..3).all(|d| bounds.min[d] <= bounds.max[d]) {
            // nothing finite: one cell at the origin
            bounds = Aabb {
                min: [0.0; 3],
                max: [0.0; 3],
            };
        }
        let ext = bounds.extent();
        if h.is_nan() || h <= 0.0 || !h.is_finite() {
            h = if ext > 0.0 && ext.is_finite() {
                ext
            } else {
                1.0
            };
        }
        let mut dims = [1usize; 3];
        for _ in 0..64 {
            let n: [f64; 3] =
                std::array::from_fn(|d| ((bounds.max[d] - bounds.min[d]) / h).floor() + 1.0);
            let total = n[0] * n[1] * n[2];
            if total <= cap && n.iter().all(|&v| v < 2_097_152.0) {
                dims = n.map(|v| if v.is_finite() { v as usize } else { 1 });
                break;
            }
            h *= (total / cap).cbrt().max(1.01);
        }
        // -0 as +0: the bounds are minima and maxima, and which zero f64::min/max give of a
        // tie is left open, so a -0 could depend on the order the threads joined their parts
        // (the cells would not, the bytes of a restart file would)
        bounds.min = bounds.min.map(|v| v + 0.0);
        bounds.max = bounds.max.map(|v| v + 0.0);
        self.bounds = Some(bounds);
        self.h = h;
        self.dims = dims;
    }

    /// List each item (`len` of them, `item(k)` ascending) in the cells from its `span(item)`
    /// (min and max corner): a counting sort, each cell listing its items ascending, on every
    /// thread where there are many ([`cell_lists::fill`]). Buffers more than a quarter larger
    /// than this build needs are trimmed ([`trim`]).
    fn fill(
        &mut self,
        len: usize,
        item: impl Fn(usize) -> u32 + Sync,
        span: impl Fn(u32) -> (Vec3, Vec3) + Sync,
    ) {
        // the grid's geometry only (the lists are being made)
        let this = Level {
            bounds: self.bounds,
            h: self.h,
            dims: self.dims,
            start: Vec::new(),
            items: Vec::new(),
        };
        let span = |q| {
            let (a, b) = span(q);
            (this.index(a), this.index(b))
        };
        self.fill_cells(len, item, span);
    }

    /// [`Level::fill`] with each item's span given as its lowest and highest cell.
    fn fill_cells(
        &mut self,
        len: usize,
        item: impl Fn(usize) -> u32 + Sync,
        span: impl Fn(u32) -> ([usize; 3], [usize; 3]) + Sync,
    ) {
        let cells = Cells { dims: self.dims };
        let (mut start, mut items) = (
            std::mem::take(&mut self.start),
            std::mem::take(&mut self.items),
        );
        cell_lists::fill(cells, len, item, span, &mut start, &mut items);
        trim(&mut start);
        trim(&mut items);
        (self.start, self.items) = (start, items);
    }

    /// Cell coordinates of a point, clamped to the grid. Monotone in each coordinate, so a
    /// point inside a box falls in one of the box's cells.
    #[inline]
    fn index(&self, p: Vec3) -> [usize; 3] {
        let b = self.bounds.as_ref().expect("grid built");
        // truncation is the floor for t > 0 (and no call of libm's floor, which the baseline
        // x86-64 target makes: 1% of the breaking ball's step)
        std::array::from_fn(|d| {
            let t = (p[d] - b.min[d]) / self.h;
            if t > 0.0 {
                (t as usize).min(self.dims[d] - 1)
            } else {
                0 // also NaN
            }
        })
    }

    #[inline]
    fn flat(&self, c: [usize; 3]) -> usize {
        Cells { dims: self.dims }.flat(c)
    }

    /// The cell holding `p`, or `None` outside the level's bounds (then no box of it holds p).
    #[inline]
    fn cell_of(&self, p: Vec3) -> Option<usize> {
        let b = self.bounds.as_ref()?;
        b.contains(p).then(|| self.flat(self.index(p)))
    }
}

/// The same lists as [`BucketGrid::candidates`] by testing every point against every box: the
/// reference the grid is checked against. Test-only: quadratic.
#[cfg(test)]
pub fn brute_force_candidates(
    boxes: &[Aabb],
    points: &[Vec3],
    keep: impl Fn(usize, u32) -> bool,
    out: &mut Candidates,
) {
    out.reset();
    for (i, &p) in points.iter().enumerate() {
        for (f, b) in boxes.iter().enumerate() {
            if b.contains(p) && keep(i, f as u32) {
                out.list.push(f as u32);
            }
        }
        out.start.push(out.list.len() as u32);
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A tiny deterministic generator (SplitMix64), for reproducible random geometry.
    pub(crate) struct Rng(pub u64);
    impl Rng {
        pub(crate) fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        /// Uniform in [0, 1).
        pub(crate) fn unit(&mut self) -> f64 {
            (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
        }
        pub(crate) fn range(&mut self, a: f64, b: f64) -> f64 {
            a + (b - a) * self.unit()
        }
    }

    /// A soup of random quads (random centre, size spread over two decades, random shape),
    /// their boxes inflated by a random reach, and random points around them (some outside
    /// every box, some exactly on a box corner).
    fn soup(seed: u64, faces: usize, points: usize) -> (Vec<Aabb>, Vec<Vec3>) {
        let mut r = Rng(seed);
        let mut boxes = Vec::with_capacity(faces);
        for _ in 0..faces {
            let c = [r.range(0.0, 10.0), r.range(0.0, 5.0), r.range(-1.0, 1.0)];
            let s = 10f64.powf(r.range(-1.5, 0.5));
            let quad: Vec<Vec3> = (0..4)
                .map(|_| std::array::from_fn(|d| c[d] + s * r.range(-1.0, 1.0)))
                .collect();
            boxes.push(Aabb::of_points(&quad).inflated(r.range(0.0, 0.2)));
        }
        let mut pts: Vec<Vec3> = (0..points)
            .map(|_| [r.range(-1.0, 11.0), r.range(-1.0, 6.0), r.range(-2.0, 2.0)])
            .collect();
        for k in 0..faces.min(points / 10) {
            pts[k] = boxes[k].max; // on a box's corner: bounds are inclusive
        }
        (boxes, pts)
    }

    /// A box kept in single precision holds every point its double-precision box holds,
    /// its corners included, and the grid over such boxes lists every candidate of the
    /// double-precision grid.
    #[test]
    fn single_precision_boxes_hold_their_boxes() {
        let (boxes, mut pts) = soup(17, 400, 3000);
        for b in &boxes {
            pts.push(b.min);
            pts.push([b.min[0], b.max[1], b.min[2]]);
        }
        let small: Vec<Aabb32> = boxes.iter().map(|&b| b.into()).collect();
        for (b, s) in boxes.iter().zip(&small) {
            for &p in &pts {
                assert!(!b.contains(p) || s.holds(p), "{b:?} {s:?} {p:?}");
            }
            assert!(s.size() >= b.extent());
        }
        let (mut a, mut b) = (Candidates::default(), Candidates::default());
        BucketGrid::default().candidates(&boxes, &pts, |_, _| true, &mut a);
        BucketGrid::default().candidates(&small, &pts, |_, _| true, &mut b);
        for i in 0..pts.len() {
            let wide = b.of(i);
            assert!(a.of(i).iter().all(|f| wide.contains(f)), "point {i}");
        }
    }

    /// The bucket grid finds exactly the brute-force candidates (same faces, same order) on
    /// random face soups, with and without a filter, for several seeds and sizes.
    #[test]
    fn bucket_equals_brute_force() {
        let mut grid = BucketGrid::default();
        let (mut a, mut b) = (Candidates::default(), Candidates::default());
        let mut total = 0;
        for seed in 1..=8u64 {
            let faces = 50 + 150 * seed as usize;
            let (boxes, pts) = soup(seed, faces, 2000);
            let keep = |i: usize, f: u32| !(i + f as usize).is_multiple_of(7);
            grid.candidates(&boxes, &pts, keep, &mut a);
            brute_force_candidates(&boxes, &pts, keep, &mut b);
            assert_eq!(a, b, "seed {seed}");
            grid.candidates(&boxes, &pts, |_, _| true, &mut a);
            brute_force_candidates(&boxes, &pts, |_, _| true, &mut b);
            assert_eq!(a, b, "seed {seed}, no filter");
            total += a.list.len();
        }
        // the soups are dense enough that the comparison is not vacuous
        assert!(total > 10_000, "only {total} candidates");
    }

    /// Grids large enough to be built on every thread (a size level and the point grid over
    /// [`cell_lists`]' threshold): on three threads the candidates are the brute-force ones and
    /// those of one thread, and the points in random boxes are the brute-force ones.
    #[test]
    fn grids_built_on_several_threads_are_exact() {
        let (boxes, pts) = soup(31, 40_000, 20_000);
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        let (mut a, mut b, mut c) = (
            Candidates::default(),
            Candidates::default(),
            Candidates::default(),
        );
        let few = &pts[..4000];
        let mut grid = BucketGrid::default();
        pool(3).install(|| grid.candidates(&boxes, few, |_, _| true, &mut a));
        let level0 = grid.levels[0].items.len();
        assert!(level0 >= 2 * 8192, "level 0 lists {level0} entries");
        pool(1).install(|| BucketGrid::default().candidates(&boxes, few, |_, _| true, &mut b));
        brute_force_candidates(&boxes, few, |_, _| true, &mut c);
        assert_eq!(a, c, "3 threads against brute force");
        assert_eq!(a, b, "3 threads against 1");
        assert!(a.list.len() > 100_000, "only {} candidates", a.list.len());
        pool(3).install(|| grid.build(&boxes, &pts));
        let found = points_in_random_boxes(&grid, &pts, 78, 100, 1.0);
        assert!(found > 5000, "{found}");
    }

    /// Far-apart clusters (a domain much larger than the faces) hit the cell cap; the result
    /// is still exact.
    #[test]
    fn sparse_domain_is_capped_and_exact() {
        let (mut boxes, mut pts) = soup(99, 300, 1000);
        let (b2, p2) = soup(100, 300, 1000);
        let shift = |v: Vec3| [v[0] + 1e5, v[1] - 3e4, v[2] + 7e4];
        boxes.extend(b2.iter().map(|b| Aabb {
            min: shift(b.min),
            max: shift(b.max),
        }));
        pts.extend(p2.iter().map(|&p| shift(p)));
        let mut grid = BucketGrid::default();
        let (mut a, mut b) = (Candidates::default(), Candidates::default());
        grid.candidates(&boxes, &pts, |_, _| true, &mut a);
        brute_force_candidates(&boxes, &pts, |_, _| true, &mut b);
        assert_eq!(a, b);
        let cells = grid.cells();
        assert!(cells <= 27 * boxes.len() + 64 * grid.used, "{cells} cells");
    }

    /// The points a box query finds are exactly the points inside the box (brute force), for
    /// random boxes over a face soup's grid.
    #[test]
    fn points_in_box_equals_brute_force() {
        let (boxes, pts) = soup(5, 400, 3000);
        let mut grid = BucketGrid::default();
        grid.build(&boxes, &pts);
        let found = points_in_random_boxes(&grid, &pts, 77, 200, 1.5);
        assert!(found > 1000, "{found}");
    }

    /// `count` random cubes of half-width up to `h_max` over the soups' domain: the grid's
    /// [`BucketGrid::points_in`] finds exactly the points inside each (brute force); returns
    /// how many it found in all.
    fn points_in_random_boxes(
        grid: &BucketGrid,
        pts: &[Vec3],
        seed: u64,
        count: usize,
        h_max: f64,
    ) -> usize {
        let mut r = Rng(seed);
        let mut found = 0;
        for _ in 0..count {
            let c = [r.range(-1.0, 11.0), r.range(-1.0, 6.0), r.range(-2.0, 2.0)];
            let h = r.range(0.0, h_max);
            let b = Aabb {
                min: c.map(|v| v - h),
                max: c.map(|v| v + h),
            };
            let mut got = Vec::new();
            grid.points_in(&b, |q| pts[q as usize], &mut got);
            got.sort_unstable();
            let want: Vec<u32> = (0..pts.len() as u32)
                .filter(|&q| b.contains(pts[q as usize]))
                .collect();
            assert_eq!(got, want);
            found += got.len();
        }
        found
    }

    /// Each cell lists its items in ascending order, and each item in exactly the cells its
    /// span covers (the counting sort of [`Level::fill`]); a build after a larger one trims
    /// the buffers it no longer needs.
    #[test]
    fn cells_list_their_items_ascending_and_once() {
        let (boxes, pts) = soup(8, 500, 2000);
        let mut grid = BucketGrid::default();
        grid.build(&boxes, &pts);
        let check = |l: &Level, span: &dyn Fn(u32) -> (Vec3, Vec3), n: usize| {
            let ncell = l.dims.iter().product::<usize>();
            let mut seen = vec![0usize; n];
            for c in 0..ncell {
                let items = &l.items[l.start[c] as usize..l.start[c + 1] as usize];
                assert!(items.windows(2).all(|w| w[0] < w[1]), "cell {c}: {items:?}");
                for &q in items {
                    seen[q as usize] += 1;
                }
            }
            assert_eq!(l.start[ncell] as usize, l.items.len());
            for (q, &times) in seen.iter().enumerate() {
                let (a, b) = span(q as u32);
                let (lo, hi) = (l.index(a), l.index(b));
                let cells: usize = (0..3).map(|d| hi[d] - lo[d] + 1).product();
                assert!(times == 0 || times == cells, "item {q}: {times} of {cells}");
            }
            seen.iter().sum::<usize>()
        };
        let mut listed = 0;
        for l in &grid.levels[..grid.used] {
            listed += check(
                l,
                &|f| (boxes[f as usize].lo(), boxes[f as usize].hi()),
                boxes.len(),
            );
        }
        assert!(listed >= boxes.len(), "{listed}");
        assert_eq!(
            check(
                &grid.points,
                &|q| (pts[q as usize], pts[q as usize]),
                pts.len()
            ),
            pts.len()
        );
        // a much smaller build gives back the room of the larger one
        let before: usize = grid.levels.iter().map(|l| l.items.capacity()).sum();
        grid.build(&boxes[..50], &pts[..100]);
        let after: usize = grid.levels.iter().map(|l| l.items.capacity()).sum();
        let used: usize = grid.levels[..grid.used].iter().map(|l| l.items.len()).sum();
        assert!(after < before / 2, "{after} of {before}");
        assert!(
            grid.levels[..grid.used]
                .iter()
                .all(|l| l.items.capacity() <= l.items.len() + l.items.len() / 4 + 64),
            "{used}"
        );
    }

    /// A grid of points only (no face joined one side while nodes joined the other) still
    /// finds its points.
    #[test]
    fn points_only_grid() {
        let pts: Vec<Vec3> = (0..50).map(|i| [i as f64 * 0.1, 0.0, 1.0]).collect();
        let mut grid = BucketGrid::default();
        grid.build::<Aabb>(&[], &pts);
        let b = Aabb {
            min: [0.25, -1.0, 0.0],
            max: [0.55, 1.0, 2.0],
        };
        let mut a = Vec::new();
        grid.points_in(&b, |q| pts[q as usize], &mut a);
        a.sort_unstable();
        assert_eq!(a, vec![3, 4, 5]);
        let mut f = Vec::new();
        grid.faces_at::<Aabb>(pts[0], &[], |_| true, |q| f.push(q));
        assert!(f.is_empty());
    }

    #[test]
    fn no_faces_no_candidates() {
        let mut grid = BucketGrid::default();
        let mut a = Candidates::default();
        grid.candidates::<Aabb>(&[], &[[0.0; 3]; 3], |_, _| true, &mut a);
        assert_eq!(a.len(), 3);
        assert!(a.list.is_empty());
    }
}
