//! The bounds of the faces a step tests, worked out when first needed, once per thread.
//!
//! A node check reads a face's [`Cull`] and [`CullMore`] (its bounds at the current positions)
//! for each candidate pair that is due. Only a fraction of the faces in some candidate list
//! has a pair due at a given step: on the fracturing 2800-element ball (`cleave bench ball`,
//! 1 thread, 50 us) 736 distinct faces a step on average, of 3125 in some list. So instead of
//! bounding every listed face each step, each thread keeps a cache of the bounds it worked out,
//! stamped with the *generation* of the pass they were worked out in: a new number for every
//! pass of every step of every contact definition (one global counter), so an entry is valid
//! exactly when its stamp is the current generation, whichever definition or test ran on the
//! thread meanwhile. The bounds are a function of the face's corners alone, so the thread
//! that works them out does not change them: results stay bit-identical on any thread count.
//!
//! Memory: a slot of 108 bytes (bounds, stamp and face) per face of the largest side, rounded
//! up to a power of two and at most [`MAX_SLOTS`] (885 KB), per thread, kept for the thread's
//! life (rayon's workers outlive a run). Face `f` has slot `f mod slots`: up to `MAX_SLOTS`
//! faces each has its own; beyond, faces share slots, and a face that finds its slot holding
//! another face (or another generation) works its bounds out again. On the 20,000-element ball
//! (31,000 faces at 20 us) the caches took 10.8 MB over two threads before the bound. The
//! caches grow when faces join ([`reserve_everywhere`], on every thread of the pool at once, so
//! no check allocates), or when a thread first tests a face beyond its size. A check must not
//! call into rayon while it holds the cache (a stolen task would find it borrowed).

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

use super::penalty::{Cull, CullMore, FaceBounds};
use super::Face;
use super::{Points, GAP_TOL};

/// The last generation handed out.
static GENERATION: AtomicU64 = AtomicU64::new(0);

/// A new generation: call once per pass and step, before its node checks.
pub fn next_generation() -> u64 {
    GENERATION.fetch_add(1, Ordering::Relaxed) + 1
}

/// Most slots a thread's cache has (a power of two).
pub const MAX_SLOTS: usize = 8192;

/// One thread's bounds, in slot `face index mod slots` of the side being checked.
#[derive(Default)]
pub struct BoundsCache {
    stamp: Vec<u64>,
    face: Vec<u32>,
    bounds: Vec<(Cull, CullMore)>,
}

thread_local! {
    // const: no lazy-initialisation check on each access
    static CACHE: RefCell<BoundsCache> = const {
        RefCell::new(BoundsCache {
            stamp: Vec::new(),
            face: Vec::new(),
            bounds: Vec::new(),
        })
    };
}

/// Make room for `n` faces in the cache of every thread of the current rayon pool. Which
/// thread checks which node is up to rayon, so a thread may run its first check at any step;
/// calling this whenever a side grows keeps the checks from allocating.
pub fn reserve_everywhere(n: usize) {
    rayon::broadcast(|_| CACHE.with_borrow_mut(|c| c.reserve(n)));
}

impl BoundsCache {
    /// Room for `n` faces: `n` slots rounded up to a power of two, at most [`MAX_SLOTS`].
    fn reserve(&mut self, n: usize) {
        let slots = n.next_power_of_two().min(MAX_SLOTS);
        if self.stamp.len() < slots {
            // the slots move: no entry is valid (generations start at 1)
            self.stamp.clear();
            self.stamp.resize(slots, 0);
            self.face.resize(slots, 0);
            self.bounds.resize(slots, Default::default());
        }
    }

    /// Run `f` with this thread's cache.
    pub fn with<R>(f: impl FnOnce(&mut BoundsCache) -> R) -> R {
        CACHE.with_borrow_mut(f)
    }

    /// The bounds of face `fi` (of `faces`, at positions `x`) in generation `generation`.
    #[inline]
    pub fn get(
        &mut self,
        generation: u64,
        fi: u32,
        faces: &[Face],
        x: Points,
    ) -> &(Cull, CullMore) {
        // grows with the faces of the sides only (no allocation once they stop joining, nor
        // after `reserve_everywhere`); the slots are a power of two, so this is `reserve`'s
        // own test without its rounding
        if self.stamp.len() < faces.len().min(MAX_SLOTS) {
            self.reserve(faces.len());
        }
        let k = fi as usize & (self.stamp.len() - 1);
        if self.stamp[k] != generation || self.face[k] != fi {
            let face = &faces[fi as usize];
            let p = face.nodes.map(|n| x[n as usize]);
            let b = FaceBounds::new(&p);
            self.bounds[k] = Cull::new(&b, face.depth, GAP_TOL * b.r);
            self.stamp[k] = generation;
            self.face[k] = fi;
        }
        &self.bounds[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn face(z: f64) -> (Vec<Face>, Vec<Vec3>) {
        let x = vec![[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]];
        let f = Face {
            elem: 0,
            face: 0,
            nodes: [0, 1, 2, 3],
            k: 1.0,
            depth: 0.4,
        };
        (vec![f], x)
    }

    /// An entry is reused within its generation and worked out again in the next one.
    #[test]
    fn entries_hold_for_their_generation_only() {
        let (faces, x) = face(0.0);
        let g1 = next_generation();
        let mut c = BoundsCache::default();
        let first = *c.get(g1, 0, &faces, (&x).into());
        let want = {
            let b = FaceBounds::new(&[x[0], x[1], x[2], x[3]]);
            Cull::new(&b, 0.4, GAP_TOL * b.r)
        };
        assert_eq!(first, want);
        // same generation, moved face: the entry is kept (the positions are those of one step)
        let (_, moved) = face(1.0);
        assert_eq!(*c.get(g1, 0, &faces, (&moved).into()), first);
        // a new generation sees the move
        let g2 = next_generation();
        assert!(g2 > g1);
        assert_ne!(*c.get(g2, 0, &faces, (&moved).into()), first);
        assert_eq!(c.get(g2, 0, &faces, (&moved).into()).0.c, [0.5, 0.5, 1.0]);
    }

    /// Beyond MAX_SLOTS faces, faces 0 and MAX_SLOTS share a slot: asked in turn within one
    /// generation, each gets its own bounds every time, and the cache stays at MAX_SLOTS.
    #[test]
    fn faces_sharing_a_slot_get_their_own_bounds() {
        let (mut faces, mut x) = face(0.0);
        x.extend(face(2.0).1);
        faces.resize(MAX_SLOTS + 1, faces[0]);
        faces[MAX_SLOTS].nodes = [4, 5, 6, 7];
        let mut c = BoundsCache::default();
        let g = next_generation();
        for _ in 0..3 {
            assert_eq!(c.get(g, 0, &faces, (&x).into()).0.c, [0.5, 0.5, 0.0]);
            let far = MAX_SLOTS as u32;
            assert_eq!(c.get(g, far, &faces, (&x).into()).0.c, [0.5, 0.5, 2.0]);
        }
        assert_eq!(c.stamp.len(), MAX_SLOTS);
    }
}
