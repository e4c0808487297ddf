//! A split of the coincident sets brought to the GPU's arrays in place: the work of a split
//! grows with what it changes, not with the model.
//!
//! When interfaces fail, the sets that held their nodes split: the piece of a set's
//! representative keeps its slot and the other pieces get new slots, numbered on
//! (`cleave_core::separation::coincident::CoincidentSets::born`). The arrays of the layout
//! indexed by slot ([`Layout`]) change only at the slots of those sets, at the elements of their
//! members and at the interfaces that hold them:
//! - each changed node's corners name its new slot (`conn`);
//! - the corners a set gathered (`ninc`, in element order) are shared out among its pieces in
//!   the same range of `ninc`: the piece that keeps the slot first, then the new slots in the
//!   order numbered, each piece's corners in element order. So every slot sums its corner
//!   forces in the order a layout made afresh gives it ([`Layout::new`]), and a run taken up
//!   from a restart file (whose layout is made afresh) gives the same bits;
//! - `nptr` gives each of those slots its new start and end; `nflag` each its members' SPC and
//!   wall bits; `emat` the elements that became loose their free-element slot;
//! - the interfaces that hold a changed node, or that were released, get their row again.
//!
//! [`Relayout`] keeps a copy of those arrays as the device holds them and says which values a
//! split changed ([`Changes`]), so the host writes only those (through one staging buffer,
//! [`Writes`]). Its cost: the copies and a corner and interface list per node, about 150 bytes
//! per element of host memory, and three layouts made when the stepper is. A split whose changed nodes carry
//! a load, a pressure segment or a prescribed motion (whose blocks in `par` are ordered by slot)
//! is not done in place ([`Relayout::split`] gives `None`): the layout is then made afresh.

use cleave_core::solver::Solver;

use crate::by_entry::ByEntry;
use crate::layout::{by_component, Layout, Slots};
use crate::separation::{interface_row, IF_STRIDE};

/// The arrays a split changes, as the device holds them, and what a split reads to change them.
pub(crate) struct Relayout {
    /// Per node of the model, its element corners `8 e + a` in element order.
    corners: ByEntry,
    /// Per node, the interfaces that hold it.
    interfaces: ByEntry,
    /// Per node, its SPC and wall bits.
    flag: Vec<u32>,
    /// Per node, whether it carries a node action (a load, a pressure segment's corner, a
    /// prescribed motion).
    acts: Vec<bool>,
    /// Each element's `emat`: tight, and loose (the free-element slot).
    emat_of: [Vec<u32>; 2],
    /// The device's arrays: `conn` by component, `emat`, `nptr`, `ninc`, `nflag`, `ifu`.
    pub conn: Vec<u32>,
    pub emat: Vec<u32>,
    pub nptr: Vec<u32>,
    pub ninc: Vec<u32>,
    pub nflag: Vec<u32>,
    pub ifu: Vec<u32>,
    /// Each element's loose flag as `emat` holds it.
    loose: Vec<bool>,
    /// The slots the arrays hold.
    slots: usize,
}

/// The values a split changed, as indices into each array (repeats allowed), and the slots whose
/// mass, position and velocities change (the split sets' pieces).
#[derive(Default)]
pub(crate) struct Changes {
    pub conn: Vec<usize>,
    pub emat: Vec<usize>,
    pub nptr: Vec<usize>,
    pub ninc: Vec<usize>,
    pub nflag: Vec<usize>,
    pub ifu: Vec<usize>,
    pub slots: Vec<usize>,
}

impl Relayout {
    /// The arrays of `lay`, the layout of `solver`'s split model as it stands; `None` without
    /// element separation.
    pub fn new(solver: &Solver, lay: &Layout) -> Option<Self> {
        let sep = solver.separation()?;
        let (model, setup, ties) = (solver.model, &solver.setup, solver.ties());
        let nn = model.num_nodes();
        // the model's own layout (a slot per node): each node's corners, flags and actions
        let own = Layout::new(model, setup, ties, None);
        let corners = ByEntry::new(
            nn,
            (0..nn as u32).flat_map(|n| {
                let (a, b) = (own.nptr[2 * n as usize], own.nptr[2 * n as usize + 1]);
                own.ninc[a as usize..b as usize]
                    .iter()
                    .map(move |&c| (n, c))
            }),
        );
        let acts = (own.mptr.windows(2)).map(|w| w[1] > w[0]).collect();
        let n_if = sep.num_interfaces();
        let faces = &sep.faces()[..n_if];
        let interfaces = ByEntry::new(
            nn,
            (faces.iter().enumerate()).flat_map(|(i, f)| f.nodes.map(|n| (n, i as u32))),
        );
        let of = sep.sets().slots();
        let emat_of = [false, true].map(|l| {
            let loose = vec![l; model.num_elements()];
            Layout::new(model, setup, ties, Some(Slots { of, loose: &loose })).emat
        });
        let (ifu, ..) = crate::separation::interface_table(solver);
        let mut out = Self {
            corners,
            interfaces,
            flag: own.nflag,
            acts,
            emat_of,
            conn: vec![],
            emat: vec![],
            nptr: vec![],
            ninc: vec![],
            nflag: vec![],
            ifu: vec![],
            loose: vec![],
            slots: 0,
        };
        out.reset(solver, lay, ifu);
        Some(out)
    }

    /// Take the arrays from `lay` and `ifu`, the layout and interface table of `solver`'s split
    /// model made afresh.
    pub fn reset(&mut self, solver: &Solver, lay: &Layout, ifu: Vec<u32>) {
        let Some(sep) = solver.separation() else {
            return;
        };
        self.conn = by_component(&lay.conn, 8);
        self.emat.clone_from(&lay.emat);
        self.nptr.clone_from(&lay.nptr);
        self.ninc.clone_from(&lay.ninc);
        self.nflag.clone_from(&lay.nflag);
        self.ifu = ifu;
        self.loose = sep.loose_elements().to_vec();
        self.slots = sep.sets().num_slots();
    }

    /// Bring the arrays to the split that `solver`'s separation has just made (its sets' last
    /// split; `released`: at least the interfaces it released, e.g. all those listed as failed,
    /// whose rows are written again whether or not they were) and say what changed; `None` when
    /// the split is not done in place (the arrays are then as before: make the layout afresh
    /// and [`Self::reset`]). A slot born of a slot born in the same split (which the sets do
    /// not make: a release unties all its interfaces before the sets split) is traced to the
    /// slot before the split; should the ranges not add up, `None`.
    pub fn split(&mut self, solver: &Solver, released: &[u32]) -> Option<Changes> {
        let sep = solver.separation()?;
        let sets = sep.sets();
        let slot = sets.slots();
        let before = self.slots;
        let born = sets.born();
        // the new slots are numbered on from those the arrays hold
        if born
            .iter()
            .enumerate()
            .any(|(k, b)| b.0 as usize != before + k)
            || sets.num_slots() != before + born.len()
        {
            return None;
        }
        let mut nodes: Vec<u32> = sets.changed_nodes().collect();
        nodes.sort_unstable();
        nodes.dedup();
        if nodes.iter().any(|&n| self.acts[n as usize]) {
            return None;
        }
        // each slot's family: the slot that held its corners before this split
        let mut root: Vec<u32> = Vec::with_capacity(born.len());
        for &(_, from) in born {
            let r = match (from as usize).checked_sub(before) {
                Some(k) => root[k],
                None => from,
            };
            root.push(r);
        }
        let root_of = |s: u32| (s as usize).checked_sub(before).map_or(s, |k| root[k]);
        // the corners of each changed slot, in element order, the slots in family order (the
        // slot before the split first, then the new ones as numbered)
        let mut lists: Vec<(u32, u32, u32)> = Vec::new(); // (root, slot, corner)
        for &n in &nodes {
            let s = slot[n as usize];
            lists.extend(self.corners.of(n).iter().map(|&c| (root_of(s), s, c)));
        }
        lists.sort_unstable_by_key(|&(r, s, c)| (r, s != r, s, c));
        // each family fills the range its slot held: check first, then change
        let mut k = 0;
        while k < lists.len() {
            let r = lists[k].0;
            let n = lists[k..].iter().take_while(|l| l.0 == r).count();
            let (a, b) = (self.nptr[2 * r as usize], self.nptr[2 * r as usize + 1]);
            if (b - a) as usize != n {
                return None;
            }
            k += n;
        }
        let mut ch = Changes::default();
        let mut k = 0;
        while k < lists.len() {
            let r = lists[k].0;
            let mut at = self.nptr[2 * r as usize];
            ch.ninc
                .extend(at as usize..self.nptr[2 * r as usize + 1] as usize);
            while k < lists.len() && lists[k].0 == r {
                let s = lists[k].1 as usize;
                self.nptr[2 * s] = at;
                while k < lists.len() && lists[k].1 as usize == s {
                    self.ninc[at as usize] = lists[k].2;
                    at += 1;
                    k += 1;
                }
                self.nptr[2 * s + 1] = at;
                ch.nptr.extend([2 * s, 2 * s + 1]);
                ch.slots.push(s);
            }
        }
        // the slots' flags, the corners' slots
        let ne = self.emat.len();
        for &s in &ch.slots {
            self.nflag[s] = 0;
        }
        for &n in &nodes {
            let s = slot[n as usize] as usize;
            self.nflag[s] |= self.flag[n as usize];
            for &c in self.corners.of(n) {
                let i = (c as usize % 8) * ne + c as usize / 8;
                self.conn[i] = s as u32;
                ch.conn.push(i);
            }
        }
        ch.nflag.extend_from_slice(&ch.slots);
        // the elements that became loose
        for (e, (&now, was)) in sep.loose_elements().iter().zip(&mut self.loose).enumerate() {
            if now != *was {
                *was = now;
                self.emat[e] = self.emat_of[now as usize][e];
                ch.emat.push(e);
            }
        }
        // the interfaces released or holding a changed node
        let mut rows: Vec<u32> = released.to_vec();
        for &n in &nodes {
            rows.extend_from_slice(self.interfaces.of(n));
        }
        rows.sort_unstable();
        rows.dedup();
        for &i in &rows {
            let i = i as usize;
            let row = &mut self.ifu[IF_STRIDE * i..IF_STRIDE * (i + 1)];
            interface_row(sep, slot, i, row);
            ch.ifu.extend(IF_STRIDE * i..IF_STRIDE * (i + 1));
        }
        self.slots = sets.num_slots();
        Some(ch)
    }
}

/// Writes of many small ranges of buffers through one staging buffer: the values put one after
/// another, then a copy for each range, recorded in one command encoder (a `Queue::write_buffer`
/// for each range makes a staging buffer for each); and copies of ranges within a buffer. The
/// buffers are held by handle, so a step's writes can be gathered while the stepper changes and
/// recorded at the head of the submission that runs the rest of the step
/// (`GpuStepper::finish_step_after`).
#[derive(Default)]
pub(crate) struct Writes {
    data: Vec<u8>,
    /// (target, byte offset in it, byte offset in `data`, bytes)
    copies: Vec<(wgpu::Buffer, u64, u64, u64)>,
    /// Copies within a buffer, through a scratch buffer (a buffer is not copied to itself):
    /// (buffer, from, to, bytes), done in order before the writes.
    relays: Vec<(wgpu::Buffer, u64, u64, u64)>,
}

impl Writes {
    /// Write `values` into `buf` at byte `offset` (a multiple of 4, as the values' size).
    pub fn put<T: bytemuck::Pod>(&mut self, buf: &wgpu::Buffer, offset: u64, values: &[T]) {
        let bytes: &[u8] = bytemuck::cast_slice(values);
        if bytes.is_empty() {
            return;
        }
        debug_assert!(offset.is_multiple_of(4) && bytes.len().is_multiple_of(4));
        debug_assert!(offset + bytes.len() as u64 <= buf.size());
        let at = self.data.len() as u64;
        self.data.extend_from_slice(bytes);
        self.copies
            .push((buf.clone(), offset, at, bytes.len() as u64));
    }

    /// Copy `len` bytes of `buf` at byte `from` to byte `to` of it (multiples of 4), on the
    /// device, before the writes (and each after the relays put before it).
    pub fn relay(&mut self, buf: &wgpu::Buffer, from: u64, to: u64, len: u64) {
        self.relays.push((buf.clone(), from, to, len));
    }

    /// Record the relays, then the writes, in `enc` (they run after the queue's writes made
    /// before the submission of `enc`). On a device that has failed (its staging buffer cannot
    /// be mapped) nothing is recorded: the stepper reports the failure at its next check.
    pub fn record(self, gpu: &crate::device::Gpu, enc: &mut wgpu::CommandEncoder) {
        // the staging buffer first: where it cannot be mapped, nothing is recorded
        let staging = if self.copies.is_empty() {
            None
        } else {
            // (not `create_buffer_init`: it panics where the device is lost)
            let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("split writes"),
                size: (self.data.len() as u64).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT),
                usage: wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: true,
            });
            let Ok(mut view) = staging.slice(..).get_mapped_range_mut() else {
                return;
            };
            view.slice(..self.data.len()).copy_from_slice(&self.data);
            drop(view);
            staging.unmap();
            Some(staging)
        };
        if !self.relays.is_empty() {
            let scratch = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("split relays"),
                size: self.relays.iter().map(|r| r.3).sum(),
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut at = 0;
            for (buf, from, to, len) in self.relays {
                enc.copy_buffer_to_buffer(&buf, from, &scratch, at, len);
                enc.copy_buffer_to_buffer(&scratch, at, &buf, to, len);
                at += len;
            }
        }
        if let Some(staging) = staging {
            for (buf, offset, at, len) in self.copies {
                enc.copy_buffer_to_buffer(&staging, at, &buf, offset, len);
            }
        }
    }

    /// Submit the relays, then the writes (after the queue's writes before them), in a
    /// submission of their own.
    pub fn submit(self, gpu: &crate::device::Gpu) {
        if self.copies.is_empty() && self.relays.is_empty() {
            return;
        }
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        self.record(gpu, &mut enc);
        gpu.queue.submit([enc.finish()]);
    }
}

/// The runs of `idx` (indices into an array, any order, repeats allowed) to write: sorted, and
/// those less than `gap` apart joined (one write of a few values between two changed ones
/// costs less than a second write).
pub(crate) fn runs(mut idx: Vec<usize>, gap: usize) -> Vec<std::ops::Range<usize>> {
    idx.sort_unstable();
    idx.dedup();
    let mut out: Vec<std::ops::Range<usize>> = Vec::new();
    for i in idx {
        match out.last_mut() {
            Some(r) if i < r.end + gap => r.end = i + 1,
            _ => out.push(i..i + 1),
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use cleave_core::curve::Curve;
    use cleave_core::mesh::box_model;
    use cleave_core::model::{
        BodyLoad, Material, MaterialKind, MotionDof, MotionTarget, PrescribedMotion, SeparationDef,
        Spc, Vad, Window,
    };
    use cleave_core::separation::interfaces::{Separation, Status};
    use cleave_core::separation::split::split_model;

    /// A steel block (3 x 3 x 6 elements) clamped at its foot, its top driven down, sheared by
    /// its initial velocity and a body load (the GPU tests' cracking block, `tests/common`,
    /// written again: a unit test cannot reach the integration tests' helpers), every element in a MODEL 2 group of 250 MPa: interfaces fail
    /// over the run, some at the top, whose nodes carry a prescribed motion.
    pub(crate) fn cracking_block() -> cleave_core::model::Model {
        let steel = Material {
            id: 1,
            density: 7850.0,
            young: 210e9,
            poisson: 0.3,
            kind: MaterialKind::PlasticKinematic {
                sigy: 300e6,
                etan: 2e9,
                beta: 0.5,
            },
        };
        let mut m = box_model([3, 3, 6], [0.03, 0.03, 0.06], steel, 1.0);
        m.curves.push(Curve {
            id: 1,
            t: vec![0.0, 5e-6, 1.0],
            y: vec![0.0, 1.0, 1.0],
        });
        for (i, x) in m.x0.to_vec().iter().enumerate() {
            let n = i as u32;
            m.v0.as_mut_slice()[i] = [30.0 * x[2] / 0.06, 0.0, 0.0];
            if x[2] < 1e-9 {
                m.spcs.push(Spc {
                    node: n,
                    dof: [true, true, true, false, false, false],
                });
            } else if (x[2] - 0.06).abs() < 1e-9 {
                m.prescribed.push(PrescribedMotion {
                    window: Window::ALWAYS,
                    target: MotionTarget::Node(n),
                    dof: MotionDof::Axis(2),
                    vad: Vad::Velocity,
                    curve: 0,
                    sf: -40.0,
                });
            }
        }
        m.body_loads.push(BodyLoad {
            axis: 1,
            curve: Some(0),
            sf: 5e5,
        });
        m.separations.push(SeparationDef {
            material: 0,
            model: 2,
            sigmax: 250e6,
            beta: 0.7,
            gc: 0.0,
            bond: 1,
            strength: Default::default(),
        });
        let (dt, _) = cleave_core::setup::estimate_time_step(&m).unwrap();
        m.control.end_time = 200.0 * dt * m.control.tssfac;
        m
    }

    /// The arrays `r` holds are those of a layout made afresh for `solver`: the same
    /// connectivity, element slots, flags and interface table, and every slot's corners in
    /// the same order (where in `ninc` they lie may differ).
    fn same_as_afresh(r: &Relayout, solver: &Solver) {
        let fresh = Layout::new(
            solver.model,
            &solver.setup,
            solver.ties(),
            crate::separation::slots(solver),
        );
        assert_eq!(r.conn, by_component(&fresh.conn, 8));
        assert_eq!(r.emat, fresh.emat);
        assert_eq!(r.nflag, fresh.nflag);
        assert_eq!(r.ifu, crate::separation::interface_table(solver).0);
        let list = |l: &Layout, s: usize| {
            let (a, b) = (l.nptr[2 * s] as usize, l.nptr[2 * s + 1] as usize);
            l.ninc[a..b].to_vec()
        };
        let mine = Layout {
            nptr: r.nptr.clone(),
            ninc: r.ninc.clone(),
            ..Layout::default()
        };
        for s in 0..solver.separation().unwrap().sets().num_slots() {
            assert_eq!(list(&mine, s), list(&fresh, s), "slot {s}");
        }
    }

    /// Every split of the cracking block, done in place, gives the arrays a layout made afresh
    /// gives; the splits at its top, whose nodes carry a prescribed motion, are refused (made
    /// afresh), and both kinds occur.
    #[test]
    fn splits_in_place_give_the_arrays_made_afresh() {
        let split = split_model(&cracking_block());
        let mut s = Solver::new(&split.model).unwrap();
        s.attach_separation(Separation::new(&split).unwrap());
        let lay = Layout::new(s.model, &s.setup, s.ties(), crate::separation::slots(&s));
        let mut r = Relayout::new(&s, &lay).unwrap();
        let n_if = s.separation().unwrap().num_interfaces();
        let status = |s: &Solver| -> Vec<Status> {
            let sep = s.separation().unwrap();
            (0..n_if).map(|i| sep.status(i)).collect()
        };
        let (mut was, mut in_place, mut afresh) = (status(&s), 0, 0);
        while !s.is_finished() {
            s.advance_to_half_step().unwrap();
            let now = status(&s);
            let released: Vec<u32> = (0..n_if as u32)
                .filter(|&i| now[i as usize] != was[i as usize])
                .collect();
            if !released.is_empty() {
                if r.split(&s, &released).is_some() {
                    in_place += 1;
                } else {
                    afresh += 1;
                    let lay =
                        Layout::new(s.model, &s.setup, s.ties(), crate::separation::slots(&s));
                    r.reset(&s, &lay, crate::separation::interface_table(&s).0);
                }
                same_as_afresh(&r, &s);
            }
            was = now;
            s.update_positions().unwrap();
        }
        let failed = s.separation().unwrap().num_failed();
        eprintln!("{failed} interfaces failed: {in_place} splits in place, {afresh} made afresh");
        assert!(failed >= 20 && in_place >= 5 && afresh >= 1);
    }

    /// Writes recorded on a device that was lost neither panic (wgpu's `create_buffer_init`
    /// does where it cannot map its buffer) nor record anything; the stepper reports the loss
    /// at its next check.
    #[test]
    fn writes_on_a_lost_device_do_not_panic() {
        let g = match crate::device::Gpu::new() {
            Ok(g) => g,
            Err(e) => {
                eprintln!("SKIPPED: {e}");
                return;
            }
        };
        let buf = g.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: 64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        g.device.destroy();
        let mut w = Writes::default();
        w.put(&buf, 8, &[1.0f64, 2.0]);
        w.relay(&buf, 0, 32, 8);
        let mut enc = g.device.create_command_encoder(&Default::default());
        w.record(&g, &mut enc);
        g.queue.submit([enc.finish()]);
        g.wait();
        assert!(g.failure().is_some(), "the loss is known after a wait");
    }

    #[test]
    fn runs_join_near_indices() {
        assert_eq!(runs(vec![9, 3, 4, 4, 20, 5], 3), vec![3..6, 9..10, 20..21]);
        assert_eq!(runs(vec![9, 3, 5], 5), vec![3..10]);
        assert!(runs(vec![], 4).is_empty());
    }
}
