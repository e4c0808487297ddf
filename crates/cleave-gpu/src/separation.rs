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
//! constraints, loads, the loose elements' material slots, the interface table) and runs the
//! rest of the step on the GPU, which gathers the split sets' forces from the corner forces it
//! kept. So the pieces part in the step their interface fails, as on the CPU.
//!
//! What the GPU does not run yet is refused ([`crate::support::unsupported`]): cohesive laws
//! (MODELs 3 and 4), contact, rigid bodies, tied contact, erosion or ELFORM 13 with separation.

use cleave_core::math::Vec3;
use cleave_core::separation::interfaces::Status;
use cleave_core::solver::{RunError, Solver};

use crate::layout::{Layout, Slots};
use crate::stepper::{Control, GpuStepper};

/// Values per interface in `ifu` (step.wgsl `IF_STRIDE`).
const IF_STRIDE: usize = 12;

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
}

/// The split model's sets as the layout takes them; `None` without separation.
pub(crate) fn slots<'a>(solver: &'a Solver) -> Option<Slots<'a>> {
    solver.separation().map(|sep| Slots {
        of: sep.sets().slots(),
        loose: sep.loose_elements(),
    })
}

/// Positions, velocities (flat, 3 per entry) and masses as the GPU keeps them: one entry per
/// node, or with separation per slot of the coincident sets, padded with zeros to one per node
/// (the passes skip the unused slots, [`entries`]).
pub(crate) fn kinematics(solver: &Solver) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let nn = solver.model.num_nodes();
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
    for (i, face) in sep.faces()[..n].iter().enumerate() {
        let intact = sep.status(i) == Status::Intact;
        ifu.extend_from_slice(&[
            face.elems[0],
            face.elems[1],
            u32::from(face.group),
            intact as u32,
        ]);
        ifu.extend(face.nodes.iter().map(|&k| slots[k as usize]));
        ifs.push(face.strength);
    }
    for d in &solver.model.separations {
        ifs.extend_from_slice(&[f64::from(d.model), d.beta]);
    }
    let if_index = ifs.len() as u32;
    ifs.resize(ifs.len() + n, 0.0);
    (ifu, ifs, n as u32, if_index)
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
    /// interface table; and empty the failure list.
    pub(crate) fn upload_sets(&self, solver: &Solver) {
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
        u32s(&b.conn, &lay.conn);
        u32s(&b.emat, &lay.emat);
        u32s(&b.nptr, &lay.nptr);
        u32s(&b.ninc, &lay.ninc);
        u32s(&b.nflag, &lay.nflag);
        u32s(&b.mptr, &lay.mptr);
        let (x, v, mass) = kinematics(solver);
        f64s(&b.mass, &mass);
        f64s(&self.state.x, &x);
        f64s(&self.state.v, &v);
        // v^n: the solver's own (the GPU's v^n of a slot is only used within a step)
        let mut vn: Vec<f64> = (solver.velocities().entries().iter().flatten().copied()).collect();
        vn.resize(x.len(), 0.0);
        f64s(&self.state.vn, &vn);
        let (ifu, ifs, _, _) = interface_table(solver);
        u32s(&self.sep.ifu, &ifu);
        f64s(&self.sep.ifs, &ifs);
        u32s(&self.sep.ifl, &[0]);
        q.write_buffer(
            &self.cf,
            (crate::stepper::cf::SLOTS * 8) as u64,
            bytemuck::bytes_of(&entries(solver)),
        );
        q.write_buffer(
            &self.node_groups,
            0,
            bytemuck::cast_slice(&node_grid(solver)),
        );
    }

    /// The GPU halted in a step in which interfaces reached their strength: release them on
    /// the host (the CPU's rules), rewrite what the split sets change, and run the rest of the
    /// step.
    pub(crate) fn split(&mut self, solver: &mut Solver, c: &Control) -> Result<(), RunError> {
        self.mirror(solver, c);
        let list: Vec<u32> = bytemuck::pod_collect_to_vec(&self.download_bytes(&self.sep.ifl));
        let ifs = self.download(&self.sep.ifs);
        let count = list[0] as usize;
        let found: Vec<(f32, u32)> = list[1..=count]
            .iter()
            .map(|&i| (ifs[self.sep.if_index as usize + i as usize] as f32, i))
            .collect();
        solver.release_interfaces(&found).map_err(|e| {
            RunError::Output(std::io::Error::other(format!(
                "the GPU's interface table is out of date: {e}"
            )))
        })?;
        self.upload_sets(solver);
        self.clear_halt();
        self.finish_step_after("interfaces_done");
        Ok(())
    }
}
