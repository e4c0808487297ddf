//! When each candidate pair of a node is tested again.
//!
//! A test of a node against a face that finds them apart returns a *clearance* D (see
//! `contact` module docs): the pair cannot touch while the definition's motion bound grows by
//! less than D, so it is next due at `due = motion + D`. A node's candidates are kept in two
//! groups: the *hot* ones, due within a few steps (by `hot_until`), looked at every step, the
//! first [`HOT`] of them inline in the node's [`Sched`] (32 bytes, in a dense array) and
//! any others at the end of the node's list; and the *cold* ones, a min-heap on `due` at the
//! start of the list, of which only the top is looked at (its `due` is kept in the [`Sched`]
//! too). A node whose hot candidates are not due and whose heap top is not due costs one
//! read of its [`Sched`]; the caller keeps each node's earliest due ([`Sched::next_due`]) in a
//! dense array, so such a node costs it 4 bytes.
//!
//! The candidates tested at a step are exactly those with `due <= motion` (or NaN), whatever
//! group they are in; the order in which they are tested differs from the list's, so the
//! caller must not depend on it.

/// A candidate face of a node, and when the pair must be tested next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cand {
    pub face: u32,
    /// Test the pair once the motion bound reaches this (rounded down to f32; -inf: at once).
    pub due: f32,
}

impl Cand {
    /// A new candidate, due at once.
    pub fn new(face: u32) -> Self {
        Self {
            face,
            due: f32::NEG_INFINITY,
        }
    }
}

/// Hot candidates kept inline in a [`Sched`]. A node that a step checks tests 1.1 faces on average
/// (the 2800 and the 20,000 ball, `cleave bench ball`), so two cover most; six (a cache line) cost
/// 32 more bytes for each of the ~75,000 surface nodes of the 20,000 ball at 20 us.
pub const HOT: usize = 2;

/// A node's inline hot candidates and the size and top of its heap of cold ones (module docs).
/// The node's list is `[heap (cold) | hot candidates beyond the inline ones]`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(align(32))]
pub struct Sched {
    hot: [Cand; HOT],
    n_hot: u32,
    cold: u32,
    /// `due` of the heap's top (+inf when the heap is empty).
    top: f32,
}

impl Default for Sched {
    fn default() -> Self {
        Self {
            hot: [Cand::new(0); HOT],
            n_hot: 0,
            cold: 0,
            top: f32::INFINITY,
        }
    }
}

/// The largest f32 not above `v` ([`crate::math::f32_down`]): a due kept in single precision
/// comes no later than asked.
pub use crate::math::f32_down as down;

/// Whether a candidate is due: `due <= motion`, or NaN.
#[inline]
pub fn is_due(due: f32, motion: f64) -> bool {
    (due as f64).partial_cmp(&motion) != Some(std::cmp::Ordering::Greater)
}

impl Sched {
    /// Number of candidates (inline and in `list`).
    pub fn len(&self, list: &[Cand]) -> usize {
        self.n_hot as usize + list.len()
    }

    /// The candidate faces, in no particular order.
    pub fn faces<'a>(&'a self, list: &'a [Cand]) -> impl Iterator<Item = u32> + 'a {
        self.hot[..self.n_hot as usize]
            .iter()
            .chain(list)
            .map(|c| c.face)
    }

    /// Number of candidates not due at `motion` (waiting).
    #[cfg(test)]
    pub fn waiting(&self, list: &[Cand], motion: f64) -> usize {
        self.hot[..self.n_hot as usize]
            .iter()
            .chain(list)
            .filter(|c| !is_due(c.due, motion))
            .count()
    }

    /// The earliest `due` of the node's candidates (`-inf` if one is NaN, `+inf` when there
    /// is none): while the motion bound is below it, [`Sched::visit`] tests nothing.
    pub fn next_due(&self, list: &[Cand]) -> f32 {
        let hot = &list[self.cold as usize..];
        let mut next = self.top;
        for c in self.hot[..self.n_hot as usize].iter().chain(hot) {
            if c.due.is_nan() {
                return f32::NEG_INFINITY;
            }
            next = next.min(c.due);
        }
        if next.is_nan() {
            f32::NEG_INFINITY
        } else {
            next
        }
    }

    /// Move every candidate into `list` (in no particular order), for a new search.
    pub fn gather(&mut self, list: &mut Vec<Cand>) {
        list.extend_from_slice(&self.hot[..self.n_hot as usize]);
        *self = Self::default();
    }

    /// After a search: `list` holds all the node's candidates; those due by `hot_until` (or
    /// NaN) become hot, the others the heap.
    pub fn split(&mut self, list: &mut Vec<Cand>, hot_until: f64) {
        let mut cold = 0;
        for k in 0..list.len() {
            if !is_due(list[k].due, hot_until) {
                list.swap(k, cold);
                cold += 1;
            }
        }
        for k in (0..cold / 2).rev() {
            sift_down(&mut list[..cold], k);
        }
        let mut n_hot = 0;
        while n_hot < HOT && list.len() > cold {
            self.hot[n_hot] = list.pop().expect("hot candidate");
            n_hot += 1;
        }
        self.n_hot = n_hot as u32;
        self.set_cold(list, cold);
        // room for every candidate, so `visit` never grows the list
        list.reserve(n_hot);
    }

    /// Every candidate due at once.
    pub fn renew(&mut self, list: &mut [Cand]) {
        for c in self.hot[..self.n_hot as usize]
            .iter_mut()
            .chain(list.iter_mut())
        {
            c.due = f32::NEG_INFINITY;
        }
        self.cold = 0;
        self.top = f32::INFINITY;
    }

    fn set_cold(&mut self, list: &[Cand], cold: usize) {
        self.cold = cold as u32;
        self.top = if cold > 0 { list[0].due } else { f32::INFINITY };
    }

    /// Test the candidates due at `motion`: `test(face)` returns the pair's clearance; the
    /// pair is due again at `motion + clearance`, and is hot if that is by `hot_until` (which
    /// must be at least `motion`).
    #[inline]
    pub fn visit(
        &mut self,
        list: &mut Vec<Cand>,
        motion: f64,
        hot_until: f64,
        mut test: impl FnMut(u32) -> f64,
    ) {
        let mut cold = self.cold as usize;
        let heap_due = is_due(self.top, motion);
        if self.n_hot == 0 && cold == list.len() && !heap_due {
            return;
        }
        // the next due
        let mut next = |face: u32| down(motion + test(face));
        let hot = |due: f32| is_due(due, hot_until);
        // inline hot candidates
        let mut k = 0;
        while k < self.n_hot as usize {
            let c = self.hot[k];
            if !is_due(c.due, motion) {
                k += 1;
                continue;
            }
            let due = next(c.face);
            if hot(due) {
                self.hot[k].due = due;
                k += 1;
            } else {
                // into the heap (the first hot candidate of the list, if any, moves to the end)
                self.n_hot -= 1;
                self.hot[k] = self.hot[self.n_hot as usize];
                list.push(Cand { face: c.face, due });
                let last = list.len() - 1;
                list.swap(cold, last);
                cold += 1;
                sift_up(&mut list[..cold], cold - 1);
            }
        }
        // hot candidates in the list
        let mut k = cold;
        while k < list.len() {
            let c = list[k];
            if !is_due(c.due, motion) {
                k += 1;
                continue;
            }
            let due = next(c.face);
            list[k].due = due;
            if !hot(due) {
                // into the heap; the candidate at `cold` (already seen) takes its place
                list.swap(k, cold);
                cold += 1;
                sift_up(&mut list[..cold], cold - 1);
                k += 1;
            } else if (self.n_hot as usize) < HOT {
                self.hot[self.n_hot as usize] = list.swap_remove(k);
                self.n_hot += 1;
            } else {
                k += 1;
            }
        }
        // the heap's due candidates, from the top (the list is only read when the top is due)
        while heap_due && cold > 0 && is_due(list[0].due, motion) {
            let c = list[0];
            let due = next(c.face);
            if !hot(due) {
                list[0].due = due;
                sift_down(&mut list[..cold], 0);
            } else {
                // out of the heap, to the first place of the list's hot candidates
                list.swap(0, cold - 1);
                cold -= 1;
                sift_down(&mut list[..cold], 0);
                list[cold].due = due;
                if (self.n_hot as usize) < HOT {
                    self.hot[self.n_hot as usize] = list.swap_remove(cold);
                    self.n_hot += 1;
                }
            }
        }
        self.set_cold(list, cold);
    }
}

/// Restore the min-heap order of `heap` on `due` below position k.
#[inline]
fn sift_down(heap: &mut [Cand], mut k: usize) {
    loop {
        let mut m = k;
        for c in [2 * k + 1, 2 * k + 2] {
            if c < heap.len() && heap[c].due < heap[m].due {
                m = c;
            }
        }
        if m == k {
            return;
        }
        heap.swap(k, m);
        k = m;
    }
}

/// Restore the min-heap order of `heap` above position k.
#[inline]
fn sift_up(heap: &mut [Cand], mut k: usize) {
    while k > 0 {
        let p = (k - 1) / 2;
        if heap[k].due >= heap[p].due {
            return;
        }
        heap.swap(k, p);
        k = p;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::search::tests::Rng;

    /// Over 400 steps of random motion and random clearances (many zero, some tiny, some
    /// large), the faces tested each step are exactly those a plain list with one `due` per
    /// candidate says are due, for nodes with 0 to 40 candidates (so the inline hot places
    /// overflow), with searches (`gather` / `split`, some taking candidates out of the list
    /// and bringing back those out) and renewals now and then.
    #[test]
    fn tests_exactly_the_due_candidates() {
        let mut r = Rng(5);
        for n in [0usize, 1, 3, 6, 7, 12, 40] {
            let mut sched = Sched::default();
            let mut list: Vec<Cand> = (0..n as u32).map(Cand::new).collect();
            sched.split(&mut list, 0.0);
            let mut plain: Vec<Cand> = (0..n as u32).map(Cand::new).collect();
            let mut motion = 0.0;
            let mut total = 0;
            for step in 0..400 {
                let rho = if r.unit() < 0.1 {
                    0.0
                } else {
                    r.range(0.0, 1.0)
                };
                motion += rho;
                let hot_until = motion + 4.0 * rho;
                let clearance = |face: u32, step: usize| -> f64 {
                    let h = (face as u64 * 2654435761 + step as u64 * 40503) % 97;
                    match h % 4 {
                        0 => 0.0,
                        1 => h as f64 * 1e-3,
                        2 => h as f64 * 0.1,
                        _ => h as f64,
                    }
                };
                let mut want: Vec<u32> = plain
                    .iter_mut()
                    .filter(|c| is_due(c.due, motion))
                    .map(|c| {
                        c.due = down(motion + clearance(c.face, step));
                        c.face
                    })
                    .collect();
                let mut got = Vec::new();
                sched.visit(&mut list, motion, hot_until, |f| {
                    got.push(f);
                    clearance(f, step)
                });
                want.sort_unstable();
                got.sort_unstable();
                assert_eq!(got, want, "{n} candidates, step {step}");
                // the earliest due, as the plain list has it
                let earliest = plain.iter().fold(f32::INFINITY, |m, c| m.min(c.due));
                assert_eq!(sched.next_due(&list), earliest, "{n}: step {step}");
                total += got.len();
                let mut all: Vec<Cand> = sched.hot[..sched.n_hot as usize]
                    .iter()
                    .chain(&list)
                    .copied()
                    .collect();
                all.sort_unstable_by_key(|c| c.face);
                assert_eq!(all, plain, "{n} candidates, step {step}");
                if step % 37 == 5 {
                    sched.gather(&mut list);
                    sched.split(&mut list, hot_until);
                }
                if step % 101 == 50 {
                    sched.renew(&mut list);
                    plain.iter_mut().for_each(|c| c.due = f32::NEG_INFINITY);
                }
                if step % 53 == 20 {
                    // a search: some candidates leave the list, those out come back
                    let leaves = |f: u32| (f as usize + step).is_multiple_of(5);
                    sched.gather(&mut list);
                    let absent: Vec<u32> = (0..n as u32)
                        .filter(|&f| !plain.iter().any(|c| c.face == f))
                        .collect();
                    list.retain(|c| !leaves(c.face));
                    plain.retain(|c| !leaves(c.face));
                    for f in absent {
                        plain.push(Cand::new(f));
                        list.push(Cand::new(f));
                    }
                    plain.sort_unstable_by_key(|c| c.face);
                    sched.split(&mut list, hot_until);
                }
            }
            assert!(n == 0 || total > 10 * n.min(10), "{n}: {total}");
        }
    }
}
