//! The model as the GPU reads it: flat arrays built once on the host.
//!
//! - `par` (f64): the material slots (`MAT_STRIDE` values each: density, Lame lambda, shear
//!   modulus, wave speed, step speed, law 0 elastic / 1 bilinear plastic / 2 Johnson-Cook /
//!   3 piecewise linear, SIGY, Hp, beta (laws 2 and 3: the offset of their parameter block,
//!   `johnson_cook_block`, `piecewise_block`), then the element controls of the part:
//!   hourglass form 0 viscous / 1 stiffness, QH, Q1, Q2; the offset of the material's erosion
//!   rule, `erosion_block`, or -1), the laws' and rules' blocks, then
//!   the curves (n, abscissae, ordinates), the body loads (axis, curve offset or -1, SF), the
//!   node actions (`NODE_STRIDE` values each, see [`NODE_STRIDE`]) and the planar rigid walls
//!   (a point, the unit normal, FRIC);
//! - `emat`: each element's material slot, with the bits [`TET`] (a tetrahedron), [`NP`] (one
//!   with nodal pressure averaging, ELFORM 13), [`SRI`] (a fully integrated hexahedron, ELFORM
//!   2) and [`RIGID`] (an element of a rigid part). A slot is one material with one part's controls
//!   (its `*HOURGLASS`, else the global cards: `cleave_core::solver::kernel_controls`), so parts
//!   that share a material but not their hourglass control get slots of their own;
//! - `nptr`/`ninc`: for each node n, its element corners `8 e + a` in element order (the order
//!   its forces are summed in, so the sum is the same bits every run), at
//!   `ninc[nptr[2 n]..nptr[2 n + 1]]` (a start and an end per node, so that a split of the
//!   coincident sets moves the lists of the sets it splits only: `crate::relayout`);
//!
//!   with element separation every array indexed by node is indexed by the coincident sets'
//!   slots instead ([`Slots`]);
//! - `nflag`: the SPC bits of each node (1 x, 2 y, 4 z), and 8 << w for each rigid wall w
//!   that stops it;
//! - `rbi`: for each node, its entry in the rigid bodies' node list (`u32::MAX`: none), then
//!   that list, the bodies' nodes body after body (the entry k's body and arm are at
//!   `rb_off + RB_PAR n_rigid + 4 k` in `par`);
//! - `mptr`: for each node, its node actions: its concentrated loads and the pressure segments
//!   it carries (in the order the CPU adds them: `cleave_core::loads`), then its prescribed
//!   motions (in the deck's order).

use cleave_core::element::Shape;
use cleave_core::erosion::ErosionRule;
use cleave_core::material::{Eos, JohnsonCook, PiecewiseLinear, SolidLaw};
use cleave_core::math::sub;
use cleave_core::model::{Hourglass, Model, MotionDof, MotionTarget, Vad, WallShape};
use cleave_core::setup::Setup;
use cleave_core::solver::kernel_controls;
use cleave_core::tied::Tie;

/// The bit of `emat` that marks a tetrahedron.
pub const TET: u32 = 1 << 31;
/// The bit of `emat` that marks an element of a rigid part (no kernel: it moves with its body).
pub const RIGID: u32 = 1 << 30;
/// The bit of `emat` that marks a tetrahedron with nodal pressure averaging (ELFORM 13).
pub const NP: u32 = 1 << 29;
/// The bit of `emat` that marks a fully integrated, selectively reduced hexahedron (ELFORM 2).
pub const SRI: u32 = 1 << 28;
/// The bits of `emat` that hold the material slot.
pub const SLOT: u32 = (1 << 28) - 1;
/// Values per material slot in `par`.
pub const MAT_STRIDE: usize = 14;
/// Values per node action in `par` (at `mot_off + NODE_STRIDE k`), the first its kind:
/// - 0, a prescribed motion: axis, VAD 0 velocity / 1 displacement, SF, curve offset, the
///   node's initial coordinate on the axis, two unused, its birth and death times;
/// - 1, a concentrated load (`*LOAD_NODE`): axis, SF, curve offset;
/// - 2, a pressure segment (`*LOAD_SEGMENT`) the node carries: SF, curve offset, birth time,
///   then its nodes N1 N2 N3 N4 (a triangle `N1 N2 N3 N3`);
/// - 3, a tied slave node whose force the node takes (`crate::tied`): the slave, the weight;
/// - 4 and 5, a prescribed motion along a unit vector d (DOF 4; 5: DOF -4, the motion normal
///   to d held): d_x, VAD, SF, curve offset, the node's initial coordinate along d, d_y, d_z,
///   its birth and death times.
pub const NODE_STRIDE: usize = 10;
/// The most rigid walls (the bits of `nflag` above the SPC's, the ledger's partial sums).
pub const MAX_WALLS: usize = 8;

/// The flat arrays of a model ([module docs](self)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layout {
    pub par: Vec<f64>,
    pub body_off: u32,
    pub n_body: u32,
    pub mot_off: u32,
    pub wall_off: u32,
    /// The offset in `par` of the curve of the largest time step (LCTM), `u32::MAX`: none.
    pub dt_max_off: u32,
    pub conn: Vec<u32>,
    pub emat: Vec<u32>,
    pub nptr: Vec<u32>,
    pub ninc: Vec<u32>,
    pub nflag: Vec<u32>,
    pub mptr: Vec<u32>,
    /// Rigid bodies: their count, the offset of their blocks in `par` ([`RB_PAR`] each), and
    /// `rbi` ([module docs](self)).
    pub n_rigid: u32,
    pub rb_off: u32,
    pub rbi: Vec<u32>,
    /// Tied contact: the number of ties and their offset in `par` (9 values each: the slave,
    /// its face's 4 nodes, their weights).
    pub n_ties: u32,
    pub tie_off: u32,
}

/// Values per rigid body in `par`: mass, reference centre of mass (3), reference inertia (9,
/// by rows), the fixed translations and rotations (3 + 3, 1 fixed), the offset and number of
/// its prescribed motions (10 values each: code 0-2 a global axis, 3 a translation along d, 4
/// a rotation about d; VAD 0 velocity / 1 displacement; SF; curve offset; d (3); 1 when the
/// motion normal to d is held; birth and death times), the first and the number of its
/// entries in the node list; then the mass that no node carries (a given inertia,
/// `*PART_INERTIA`: `cleave_core::rigid::Unlumped`; zero without one), its arm from the
/// reference centre of mass (3), its second moment J (9, by rows), and the body's initial
/// velocity and angular velocity (3 + 3, after its constraints: `RigidState::v0`, `omega0`).
pub const RB_PAR: usize = 42;
/// Values per rigid body in the state buffer `rb`: centre of mass (3), velocity of the centre
/// (3), rotation (9), angular momentum (3), angular velocity (3), the next placement (3 + 9),
/// the work of the body's constraints now and later (2), the previous placement (3 + 9).
pub const RB_STATE: usize = 48;

/// A split model's coincident sets as the GPU steps them (element separation): the GPU's
/// "nodes" are the sets' slots (`cleave_core::separation::coincident::CoincidentSets::slots`),
/// each a set that moves as one or a node in none, with the set's mass. Every array of the
/// layout indexed by node is indexed by slot: the connectivity names slots, a slot gathers
/// the corners of all its members' elements (in element order), and takes their SPC, walls,
/// loads and prescribed motions (members in node order). The arrays keep the size of one slot
/// per node, the most there can be, so a split only rewrites them.
#[derive(Clone, Copy)]
pub struct Slots<'a> {
    /// Per node, its slot.
    pub of: &'a [u32],
    /// Per element, whether it steps with the free-element speed (an interface failure has
    /// touched its nodes' sets: `Separation::loose_elements`).
    pub loose: &'a [bool],
}

impl Layout {
    /// The arrays of a model that [`crate::support::unsupported`] accepts (hexahedra of
    /// deformable materials, nodal constraints); with `slots`, of a split model stepped by its
    /// coincident sets ([`Slots`]).
    pub fn new(model: &Model, setup: &Setup, ties: &[Tie], slots: Option<Slots>) -> Self {
        let nn = model.num_nodes();
        // where node n's values live: its slot (itself without separation)
        let at = |n: u32| slots.map_or(n, |s| s.of[n as usize]);
        let loose = |e: usize| slots.is_some_and(|s| s.loose[e]);
        let mut par = Vec::new();
        // the material slots: each element's material (again with the free-element step for
        // the lone elements) with its part's controls, in the order the elements first use them
        let controls = kernel_controls(model);
        let mut mat_slots: Vec<(u32, usize)> = Vec::new();
        let mut slot_of = |key: (u32, usize)| match mat_slots.iter().position(|k| *k == key) {
            Some(k) => k,
            None => {
                mat_slots.push(key);
                mat_slots.len() - 1
            }
        };
        let mut emat = Vec::with_capacity(model.num_elements());
        let n_params = setup.params.len() as u32;
        for (e, (&m, &lone)) in setup.elem_mat.iter().zip(&setup.lone).enumerate() {
            let part = model.elem_part[e] as usize;
            // parts with equal controls share a slot
            let class = controls
                .iter()
                .position(|c| *c == controls[part])
                .unwrap_or(part);
            if slots.is_some() {
                // both of a split model's slots from the start (in the same order whichever
                // elements are loose), so a split changes no offset in `par`
                slot_of((m, class));
                slot_of((m + n_params, class));
            }
            let base = m + if lone || loose(e) { n_params } else { 0 };
            let slot = slot_of((base, class));
            // a tetrahedron runs the constant-strain kernel: the slot's top bit; an element of
            // a rigid part none
            let tet = setup.elem_shape[e] == Shape::Tet;
            let rigid = setup.params[m as usize].is_none();
            let elform = model.sections[model.parts[part].section].elform;
            let np = tet && elform == 13;
            let sri = setup.elem_shape[e] == Shape::Hex && elform == 2;
            let mut bits = slot as u32;
            for (on, bit) in [(tet, TET), (rigid, RIGID), (np, NP), (sri, SRI)] {
                if on {
                    bits |= bit;
                }
            }
            emat.push(bits);
        }
        let all: Vec<_> = setup.params.iter().chain(&setup.loose_params).collect();
        // the laws' parameter blocks, after the slots
        let ext_base = mat_slots.len() * MAT_STRIDE;
        let mut ext: Vec<f64> = Vec::new();
        for &(base, class) in &mat_slots {
            let mut m = [0.0; MAT_STRIDE];
            if let Some(p) = all[base as usize] {
                m[..5].copy_from_slice(&[p.density, p.lambda, p.shear, p.wave_speed, p.step_speed]);
                match &p.law {
                    SolidLaw::Elastic => {}
                    SolidLaw::PlasticKinematic { sigy, hp, beta } => {
                        m[5..9].copy_from_slice(&[1.0, *sigy, *hp, *beta]);
                    }
                    SolidLaw::JohnsonCook(jc) => {
                        m[5..7].copy_from_slice(&[2.0, (ext_base + ext.len()) as f64]);
                        johnson_cook_block(jc, &mut ext);
                    }
                    SolidLaw::Piecewise(pw) => {
                        m[5..7].copy_from_slice(&[3.0, (ext_base + ext.len()) as f64]);
                        piecewise_block(pw, ext_base, &mut ext);
                    }
                }
            }
            let c = &controls[class];
            let form = match c.hourglass {
                Hourglass::Viscous => 0.0,
                Hourglass::Stiffness => 1.0,
            };
            m[9..13].copy_from_slice(&[form, c.qh, c.q1, c.q2]);
            // the material's erosion rule, if it has one
            let material = base as usize % setup.params.len().max(1);
            m[13] = match model.erosion.iter().find(|d| d.material == material) {
                Some(d) => {
                    let o = (ext_base + ext.len()) as f64;
                    erosion_block(&d.rule, &mut ext);
                    o
                }
                None => -1.0,
            };
            par.extend_from_slice(&m);
        }
        par.extend_from_slice(&ext);
        let mut curve_off = Vec::with_capacity(model.curves.len());
        for c in &model.curves {
            curve_off.push(par.len() as f64);
            par.push(c.t.len() as f64);
            par.extend_from_slice(&c.t);
            par.extend_from_slice(&c.y);
        }
        let body_off = par.len() as u32;
        for b in &model.body_loads {
            par.extend_from_slice(&[b.axis as f64, b.curve.map_or(-1.0, |c| curve_off[c]), b.sf]);
        }
        let mot_off = par.len() as u32;
        // (node, action) in the order each node runs them: loads first (node loads, then
        // pressure segments, as `Loads::apply` adds them), then prescribed motions; the sort is
        // stable, so a node's actions keep that order
        let mut actions: Vec<(u32, [f64; NODE_STRIDE])> = Vec::new();
        for l in &model.node_loads {
            let mut a = [0.0; NODE_STRIDE];
            a[..4].copy_from_slice(&[1.0, l.axis as f64, l.sf, curve_off[l.curve]]);
            actions.push((at(l.node), a));
        }
        for l in &model.pressure_loads {
            let pts = if l.nodes[3] == l.nodes[2] { 3 } else { 4 };
            let mut a = [0.0; NODE_STRIDE];
            a[..4].copy_from_slice(&[2.0, l.sf, curve_off[l.curve], l.at]);
            for (k, &n) in l.nodes.iter().enumerate() {
                a[4 + k] = at(n) as f64;
            }
            for &n in &l.nodes[..pts] {
                actions.push((at(n), a));
            }
        }
        // tied slave nodes' forces go to their face's nodes, in the ties' order
        for t in ties {
            for a in 0..4 {
                let w = t.weights[a];
                actions.push((t.masters[a], {
                    let mut a = [0.0; NODE_STRIDE];
                    a[..3].copy_from_slice(&[3.0, t.slave as f64, w]);
                    a
                }));
            }
        }
        for m in &setup.node_motion {
            if let MotionTarget::Node(n) = m.target {
                let vad = match m.vad {
                    Vad::Velocity => 0.0,
                    Vad::Displacement => 1.0,
                };
                let x0 = m.dof.component(model.x0[n as usize]);
                // kind 0: along a global axis; 4 and 5: along a unit vector, the normal motion
                // free (4, DOF 4) or held (5, DOF -4)
                let (kind, d) = match m.dof {
                    MotionDof::Axis(axis) => (0.0, [axis as f64, 0.0, 0.0]),
                    MotionDof::Along { dir, only } => (if only { 5.0 } else { 4.0 }, dir),
                    // the reader refuses rotations of nodes
                    MotionDof::Rotation { .. } => continue,
                };
                let w = m.window;
                let a = [
                    kind,
                    d[0],
                    vad,
                    m.sf,
                    curve_off[m.curve],
                    x0,
                    d[1],
                    d[2],
                    w.birth,
                    w.death.min(f64::MAX),
                ];
                actions.push((at(n), a));
            }
        }
        actions.sort_by_key(|&(n, _)| n);
        let mut mptr = vec![0u32; nn + 1];
        for (n, a) in &actions {
            mptr[*n as usize + 1] += 1;
            par.extend_from_slice(a);
        }
        for i in 0..nn {
            mptr[i + 1] += mptr[i];
        }
        // rigid bodies: each body's block, then each body-node entry (body, arm X - X_cm0),
        // then the bodies' prescribed motions
        let bodies = &setup.rigid;
        let rb_off = par.len() as u32;
        let entries: usize = bodies.iter().map(|b| b.nodes.len()).sum();
        let entry_off = rb_off as usize + RB_PAR * bodies.len();
        let motion_off = entry_off + 4 * entries;
        // a body's prescribed motion: [code, VAD, SF, curve, d_x, d_y, d_z, only, birth,
        // death], code 0-2 a global axis, 3 a translation along d, 4 a rotation about d
        const BODY_MOTION: usize = 10;
        let mut rbi = vec![u32::MAX; nn];
        let (mut first, mut motions) = (0usize, 0usize);
        for (b, body) in bodies.iter().enumerate() {
            let n_mot = setup.rigid_motion.iter().filter(|(rb, _)| *rb == b).count();
            par.push(body.mass);
            par.extend_from_slice(&body.x_cm0);
            par.extend(body.inertia0.iter().flatten());
            par.extend(
                body.fix_v
                    .iter()
                    .chain(&body.fix_w)
                    .map(|&f| f as u8 as f64),
            );
            par.extend_from_slice(&[
                (motion_off + BODY_MOTION * motions) as f64,
                n_mot as f64,
                first as f64,
                body.nodes.len() as f64,
            ]);
            // the unlumped mass (the arm as `RigidBody::place` takes it, `centre - x_cm0`) and
            // the initial velocities its first step reads; zeros without one (the shader reads
            // none of them then, and a split's layout need not work out the body's start)
            match &body.unlumped {
                Some(u) => {
                    par.push(u.mass);
                    par.extend_from_slice(&sub(u.centre, body.x_cm0));
                    par.extend(u.second_moment.iter().flatten());
                    let st = body.initial_state(&model.x0, &model.v0, &setup.mass);
                    par.extend_from_slice(&st.v0);
                    par.extend_from_slice(&st.omega0);
                }
                None => par.extend_from_slice(&[0.0; 19]),
            }
            first += body.nodes.len();
            motions += n_mot;
        }
        for (b, body) in bodies.iter().enumerate() {
            for &n in &body.nodes {
                // (a body's node is in no coincident set: its own slot, GpuStepper::new)
                rbi[at(n) as usize] = (par.len() - entry_off) as u32 / 4;
                par.push(b as f64);
                par.extend_from_slice(&sub(model.x0[n as usize], body.x_cm0));
            }
        }
        for b in 0..bodies.len() {
            for (_, pm) in setup.rigid_motion.iter().filter(|(rb, _)| *rb == b) {
                let vad = match pm.vad {
                    Vad::Velocity => 0.0,
                    Vad::Displacement => 1.0,
                };
                let (code, dir, only) = match pm.dof {
                    MotionDof::Axis(a) => (a as f64, [0.0; 3], false),
                    MotionDof::Along { dir, only } => (3.0, dir, only),
                    MotionDof::Rotation { dir, only } => (4.0, dir, only),
                };
                par.extend_from_slice(&[code, vad, pm.sf, curve_off[pm.curve]]);
                par.extend_from_slice(&dir);
                par.push(only as u8 as f64);
                par.extend_from_slice(&[pm.window.birth, pm.window.death.min(f64::MAX)]);
            }
        }
        rbi.extend(bodies.iter().flat_map(|b| b.nodes.iter().map(|&n| at(n))));
        let tie_off = par.len() as u32;
        for t in ties {
            par.push(t.slave as f64);
            par.extend(t.masters.iter().map(|&m| m as f64));
            par.extend_from_slice(&t.weights);
        }
        let wall_off = par.len() as u32;
        // each wall (WALL_STRIDE values): tail, unit normal, FRIC; for a finite plane l, LENL,
        // LENM (else LENL -1); the shape (0 plane, 1 sphere, 2 cylinder), its radius and length
        // (infinite: -1); the motion's curve offset (-1: fixed), 1 for a displacement curve,
        // its direction
        for wall in &model.rigid_walls {
            par.extend_from_slice(&wall.tail);
            par.extend_from_slice(&wall.normal());
            par.push(wall.fric);
            match wall.extent {
                Some(e) => {
                    par.extend_from_slice(&e.l);
                    par.extend_from_slice(&[e.len_l, e.len_m]);
                }
                None => par.extend_from_slice(&[0.0, 0.0, 0.0, -1.0, 0.0]),
            }
            let (code, radius, length) = match wall.shape {
                WallShape::Plane => (0.0, 0.0, -1.0),
                WallShape::Sphere { radius } => (1.0, radius, -1.0),
                WallShape::Cylinder { radius, length } => {
                    (2.0, radius, if length.is_finite() { length } else { -1.0 })
                }
            };
            par.extend_from_slice(&[code, radius, length]);
            match wall.motion {
                Some(m) => {
                    par.extend_from_slice(&[curve_off[m.curve], m.displacement as u8 as f64]);
                    par.extend_from_slice(&m.dir);
                }
                None => par.extend_from_slice(&[-1.0, 0.0, 0.0, 0.0, 0.0]),
            }
        }
        let mut nflag = vec![0u32; nn];
        for (w, nodes) in setup.wall_nodes.iter().enumerate() {
            for &n in nodes {
                nflag[at(n) as usize] |= 8 << w;
            }
        }
        for &(n, d) in &setup.spc {
            for (a, &fixed) in d.iter().enumerate() {
                if fixed {
                    nflag[at(n) as usize] |= 1 << a;
                }
            }
        }
        let conn: Vec<u32> = model.conn.iter().flatten().map(|&n| at(n)).collect();
        // each node's list: its start and end (a split moves lists in place, relayout.rs)
        let mut start = vec![0u32; nn + 1];
        for &n in &conn {
            start[n as usize + 1] += 1;
        }
        for i in 0..nn {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut ninc = vec![0u32; 8 * model.num_elements()];
        for (e, c) in conn.chunks_exact(8).enumerate() {
            for (a, &n) in c.iter().enumerate() {
                let k = &mut fill[n as usize];
                ninc[*k as usize] = 8 * e as u32 + a as u32;
                *k += 1;
            }
        }
        let nptr = (start.windows(2)).flat_map(|w| [w[0], w[1]]).collect();
        Self {
            par,
            body_off,
            n_body: model.body_loads.len() as u32,
            mot_off,
            wall_off,
            dt_max_off: model
                .control
                .dt_max_curve
                .map_or(u32::MAX, |k| curve_off[k] as u32),
            conn,
            emat,
            nptr,
            ninc,
            nflag,
            mptr,
            n_rigid: bodies.len() as u32,
            rb_off,
            rbi,
            n_ties: ties.len() as u32,
            tie_off,
        }
    }

    /// The features the model uses, as WGSL constants put before step.wgsl (`HAS_RIGID`,
    /// `HAS_TET`, `HAS_SRI`, `HAS_EROSION`, and `LAWS`, a bit per law in use: 1 elastic,
    /// 2 bilinear plastic, 4 Johnson-Cook, 8 piecewise linear). The paths that are off are
    /// constant-false branches the driver's compiler drops, so a model of elastic hexahedra
    /// runs a kernel without the registers of every other path. `WALL_VALUES` (4 per rigid
    /// wall, at least 1) sizes the nodes pass's private array of the walls' impulses: indexed
    /// at run time, it lives in local memory, and a fixed size for the most walls cost every
    /// node its zeroing.
    pub fn shader_constants(&self, erodes: bool, walls: usize) -> String {
        let any = |bit: u32| self.emat.iter().any(|&b| b & bit != 0);
        let mut laws = 0u32;
        for &b in self.emat.iter().filter(|&&b| b & RIGID == 0) {
            let slot = (b & SLOT) as usize;
            laws |= 1 << (self.par[slot * MAT_STRIDE + 5].round() as u32).min(3);
        }
        format!(
            "const HAS_RIGID: bool = {};\nconst HAS_TET: bool = {};\nconst HAS_SRI: bool = {};\n\
             const HAS_EROSION: bool = {erodes};\nconst LAWS: u32 = {laws}u;\n\
             const WALL_VALUES: u32 = {}u;\n",
            any(RIGID),
            any(TET),
            any(SRI),
            (4 * walls).max(1),
        )
    }
}

/// An erosion rule's block: FAIL (on, value), MXPRES, MNPRES, SIGVM, FAILTM (each on, value),
/// NCS, the number of `*MAT_ADD_EROSION` criteria, Johnson-Cook damage (on, D1..D5, EFMIN),
/// SIGP1, MXEPS, MNEPS, EFFEPS, VOLEPS (each on, value).
fn erosion_block(r: &ErosionRule, out: &mut Vec<f64>) {
    for v in [
        r.plastic_strain,
        r.max_pressure,
        r.min_pressure,
        r.max_von_mises,
        r.failure_time,
    ] {
        out.extend_from_slice(&[v.is_some() as u8 as f64, v.unwrap_or(0.0)]);
    }
    out.extend_from_slice(&[r.ncs as f64, r.criteria() as f64]);
    match r.johnson_cook {
        Some(d) => {
            out.push(1.0);
            out.extend_from_slice(&d.d);
            out.push(d.efmin);
        }
        None => out.extend_from_slice(&[0.0; 7]),
    }
    for v in [
        r.max_principal,
        r.max_principal_strain,
        r.min_principal_strain,
        r.effective_strain,
        r.volumetric_strain,
    ] {
        out.extend_from_slice(&[v.is_some() as u8 as f64, v.unwrap_or(0.0)]);
    }
}

/// Johnson-Cook's block (law 2): A, B, N, C, EPSO, M, TM, TR, RO CP, SIGMAX, SIGSAT, then the
/// equation of state: kind (0 none, 1 linear polynomial, 2 Mie-Gruneisen), its parameters
/// (C0..C6, or C, S1, S2, S3, GAMMA0, A, rho0), E0, V0.
fn johnson_cook_block(jc: &JohnsonCook, out: &mut Vec<f64>) {
    out.extend_from_slice(&[
        jc.a, jc.b, jc.n, jc.c, jc.eps0, jc.m, jc.t_melt, jc.t_room, jc.rho_cp, jc.sig_max,
        jc.sig_sat,
    ]);
    let eos: [f64; 10] = match jc.eos {
        None => [0.0; 10],
        Some(Eos::LinearPolynomial { c, e0, v0 }) => {
            [1.0, c[0], c[1], c[2], c[3], c[4], c[5], c[6], e0, v0]
        }
        Some(Eos::Gruneisen {
            c,
            s,
            gamma0,
            a,
            rho0,
            e0,
            v0,
        }) => [2.0, c, s[0], s[1], s[2], gamma0, a, rho0, e0, v0],
    };
    out.extend_from_slice(&eos);
}

/// `*MAT_024`'s block (law 3): C, P, the number of table values nt (0: one hardening curve),
/// the log flag of the table's values, the curve's offset; with a table, then its nt values and
/// their curves' offsets. Each curve after it: n, the plastic strains, the yield stresses.
fn piecewise_block(pw: &PiecewiseLinear, ext_base: usize, out: &mut Vec<f64>) {
    let start = out.len();
    let curves: Vec<&[[f64; 2]]> = match &pw.table {
        None => vec![&pw.points],
        Some(t) => t.curves.iter().map(|(_, c)| &c[..]).collect(),
    };
    let nt = pw.table.as_ref().map_or(0, |t| t.values.len());
    let log = pw.table.as_ref().is_some_and(|t| t.log);
    out.extend_from_slice(&[pw.c, pw.p, nt as f64, if log { 1.0 } else { 0.0 }, 0.0]);
    if let Some(t) = &pw.table {
        out.extend_from_slice(&t.values);
        out.extend(std::iter::repeat_n(0.0, nt));
    }
    for (k, c) in curves.iter().enumerate() {
        let off = (ext_base + out.len()) as f64;
        if nt == 0 {
            out[start + 4] = off;
        } else {
            out[start + 5 + nt + k] = off;
        }
        out.push(c.len() as f64);
        out.extend(c.iter().map(|p| p[0]));
        out.extend(c.iter().map(|p| p[1]));
    }
}

/// An element array as the device stores it, by component (value k of element e at
/// k ne + e, step.wgsl `ek`), from one stored by element (value k of element e at
/// e k_count + k); `k_count` values per element. A tail past the whole elements (a buffer's
/// padding) stays as it is.
pub(crate) fn by_component<T: Copy>(a: &[T], k_count: usize) -> Vec<T> {
    transpose(a, a.len() / k_count, k_count)
}

/// The inverse of [`by_component`]: an element array read back from the device, by element.
pub(crate) fn by_element<T: Copy>(a: &[T], k_count: usize) -> Vec<T> {
    transpose(a, k_count, a.len() / k_count)
}

/// The first `rows x cols` values of `a` (a matrix by rows) by columns; the rest as they are.
fn transpose<T: Copy>(a: &[T], rows: usize, cols: usize) -> Vec<T> {
    let mut out = a.to_vec();
    for r in 0..rows {
        for c in 0..cols {
            out[c * rows + r] = a[r * cols + c];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use cleave_core::mesh::box_model;
    use cleave_core::model::{Material, MaterialKind};

    /// The shader reads `par` and `rb` with the strides written here: the two must agree.
    #[test]
    fn the_shader_reads_the_layout_strides() {
        let shader = include_str!("step.wgsl");
        for (name, value) in [
            ("MAT_STRIDE", MAT_STRIDE),
            ("RB_PAR", RB_PAR),
            ("RB_STATE", RB_STATE),
        ] {
            let line = format!("const {name}: u32 = {value}u;");
            assert!(shader.contains(&line), "step.wgsl lacks `{line}`");
        }
    }

    #[test]
    fn every_corner_is_gathered_once_in_element_order() {
        let steel = Material {
            id: 1,
            density: 7850.0,
            young: 210e9,
            poisson: 0.3,
            kind: MaterialKind::Elastic,
        };
        let model = box_model([3, 2, 2], [0.3, 0.2, 0.2], steel, 1.0);
        let setup = Setup::new(&model).unwrap();
        let l = Layout::new(&model, &setup, &[], None);
        let nn = model.num_nodes();
        assert_eq!(l.nptr[2 * nn - 1] as usize, 8 * model.num_elements());
        let mut seen = vec![false; 8 * model.num_elements()];
        for n in 0..nn {
            let incs = &l.ninc[l.nptr[2 * n] as usize..l.nptr[2 * n + 1] as usize];
            assert!(incs.windows(2).all(|w| w[0] < w[1]), "element order");
            for &c in incs {
                assert_eq!(model.conn[c as usize / 8][c as usize % 8], n as u32);
                assert!(!std::mem::replace(&mut seen[c as usize], true));
            }
        }
        assert!(seen.iter().all(|&s| s));
        // the material: density, then elastic law 0
        assert_eq!(l.par[0], 7850.0);
        assert_eq!(l.par[5], 0.0);
    }

    #[test]
    fn element_arrays_by_component_and_back() {
        // two elements of three values, and a padding word that stays where it is
        let a = [10, 11, 12, 20, 21, 22, 99];
        let d = by_component(&a, 3);
        assert_eq!(d, [10, 20, 11, 21, 12, 22, 99]);
        assert_eq!(by_element(&d, 3), a);
    }
}
