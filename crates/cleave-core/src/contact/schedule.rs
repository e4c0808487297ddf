//! When each candidate pair of a node is tested again.
//!
//! A test of a node against a face that finds them apart returns a *clearance* D (see
//! `contact` module docs): the pair cannot touch while the definition's motion bound grows by
//! less than D, so it is next due at `due = motion + D`. A node's candidates are kept in two
//! groups: the *hot* ones, due within a few steps (by `hot_until`), looked at every step, the
//! first [`HOT`] of them inline in the node's [`Sched`] (32 bytes, before its list) and
//! any others at the end of the node's list; and the *cold* ones, a min-heap on `due` at the
//! start of the list, of which only the top is looked at (its `due` is kept in the [`Sched`]
//! too). The node's candidates fill a *room* of fixed size, their number, between two searches
//! (its place in [`super::cand_lists`]): the list, then the places of the inline ones, so a
//! candidate moving between the list and the inline places never needs more room. A node
//! whose hot candidates are not due and whose heap top is not due costs one
//! read of its [`Sched`]; the caller keeps each node's earliest due ([`Sched::next_due`]) in a
//! dense array, so such a node costs it 4 bytes.
//!
//! The candidates tested at a step are exactly those with `due <= motion` (or NaN), whatever
//! group they are in; the order in which they are tested differs from the list's, so the
//! caller must not depend on it.

/// A candidate face of a node, and when the pair must be tested next.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
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

/// Hot candidates kept inline in a [`Sched`] ([`Sched::store`] has room for two). A node that a
/// step checks tests 1.1 faces on average (the 2800 and the 20,000 ball, `cleave bench ball`), so
/// two cover most.
pub const HOT: usize = 2;

// [`Sched::store`] keeps two inline candidates
const _: () = assert!(HOT == 2);

/// A node's inline hot candidates and the size and top of its heap of cold ones (module docs).
/// The node's room is `[heap (cold) | hot candidates beyond the inline ones | n_hot places]`.
/// It is kept in [`Sched::UNITS`] candidates' space just before the room
/// ([`super::cand_lists`]), so a node without candidates needs none.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
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
    /// Candidates' space a schedule is kept in ([`Sched::store`]).
    pub const UNITS: usize = 4;

    /// The schedule kept in `h` ([`Sched::store`]).
    #[inline]
    pub fn load(h: &[Cand]) -> Self {
        Self {
            hot: [h[0], h[1]],
            n_hot: h[2].face,
            top: h[2].due,
            cold: h[3].face,
        }
    }

    /// Keep the schedule in `h` ([`Sched::UNITS`] candidates: the inline ones, then the
    /// counts and the heap's top in the candidates' fields).
    #[inline]
    pub fn store(&self, h: &mut [Cand]) {
        h[0] = self.hot[0];
        h[1] = self.hot[1];
        h[2] = Cand {
            face: self.n_hot,
            due: self.top,
        };
        h[3] = Cand {
            face: self.cold,
            due: 0.0,
        };
    }

    /// The list's length in the room (the rest of the room is the inline hot candidates').
    #[inline]
    fn list_len(&self, room: &[Cand]) -> usize {
        room.len() - self.n_hot as usize
    }

    /// The candidate faces, in no particular order.
    pub fn faces<'a>(&'a self, room: &'a [Cand]) -> impl Iterator<Item = u32> + 'a {
        self.hot[..self.n_hot as usize]
            .iter()
            .chain(&room[..self.list_len(room)])
            .map(|c| c.face)
    }

    /// Number of candidates not due at `motion` (waiting).
    #[cfg(test)]
    pub fn waiting(&self, room: &[Cand], motion: f64) -> usize {
        self.hot[..self.n_hot as usize]
            .iter()
            .chain(&room[..self.list_len(room)])
            .filter(|c| !is_due(c.due, motion))
            .count()
    }

    /// The earliest `due` of the node's candidates (`-inf` if one is NaN, `+inf` when there
    /// is none): while the motion bound is below it, [`Sched::visit`] tests nothing.
    pub fn next_due(&self, room: &[Cand]) -> f32 {
        let hot = &room[self.cold as usize..self.list_len(room)];
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

    /// Put every candidate in the room (in no particular order), for a new search.
    pub fn gather(&mut self, room: &mut [Cand]) {
        let len = self.list_len(room);
        room[len..].copy_from_slice(&self.hot[..self.n_hot as usize]);
        *self = Self::default();
    }

    /// After a search (the schedule empty, [`Sched::gather`]): `room` holds all the node's
    /// candidates; those due by `hot_until` (or NaN) become hot, the others the heap.
    pub fn split(&mut self, room: &mut [Cand], hot_until: f64) {
        debug_assert_eq!(self.n_hot, 0, "split after gather");
        let mut cold = 0;
        for k in 0..room.len() {
            if !is_due(room[k].due, hot_until) {
                room.swap(k, cold);
                cold += 1;
            }
        }
        for k in (0..cold / 2).rev() {
            sift_down(&mut room[..cold], k);
        }
        let mut n_hot = 0;
        let mut len = room.len();
        while n_hot < HOT && len > cold {
            len -= 1;
            self.hot[n_hot] = room[len];
            n_hot += 1;
        }
        self.n_hot = n_hot as u32;
        self.set_cold(room, cold);
    }

    /// Every candidate due at once.
    pub fn renew(&mut self, room: &mut [Cand]) {
        let len = self.list_len(room);
        for c in self.hot[..self.n_hot as usize]
            .iter_mut()
            .chain(room[..len].iter_mut())
        {
            c.due = f32::NEG_INFINITY;
        }
        self.cold = 0;
        self.top = f32::INFINITY;
    }

    fn set_cold(&mut self, room: &[Cand], cold: usize) {
        self.cold = cold as u32;
        self.top = if cold > 0 { room[0].due } else { f32::INFINITY };
    }

    /// Test the candidates due at `motion`: `test(face)` returns the pair's clearance; the
    /// pair is due again at `motion + clearance`, and is hot if that is by `hot_until` (which
    /// must be at least `motion`). The candidates move between the inline places and the
    /// list within the room, whose size (their number) does not change.
    #[inline]
    pub fn visit(
        &mut self,
        room: &mut [Cand],
        motion: f64,
        hot_until: f64,
        mut test: impl FnMut(u32) -> f64,
    ) {
        let mut cold = self.cold as usize;
        let mut len = self.list_len(room);
        let heap_due = is_due(self.top, motion);
        if self.n_hot == 0 && cold == len && !heap_due {
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
                room[len] = Cand { face: c.face, due };
                len += 1;
                room.swap(cold, len - 1);
                cold += 1;
                sift_up(&mut room[..cold], cold - 1);
            }
        }
        // hot candidates in the list
        let mut k = cold;
        while k < len {
            let c = room[k];
            if !is_due(c.due, motion) {
                k += 1;
                continue;
            }
            let due = next(c.face);
            room[k].due = due;
            if !hot(due) {
                // into the heap; the candidate at `cold` (already seen) takes its place
                room.swap(k, cold);
                cold += 1;
                sift_up(&mut room[..cold], cold - 1);
                k += 1;
            } else if (self.n_hot as usize) < HOT {
                // out of the list (its last candidate takes the place)
                len -= 1;
                room.swap(k, len);
                self.hot[self.n_hot as usize] = room[len];
                self.n_hot += 1;
            } else {
                k += 1;
            }
        }
        // the heap's due candidates, from the top (the list is only read when the top is due)
        while heap_due && cold > 0 && is_due(room[0].due, motion) {
            let c = room[0];
            let due = next(c.face);
            if !hot(due) {
                room[0].due = due;
                sift_down(&mut room[..cold], 0);
            } else {
                // out of the heap, to the first place of the list's hot candidates
                room.swap(0, cold - 1);
                cold -= 1;
                sift_down(&mut room[..cold], 0);
                room[cold].due = due;
                if (self.n_hot as usize) < HOT {
                    len -= 1;
                    room.swap(cold, len);
                    self.hot[self.n_hot as usize] = room[len];
                    self.n_hot += 1;
                }
            }
        }
        debug_assert_eq!(len, self.list_len(room));
        self.set_cold(room, cold);
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

    /// A schedule kept in the candidates' space comes back the same, with NaN and infinite
    /// dues.
    #[test]
    fn a_stored_schedule_loads_back() {
        let mut list: Vec<Cand> = (0..9u32)
            .map(|f| Cand {
                face: f,
                due: [f32::NEG_INFINITY, 0.5, f32::INFINITY, f32::NAN][f as usize % 4] + f as f32,
            })
            .collect();
        let mut sched = Sched::default();
        sched.split(&mut list, 3.0);
        assert!(sched.n_hot > 0 && sched.cold > 0);
        let mut h = [Cand::new(7); Sched::UNITS];
        sched.store(&mut h);
        let back = Sched::load(&h);
        // PartialEq fails on NaN: compare the bits
        let bits = |s: &Sched| {
            let c = |c: &Cand| (c.face, c.due.to_bits());
            (c(&s.hot[0]), c(&s.hot[1]), s.n_hot, s.cold, s.top.to_bits())
        };
        assert_eq!(bits(&back), bits(&sched));
        assert_eq!(
            bits(&Sched::load(&{
                let mut h = [Cand::new(0); Sched::UNITS];
                Sched::default().store(&mut h);
                h
            })),
            bits(&Sched::default())
        );
    }

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
                    .chain(&list[..sched.list_len(&list)])
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
