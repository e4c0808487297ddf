//! Crack closure: the two faces of a failed interface, while they still lie on each other,
//! resist interpenetration through their node pairs instead of through the node-to-face search.
//!
//! When an interface fails its faces A and B join the contact surface, but they start flush,
//! with each node of A at a corner of B and its copy on B at a corner of A. Node-to-face
//! contact finds no clearance for such pairs (the node sits on the face's edge), and the faces
//! of a fresh crack ring at speeds near the impact's, so the search would test them every step:
//! most of the contact's work on a fragmenting ball. Yet the geometry is known: the node pairs
//! `(a_k, b_k)` of the interface (copies of one deck node) were one point when it failed.
//! So, as a cohesive element does once open (Akantu's contact penalty of its cohesive laws;
//! LS-DYNA's cohesive materials in compression), each pair carries a penalty on its normal
//! opening:
//!
//! ```text
//! n   = unit normal of the mid-surface (the mid-points of the 4 pairs), out of A into B
//! d_k = x(b_k) - x(a_k),   g_k = d_k . n      (g_k < 0: B has entered A)
//! f_k = -k g_k n + f_t     on b_k, and -f_k on a_k, while g_k < 0
//! k   = k(B, a) + k(A, b)  (k(B, a): the spring of a node a against face B,
//!                           [`super::surface::FaceTable::pair_stiffness`])
//! ```
//!
//! with `f_t` the Coulomb friction of the contact definition ([`super::friction`]: elastic trial
//! `f_t - k du_t`, capped at `mu |f_n|`, du_t the pair's tangential slip over the step). The
//! stiffness is that of the two node-to-face passes at a node of the pair (a_k against B, b_k
//! against A: with PENOPT 1, the smaller of the face's `SLSFAC K A^2 / V` and the node's, the least
//! node of the four for all pairs; for two like elements, k_A + k_B), so where a node has one crack
//! face (a crack one element wide, the edge of a crack) the closure pushes back as node-to-face
//! contact would: the broken bar pushed back in `tests/contact.rs` closes to 3.7% of h either way.
//! Where several crack faces share a node, each adds its pair (node-to-face would give one spring
//! per node and side): up to four times stiffer inside a flat crack. It stays stable at the contact
//! time step ([`super::ContactSet::stable_dt`]): each of the two springs is at most the stiffness
//! of either copy (the copies of one deck node have the same), so a pair's copies held by them
//! vibrate at `omega^2 <= 2 k_a/m_a + 2 k_b/m_b`, the case that step is made for, and n pairs
//! between two sets of n copies each (a flat crack: 4 faces, 4 copies a side) at the same frequency
//! (PENOPT 2's step covers the stiffest face on the lightest node). Not covered: a copy in three
//! closed cracks at once (every face of its element at a corner failed and closed, the copies
//! around it untied) is held by three pairs, up to `omega^2 = 12 k/m` where the step allows
//! `4 k/m`; the fragmenting balls' energy balance (1.00001 at 50 us) shows no such growth. The
//! pairs act in equal and opposite forces: momentum is kept exactly.
//!
//! While a crack is *closed* this way, the node-to-face search leaves out the pairs it covers:
//! a node (or a node tied to it) that is a partner of a corner of a face is not tested against
//! that face ([`Chains::held`]). The closure holds only while the faces still lie on
//! each other: once any pair has slid along the mid-surface by more than [`SLIP`] times the
//! shortest edge of A, or the faces have turned apart by more than [`TURN`] (their normals),
//! the crack is *released* for good: the node-to-face search takes its faces back (the nodes
//! near them get new candidate lists at once, as when an interface fails), and the pair's
//! friction history ends there. Openings along the normal need no release: faces that fly
//! apart and come back straight meet as they parted, and the closure catches them. While no
//! pair has opened by more than [`TIGHT`] times that edge the crack is *tight*, and a node
//! whose every face is on a tight crack is left out of the search (the contact module's docs,
//! Buried nodes).

use super::friction::{tangential_force, Friction};
use super::surface::FaceId;
use super::Points;
use crate::element::hex8::diagonal_cross;
use crate::math::{add, dot, norm, scale, sub, Vec3};
use crate::separation::split::{copies_of, Copies};
use std::sync::Arc;

/// A closed crack is released when a node pair has slid by more than this fraction of the
/// shortest edge of its face A (then the node-to-face search takes over: the node lies that
/// far inside the face opposite, which the projection handles).
pub const SLIP: f64 = 0.2;

/// A closed crack is *tight* while no node pair has opened along the normal by more than this
/// fraction of the shortest edge of A: only then does it bury its nodes (the search leaves
/// out a node all of whose faces lie on tight cracks, [`super`] module docs, Buried nodes).
pub const TIGHT: f64 = 0.2;

/// ... or when the faces' unit normals n_A, n_B have turned apart: `n_A . n_B > -TURN`
/// (cos 30 degrees = 0.866: flush faces have `n_A . n_B = -1`).
pub const TURN: f64 = 0.866;

/// A failed interface: its two faces and their node pairs (`nodes[0][k]` and `nodes[1][k]` are
/// the copies of one deck node, on A and on B), as the separation lists it
/// (`SharedFace::elems`, `faces`, `nodes`).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct Crack {
    pub faces: [FaceId; 2],
    pub nodes: [[u32; 4]; 2],
}

/// A closed crack: the node pairs of one failed interface with their penalty.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub(super) struct Closure {
    pub faces: [FaceId; 2],
    /// `a[k]` in the outward order of face A (so the mid-surface normal points out of A),
    /// `b[k]` its partner on B.
    pub a: [u32; 4],
    pub b: [u32; 4],
    /// Penalty per pair (module docs).
    pub k: f64,
    /// Tangential force on b_k at the last step (zero when the pair was open).
    pub ft: [Vec3; 4],
    /// This step's unit normal of the mid-surface and each pair's normal force magnitude: the
    /// force on b_k is [`Closure::force`] (on a_k the opposite). Kept instead of the four
    /// forces: 72 bytes less a crack (0.6 MB on the 20,000-element ball's 8,747).
    pub n: Vec3,
    pub fn_mag: [f64; 4],
    /// No pair has opened by more than [`TIGHT`] times A's shortest edge (at the last step).
    pub tight: bool,
}

impl Closure {
    /// A crack closed with node pairs `a[k]`, `b[k]` and penalty `k` per pair.
    pub fn new(faces: [FaceId; 2], a: [u32; 4], b: [u32; 4], k: f64) -> Self {
        Self {
            faces,
            a,
            b,
            k,
            ft: [[0.0; 3]; 4],
            n: [0.0; 3],
            fn_mag: [0.0; 4],
            tight: true,
        }
    }

    /// This step's force on b_k: `fn_mag n`, plus the friction `f_t` unless the contact is
    /// frictionless (then `f_t` is zero and not added, so the sum is bit for bit what
    /// [`Closure::step`] worked out).
    #[inline]
    pub fn force(&self, k: usize, frictionless: bool) -> Vec3 {
        let f = scale(self.n, self.fn_mag[k]);
        if frictionless {
            f
        } else {
            add(f, self.ft[k])
        }
    }

    /// One step at positions `x` (velocities `v` over the last step `dt_prev`): whether the
    /// faces no longer lie on each other (module docs: a pair slid by more than [`SLIP`] times
    /// A's shortest edge, or the faces turned apart beyond [`TURN`]); if they still do, the
    /// pairs' forces (on the B nodes, [`Closure::force`]; zero for open pairs), and whether
    /// the crack is [`Closure::tight`].
    pub fn step(&mut self, x: Points, v: Points, dt_prev: f64, friction: &Friction) -> bool {
        let pa = self.a.map(|i| x[i as usize]);
        let pb = self.b.map(|i| x[i as usize]);
        let edge2 = (0..4)
            .map(|k| {
                let e = sub(pa[(k + 1) % 4], pa[k]);
                dot(e, e)
            })
            .fold(f64::INFINITY, f64::min);
        // both normals in A's node order: flush faces give na . nb = |na| |nb|
        let na = diagonal_cross(pa[0], pa[1], pa[2], pa[3]);
        let nb = diagonal_cross(pb[0], pb[1], pb[2], pb[3]);
        let (la, lb) = (norm(na), norm(nb));
        let m: [Vec3; 4] = std::array::from_fn(|k| scale(add(pa[k], pb[k]), 0.5));
        let c = diagonal_cross(m[0], m[1], m[2], m[3]);
        let lc = norm(c);
        if !(la > 0.0 && lb > 0.0 && lc > 0.0) || dot(na, nb) < TURN * la * lb {
            return true;
        }
        // unit normal of the mid-surface, out of A
        let n = scale(c, 1.0 / lc);
        self.n = n;
        let d: [Vec3; 4] = std::array::from_fn(|k| sub(pb[k], pa[k]));
        let lim = SLIP * SLIP * edge2;
        if d.iter().any(|&d| {
            let t = sub(d, scale(n, dot(d, n)));
            let t2 = dot(t, t);
            t2 > lim || t2.is_nan()
        }) {
            return true;
        }
        let open = TIGHT * TIGHT * edge2;
        self.tight = true;
        for (k, &dk) in d.iter().enumerate() {
            let g = dot(dk, n);
            if g >= 0.0 || g.is_nan() {
                self.tight &= g * g <= open;
                self.ft[k] = [0.0; 3];
                self.fn_mag[k] = 0.0;
                continue;
            }
            let fn_mag = -self.k * g;
            if !friction.is_frictionless() {
                let (ia, ib) = (self.a[k] as usize, self.b[k] as usize);
                let v_rel = sub(v[ib], v[ia]);
                let v_t = sub(v_rel, scale(n, dot(v_rel, n)));
                let mu = friction.coefficient(norm(v_t));
                let du_t = scale(v_t, dt_prev);
                let f_t = tangential_force(self.ft[k], n, du_t, self.k, mu * fn_mag).0;
                self.ft[k] = f_t;
            }
            self.fn_mag[k] = fn_mag;
        }
        false
    }
}

const NONE: u32 = u32::MAX;

/// Partners a node's bit mask holds: the first 32 copies of its deck node ([`Chains`]).
const MASK_BITS: usize = 32;

/// Which copies of each deck node are held together, by a tie (one coincident set) or through
/// a chain of closed cracks: the search leaves out a face that holds a node so held with the
/// node checked (module docs, Chains).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub(super) struct Chains {
    /// Deck node of each model node (empty when the model is not split): the split model's
    /// own `origin` when it shares it ([`Chains::new`]), not a copy.
    deck: Arc<[u32]>,
    /// The copies of each deck node.
    copies: Copies,
    deck_nodes: usize,
    /// Each node's partners across its closed cracks, copies of its deck node: bit j for the
    /// copy at place j of [`Chains::copies`] (4 bytes a node; a list of 3 partners took 12).
    /// A pair with a partner at place [`MASK_BITS`] or beyond (a deck node with more copies, an
    /// irregular mesh) is in `far` instead, as (node, partner) both ways.
    pair: Vec<u32>,
    far: Vec<(u32, u32)>,
    /// Per model node: the lowest node of its chain (the node itself until its deck node is
    /// relabelled).
    pub label: Vec<u32>,
    /// Deck nodes to relabel at the next [`Chains::refresh`].
    dirty: Vec<u32>,
}

impl Chains {
    /// For a split model (`origin[i]`: deck node of model node i); empty otherwise.
    /// `shared` is the model's own origin ([`crate::per_node::PerNode::origin_shared`]): it
    /// is kept when it is `origin`, else `origin` is copied.
    pub fn new(origin: Option<&[u32]>, shared: Option<Arc<[u32]>>) -> Self {
        let Some(origin) = origin else {
            return Self::default();
        };
        let deck = match shared {
            Some(s) if std::ptr::eq(&s[..], origin) => s,
            _ => Arc::from(origin),
        };
        let deck_nodes = origin.iter().map(|&d| d as usize + 1).max().unwrap_or(0);
        Self {
            deck,
            copies: copies_of(origin, deck_nodes),
            deck_nodes,
            pair: vec![0; origin.len()],
            far: Vec::new(),
            label: (0..origin.len() as u32).collect(),
            dirty: Vec::new(),
        }
    }

    /// Whether the deck nodes read are those of `origin` itself, not a copy of them.
    #[cfg(test)]
    pub fn reads(&self, origin: &[u32]) -> bool {
        std::ptr::eq(&self.deck[..], origin)
    }

    /// Whether the model is split (else there are no copies to chain).
    pub fn is_split(&self) -> bool {
        !self.deck.is_empty()
    }

    /// The copies of model node n's deck node (n among them); empty when not split.
    pub fn copies(&self, n: u32) -> &[u32] {
        match self.deck.get(n as usize) {
            Some(&d) => self.copies.of(d),
            None => &[],
        }
    }

    /// Whether nodes a and s are held together (see the type); false when not split.
    #[inline]
    pub fn held(&self, a: u32, s: u32) -> bool {
        self.is_split() && self.label[a as usize] == self.label[s as usize]
    }

    /// The ties of deck node `d`'s copies may have changed: relabel it.
    pub fn touch(&mut self, n: u32) {
        if let Some(&d) = self.deck.get(n as usize) {
            self.dirty.push(d);
        }
    }

    /// Every deck node is relabelled at the next refresh.
    pub fn touch_all(&mut self) {
        self.dirty.clear();
        self.dirty.extend(0..self.deck_nodes as u32);
    }

    /// Copies a and b face each other across a closed crack (`on`) or no longer (`!on`). A pair
    /// may face each other across several cracks at once (a node outside the groups and a
    /// group's copy, across each failed interface of the copy's element at that node): the
    /// first is the mask's bit, the others are listed in `far`, and a release takes one away.
    pub fn link(&mut self, a: u32, b: u32, on: bool) {
        if self.pair.is_empty() {
            return;
        }
        for (p, q) in [(a, b), (b, a)] {
            // q's place among p's deck node's copies (beyond the masks when not one of them)
            let j = self
                .copies(p)
                .iter()
                .position(|&n| n == q)
                .unwrap_or(usize::MAX);
            let bit = if j < MASK_BITS { 1u32 << j } else { 0 };
            let mask = &mut self.pair[p as usize];
            if on {
                if *mask & bit == 0 && bit != 0 {
                    *mask |= bit;
                } else {
                    self.far.push((p, q));
                }
            } else if let Some(k) = self.far.iter().position(|&e| e == (p, q)) {
                self.far.swap_remove(k);
            } else {
                *mask &= !bit;
            }
        }
        self.touch(a);
        self.touch(b);
    }

    /// Relabel the touched deck nodes: each copy gets the lowest copy it is joined to through
    /// ties (`tie[a] == tie[b] != NONE`) and closed cracks.
    pub fn refresh(&mut self, tie: &[u32]) {
        if self.dirty.is_empty() {
            return;
        }
        self.dirty.sort_unstable();
        self.dirty.dedup();
        let Self {
            copies,
            pair,
            far,
            label,
            dirty,
            ..
        } = self;
        for &d in dirty.iter() {
            let c = copies.of(d);
            for &i in c {
                label[i as usize] = i;
            }
            // a chain has at most c.len() links: that many sweeps settle every label
            for _ in 0..c.len() {
                let mut changed = false;
                for &i in c {
                    let set = tie.get(i as usize).copied().unwrap_or(NONE);
                    let mut m = label[i as usize];
                    for &j in c {
                        if set != NONE && tie[j as usize] == set {
                            m = m.min(label[j as usize]);
                        }
                    }
                    let mut bits = pair[i as usize];
                    while bits != 0 {
                        let j = c[bits.trailing_zeros() as usize];
                        m = m.min(label[j as usize]);
                        bits &= bits - 1;
                    }
                    if !far.is_empty() {
                        for &(_, j) in far.iter().filter(|e| e.0 == i) {
                            m = m.min(label[j as usize]);
                        }
                    }
                    if m < label[i as usize] {
                        label[i as usize] = m;
                        changed = true;
                    }
                }
                if !changed {
                    break;
                }
            }
        }
        dirty.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chains join copies through ties and closed-crack pairs, and come apart when a pair is
    /// unlinked: for a deck node with 40 copies, pairs among its first 32 copies (bit masks)
    /// and pairs with copies beyond (`far`), against the labels worked out by hand.
    #[test]
    fn chains_follow_links_and_ties() {
        // deck node 0: copies 0..40; deck node 1: copies 40..44 (ascending in `copies`)
        let origin: Vec<u32> = (0..44).map(|i| u32::from(i >= 40)).collect();
        let mut ch = Chains::new(Some(&origin), None);
        let untied = vec![NONE; 44];
        ch.touch_all();
        ch.refresh(&untied);
        assert!(!ch.held(3, 5));
        // 3 - 5 - 35 - 39 by closed cracks (the last two beyond the masks), 41 tied to 43
        ch.link(3, 5, true);
        ch.link(5, 35, true);
        ch.link(35, 39, true);
        let mut tie = untied.clone();
        tie[41] = 41;
        tie[43] = 41;
        ch.touch(41);
        ch.refresh(&tie);
        for (a, b) in [(3, 5), (3, 35), (5, 39), (39, 3), (41, 43)] {
            assert!(ch.held(a, b), "{a} {b}");
        }
        for (a, b) in [(3, 4), (39, 38), (0, 40), (41, 42)] {
            assert!(!ch.held(a, b), "{a} {b}");
        }
        assert_eq!(ch.label[39], 3);
        // the crack between 5 and 35 released: 3 - 5 and 35 - 39 stay
        ch.link(5, 35, false);
        ch.refresh(&tie);
        assert!(ch.held(3, 5) && ch.held(35, 39));
        assert!(!ch.held(5, 35) && !ch.held(3, 39));
        assert_eq!((ch.label[5], ch.label[39]), (3, 35));
        ch.link(35, 39, false);
        ch.refresh(&tie);
        assert!(!ch.held(35, 39));
        assert!(ch.far.is_empty());
        // a pair across two cracks at once stays held until both are released
        ch.link(3, 5, true);
        ch.refresh(&tie);
        ch.link(3, 5, false);
        ch.refresh(&tie);
        assert!(ch.held(3, 5));
        ch.link(3, 5, false);
        ch.refresh(&tie);
        assert!(!ch.held(3, 5));
        // copies of two deck nodes (no crack pairs them; the chains take it without harm)
        ch.link(3, 42, true);
        ch.refresh(&tie);
        ch.link(3, 42, false);
        ch.refresh(&tie);
        assert!(!ch.held(3, 42) && ch.far.is_empty());
        assert_eq!(ch.pair.iter().filter(|&&m| m != 0).count(), 0);
    }
}
