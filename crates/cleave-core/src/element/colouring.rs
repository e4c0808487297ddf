//! Colours of element chunks, so the element pass can add its corner forces straight into the
//! nodal forces on all cores without a race and without a per-element force buffer.
//!
//! The elements are cut into chunks of `size` consecutive elements. Two chunks that share a
//! node get different colours (greedy colouring, chunks in ascending order, each taking, of the
//! colours none of its neighbours has, the one with the fewest chunks so far, the lowest of
//! equals; a new colour only when every colour is taken). Taking the least used colour keeps
//! the colours about equal in size: the plain greedy rule (the lowest free colour) left the
//! 20,000-element ball's O-grid with 11 colours of 55 down to 1 chunk, and the last, small
//! colours ran on one core. The element pass runs the colours one after the
//! other; the chunks of one colour run in parallel, each adding its elements' corner forces in
//! element order. A node then receives its corner forces in a fixed order (by colour, then
//! element) whatever the number of threads: the sums are bit-identical on any thread count.
//!
//! The chunk size is the largest of [`SIZES`] that leaves at least [`MIN_PER_COLOUR`] chunks per
//! colour on average: decks numbered in space order (meshers, the examples) keep 256-element
//! chunks and 2 to 4 colours; a deck numbered at random, whose 256-element chunks all touch
//! each other, falls back to smaller chunks down to single elements (at most one colour more
//! than the most elements around one element). It depends on the mesh only, never on the
//! number of threads.
//!
//! Memory: 4 bytes per chunk (the per-element force buffer it replaces took 192 bytes per
//! element, and its node-to-corner index 4 more per corner).
//!
//! Classes: a split model's elements share no node, yet the element pass adds a tied copy's
//! corner forces into its coincident set's representative, another copy of the same deck node
//! ([`crate::separation::coincident`]). [`Colouring::with_classes`] colours the chunks by a
//! class of each node instead (the representative of the node's set with every interface
//! intact: the deck node, in effect), so two chunks of a colour share no deck node and write
//! no representative in common. The colours are then those of the mesh before it was split.
//!
//! Soundness: the element pass writes the nodes through [`Scatter`] from several threads at
//! once, which is race-free only because no two chunks of a colour write the same node. A
//! [`Colouring`] keeps the connectivity and classes it was made for, its fields are private,
//! and the solver checks it with [`Colouring::is_proper`] once and reads the elements' nodes
//! from it, so the colours and the nodes written cannot disagree; with classes, the solver
//! also checks that each node it writes for a node n is of n's class
//! ([`Colouring::same_class`]) whenever the representatives change.

use crate::math::Vec3;

/// Chunk sizes tried, largest first.
pub const SIZES: [usize; 5] = [256, 64, 16, 4, 1];

/// Chunks per colour, on average, a chunk size must leave (so 2 threads share each colour).
pub const MIN_PER_COLOUR: usize = 8;

/// The chunks of a mesh grouped by colour, with the mesh's connectivity.
#[derive(Clone, Debug, PartialEq)]
pub struct Colouring<'m> {
    conn: &'m [[u32; 8]],
    /// Class of each node (`None`: each node its own class).
    class: Option<Vec<u32>>,
    /// Elements per chunk (the last chunk may be shorter).
    size: usize,
    /// Colour of each chunk.
    colour: Vec<u32>,
    /// Number of colours.
    colours: usize,
}

impl<'m> Colouring<'m> {
    /// The colouring of the elements `conn` over `num_nodes` nodes (see the module docs).
    pub fn new(conn: &'m [[u32; 8]], num_nodes: usize) -> Self {
        Self::best(conn, num_nodes, None)
    }

    /// The colouring of the elements `conn` over `num_nodes` nodes, two chunks clashing when
    /// they hold nodes of one class (`class[n] < num_nodes`, one entry per node).
    pub fn with_classes(conn: &'m [[u32; 8]], num_nodes: usize, class: Vec<u32>) -> Self {
        assert_eq!(class.len(), num_nodes, "one class per node");
        Self::best(conn, num_nodes, Some(class))
    }

    fn best(conn: &'m [[u32; 8]], num_nodes: usize, class: Option<Vec<u32>>) -> Self {
        let mut best = Self::sized(conn, num_nodes, SIZES[0], class.as_deref());
        for &size in &SIZES[1..] {
            if best.chunks() >= MIN_PER_COLOUR * best.colours {
                break;
            }
            let next = Self::sized(conn, num_nodes, size, class.as_deref());
            // a smaller chunk only when it shares the work better
            if next.chunks() * best.colours > best.chunks() * next.colours {
                best = next;
            }
        }
        best.class = class;
        best
    }

    /// Whether nodes `a` and `b` are of one class.
    #[inline]
    pub fn same_class(&self, a: u32, b: u32) -> bool {
        match &self.class {
            None => a == b,
            Some(c) => c[a as usize] == c[b as usize],
        }
    }

    /// Greedy colouring of the chunks of `size` elements.
    pub fn with_size(conn: &'m [[u32; 8]], num_nodes: usize, size: usize) -> Self {
        Self::sized(conn, num_nodes, size, None)
    }

    /// Greedy colouring of the chunks of `size` elements by the nodes' classes (the classes
    /// themselves are not kept).
    fn sized(conn: &'m [[u32; 8]], num_nodes: usize, size: usize, class: Option<&[u32]>) -> Self {
        let size = size.max(1);
        let chunks = conn.len().div_ceil(size);
        // class -> chunks touching it (CSR, each chunk once per class)
        let mut start = vec![0u32; num_nodes + 1];
        let mut last = vec![u32::MAX; num_nodes];
        let key = |n: u32| class.map_or(n, |c| c[n as usize]);
        let each = |f: &mut dyn FnMut(u32, u32)| {
            for (c, elems) in conn.chunks(size).enumerate() {
                for &n in elems.iter().flatten() {
                    f(key(n), c as u32);
                }
            }
        };
        each(&mut |n, c| {
            if last[n as usize] != c {
                last[n as usize] = c;
                start[n as usize + 1] += 1;
            }
        });
        for i in 0..num_nodes {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut touching = vec![0u32; start[num_nodes] as usize];
        last.iter_mut().for_each(|l| *l = u32::MAX);
        each(&mut |n, c| {
            if last[n as usize] != c {
                last[n as usize] = c;
                touching[fill[n as usize] as usize] = c;
                fill[n as usize] += 1;
            }
        });
        // greedy: each chunk the lowest colour no chunk it touches has yet
        let mut colour = vec![u32::MAX; chunks];
        let mut taken: Vec<u32> = Vec::new(); // stamp: the chunk that found the colour taken
        let mut count: Vec<usize> = Vec::new(); // chunks of each colour
        let mut colours = 0;
        for (c, elems) in conn.chunks(size).enumerate() {
            for &n in elems.iter().flatten() {
                let n = key(n) as usize;
                for &d in &touching[start[n] as usize..start[n + 1] as usize] {
                    let k = colour[d as usize];
                    if k != u32::MAX {
                        taken[k as usize] = c as u32;
                    }
                }
            }
            // of the free colours the least used (ties: the lowest), so the colours come out
            // about equal in size; a new colour only when none is free
            let k = (0..taken.len())
                .filter(|&k| taken[k] != c as u32)
                .min_by_key(|&k| (count[k], k))
                .unwrap_or(taken.len());
            if k == taken.len() {
                taken.push(u32::MAX);
                count.push(0);
            }
            count[k] += 1;
            colour[c] = k as u32;
            colours = colours.max(k + 1);
        }
        Self {
            conn,
            class: None,
            size,
            colour,
            colours,
        }
    }

    /// The elements' nodes.
    pub fn conn(&self) -> &'m [[u32; 8]] {
        self.conn
    }

    /// Elements per chunk (the last chunk may be shorter).
    pub fn size(&self) -> usize {
        self.size
    }

    /// Number of colours.
    pub fn colours(&self) -> usize {
        self.colours
    }

    /// Colour of each chunk.
    pub fn colour(&self) -> &[u32] {
        &self.colour
    }

    /// Number of chunks.
    pub fn chunks(&self) -> usize {
        self.colour.len()
    }

    /// Whether every chunk has a colour and no two chunks of one colour share a node, or with
    /// classes a class (what the element pass relies on), the nodes and classes being below
    /// `num_nodes`.
    pub fn is_proper(&self, num_nodes: usize) -> bool {
        let conn = self.conn;
        if self.size == 0
            || self.colour.len() != conn.len().div_ceil(self.size)
            || self.colour.iter().any(|&k| k as usize >= self.colours)
            || conn.iter().flatten().any(|&n| n as usize >= num_nodes)
        {
            return false;
        }
        if let Some(c) = &self.class {
            if c.len() != num_nodes || c.iter().any(|&k| k as usize >= num_nodes) {
                return false;
            }
        }
        let key = |n: u32| self.class.as_ref().map_or(n, |c| c[n as usize]);
        // the last chunk that touched each node: a chunk of the same colour is a clash
        let mut seen = vec![u32::MAX; num_nodes];
        for k in 0..self.colours as u32 {
            for (c, elems) in conn.chunks(self.size).enumerate() {
                if self.colour[c] != k {
                    continue;
                }
                for &n in elems.iter().flatten() {
                    let slot = &mut seen[key(n) as usize];
                    if *slot != u32::MAX && *slot != c as u32 && self.colour[*slot as usize] == k {
                        return false;
                    }
                    *slot = c as u32;
                }
            }
        }
        true
    }
}

/// The nodal forces, shared by the chunks of one colour while they add their corner forces.
///
/// [`Scatter::add`] writes node i through a raw pointer; the mutable borrow of the slice keeps
/// everything else off it meanwhile. Crate-private: only the element pass uses it, from the
/// chunks of one colour at a time of a proper [`Colouring`] (module docs).
pub(crate) struct Scatter<'a> {
    ptr: *mut Vec3,
    len: usize,
    _borrow: std::marker::PhantomData<&'a mut [Vec3]>,
}

// SAFETY: see the type's docs: threads write disjoint nodes.
unsafe impl Sync for Scatter<'_> {}

impl<'a> Scatter<'a> {
    pub(crate) fn new(f: &'a mut [Vec3]) -> Self {
        Self {
            ptr: f.as_mut_ptr(),
            len: f.len(),
            _borrow: std::marker::PhantomData,
        }
    }

    /// `f[i] += g` (the index is bounds checked).
    ///
    /// # Safety
    /// No other thread may add to node i at the same time: call it only from the chunks of
    /// one colour at a time of a proper [`Colouring`].
    #[inline]
    pub unsafe fn add(&self, i: u32, g: Vec3) {
        let i = i as usize;
        assert!(i < self.len, "node {i} out of range");
        // SAFETY: in bounds; no other thread touches node i meanwhile (the caller's contract)
        unsafe {
            let p = self.ptr.add(i);
            *p = crate::math::add(*p, g);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::search::tests::Rng;

    /// Connectivity of an n x n x n block of hexahedra, numbered x fastest, and its node count.
    fn block(n: usize) -> (Vec<[u32; 8]>, usize) {
        let mesh = crate::mesh::BoxMesh::new([n; 3], [1.0; 3]);
        (mesh.conn, mesh.x.len())
    }

    #[test]
    fn a_block_in_order_keeps_big_chunks_and_few_colours() {
        let (conn, nn) = block(30); // 27,000 elements, 106 chunks of 256
        let c = Colouring::new(&conn, nn);
        assert_eq!(c.size(), 256);
        assert!(c.is_proper(nn));
        // a chunk is about 8.5 rows of a 30 x 30 layer: it touches the chunks next to it in
        // its layer and those under and over it (3.5 chunks away)
        assert!(c.colours <= 4, "{} colours", c.colours);
        assert!(c.chunks() >= MIN_PER_COLOUR * c.colours);
    }

    /// The 20,000-element ball's O-grid (`cleave bench ball --elements 20000`): with the
    /// lowest free colour it got 11 colours of 64-element chunks, the last three of 8, 9 and 1
    /// chunks (a single chunk runs on one core); taking the least used free colour leaves no
    /// colour with fewer than 4 chunks, 2 for each of 2 threads.
    #[test]
    fn the_ball_gets_colours_of_even_size() {
        let m = crate::mesh::ogrid_sphere(0.005, 20, 5);
        let c = Colouring::new(&m.conn, m.x.len());
        assert!(c.is_proper(m.x.len()));
        let mut count = vec![0usize; c.colours()];
        for &k in c.colour() {
            count[k as usize] += 1;
        }
        let (lo, hi) = (count.iter().min().unwrap(), count.iter().max().unwrap());
        assert!(
            *lo >= 4,
            "{} colours of size {}: {count:?}",
            c.colours(),
            c.size()
        );
        assert!(c.chunks() >= MIN_PER_COLOUR * c.colours());
        assert!(*hi <= 4 * lo, "{count:?}");
    }

    #[test]
    fn a_block_numbered_at_random_falls_back_to_small_chunks() {
        let (mut conn, nn) = block(20); // 8,000 elements
        let mut r = Rng(11);
        for i in (1..conn.len()).rev() {
            let j = (r.unit() * (i + 1) as f64) as usize % (i + 1);
            conn.swap(i, j);
        }
        let big = Colouring::with_size(&conn, nn, 256);
        // every 256-element chunk touches nearly every other: about one chunk per colour
        assert!(
            big.chunks() < 2 * big.colours,
            "{} / {}",
            big.chunks(),
            big.colours
        );
        let c = Colouring::new(&conn, nn);
        assert!(c.size() < 256);
        assert!(c.is_proper(nn));
        assert!(c.chunks() >= MIN_PER_COLOUR * c.colours, "{c:?}");
        // single elements: at most 27 colours (an element touches 26 others in a block)
        let one = Colouring::with_size(&conn, nn, 1);
        assert!(one.is_proper(nn));
        assert!(one.colours <= 27, "{}", one.colours);
    }

    #[test]
    fn a_wrong_colouring_is_caught() {
        let (conn, nn) = block(10);
        let mut c = Colouring::with_size(&conn, nn, 16);
        assert!(c.is_proper(nn));
        c.colour[1] = c.colour[0]; // chunks 0 and 1 share the nodes between them
        assert!(!c.is_proper(nn));
    }

    /// A block split as a separation group splits it (8 nodes of its own per element): by
    /// nodes its chunks share nothing and take one colour; by classes (each copy's deck node)
    /// they get the colours of the block before the split, and a clash of classes is caught.
    #[test]
    fn classes_colour_a_split_block_as_the_block() {
        let (conn, nn) = block(10);
        let split: Vec<[u32; 8]> = (0..conn.len() as u32)
            .map(|e| std::array::from_fn(|a| 8 * e + a as u32))
            .collect();
        let class: Vec<u32> = conn.iter().flatten().copied().collect();
        let copies = split.len() * 8;
        let by_node = Colouring::with_size(&split, copies, 16);
        assert_eq!(by_node.colours(), 1);
        let whole = Colouring::with_size(&conn, nn, 16);
        let mut c = Colouring::with_classes(&split, copies, class);
        assert_eq!(c.size(), Colouring::new(&conn, nn).size());
        assert!(c.is_proper(copies));
        let by_class = Colouring::sized(&split, copies, 16, c.class.as_deref());
        assert_eq!(by_class.colour(), whole.colour());
        assert!(
            c.same_class(1, 8),
            "element 1's first node is element 0's second"
        );
        assert!(!c.same_class(0, 1));
        let k = c.colour[1];
        c.colour[0] = k; // chunks 0 and 1 hold copies of the nodes between them
        assert!(!c.is_proper(copies));
    }

    #[test]
    fn no_elements_no_chunks() {
        let c = Colouring::new(&[], 5);
        assert_eq!((c.chunks(), c.colours), (0, 0));
        assert!(c.is_proper(5));
    }
}
