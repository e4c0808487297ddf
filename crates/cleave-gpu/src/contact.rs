//! Automatic contact on the GPU (`contact.wgsl`): the tables its passes read, its buffers and
//! pipelines, and the resultants for `rcforc.csv`.
//!
//! The host solver's [`ContactSet`] (cleave-core contact/) gives the surfaces: each
//! definition's sides (faces, with their stiffness and depth), its passes, the order the CPU
//! scatters the nodes' forces in, the faces that make each node's normal, the nodes'
//! stiffness and the friction. The GPU runs the same node-to-face penalty contact with friction
//! (closest point, least penetration, the engagement of a spring, PENOPT, the energy's
//! trapezoid) with its own broad phase, a hashed grid rebuilt every step (contact.wgsl), and
//! adds each node's contact force in the CPU's order. The stable time step of the springs is
//! the CPU's ([`Solver::contact_time_step`]), a constant.
//!
//! Surfaces that change are not taken (faces of failed interfaces or eroded elements joining
//! them): `support::unsupported` refuses contact with element separation or erosion.

use cleave_core::contact::{ContactForce, ContactSet};
use cleave_core::model::PenaltyRule;
use cleave_core::solver::Solver;
use wgpu::util::DeviceExt;

use crate::device::{Gpu, GpuError};

/// Values per pass-node in the hits array (contact.wgsl HIT).
pub(crate) const HIT: usize = 14;

/// Largest cells a face's sphere spans along an axis before it goes to the list every node
/// reads (contact.wgsl SPAN), so at most `CELLS` cells a face.
const CELLS: usize = 27;

/// The tables of contact.wgsl, built on the host from the solver's definitions.
#[derive(Debug, Default)]
pub(crate) struct Tables {
    /// `u32` tables (`ci`) and `f64` tables (`cfl`), with the offsets of their parts.
    pub ci: Vec<u32>,
    pub cfl: Vec<f64>,
    /// The shader's constants: name, value.
    pub consts: Vec<(&'static str, u64)>,
    pub faces: usize,
    pub pass_nodes: usize,
    pub surface_nodes: usize,
    /// Each pass-node's definition and sign in its definition's resultant (1 for a slave
    /// node's pass, -1 for a master node's: the force on the slave side).
    pub pn_def: Vec<(usize, f64)>,
    /// u32 values of the grid and hit lists.
    pub grid_len: usize,
}

/// The tables of the solver's contact definitions; `None` without contact.
pub(crate) fn tables(solver: &Solver) -> Option<Tables> {
    let cs: &ContactSet = solver.contact()?;
    if cs.is_empty() {
        return None;
    }
    let model = solver.model;
    let nn = model.num_nodes();
    // faces of every side of every definition, numbered in that order; each side a tag
    let mut face_nodes: Vec<u32> = vec![];
    let (mut face_tag, mut fk, mut fdepth) = (vec![], vec![], vec![]);
    let mut side_start: Vec<Vec<(u32, u32)>> = vec![]; // (first face, tag) per def, side
    let mut tag = 0u32;
    for c in cs.contacts() {
        let mut sides = vec![];
        for side in 0..c.num_sides() {
            sides.push((face_tag.len() as u32, tag));
            for f in c.faces(side) {
                face_nodes.extend_from_slice(&f.nodes);
                face_tag.push(tag);
                fk.push(f.k);
                fdepth.push(f.depth);
            }
            tag += 1;
        }
        side_start.push(sides);
    }
    let nf = face_tag.len();
    // the pass-nodes: definitions, passes, each node side's nodes in scatter order
    let (mut pn, mut pass_tab, mut kn, mut pn_def) = (vec![], vec![], vec![], vec![]);
    let mut frame: Vec<Vec<u32>> = vec![];
    for (d, c) in cs.contacts().iter().enumerate() {
        for (p, (ns, fs)) in c.pass_sides().into_iter().enumerate() {
            let q = pass_tab.len() as u32 / 2;
            pass_tab.extend([side_start[d][fs].1, d as u32]);
            let sign = if p == 0 { 1.0 } else { -1.0 };
            for n in c.nodes_in_scatter_order(ns) {
                pn.extend([n, q]);
                kn.push(cs.node_stiffness(n));
                pn_def.push((d, sign));
                let first = side_start[d][ns].0;
                frame.push(c.faces_of_node(ns, n).iter().map(|f| first + f).collect());
            }
        }
    }
    let np = pn_def.len();
    // the surface nodes: every node of a pass or a face, ascending; what acts on each
    let mut own: Vec<Vec<u32>> = vec![vec![]; nn];
    let mut corner: Vec<Vec<u32>> = vec![vec![]; nn];
    for j in 0..np {
        own[pn[2 * j] as usize].push(j as u32);
    }
    for (k, &n) in face_nodes.iter().enumerate() {
        corner[n as usize].push(k as u32); // 4 f + a
    }
    let surface: Vec<u32> = (0..nn as u32)
        .filter(|&n| !own[n as usize].is_empty() || !corner[n as usize].is_empty())
        .collect();
    let ng = surface.len();
    // ci: faces' nodes and tags, pass-nodes, passes, then three lists with their pointers
    // (absolute indices into ci)
    let mut ci = face_nodes;
    ci.extend_from_slice(&face_tag);
    let ci_pn = ci.len();
    ci.extend_from_slice(&pn);
    let ci_pass = ci.len();
    ci.extend_from_slice(&pass_tab);
    let csr = |ci: &mut Vec<u32>, lists: &mut dyn Iterator<Item = Vec<u32>>, count: usize| {
        let ptr = ci.len();
        ci.resize(ptr + count + 1, 0);
        for (k, list) in lists.enumerate() {
            ci[ptr + k] = ci.len() as u32;
            ci.extend(list);
        }
        ci[ptr + count] = ci.len() as u32;
        ptr
    };
    let ci_nfptr = csr(&mut ci, &mut frame.into_iter(), np);
    let ci_gn = ci.len();
    ci.extend_from_slice(&surface);
    let ci_goptr = csr(
        &mut ci,
        &mut surface.iter().map(|&n| own[n as usize].clone()),
        ng,
    );
    let ci_gfptr = csr(
        &mut ci,
        &mut surface.iter().map(|&n| corner[n as usize].clone()),
        ng,
    );
    // cfl: faces' stiffness and depth, pass-nodes' stiffness, friction per definition,
    // PENOPT, the cell size
    let mut cfl = fk;
    cfl.extend_from_slice(&fdepth);
    let cf_kn = cfl.len();
    cfl.extend_from_slice(&kn);
    let cf_def = cfl.len();
    for c in cs.contacts() {
        let fr = c.friction;
        cfl.extend([fr.fs, fr.fd, fr.dc, fr.is_frictionless() as u8 as f64]);
    }
    let cf_pen = cfl.len();
    cfl.push(match model.control.penalty {
        PenaltyRule::Smaller => 1.0,
        PenaltyRule::Face => 2.0,
    });
    cfl.push(cell_size(solver, &ci[..4 * nf], &cfl[nf..2 * nf]));
    // the grid: counts, offsets, cursors of the cells; of the hit lists per face; the cells'
    // entries, the big faces, the hit lists
    let m = (2 * nf).max(1024).next_power_of_two();
    let g_off = m;
    let g_fill = 2 * m + 1;
    let g_bign = 3 * m + 1;
    let h_count = g_bign + 1;
    let h_off = h_count + nf;
    let h_fill = h_off + nf + 1;
    let g_ent = h_fill + nf;
    let g_big = g_ent + CELLS * nf;
    let h_list = g_big + nf;
    let grid_len = h_list + np;
    let consts = vec![
        ("C_NN", nn as u64),
        ("C_NF", nf as u64),
        ("C_NP", np as u64),
        ("C_NG", ng as u64),
        ("C_GG", ng.div_ceil(64) as u64),
        ("C_M", m as u64),
        ("CI_FACE", 0),
        ("CI_FSIDE", 4 * nf as u64),
        ("CI_PN", ci_pn as u64),
        ("CI_PASS", ci_pass as u64),
        ("CI_NFPTR", ci_nfptr as u64),
        ("CI_GN", ci_gn as u64),
        ("CI_GOPTR", ci_goptr as u64),
        ("CI_GFPTR", ci_gfptr as u64),
        ("CF_K", 0),
        ("CF_DEPTH", nf as u64),
        ("CF_KN", cf_kn as u64),
        ("CF_DEF", cf_def as u64),
        ("CF_PEN", cf_pen as u64),
        ("CF_H", cf_pen as u64 + 1),
        ("G_COUNT", 0),
        ("G_OFF", g_off as u64),
        ("G_FILL", g_fill as u64),
        ("G_BIGN", g_bign as u64),
        ("H_COUNT", h_count as u64),
        ("H_OFF", h_off as u64),
        ("H_FILL", h_fill as u64),
        ("G_ENT", g_ent as u64),
        ("G_BIG", g_big as u64),
        ("H_LIST", h_list as u64),
    ];
    Some(Tables {
        ci,
        cfl,
        consts,
        faces: nf,
        pass_nodes: np,
        surface_nodes: ng,
        pn_def,
        grid_len,
    })
}

/// The grid's cell size: the 90th percentile of the faces' search-sphere diameters
/// `2 (E r + depth)` at the start (penalty.rs WEIGHT_SUM E, r the largest centre-corner
/// distance), so that nine faces in ten span at most two cells a side (three once grown) and
/// the few largest (a thick plate's faces, whose depth 0.4 V/A reaches far) go to the list
/// every node reads, rather than making every cell hold many small faces; 1 when no face has
/// a finite positive one. On the 2800-element ball on its plate, the largest diameter (as the
/// cell size) made the node checks 77% of a step on lavapipe.
fn cell_size(solver: &Solver, face_nodes: &[u32], depth: &[f64]) -> f64 {
    let x = solver.positions();
    let mut d: Vec<f64> = (face_nodes.chunks(4).zip(depth))
        .map(|(f, depth)| {
            let p: Vec<[f64; 3]> = f.iter().map(|&n| x[n as usize]).collect();
            let c: [f64; 3] =
                std::array::from_fn(|k| 0.25 * (p[0][k] + p[1][k] + p[2][k] + p[3][k]));
            let r = (p.iter())
                .map(|q| (0..3).map(|k| (q[k] - c[k]).powi(2)).sum::<f64>().sqrt())
                .fold(0.0, f64::max);
            2.0 * (cleave_core::contact::penalty::WEIGHT_SUM * r + depth)
        })
        .filter(|s| s.is_finite() && *s > 0.0)
        .collect();
    if d.is_empty() {
        return 1.0;
    }
    d.sort_by(f64::total_cmp);
    d[(d.len() - 1) * 9 / 10]
}

/// The contact passes of the step, their buffers and their bind group.
pub(crate) struct ContactGpu {
    pub passes: Vec<(&'static str, wgpu::ComputePipeline, usize)>,
    pub bind_group: wgpu::BindGroup,
    /// Each node's contact force of the step (3 per model node), read by the step's shader.
    pub fcon: wgpu::Buffer,
    /// What carries over to the next step: the hits (HIT values per pass-node) and the last
    /// step's contact force of each surface node (3 each).
    pub hits: wgpu::Buffer,
    pub fprev: wgpu::Buffer,
    pub bytes: u64,
    tables: Tables,
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

impl ContactGpu {
    /// The contact of `solver` on `gpu`, reading the step's control block `cf`, positions `x`
    /// and velocities `v`; `None` without contact. Refuses (TooLarge) an array larger than the
    /// device binds: the contact binds every array whole.
    pub fn new(
        gpu: &Gpu,
        solver: &Solver,
        cf: &wgpu::Buffer,
        x: &wgpu::Buffer,
        v: &wgpu::Buffer,
    ) -> Result<Option<Self>, GpuError> {
        let Some(t) = tables(solver) else {
            return Ok(None);
        };
        let dev = &gpu.device;
        let limit = gpu.limits.max_storage_buffer_binding_size;
        let nn = solver.model.num_nodes();
        let sizes = [
            ("its tables", (4 * t.ci.len()).max(8 * t.cfl.len()) as u64),
            ("its search grid", 4 * t.grid_len as u64),
            ("its contact pairs", (8 * HIT * t.pass_nodes) as u64),
            ("the positions", x.size()),
        ];
        if let Some((what, bytes)) = sizes.iter().find(|(_, b)| *b > limit) {
            return Err(GpuError::TooLarge(format!(
                "contact on the GPU binds each array whole, and {what} need {bytes} bytes; {} binds at most {limit} bytes per array",
                gpu.info.name
            )));
        }
        let storage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let init = |label: &str, contents: &[u8]| {
            dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: storage,
            })
        };
        let zeros = |label: &str, bytes: usize| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(8) as u64,
                usage: storage,
                mapped_at_creation: false,
            })
        };
        let ci = init("contact tables", bytemuck::cast_slice(&t.ci));
        let cfl = init("contact values", bytemuck::cast_slice(&t.cfl));
        let mut h = vec![0.0f64; HIT * t.pass_nodes.max(1)];
        h.iter_mut().step_by(HIT).for_each(|f| *f = -1.0);
        let hits = init("contact pairs", bytemuck::cast_slice(&h));
        let fcon = zeros("contact forces", 24 * nn);
        let fprev = zeros("contact forces, last step", 24 * t.surface_nodes);
        let grid = zeros("contact grid", 4 * t.grid_len);
        let gg = t.surface_nodes.div_ceil(64);
        let cpart = zeros("contact work partials", 8 * gg);
        let bufs: [(&wgpu::Buffer, bool); 10] = [
            (cf, false),
            (x, true),
            (v, true),
            (&ci, true),
            (&cfl, true),
            (&hits, false),
            (&fcon, false),
            (&fprev, false),
            (&grid, false),
            (&cpart, false),
        ];
        let layout_entries: Vec<_> = (bufs.iter().enumerate())
            .map(|(b, &(_, read_only))| wgpu::BindGroupLayoutEntry {
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
        let bgl = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("contact"),
            entries: &layout_entries,
        });
        let entries: Vec<_> = (bufs.iter().enumerate())
            .map(|(b, (buf, _))| wgpu::BindGroupEntry {
                binding: b as u32,
                resource: buf.as_entire_binding(),
            })
            .collect();
        let bind_group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("contact"),
            layout: &bgl,
            entries: &entries,
        });
        let source = shader_source(&t);
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("contact.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("contact"),
            bind_group_layouts: &[Some(&bgl)],
            immediate_size: 0,
        });
        let per = |n: usize| n.div_ceil(crate::stepper::GROUP);
        let passes = [
            ("c_count", per(t.faces)),
            ("c_scan", 1),
            ("c_fill", per(t.faces)),
            ("c_detect", per(t.pass_nodes)),
            ("c_hscan", 1),
            ("c_hfill", per(t.pass_nodes)),
            ("c_gather", gg),
            ("c_energy", 1),
        ]
        .map(|(name, groups)| {
            let p = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&pl),
                module: &module,
                entry_point: Some(name),
                compilation_options: Default::default(),
                cache: None,
            });
            (name, p, groups)
        });
        let bytes = [&ci, &cfl, &hits, &fcon, &fprev, &grid, &cpart]
            .iter()
            .map(|b| b.size())
            .sum();
        Ok(Some(Self {
            passes: passes.into(),
            bind_group,
            fcon,
            hits,
            fprev,
            bytes,
            tables: t,
        }))
    }

    /// Each definition's resultants from the hits read back (mod.rs ContactForce: the force
    /// on the slave side, the sum of |f_n|, the pairs), summed in the CPU's order.
    pub fn resultants(&self, hits: &[f64], ids: impl Iterator<Item = i64>) -> Vec<ContactForce> {
        let mut out: Vec<ContactForce> = ids
            .map(|id| ContactForce {
                id,
                ..Default::default()
            })
            .collect();
        for (j, &(d, sign)) in self.tables.pn_def.iter().enumerate() {
            let h = &hits[HIT * j..HIT * (j + 1)];
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

/// contact.wgsl with its constants and the shared math before it.
pub(crate) fn shader_source(t: &Tables) -> String {
    let mut s = String::new();
    for (name, v) in &t.consts {
        s += &format!("const {name}: u32 = {v}u;\n");
    }
    s + include_str!("math.wgsl") + include_str!("contact.wgsl")
}

#[cfg(test)]
mod tests {
    use super::*;
    use cleave_core::model::{ContactDef, ContactSurface, Material, MaterialKind};
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
        m.contacts.push(ContactDef {
            id: 1,
            single_surface: true,
            one_way: false,
            slave: ContactSurface::All,
            master: None,
            fs: 0.1,
            fd: 0.1,
            dc: 0.0,
        });
        let mut s = Solver::new(&m).unwrap();
        s.attach_contact(ContactSet::new(&m, None).unwrap());
        let t = tables(&s).unwrap();
        // 24 exterior faces, the 26 nodes on the surface (all but the centre), one pass
        assert_eq!((t.faces, t.pass_nodes, t.surface_nodes), (24, 26, 26));
        let c = |name: &str| t.consts.iter().find(|(n, _)| *n == name).unwrap().1 as usize;
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
        // the cell: every face's sphere diameter, 2 (E r + 0.4 V/A) with r = sqrt(2)/4 for the
        // 0.5 squares of elements 0.125 in volume
        let h = t.cfl[c("CF_H")];
        let want = 2.0 * (1.08 * 2f64.sqrt() / 4.0 + 0.4 * 0.125 / 0.25);
        assert!((h - want).abs() < 1e-12, "{h} {want}");
        let src = shader_source(&t);
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
