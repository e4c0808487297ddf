//! The tables contact.wgsl reads, made on the host from the solver's contact definitions, and
//! the pairs carried over when they are made again (at a split, a crack's release, an
//! erosion).
//!
//! A split remakes them from the host's contact as it then is, and that is most steps of a
//! breaking ball, so they are made without hashing and with few allocations (the host
//! contact's lists of leads and closed cracks): the arrays of the tables before and the work
//! arrays ([`Scratch`]) are kept and refilled, each entry's lists are written into `ci` where
//! they go (a counting sort by entry), a face's closed crack is found through an array by
//! element face, and the carried pairs through an array by node and by each face's place in
//! its side (faces only join the end of a side, and an eroded face stays in its place with no
//! stiffness and depth, so a face keeps its place; a hash map by what the face is would catch
//! tables whose sides were made otherwise, none today). The tables are those made afresh,
//! value for value: a restarted run makes them afresh and gives the same bits.

use cleave_core::contact::view::CLOSURE_STATE;
use cleave_core::contact::ContactSet;
use cleave_core::model::PenaltyRule;
use cleave_core::solver::Solver;
use std::hash::{BuildHasherDefault, Hasher};

/// The look-up of a face by what it is, when its place in its side misses ([`FaceMap`]): keyed
/// by small integers, looked up only (never iterated, so its order cannot reach a result), hashed by a
/// multiply-xor of each integer (std's SipHash, made for keys an adversary chooses, is slower).
type HashMap<K, V> = std::collections::HashMap<K, V, BuildHasherDefault<IntHasher>>;

#[derive(Default)]
struct IntHasher(u64);

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

/// Counts of a group in the scans (contact.wgsl BLOCK).
const BLOCK: usize = 1024;

/// Groups that sort and add the long lists of the nodes pushing on a face (contact.wgsl
/// c_hlong): each takes every LONG_GROUPS-th, enough to fill a large GPU's cores with the few
/// such faces there are.
const LONG_GROUPS: usize = 32;

/// The most cells a face takes in the grid: one whose sphere's box spans more than 3 along an
/// axis goes to the list every node reads instead (contact.wgsl SPAN).
const CELLS: usize = 27;

/// The most faces a pass-node's list of candidates holds (contact.wgsl CANDS; C_K at most
/// this): a node with more is checked against its cell's faces every step until the lists are
/// made again. 256 bytes a pass-node on the device; on the breaking 2800 ball a node lay in
/// the (not grown) spheres of 15 faces on average (a probe).
const CANDS: usize = 64;

/// The sizes and offsets contact.wgsl reads from the head of `ci` (its `params()`), in order.
pub(crate) const PARAMS: [&str; 51] = [
    "C_NN",
    "C_NF",
    "C_NP",
    "C_NG",
    "C_GG",
    "C_M",
    "C_NC",
    "CI_FACE",
    "CI_FSIDE",
    "CI_FLAB",
    "CI_PN",
    "CI_PASS",
    "CI_NFPTR",
    "CI_GN",
    "CI_GOPTR",
    "CI_GFPTR",
    "CI_GCPTR",
    "CI_CLO",
    "CI_FCLO",
    "CF_K",
    "CF_DEPTH",
    "CF_KN",
    "CF_DEF",
    "CF_PEN",
    "CF_H",
    "CF_MU",
    "CF_CK",
    "G_COUNT",
    "G_OFF",
    "G_FILL",
    "G_BIGN",
    "H_COUNT",
    "H_OFF",
    "H_FILL",
    "G_ENT",
    "G_BIG",
    "H_LIST",
    "G_SPAN",
    "G_REL",
    "G_LONGN",
    "G_LONG",
    "G_PART",
    "G_CAND",
    "G_CANDN",
    "G_FLAGS",
    "C_SHORT",
    "C_LONG",
    "C_LANES",
    "C_REVERSE",
    "C_K",
    "C_VERIFY",
];

/// The grid's flags (contact.wgsl G_FLAGS): the tables' age in steps, this step's mode, some
/// node's candidates past its list, the lists made so far, whether they are made, and for
/// tests ([`Tuning::verify`]) the faces a node's list missed and the faces looked for.
pub(crate) const FLAGS: usize = 7;

/// How the contact's passes share their work (contact.wgsl C_SHORT, C_LONG, C_LANES, C_REVERSE,
/// C_K, C_VERIFY, the last values of [`PARAMS`]); no choice changes a result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Tuning {
    /// The longest list of the nodes pushing on a face that one thread sorts and adds
    /// (c_hsort), and the longest a group sorts in its own memory (c_hlong): at most
    /// contact.wgsl SHORT and LONG_MAX, 16 and 1024, and less only in tests of the longer
    /// lists' paths.
    pub lists: [u32; 2],
    /// The threads that check one pass-node (c_detect), a power of two up to 64.
    pub lanes: u32,
    /// For tests: 1 fills each face's list of the nodes pushing on it from its end (c_hfill),
    /// so that the sorts, not the order of the atomics, must give the sums' order.
    pub reverse: u32,
    /// The most candidates a pass-node's list holds ([`CANDS`]; fewer only in tests and
    /// measurements: with 0 every node is checked against its cell every step).
    pub cands: u32,
    /// For tests: 1 checks every step that each node's list holds every face whose search
    /// sphere holds the node (counted in the grid's flags: [`FLAGS`]).
    pub verify: u32,
}

impl Tuning {
    /// [`Self::lists`] but in tests.
    const LISTS: [u32; 2] = [16, 1024];

    /// The choice for the device of `info`: 32 threads a pass-node on a GPU, 8 on a CPU's
    /// Vulkan (lavapipe), or the power of two up to 64 that the environment's CLEAVE_GPU_LANES
    /// names; lists of [`CANDS`] candidates, or as many (up to that) as CLEAVE_GPU_CANDS names
    /// (0: no lists, to measure them). On an H100 the node checks of the 2800 ball (to 20 us) took 588 us a step with
    /// one thread a node, 114 with 8 and 63 with 32 (`cleave bench ball --elements 2800
    /// --end-time 2e-5 --gpu --passes`); on lavapipe, whose threads are the CPU's lanes, more
    /// only add work.
    pub fn for_device(info: &wgpu::AdapterInfo) -> Self {
        let default = match info.device_type {
            wgpu::DeviceType::Cpu => 8,
            _ => 32,
        };
        let lanes = std::env::var("CLEAVE_GPU_LANES")
            .ok()
            .and_then(|v| v.parse::<u32>().ok())
            .filter(|l| l.is_power_of_two() && *l <= 64)
            .unwrap_or(default);
        let cands = std::env::var("CLEAVE_GPU_CANDS")
            .ok()
            .and_then(|v| v.parse::<u32>().ok())
            .map_or(CANDS as u32, |k| k.min(CANDS as u32));
        Tuning {
            lists: Self::LISTS,
            lanes,
            reverse: 0,
            cands,
            verify: 0,
        }
    }

    fn values(&self) -> [u32; 6] {
        let cands = self.cands.min(CANDS as u32);
        let [short, long] = self.lists;
        [short, long, self.lanes, self.reverse, cands, self.verify]
    }
}

/// Values per closed crack in the `clo` array: its state between steps (cleave-core
/// contact/view.rs CLOSURE_STATE), then 1 in the step it is released.
pub(crate) const CLO: usize = CLOSURE_STATE + 1;

/// No face, closed crack, pass-node or entry (contact.wgsl NONE).
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
    /// Each side of each definition in order: (definition, side, its first face).
    pub sides: Vec<(u32, u32, u32)>,
    /// Each pass-node's coincident set on its side, along the member chain (its lead first):
    /// pass-node j's at `members[members_at[j]..members_at[j + 1]]` ([`Tables::members_of`]).
    pub members: Vec<u32>,
    pub members_at: Vec<u32>,
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

    /// The pairs of these tables with no contact yet (face -1), and zero last forces.
    pub fn no_pairs(&self) -> (Vec<f64>, Vec<f64>) {
        let mut h = vec![0.0f64; HIT * self.pass_nodes.max(1)];
        h.iter_mut().step_by(HIT).for_each(|f| *f = -1.0);
        (h, vec![0.0f64; 3 * self.surface_nodes.max(1)])
    }

    /// The bytes of the closed cracks' states on the device (a binding is never empty).
    pub fn closure_bytes(&self) -> u64 {
        (8 * self.clo.len().max(CLO)) as u64
    }

    /// Tune these tables' passes ([`Tuning`]); returns the values and their place in `ci`.
    pub fn tune(&mut self, t: Tuning) -> ([u32; 6], usize) {
        let k = PARAMS.len() - 6;
        debug_assert_eq!(PARAMS[k], "C_SHORT");
        self.ci[k..k + 6].copy_from_slice(&t.values());
        (t.values(), k)
    }

    /// The groups of 64 threads each pass runs, in contact.rs PASSES order: one thread a
    /// closed crack, face, pass-node or surface node, [`Tuning::lanes`] a pass-node in c_detect, and
    /// [`LONG_GROUPS`] groups for the long lists of c_hlong.
    pub fn groups(&self) -> [usize; 16] {
        let per = |n: usize| n.div_ceil(crate::stepper::GROUP);
        let (f, p, g, c) = (
            per(self.faces),
            per(self.pass_nodes),
            per(self.surface_nodes),
            per(self.closures.len()),
        );
        let lanes = per(self.param("C_LANES").max(1) * self.pass_nodes);
        let (cells, faces) = (
            self.param("C_M").div_ceil(BLOCK),
            self.faces.div_ceil(BLOCK),
        );
        [
            c,
            1,
            f,
            cells,
            1,
            cells,
            f,
            lanes,
            faces,
            1,
            faces,
            p,
            f,
            LONG_GROUPS,
            g,
            1,
        ]
    }

    /// These tables emptied, their arrays kept for the next ones.
    fn emptied(mut self) -> Self {
        for v in [
            &mut self.ci,
            &mut self.members,
            &mut self.members_at,
            &mut self.surface,
        ] {
            v.clear();
        }
        self.cfl.clear();
        self.clo.clear();
        self.pn_def.clear();
        self.pn_key.clear();
        self.face_key.clear();
        self.sides.clear();
        self.closures.clear();
        self
    }
}

/// The work arrays of [`tables`] and [`carry_pairs`], kept from one call to the next.
#[derive(Default)]
pub(crate) struct Scratch {
    /// Each face's model nodes (for the cell size).
    face_nodes: Vec<u32>,
    /// The closed crack on each element face (element * stride + local face), NONE elsewhere
    /// (NONE again after each definition).
    crack_at: Vec<u32>,
    /// Each face's closed crack (NONE: none).
    fclo: Vec<u32>,
    /// The faces' entries (4 each) and search-sphere diameters (for the cell size).
    face_entries: Vec<u32>,
    diameters: Vec<f64>,
    /// The closed cracks' entries (a's four, b's four) and definition, 9 each.
    clo_tab: Vec<u32>,
    /// The pass-nodes (entry, pass, buried, chain label), the passes (face side's tag,
    /// definition), the pass-nodes' stiffness and the closed cracks' penalties.
    pn: Vec<u32>,
    pass_tab: Vec<u32>,
    kn: Vec<f64>,
    ck: Vec<f64>,
    /// The faces making each pass-node's normal, one list (`frame_at` its starts).
    frame: Vec<u32>,
    frame_at: Vec<usize>,
    /// Per entry: the count, then the cursor, of each of its three lists; its place in the
    /// surface (NONE off it).
    count: [Vec<u32>; 3],
    surface_at: Vec<u32>,
    /// The pass-node of the tables before that each node was a member of, by pass and node
    /// (NONE elsewhere, and again after each use): 4 bytes per pass and model node.
    member_of: Vec<u32>,
}

/// The tables of the solver's contact definitions as they are now, with the grid's cell from
/// the surfaces as they are ([`cell_size`]), made in the arrays of `recycled` (tables no longer
/// needed) and `s`; `None` without contact. With element separation the nodes are read at their
/// coincident sets' slots (where the GPU keeps their positions and gathers their forces), only
/// each set's lead is checked (with its set's normal), and a node is not checked against a face
/// that holds a node of its chain ([`cleave_core::contact::Contact::chain_label`]); the host's
/// contact must be settled ([`Solver::settle_contact`]).
pub(crate) fn tables(solver: &Solver, s: &mut Scratch, recycled: Tables) -> Option<Tables> {
    let cs: &ContactSet = solver.contact()?;
    if cs.is_empty() {
        return None;
    }
    let mut t = recycled.emptied();
    let model = solver.model;
    let nn = model.num_nodes();
    // where each node's position and force are: its coincident set's slot, or itself
    let slots = solver.separation().map(|s| s.sets().slots());
    let entry = |n: u32| slots.map_or(n, |s| s[n as usize]);
    // the entries in use (the sets' slots: a split model's entries past them hold nothing, so
    // the lists by entry below need not pass over the one per node of the arrays)
    let ne = solver.separation().map_or(nn, |s| s.sets().num_slots());
    // the faces of every side of every definition, numbered in that order; each side a tag
    let mut nf = 0;
    let mut stride = 1;
    for (d, c) in cs.contacts().iter().enumerate() {
        for side in 0..c.num_sides() {
            t.sides.push((d as u32, side as u32, nf as u32));
            nf += c.faces(side).len();
            stride = (c.faces(side).iter()).fold(stride, |m, f| m.max(f.face as usize + 1));
        }
    }
    // ci: the parameters, then the faces' entries (4 each), tags, chain labels (4 each)
    let p = PARAMS.len();
    let (ci_fside, ci_flab) = (p + 4 * nf, p + 5 * nf);
    t.ci.resize(p + 9 * nf, 0);
    t.cfl.resize(2 * nf, 0.0);
    s.face_nodes.clear();
    let mut f = 0;
    for (tag, &(d, side, _)) in t.sides.iter().enumerate() {
        let c = &cs.contacts()[d as usize];
        for face in c.faces(side as usize) {
            t.face_key.push((d, side, face.elem, face.face));
            s.face_nodes.extend_from_slice(&face.nodes);
            for (a, &n) in face.nodes.iter().enumerate() {
                t.ci[p + 4 * f + a] = entry(n);
                t.ci[ci_flab + 4 * f + a] = c.chain_label(n);
            }
            t.ci[ci_fside + f] = tag as u32;
            (t.cfl[f], t.cfl[nf + f]) = (face.k, face.depth);
            f += 1;
        }
    }
    // the closed cracks: each one's nodes' entries and definition; the closure each face lies
    // on (of its own definition)
    let faces_of_model = model.num_elements() * stride;
    if s.crack_at.len() < faces_of_model {
        s.crack_at.resize(faces_of_model, NONE);
    }
    let at = |(e, k): (u32, u8)| e as usize * stride + k as usize;
    let mut first_face = 0;
    s.fclo.clear();
    s.fclo.resize(nf, NONE);
    s.clo_tab.clear();
    s.ck.clear();
    for (d, c) in cs.contacts().iter().enumerate() {
        let closed = c.closed_cracks();
        let known = |f: (u32, u8)| (f.1 as usize) < stride && at(f) < faces_of_model;
        for (k, cc) in closed.iter().enumerate() {
            for f in cc.faces.into_iter().filter(|&f| known(f)) {
                s.crack_at[at(f)] = (t.closures.len() + k) as u32;
            }
        }
        for side in 0..c.num_sides() {
            for (i, face) in c.faces(side).iter().enumerate() {
                s.fclo[first_face + i] = s.crack_at[at((face.elem, face.face))];
            }
            first_face += c.faces(side).len();
        }
        for cc in &closed {
            for f in cc.faces.into_iter().filter(|&f| known(f)) {
                s.crack_at[at(f)] = NONE;
            }
            s.clo_tab.extend(cc.a.map(entry));
            s.clo_tab.extend(cc.b.map(entry));
            s.clo_tab.push(d as u32);
            t.clo.extend_from_slice(&cc.state);
            t.clo.push(0.0);
            s.ck.push(cc.k);
            t.closures.push(d);
        }
    }
    let nc = t.closures.len();
    // the pass-nodes: definitions, passes, each node side's leads in scatter order
    s.pn.clear();
    s.pass_tab.clear();
    s.kn.clear();
    s.frame.clear();
    s.frame_at.clear();
    s.frame_at.push(0);
    t.members_at.push(0);
    for (d, c) in cs.contacts().iter().enumerate() {
        let side_start = |side: usize| {
            let k = (t.sides.iter()).position(|&(e, sd, _)| (e, sd) == (d as u32, side as u32));
            k.map_or((0, 0), |k| (t.sides[k].2, k as u32))
        };
        for (pass, (ns, fs)) in c.pass_sides().into_iter().enumerate() {
            let q = s.pass_tab.len() as u32 / 2;
            s.pass_tab.extend([side_start(fs).1, d as u32]);
            let sign = if pass == 0 { 1.0 } else { -1.0 };
            let first = side_start(ns).0;
            for n in c.leads_in_scatter_order(ns) {
                // the faces that make its normal: none when all of them eroded (buried)
                let start = s.frame.len();
                c.frame_of_lead(ns, n, &mut s.frame);
                for f in &mut s.frame[start..] {
                    *f += first;
                }
                s.frame_at.push(s.frame.len());
                let buried = s.frame.len() == start;
                s.pn.extend([entry(n), q, buried as u32, c.chain_label(n)]);
                s.kn.push(cs.node_stiffness(n));
                t.pn_def.push((d, sign));
                t.pn_key.push((q, n));
                c.members_of_lead(ns, n, &mut t.members);
                t.members_at.push(t.members.len() as u32);
            }
        }
    }
    let np = t.pn_def.len();
    // ci after the faces: the pass-nodes, the passes, each pass-node's normal's faces
    // (pointers, then the lists)
    let ci_pn = t.ci.len();
    t.ci.extend_from_slice(&s.pn);
    let ci_pass = t.ci.len();
    t.ci.extend_from_slice(&s.pass_tab);
    let ci_nfptr = t.ci.len();
    t.ci.resize(ci_nfptr + np + 1, 0);
    for j in 0..np {
        t.ci[ci_nfptr + j] = (t.ci.len() + s.frame_at[j]) as u32;
    }
    t.ci[ci_nfptr + np] = (t.ci.len() + s.frame.len()) as u32;
    t.ci.extend_from_slice(&s.frame);
    // the surface entries: every entry of a pass-node or a face, ascending; what acts on each
    // (its own pass-nodes, the corners of faces, the closed cracks' pairs: 8 k + 2 pair + 1
    // on the A side), each entry's in the order of the items
    s.face_entries.clear();
    s.face_entries.extend_from_slice(&t.ci[p..p + 4 * nf]);
    let (pn, fe, clo_tab) = (&s.pn, &s.face_entries, &s.clo_tab);
    let own = (0..np).map(|j| (pn[4 * j], j as u32));
    let corner = (0..4 * nf).map(|k| (fe[k], k as u32));
    // the force on b_k, then its opposite on a_k (mod.rs Contact::compute): item 8 c + 2 k + a
    let paired = (0..8 * nc).map(|i| {
        let (c, k, a) = (i / 8, i % 8 / 2, i % 2);
        (clo_tab[9 * c + 4 * (1 - a) + k], i as u32)
    });
    let [c_own, c_corner, c_paired] = &mut s.count;
    count(c_own, ne, own.clone());
    count(c_corner, ne, corner.clone());
    count(c_paired, ne, paired.clone());
    s.surface_at.clear();
    s.surface_at.resize(ne, NONE);
    for e in 0..ne {
        if c_own[e] + c_corner[e] > 0 {
            s.surface_at[e] = t.surface.len() as u32;
            t.surface.push(e as u32);
        }
    }
    let ng = t.surface.len();
    let ci_gn = t.ci.len();
    t.ci.extend_from_slice(&t.surface);
    let ci_goptr = lists(&mut t.ci, c_own, &t.surface, &s.surface_at, own);
    let ci_gfptr = lists(&mut t.ci, c_corner, &t.surface, &s.surface_at, corner);
    let ci_gcptr = lists(&mut t.ci, c_paired, &t.surface, &s.surface_at, paired);
    let ci_clo = t.ci.len();
    t.ci.extend_from_slice(clo_tab);
    let ci_fclo = t.ci.len();
    t.ci.extend_from_slice(&s.fclo);
    // cfl after the faces' stiffness and depth: the pass-nodes' stiffness, friction per
    // definition, PENOPT, the cell size, the closed cracks' penalties
    let cf_kn = t.cfl.len();
    t.cfl.extend_from_slice(&s.kn);
    let cf_def = t.cfl.len();
    for c in cs.contacts() {
        let fr = c.friction;
        (t.cfl).extend([fr.fs, fr.fd, fr.dc, fr.is_frictionless() as u8 as f64]);
    }
    let cf_pen = t.cfl.len();
    t.cfl.push(match model.control.penalty {
        PenaltyRule::Smaller => 1.0,
        PenaltyRule::Face => 2.0,
    });
    let h = cell_size(solver, &s.face_nodes, &t.cfl[nf..2 * nf], &mut s.diameters);
    // the lists' margin: the host search's, the least of the definitions'
    let mu = (cs.contacts().iter()).fold(f64::INFINITY, |m, c| m.min(c.margin()));
    t.cfl.extend([h, mu]);
    let cf_ck = t.cfl.len();
    t.cfl.extend_from_slice(&s.ck);
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
    let g_longn = g_rel + 1;
    let g_long = g_longn + 1;
    let g_part = g_long + nf;
    let g_cand = g_part + m.max(nf).div_ceil(BLOCK) + 1;
    let g_candn = g_cand + CANDS * np;
    let g_flags = g_candn + np;
    t.grid_len = g_flags + FLAGS;
    let values = [
        ("C_NN", nn),
        ("C_NF", nf),
        ("C_NP", np),
        ("C_NG", ng),
        ("C_GG", ng.div_ceil(64)),
        ("C_M", m),
        ("C_NC", nc),
        ("CI_FACE", p),
        ("CI_FSIDE", ci_fside),
        ("CI_FLAB", ci_flab),
        ("CI_PN", ci_pn),
        ("CI_PASS", ci_pass),
        ("CI_NFPTR", ci_nfptr),
        ("CI_GN", ci_gn),
        ("CI_GOPTR", ci_goptr),
        ("CI_GFPTR", ci_gfptr),
        ("CI_GCPTR", ci_gcptr),
        ("CI_CLO", ci_clo),
        ("CI_FCLO", ci_fclo),
        ("CF_K", 0),
        ("CF_DEPTH", nf),
        ("CF_KN", cf_kn),
        ("CF_DEF", cf_def),
        ("CF_PEN", cf_pen),
        ("CF_H", cf_pen + 1),
        ("CF_MU", cf_pen + 2),
        ("CF_CK", cf_ck),
        ("G_COUNT", 0),
        ("G_OFF", g_off),
        ("G_FILL", g_fill),
        ("G_BIGN", g_bign),
        ("H_COUNT", h_count),
        ("H_OFF", h_off),
        ("H_FILL", h_fill),
        ("G_ENT", g_ent),
        ("G_BIG", g_big),
        ("H_LIST", h_list),
        ("G_SPAN", g_span),
        ("G_REL", g_rel),
        ("G_LONGN", g_longn),
        ("G_LONG", g_long),
        ("G_PART", g_part),
        ("G_CAND", g_cand),
        ("G_CANDN", g_candn),
        ("G_FLAGS", g_flags),
        // (set by `Tables::tune` before they go to the device: ContactGpu)
        ("C_SHORT", 0),
        ("C_LONG", 0),
        ("C_LANES", 0),
        ("C_REVERSE", 0),
        ("C_K", 0),
        ("C_VERIFY", 0),
    ];
    for (k, (name, v)) in values.into_iter().enumerate() {
        debug_assert_eq!(PARAMS[k], name);
        // (a table past u32 is past any binding: refused by ContactGpu::upload)
        t.ci[k] = u32::try_from(v).unwrap_or(u32::MAX);
    }
    (t.faces, t.pass_nodes, t.surface_nodes) = (nf, np, ng);
    Some(t)
}

/// Each entry's number of `items` (entry, value) into `count` (`n` entries).
fn count(count: &mut Vec<u32>, n: usize, items: impl Iterator<Item = (u32, u32)>) {
    count.clear();
    count.resize(n, 0);
    for (e, _) in items {
        count[e as usize] += 1;
    }
}

/// The values of `items` (entry, value) appended to `ci` as one list per surface entry, in
/// the order of the items, behind their pointers (absolute indices into `ci`, the end last);
/// `count`: each entry's number of items ([`count`]), used up as the cursors; items of entries
/// off the surface (`surface_at` NONE) are left out. Returns where the pointers start.
fn lists(
    ci: &mut Vec<u32>,
    count: &mut [u32],
    surface: &[u32],
    surface_at: &[u32],
    items: impl Iterator<Item = (u32, u32)>,
) -> usize {
    let (ptr, ng) = (ci.len(), surface.len());
    let mut at = ptr + ng + 1;
    ci.resize(at, 0);
    for (g, &e) in surface.iter().enumerate() {
        ci[ptr + g] = at as u32;
        let n = count[e as usize] as usize;
        count[e as usize] = at as u32;
        at += n;
    }
    ci[ptr + ng] = at as u32;
    ci.resize(at, 0);
    for (e, v) in items {
        if surface_at[e as usize] != NONE {
            let c = &mut count[e as usize];
            ci[*c as usize] = v;
            *c += 1;
        }
    }
    ptr
}

/// The grid's cell size when the tables are made (at the start, and again when faces join or
/// erode): [`CELL_FRACTION`] of the 90th percentile D of the faces' search-sphere diameters
/// `2 (E r + depth)` (penalty.rs WEIGHT_SUM E, r the largest centre-corner distance), so that a
/// face up to 1.4 D across, its sphere grown by the lists' margin included, spans at most three
/// cells a side, and the few largest (a thick plate's faces, whose depth 0.4 V/A reaches far)
/// go to the list every node reads, rather than making every cell hold many small faces; 1 when
/// no face has a finite positive one. On the 2800-element ball on its plate, the largest
/// diameter (as the cell size) made the node checks 77% of a step on lavapipe. `d`: work array.
fn cell_size(solver: &Solver, face_nodes: &[u32], depth: &[f64], d: &mut Vec<f64>) -> f64 {
    let x = solver.positions();
    d.clear();
    d.extend(
        (face_nodes.chunks_exact(4).zip(depth))
            .map(|(f, depth)| {
                let p: [[f64; 3]; 4] = std::array::from_fn(|a| x[f[a] as usize]);
                let c: [f64; 3] =
                    std::array::from_fn(|k| 0.25 * (p[0][k] + p[1][k] + p[2][k] + p[3][k]));
                let r = (p.iter())
                    .map(|q| (0..3).map(|k| (q[k] - c[k]).powi(2)).sum::<f64>().sqrt())
                    .fold(0.0, f64::max);
                2.0 * (cleave_core::contact::penalty::WEIGHT_SUM * r + depth)
            })
            .filter(|s| s.is_finite() && *s > 0.0),
    );
    if d.is_empty() {
        return 1.0;
    }
    let k = (d.len() - 1) * 9 / 10;
    CELL_FRACTION * *d.select_nth_unstable_by(k, f64::total_cmp).1
}

/// The grid's cell as a fraction of the 90th percentile of the faces' search-sphere diameters
/// ([`cell_size`]). Smaller cells hold fewer faces for a node to test, but past half the
/// percentile more faces span more than three cells and go to the list every node reads. On
/// lavapipe's machine, `cleave bench ball --elements 2800 --end-time 2e-5 --gpu --passes`, the
/// device's time a step breaking: 30.4 and 30.7 ms at 1, 28.9 at 0.8, 27.7 and 28.5 at 0.7,
/// 26.8 and 27.0 at 0.6, 28.4 at 0.55, 36.9 at 0.5; unbroken (`--no-separation`): 4.96 and
/// 5.13 ms at 1, 4.98 at 0.7, 5.08 at 0.6. 0.7 leaves room for faces that stretch (a uniform
/// mesh's grown spheres span 1.7 cells).
const CELL_FRACTION: f64 = 0.7;

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
/// `s`: the work arrays.
pub(crate) fn carry_pairs(
    old: &Tables,
    t: &Tables,
    (hits, fprev, born): Carry,
    h: &mut [f64],
    fp: &mut [f64],
    s: &mut Scratch,
) -> Vec<u32> {
    // each node of the sides before: the pass-node whose set it was in, by pass
    let nn = t.param("C_NN");
    let passes = (old.pn_key.iter())
        .map(|&(q, _)| q as usize + 1)
        .max()
        .unwrap_or(0);
    if s.member_of.len() < passes * nn {
        s.member_of.resize(passes * nn, NONE);
    }
    let key = |q: u32, m: u32| q as usize * nn + m as usize;
    for (j, &(q, _)) in old.pn_key.iter().enumerate() {
        for &m in old.members_of(j) {
            s.member_of[key(q, m)] = j as u32;
        }
    }
    let mut faces = FaceMap::new(old, t);
    for (jn, &(q, _)) in t.pn_key.iter().enumerate() {
        // a lead carries on its set's contact: that of the lead before of its first
        // member (along the chain) that was on the side (mod.rs Contact::regroup_where)
        let member_of = &s.member_of;
        let Some(j) = t.members_of(jn).iter().find_map(|&m| {
            let known = (q as usize) < passes && (m as usize) < nn;
            let j = if known { member_of[key(q, m)] } else { NONE };
            (j != NONE).then_some(j as usize)
        }) else {
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
        if let Some(f) = faces.now(o[0] as usize) {
            dst.copy_from_slice(o);
            dst[0] = f64::from(f);
        }
    }
    for (j, &(q, _)) in old.pn_key.iter().enumerate() {
        for &m in old.members_of(j) {
            s.member_of[key(q, m)] = NONE;
        }
    }
    // the surface entries, ascending in both tables: a merge
    let mut left = vec![];
    let mut gn = 0;
    for (g, &n) in old.surface.iter().enumerate() {
        let Some(f) = fprev.get(3 * g..3 * g + 3) else {
            continue;
        };
        while gn < t.surface.len() && t.surface[gn] < n {
            gn += 1;
        }
        if t.surface.get(gn) == Some(&n) {
            fp[3 * gn..3 * gn + 3].copy_from_slice(f);
            continue;
        }
        left.push(n);
        // the slots born of it (and of those, in this step), in order: the first on the surface
        let mut family = vec![n];
        let mut k = 0;
        while k < family.len() {
            let from = family[k];
            family.extend(born.iter().filter(|b| b.1 == from).map(|b| b.0));
            k += 1;
        }
        if let Some(at) = (family.iter()).find_map(|e| t.surface.binary_search(e).ok()) {
            for i in 0..3 {
                fp[3 * at + i] += f[i];
            }
        }
    }
    left
}

/// The faces of tables `old` in the numbering of tables `new`, by what they are. A side's
/// faces only join its end (an eroded face keeps its place, with no stiffness and depth), so a
/// face keeps its place in its side: that place is tried first, and a map by what the faces
/// are is made only when it misses (tables whose sides were made otherwise: none today, kept
/// so that such a change stays correct).
struct FaceMap<'a> {
    old: &'a Tables,
    new: &'a Tables,
    map: Option<HashMap<(u32, u32, u32, u8), u32>>,
}

impl<'a> FaceMap<'a> {
    fn new(old: &'a Tables, new: &'a Tables) -> Self {
        FaceMap {
            old,
            new,
            map: None,
        }
    }

    /// Face `f` of the old tables in the new ones; `None` when it left the surface.
    fn now(&mut self, f: usize) -> Option<u32> {
        let key = *self.old.face_key.get(f)?;
        let side = self
            .old
            .sides
            .partition_point(|s| s.2 as usize <= f)
            .checked_sub(1)?;
        let (d, sd, first) = self.old.sides[side];
        if let Some(&(dn, sdn, first_new)) = self.new.sides.get(side) {
            let at = first_new as usize + (f - first as usize);
            if (dn, sdn) == (d, sd) && self.new.face_key.get(at) == Some(&key) {
                return Some(at as u32);
            }
        }
        let new = self.new;
        let map = self.map.get_or_insert_with(|| {
            (new.face_key.iter().enumerate())
                .map(|(f, &k)| (k, f as u32))
                .collect()
        });
        map.get(&key).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tables of one pass whose node side holds `sets` (each a lead and its other members,
    /// along the chain), with faces `faces` (element numbers) and surface entries `surface`.
    fn pass_tables(sets: &[&[u32]], faces: &[u32], surface: &[u32]) -> Tables {
        let mut ci = vec![0; PARAMS.len()];
        ci[0] = 100; // C_NN
        let mut t = Tables {
            ci,
            sides: vec![(0, 0, 0)],
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
        let mut s = Scratch::default();
        let (mut h, mut fp) = new.no_pairs();
        let born = [(8, 7), (9, 8)];
        let left = carry_pairs(&old, &new, (&hits, &fprev, &born), &mut h, &mut fp, &mut s);
        // 10 and 12 carry lead 10's pair on element 200's face, now face 0; 16 carries 15's
        let want = [hit(0.0, 5.0), hit(0.0, 5.0), hit(1.0, 6.0)].concat();
        assert_eq!(h, want);
        assert_eq!(fp, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(left, vec![7]);
        // without the born slots, the force of entry 7 has no heir
        let (mut h, mut fp) = new.no_pairs();
        carry_pairs(&old, &new, (&hits, &fprev, &[]), &mut h, &mut fp, &mut s);
        assert_eq!(fp, vec![1.0, 2.0, 3.0, 0.0, 0.0, 0.0]);
    }

    /// A face keeps its place in its side when faces join its end, and the pair on it is
    /// carried there; a pair whose face left (a side made again without it) starts from none.
    #[test]
    fn a_pair_keeps_its_face_when_faces_join_the_side() {
        let old = pass_tables(&[&[10], &[11]], &[100, 200], &[3]);
        let new = pass_tables(&[&[10], &[11]], &[100, 200, 300], &[3]);
        let hits = [hit(1.0, 5.0), hit(0.0, 6.0)].concat();
        let (mut h, mut fp) = new.no_pairs();
        let mut s = Scratch::default();
        carry_pairs(&old, &new, (&hits, &[0.0; 3], &[]), &mut h, &mut fp, &mut s);
        assert_eq!(h, hits);
        let gone = pass_tables(&[&[10], &[11]], &[100], &[3]);
        let (mut h, mut fp) = gone.no_pairs();
        carry_pairs(
            &old,
            &gone,
            (&hits, &[0.0; 3], &[]),
            &mut h,
            &mut fp,
            &mut s,
        );
        assert_eq!(
            h,
            [gone.no_pairs().0[..HIT].to_vec(), hit(0.0, 6.0)].concat()
        );
    }

    /// Tables made in the arrays of earlier ones, with the work arrays of every call before,
    /// are those made afresh, array for array: the cracking block (its interfaces failing over
    /// the run, their faces joining its single surface contact) after every step in which an
    /// interface failed.
    #[test]
    fn tables_made_in_used_arrays_are_those_made_afresh() {
        use cleave_core::contact::ContactSet;
        use cleave_core::model::ContactDef;
        use cleave_core::separation::interfaces::Separation;
        use cleave_core::separation::split::split_model;
        let mut m = crate::relayout::tests::cracking_block();
        m.contacts.push(ContactDef::single_surface_all(0.1, 0.1));
        let split = split_model(&m);
        let mut s = Solver::new(&split.model).unwrap();
        s.attach_separation(Separation::new(&split).unwrap());
        s.attach_contact(ContactSet::new(&split.model, Some(&split.origin)).unwrap());
        s.settle_contact(false);
        let mut scratch = Scratch::default();
        let (mut now, mut spare) = (Tables::default(), Tables::default());
        let (mut failed, mut compared, faces_at_start) = (0, 0, tables_afresh(&s).faces);
        while !s.is_finished() {
            s.advance_to_half_step().unwrap();
            let f = s.separation().unwrap().num_failed();
            if f != failed {
                failed = f;
                s.settle_contact(true);
                let t = tables(&s, &mut scratch, spare).unwrap();
                let want = tables_afresh(&s);
                assert_eq!(t.ci, want.ci);
                assert_eq!(t.cfl, want.cfl);
                assert_eq!((&t.pn_def, &t.pn_key), (&want.pn_def, &want.pn_key));
                assert_eq!((&t.face_key, &t.sides), (&want.face_key, &want.sides));
                assert_eq!(
                    (&t.members, &t.members_at),
                    (&want.members, &want.members_at)
                );
                assert_eq!((&t.surface, &t.closures), (&want.surface, &want.closures));
                assert_eq!((&t.clo, t.grid_len), (&want.clo, want.grid_len));
                spare = std::mem::replace(&mut now, t);
                compared += 1;
            }
            s.update_positions().unwrap();
        }
        let faces = now.faces;
        eprintln!(
            "{failed} failed, {compared} tables compared, {faces} faces from {faces_at_start}"
        );
        assert!(compared >= 5 && now.faces > faces_at_start);
    }

    fn tables_afresh(s: &Solver) -> Tables {
        tables(s, &mut Scratch::default(), Tables::default()).unwrap()
    }
}
