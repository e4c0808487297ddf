//! Element separation on the GPU (the paper's algorithm, cleave-core `separation/`).
//!
//! The GPU steps a split model by its coincident sets: its "nodes" are the sets' slots
//! ([`crate::layout::Slots`]), each moving with `a = sum f / sum m` over its members, and
//! every intact interface is checked against its group's criterion each step on the GPU
//! (step.wgsl `interfaces`). A step in which some reach their strength halts after the check;
//! the host then does what changes the topology, with the CPU's own code: it reads the failed
//! interfaces and their failure indices, releases them ([`Solver::release_interfaces`]: at
//! most one per element, in order of failure index, as on the CPU), splits the sets, rewrites
//! the arrays that depend on them (connectivity by slot, each slot's corners, masses,
//! constraints, loads, the loose elements' material slots, the interface table: in place, the
//! values of the sets that split alone, `crate::relayout`) and runs the rest of the step on
//! the GPU, which gathers the split sets' forces from the corner forces it
//! kept. So the pieces part in the step their interface fails, as on the CPU.
//!
//! Cohesive laws (MODELs 3 and 4): the softening faces live on the GPU ([`Cohesive`]); each
//! step a pass computes their tractions, forces, work and springs (before the time step, which
//! the springs bound), the nodes gather the forces per slot in the faces' order, and the host
//! takes their state up whenever it reads the GPU's (outputs, splits, restart files).
//!
//! With automatic contact the faces of the released interfaces join the surfaces in the same
//! halt, and their cracks close, on the host (`Solver::activate_cracks`), and the contact's
//! tables are made again (contact.rs).
//!
//! Rigid bodies run with it when their nodes are in no group (each node a slot of its own), and
//! erosion in the other materials (a material that both erodes and separates the deck reader
//! refuses): with contact, a step in which elements erode halts before the interfaces' check
//! (HALT 5, their faces leave the contact's surfaces, the closed cracks' states taken from the
//! GPU first), in the CPU's order, which erodes before it checks (with erosion in other
//! materials than the groups' the split reads nothing of it, so the order of the two halts of
//! such a step does not change the results). What the GPU does not run yet is refused
//! ([`crate::support::unsupported`], [`crate::support::unsupported_split`]): a rigid body
//! bonded to a group's nodes. (Tied contact and ELFORM 13 with separation the deck reader
//! refuses, for the CPU too.)

use cleave_core::element::shape::face_points;
use cleave_core::math::Vec3;
use cleave_core::separation::cohesive::Envelope;
use cleave_core::separation::interfaces::{Separation, Status};
use cleave_core::solver::{RunError, Solver};

use crate::layout::{by_component, by_element, Layout, Slots};
use crate::relayout::{runs, Writes};
use crate::stepper::{Control, GpuStepper, Part};

/// Values per interface in `ifu` (step.wgsl `IF_STRIDE`).
pub(crate) const IF_STRIDE: usize = 12;

/// The interface buffers (empty arrays and `n_if` 0 without separation).
pub(crate) struct SepBuffers {
    /// Per interface: its elements, group, 1 while intact, the slots of its 8 nodes.
    pub ifu: wgpu::Buffer,
    /// Strengths, each group's MODEL and BETA, then the failure indices of a step.
    pub ifs: wgpu::Buffer,
    /// The number of interfaces that failed in a step, then their numbers.
    pub ifl: wgpu::Buffer,
    pub n_if: u32,
    /// Where the failure indices start in `ifs`.
    pub if_index: u32,
    /// The groups of the cohesive pass (an indirect dispatch).
    pub coh_groups: wgpu::Buffer,
    /// The most softening faces there can be (interfaces of groups with a cohesive law).
    pub coh_cap: u32,
    /// The softening faces ([`Cohesive`]): where `cix` starts in `ifu`, where its entries and
    /// slots start in it (0 without cohesive laws), where `coh` starts in `ifs`.
    pub c_ptr: u32,
    pub c_inc: u32,
    pub c_slots: u32,
    pub c_coh: u32,
}

/// Values per softening face in `coh` (step.wgsl `CO_STRIDE`).
const CO_STRIDE: usize = 58;

/// The softening faces of the cohesive laws (MODELs 3 and 4) as the GPU keeps them (step.wgsl,
/// "cohesive laws"): each face's law and state in `coh`, in the order the host's separation
/// holds them (the order of release; a face that opens fully stays in place, marked free, so
/// the order and the sums over it do not depend on when the host looks), and per slot the
/// points whose force it takes, in `cix`.
pub(crate) struct Cohesive {
    pub coh: Vec<f64>,
    pub cix: Vec<u32>,
    /// Capacity, faces now, slots with entries now.
    pub cap: u32,
    pub faces: u32,
    pub slots: u32,
    pub c_inc: u32,
    pub c_slots: u32,
}

impl Cohesive {
    pub fn of(solver: &Solver) -> Self {
        let mut out = Self {
            coh: Vec::new(),
            cix: Vec::new(),
            cap: 0,
            faces: 0,
            slots: 0,
            c_inc: 0,
            c_slots: 0,
        };
        let Some(sep) = solver.separation() else {
            return out;
        };
        let laws: Vec<bool> = (solver.model.separations.iter())
            .map(|d| d.model >= 3)
            .collect();
        let n_if = sep.num_interfaces();
        let cap = (sep.faces()[..n_if].iter())
            .filter(|f| laws[f.group as usize])
            .count();
        if cap == 0 {
            return out;
        }
        let nn = solver.model.num_nodes();
        let slots = sep.sets().slots();
        let faces = sep.cohesive_faces();
        let mut coh = vec![0.0; CO_STRIDE * cap];
        // (slot, entry) of each point of each softening face, in the faces' order
        let mut entries: Vec<(u32, u32)> = Vec::new();
        for (k, c) in faces.iter().enumerate() {
            let face = &sep.faces()[c.interface as usize];
            let points = face_points(&std::array::from_fn(|j| face.nodes[j]));
            let free = sep.status(c.interface as usize) != Status::Softening;
            let law = &c.law;
            let row = &mut coh[CO_STRIDE * k..CO_STRIDE * (k + 1)];
            row[..6].copy_from_slice(&[
                f64::from(c.interface),
                law.sigmax,
                law.beta,
                law.delta_c,
                match law.envelope {
                    Envelope::Linear => 0.0,
                    Envelope::Exponential => 1.0,
                },
                law.delta_open(),
            ]);
            row[6..10].copy_from_slice(&c.softened);
            row[10..13].copy_from_slice(&c.t0);
            row[13..16].copy_from_slice(&[c.k_max, face.area0, points as f64]);
            row[16..28].copy_from_slice(c.d_prev.as_flattened());
            row[28..40].copy_from_slice(c.f_prev.as_flattened());
            row[40] = free as u8 as f64;
            if free {
                continue;
            }
            for p in 0..points {
                for side in 0..2 {
                    let node = face.nodes[4 * side + p];
                    let e = 8 * k as u32 + 2 * p as u32 + side as u32;
                    entries.push((slots[node as usize], e));
                }
            }
        }
        // per slot, its entries in that order
        let mut cptr = vec![0u32; nn + 1];
        for &(s, _) in &entries {
            cptr[s as usize + 1] += 1;
        }
        for i in 0..nn {
            cptr[i + 1] += cptr[i];
        }
        let mut fill = cptr.clone();
        let mut cinc = vec![0u32; 8 * cap];
        for &(s, e) in &entries {
            let at = &mut fill[s as usize];
            cinc[*at as usize] = e;
            *at += 1;
        }
        let mut touched: Vec<u32> = entries.iter().map(|&(s, _)| s).collect();
        touched.sort_unstable();
        touched.dedup();
        out.slots = touched.len() as u32;
        touched.resize(8 * cap, 0);
        out.c_inc = (nn + 1) as u32;
        out.c_slots = out.c_inc + 8 * cap as u32;
        out.cix = [cptr, cinc, touched].concat();
        out.coh = coh;
        out.cap = cap as u32;
        out.faces = faces.len() as u32;
        out
    }

    /// The groups of the cohesive pass.
    pub fn groups(&self) -> [u32; 3] {
        crate::stepper::group_grid((self.faces as usize).div_ceil(crate::stepper::GROUP))
    }
}

/// The split model's sets as the layout takes them; `None` without separation.
pub(crate) fn slots<'a>(solver: &'a Solver) -> Option<Slots<'a>> {
    solver.separation().map(|sep| Slots {
        of: sep.sets().slots(),
        loose: sep.loose_elements(),
    })
}

/// Positions, velocities (flat, 3 per entry) and masses as the GPU keeps them: one entry per
/// node, or with separation per slot of the coincident sets, with `padded` padded with zeros
/// to one per node (the passes skip the unused slots, [`entries`]).
pub(crate) fn kinematics(solver: &Solver, padded: bool) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let nn = if padded {
        solver.model.num_nodes()
    } else {
        entries(solver) as usize
    };
    let flat = |v: &[Vec3]| {
        let mut f: Vec<f64> = v.iter().flatten().copied().collect();
        f.resize(3 * nn, 0.0);
        f
    };
    let x = flat(solver.positions().entries());
    let v = flat(solver.half_step_velocities().entries());
    let mut mass = solver.slot_masses().unwrap_or(&solver.setup.mass).to_vec();
    mass.resize(nn, 0.0);
    (x, v, mass)
}

/// The node entries in use (`cf[SLOTS]`): every node, or the slots of the coincident sets
/// (the entries past them have no mass and are skipped).
pub(crate) fn entries(solver: &Solver) -> f64 {
    solver.positions().entries().len() as f64
}

/// The groups of the per-node passes: enough for the entries in use ([`entries`]).
pub(crate) fn node_grid(solver: &Solver) -> [u32; 3] {
    crate::stepper::group_grid((entries(solver) as usize).div_ceil(crate::stepper::GROUP))
}

/// The interface table (`ifu`, `ifs`, the number of interfaces, the offset of the failure
/// indices in `ifs`) of the solver's separation as it stands.
pub(crate) fn interface_table(solver: &Solver) -> (Vec<u32>, Vec<f64>, u32, u32) {
    let Some(sep) = solver.separation() else {
        return (Vec::new(), Vec::new(), 0, 0);
    };
    let n = sep.num_interfaces();
    let slots = sep.sets().slots();
    let mut ifu = Vec::with_capacity(IF_STRIDE * n);
    let mut ifs = Vec::with_capacity(3 * n);
    ifu.resize(IF_STRIDE * n, 0);
    for (i, (face, row)) in (sep.faces()[..n].iter())
        .zip(ifu.chunks_exact_mut(IF_STRIDE))
        .enumerate()
    {
        interface_row(sep, slots, i, row);
        ifs.push(face.strength);
    }
    for d in &solver.model.separations {
        ifs.extend_from_slice(&[f64::from(d.model), d.beta]);
    }
    let if_index = ifs.len() as u32;
    ifs.resize(ifs.len() + n, 0.0);
    (ifu, ifs, n as u32, if_index)
}

/// Interface `i`'s row of `ifu` (`IF_STRIDE` values) as the separation stands, `slots` its
/// sets' slot of each node: its elements, group, 1 while intact, the slots of its 8 nodes.
pub(crate) fn interface_row(sep: &Separation, slots: &[u32], i: usize, row: &mut [u32]) {
    let face = &sep.faces()[i];
    let intact = sep.status(i) == Status::Intact;
    row[..4].copy_from_slice(&[
        face.elems[0],
        face.elems[1],
        u32::from(face.group),
        intact as u32,
    ]);
    for (v, &k) in row[4..].iter_mut().zip(&face.nodes) {
        *v = slots[k as usize];
    }
}

/// The node of entry `k` of the GPU's node arrays: `k` itself, or with separation the first
/// node of slot `k` (for messages).
pub(crate) fn node_of_entry(solver: &Solver, k: u32) -> usize {
    match (solver.separation(), solver.slot_masses()) {
        (Some(sep), Some(_)) => (sep.sets().slots().iter())
            .position(|&s| s == k)
            .unwrap_or(k as usize),
        _ => k as usize,
    }
}

impl GpuStepper {
    /// Write the arrays that depend on the coincident sets from the solver's separation as it
    /// stands: the layout by slot, the masses, positions and velocities (per slot), the
    /// interface table; and empty the failure list. The copy of the arrays a split changes in
    /// place ([`crate::relayout::Relayout`]) is taken from them.
    pub(crate) fn upload_sets(&mut self, solver: &Solver, step: f64) {
        let lay = Layout::new(solver.model, &solver.setup, solver.ties(), slots(solver));
        let q = &self.gpu().queue;
        let b = &self.model_bufs;
        let f64s = |buf: &wgpu::Buffer, d: &[f64]| {
            debug_assert!(8 * d.len() as u64 <= buf.size());
            q.write_buffer(buf, 0, bytemuck::cast_slice(d));
        };
        let u32s = |buf: &wgpu::Buffer, d: &[u32]| {
            debug_assert!(4 * d.len() as u64 <= buf.size());
            q.write_buffer(buf, 0, bytemuck::cast_slice(d));
        };
        // (the layout keeps its sizes: one slot per node, both material slots of each element)
        f64s(&b.par, &lay.par);
        u32s(&b.conn, &by_component(&lay.conn, 8));
        u32s(&b.emat, &lay.emat);
        u32s(&b.nptr, &lay.nptr);
        u32s(&b.ninc, &lay.ninc);
        u32s(&b.nflag, &lay.nflag);
        u32s(&b.mptr, &lay.mptr);
        // the entries in use only: no pass reads those past them (the node passes stop at
        // `cf[SLOTS]`, the others reach nodes through the layout's slots)
        let (x, v, mass) = kinematics(solver, false);
        f64s(&b.mass, &mass);
        // (x^n, in the half of the positions of step `step`)
        q.write_buffer(
            &self.state.x,
            8 * self.x_half(step).start as u64,
            bytemuck::cast_slice(&x),
        );
        f64s(&self.state.v, &v);
        // v^n: the solver's own (the GPU's v^n of a slot is only used within a step)
        let vn: Vec<f64> = (solver.velocities().entries().iter().flatten().copied()).collect();
        f64s(&self.state.vn, &vn);
        let (ifu, ifs, _, _) = interface_table(solver);
        u32s(&self.sep.ifu, &ifu);
        f64s(&self.sep.ifs, &ifs);
        let mut w = Writes::default();
        self.upload_set_counts(solver, &mut w);
        w.submit(self.gpu());
        if let Some(r) = &mut self.relayout {
            r.reset(solver, &lay, ifu);
        }
    }

    /// Write what a split changed in place ([`crate::relayout::Relayout::split`]; `released`:
    /// the interfaces listed as failed in it, the released among them), or when it cannot be
    /// changed in place, everything ([`Self::upload_sets`]). The new slots' positions and
    /// velocities are their sets', copied on the device; `fresh`: the host's mirror holds this
    /// step's (read back for a cohesive law), else it is read back first when everything is
    /// written. What a split changes in place is put in `w`, for the submission of the rest of
    /// the step; otherwise `w` is submitted first.
    pub(crate) fn upload_split(
        &mut self,
        solver: &mut Solver,
        step: f64,
        released: &[u32],
        fresh: bool,
        w: &mut Writes,
    ) {
        let born: Vec<(u32, u32)> = solver
            .separation()
            .map_or(vec![], |s| s.sets().born().to_vec());
        let x_at = 8 * self.x_half(step).start as u64;
        for &(new, from) in &born {
            let (new, from) = (24 * u64::from(new), 24 * u64::from(from));
            for (buf, at) in [
                (&self.state.x, x_at),
                (&self.state.v, 0),
                (&self.state.vn, 0),
            ] {
                w.relay(buf, at + from, at + new, 24);
            }
        }
        let Some(ch) = (self.relayout.as_mut()).and_then(|r| r.split(solver, released)) else {
            std::mem::take(w).submit(self.gpu());
            if !fresh {
                self.mirror_kinematics(solver, step);
            }
            self.upload_sets(solver, step);
            return;
        };
        let r = self.relayout.as_ref().expect("the arrays a split changes");
        let b = &self.model_bufs;
        // each array's changed values, in runs (a few unchanged values between two changed
        // ones are written again rather than cost a copy of their own), all in one staging
        // buffer: a write of its own for each run made a staging buffer for each
        const GAP: usize = 1024;
        for (buf, data, idx) in [
            (&b.conn, &r.conn, ch.conn),
            (&b.emat, &r.emat, ch.emat),
            (&b.nptr, &r.nptr, ch.nptr),
            (&b.ninc, &r.ninc, ch.ninc),
            (&b.nflag, &r.nflag, ch.nflag),
            (&self.sep.ifu, &r.ifu, ch.ifu),
        ] {
            for run in runs(idx, GAP) {
                w.put(buf, 4 * run.start as u64, &data[run]);
            }
        }
        // the split sets' pieces' masses (their positions and velocities are on the device:
        // those of the slots they keep, and of the new ones copied above)
        let mass = solver.slot_masses().expect("masses per slot");
        for run in runs(ch.slots, GAP) {
            w.put(&b.mass, 8 * run.start as u64, &mass[run]);
        }
        self.upload_set_counts(solver, w);
    }

    /// Write what follows the number of sets: the failure list emptied, the softening faces
    /// (with a cohesive law), the entries in use and the node passes' groups, into `w`.
    fn upload_set_counts(&self, solver: &Solver, w: &mut Writes) {
        w.put(&self.sep.ifl, 0, &[0u32]);
        if self.sep.coh_cap > 0 {
            let co = Cohesive::of(solver);
            w.put(&self.sep.ifs, 8 * u64::from(self.sep.c_coh), &co.coh);
            w.put(&self.sep.ifu, 4 * u64::from(self.sep.c_ptr), &co.cix);
            w.put(&self.sep.coh_groups, 0, &co.groups());
            w.put(
                &self.cu,
                (4 * crate::stepper::cu::N_COH) as u64,
                &[co.faces],
            );
            w.put(
                &self.cu,
                (4 * crate::stepper::cu::N_CSLOT) as u64,
                &[co.slots],
            );
        }
        w.put(
            &self.cf,
            (crate::stepper::cf::SLOTS * 8) as u64,
            &[entries(solver)],
        );
        w.put(&self.node_groups, 0, &node_grid(solver));
    }

    /// The rows of the softening faces the host knows in `ifs` (with a cohesive law; none
    /// without), to read back with the kinematics.
    pub(crate) fn cohesive_part(&self, solver: &Solver) -> Option<Part<'_>> {
        let sep = solver.separation().filter(|_| self.sep.coh_cap > 0)?;
        let ifs = &self.sep.ifs;
        let from = 8 * u64::from(self.sep.c_coh);
        let rows = (8 * CO_STRIDE * sep.cohesive_faces().len()) as u64;
        Some((ifs, from, rows.min(ifs.size() - from)))
    }

    /// Take up the softening faces' state read back (`rows`, [`Self::cohesive_part`]) into the
    /// host's separation (their largest openings, last openings and forces; the fully open ones
    /// marked free).
    pub(crate) fn import_cohesive(&self, solver: &mut Solver, rows: &[u8]) {
        let Some(sep) = solver.separation_mut() else {
            return;
        };
        let coh: Vec<f64> = bytemuck::pod_collect_to_vec(rows);
        let mut open = Vec::new();
        for (k, c) in sep.cohesive_faces_mut().iter_mut().enumerate() {
            let row = &coh[CO_STRIDE * k..CO_STRIDE * (k + 1)];
            c.softened.copy_from_slice(&row[6..10]);
            for p in 0..4 {
                c.d_prev[p].copy_from_slice(&row[16 + 3 * p..19 + 3 * p]);
                c.f_prev[p].copy_from_slice(&row[28 + 3 * p..31 + 3 * p]);
            }
            if row[40] != 0.0 {
                open.push(c.interface as usize);
            }
        }
        for i in open {
            sep.mark_open(i);
        }
    }

    /// The GPU halted in a step in which interfaces reached their strength: release them on
    /// the host (the CPU's rules), rewrite what the split sets change, and run the rest of the
    /// step.
    pub(crate) fn split(&mut self, solver: &mut Solver, c: &Control) -> Result<(), RunError> {
        // One read-back: the head of the failure list and of their indices; what the release
        // reads with a cohesive law (the positions, velocities and stresses: the onset
        // traction and opening; without one it reads none, the new slots get their sets'
        // positions and velocities on the device, and the host's mirror waits for the next
        // output, the contact's grid cell taken from the positions it holds, which changes the
        // speed only); with contact what its remake reads
        let began = std::time::Instant::now();
        let (ifl, ifs, sig) = (&self.sep.ifl, &self.sep.ifs, &self.state.sig);
        let head = u64::from(self.sep.n_if).min(self.list_head);
        let index_at = 8 * u64::from(self.sep.if_index);
        let cohesive = self.sep.coh_cap > 0;
        let mut parts = match cohesive {
            true => self.kinematics_parts(solver, c.step()),
            false => vec![],
        };
        let k = parts.len();
        parts.extend([(ifl, 0, 4 * (1 + head)), (ifs, index_at, 8 * head)]);
        if cohesive {
            parts.push((sig, 0, sig.size()));
        }
        let contact = parts.len();
        parts.extend(self.contact_parts());
        let got = self.download_ranges(&parts);
        let read = began.elapsed().as_secs_f64();
        // (nothing of a failed device's read is taken into the host's state)
        if let Some(e) = self.failed(solver) {
            return Err(e);
        }
        if cohesive {
            self.take_kinematics(solver, &got[..k]);
        }
        if cohesive {
            let sig = by_element(&bytemuck::pod_collect_to_vec::<u8, f64>(&got[k + 2]), 6);
            for (e, s) in solver.state.stress.iter_mut().enumerate() {
                s.copy_from_slice(&sig[6 * e..6 * e + 6]);
            }
        }
        c.apply(solver);
        let mut list: Vec<u32> = bytemuck::pod_collect_to_vec(&got[k]);
        let mut index_of: Vec<f64> = bytemuck::pod_collect_to_vec(&got[k + 1]);
        // (bounded by the table whatever was read)
        let count = (list[0] as usize).min(self.sep.n_if as usize);
        if count as u64 > head {
            // the rest of a long list
            let rest = (count as u64 - head) as usize;
            let more = self.download_ranges(&[
                (ifl, 4 * (1 + head), 4 * rest as u64),
                (ifs, index_at + 8 * head, 8 * rest as u64),
            ]);
            if let Some(e) = self.failed(solver) {
                return Err(e);
            }
            list.extend(bytemuck::pod_collect_to_vec::<u8, u32>(&more[0]));
            index_of.extend(bytemuck::pod_collect_to_vec::<u8, f64>(&more[1]));
        }
        let found: Vec<(f32, u32)> = (list[1..=count].iter().zip(&index_of))
            .map(|(&i, &index)| (index as f32, i))
            .collect();
        if let Err(e) = solver.release_interfaces(&found) {
            return Err(self.internal(solver, format!("its interface table is out of date: {e}")));
        }
        let released: Vec<u32> = found.iter().map(|f| f.1).collect();
        // what the split changes, written at the head of the submission of the rest of the
        // step (one staging buffer and one submission for the whole halt)
        let mut w = Writes::default();
        self.upload_split(solver, c.step(), &released, cohesive, &mut w);
        // with contact (each a no-op without): the new crack faces join the surfaces and the
        // cracks close on the host, whose closed cracks take the GPU's states first; the
        // contact's tables made again
        if let Some(clo) = got.get(contact) {
            self.closures_to_host(solver, clo, false)?;
        }
        solver.activate_cracks();
        let carried = got.get(contact + 1..).unwrap_or(&[]);
        let remade = std::time::Instant::now();
        self.remake_contact(solver, true, carried, Some(&mut w))?;
        let tables = remade.elapsed().as_secs_f64();
        self.clear_halt_into(&mut w);
        self.finish_step_after("interfaces_done", w);
        let all = began.elapsed().as_secs_f64();
        for (s, t) in self
            .split_parts
            .iter_mut()
            .zip([read, tables, all - read - tables])
        {
            *s += t;
        }
        Ok(())
    }
}
