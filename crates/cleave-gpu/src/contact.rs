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

use cleave_core::contact::view::CLOSURE_STATE;
use cleave_core::contact::{ContactForce, ContactSet};
use cleave_core::model::PenaltyRule;
use cleave_core::solver::Solver;
use std::hash::{BuildHasherDefault, Hasher};
use wgpu::util::DeviceExt;

use crate::by_entry::ByEntry;
use crate::device::{Gpu, GpuError};

/// The tables' look-ups (a node's lead, a face or pass-node by what it is), remade at every
/// split: keyed by small integers, looked up only (never iterated, so their order cannot reach
/// a result), hashed by a multiply-xor of each integer (std's SipHash, made for keys an
/// adversary chooses, took most of the time of making the tables).
type HashMap<K, V> = std::collections::HashMap<K, V, BuildHasherDefault<IntHasher>>;

#[derive(Default)]
pub(crate) struct IntHasher(u64);

impl Hasher for IntHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u8(&mut self, i: u8) {
        self.write_u64(u64::from(i));
    }
    fn write_u32(&mut self, i: u32) {
        self.write_u64(u64::from(i));
    }
    fn write_u64(&mut self, i: u64) {
        // (the multiplier of FxHash: odd, bits spread)
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
}

/// Values per pass-node in the hits array (contact.wgsl HIT).
pub(crate) const HIT: usize = 14;

/// The most cells a face takes in the grid: one whose sphere's box spans more than 3 along an
/// axis goes to the list every node reads instead (contact.wgsl SPAN).
const CELLS: usize = 27;

/// The sizes and offsets contact.wgsl reads from the head of `ci` (its `params()`), in order.
const PARAMS: [&str; 38] = [
    "C_NN", "C_NF", "C_NP", "C_NG", "C_GG", "C_M", "C_NC", "CI_FACE", "CI_FSIDE", "CI_FLAB",
    "CI_PN", "CI_PASS", "CI_NFPTR", "CI_GN", "CI_GOPTR", "CI_GFPTR", "CI_GCPTR", "CI_CLO",
    "CI_FCLO", "CF_K", "CF_DEPTH", "CF_KN", "CF_DEF", "CF_PEN", "CF_H", "CF_CK", "G_COUNT",
    "G_OFF", "G_FILL", "G_BIGN", "H_COUNT", "H_OFF", "H_FILL", "G_ENT", "G_BIG", "H_LIST",
    "G_SPAN", "G_REL",
];

/// Values per closed crack in the `clo` array: its state between steps (cleave-core
/// contact/view.rs CLOSURE_STATE), then 1 in the step it is released.
pub(crate) const CLO: usize = CLOSURE_STATE + 1;

/// No face, closed crack or pass-node (contact.wgsl NONE).
const NONE: u32 = u32::MAX;

/// The tables of contact.wgsl, built on the host from the solver's definitions.
#[derive(Debug, Default)]
pub(crate) struct Tables {
    /// `u32` tables (`ci`, the [`PARAMS`] first) and `f64` tables (`cfl`).
    pub ci: Vec<u32>,
    pub cfl: Vec<f64>,
    pub faces: usize,
    pub pass_nodes: usize,
    pub surface_nodes: usize,
    /// Each pass-node's definition and sign in its definition's resultant (1 for a slave
    /// node's pass, -1 for a master node's: the force on the slave side).
    pub pn_def: Vec<(usize, f64)>,
    /// What each pass-node and face is, to carry the pairs over when the tables are made
    /// again: (pass, lead node); (definition, side, element, local face).
    pub pn_key: Vec<(u32, u32)>,
    pub face_key: Vec<(u32, u32, u32, u8)>,
    /// Each pass-node's coincident set on its side, along the member chain (its lead first):
    /// pass-node j's at `members[members_at[j]..members_at[j + 1]]` ([`Tables::members_of`]).
    pub members: Vec<u32>,
    pub members_at: Vec<u32>,
    /// The lead of each node of a pass's node side, by (pass, node): as many entries as the
    /// sides have nodes (not the model).
    pub lead_of: HashMap<(u32, u32), u32>,
    /// The entries of the surface nodes (slots of the coincident sets, or nodes), ascending:
    /// each one's last contact force is kept, in this order.
    pub surface: Vec<u32>,
    /// The closed cracks of every definition in order, with their definition, and their states
    /// ([`CLO`] values each, the release flag zero).
    pub closures: Vec<usize>,
    pub clo: Vec<f64>,
    /// u32 values of the grid and hit lists.
    pub grid_len: usize,
}

impl Tables {
    /// Pass-node j's coincident set on its side, along the member chain (its lead first).
    pub fn members_of(&self, j: usize) -> &[u32] {
        &self.members[self.members_at[j] as usize..self.members_at[j + 1] as usize]
    }

    /// The value of parameter `name` ([`PARAMS`]).
    pub fn param(&self, name: &str) -> usize {
        let k = PARAMS.iter().position(|&p| p == name).expect("a parameter");
        self.ci[k] as usize
    }

    /// The bytes of the pairs (hits) and of the surface entries' last forces on the device.
    pub fn pair_bytes(&self) -> [u64; 2] {
        [
            (8 * HIT * self.pass_nodes.max(1)) as u64,
            (24 * self.surface_nodes.max(1)) as u64,
        ]
    }

    /// The groups of 64 threads each pass runs, in [`PASSES`] order.
    fn groups(&self) -> [usize; 11] {
        let per = |n: usize| n.div_ceil(crate::stepper::GROUP);
        let (f, p, g, c) = (
            per(self.faces),
            per(self.pass_nodes),
            per(self.surface_nodes),
            per(self.closures.len()),
        );
        [c, 1, f, 1, f, p, 1, p, f, g, 1]
    }
}

/// The passes of contact.wgsl, in the order they run.
pub(crate) const PASSES: [&str; 11] = [
    "c_close",
    "c_close_done",
    "c_count",
    "c_scan",
    "c_fill",
    "c_detect",
    "c_hscan",
    "c_hfill",
    "c_hsort",
    "c_gather",
    "c_energy",
];

/// The tables of the solver's contact definitions as they are now, with the grid's cell from
/// the surfaces as they are ([`cell_size`]); `None` without contact. With element separation the
/// nodes are read at their coincident sets' slots (where the GPU keeps their positions and
/// gathers their forces), only each set's lead is checked (with its set's normal), and a node
/// is not checked against a face that holds a node of its chain
/// ([`cleave_core::contact::Contact::chain_label`]); the host's contact must be settled
/// ([`ContactSet::settle`]).
pub(crate) fn tables(solver: &Solver) -> Option<Tables> {
    let cs: &ContactSet = solver.contact()?;
    if cs.is_empty() {
        return None;
    }
    let model = solver.model;
    let nn = model.num_nodes();
    // where each node's position and force are: its coincident set's slot, or itself
    let slots = solver.separation().map(|s| s.sets().slots());
    let entry = |n: u32| slots.map_or(n, |s| s[n as usize]);
    // the entries in use (the sets' slots: a split model's entries past them hold nothing, so
    // the lists by entry below need not pass over the one per node of the arrays)
    let ne = solver.separation().map_or(nn, |s| s.sets().num_slots());
    // faces of every side of every definition, numbered in that order; each side a tag
    let (mut face_nodes, mut face_entries, mut face_labels) = (vec![], vec![], vec![]);
    let (mut face_tag, mut fk, mut fdepth) = (vec![], vec![], vec![]);
    let mut side_start: Vec<Vec<(u32, u32)>> = vec![]; // (first face, tag) per def, side
    let mut face_key = vec![];
    let mut tag = 0u32;
    for (d, c) in cs.contacts().iter().enumerate() {
        let mut sides = vec![];
        for side in 0..c.num_sides() {
            sides.push((face_tag.len() as u32, tag));
            for f in c.faces(side) {
                face_key.push((d as u32, side as u32, f.elem, f.face));
                face_nodes.extend_from_slice(&f.nodes);
                face_entries.extend(f.nodes.map(entry));
                face_labels.extend(f.nodes.map(|n| c.chain_label(n)));
                face_tag.push(tag);
                fk.push(f.k);
                fdepth.push(f.depth);
            }
            tag += 1;
        }
        side_start.push(sides);
    }
    let nf = face_tag.len();
    // the closed cracks: each one's nodes' entries and definition; the closure each face lies
    // on (of its own definition)
    let (mut clo_tab, mut clo, mut ck, mut closures) = (vec![], vec![], vec![], vec![]);
    let mut fclo = vec![NONE; nf];
    for (d, c) in cs.contacts().iter().enumerate() {
        let closed = c.closed_cracks();
        let at: HashMap<(u32, u8), u32> = closed
            .iter()
            .enumerate()
            .flat_map(|(k, cc)| cc.faces.map(|f| (f, (closures.len() + k) as u32)))
            .collect();
        for (side, &(first, _)) in side_start[d].iter().enumerate() {
            for (f, face) in c.faces(side).iter().enumerate() {
                if let Some(&k) = at.get(&(face.elem, face.face)) {
                    fclo[first as usize + f] = k;
                }
            }
        }
        for cc in closed {
            clo_tab.extend(cc.a.map(entry));
            clo_tab.extend(cc.b.map(entry));
            clo_tab.push(d as u32);
            clo.extend_from_slice(&cc.state);
            clo.push(0.0);
            ck.push(cc.k);
            closures.push(d);
        }
    }
    let nc = closures.len();
    // the pass-nodes: definitions, passes, each node side's leads in scatter order
    let (mut pn, mut pass_tab, mut kn, mut pn_def) = (vec![], vec![], vec![], vec![]);
    // (each pass-node's faces in one list: `frame[frame_at[j]..frame_at[j + 1]]`)
    let (mut frame, mut frame_at) = (vec![], vec![0]);
    let (mut pn_key, mut members, mut members_at) = (vec![], vec![], vec![0]);
    let side_nodes: usize = (cs.contacts().iter())
        .flat_map(|c| {
            c.pass_sides()
                .into_iter()
                .map(|(ns, _)| c.side_nodes(ns).len())
        })
        .sum();
    let mut lead_of = HashMap::with_capacity_and_hasher(side_nodes, Default::default());
    for (d, c) in cs.contacts().iter().enumerate() {
        for (p, (ns, fs)) in c.pass_sides().into_iter().enumerate() {
            let q = pass_tab.len() as u32 / 2;
            pass_tab.extend([side_start[d][fs].1, d as u32]);
            let sign = if p == 0 { 1.0 } else { -1.0 };
            for &n in c.side_nodes(ns) {
                if let Some(l) = c.lead_of(ns, n) {
                    lead_of.insert((q, n), l);
                }
            }
            for n in c.leads_in_scatter_order(ns) {
                // the faces that make its normal: none when all of them eroded (buried)
                let first = side_start[d][ns].0;
                let start = frame.len();
                c.frame_of_lead(ns, n, &mut frame);
                for f in &mut frame[start..] {
                    *f += first;
                }
                frame_at.push(frame.len());
                let buried = frame.len() == start;
                pn.extend([entry(n), q, buried as u32, c.chain_label(n)]);
                kn.push(cs.node_stiffness(n));
                pn_def.push((d, sign));
                pn_key.push((q, n));
                c.members_of_lead(ns, n, &mut members);
                members_at.push(members.len() as u32);
            }
        }
    }
    let np = pn_def.len();
    // the surface entries: every entry of a pass-node or a face, ascending; what acts on each
    // (its own pass-nodes, the corners of faces, the closed cracks' pairs: 8 k + 2 pair + 1
    // on the A side)
    let own = ByEntry::new(ne, (0..np).map(|j| (pn[4 * j], j as u32)));
    // 4 f + a
    let corner = ByEntry::new(
        ne,
        (face_entries.iter().enumerate()).map(|(k, &e)| (e, k as u32)),
    );
    // the force on b_k, then its opposite on a_k (mod.rs Contact::compute)
    let clo_tab = &clo_tab;
    let paired = ByEntry::new(
        ne,
        (0..nc).flat_map(|c| {
            (0..4).flat_map(move |k| {
                [
                    (clo_tab[9 * c + 4 + k], (8 * c + 2 * k) as u32),
                    (clo_tab[9 * c + k], (8 * c + 2 * k + 1) as u32),
                ]
            })
        }),
    );
    let surface: Vec<u32> = (0..ne as u32)
        .filter(|&n| !own.of(n).is_empty() || !corner.of(n).is_empty())
        .collect();
    let ng = surface.len();
    // ci: the parameters, faces' entries, tags and labels, pass-nodes, passes, lists with
    // their pointers (absolute indices into ci), the closed cracks, each face's crack
    let mut ci = vec![0; PARAMS.len()];
    ci.extend_from_slice(&face_entries);
    ci.extend_from_slice(&face_tag);
    let ci_flab = ci.len();
    ci.extend_from_slice(&face_labels);
    let ci_pn = ci.len();
    ci.extend_from_slice(&pn);
    let ci_pass = ci.len();
    ci.extend_from_slice(&pass_tab);
    let ci_nfptr = csr(&mut ci, np, |j| &frame[frame_at[j]..frame_at[j + 1]]);
    let ci_gn = ci.len();
    ci.extend_from_slice(&surface);
    let ci_goptr = csr(&mut ci, ng, |g| own.of(surface[g]));
    let ci_gfptr = csr(&mut ci, ng, |g| corner.of(surface[g]));
    let ci_gcptr = csr(&mut ci, ng, |g| paired.of(surface[g]));
    let ci_clo = ci.len();
    ci.extend_from_slice(clo_tab);
    let ci_fclo = ci.len();
    ci.extend_from_slice(&fclo);
    // cfl: faces' stiffness and depth, pass-nodes' stiffness, friction per definition,
    // PENOPT, the cell size, the closed cracks' penalties
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
    let h = cell_size(solver, &face_nodes, &cfl[nf..2 * nf]);
    cfl.push(h);
    let cf_ck = cfl.len();
    cfl.extend_from_slice(&ck);
    // the grid: counts, offsets, cursors of the cells; of the hit lists per face; the cells'
    // entries, the big faces, the hit lists, the faces' spans, the count of cracks released
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
    let g_span = h_list + np;
    let g_rel = g_span + 6 * nf;
    let grid_len = g_rel + 1;
    let values = [
        ("C_NN", nn as u64),
        ("C_NF", nf as u64),
        ("C_NP", np as u64),
        ("C_NG", ng as u64),
        ("C_GG", ng.div_ceil(64) as u64),
        ("C_M", m as u64),
        ("C_NC", nc as u64),
        ("CI_FACE", PARAMS.len() as u64),
        ("CI_FSIDE", (PARAMS.len() + 4 * nf) as u64),
        ("CI_FLAB", ci_flab as u64),
        ("CI_PN", ci_pn as u64),
        ("CI_PASS", ci_pass as u64),
        ("CI_NFPTR", ci_nfptr as u64),
        ("CI_GN", ci_gn as u64),
        ("CI_GOPTR", ci_goptr as u64),
        ("CI_GFPTR", ci_gfptr as u64),
        ("CI_GCPTR", ci_gcptr as u64),
        ("CI_CLO", ci_clo as u64),
        ("CI_FCLO", ci_fclo as u64),
        ("CF_K", 0),
        ("CF_DEPTH", nf as u64),
        ("CF_KN", cf_kn as u64),
        ("CF_DEF", cf_def as u64),
        ("CF_PEN", cf_pen as u64),
        ("CF_H", cf_pen as u64 + 1),
        ("CF_CK", cf_ck as u64),
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
        ("G_SPAN", g_span as u64),
        ("G_REL", g_rel as u64),
    ];
    for (name, v) in values {
        let k = PARAMS.iter().position(|&p| p == name).expect("a parameter");
        // (a table past u32 is past any binding: refused by ContactGpu::upload)
        ci[k] = u32::try_from(v).unwrap_or(u32::MAX);
    }
    Some(Tables {
        ci,
        cfl,
        faces: nf,
        pass_nodes: np,
        surface_nodes: ng,
        pn_def,
        pn_key,
        face_key,
        members,
        members_at,
        lead_of,
        surface,
        closures,
        clo,
        grid_len,
    })
}

/// Append `count` lists to `ci` behind their pointers (absolute indices into `ci`, the end
/// last); returns where the pointers start.
fn csr<'a>(ci: &mut Vec<u32>, count: usize, list: impl Fn(usize) -> &'a [u32]) -> usize {
    let ptr = ci.len();
    ci.resize(ptr + count + 1, 0);
    for k in 0..count {
        ci[ptr + k] = ci.len() as u32;
        ci.extend_from_slice(list(k));
    }
    ci[ptr + count] = ci.len() as u32;
    ptr
}

/// What carries over to new tables: the hits and each surface entry's last force of the tables
/// before, as read back, and the slots born in this step, each with the slot it split from.
pub(crate) type Carry<'a> = (&'a [f64], &'a [f64], &'a [(u32, u32)]);

/// The pairs and forces of tables `old` (`hits`, `fprev` as read back; `born`: the slots born
/// in this step, each with the slot it split from) into the numbering of `t` (`h`, `fp`, filled
/// with none and zeros): a pass-node takes the pair of its set's lead before (that of its first
/// member, along the chain, that was on the side), with its face by what it is; a surface
/// entry keeps its last force. An entry that is no longer on the surface (its set split and
/// its surface nodes went to the slots born of it) hands its last force to the first of those
/// on the surface: they move as it did in this step (a born slot starts with its set's
/// velocity), so the energy's `f^(n-1).v^(n-1/2)` is kept, as the CPU keeps every node's last
/// force. Returns those entries (their contact force on the device is to be set to zero).
fn carry_pairs(
    old: &Tables,
    t: &Tables,
    (hits, fprev, born): Carry,
    h: &mut [f64],
    fp: &mut [f64],
) -> Vec<u32> {
    let face_at: HashMap<_, u32> = (t.face_key.iter().enumerate())
        .map(|(f, &k)| (k, f as u32))
        .collect();
    let pn_was: HashMap<_, usize> = (old.pn_key.iter().enumerate())
        .map(|(j, &k)| (k, j))
        .collect();
    for (jn, &(q, _)) in t.pn_key.iter().enumerate() {
        let members = t.members_of(jn);
        // a lead carries on its set's contact: that of the lead before of its first
        // member (along the chain) that was on the side (mod.rs Contact::regroup_where)
        let Some(&j) = (members.iter())
            .find_map(|&m| old.lead_of.get(&(q, m)))
            .and_then(|&lead| pn_was.get(&(q, lead)))
        else {
            continue;
        };
        let Some(o) = hits.get(HIT * j..HIT * (j + 1)) else {
            continue;
        };
        let dst = &mut h[HIT * jn..HIT * (jn + 1)];
        if o[0] < 0.0 {
            // out of contact: its friction force may carry (zero unless kept)
            dst.copy_from_slice(o);
            continue;
        }
        // the face by what it is; a pair whose face left the surface starts again from
        // none, as a new pair does
        if let Some(&f) = old.face_key.get(o[0] as usize).and_then(|k| face_at.get(k)) {
            dst.copy_from_slice(o);
            dst[0] = f64::from(f);
        }
    }
    let at: HashMap<u32, usize> = (t.surface.iter().enumerate())
        .map(|(g, &n)| (n, g))
        .collect();

    let mut left = vec![];
    for (g, n) in old.surface.iter().enumerate() {
        let Some(f) = fprev.get(3 * g..3 * g + 3) else {
            continue;
        };
        if let Some(&gn) = at.get(n) {
            fp[3 * gn..3 * gn + 3].copy_from_slice(f);
            continue;
        }
        left.push(*n);
        // the slots born of it (and of those, in this step), in order: the first on the surface
        let mut family = vec![*n];
        let mut k = 0;
        while k < family.len() {
            let from = family[k];
            family.extend(born.iter().filter(|b| b.1 == from).map(|b| b.0));
            k += 1;
        }
        if let Some(&gn) = family.iter().find_map(|e| at.get(e)) {
            for i in 0..3 {
                fp[3 * gn + i] += f[i];
            }
        }
    }
    left
}

/// Bring the host's contact up to its coincident sets as they are now (the chains of closed
/// cracks, the sets' leads: [`ContactSet::settle`]) before its tables are read; `halt`: in a
/// halt of the step (a split, a crack's release, an erosion), where only the copies of the
/// faces activated since the last settle are regrouped ([`ContactSet::settle_pending`]); not
/// when a restart file's state is taken up.
pub(crate) fn settle(solver: &mut Solver, halt: bool) {
    let tie: Vec<u32> = (solver.separation())
        .map(|s| s.sets().node_sets().to_vec())
        .unwrap_or_default();
    if let Some(cs) = solver.contact_mut() {
        match halt {
            true => cs.settle_pending(&tie),
            false => cs.settle(&tie),
        }
    }
}

/// The grid's cell size: the 90th percentile of the faces' search-sphere diameters
/// `2 (E r + depth)` when the tables are made (at the start, and again when faces join or
/// erode; penalty.rs WEIGHT_SUM E, r the largest centre-corner
/// distance), so that nine faces in ten span at most two cells a side (three once grown) and
/// the few largest (a thick plate's faces, whose depth 0.4 V/A reaches far) go to the list
/// every node reads, rather than making every cell hold many small faces; 1 when no face has
/// a finite positive one. On the 2800-element ball on its plate, the largest diameter (as the
/// cell size) made the node checks 77% of a step on lavapipe.
fn cell_size(solver: &Solver, face_nodes: &[u32], depth: &[f64]) -> f64 {
    let x = solver.positions();
    let mut d: Vec<f64> = (face_nodes.chunks_exact(4).zip(depth))
        .map(|(f, depth)| {
            let p: [[f64; 3]; 4] = std::array::from_fn(|a| x[f[a] as usize]);
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
    let k = (d.len() - 1) * 9 / 10;
    *d.select_nth_unstable_by(k, f64::total_cmp).1
}

/// The contact passes of the step, their buffers and their bind group.
pub(crate) struct ContactGpu {
    /// The passes ([`PASSES`]) and the groups each runs over the present tables.
    pub passes: Vec<(&'static str, wgpu::ComputePipeline)>,
    pub groups: [usize; 11],
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
    /// What carries over to the next step: the hits (HIT values per pass-node) and the last
    /// step's contact force of each surface node (3 each).
    pub hits: wgpu::Buffer,
    pub fprev: wgpu::Buffer,
    /// The closed cracks' states ([`CLO`] values each).
    pub clo: wgpu::Buffer,
    /// The tables, their buffers and the grid's.
    bufs: Vec<wgpu::Buffer>,
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

fn init(gpu: &Gpu, label: &str, contents: &[u8]) -> wgpu::Buffer {
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: STORAGE,
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

/// The pairs of tables `t` with no contact yet (face -1), and zero last forces.
fn fresh(t: &Tables) -> (Vec<f64>, Vec<f64>) {
    let mut h = vec![0.0f64; HIT * t.pass_nodes.max(1)];
    h.iter_mut().step_by(HIT).for_each(|f| *f = -1.0);
    (h, vec![0.0f64; 3 * t.surface_nodes.max(1)])
}

/// The buffers of a set of tables and their bind group.
struct Buffers {
    bind_group: wgpu::BindGroup,
    hits: wgpu::Buffer,
    fprev: wgpu::Buffer,
    clo: wgpu::Buffer,
    bufs: Vec<wgpu::Buffer>,
}

impl Buffers {
    /// Tables `t` (with their closed cracks' states) with pairs `h` and last forces `fp` on
    /// the device, bound with the step's control block, positions and velocities `step`
    /// (`cf`, `x`, `v`, `cu`) and the contact forces `fcon`.
    fn new(
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        step: [&wgpu::Buffer; 4],
        fcon: &wgpu::Buffer,
        t: &Tables,
        h: &[f64],
        fp: &[f64],
    ) -> Self {
        let ci = init(gpu, "contact tables", bytemuck::cast_slice(&t.ci));
        let cfl = init(gpu, "contact values", bytemuck::cast_slice(&t.cfl));
        let hits = init(gpu, "contact pairs", bytemuck::cast_slice(h));
        let fprev = init(gpu, "contact forces, last step", bytemuck::cast_slice(fp));
        let grid = zeros(gpu, "contact grid", 4 * t.grid_len);
        let cpart = zeros(gpu, "contact work partials", 8 * t.groups()[9]);
        let fsph = zeros(gpu, "contact face spheres", 32 * t.faces);
        // (a binding is never empty)
        let none = [0.0f64; CLO];
        let clo_values = if t.clo.is_empty() {
            &none[..]
        } else {
            &t.clo[..]
        };
        let clo = init(gpu, "closed cracks", bytemuck::cast_slice(clo_values));
        let bound = [
            step[0], step[1], step[2], &ci, &cfl, &hits, fcon, &fprev, &grid, &cpart, &fsph, &clo,
            step[3],
        ];
        let entries: Vec<_> = (bound.iter().enumerate())
            .map(|(b, buf)| wgpu::BindGroupEntry {
                binding: b as u32,
                resource: buf.as_entire_binding(),
            })
            .collect();
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("contact"),
            layout,
            entries: &entries,
        });
        Self {
            bind_group,
            hits,
            fprev,
            clo,
            bufs: vec![ci, cfl, grid, cpart, fsph],
        }
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
        settle(solver, false);
        let Some(t) = tables(solver) else {
            return Ok(None);
        };
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
        let (h, fp) = fresh(&t);
        let d = Buffers::new(gpu, &layout, [cf, x, v, cu], &fcon, &t, &h, &fp);
        Ok(Some(Self {
            passes: passes.into(),
            groups: t.groups(),
            bind_group: d.bind_group,
            layout,
            cf: cf.clone(),
            cu: cu.clone(),
            x: x.clone(),
            v: v.clone(),
            hits: d.hits,
            fprev: d.fprev,
            clo: d.clo,
            fcon,
            bufs: d.bufs,
            tables: t,
        }))
    }

    /// Put tables `t` on the device (new buffers, a new bind group; the pipelines stay), the
    /// pairs and last forces `carry` (the hits and each surface entry's force of the tables
    /// before, as read back, and the slots born in this step with the slot each split from)
    /// carried over to the new numbering ([`carry_pairs`]); new ones start from none.
    pub fn upload(&mut self, gpu: &Gpu, t: Tables, carry: Option<Carry>) -> Result<(), GpuError> {
        check_sizes(gpu, &t, &self.x)?;
        let (mut h, mut fp) = fresh(&t);
        if let Some((hits, fprev, born)) = carry {
            // an entry that left the surface gathers no force from now on
            for e in carry_pairs(&self.tables, &t, (hits, fprev, born), &mut h, &mut fp) {
                let at = 24 * u64::from(e);
                if at + 24 <= self.fcon.size() {
                    gpu.queue.write_buffer(&self.fcon, at, &[0u8; 24]);
                }
            }
        }
        let d = Buffers::new(
            gpu,
            &self.layout,
            [&self.cf, &self.x, &self.v, &self.cu],
            &self.fcon,
            &t,
            &h,
            &fp,
        );
        (self.bind_group, self.hits, self.fprev, self.clo, self.bufs) =
            (d.bind_group, d.hits, d.fprev, d.clo, d.bufs);
        self.groups = t.groups();
        self.tables = t;
        Ok(())
    }

    /// The present tables.
    pub fn tables(&self) -> &Tables {
        &self.tables
    }

    /// The bytes of the contact's buffers on the device.
    pub fn bytes(&self) -> u64 {
        (self.bufs.iter().chain([&self.hits, &self.fprev, &self.clo]))
            .map(|b| b.size())
            .sum()
    }

    /// The closed cracks' states `clo` (as read back) into the host's contact of `solver`,
    /// the cracks flagged released leaving it when `released` ([`ContactSet::closures_stepped`]).
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
                states.extend_from_slice(&s[..CLOSURE_STATE]);
                flags.push(released && s[CLOSURE_STATE] != 0.0);
            }
            cs.closures_stepped(d, &states, &flags)?;
        }
        Ok(())
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
    use cleave_core::model::{ContactDef, ContactSurface, Material, MaterialKind};
    use wgpu::naga;

    /// Tables of one pass whose node side holds `sets` (each a lead and its other members,
    /// along the chain), with faces `faces` (element numbers) and surface entries `surface`.
    fn pass_tables(sets: &[&[u32]], faces: &[u32], surface: &[u32]) -> Tables {
        let mut t = Tables {
            members_at: vec![0],
            faces: faces.len(),
            pass_nodes: sets.len(),
            surface_nodes: surface.len(),
            surface: surface.to_vec(),
            face_key: faces.iter().map(|&e| (0, 0, e, 0)).collect(),
            ..Default::default()
        };
        for set in sets {
            t.pn_key.push((0, set[0]));
            t.members.extend_from_slice(set);
            t.members_at.push(t.members.len() as u32);
            for &m in *set {
                t.lead_of.insert((0, m), set[0]);
            }
        }
        t
    }

    /// A hit on face `f` with force `fx` along x.
    fn hit(f: f64, fx: f64) -> Vec<f64> {
        let mut h = vec![0.0; HIT];
        (h[0], h[5], h[10]) = (f, fx, fx);
        h
    }

    /// The pairs and last forces carried over when tables are made again: a set that splits
    /// (lead 10 with members 12 and 14) gives its pair to each new lead, the one that was its
    /// lead (10) and one that was not (12, whose first member on the side before was itself,
    /// under lead 10); a lead whose own node left the side (16 under lead 15, 15 gone) takes
    /// its set's pair; the face is renumbered by what it is; a surface entry keeps its force,
    /// and one that left the surface (entry 7, whose surface nodes went to slot 9, born of 8,
    /// itself born of 7 in this step) hands it to the first slot born of it on the surface,
    /// and is returned (its force on the device is then zeroed).
    #[test]
    fn pairs_and_forces_carry_over_splits() {
        let old = pass_tables(&[&[10, 12, 14], &[15, 16]], &[100, 200], &[3, 7]);
        let new = pass_tables(&[&[10, 14], &[12], &[16]], &[200, 100], &[3, 9]);
        let hits = [hit(1.0, 5.0), hit(0.0, 6.0)].concat();
        let fprev = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let (mut h, mut fp) = fresh(&new);
        let born = [(8, 7), (9, 8)];
        let left = carry_pairs(&old, &new, (&hits, &fprev, &born), &mut h, &mut fp);
        // 10 and 12 carry lead 10's pair on element 200's face, now face 0; 16 carries 15's
        let want = [hit(0.0, 5.0), hit(0.0, 5.0), hit(1.0, 6.0)].concat();
        assert_eq!(h, want);
        assert_eq!(fp, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(left, vec![7]);
        // without the born slots, the force of entry 7 has no heir
        let (mut h, mut fp) = fresh(&new);
        carry_pairs(&old, &new, (&hits, &fprev, &[]), &mut h, &mut fp);
        assert_eq!(fp, vec![1.0, 2.0, 3.0, 0.0, 0.0, 0.0]);
    }

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
        // the cell: every face's sphere diameter, 2 (E r + 0.4 V/A) with r = sqrt(2)/4 for the
        // 0.5 squares of elements 0.125 in volume
        let h = t.cfl[c("CF_H")];
        let want = 2.0 * (1.08 * 2f64.sqrt() / 4.0 + 0.4 * 0.125 / 0.25);
        assert!((h - want).abs() < 1e-12, "{h} {want}");
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
