//! The host side of the GPU step: buffers, pipelines, batches of steps, read-back.
//!
//! The GPU holds the state; a [`Solver`] on the host holds the model, the setup and a mirror of
//! the state that is filled from the GPU whenever the observer is due, so every output of the
//! CPU run (ParaView states, histories, energies) is written by the same code.
//!
//! Steps are recorded in batches, two in flight: while the GPU runs one, the host records the
//! next. A step that is due for output (or the last, or a failing one) sets a halt flag that
//! turns every later dispatch into a no-op, so a batch recorded past it changes nothing and the
//! host reads the state of exactly that step.

use std::time::Instant;

use cleave_core::error::SolverError;
use cleave_core::material::SolidLaw;
use cleave_core::math::Vec3;
use cleave_core::solver::{Observer, RunError, Solver};
use wgpu::util::DeviceExt;

use crate::contact::ContactGpu;
use crate::device::{Gpu, GpuError};
use crate::layout::{by_component, by_element, Layout, RB_STATE};
use crate::pass_times::PassTimes;
use crate::relayout::Writes;
use crate::separation::{kinematics, SepBuffers};

/// The groups of `groups` threads' dispatch: (x, y), a second dimension past the per-dimension
/// limit.
pub(crate) fn group_grid(groups: usize) -> [u32; 3] {
    let x = groups.clamp(1, MAX_DIM);
    [x as u32, groups.div_ceil(MAX_DIM).max(1) as u32, 1]
}

/// How many groups a pass runs.
#[derive(Clone, Copy)]
enum Groups {
    Fixed(usize),
    /// One thread per node entry in use (`cf[SLOTS]`): the groups are read from the
    /// `node_groups` buffer (an indirect dispatch), which the host rewrites when sets split.
    Nodes,
    /// One thread per softening face (`cu[N_COH]`, the `coh_groups` buffer).
    Cohesive,
    /// Contact pass k (contact.rs PASSES): its groups over the contact's present tables.
    Contact(usize),
}

/// One pass of the step: its entry point, pipeline and groups.
struct Pass {
    name: &'static str,
    pipeline: wgpu::ComputePipeline,
    groups: Groups,
    /// A pass of contact.wgsl, with the contact's bind group.
    contact: bool,
}

/// Control floats (`cf` in step.wgsl).
pub(crate) mod cf {
    pub const T: usize = 0;
    pub const DT_PREV: usize = 1;
    pub const DT: usize = 2;
    pub const STEP: usize = 3;
    pub const DT_FLOOR: usize = 4;
    pub const E_INT: usize = 5;
    pub const E_HG: usize = 6;
    pub const E_KIN: usize = 7;
    pub const E_EXT: usize = 8;
    pub const E_INIT: usize = 10;
    pub const T_STOP: usize = 11;
    pub const TSSFAC: usize = 18;
    pub const DT_INIT: usize = 19;
    pub const DT_MIN: usize = 20;
    pub const END_TIME: usize = 21;
    pub const HALTED: usize = 22;
    pub const PENDING: usize = 23;
    pub const COMMIT_DUE: usize = 24;
    pub const SLOTS: usize = 25;
    pub const E_ERODED: usize = 29;
    pub const E_FRAC: usize = 31;
    pub const WALL_FORCE: usize = 32;
    pub const E_CONTACT: usize = 64;
    pub const DT_CONTACT: usize = 65;
    pub const LEN: usize = 66;
}

/// Control integers (`cu` in step.wgsl).
pub(crate) mod cu {
    pub const HALT: usize = 0;
    pub const ERROR: usize = 1;
    pub const INVERTED: usize = 2;
    pub const NONFINITE: usize = 3;
    pub const DT_ELEM: usize = 4;
    pub const N_COH: usize = 5;
    pub const FINISHED: usize = 6;
    pub const N_CSLOT: usize = 7;
    // 8: ERODED_NOW (step.wgsl erosion_done)
    pub const LEN: usize = 9;
}

const CTL_BYTES: u64 = (cf::LEN * 8 + cu::LEN * 4) as u64;
/// Threads of a group in the per-element and per-node kernels.
pub(crate) const GROUP: usize = 64;

/// Most bytes [`GpuStepper::download_ranges`] reads back through one staging buffer (256 MiB: the
/// mirror of a few million elements' state in a few reads, not one buffer of its whole size).
const READ_BACK: u64 = 1 << 28;

/// Largest read-back buffer kept from one read to the next (4 MiB: a split's read of a large
/// breaking model, not the mirror of a large state).
const KEEP_READ_BACK: u64 = 1 << 22;
/// The most groups one dispatch dimension takes (WebGPU's guaranteed limit).
const MAX_DIM: usize = 65535;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    ne: u32,
    nn: u32,
    groups_e: u32,
    groups_n: u32,
    n_body: u32,
    body_off: u32,
    mot_off: u32,
    n_rigid: u32,
    n_walls: u32,
    wall_off: u32,
    n_part: u32,
    rb_off: u32,
    erosion: u32,
    n_ties: u32,
    tie_off: u32,
    n_if: u32,
    if_index: u32,
    c_ptr: u32,
    c_inc: u32,
    c_slots: u32,
    c_coh: u32,
    dt_max_off: u32,
    pad: u32,
}

/// The state arrays read back for output, in their binding order.
pub(crate) struct StateBuffers {
    pub x: wgpu::Buffer,
    pub v: wgpu::Buffer,
    pub vn: wgpu::Buffer,
    pub sig: wgpu::Buffer,
    hist: wgpu::Buffer,
    hg: wgpu::Buffer,
    bq: wgpu::Buffer,
}

/// A model on the GPU, ready to step.
pub struct GpuStepper {
    gpu: Gpu,
    /// The step's passes in order, each with its entry point and number of groups.
    pipelines: Vec<Pass>,
    /// The end of a step that halted, and the body loads at the start: first in each batch.
    commit: wgpu::ComputePipeline,
    /// Bytes of the buffers on the device.
    device_bytes: u64,
    /// The buffers that carry the state from one step to the next, in the order of
    /// [`Self::save`], each with how it is stored.
    persistent: Vec<(wgpu::Buffer, Stored)>,
    /// Values of the positions of one step (3 per node entry); the buffer holds two steps'
    /// (step.wgsl halves).
    x_len: usize,
    /// The pass that writes x^(n+1) from x^n and v^(n+1/2), after a restart file is taken up.
    positions: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    pub(crate) cf: wgpu::Buffer,
    pub(crate) cu: wgpu::Buffer,
    pub(crate) state: StateBuffers,
    ctl_staging: [wgpu::Buffer; 2],
    /// The rigid bodies' states (read back with the rest).
    rb: wgpu::Buffer,
    /// Per element: eroded, its energy, Johnson-Cook damage (when the model erodes).
    ero: Option<wgpu::Buffer>,
    /// Steps recorded in one submission (grown while a batch takes under 20 ms).
    pub batch: usize,
    /// The model's arrays ([`Layout`]) and the masses: rewritten when coincident sets split.
    pub(crate) model_bufs: ModelBuffers,
    /// Element separation: the interfaces (their number is 0 without).
    pub(crate) sep: SepBuffers,
    /// The groups of the per-node passes ([`group_grid`] of the entries in use), read by their
    /// indirect dispatches.
    pub(crate) node_groups: wgpu::Buffer,
    /// The arrays bound in parts (split.rs): name and number of chunks.
    split: Vec<(String, usize)>,
    /// Automatic contact (contact.rs), when the deck has some.
    contact: Option<ContactGpu>,
    /// With element separation: the arrays a split changes, kept to change them in place
    /// (relayout.rs).
    pub(crate) relayout: Option<crate::relayout::Relayout>,
    /// The failures of a step read back with the rest of a split's one read-back (a step in
    /// which more fail reads the others in a second one).
    pub(crate) list_head: u64,
    /// For tests: the device is destroyed as the read of the state this many reads on starts
    /// (0: never; [`Self::lose_device_in_read`]).
    lose_in_read: std::cell::Cell<u32>,
    /// The read-back buffer kept between reads ([`Self::download_ranges`]).
    read_back: std::cell::RefCell<Option<wgpu::Buffer>>,
    /// Each pass timed over the run, when asked ([`Self::time_passes`]).
    times: Option<PassTimes>,
    /// The halts for the host in a step ([`Self::host_halts`]): count and wall seconds.
    halts: [(u64, f64); 3],
    /// The splits' wall seconds by part ([`Self::split_parts`]).
    pub(crate) split_parts: [f64; 3],
}

/// How a buffer that carries the state is stored on the device, and so turned for a restart
/// file (which holds every array as the host does: by element, and one step's positions).
#[derive(Clone, Copy)]
enum Stored {
    AsIs,
    /// An element array of this many values per element, by component (layout.rs
    /// by_component).
    ByComponent(usize),
    /// The positions of two steps, x^n in the half of the step's parity (step.wgsl halves).
    Positions,
}

/// The buffers of the model's arrays that a split rewrites ([`Layout`], per slot).
pub(crate) struct ModelBuffers {
    pub par: wgpu::Buffer,
    pub conn: wgpu::Buffer,
    pub emat: wgpu::Buffer,
    pub mass: wgpu::Buffer,
    pub nptr: wgpu::Buffer,
    pub ninc: wgpu::Buffer,
    pub nflag: wgpu::Buffer,
    pub mptr: wgpu::Buffer,
}

fn control_block(solver: &Solver) -> [f64; cf::LEN] {
    let c = &solver.model.control;
    let mut f = [0.0; cf::LEN];
    f[cf::SLOTS] = crate::separation::entries(solver);
    f[cf::TSSFAC] = c.tssfac;
    f[cf::DT_INIT] = c.dt_init;
    f[cf::DT_MIN] = c.dt_min;
    f[cf::END_TIME] = c.end_time;
    f[cf::E_CONTACT] = solver.state.energy.contact;
    let dt_contact = solver.contact_time_step();
    f[cf::DT_CONTACT] = if dt_contact.is_finite() {
        dt_contact
    } else {
        f64::MAX
    };
    f
}

/// The step's shader text: the contact forces' reader (contact.rs step_prefix), the model's
/// constants (layout.rs shader_constants), the shared math, then step.wgsl.
pub(crate) fn step_source(lay: &Layout, erodes: bool, walls: usize, contact: bool) -> String {
    crate::contact::step_prefix(contact).to_string()
        + &lay.shader_constants(erodes, walls)
        + include_str!("math.wgsl")
        + include_str!("step.wgsl")
}

/// The rigid bodies' states as the GPU keeps them (`layout::RB_STATE` values each).
fn rigid_state(solver: &Solver) -> Vec<f64> {
    let mut out = Vec::with_capacity(RB_STATE * solver.state.rigid.len());
    for st in &solver.state.rigid {
        let start = out.len();
        out.extend_from_slice(&st.x_cm);
        out.extend_from_slice(&st.v_cm);
        out.extend(st.rot.iter().flatten());
        out.extend_from_slice(&st.ang_mom);
        out.extend_from_slice(&st.omega);
        // the next placement: the present one until a step is taken
        out.extend_from_slice(&st.x_cm);
        out.extend(st.rot.iter().flatten());
        out.extend_from_slice(&[0.0, 0.0, 0.0]); // the work now and later, a spare
        out.extend_from_slice(&st.prev_x_cm);
        out.extend(st.prev_rot.iter().flatten());
        assert_eq!(out.len() - start, RB_STATE);
    }
    out
}

/// Per element, the inverse of its reference Jacobian at the centre (9 values, by rows), when
/// an erosion rule has a strain criterion (solver/erosion.rs); else nothing.
fn reference_jacobians(model: &cleave_core::model::Model) -> Vec<f64> {
    if !model.erosion.iter().any(|d| d.rule.needs_strain()) {
        return Vec::new();
    }
    let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut out = Vec::with_capacity(9 * model.num_elements());
    for c in &model.conn {
        let x0: [Vec3; 8] = c.map(|n| model.x0[n as usize]);
        let inv =
            cleave_core::math::inverse(&cleave_core::element::hex8::jacobian_at(&x0, [0.0; 3]))
                .unwrap_or(id);
        out.extend(inv.iter().flatten());
    }
    out
}

/// The storage arrays of `storage` (binding, buffer, read-only) that `gpu` cannot bind whole,
/// each with its chunks (split.rs); an error where an array cannot be split (an array of
/// atomics) or the chunks need more bindings than the device has.
fn bind_splits(
    gpu: &Gpu,
    source: &str,
    storage: &[(u32, &wgpu::Buffer, bool)],
) -> Result<Vec<crate::split::Split>, GpuError> {
    let limit = gpu.limits.max_storage_buffer_binding_size;
    let align = gpu.limits.min_storage_buffer_offset_alignment as u64;
    let decls = crate::split::declarations(source);
    let mut next = storage.iter().map(|s| s.0).max().unwrap_or(28).max(28) + 1;
    let mut splits = vec![];
    for &(binding, buffer, _) in storage {
        let bytes = buffer.size();
        let decl = decls.iter().find(|d| d.binding == binding);
        // an array's limit: the device's, or less where asked (Gpu::force_split)
        let limit = (decl.and_then(|d| gpu.force_split.iter().find(|f| f.0 == d.name)))
            .map_or(limit, |f| f.1.min(limit));
        if bytes <= limit {
            continue;
        }
        let Some(d) = decl else {
            return Err(GpuError::TooLarge(format!(
                "array {binding} of the step needs {bytes} bytes and cannot be bound in parts; {} binds at most {limit} bytes per array",
                gpu.info.name
            )));
        };
        splits.extend(crate::split::plan(d, bytes, limit, align, &mut next));
    }
    let extra: usize = splits.iter().map(|s| s.chunks.len() - 1).sum();
    let most = gpu.limits.max_storage_buffers_per_shader_stage as usize;
    if storage.len() + extra > most {
        return Err(GpuError::TooLarge(format!(
            "the model's arrays need {} storage bindings once those over the {limit} bytes {} binds per array are bound in parts; it has {most}",
            storage.len() + extra,
            gpu.info.name
        )));
    }
    Ok(splits)
}

impl GpuStepper {
    /// Upload `solver`'s model and initial state to `gpu`. Refuses a deck with a feature the
    /// GPU step lacks ([`crate::support::unsupported`], [`crate::support::unsupported_split`])
    /// or an array larger than the device binds. With contact, the host's contact is brought
    /// up to the coincident sets first (`ContactSet::settle`: leads, chains; what the CPU's
    /// searches keep pending is dropped), and from then on the GPU runs it.
    pub fn new(gpu: Gpu, solver: &mut Solver) -> Result<Self, GpuError> {
        let model = solver.model;
        if let Some(what) = crate::support::unsupported(model, &solver.setup) {
            return Err(GpuError::Unsupported(what));
        }
        if let Some(what) = crate::support::unsupported_split(solver) {
            return Err(GpuError::Unsupported(what));
        }
        let (ne, nn) = (model.num_elements(), model.num_nodes());
        // one buffer per array, at most `max_buffer_size` bytes; an array larger than the
        // device binds is bound in chunks (split.rs)
        let limit = gpu.limits.max_buffer_size;
        // the largest arrays: 12 f64 per element (hourglass forces, each half of the corner
        // forces), 8 u32 per element (connectivity, corners per node); with ELFORM 2, 104 f64
        // per element (the Gauss points); per node, two steps' positions (6 f64)
        let per_elem = if model.sections.iter().any(|s| s.elform == 2) {
            832
        } else {
            96
        };
        let largest = (per_elem * ne).max(48 * nn) as u64;
        if largest > limit {
            return Err(GpuError::TooLarge(format!(
                "{ne} elements need arrays of {largest} bytes; {} holds at most {limit} bytes in one buffer: at most {} elements on this device",
                gpu.info.name,
                limit / per_elem as u64
            )));
        }
        let lay = Layout::new(
            model,
            &solver.setup,
            solver.ties(),
            crate::separation::slots(solver),
        );
        // the parameters (loads, ties, rigid bodies' nodes) are one array too
        let par_bytes = 8 * lay.par.len() as u64;
        if par_bytes > limit {
            return Err(GpuError::TooLarge(format!(
                "the model's parameters (loads, ties, rigid bodies' nodes) need an array of {par_bytes} bytes; {} holds at most {limit} bytes in one buffer",
                gpu.info.name
            )));
        }
        // element separation: the interfaces, and the softening faces of the cohesive laws
        // (58 values for each interface that may soften)
        let (ifu, ifs, n_if, if_index) = crate::separation::interface_table(solver);
        let co = crate::separation::Cohesive::of(solver);
        let sep_bytes = (4 * (ifu.len() + co.cix.len())).max(8 * (ifs.len() + co.coh.len())) as u64;
        if sep_bytes > limit {
            return Err(GpuError::TooLarge(format!(
                "the {n_if} interfaces of element separation (with their cohesive faces) need an array of {sep_bytes} bytes; {} holds at most {limit} bytes in one buffer",
                gpu.info.name
            )));
        }
        let dev = &gpu.device;
        let groups_e = ne.div_ceil(GROUP);
        let groups_n = nn.div_ceil(GROUP);
        let storage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        // a binding may not be empty: every array holds at least one value
        let f64s = |label: &str, data: &[f64]| {
            let mut d = data.to_vec();
            if d.is_empty() {
                d.push(0.0);
            }
            dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&d),
                usage: storage,
            })
        };
        let u32s = |label: &str, data: &[u32]| {
            let mut d = data.to_vec();
            d.resize(d.len().max(2), 0);
            dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(&d),
                usage: storage,
            })
        };
        let zeros = |label: &str, n: usize| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 8 * n.max(1) as u64,
                usage: storage,
                mapped_at_creation: false,
            })
        };
        let cf_buf = f64s("control floats", &control_block(solver));
        let mut cu0 = [0u32; cu::LEN];
        cu0[cu::INVERTED] = u32::MAX;
        cu0[cu::NONFINITE] = u32::MAX;
        cu0[cu::N_COH] = co.faces;
        cu0[cu::N_CSLOT] = co.slots;
        let cu_buf = u32s("control integers", &cu0);
        // the state's positions (a tied slave node starts on its face), one entry per node or
        // per slot of the coincident sets
        let (x0, v0, mass0) = kinematics(solver, true);
        // (two steps' positions: x^n and x^(n+1), step.wgsl halves)
        let x_len = x0.len();
        let state = StateBuffers {
            x: f64s("x", &[x0.as_slice(), &x0].concat()),
            v: f64s("v", &v0),
            vn: f64s("v_n", &v0),
            sig: zeros("stress", 6 * ne),
            hist: zeros("history", 7 * ne),
            hg: zeros("hourglass forces", 12 * ne),
            bq: zeros("bulk viscosity", ne),
        };
        let contact = ContactGpu::new(&gpu, solver, [&cf_buf, &cu_buf, &state.x, &state.v])?;
        let par = f64s("parameters", &lay.par);
        let conn = u32s("connectivity", &by_component(&lay.conn, 8));
        let emat = u32s("element materials", &lay.emat);
        let mass = f64s("mass", &mass0);
        let fe_lo = zeros("corner forces 1-4", 12 * ne);
        let fe_hi = zeros("corner forces 5-8", 12 * ne);
        let epart = zeros("element partial sums", 6 * groups_e);
        let nptr = u32s("node corners start", &lay.nptr);
        let ninc = u32s("node corners", &lay.ninc);
        let nflag = u32s("spc", &lay.nflag);
        let mptr = u32s("node motions start", &lay.mptr);
        let n_part = 6 + 4 * model.rigid_walls.len();
        let npart = zeros("node partial sums", n_part * groups_n);
        let rbi = u32s("rigid body nodes", &lay.rbi);
        let rb = f64s("rigid bodies", &rigid_state(solver));
        let np = lay.emat.iter().any(|&b| b & crate::layout::NP != 0);
        let npe = zeros("nodal pressure, elements", if np { 3 * ne } else { 1 });
        let npn = zeros("nodal pressure, nodes", if np { nn } else { 1 });
        let sri = lay.emat.iter().any(|&b| b & crate::layout::SRI != 0);
        let gps = zeros("gauss points", if sri { 104 * ne } else { 1 });
        let erodes = !model.erosion.is_empty();
        let ero = zeros("erosion", if erodes { 4 * ne } else { 1 });
        let eref = f64s("reference jacobians", &reference_jacobians(model));
        // (the softening faces' blocks after the interfaces' in the same arrays: fewer bindings)
        let (c_ptr, c_coh) = (ifu.len() as u32, ifs.len() as u32);
        let sep = SepBuffers {
            ifu: u32s("interfaces", &[ifu, co.cix.clone()].concat()),
            ifs: f64s("interface strengths", &[ifs, co.coh.clone()].concat()),
            ifl: u32s("failed interfaces", &vec![0; 1 + n_if as usize]),
            coh_groups: dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("cohesive groups"),
                contents: bytemuck::cast_slice(&co.groups()),
                usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            }),
            n_if,
            if_index,
            coh_cap: co.cap,
            c_ptr,
            c_inc: co.c_inc,
            c_slots: co.c_slots,
            c_coh,
        };
        let params = Params {
            ne: ne as u32,
            nn: nn as u32,
            groups_e: groups_e as u32,
            groups_n: groups_n as u32,
            n_body: lay.n_body,
            body_off: lay.body_off,
            mot_off: lay.mot_off,
            n_rigid: lay.n_rigid,
            n_walls: model.rigid_walls.len() as u32,
            wall_off: lay.wall_off,
            n_part: n_part as u32,
            rb_off: lay.rb_off,
            erosion: erodes as u32,
            n_ties: lay.n_ties,
            tie_off: lay.tie_off,
            n_if,
            if_index,
            c_ptr: sep.c_ptr,
            c_inc: sep.c_inc,
            c_slots: sep.c_slots,
            c_coh: sep.c_coh,
            dt_max_off: lay.dt_max_off,
            pad: 0,
        };
        let uniform = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bindings: [(&wgpu::Buffer, bool); 28] = [
            (&cf_buf, false),
            (&cu_buf, false),
            (&par, true),
            (&conn, true),
            (&emat, true),
            (&state.x, false),
            (&state.v, false),
            (&state.vn, false),
            (&mass, true),
            (&state.sig, false),
            (&state.hist, false),
            (&state.hg, false),
            (&state.bq, false),
            (&fe_lo, false),
            (&fe_hi, false),
            (&epart, false),
            (&nptr, true),
            (&ninc, true),
            (&nflag, true),
            (&mptr, true),
            (&npart, false),
            (&rbi, true),
            (&rb, false),
            (&npe, false),
            (&npn, false),
            (&gps, false),
            (&ero, false),
            (&eref, true),
        ];
        // the storage arrays (the separation's after the uniform parameters, binding 28)
        // (and the contact forces after them, binding 32)
        let sep_bindings = [(&sep.ifu, true), (&sep.ifs, false), (&sep.ifl, false)];
        let storage: Vec<(u32, &wgpu::Buffer, bool)> = (bindings.iter().enumerate())
            .map(|(i, &(b, r))| (i as u32, b, r))
            .chain((sep_bindings.iter().enumerate()).map(|(k, &(b, r))| (29 + k as u32, b, r)))
            .chain(contact.iter().map(|c| (32, &c.fcon, true)))
            .collect();
        let source = step_source(&lay, erodes, model.rigid_walls.len(), contact.is_some());
        let splits = bind_splits(&gpu, &source, &storage)?;
        let buffer_entry = |binding: u32, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let mut layout_entries = vec![buffer_entry(28, wgpu::BufferBindingType::Uniform)];
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 28,
            resource: uniform.as_entire_binding(),
        }];
        for &(binding, buffer, read_only) in &storage {
            let ty = wgpu::BufferBindingType::Storage { read_only };
            match splits.iter().find(|s| s.chunks[0].0 == binding) {
                None => {
                    layout_entries.push(buffer_entry(binding, ty));
                    entries.push(wgpu::BindGroupEntry {
                        binding,
                        resource: buffer.as_entire_binding(),
                    });
                }
                Some(s) => {
                    for &(b, offset, size) in &s.chunks {
                        layout_entries.push(buffer_entry(b, ty));
                        entries.push(wgpu::BindGroupEntry {
                            binding: b,
                            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                                buffer,
                                offset,
                                size: std::num::NonZeroU64::new(size),
                            }),
                        });
                    }
                }
            }
        }
        let bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("step"),
            entries: &layout_entries,
        });
        let bind_group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("step"),
            layout: &bgl,
            entries: &entries,
        });
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("step.wgsl"),
            source: wgpu::ShaderSource::Wgsl(crate::split::rewrite(&source, &splits).into()),
        });
        let pl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("step"),
            bind_group_layouts: &[Some(&bgl)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str| {
            dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pl),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        // (entry point, groups) of each step; the passes of ELFORM 13 only where it is used.
        // The end of a step (time, step count) is the finish pass's, and the commit pass's
        // once at the start of each batch for a step that halted
        let mut passes = vec![];
        if np {
            passes.extend([("np_theta", groups_e), ("np_node_theta", groups_n)]);
        }
        passes.push(("elements", groups_e));
        if np {
            passes.extend([("np_node_p", groups_n), ("np_correct", groups_e)]);
        }
        // a step in which elements erode halts after them (the contact's surfaces change on
        // the host), before the interfaces' check, as on the CPU (solver.rs
        // advance_to_half_step: erode_elements, then check_interfaces)
        if erodes && contact.is_some() {
            passes.push(("erosion_done", 1));
        }
        if n_if > 0 {
            // a step in which interfaces fail halts after them; the softening faces' forces
            // and springs before the time step (which their springs bound), as on the CPU
            passes.extend([
                ("interfaces", (n_if as usize).div_ceil(GROUP)),
                ("interfaces_done", 1),
            ]);
            if sep.coh_cap > 0 {
                passes.push(("cohesive", 0));
            }
        }
        let contact_at = passes.len();
        passes.push(("control", 1));
        if lay.n_rigid > 0 {
            passes.push(("rigid", lay.n_rigid as usize));
        }
        passes.push(("nodes", groups_n));
        if lay.n_ties > 0 {
            passes.push(("tied", (lay.n_ties as usize).div_ceil(GROUP)));
        }
        passes.push(("finish", 1));
        // the per-node passes of the central-difference update run over the entries in use
        let mut pipelines: Vec<Pass> = (passes.iter())
            .map(|&(name, g)| Pass {
                name,
                pipeline: pipeline(name),
                groups: match name {
                    "nodes" => Groups::Nodes,
                    "cohesive" => Groups::Cohesive,
                    _ => Groups::Fixed(g),
                },
                contact: false,
            })
            .collect();
        // the contact's passes after the forces of the elements (and the interfaces'), before
        // the time step and the nodes, which add its forces
        if let Some(c) = &contact {
            // (the closed cracks' passes only where interfaces can fail)
            let cp = (c.passes.iter().enumerate())
                .filter(|(_, (name, _))| n_if > 0 || !name.starts_with("c_close"))
                .map(|(k, (name, p))| Pass {
                    name,
                    pipeline: p.clone(),
                    groups: Groups::Contact(k),
                    contact: true,
                });
            pipelines.splice(contact_at..contact_at, cp);
        }
        let commit = pipeline("commit");
        let positions = pipeline("positions");
        let device_bytes =
            storage.iter().map(|(_, b, _)| b.size()).sum::<u64>() + uniform.size() + 2 * CTL_BYTES;
        let staging = || {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("control read-back"),
                size: CTL_BYTES,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let ctl_staging = [staging(), staging()];
        let node_groups = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("node groups"),
            contents: bytemuck::cast_slice(&crate::separation::node_grid(solver)),
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
        });
        let mut persistent = vec![
            (cf_buf.clone(), Stored::AsIs),
            (cu_buf.clone(), Stored::AsIs),
            (state.x.clone(), Stored::Positions),
            (state.v.clone(), Stored::AsIs),
            (state.vn.clone(), Stored::AsIs),
            (state.sig.clone(), Stored::ByComponent(6)),
            (state.hist.clone(), Stored::AsIs),
            (state.hg.clone(), Stored::ByComponent(12)),
            (state.bq.clone(), Stored::AsIs),
            (rb.clone(), Stored::AsIs),
            (gps.clone(), Stored::AsIs),
        ];
        if erodes {
            persistent.push((ero.clone(), Stored::AsIs));
        }
        if let Some(m) = gpu.failure() {
            return Err(GpuError::Failed(m));
        }
        Ok(Self {
            pipelines,
            commit,
            device_bytes,
            persistent,
            x_len,
            positions,
            bind_group,
            cf: cf_buf,
            cu: cu_buf,
            state,
            ctl_staging,
            rb,
            ero: erodes.then_some(ero),
            batch: 4,
            times: None,
            halts: [(0, 0.0); 3],
            split_parts: [0.0; 3],
            gpu,
            model_bufs: ModelBuffers {
                par,
                conn,
                emat,
                mass,
                nptr,
                ninc,
                nflag,
                mptr,
            },
            sep,
            node_groups,
            split: (splits.iter())
                .map(|s| (s.decl.name.clone(), s.chunks.len()))
                .collect(),
            contact,
            relayout: crate::relayout::Relayout::new(solver, &lay),
            list_head: 1024,
            lose_in_read: std::cell::Cell::new(0),
            read_back: Default::default(),
        })
    }

    /// For tests: write `value` all over the contact's grid and work arrays whenever new
    /// tables are written into their buffers ([`ContactGpu::poison`]); returns how many
    /// buffers were so far. A run gives the same bits with it as without when the grid is
    /// zeroed before the contact's next pass, wherever that pass is recorded.
    #[doc(hidden)]
    pub fn poison_contact_grid(&mut self, value: Option<u32>) -> u64 {
        match &mut self.contact {
            Some(c) => {
                c.poison = value;
                c.poisoned()
            }
            None => 0,
        }
    }

    /// For tests: the longest list of the nodes pushing on a contact face that one thread
    /// sorts and adds, and the longest a group sorts in its own memory (16 and 1024 by
    /// default; less to run the longer lists' paths on small models), and whether the lists
    /// are filled from their end (the sorts must then give the same sums).
    #[doc(hidden)]
    pub fn set_contact_lists(&mut self, short: u32, long: u32, reverse: bool) {
        if let Some(c) = &mut self.contact {
            c.set_lists(&self.gpu, [short, long], reverse);
        }
    }

    /// For tests: the most candidates a contact node's list holds (at most 64; with 0 every
    /// node is checked against its cell of the grid every step), and with `verify` each list
    /// checked at every step against the node's cell, for the present tables and the ones
    /// made from now on.
    #[doc(hidden)]
    pub fn set_contact_cands(&mut self, cands: u32, verify: bool) {
        if let Some(c) = &mut self.contact {
            c.set_cands(&self.gpu, cands, verify);
        }
    }

    /// For tests: the times the contact's candidate lists were made, and with `verify`
    /// ([`Self::set_contact_cands`]) the faces a list missed and the faces looked for: since
    /// its tables were made, or with `verify` since it was set; zeros without contact.
    #[doc(hidden)]
    pub fn contact_lists(&self) -> [u64; 3] {
        match &self.contact {
            Some(c) => c.tally(&self.download_ranges(&[c.flags()])[0]),
            None => [0; 3],
        }
    }

    /// For tests: the halts for closed cracks' release so far, those let go on the device in
    /// place and those for which the contact's tables were made again; with `remake`, every
    /// release from now on makes them again.
    #[doc(hidden)]
    pub fn contact_releases(&mut self, remake: bool) -> [u64; 2] {
        match &mut self.contact {
            Some(c) => {
                c.remake_releases = remake;
                c.releases
            }
            None => [0; 2],
        }
    }

    /// Read at most `n` (at least 1) of a step's failed interfaces with the rest of a split's
    /// read-back, the others in a second one (1024 by default; for tests of the second).
    #[doc(hidden)]
    pub fn set_failure_list_head(&mut self, n: u64) {
        self.list_head = n.max(1);
    }

    /// For tests: destroy the device just before the `k`-th read of the state from now (an
    /// output's, a split's, an erosion's, a crack release's or a restart file's: 1 the next; 0
    /// never), so the read itself finds it lost.
    #[doc(hidden)]
    pub fn lose_device_in_read(&mut self, k: u32) {
        self.lose_in_read.set(k);
    }

    /// The device this stepper runs on.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The arrays larger than the device binds, each bound in parts (split.rs): the array's
    /// name in step.wgsl and its number of chunks; empty when every array binds whole.
    pub fn split_arrays(&self) -> &[(String, usize)] {
        &self.split
    }

    /// Give the device back (for another model).
    pub fn into_gpu(self) -> Gpu {
        self.gpu
    }

    /// Record `steps` steps and the copy of the control block into `staging`.
    fn record(&self, steps: usize, staging: usize) -> wgpu::CommandBuffer {
        let mut enc = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("steps"),
            });
        self.clear_contact(&mut enc);
        if let Some(times) = &self.times {
            self.record_timed(&mut enc, times, staging, &self.pipelines, 0, steps);
            self.copy_control(&mut enc, staging);
            return enc.finish();
        }
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("steps"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.set_pipeline(&self.commit);
            pass.dispatch_workgroups(1, 1, 1);
            for _ in 0..steps {
                self.dispatch_all(&mut pass, &self.pipelines);
            }
        }
        self.copy_control(&mut enc, staging);
        enc.finish()
    }

    /// The contact's zeroing of its grid after new tables, if due ([`ContactGpu::clear`]):
    /// first in every encoder that records passes.
    fn clear_contact(&self, enc: &mut wgpu::CommandEncoder) {
        if let Some(c) = &self.contact {
            c.clear(enc);
        }
    }

    /// The run's error when the device failed (lost, or an error it reported: [`Gpu::failure`]),
    /// at the time and step the host last read.
    pub(crate) fn failed(&self, solver: &Solver) -> Option<RunError> {
        let m = self.gpu.failure()?;
        Some(RunError::Device(format!(
            "the GPU run stopped after t = {:e} (step {}, the last the host read): {m}",
            solver.state.t, solver.state.step
        )))
    }

    /// The run's error when the device's state disagrees with the host's (`what`): that of a
    /// failed device when it failed ([`Self::failed`]; what it read back is then garbage).
    pub(crate) fn internal(&self, solver: &Solver, what: String) -> RunError {
        self.failed(solver)
            .unwrap_or_else(|| RunError::Device(format!("the GPU run stopped: {what}")))
    }

    /// Submit the passes of the step in flight that come after `after` (an entry point), the
    /// host's writes of the halt `w` recorded first in the same submission (one staging buffer
    /// and one submission for a halt's writes: a `Queue::write_buffer` makes a staging buffer
    /// each); the queue runs them before anything submitted later.
    pub(crate) fn finish_step_after(&mut self, after: &str, w: Writes) {
        let Some(k) = self.pipelines.iter().position(|p| p.name == after) else {
            w.submit(&self.gpu);
            return;
        };
        let mut enc = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("the rest of a step"),
            });
        w.record(&self.gpu, &mut enc);
        self.clear_contact(&mut enc);
        if let Some(times) = &self.times {
            // (its times are taken with the next batch's, which the queue runs after it)
            let rest = &self.pipelines[k + 1..];
            self.record_timed(&mut enc, times, 2, rest, k + 1, 1);
            self.gpu.queue.submit([enc.finish()]);
            return;
        }
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_bind_group(0, &self.bind_group, &[]);
            self.dispatch_all(&mut pass, &self.pipelines[k + 1..]);
        }
        self.gpu.queue.submit([enc.finish()]);
    }

    /// The steps that halted for the host so far, each kind's count and wall seconds of the
    /// host's work (its read-backs, its changes, the writes and the submission of the rest of
    /// the step): sets split (interfaces failed), elements eroded from a contact's surfaces,
    /// closed cracks released. On a GPU these, not the passes, can set a breaking run's time.
    pub fn host_halts(&self) -> [(u64, f64); 3] {
        self.halts
    }

    /// The wall seconds of the splits so far ([`Self::host_halts`]' first) by part: waiting
    /// for their read-backs, making the contact's tables again and putting them on the device,
    /// and the rest (the sets split on the host, the layout's changes and their writes, the
    /// submission of the rest of the step).
    pub fn split_parts(&self) -> [f64; 3] {
        self.split_parts
    }

    /// Time each pass over the runs that follow, with the device's timestamps, or stop doing
    /// so; returns whether the device can ([`Self::pass_times`]). Each pass then goes in a
    /// compute pass of its own, which costs more than a plain batch: for benchmarks.
    pub fn time_passes(&mut self, on: bool) -> bool {
        self.times = if on {
            PassTimes::new(&self.gpu, self.pipelines.len())
        } else {
            None
        };
        self.times.is_some()
    }

    /// The device seconds of each pass, by name in the step's order, summed over the steps run
    /// since [`Self::time_passes`] (those that halt for the host and the rest of such a step
    /// included; the idle steps of a batch recorded past a halt left out, but for a batch that
    /// starts halted, when the rest of a halted step halts again).
    pub fn pass_times(&self) -> Option<Vec<(&'static str, f64)>> {
        let t = self.times.as_ref()?;
        Some(
            (self.pipelines.iter().zip(&t.secs))
                .map(|(p, &s)| (p.name, s))
                .collect(),
        )
    }

    /// Record `steps` steps of `passes` (the step's from number `first` on), each pass in a
    /// compute pass of its own timed in `slot` of `times`, then the read-back of the times.
    /// A batch (`first` 0) starts with the commit of a halted step, as [`Self::record`]'s.
    fn record_timed(
        &self,
        enc: &mut wgpu::CommandEncoder,
        times: &PassTimes,
        slot: usize,
        passes: &[Pass],
        first: usize,
        steps: usize,
    ) {
        times.begin(slot);
        if first == 0 {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.set_pipeline(&self.commit);
            pass.dispatch_workgroups(1, 1, 1);
        }
        for _ in 0..steps {
            for (i, p) in passes.iter().enumerate() {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(p.name),
                    timestamp_writes: times.writes(slot, first + i),
                });
                pass.set_bind_group(0, self.bind_group_of(p), &[]);
                self.dispatch(&mut pass, p);
            }
        }
        times.finish(enc, slot);
    }

    /// The time at which the GPU halts next (for output, a restart file or a stop; 0: at the
    /// next step).
    fn set_stop_time(&self, t: f64) {
        (self.gpu.queue).write_buffer(&self.cf, (cf::T_STOP * 8) as u64, bytemuck::bytes_of(&t));
    }

    /// Clear the halt flags, so that the next dispatches run.
    pub(crate) fn clear_halt(&self) {
        let q = &self.gpu.queue;
        q.write_buffer(&self.cu, (cu::HALT * 4) as u64, bytemuck::bytes_of(&0u32));
        q.write_buffer(
            &self.cf,
            (cf::HALTED * 8) as u64,
            bytemuck::bytes_of(&0.0f64),
        );
    }

    /// [`Self::clear_halt`]'s writes, into `w` (for a halt whose other writes go there too).
    pub(crate) fn clear_halt_into(&self, w: &mut Writes) {
        w.put(&self.cu, (cu::HALT * 4) as u64, &[0u32]);
        w.put(&self.cf, (cf::HALTED * 8) as u64, &[0.0f64]);
    }

    /// The bind group of pass `p`: the step's, or the contact's for its passes.
    fn bind_group_of(&self, p: &Pass) -> &wgpu::BindGroup {
        match &self.contact {
            Some(c) if p.contact => &c.bind_group,
            _ => &self.bind_group,
        }
    }

    /// Dispatch `passes` in order, in a compute pass whose bind group is the step's; each
    /// group of contact passes binds the contact's, and the step's is bound again after it.
    fn dispatch_all(&self, pass: &mut wgpu::ComputePass<'_>, passes: &[Pass]) {
        let mut contact = false;
        for p in passes {
            if p.contact != contact {
                pass.set_bind_group(0, self.bind_group_of(p), &[]);
                contact = p.contact;
            }
            self.dispatch(pass, p);
        }
        if contact {
            pass.set_bind_group(0, &self.bind_group, &[]);
        }
    }

    /// Dispatch pass `p`.
    fn dispatch(&self, pass: &mut wgpu::ComputePass<'_>, p: &Pass) {
        pass.set_pipeline(&p.pipeline);
        match p.groups {
            Groups::Fixed(g) => {
                let [x, y, z] = group_grid(g);
                pass.dispatch_workgroups(x, y, z);
            }
            Groups::Nodes => pass.dispatch_workgroups_indirect(&self.node_groups, 0),
            Groups::Cohesive => pass.dispatch_workgroups_indirect(&self.sep.coh_groups, 0),
            Groups::Contact(k) => {
                let g = self.contact.as_ref().map_or(0, |c| c.groups[k]);
                let [x, y, z] = group_grid(g);
                pass.dispatch_workgroups(x, y, z);
            }
        }
    }

    /// Record the copy of the control block (`cf`, then `cu`) into read-back buffer `staging`.
    fn copy_control(&self, enc: &mut wgpu::CommandEncoder, staging: usize) {
        let s = &self.ctl_staging[staging];
        enc.copy_buffer_to_buffer(&self.cf, 0, s, 0, (cf::LEN * 8) as u64);
        enc.copy_buffer_to_buffer(&self.cu, 0, s, (cf::LEN * 8) as u64, (cu::LEN * 4) as u64);
    }

    /// The state on the device between two steps, as bytes, for a restart file: every buffer
    /// that carries from one step to the next (the control block, positions, velocities,
    /// stresses, histories, hourglass forces, bulk viscosity, rigid bodies, Gauss points,
    /// erosion), each as its length (u64, little-endian) and its bytes. Taken at a halt (an
    /// output or restart time), it is what [`Self::load`] takes up to go on bit for bit.
    ///
    /// With element separation, or contact on surfaces that erosion changes, one more part
    /// follows: the host solver's state ([`Solver::save_state`]), which holds the interfaces
    /// and the coincident sets as they have split, and the contact surfaces as elements eroded
    /// from them or cracks joined them, with the closed cracks (their states taken from the
    /// GPU by the mirror of this halt, which the solver's must be). With contact, the last two parts
    /// are its pairs and each surface node's last contact force (`contact.rs`), whose tables
    /// [`Self::load`] makes again from that state.
    pub fn save(&self, solver: &Solver) -> Vec<u8> {
        let mut out = Vec::new();
        let mut put = |bytes: &[u8]| {
            out.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
            out.extend_from_slice(bytes);
        };
        // every array in one read-back (with contact, its pairs and last forces last); the
        // control block (the first) gives the step whose half of the positions is x^n
        let mut parts: Vec<_> = (self.persistent.iter())
            .map(|(b, _)| (b, 0, b.size()))
            .collect();
        if let Some(c) = &self.contact {
            parts.extend([c.hits(), c.fprev()]);
        }
        let got = self.download_ranges(&parts);
        let step = f64::from_le_bytes(
            got[0][8 * cf::STEP..8 * cf::STEP + 8]
                .try_into()
                .expect("8 bytes"),
        );
        for ((_, stored), bytes) in self.persistent.iter().zip(&got) {
            match *stored {
                Stored::AsIs => put(bytes),
                Stored::ByComponent(k) => {
                    let values: Vec<f64> = bytemuck::pod_collect_to_vec(bytes);
                    put(bytemuck::cast_slice(&by_element(&values, k)));
                }
                Stored::Positions => {
                    let half = self.x_half(step);
                    put(&bytes[8 * half.start..8 * half.end]);
                }
            }
        }
        if self.sep.n_if > 0 || self.contact_erodes() {
            put(&solver.save_state());
        }
        if self.contact.is_some() {
            // the pairs and last forces (their tables made again from the solver's state)
            let n = self.persistent.len();
            put(&got[n]);
            put(&got[n + 1]);
        }
        out
    }

    /// Elements eroded in the step halted (HALT 5): the host's contact drops their faces and
    /// takes the faces they covered ([`Solver::erode_contact`]), the contact's tables are made
    /// again with the pairs carried over, and the rest of the step runs.
    fn erode_contact(&mut self, solver: &mut Solver) -> Result<(), RunError> {
        let Some(ero) = self.ero.as_ref().filter(|_| self.contact.is_some()) else {
            return Ok(());
        };
        // (one read-back: the erosion flags, then what the contact's remake reads)
        let mut parts = vec![(ero, 0, ero.size())];
        parts.extend(self.contact_parts());
        let got = self.download_ranges(&parts);
        // (nothing of a failed device's read is taken: NaN flags would erode every element)
        if let Some(e) = self.failed(solver) {
            return Err(e);
        }
        let ero: Vec<f64> = bytemuck::pod_collect_to_vec(&got[0]);
        let newly: Vec<u32> = (0..solver.model.num_elements())
            .filter(|&e| ero[4 * e] != 0.0 && !solver.state.eroded[e])
            .map(|e| e as u32)
            .collect();
        // the closed cracks' states as the GPU has them first (with element separation): the
        // tables made again upload the host's, which are those of the last output or split
        self.closures_to_host(solver, &got[1], false)?;
        solver.erode_contact(&newly);
        let mut w = Writes::default();
        self.remake_contact(solver, false, &got[2..], Some(&mut w))?;
        self.clear_halt_into(&mut w);
        self.finish_step_after("erosion_done", w);
        Ok(())
    }

    /// Closed cracks released in the step halted (HALT 6, after the cracks' pass): the host's
    /// contact takes their states and lets the released ones go (their pairs unchained), the
    /// device lets them go in place (or, should the host's surfaces differ from the tables,
    /// the tables are made again with the pairs carried over), and the rest of the step runs.
    fn release_cracks(&mut self, solver: &mut Solver) -> Result<(), RunError> {
        // one read-back: the closed cracks' states; the host lets the released ones go and
        // the device does too, in place ([`ContactGpu::release_in_place`]), or, should the
        // host's surfaces differ from the tables, the tables are made again (the pairs and last
        // forces read back for them)
        let got = match &self.contact {
            Some(c) => self.download_ranges(&[c.clo()]),
            None => vec![],
        };
        if let Some(e) = self.failed(solver) {
            return Err(e);
        }
        let mut w = Writes::default();
        if let Some(clo) = got.first() {
            self.closures_to_host(solver, clo, true)?;
            solver.settle_contact(true);
            let clo: Vec<f64> = bytemuck::pod_collect_to_vec(clo);
            let done =
                (self.contact.as_mut()).is_some_and(|c| c.release_in_place(solver, &clo, &mut w));
            if !done {
                let parts = self.contact_parts();
                let got = self.download_ranges(&parts[1..]);
                if let Some(e) = self.failed(solver) {
                    return Err(e);
                }
                self.remake_contact(solver, false, &got, Some(&mut w))?;
            }
        }
        self.clear_halt_into(&mut w);
        self.finish_step_after("c_close_done", w);
        Ok(())
    }

    /// What a halt reads back of the contact (none without contact), so that it joins the
    /// halt's one read-back: the closed cracks' states, the pairs, each surface entry's last
    /// force.
    pub(crate) fn contact_parts(&self) -> Vec<Part<'_>> {
        match &self.contact {
            Some(c) => vec![c.clo(), c.hits(), c.fprev()],
            None => vec![],
        }
    }

    /// The closed cracks' states as the GPU had them (`clo`, read back with
    /// [`Self::contact_parts`]) into the host's contact, those released in this step leaving
    /// it when `released` (a halt after the cracks' pass). Nothing without contact.
    pub(crate) fn closures_to_host(
        &self,
        solver: &mut Solver,
        clo: &[u8],
        released: bool,
    ) -> Result<(), RunError> {
        let Some(c) = &self.contact else {
            return Ok(());
        };
        let clo: Vec<f64> = bytemuck::pod_collect_to_vec(clo);
        (c.closures_to_host(solver, &clo, released)).map_err(|e| self.internal(solver, e))
    }

    /// The contact's tables made again from the host's (after its surfaces, sets or closed
    /// cracks changed), the pairs and last forces carried over (`got`: the pairs and the last
    /// forces as read back, the last two of [`Self::contact_parts`]); `split`: the halt of a
    /// step in which sets split (their born slots inherit the last forces,
    /// [`ContactGpu::upload`]). Nothing without contact.
    /// The grid's cell is found again from the surfaces as they are, crack faces among them, at
    /// the positions the host last read (at a split this step's; after erosion or a release
    /// those of the last output or split): the cell changes the speed only, as a node finds
    /// every face whose sphere holds it whatever the cell (BENCHMARKS.md: the breaking ball).
    pub(crate) fn remake_contact(
        &mut self,
        solver: &mut Solver,
        split: bool,
        got: &[Vec<u8>],
        w: Option<&mut Writes>,
    ) -> Result<(), RunError> {
        (self.remake_tables(solver, split, got, w)).map_err(|e| self.internal(solver, e))
    }

    /// [`Self::remake_contact`], its errors as text.
    fn remake_tables(
        &mut self,
        solver: &mut Solver,
        split: bool,
        got: &[Vec<u8>],
        w: Option<&mut Writes>,
    ) -> Result<(), String> {
        // (for tests: the lists' counts, before the new tables zero them)
        let verified = (self.contact.as_ref())
            .filter(|c| c.verifying())
            .map(|c| c.tally(&self.download_ranges(&[c.flags()])[0]));
        let Some(c) = self.contact.as_mut() else {
            return Ok(());
        };
        if let Some(v) = verified {
            c.verified = v;
        }
        let [hits, fprev] = [0, 1].map(|k| {
            got.get(k)
                .map_or(vec![], |b| bytemuck::pod_collect_to_vec::<u8, f64>(b))
        });
        // (in a halt: only the copies of the faces activated since the last settle regroup)
        solver.settle_contact(true);
        let t = (c.tables_now(solver)).ok_or("the solver's contact is gone")?;
        // (the slots born in this step: a halt after a split; none after erosion or a release.
        // A split halt whose failure list read back empty splits nothing, and then no entry
        // leaves the surface: the older births `born` still lists are not read)
        let born = match (solver.separation(), split) {
            (Some(sep), true) => sep.sets().born(),
            _ => &[],
        };
        (c.upload(&self.gpu, t, Some((&hits, &fprev, born)), w)).map_err(|e| e.to_string())
    }

    /// Contact on surfaces that elements erode from: the host changes them (HALT 5).
    fn contact_erodes(&self) -> bool {
        self.contact.is_some() && self.ero.is_some()
    }

    /// Take up a state of [`Self::save`] made by a stepper of the same model, and fill the
    /// solver's mirror from it; the error says what does not match.
    pub fn load(&mut self, solver: &mut Solver, bytes: &[u8]) -> Result<(), String> {
        let mut rest = bytes;
        let mut parts: Vec<Vec<u8>> = Vec::with_capacity(self.persistent.len());
        for (k, (b, stored)) in self.persistent.iter().enumerate() {
            let (len, tail) = rest
                .split_at_checked(8)
                .ok_or("the GPU state is cut short")?;
            let len = u64::from_le_bytes(len.try_into().expect("8 bytes"));
            let size = match stored {
                Stored::Positions => 8 * self.x_len as u64,
                _ => b.size(),
            };
            // (the control block of an earlier cleave is shorter, 64 floats and 8 integers: its
            // missing values are zero, the contact's energy and step, an erosion flag)
            let earlier = (k == 0 && len == 8 * 64) || (k == 1 && len == 4 * 8);
            if len != size && !earlier {
                return Err(format!(
                    "the GPU state holds an array of {len} bytes where this model has {size}"
                ));
            }
            let (data, tail) = tail
                .split_at_checked(len as usize)
                .ok_or("the GPU state is cut short")?;
            let mut data = data.to_vec();
            data.resize(size as usize, 0);
            parts.push(data);
            rest = tail;
        }
        // (the control block is the first array, its size checked above)
        let cf_saved = &parts[0];
        let saved =
            |k: usize| f64::from_le_bytes(cf_saved[8 * k..8 * k + 8].try_into().expect("8 bytes"));
        let step = saved(cf::STEP);
        // the next array of the file, with its length
        let next = |rest: &mut &[u8], what: &str| -> Result<Vec<u8>, String> {
            let (len, tail) = rest
                .split_at_checked(8)
                .ok_or_else(|| format!("the GPU state has no {what}"))?;
            let len = u64::from_le_bytes(len.try_into().expect("8 bytes")) as usize;
            let (data, tail) = tail
                .split_at_checked(len)
                .ok_or("the GPU state is cut short")?;
            *rest = tail;
            Ok(data.to_vec())
        };
        // the host's interfaces and sets, its contact surfaces as elements eroded from them;
        // the contact's pairs and last forces: every part read before anything is changed
        let host = (self.sep.n_if > 0 || self.contact_erodes())
            .then(|| next(&mut rest, "separation or contact state"))
            .transpose()?;
        let pairs = match self.contact {
            Some(_) => Some([
                next(&mut rest, "contact pairs")?,
                next(&mut rest, "contact forces")?,
            ]),
            None => None,
        };
        if !rest.is_empty() {
            return Err("the GPU state holds more arrays than this model".into());
        }
        if let Some(h) = host {
            solver.restore_state(&h)?;
            if self.sep.n_if > 0 {
                self.upload_sets(solver, step);
            }
        }
        if let (Some(c), Some(pairs)) = (&mut self.contact, pairs) {
            // the surfaces, sets and closed cracks as the host's state holds them, made into
            // tables; the pairs checked against them before the device is changed
            let remade = match self.ero.is_some() || self.sep.n_if > 0 {
                true => {
                    solver.settle_contact(false);
                    Some((c.tables_now(solver)).ok_or("the GPU state's model has no contact")?)
                }
                false => None,
            };
            let sizes = remade.as_ref().unwrap_or(c.tables()).pair_bytes();
            for (data, (size, what)) in pairs
                .iter()
                .zip(sizes.into_iter().zip(["contact pairs", "contact forces"]))
            {
                if data.len() as u64 != size {
                    return Err(format!(
                        "the GPU state holds {} bytes of {what} where this model has {size}",
                        data.len(),
                    ));
                }
            }
            if let Some(t) = remade {
                c.upload(&self.gpu, t, None, None)
                    .map_err(|e| e.to_string())?;
            }
            for (data, (buf, _, _)) in pairs.iter().zip([c.hits(), c.fprev()]) {
                self.gpu.queue.write_buffer(buf, 0, data);
            }
        }
        let q = &self.gpu.queue;
        for ((b, stored), data) in self.persistent.iter().zip(&parts) {
            match *stored {
                Stored::AsIs => q.write_buffer(b, 0, data),
                Stored::ByComponent(k) => {
                    let values: Vec<f64> = bytemuck::pod_collect_to_vec(data);
                    q.write_buffer(b, 0, bytemuck::cast_slice(&by_component(&values, k)));
                }
                Stored::Positions => {
                    q.write_buffer(b, 8 * self.x_half(step).start as u64, data);
                }
            }
        }
        // the deck's controls are this run's (a continued run may be given another end time)
        let deck = control_block(solver);
        // (and the entries in use: a file of an earlier cleave has none)
        for k in [
            cf::TSSFAC,
            cf::DT_INIT,
            cf::DT_MIN,
            cf::END_TIME,
            cf::SLOTS,
            cf::DT_CONTACT,
        ] {
            q.write_buffer(&self.cf, (k * 8) as u64, bytemuck::bytes_of(&deck[k]));
        }
        // it was saved halted: running again from here, the step it halted at to be ended
        // first if it had begun (a file of an earlier cleave, which ended a step at the
        // start of the next, has no COMMIT_DUE of its own)
        let pending = saved(cf::PENDING);
        q.write_buffer(
            &self.cf,
            (cf::COMMIT_DUE * 8) as u64,
            bytemuck::bytes_of(&pending),
        );
        self.clear_halt();
        // a state saved at its end time goes on to the deck's (later) one
        q.write_buffer(
            &self.cu,
            (cu::FINISHED * 4) as u64,
            bytemuck::bytes_of(&0u32),
        );
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        {
            // x^(n+1) of a step that had begun, which its nodes pass wrote on the device it ran
            // on (the file holds one step's positions)
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.set_pipeline(&self.positions);
            pass.dispatch_workgroups_indirect(&self.node_groups, 0);
        }
        self.copy_control(&mut enc, 0);
        q.submit([enc.finish()]);
        let c = self.read_control(0);
        if let Some(m) = self.gpu.failure() {
            return Err(format!("the GPU failed: {m}"));
        }
        self.mirror(solver, &c).map_err(|e| match e {
            RunError::Output(e) => e.to_string(),
            RunError::Device(m) => m,
            e => format!("{e:?}"),
        })
    }

    /// Seconds per step of `steps` steps recorded in one submission while the state is
    /// halted: every pass dispatched, each returning at its halt test. The floor that the
    /// dispatches, their barriers and the one-group passes' launches set under a step's cost,
    /// for benchmarks; the state is left as it was, its halt flags too.
    pub fn idle_step_seconds(&self, steps: usize) -> f64 {
        let q = &self.gpu.queue;
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        self.copy_control(&mut enc, 0);
        q.submit([enc.finish()]);
        let before = self.read_control(0);
        let halted = 1.0f64;
        q.write_buffer(
            &self.cf,
            (cf::HALTED * 8) as u64,
            bytemuck::bytes_of(&halted),
        );
        // (the write lands before the batch: the queue runs them in order)
        let cmd = self.record(steps, 0);
        let start = Instant::now();
        q.submit([cmd]);
        self.read_control(0);
        let secs = start.elapsed().as_secs_f64() / steps.max(1) as f64;
        let was = before.f[cf::HALTED];
        q.write_buffer(&self.cf, (cf::HALTED * 8) as u64, bytemuck::bytes_of(&was));
        q.write_buffer(
            &self.cu,
            (cu::HALT * 4) as u64,
            bytemuck::bytes_of(&before.halt()),
        );
        secs
    }

    /// Bytes of the buffers this stepper keeps on the device (the model, the state, the
    /// scratch arrays of the passes and the read-back buffer kept between reads).
    pub fn device_bytes(&self) -> u64 {
        let read_back = self
            .read_back
            .borrow()
            .as_ref()
            .map_or(0, wgpu::Buffer::size);
        self.device_bytes + self.contact.as_ref().map_or(0, ContactGpu::bytes) + read_back
    }

    /// Take `steps` steps with each pass in a compute pass of its own, timed by the device's
    /// timestamps, and return each pass's share of their sum, in the step's order; `None` when
    /// the device has no timestamp queries or the steps did not all run (an output time, the
    /// end or a failure came first). The solver's time and step move on with the steps taken.
    /// For benchmarks: the separate passes cost more than a plain step's.
    pub fn profile(
        &mut self,
        solver: &mut Solver,
        steps: usize,
    ) -> Option<Vec<(&'static str, f64)>> {
        let mut times = PassTimes::new(&self.gpu, self.pipelines.len())?;
        if steps == 0 || steps > times.max_steps {
            return None;
        }
        // no output time inside the profiled steps
        self.set_stop_time(f64::MAX);
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        self.clear_contact(&mut enc);
        self.record_timed(&mut enc, &times, 0, &self.pipelines, 0, steps);
        self.copy_control(&mut enc, 0);
        self.gpu.queue.submit([enc.finish()]);
        let c = self.read_control(0);
        times.collect(&self.gpu, 0, steps);
        if self.gpu.failure().is_some() {
            return None;
        }
        c.apply(solver);
        if c.halt() != 0 {
            return None;
        }
        let total: f64 = times.secs.iter().sum();
        (total > 0.0).then(|| {
            (self.pipelines.iter().zip(&times.secs))
                .map(|(p, s)| (p.name, s / total))
                .collect()
        })
    }

    /// Add the pass times of the first `steps` steps of the batch read back from `staging`,
    /// when they are taken.
    fn collect_times(&mut self, staging: usize, steps: usize) {
        if let Some(t) = &mut self.times {
            t.collect(&self.gpu, staging, steps);
            t.collect_rest(&self.gpu);
        }
    }

    /// Wait for the read-back of `staging` and decode it.
    fn read_control(&self, staging: usize) -> Control {
        let s = &self.ctl_staging[staging];
        s.slice(..).map_async(wgpu::MapMode::Read, |_| {});
        // a lost device surfaces as a mapping error just below
        self.gpu.wait();
        let c = {
            let view = s.slice(..).get_mapped_range();
            match view {
                Ok(bytes) => {
                    let f: Vec<f64> = bytemuck::pod_collect_to_vec(&bytes[..cf::LEN * 8]);
                    let u: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes[cf::LEN * 8..]);
                    Control { f, u }
                }
                Err(_) => Control::lost(),
            }
        };
        s.unmap();
        c
    }

    /// Read parts of buffers back in one submission and one wait: each part a buffer, a byte
    /// offset and a byte count (multiples of 4); NaNs where the device is lost. Parts that
    /// together exceed [`READ_BACK`] bytes are read in consecutive groups of at most that (a
    /// part larger alone), one submission and wait each.
    pub(crate) fn download_ranges(&self, parts: &[Part]) -> Vec<Vec<u8>> {
        match self.lose_in_read.get() {
            0 => {}
            1 => {
                self.lose_in_read.set(0);
                self.gpu.device.destroy();
            }
            k => self.lose_in_read.set(k - 1),
        }
        let mut out = Vec::with_capacity(parts.len());
        let mut start = 0;
        while start < parts.len() {
            let mut end = start + 1;
            let mut size = parts[start].2;
            while end < parts.len() && size + parts[end].2 <= READ_BACK {
                size += parts[end].2;
                end += 1;
            }
            out.extend(self.download_group(&parts[start..end]));
            start = end;
        }
        out
    }

    /// [`Self::download_ranges`] of parts read in one staging buffer: the one kept from the
    /// reads before where it is large enough, else a new one (kept instead when at most
    /// [`KEEP_READ_BACK`] bytes: a split's read, and a small model's output, then makes no
    /// buffer).
    fn download_group(&self, parts: &[Part]) -> Vec<Vec<u8>> {
        let size: u64 = parts.iter().map(|p| p.2).sum::<u64>().max(4);
        let kept = {
            let mut k = self.read_back.borrow_mut();
            k.take_if(|b| b.size() >= size)
        };
        let staging = kept.unwrap_or_else(|| {
            // (room to grow into, as the reads of a breaking run grow)
            let room = match size <= KEEP_READ_BACK {
                true => size.next_power_of_two().clamp(1 << 16, KEEP_READ_BACK),
                false => size,
            };
            self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("state read-back"),
                size: room,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        let mut at = 0;
        for &(buf, offset, len) in parts {
            enc.copy_buffer_to_buffer(buf, offset, &staging, at, len);
            at += len;
        }
        self.gpu.queue.submit([enc.finish()]);
        staging.slice(..size).map_async(wgpu::MapMode::Read, |_| {});
        self.gpu.wait();
        // (each part copied once, from the mapped range, or from NaNs where it is lost)
        let cut = |all: &[u8]| -> Vec<Vec<u8>> {
            let mut at = 0;
            (parts.iter())
                .map(|&(_, _, len)| {
                    let part = all[at..at + len as usize].to_vec();
                    at += len as usize;
                    part
                })
                .collect()
        };
        let (out, read) = match staging.slice(..size).get_mapped_range() {
            Ok(all) => (cut(&all), true),
            Err(_) => (
                cut(bytemuck::cast_slice(&vec![
                    f64::NAN;
                    size.div_ceil(8) as usize
                ])),
                false,
            ),
        };
        staging.unmap();
        if read && staging.size() <= KEEP_READ_BACK {
            *self.read_back.borrow_mut() = Some(staging);
        }
        out
    }

    /// The values of the positions buffer that hold x^n at step `step` (step.wgsl halves).
    pub(crate) fn x_half(&self, step: f64) -> std::ops::Range<usize> {
        let o = (step as u64 % 2) as usize * self.x_len;
        o..o + self.x_len
    }

    /// Fill the host mirror's positions and velocities at step `step` from the GPU, and the
    /// softening faces' state; nothing when the device failed in the read (the stepper reports
    /// it at its next check).
    pub(crate) fn mirror_kinematics(&self, solver: &mut Solver, step: f64) {
        let got = self.download_ranges(&self.kinematics_parts(solver, step));
        if self.gpu.failure().is_none() {
            self.take_kinematics(solver, &got);
        }
    }

    /// The parts of the GPU's arrays that hold x^n at step `step`, v^(n+1/2) and v^n (one
    /// entry per node, or per slot of the coincident sets: as many as there are now, the
    /// GPU's arrays hold one per node, the entries past these unused), and with a cohesive law
    /// the softening faces' rows.
    pub(crate) fn kinematics_parts(&self, solver: &Solver, step: f64) -> Vec<Part<'_>> {
        let nn = solver.positions().entries().len();
        let bytes = (24 * nn as u64).min(8 * self.x_len as u64);
        let half = self.x_half(step);
        let mut parts = vec![
            (&self.state.x, 8 * half.start as u64, bytes),
            (&self.state.v, 0, bytes),
            (&self.state.vn, 0, bytes),
        ];
        parts.extend(self.cohesive_part(solver));
        parts
    }

    /// The host mirror's positions and velocities, and the softening faces' state, from
    /// [`Self::kinematics_parts`] as read back (`got`).
    pub(crate) fn take_kinematics(&self, solver: &mut Solver, got: &[Vec<u8>]) {
        let [x, v, vn] = [0, 1, 2].map(|k| bytemuck::pod_collect_to_vec::<u8, Vec3>(&got[k]));
        solver.set_kinematics(x, v, vn);
        if let Some(rows) = got.get(3) {
            self.import_cohesive(solver, rows);
        }
    }

    /// Fill the host mirror of the state from the GPU, all of it read in one submission and
    /// wait ([`Self::download_ranges`]); a device that failed in the read leaves the mirror as
    /// it was (the last good read) and stops the run.
    pub(crate) fn mirror(&self, solver: &mut Solver, c: &Control) -> Result<(), RunError> {
        fn whole(b: &wgpu::Buffer) -> Part<'_> {
            (b, 0, b.size())
        }
        let mut parts = self.kinematics_parts(solver, c.step());
        let k = parts.len();
        let st = &self.state;
        parts.extend([&st.sig, &st.hist, &st.hg, &st.bq].map(whole));
        let ero_at = parts.len();
        parts.extend(self.ero.as_ref().map(whole));
        let rb_at = parts.len();
        if !solver.state.rigid.is_empty() {
            parts.push(whole(&self.rb));
        }
        let contact_at = parts.len();
        if let Some(ct) = &self.contact {
            parts.extend([ct.hits(), ct.clo()]);
        }
        let got = self.download_ranges(&parts);
        if let Some(e) = self.failed(solver) {
            return Err(e);
        }
        let f64s = |k: usize| bytemuck::pod_collect_to_vec::<u8, f64>(&got[k]);
        self.take_kinematics(solver, &got[..k]);
        let ne = solver.model.num_elements();
        let sig = by_element(&f64s(k), 6);
        let hist = f64s(k + 1);
        let hg = by_element(&f64s(k + 2), 12);
        let bq = f64s(k + 3);
        // Johnson-Cook keeps its temperature rise, ln J and energy in the back stress slots
        let jc: Vec<bool> = (solver.setup.elem_mat.iter())
            .map(|&m| {
                solver.setup.params[m as usize]
                    .as_ref()
                    .is_some_and(|p| matches!(p.law, SolidLaw::JohnsonCook(_)))
            })
            .collect();
        let st = &mut solver.state;
        for e in 0..ne {
            st.stress[e].copy_from_slice(&sig[6 * e..6 * e + 6]);
            st.hist[e].eps_p = hist[7 * e];
            if jc[e] {
                st.hist[e].heat = hist[7 * e + 1];
                st.hist[e].ln_j = hist[7 * e + 2];
                st.hist[e].energy = hist[7 * e + 3];
            } else {
                st.hist[e].back.copy_from_slice(&hist[7 * e + 1..7 * e + 7]);
            }
            st.hg[e].copy_from_slice(&hg[12 * e..12 * e + 12]);
            st.bulk_q[e] = bq[e];
        }
        if self.ero.is_some() {
            let ero = f64s(ero_at);
            for e in 0..ne {
                st.eroded[e] = ero[4 * e] != 0.0;
                st.hist[e].work = ero[4 * e + 1];
                if let Some(d) = st.damage.get_mut(e) {
                    *d = [ero[4 * e + 2], ero[4 * e + 3]];
                }
            }
        }
        if !st.rigid.is_empty() {
            let rb = f64s(rb_at);
            let v3 = |o: usize| [rb[o], rb[o + 1], rb[o + 2]];
            let m3 = |o: usize| [v3(o), v3(o + 3), v3(o + 6)];
            for (b, r) in st.rigid.iter_mut().enumerate() {
                let o = RB_STATE * b;
                r.x_cm = v3(o);
                r.v_cm = v3(o + 3);
                r.rot = m3(o + 6);
                r.ang_mom = v3(o + 15);
                r.omega = v3(o + 18);
                r.prev_x_cm = v3(o + 36);
                r.prev_rot = m3(o + 39);
            }
        }
        if let Some(ct) = &self.contact {
            // the closed cracks' states (for a restart file) and the resultants
            let (hits, clo) = (f64s(contact_at), f64s(contact_at + 1));
            (ct.closures_to_host(solver, &clo, false)).map_err(|e| self.internal(solver, e))?;
            let ids = solver
                .contact()
                .map(|cs| cs.forces().iter().map(|f| f.id).collect::<Vec<_>>());
            if let (Some(ids), Some(cs)) = (ids, solver.contact_mut()) {
                cs.set_forces(&ct.resultants(&hits, &clo, ids.into_iter()));
            }
        }
        c.apply(solver);
        Ok(())
    }

    /// Hand `obs` the state to write to a restart file ([`Self::save`]), unless the device
    /// failed meanwhile: what it read back then is not written over the last good file.
    fn checkpoint(&self, solver: &Solver, obs: &mut dyn Checkpointing) -> Result<(), RunError> {
        let state = self.save(solver);
        if let Some(e) = self.failed(solver) {
            return Err(e);
        }
        obs.checkpoint(solver, state).map_err(RunError::Output)
    }

    /// Run to the end time, showing the state to `obs` at the times it is due
    /// ([`Observer::next_due`]) and at the end, and the time and step in between
    /// ([`Observer::tick`]).
    pub fn run(&mut self, solver: &mut Solver, obs: &mut dyn Observer) -> Result<(), RunError> {
        self.run_checkpointed(solver, &mut NoCheckpoints(obs))
    }

    /// [`Self::run`], with restart files: the GPU also halts at the times `obs` asks for one
    /// ([`Checkpointing::checkpoint_due`]) and hands it the state ([`Self::save`]); when it
    /// says a signal asks to stop, the run halts at the next step, hands over the state there
    /// and returns unfinished ([`Solver::is_finished`] false).
    pub fn run_checkpointed(
        &mut self,
        solver: &mut Solver,
        obs: &mut dyn Checkpointing,
    ) -> Result<(), RunError> {
        let stop_at = |obs: &dyn Checkpointing| obs.next_due().min(obs.checkpoint_due());
        self.set_stop_time(stop_at(obs));
        let end_time = solver.model.control.end_time;
        // (staging buffer, when submitted, steps, the step count it starts from)
        let mut in_flight: Vec<(usize, Instant, usize, f64, bool)> = Vec::new();
        // whether the next batch is the first after a halt: the halted step's count comes in
        // it (the rest of the step, or its first dispatch, advances the step)
        let mut after_halt = false;
        let mut next_staging = 0;
        let mut stopping = false;
        // the time, step size and step count last read back, for the batches' lengths
        let (mut t_known, mut dt_known) = (solver.state.t, solver.state.dt);
        let mut step_known = solver.state.step as f64;
        loop {
            while in_flight.len() < 2 {
                let stop = if stopping {
                    t_known
                } else {
                    stop_at(obs).min(end_time)
                };
                let ahead: usize = in_flight.iter().map(|b| b.2).sum();
                let mut steps = batch_steps(self.batch, t_known, dt_known, stop, ahead);
                if let Some(t) = &self.times {
                    steps = steps.min(t.max_steps);
                }
                if steps == 0 {
                    // the batch in flight reaches the halt: another would only run idle
                    break;
                }
                let cmd = self.record(steps, next_staging);
                self.gpu.queue.submit([cmd]);
                let start = step_known + ahead as f64;
                in_flight.push((next_staging, Instant::now(), steps, start, after_halt));
                after_halt = false;
                next_staging = 1 - next_staging;
            }
            let (staging, started, recorded, start, first) = in_flight.remove(0);
            let c = self.read_control(staging);
            if let Some(e) = self.failed(solver) {
                return Err(e);
            }
            // (the steps it ran: those its count grew by, less the step halted before it, and
            // the one it halted in)
            let grew = c.step() - start - f64::from(u8::from(first));
            let ran = (grew.max(0.0) as usize + usize::from(c.halt() != 0)).min(recorded);
            self.collect_times(staging, ran);
            (t_known, dt_known, step_known) = (c.f[cf::T], c.f[cf::DT], c.step());
            let secs = started.elapsed().as_secs_f64();
            if c.halt() == 0 {
                if secs < 0.02 && self.batch < 4096 {
                    self.batch *= 2;
                }
                c.apply(solver);
                obs.tick(solver);
                if !stopping && obs.stop_asked() {
                    // halt at the next step (the batches recorded already run to it)
                    stopping = true;
                    self.set_stop_time(0.0);
                }
                continue;
            }
            // the batch still in flight does nothing once halted: let it finish
            for (s, _, _, _, _) in in_flight.drain(..) {
                self.read_control(s);
                self.collect_times(s, 0);
            }
            match c.halt() {
                3 => {
                    // the time and step of the failure in the host's state too (the summary)
                    if c.f[cf::T].is_finite() {
                        c.apply(solver);
                    }
                    return Err(RunError::Solver(c.error(solver)));
                }
                // interfaces failed: released on the host, the step run to its end
                // a step halted for the host, which changes what it must and runs the rest
                // of the step: interfaces failed (4: the sets split), elements eroded (5:
                // the contact surfaces change), closed cracks released (6)
                k @ 4..=6 => {
                    // such a halt comes when it comes: the rest of this batch and the one
                    // behind it ran idle, so the batches shrink to about the steps between
                    // halts (and grow again, doubling, while batches run through)
                    let done = (c.step() - start).max(0.0) as usize;
                    self.batch = (done + 1).next_power_of_two().clamp(4, self.batch.max(4));
                    let began = Instant::now();
                    match k {
                        4 => self.split(solver, &c)?,
                        5 => self.erode_contact(solver)?,
                        _ => self.release_cracks(solver)?,
                    }
                    let h = &mut self.halts[k as usize - 4];
                    *h = (h.0 + 1, h.1 + began.elapsed().as_secs_f64());
                    after_halt = true;
                    // (when halts come in every step no batch runs through: ask here)
                    if !stopping && obs.stop_asked() {
                        stopping = true;
                        self.set_stop_time(0.0);
                    }
                }
                h => {
                    self.mirror(solver, &c)?;
                    // (what a device that failed meanwhile read back is not written out)
                    if let Some(e) = self.failed(solver) {
                        return Err(e);
                    }
                    solver.set_finished(h == 2);
                    obs.observe(solver).map_err(RunError::Output)?;
                    let t = solver.state.t;
                    let due = t >= obs.checkpoint_due() * (1.0 - 1e-12);
                    if h == 2 {
                        // a restart file due at the end time is written, as on the CPU (a
                        // run may go on from it to a later end time)
                        if due {
                            self.checkpoint(solver, obs)?;
                        }
                        return Ok(());
                    }
                    // a halted step is a place to stop too (with frequent output every batch
                    // may halt, and the check after a batch that runs through never comes)
                    if !stopping && obs.stop_asked() {
                        stopping = true;
                    }
                    if stopping || due {
                        self.checkpoint(solver, obs)?;
                        if stopping {
                            return Ok(());
                        }
                    }
                    self.set_stop_time(stop_at(obs));
                    self.clear_halt();
                    after_halt = true;
                }
            }
        }
    }
}

/// The steps of the next batch: up to `batch`, but no further than two steps past the one
/// expected to halt at `stop` (a step halts when its start time reaches the halt time), from
/// the time `t` and step `dt` last read back with `ahead` steps already in flight; 0 when the
/// steps in flight reach it (a batch recorded past a halt runs idle: every dispatch a no-op,
/// yet each costs its launch, so with frequent output most of a long batch was idle). The
/// expected step count is a guess (the step may change): a batch that ends short of the halt
/// is followed by another, one that passes it idles for the rest.
fn batch_steps(batch: usize, t: f64, dt: f64, stop: f64, ahead: usize) -> usize {
    if dt.is_nan() || dt <= 0.0 || !stop.is_finite() {
        return batch.max(1);
    }
    // the halting step is the one that starts at or after `stop`: k steps from t, so k + 1
    // steps reach it (and one more for a step that came out shorter)
    let k = ((stop - t) / dt).ceil().clamp(0.0, 1e15) as usize;
    let reach = k + 2;
    if ahead == 0 {
        reach.clamp(1, batch.max(1))
    } else {
        reach.saturating_sub(ahead).min(batch.max(1))
    }
}

/// An observer of a GPU run that also takes restart files ([`GpuStepper::run_checkpointed`]).
pub trait Checkpointing: Observer {
    /// The next time a restart file is due (infinity: none).
    fn checkpoint_due(&self) -> f64;
    /// Whether a signal asks the run to stop (asked after each batch of steps and at each
    /// halt).
    fn stop_asked(&mut self) -> bool;
    /// Keep the state `gpu_state` ([`GpuStepper::save`]) of the step the solver's mirror shows,
    /// and move the next time due on.
    fn checkpoint(&mut self, solver: &Solver, gpu_state: Vec<u8>) -> std::io::Result<()>;
}

/// A plain observer: no restart files.
struct NoCheckpoints<'a>(&'a mut dyn Observer);

impl Observer for NoCheckpoints<'_> {
    fn observe(&mut self, solver: &Solver) -> std::io::Result<()> {
        self.0.observe(solver)
    }
    fn next_due(&self) -> f64 {
        self.0.next_due()
    }
    fn tick(&mut self, solver: &Solver) {
        self.0.tick(solver)
    }
}

impl Checkpointing for NoCheckpoints<'_> {
    fn checkpoint_due(&self) -> f64 {
        f64::INFINITY
    }
    fn stop_asked(&mut self) -> bool {
        false
    }
    fn checkpoint(&mut self, _: &Solver, _: Vec<u8>) -> std::io::Result<()> {
        Ok(())
    }
}

/// A part of a buffer to read back: the buffer, a byte offset and a byte count.
pub(crate) type Part<'a> = (&'a wgpu::Buffer, u64, u64);

/// The control block as read back.
pub(crate) struct Control {
    f: Vec<f64>,
    u: Vec<u32>,
}

impl Control {
    /// What a lost device reads as: an error with no element.
    fn lost() -> Self {
        let mut u = vec![0; cu::LEN];
        u[cu::HALT] = 3;
        Self {
            f: vec![f64::NAN; cf::LEN],
            u,
        }
    }

    fn halt(&self) -> u32 {
        self.u[cu::HALT]
    }

    /// The step count (the halves of the positions go by its parity).
    pub(crate) fn step(&self) -> f64 {
        self.f[cf::STEP]
    }

    /// Time, step, time steps and energies into the host's state.
    pub(crate) fn apply(&self, solver: &mut Solver) {
        let f = &self.f;
        let st = &mut solver.state;
        st.t = f[cf::T];
        st.step = f[cf::STEP] as u64;
        st.dt_prev = f[cf::DT_PREV];
        st.dt = f[cf::DT];
        st.dt_element = self.u[cu::DT_ELEM];
        st.energy.kinetic = f[cf::E_KIN];
        st.energy.internal = f[cf::E_INT];
        st.energy.hourglass = f[cf::E_HG];
        st.energy.eroded = f[cf::E_ERODED];
        st.energy.fracture = f[cf::E_FRAC];
        st.energy.contact = f[cf::E_CONTACT];
        st.energy.external_work = f[cf::E_EXT];
        st.initial_energy = f[cf::E_INIT];
        for (w, wf) in solver.wall_forces.iter_mut().enumerate() {
            let o = cf::WALL_FORCE + 4 * w;
            wf.normal = f[o];
            wf.force = [f[o + 1], f[o + 2], f[o + 3]];
        }
    }

    /// The failure the GPU stopped on, with the element or node, time and step, as the CPU
    /// step reports it.
    fn error(&self, solver: &Solver) -> SolverError {
        let m = solver.model;
        let (f, u) = (&self.f, &self.u);
        let time = f[cf::T];
        let step = f[cf::STEP] as u64;
        let elem = |e: u32| m.elem_ids.get(e as usize).copied().unwrap_or(0);
        let dt = f[cf::DT];
        let element = elem(u[cu::DT_ELEM]);
        match u[cu::ERROR] {
            1 => SolverError::InvertedElement {
                element: elem(u[cu::INVERTED]),
                time,
                step,
            },
            2 => SolverError::TimeStepTooSmall {
                dt,
                floor: f[cf::DT_FLOOR],
                element,
                time,
                step,
            },
            4 => SolverError::NonFinite {
                node: m
                    .node_ids
                    .iter()
                    .nth(crate::separation::node_of_entry(solver, u[cu::NONFINITE]))
                    .copied()
                    .unwrap_or(0),
                element: None,
                time,
                step,
            },
            _ => SolverError::BadTimeStep {
                dt,
                element,
                time,
                step,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::batch_steps;

    #[test]
    fn batches_end_just_past_the_expected_halt() {
        // dt 1, halt at t = 10 from t = 0: the step starting at 10 halts, the 11th; one spare
        assert_eq!(batch_steps(4096, 0.0, 1.0, 10.0, 0), 12);
        // 8 of them in flight already: 4 more
        assert_eq!(batch_steps(4096, 0.0, 1.0, 10.0, 8), 4);
        // the ones in flight reach it: none
        assert_eq!(batch_steps(4096, 0.0, 1.0, 10.0, 12), 0);
        // a halt far off: the whole batch, in flight or not
        assert_eq!(batch_steps(64, 0.0, 1.0, 1e9, 0), 64);
        assert_eq!(batch_steps(64, 0.0, 1.0, 1e9, 64), 64);
        // a halt due now (a signal, or an output time passed): one step (two with the spare)
        assert_eq!(batch_steps(64, 5.0, 1.0, 5.0, 0), 2);
        assert_eq!(batch_steps(64, 5.0, 1.0, 3.0, 0), 2);
        // no step known yet (the first batch) or no halt: the batch as it is
        assert_eq!(batch_steps(4, 0.0, 0.0, 10.0, 0), 4);
        assert_eq!(batch_steps(4, 0.0, 1.0, f64::INFINITY, 4), 4);
    }
}
