//! Automatic contact on the GPU (`contact.wgsl`): the tables its passes read, its buffers and
//! pipelines, and the resultants for `rcforc.csv`.
//!
//! The host solver's [`ContactSet`] (cleave-core contact/) gives the surfaces: each
//! definition's sides (faces, with their stiffness and depth), its passes, the order the CPU
//! scatters the nodes' forces in, the faces that make each node's normal, the nodes'
//! stiffness and the friction. The GPU runs the same node-to-face penalty contact with friction
//! (closest point, least penetration, the engagement of a spring, PENOPT, the energy's
//! trapezoid) with its own broad phase, a hashed grid rebuilt every step (contact.wgsl), and
//! adds each node's contact force in the CPU's order (for one definition; with several, the
//! closed cracks' pairs of all of them come first; with separation, each slot's: the closed
//! cracks' pairs, then its members' pass-nodes merged in pass-node order, where the CPU
//! sums node by node, then per slot: the same terms in another order, round-off apart). The
//! stable time step of the springs is the CPU's ([`Solver::contact_time_step`]), a constant.
//!
//! Surfaces that erosion changes are made again on the host in the steps elements erode
//! (`GpuStepper::erode_contact`, [`ContactGpu::upload`] with each pair carried over). With
//! element separation, the faces of the interfaces that fail join the surfaces and their cracks
//! close on the host in the halt of their step (`separation.rs` split), and the tables are made
//! again; the contact reads the nodes at their coincident sets' slots, checks each set's lead
//! only (with its set's normal, carrying its set's pair when the lead changes), leaves out the
//! faces that hold a copy chained to the node, and steps the closed cracks (contact.wgsl
//! c_close); a step in which one is released halts (HALT 6) for the host to let it go
//! (`GpuStepper::release_cracks`).
//!
//! [`ContactSet`]: cleave_core::contact::ContactSet

use cleave_core::contact::view::CLOSURE_STATE;
use cleave_core::contact::ContactForce;
use cleave_core::solver::Solver;

use crate::contact_tables::{carry_pairs, tables, Scratch};
pub(crate) use crate::contact_tables::{Carry, Tables, Tuning, CLO, HIT, PARAMS};
use crate::device::{Gpu, GpuError};
use crate::relayout::Writes;
use crate::stepper::Part;

/// The passes of contact.wgsl, in the order they run.
pub(crate) const PASSES: [&str; 16] = [
    "c_close",
    "c_close_done",
    "c_count",
    "c_sums",
    "c_scan",
    "c_offsets",
    "c_fill",
    "c_detect",
    "c_hsums",
    "c_hscan",
    "c_hoffsets",
    "c_hfill",
    "c_hsort",
    "c_hlong",
    "c_gather",
    "c_energy",
];

/// The release flag of a closed crack let go on the device without new tables
/// ([`ContactGpu::release_in_place`]; contact.wgsl c_close passes it by): 1 marks one released
/// in this step, 2 one released in an earlier step since the tables were made.
const DEAD: f64 = 2.0;

/// f64 values per face in the face spheres' buffer (contact.wgsl FS).
const FS: usize = 28;

/// The place of c_gather in [`PASSES`] (its groups' partial sums of the work fill `cpart`).
const GATHER: usize = 14;

/// The contact passes of the step, their buffers and their bind group.
pub(crate) struct ContactGpu {
    /// The passes ([`PASSES`]) and the groups each runs over the present tables.
    pub passes: Vec<(&'static str, wgpu::ComputePipeline)>,
    pub groups: [usize; 16],
    layout: wgpu::BindGroupLayout,
    pub bind_group: wgpu::BindGroup,
    /// The step's arrays it reads: control block (floats and integers: it halts the step
    /// when a closed crack is released), positions, velocities.
    cf: wgpu::Buffer,
    cu: wgpu::Buffer,
    x: wgpu::Buffer,
    v: wgpu::Buffer,
    /// Each node's contact force of the step (3 per model node), read by the step's shader.
    pub fcon: wgpu::Buffer,
    /// The tables' buffers (bound in `bind_group`): the tables, the pairs (hits, HIT values
    /// per pass-node) and the last step's contact force of each surface node (3 each) that
    /// carry over to the next step, the grid's, the work arrays, the closed cracks' states
    /// ([`CLO`] values each).
    b: Buffers,
    /// The present tables, the arrays of the ones before (to be filled again) and the work
    /// arrays that make them.
    tables: Tables,
    spare: Tables,
    scratch: Scratch,
    /// For tests: a value written all over the grid and the work arrays whenever new tables
    /// are written into their buffers (what the tables before may have left there;
    /// [`ContactGpu::clear`] must zero them before the contact's passes).
    pub poison: Option<u32>,
    /// How the passes share their work (for the device; other lists only in tests,
    /// [`Self::set_lists`]).
    tuning: Tuning,
    /// Closed cracks' releases let go in place, and those for which the tables were made
    /// again ([`Self::release_in_place`]); for tests, `remake_releases` makes them again always.
    pub releases: [u64; 2],
    pub remake_releases: bool,
    /// For tests ([`Tuning::verify`]): the candidate lists made, the faces a list missed and
    /// the faces looked for, under the tables before the present ones ([`Self::tally`]).
    pub verified: [u64; 3],
}

/// The step's shader text that reads the contact forces: with contact, `fcon` at binding
/// 32 (after the separation's); without, a zero force and no binding.
pub(crate) fn step_prefix(with: bool) -> &'static str {
    if with {
        "@group(0) @binding(32) var<storage, read> fcon: array<f64>;\n\
         fn contact_force(n: u32) -> vec3<f64> {\n    \
         return vec3<f64>(fcon[3u * n], fcon[3u * n + 1u], fcon[3u * n + 2u]);\n}\n"
    } else {
        "fn contact_force(n: u32) -> vec3<f64> {\n    return vec3<f64>(0.0lf, 0.0lf, 0.0lf);\n}\n"
    }
}

const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_SRC)
    .union(wgpu::BufferUsages::COPY_DST);

fn zeros(gpu: &Gpu, label: &str, bytes: usize) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(8) as u64,
        usage: STORAGE,
        mapped_at_creation: false,
    })
}

/// Refuses (TooLarge) tables `t` with an array larger than the device binds (the contact
/// binds every array whole), or positions `x` larger.
fn check_sizes(gpu: &Gpu, t: &Tables, x: &wgpu::Buffer) -> Result<(), GpuError> {
    let limit = gpu.limits.max_storage_buffer_binding_size;
    let sizes = [
        ("its tables", (4 * t.ci.len()).max(8 * t.cfl.len()) as u64),
        ("its search grid", 4 * t.grid_len as u64),
        ("its contact pairs", (8 * HIT * t.pass_nodes) as u64),
        ("its closed cracks", (8 * t.clo.len()) as u64),
        ("the positions", x.size()),
    ];
    match sizes.iter().find(|(_, b)| *b > limit) {
        Some((what, bytes)) => Err(GpuError::TooLarge(format!(
            "contact on the GPU binds each array whole, and {what} need {bytes} bytes; {} binds at most {limit} bytes per array",
            gpu.info.name
        ))),
        None => Ok(()),
    }
}

/// The contact's buffers, in this order, by their place in [`Buffers::bufs`].
const CI: usize = 0;
const CFL: usize = 1;
const HITS: usize = 2;
const FPREV: usize = 3;
const GRID: usize = 4;
const CPART: usize = 5;
const FSPH: usize = 6;
const CLOS: usize = 7;
const LABELS: [&str; 8] = [
    "contact tables",
    "contact values",
    "contact pairs",
    "contact forces, last step",
    "contact grid",
    "contact work partials",
    "contact face spheres",
    "closed cracks",
];

/// The buffers of the tables. Tables made again at a split are mostly the size of the ones
/// before, so each buffer keeps room to grow: the tables are written into it while they fit,
/// and a buffer a quarter larger than needed is made when they do not (the bind group is then
/// made again). The grid and the work arrays are zeroed on the device, as new buffers are, by
/// the first commands recorded after ([`ContactGpu::clear`]), not in a submission of their own.
#[derive(Default)]
struct Buffers {
    bufs: Vec<wgpu::Buffer>,
    to_clear: std::cell::Cell<bool>,
    /// For tests: the buffers written all over with [`ContactGpu::poison`] so far.
    poisoned: u64,
}

impl Buffers {
    /// Tables `t` (with their closed cracks' states) with pairs `h` and last forces `fp` on
    /// the device, in these buffers where they fit; true when a buffer was made anew.
    fn fit(&mut self, gpu: &Gpu, t: &Tables, h: &[f64], fp: &[f64], poison: Option<u32>) -> bool {
        // (a binding is never empty)
        let none = [0.0f64; CLO];
        let clo_values = if t.clo.is_empty() {
            &none[..]
        } else {
            &t.clo[..]
        };
        let written: [&[u8]; 4] = [
            bytemuck::cast_slice(&t.ci),
            bytemuck::cast_slice(&t.cfl),
            bytemuck::cast_slice(h),
            bytemuck::cast_slice(fp),
        ];
        // (the faces' values, then the displacement bounds of c_count's groups: contact.wgsl
        // FS, BOUNDS)
        let spheres = FS * t.faces + 6 * t.faces.div_ceil(crate::stepper::GROUP);
        let zeroed = [4 * t.grid_len, 8 * t.groups()[GATHER], 8 * spheres];
        let contents = |k: usize| match k {
            CLOS => Some(bytemuck::cast_slice(clo_values)),
            k if k < GRID => Some(written[k]),
            _ => None,
        };
        let limit = gpu.limits.max_storage_buffer_binding_size;
        let mut remade = false;
        for (k, label) in LABELS.into_iter().enumerate() {
            let bytes = contents(k).map_or(zeroed[k.saturating_sub(GRID).min(2)], |c| c.len());
            let bytes = bytes.max(8) as u64;
            match self.bufs.get(k) {
                Some(b) if b.size() >= bytes => match contents(k) {
                    Some(c) => gpu.queue.write_buffer(b, 0, c),
                    None => {
                        if let Some(p) = poison {
                            let words = vec![p; b.size() as usize / 4];
                            gpu.queue.write_buffer(b, 0, bytemuck::cast_slice(&words));
                            self.poisoned += 1;
                        }
                        self.to_clear.set(true)
                    }
                },
                _ => {
                    // (the limit may be odd, 2^31 - 1 on an H100: a binding's size must be a
                    // multiple of 4)
                    let room = (bytes + bytes / 4)
                        .next_multiple_of(8)
                        .min(limit & !7)
                        .max(bytes);
                    let b = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size: room,
                        usage: STORAGE,
                        mapped_at_creation: false,
                    });
                    if let Some(c) = contents(k) {
                        gpu.queue.write_buffer(&b, 0, c);
                    }
                    match k < self.bufs.len() {
                        true => self.bufs[k] = b,
                        false => self.bufs.push(b),
                    }
                    remade = true;
                }
            }
        }
        remade
    }

    /// Zero the grid and the work arrays in `enc`, if tables were written into them since
    /// they were last zeroed (a new buffer is zero): the first commands recorded after new
    /// tables, before any contact pass.
    fn clear(&self, enc: &mut wgpu::CommandEncoder) {
        if self.to_clear.replace(false) {
            for b in &self.bufs[GRID..CLOS] {
                enc.clear_buffer(b, 0, None);
            }
        }
    }

    /// These buffers bound with the step's control block, positions and velocities `step`
    /// (`cf`, `x`, `v`, `cu`) and the contact forces `fcon`, in contact.wgsl's bindings.
    fn bind(
        &self,
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        step: [&wgpu::Buffer; 4],
        fcon: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let b = &self.bufs;
        let bound = [
            step[0], step[1], step[2], &b[CI], &b[CFL], &b[HITS], fcon, &b[FPREV], &b[GRID],
            &b[CPART], &b[FSPH], &b[CLOS], step[3],
        ];
        let entries: Vec<_> = (bound.iter().enumerate())
            .map(|(b, buf)| wgpu::BindGroupEntry {
                binding: b as u32,
                resource: buf.as_entire_binding(),
            })
            .collect();
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("contact"),
            layout,
            entries: &entries,
        })
    }
}

impl ContactGpu {
    /// The contact of `solver` on `gpu`, reading the step's control block `cf` and `cu`,
    /// positions `x` and velocities `v`; `None` without contact. Refuses (TooLarge) an array
    /// larger than the device binds: the contact binds every array whole.
    pub fn new(
        gpu: &Gpu,
        solver: &mut Solver,
        [cf, cu, x, v]: [&wgpu::Buffer; 4],
    ) -> Result<Option<Self>, GpuError> {
        // the host's contact brought up to its coincident sets (the chains of closed cracks,
        // the sets' leads) before its tables are read
        solver.settle_contact(false);
        let mut scratch = Scratch::default();
        let Some(mut t) = tables(solver, &mut scratch, Tables::default()) else {
            return Ok(None);
        };
        let tuning = Tuning::for_device(&gpu.info);
        t.tune(tuning);
        let dev = &gpu.device;
        let read_only = [
            false, true, true, true, true, false, false, false, false, false, false, false, false,
        ];
        let layout_entries: Vec<_> = (read_only.iter().enumerate())
            .map(|(b, &read_only)| wgpu::BindGroupLayoutEntry {
                binding: b as u32,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("contact"),
            entries: &layout_entries,
        });
        let source = shader_source();
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("contact.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("contact"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let passes = PASSES.map(|name| {
            let p = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&pl),
                module: &module,
                entry_point: Some(name),
                compilation_options: Default::default(),
                cache: None,
            });
            (name, p)
        });
        let fcon = zeros(gpu, "contact forces", 24 * solver.model.num_nodes());
        check_sizes(gpu, &t, x)?;
        let (h, fp) = t.no_pairs();
        let mut b = Buffers::default();
        b.fit(gpu, &t, &h, &fp, None);
        let bind_group = b.bind(gpu, &layout, [cf, x, v, cu], &fcon);
        Ok(Some(Self {
            passes: passes.into(),
            groups: t.groups(),
            layout,
            bind_group,
            cf: cf.clone(),
            cu: cu.clone(),
            x: x.clone(),
            v: v.clone(),
            fcon,
            b,
            tables: t,
            spare: Tables::default(),
            scratch,
            poison: None,
            tuning,
            releases: [0; 2],
            remake_releases: false,
            verified: [0; 3],
        }))
    }

    /// The tables of the solver's contact as it is now ([`tables`]), made in the arrays of the
    /// tables before the present ones; `None` without contact.
    pub fn tables_now(&mut self, solver: &Solver) -> Option<Tables> {
        tables(solver, &mut self.scratch, std::mem::take(&mut self.spare))
    }

    /// Put tables `t` on the device (into the buffers where they fit, [`Buffers::fit`]; the
    /// pipelines stay), the pairs and last forces `carry` (the hits and each surface entry's
    /// force of the tables before, as read back, and the slots born in this step with the
    /// slot each split from) carried over to the new numbering ([`carry_pairs`]); new ones
    /// start from none.
    pub fn upload(
        &mut self,
        gpu: &Gpu,
        t: Tables,
        carry: Option<Carry>,
        w: Option<&mut Writes>,
    ) -> Result<(), GpuError> {
        check_sizes(gpu, &t, &self.x)?;
        let mut t = t;
        t.tune(self.tuning);
        let (mut h, mut fp) = t.no_pairs();
        if let Some(carry) = carry {
            // an entry that left the surface gathers no force from now on (through `w`, with
            // the halt's other writes, or through writes of their own)
            let left = carry_pairs(&self.tables, &t, carry, &mut h, &mut fp, &mut self.scratch);
            let mut own = Writes::default();
            let w = w.unwrap_or(&mut own);
            for e in left {
                let at = 24 * u64::from(e);
                if at + 24 <= self.fcon.size() {
                    w.put(&self.fcon, at, &[0.0f64; 3]);
                }
            }
            own.submit(gpu);
        }
        if self.b.fit(gpu, &t, &h, &fp, self.poison) {
            let step = [&self.cf, &self.x, &self.v, &self.cu];
            self.bind_group = self.b.bind(gpu, &self.layout, step, &self.fcon);
        }
        self.groups = t.groups();
        self.spare = std::mem::replace(&mut self.tables, t);
        Ok(())
    }

    /// What the device holds of the pairs, the surface entries' last forces and the closed
    /// cracks' states (whole buffers may hold more: room to grow), to be read back.
    pub fn hits(&self) -> Part<'_> {
        (&self.b.bufs[HITS], 0, self.tables.pair_bytes()[0])
    }

    /// The surface entries' last forces on the device ([`Self::hits`]).
    pub fn fprev(&self) -> Part<'_> {
        (&self.b.bufs[FPREV], 0, self.tables.pair_bytes()[1])
    }

    /// The closed cracks' states on the device ([`Self::hits`]).
    pub fn clo(&self) -> Part<'_> {
        (&self.b.bufs[CLOS], 0, self.tables.closure_bytes())
    }

    /// Record the zeroing of the grid and work arrays into `enc` when new tables were written
    /// into their buffers since ([`Buffers::fit`]): call first thing in every encoder that
    /// records the contact's passes.
    pub fn clear(&self, enc: &mut wgpu::CommandEncoder) {
        self.b.clear(enc);
    }

    /// For tests: the longest list of the nodes pushing on a face that one thread sorts and
    /// adds, and the longest a group sorts in its own memory ([`Tuning::lists`]), and whether
    /// the lists are filled from their end, for the present tables and the ones made from now
    /// on.
    pub fn set_lists(&mut self, gpu: &Gpu, lists: [u32; 2], reverse: bool) {
        self.tuning.lists = lists;
        self.tuning.reverse = u32::from(reverse);
        self.retune(gpu);
    }

    /// The present tables' tuned values written again from [`Self::tuning`] (tests).
    fn retune(&mut self, gpu: &Gpu) {
        let (values, k) = self.tables.tune(self.tuning);
        let at = 4 * k as u64;
        gpu.queue
            .write_buffer(&self.b.bufs[CI], at, bytemuck::cast_slice(&values));
    }

    /// For tests: the most candidates a node's list holds ([`Tuning::cands`]) and whether the
    /// lists are checked ([`Tuning::verify`]), for the present tables and the ones made from
    /// now on.
    pub fn set_cands(&mut self, gpu: &Gpu, cands: u32, verify: bool) {
        self.tuning.cands = cands;
        self.tuning.verify = u32::from(verify);
        self.retune(gpu);
        // the lists made again (or not used) from the next step: those made hold C_K faces
        let made = 4 * (self.tables.param("G_FLAGS") + 4) as u64;
        (gpu.queue).write_buffer(&self.b.bufs[GRID], made, bytemuck::bytes_of(&0u32));
    }

    /// Whether the lists are checked ([`Tuning::verify`]): their counts are then read back
    /// before new tables zero them, and added up ([`Self::tally`]).
    pub fn verifying(&self) -> bool {
        self.tuning.verify != 0
    }

    /// The grid's flags as read back ([`Self::flags`]): the lists' counts (made, missed,
    /// looked for), those of the present tables added to [`Self::verified`].
    pub fn tally(&self, flags: &[u8]) -> [u64; 3] {
        let f: Vec<u32> = bytemuck::pod_collect_to_vec(flags);
        let now = [f[3], f[5], f[6]];
        std::array::from_fn(|k| self.verified[k] + u64::from(now[k]))
    }

    /// The grid's flags (contact.wgsl G_FLAGS, [`FLAGS`](crate::contact_tables::FLAGS)), to be
    /// read back.
    pub fn flags(&self) -> Part<'_> {
        let at = 4 * self.tables.param("G_FLAGS") as u64;
        (
            &self.b.bufs[GRID],
            at,
            4 * crate::contact_tables::FLAGS as u64,
        )
    }

    /// For tests: the buffers written all over with [`Self::poison`] so far.
    pub fn poisoned(&self) -> u64 {
        self.b.poisoned
    }

    /// The present tables.
    pub fn tables(&self) -> &Tables {
        &self.tables
    }

    /// The bytes of the contact's buffers on the device.
    pub fn bytes(&self) -> u64 {
        self.b.bufs.iter().map(|b| b.size()).sum()
    }

    /// The closed cracks' states `clo` (as read back) into the host's contact of `solver`,
    /// the cracks flagged released leaving it when `released`
    /// ([`ContactSet::closures_stepped`]).
    ///
    /// [`ContactSet::closures_stepped`]: cleave_core::contact::ContactSet::closures_stepped
    pub fn closures_to_host(
        &self,
        solver: &mut Solver,
        clo: &[f64],
        released: bool,
    ) -> Result<(), String> {
        let Some(cs) = solver.contact_mut() else {
            return Ok(());
        };
        let t = &self.tables;
        for d in 0..cs.contacts().len() {
            let (mut states, mut flags) = (vec![], vec![]);
            for (k, _) in t.closures.iter().enumerate().filter(|&(_, &e)| e == d) {
                let s = clo
                    .get(CLO * k..CLO * (k + 1))
                    .ok_or("the closed cracks read back are cut short")?;
                // (one released in place before is the host's no longer)
                if s[CLOSURE_STATE] == DEAD {
                    continue;
                }
                states.extend_from_slice(&s[..CLOSURE_STATE]);
                flags.push(released && s[CLOSURE_STATE] == 1.0);
            }
            cs.closures_stepped(d, &states, &flags)?;
        }
        Ok(())
    }

    /// The closed cracks released in this step (their flag 1 in `clo`, as read back; the host
    /// has let them go, [`Self::closures_to_host`], and settled its contact) let go on the
    /// device without new tables: each one's state zeroed and marked [`DEAD`] (c_close passes it
    /// by, its pairs add no force, its faces are no longer tight), and every chain label of the
    /// faces and pass-nodes written again from the host's chains, through `w`. The tables made
    /// again would differ in these alone (a release changes no surface, set or lead; their
    /// order and the faces' numbers stay), and the released cracks' entries, which they leave
    /// out, add nothing. False, with nothing written, when the host's surfaces or leads are not
    /// those of the tables: then they must be made again.
    pub fn release_in_place(&mut self, solver: &Solver, clo: &[f64], w: &mut Writes) -> bool {
        let done = !self.remake_releases && self.release_labels(solver, clo, w);
        self.releases[usize::from(!done)] += 1;
        done
    }

    /// [`Self::release_in_place`], uncounted.
    fn release_labels(&mut self, solver: &Solver, clo: &[f64], w: &mut Writes) -> bool {
        let Some(cs) = solver.contact() else {
            return false;
        };
        let t = &self.tables;
        // the faces, in the tables' order, and their corners' labels
        let mut face_labels = Vec::with_capacity(4 * t.faces);
        for &(d, side, _) in &t.sides {
            let c = &cs.contacts()[d as usize];
            for face in c.faces(side as usize) {
                let f = face_labels.len() / 4;
                if t.face_key.get(f) != Some(&(d, side, face.elem, face.face)) {
                    return false;
                }
                face_labels.extend(face.nodes.map(|n| c.chain_label(n)));
            }
        }
        // the leads, in the tables' order, and their labels
        let mut lead_labels = Vec::with_capacity(t.pass_nodes);
        for (d, c) in cs.contacts().iter().enumerate() {
            for (ns, _) in c.pass_sides() {
                for n in c.leads_in_scatter_order(ns) {
                    let j = lead_labels.len();
                    if t.pn_key.get(j).map(|k| k.1) != Some(n)
                        || t.pn_def.get(j).map(|p| p.0) != Some(d)
                    {
                        return false;
                    }
                    lead_labels.push(c.chain_label(n));
                }
            }
        }
        if face_labels.len() != 4 * t.faces || lead_labels.len() != t.pass_nodes {
            return false;
        }
        let t = &mut self.tables;
        let (flab, pn) = (t.param("CI_FLAB"), t.param("CI_PN"));
        t.ci[flab..flab + 4 * t.faces].copy_from_slice(&face_labels);
        for (j, l) in lead_labels.into_iter().enumerate() {
            t.ci[pn + 4 * j + 3] = l;
        }
        let ci = &self.b.bufs[CI];
        w.put(ci, 4 * flab as u64, &t.ci[flab..flab + 4 * t.faces]);
        w.put(ci, 4 * pn as u64, &t.ci[pn..pn + 4 * t.pass_nodes]);
        let mut dead = [0.0f64; CLO];
        dead[CLOSURE_STATE] = DEAD;
        for k in 0..t.closures.len() {
            if clo.get(CLO * k + CLOSURE_STATE) == Some(&1.0) {
                w.put(&self.b.bufs[CLOS], (8 * CLO * k) as u64, &dead);
            }
        }
        true
    }

    /// Each definition's resultants from the hits and closed cracks read back (mod.rs
    /// ContactForce: the force on the slave side, the sum of |f_n|, the pairs), summed in the
    /// CPU's order: the closed cracks' pairs, then the pass-nodes.
    pub fn resultants(
        &self,
        hits: &[f64],
        clo: &[f64],
        ids: impl Iterator<Item = i64>,
    ) -> Vec<ContactForce> {
        let mut out: Vec<ContactForce> = ids
            .map(|id| ContactForce {
                id,
                ..Default::default()
            })
            .collect();
        for (k, &d) in self.tables.closures.iter().enumerate() {
            let Some(s) = clo.get(CLO * k..CLO * (k + 1)) else {
                break;
            };
            // closure.rs Closure::force: fn_mag n, plus the friction unless frictionless (the
            // closed cracks first, as the CPU adds them: mod.rs Contact::compute)
            let frictionless = self.tables.cfl[self.tables.param("CF_DEF") + 4 * d + 3] != 0.0;
            for p in 0..4 {
                let fn_mag = s[15 + p];
                if fn_mag > 0.0 {
                    let o = &mut out[d];
                    for i in 0..3 {
                        let mut f = s[12 + i] * fn_mag;
                        if !frictionless {
                            f += s[3 * p + i];
                        }
                        o.force[i] += f;
                    }
                    o.normal += fn_mag;
                    o.pairs += 1;
                }
            }
        }
        for (j, &(d, sign)) in self.tables.pn_def.iter().enumerate() {
            let Some(h) = hits.get(HIT * j..HIT * (j + 1)) else {
                break;
            };
            if h[0] < 0.0 || h[10] == 0.0 {
                continue;
            }
            let o = &mut out[d];
            for k in 0..3 {
                o.force[k] += h[5 + k] * sign;
            }
            o.normal += h[10];
            o.pairs += 1;
        }
        out
    }
}

/// contact.wgsl with the declaration and loading of its parameters ([`PARAMS`]) and the shared
/// math before it.
pub(crate) fn shader_source() -> String {
    let mut s = String::new();
    for name in PARAMS {
        s += &format!("var<private> {name}: u32;\n");
    }
    s += "fn params() {\n";
    for (k, name) in PARAMS.iter().enumerate() {
        s += &format!("    {name} = ci[{k}u];\n");
    }
    s += "}\n";
    s + include_str!("math.wgsl") + include_str!("contact.wgsl")
}

#[cfg(test)]
mod tests {
    use super::*;
    use cleave_core::model::{ContactDef, Material, MaterialKind};
    use wgpu::naga;

    /// A 2 x 2 x 2 block with single surface contact: its tables, and the shader made of them
    /// validates in naga (the WGSL front end wgpu uses), without a device.
    #[test]
    fn tables_of_a_block_and_the_shader_validates() {
        let steel = Material {
            id: 1,
            density: 7800.0,
            young: 2e11,
            poisson: 0.3,
            kind: MaterialKind::Elastic,
        };
        let mut m = cleave_core::mesh::box_model([2, 2, 2], [1.0, 1.0, 1.0], steel, 1.0);
        m.contacts.push(ContactDef::single_surface_all(0.1, 0.1));
        let mut s = Solver::new(&m).unwrap();
        s.attach_contact(cleave_core::contact::ContactSet::new(&m, None).unwrap());
        let t = tables(&s, &mut Scratch::default(), Tables::default()).unwrap();
        // 24 exterior faces, the 26 nodes on the surface (all but the centre), one pass
        assert_eq!((t.faces, t.pass_nodes, t.surface_nodes), (24, 26, 26));
        let c = |name: &str| t.param(name);
        // each surface node: one own entry, and a corner of its faces (a corner of the block
        // of 3, the middle of an edge of 4, the centre of a side of 4): 96 over the 26
        let (goptr, gfptr, ng) = (c("CI_GOPTR"), c("CI_GFPTR"), t.surface_nodes);
        let own = t.ci[goptr + ng] - t.ci[goptr];
        let corners = t.ci[gfptr + ng] - t.ci[gfptr];
        assert_eq!((own, corners), (26, 96));
        // each node's normal from its faces on the side: 3 at a corner, 4 elsewhere
        let nfptr = c("CI_NFPTR");
        let frame: Vec<u32> = (0..26)
            .map(|j| t.ci[nfptr + j + 1] - t.ci[nfptr + j])
            .collect();
        assert_eq!(frame.iter().filter(|&&k| k == 3).count(), 8);
        assert_eq!(frame.iter().sum::<u32>(), 96);
        // the cell: 0.7 of every face's sphere diameter, 2 (E r + 0.4 V/A) with r = sqrt(2)/4
        // for the 0.5 squares of elements 0.125 in volume; the lists' margin a tenth of the
        // faces' sqrt(area), 0.05
        let (h, mu) = (t.cfl[c("CF_H")], t.cfl[c("CF_MU")]);
        let want = 0.7 * 2.0 * (1.08 * 2f64.sqrt() / 4.0 + 0.4 * 0.125 / 0.25);
        assert!((h - want).abs() < 1e-12, "{h} {want}");
        assert!((mu - 0.05).abs() < 1e-15, "{mu}");
        let src = shader_source();
        let module = match naga::front::wgsl::parse_str(&src) {
            Ok(m) => m,
            Err(e) => panic!("{}", e.emit_to_string(&src)),
        };
        let mut v = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::FLOAT64,
        );
        if let Err(e) = v.validate(&module) {
            panic!("{}", e.emit_to_string(&src));
        }
    }
}
