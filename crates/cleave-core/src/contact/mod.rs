//! Automatic contact: `*CONTACT_AUTOMATIC_SINGLE_SURFACE` and
//! `*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE`, symmetric node-to-face penalty contact between the
//! exterior faces of hexahedral parts (deformable or rigid), with Coulomb friction, after the
//! LS-DYNA theory manual (penalty method, SOFT = 0; friction).
//!
//! - [`surface`]: exterior faces, the faces of each side, penalty stiffness `k = SLSFAC K A^2/V`.
//! - [`search`]: the bucket grid that finds each node's candidate faces.
//! - [`penalty`]: closest point on a bilinear face, gap, normal force and its reaction.
//! - [`friction`]: `mu = FD + (FS - FD) exp(-DC |v_rel|)`, elastic trial force capped at
//!   `mu |f_n|`.
//!
//! # Sides and passes
//! A definition has one side (single surface) or two (surface to surface, slave and master).
//! Each step runs *passes* of node-to-face checks: single surface, the nodes of the surface
//! against its own faces; surface to surface, the slave nodes against the master faces, then
//! the master nodes against the slave faces (symmetric, as LS-DYNA's automatic contacts).
//! A node is never checked against a face that holds it or holds a node tied to it (the
//! coincident copies of a split model: `tie[a] == tie[b] != u32::MAX`): such faces are left out
//! of its candidate list when the list is made. Faces of separation groups join the surfaces
//! when their interface fails ([`ContactSet::activate`]).
//!
//! # Contact of a node with a face
//! The node `s` projects on the face at `x_c` with normal `n` ([`penalty::project`]); it is in
//! contact when the projection is on the face and `-depth < g = (s - x_c).n < -GAP_TOL r`, with
//! `depth = 0.4 V/A` of the face's element ([`surface::DEPTH_FRACTION`]) and r the face's
//! radius. When it penetrates several faces it takes the one it penetrates *least* (the
//! nearest surface point, the closest-point rule): a node near the edge of a block penetrates
//! the block's top by g and its side by about its distance to the side; taking the deepest
//! would push it out sideways. Gaps within `GAP_TOL r` of zero (a node on the plane of a
//! coplanar side face, or the two faces of a crack at the moment it opens) are not contact, so
//! round-off there cannot mask a real penetration. Far-side faces are excluded by the depth.
//!
//! Orientation: a node contacts a face only when its own surface faces it, `n_s . n < -FACING`
//! with n_s the node's normal (the normalised sum of the area-weighted normals of the node's
//! faces on its side) and n the face's. A node on the flat top of a plate, under a block
//! sliding over it, lies within the depth of the block's leading face and projects onto it;
//! the block's bottom, which it really touches, does not hold it when the block lifts by a
//! few nanometres (a penalty spring vibrating), so without this test the leading face would
//! push the block back. The same geometry, an edge node just beside a face of the other
//! body, arises when two flush blocks meet face to face, and there it must be contact: the
//! two cases differ only in the node's surface (plate top: perpendicular to the leading face;
//! a block's front edge: facing the other block), hence the test on the node's normal. Edge
//! and corner nodes (n_s . n = -0.71, -0.58 against a face square to one of their faces) pass.
//!
//! Forces: normal `f_n = -k g n` on the node, plus friction `f_t` ([`friction`]); the face's
//! nodes get `-N_a(xi, eta) (f_n + f_t)`, N_a the bilinear shape functions at the contact point.
//! k is the stiffness of the face (LS-DYNA: the master segment's).
//!
//! Before projecting, a node is tested against cheap exact bounds of the face
//! ([`penalty::FaceBounds`]: sphere, mean-plane slab, lateral distance, node on a corner), which
//! reject nearly all candidates; the bounds are updated each step only for faces that are some
//! node's candidate.
//!
//! # Search
//! Candidate faces of each node come from a bucket grid ([`search`]) over face boxes inflated by
//! `depth + 4 INSIDE_TOL r + 1.1 margin`, built from the positions x_ref of that moment (a *full
//! build*). They are reused until some node of the definition has moved more than `margin / 2`
//! from x_ref: until then a node and a face it may touch have each moved less than margin/2,
//! so the node's x_ref is still in the face's box (the 1.1 covers the tolerance band growing
//! with the face). `margin` = [`MARGIN_FRACTION`] times the mean sqrt(area) of the definition's
//! faces.
//!
//! When interfaces fail ([`ContactSet::activate`]), the search is incremental: the new faces get
//! boxes from x_ref, a small grid holds them and the nodes that joined, and only the nodes whose
//! x_ref lies in a failed face's box get new lists (a broken tie or a new face only changes the
//! lists of the nodes at its corners or within its box). The lists are then what a full build
//! at x_ref with the new faces and ties would give, and stay valid under the same margin rule
//! (new nodes are watched from x_ref on). When the faces or nodes that joined since the last
//! full build exceed a quarter of those in it, a full build is made instead.
//!
//! # Energy
//! The contact energy increment of a step is the trapezoid of the work of the contact forces:
//! `dE = -1/2 sum_i (f_i^(n-1) + f_i^n) . (x_i^n - x_i^(n-1))`, with
//! `x^n - x^(n-1) = v^(n-1/2) dt^(n-1/2)`. It holds both the elastic energy of the penalty
//! springs and the frictional dissipation (both positive).
//!
//! # Determinism
//! The per-node contact detection runs in parallel, but each node's result lands in its own slot;
//! the forces are then scattered serially in a fixed order (definitions, passes, nodes). The
//! results are bit-identical for any number of threads. After the first steps no buffer grows
//! unless faces are added or the candidate lists get longer.
//!
//! # Cost (measured, 2 threads)
//! A 2800-element ball split into 8-node copies (4600 elements with a 1800-element rigid plate,
//! 25283 nodes), single surface over everything, against the solver's step of about 0.5 ms:
//! with only the exterior faces, contact takes 6-10% of the step (4442 nodes, 1328 candidate
//! pairs); after a random 10% of the interfaces failed (faces joined, ties broken) 40-50%
//! (36k candidates), at 30% about twice the step (220k candidates): coincident crack faces
//! give every crack node several zero-clearance candidates, tested each step (about 5 ns each,
//! nearly all rejected by the bounds). With 5 interfaces failing every step (1000 over 200
//! steps, 196 incremental searches, 5 full builds) the mean was 87%.

pub mod engagement;
pub mod friction;
pub mod penalty;
pub mod search;
pub mod surface;

use std::collections::HashSet;

use rayon::prelude::*;

use crate::math::{add, cross, dot, norm, scale, sub, Vec3};
use crate::model::{ContactDef, Model};
use engagement::{engage, Previous};
use friction::{tangential_force, Friction};
use penalty::{normal_force, off_corners, project, FaceBounds, Projection, INSIDE_TOL};
use search::{Aabb, BucketGrid};
use surface::{covered_parts, exterior_faces, face_nodes, side_faces, FaceId, FaceTable};

const NONE: u32 = u32::MAX;

/// Search margin as a fraction of the mean face size sqrt(A): candidates are rebuilt when a
/// node has moved more than half of it.
pub const MARGIN_FRACTION: f64 = 0.3;

/// Gaps above `-GAP_TOL r` (r the face's radius) are not contact (see the module docs).
pub const GAP_TOL: f64 = 1e-9;

/// A node contacts a face only if its surface faces the face: `n_s . n < -FACING`, n_s the
/// node's normal (the mean of its faces' normals), n the face's (an angle over 101.5 degrees).
pub const FACING: f64 = 0.2;

/// Nodes per parallel task of the detection.
const NODE_CHUNK: usize = 256;

/// A face of a contact surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    pub elem: u32,
    /// Local face number, [`crate::element::hex8::FACES`] order.
    pub face: u8,
    /// Solved nodes, outward order.
    pub nodes: [u32; 4],
    /// Penalty stiffness `SLSFAC K A^2 / V` (reference geometry).
    pub k: f64,
    /// Largest penetration counted as contact, `0.4 V / A`.
    pub depth: f64,
}

/// Resultants of one definition over the last step (for rcforc.csv).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactForce {
    /// Deck ordinal of the definition.
    pub id: i64,
    /// Surface to surface: the force of the contact on the slave side's nodes (the slave
    /// nodes' own forces plus the reactions on the slave faces). Single surface: the sum of the
    /// forces on the penetrating nodes (their reactions, the rest of the total that is zero,
    /// left out); for two bodies touching, the two directions of the symmetric treatment
    /// largely cancel here, so use `normal` for the magnitude.
    pub force: Vec3,
    /// Sum of |f_n| over the contact pairs: the total normal force across the interface.
    pub normal: f64,
    /// Number of node-face pairs in contact.
    pub pairs: usize,
}

/// What a call of [`ContactSet::compute`] reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactStep {
    /// Contact energy increment of the step (add to `Energies::contact`).
    pub energy: f64,
    /// Node-face pairs in contact, all definitions.
    pub pairs: usize,
    /// Whether some definition rebuilt its candidate lists this step.
    pub rebuilt: bool,
}

/// Search statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactStats {
    /// Faces over all sides of all definitions.
    pub faces: usize,
    /// Node checks per step (nodes over all passes).
    pub nodes: usize,
    /// Candidate node-face pairs of the current lists.
    pub candidates: usize,
    /// Full candidate-list builds so far.
    pub rebuilds: u64,
    /// Incremental searches around activated faces so far.
    pub updates: u64,
}

/// All contact definitions of a model, with the scratch they share.
#[derive(Clone, Debug)]
pub struct ContactSet {
    contacts: Vec<Contact>,
    conn: Vec<[u32; 8]>,
    elem_part: Vec<u32>,
    table: FaceTable,
    cur: NodalForces,
    prev: NodalForces,
    forces: Vec<ContactForce>,
}

impl ContactSet {
    /// The contact definitions of `model`, the model the solver runs (split or not).
    ///
    /// `origin[i]` is the deck node of solved node i for a split model
    /// (`SplitModel::origin`), `None` when the model is not split. Exterior faces are found on
    /// the deck connectivity (`origin` applied to `model.conn`), so the faces between the
    /// elements of a separation group are not surfaces until [`ContactSet::activate`] adds
    /// them; their nodes are the solved nodes of `model.conn`.
    ///
    /// Errors: a segment of a segment set that is no element face, a surface-to-surface
    /// definition without a master side.
    pub fn new(model: &Model, origin: Option<&[u32]>) -> Result<Self, String> {
        let conn = model.conn.clone();
        let deck_conn: Vec<[u32; 8]> = match origin {
            Some(o) => conn.iter().map(|c| c.map(|n| o[n as usize])).collect(),
            None => conn.clone(),
        };
        let exterior = if model.contacts.is_empty() {
            Vec::new()
        } else {
            exterior_faces(&deck_conn, |_| true)
        };
        let table = FaceTable::new(model);
        let mut contacts = Vec::with_capacity(model.contacts.len());
        for def in &model.contacts {
            let ctx = Build {
                model,
                deck_conn: &deck_conn,
                origin,
                exterior: &exterior,
                table: &table,
            };
            contacts.push(Contact::new(def, &ctx)?);
        }
        let nn = model.num_nodes();
        let forces = contacts
            .iter()
            .map(|c| ContactForce {
                id: c.id,
                ..Default::default()
            })
            .collect();
        Ok(Self {
            contacts,
            conn,
            elem_part: model.elem_part.clone(),
            table,
            cur: NodalForces::new(nn),
            prev: NodalForces::new(nn),
            forces,
        })
    }

    /// True when the model has no contact definition.
    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }

    /// The definitions, in deck order.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// Interfaces failed: add their faces to every side that covers the faces' parts (single
    /// surface or either side of a surface-to-surface definition named by parts, part sets or
    /// all parts; segment-set sides take nothing), and search again around them at the next
    /// `compute`.
    ///
    /// Call it with the two faces, `(element, local face)`, of *every* interface that fails
    /// (`SharedFace::elems` / `faces`), whether or not a contact covers it, in the step its
    /// ties break and before the next `compute`: the candidate lists leave out faces tied to
    /// the node, so they must be renewed wherever a tie breaks. Only the nodes near these
    /// faces are searched again (incremental); after many activations a full build is made.
    /// Faces already present are skipped; returns how many face-side memberships were added.
    pub fn activate(&mut self, faces: &[FaceId]) -> usize {
        let mut added = 0;
        for c in &mut self.contacts {
            added += c.activate(faces, &self.elem_part, &self.conn, &self.table);
        }
        added
    }

    /// Ties changed in some other way than by failed interfaces named to
    /// [`ContactSet::activate`]: rebuild all candidate lists at the next `compute`.
    pub fn ties_changed(&mut self) {
        for c in &mut self.contacts {
            c.dirty = true;
        }
    }

    /// Contact forces at t^n, added into `f`.
    ///
    /// - `x`: positions x^n; `v`: velocities v^(n-1/2) (before this step's velocity update);
    /// - `dt_prev`: dt^(n-1/2) = t^n - t^(n-1) (0 at the first step), so the increment over the
    ///   last step is `v dt_prev`: the tangential slip for friction and the displacement for
    ///   the energy;
    /// - `tie[i]`: coincident set of node i, or `u32::MAX`; an empty slice means no ties;
    /// - `f`: nodal forces, to which the contact forces are added.
    ///
    /// Call it after assembling the element forces and before tying the coincident sets (so a
    /// set shares the contact force of any of its members), and before the rigid bodies
    /// gather their nodes' forces.
    pub fn compute(
        &mut self,
        x: &[Vec3],
        v: &[Vec3],
        dt_prev: f64,
        tie: &[u32],
        f: &mut [Vec3],
    ) -> ContactStep {
        let nn = self.cur.f.len();
        assert!(x.len() == nn && v.len() == nn && f.len() == nn);
        assert!(tie.is_empty() || tie.len() == nn);
        std::mem::swap(&mut self.cur, &mut self.prev);
        self.cur.clear();
        let mut step = ContactStep::default();
        let inp = StepInput {
            x,
            v,
            dt_prev,
            tie,
            conn: &self.conn,
            table: &self.table,
        };
        for (c, out) in self.contacts.iter_mut().zip(self.forces.iter_mut()) {
            let rebuilt;
            (*out, rebuilt) = c.compute(&inp, &mut self.cur);
            step.pairs += out.pairs;
            step.rebuilt |= rebuilt;
        }
        // NOTE: fixed order: last step's nodes, then this step's, each in insertion order.
        let mut work = 0.0;
        for &i in &self.prev.touched {
            work += dot(self.prev.f[i as usize], v[i as usize]);
        }
        for &i in &self.cur.touched {
            let i = i as usize;
            work += dot(self.cur.f[i], v[i]);
            f[i] = add(f[i], self.cur.f[i]);
        }
        step.energy = -0.5 * dt_prev * work;
        step
    }

    /// Resultants of each definition over the last `compute`, in deck order.
    pub fn forces(&self) -> &[ContactForce] {
        &self.forces
    }

    /// The contact force on each node of the last `compute` (nodes in first-touched order).
    pub fn nodal_forces(&self) -> impl Iterator<Item = (u32, Vec3)> + '_ {
        self.cur
            .touched
            .iter()
            .map(|&i| (i, self.cur.f[i as usize]))
    }

    /// A time step the penalty springs are stable with, to compare with the element step.
    ///
    /// For each pass, `dt = sqrt(m_min / k_max)`: m_min the smallest nodal mass among the
    /// pass's nodes and face nodes, k_max the stiffest face. Derivation: a node of mass m in
    /// contact is held by its own penalty spring k and, in the symmetric pass, by the spring of
    /// the node that penetrates it; two such masses joined by 2k vibrate at
    /// `omega^2 = 2k (1/m + 1/m) = 4k/m`, and central differences need `dt <= 2/omega`.
    /// Infinite when there is no face. `mass` is the mass each node has against a spring: the
    /// solver gives a rigid body's nodes the body's mass.
    pub fn stable_dt(&self, mass: &[f64]) -> f64 {
        self.contacts
            .iter()
            .map(|c| c.stable_dt(mass))
            .fold(f64::INFINITY, f64::min)
    }

    /// Search statistics, all definitions.
    pub fn stats(&self) -> ContactStats {
        let mut s = ContactStats::default();
        for c in &self.contacts {
            s.faces += c.sides.iter().map(|sd| sd.faces.len()).sum::<usize>();
            s.nodes += c.passes.iter().map(|p| p.hits.len()).sum::<usize>();
            s.candidates += c
                .passes
                .iter()
                .flat_map(|p| &p.cand)
                .map(Vec::len)
                .sum::<usize>();
            s.rebuilds += c.rebuilds;
            s.updates += c.updates;
        }
        s
    }
}

/// Sparse nodal forces: a dense array, and the nodes touched since the last clear.
#[derive(Clone, Debug)]
struct NodalForces {
    f: Vec<Vec3>,
    touched: Vec<u32>,
    mark: Vec<bool>,
}

impl NodalForces {
    fn new(n: usize) -> Self {
        Self {
            f: vec![[0.0; 3]; n],
            touched: Vec::new(),
            mark: vec![false; n],
        }
    }
    #[inline]
    fn add(&mut self, i: u32, g: Vec3) {
        let k = i as usize;
        if !self.mark[k] {
            self.mark[k] = true;
            self.touched.push(i);
        }
        self.f[k] = add(self.f[k], g);
    }
    fn clear(&mut self) {
        for &i in &self.touched {
            self.f[i as usize] = [0.0; 3];
            self.mark[i as usize] = false;
        }
        self.touched.clear();
    }
}

/// What a build of the definitions reads.
struct Build<'a> {
    model: &'a Model,
    deck_conn: &'a [[u32; 8]],
    origin: Option<&'a [u32]>,
    exterior: &'a [FaceId],
    table: &'a FaceTable,
}

/// What a step reads.
struct StepInput<'a> {
    x: &'a [Vec3],
    v: &'a [Vec3],
    dt_prev: f64,
    tie: &'a [u32],
    conn: &'a [[u32; 8]],
    table: &'a FaceTable,
}

/// One side of a definition: its faces and their nodes.
#[derive(Clone, Debug)]
struct Side {
    faces: Vec<Face>,
    present: HashSet<FaceId>,
    /// Parts whose failed interfaces add faces to this side.
    parts: Vec<bool>,
    /// Nodes of the faces: ascending at the start, then in the order their faces joined.
    nodes: Vec<u32>,
    /// Index of each model node in `nodes`, or NONE.
    local: Vec<u32>,
    /// The faces of each node of `nodes` (indices into `faces`).
    node_faces: Vec<Vec<u32>>,
    /// Search box of each face, from the positions of the last full build.
    boxes: Vec<Aabb>,
    /// Faces `..base` are in the passes' main grids; later ones joined since the last full
    /// build. Faces `..boxed` have their box.
    base: usize,
    boxed: usize,
    /// Whether the face is some node's candidate: only those get their bounds each step.
    needed: Vec<bool>,
    /// Bounds of each needed face at the current positions.
    geo: Vec<FaceGeo>,
}

/// What the check of a node against a face reads first, in one place: the face's bounds at the
/// current positions and its depth limit.
#[derive(Clone, Copy, Debug, Default)]
struct FaceGeo {
    b: FaceBounds,
    depth: f64,
}

impl Side {
    fn new(
        ids: &[FaceId],
        parts: Vec<bool>,
        conn: &[[u32; 8]],
        table: &FaceTable,
        num_nodes: usize,
    ) -> Self {
        let mut s = Self {
            faces: Vec::with_capacity(ids.len()),
            present: HashSet::with_capacity(ids.len()),
            parts,
            nodes: Vec::new(),
            local: vec![NONE; num_nodes],
            node_faces: Vec::new(),
            boxes: Vec::new(),
            base: 0,
            boxed: 0,
            needed: Vec::new(),
            geo: Vec::new(),
        };
        for &id in ids {
            s.add(id, conn, table);
        }
        s.nodes.sort_unstable();
        for (i, &n) in s.nodes.iter().enumerate() {
            s.local[n as usize] = i as u32;
        }
        s.node_faces = vec![Vec::new(); s.nodes.len()];
        for f in 0..s.faces.len() {
            s.link(f);
        }
        s
    }

    /// Record face `f` as a face of each of its nodes.
    fn link(&mut self, f: usize) {
        self.node_faces.resize_with(self.nodes.len(), Vec::new);
        for n in self.faces[f].nodes {
            self.node_faces[self.local[n as usize] as usize].push(f as u32);
        }
    }

    /// Add a face unless present (its new nodes are appended to `nodes`); true when added.
    fn add(&mut self, id: FaceId, conn: &[[u32; 8]], table: &FaceTable) -> bool {
        if !self.present.insert(id) {
            return false;
        }
        let nodes = face_nodes(&conn[id.0 as usize], id.1);
        self.faces.push(Face {
            elem: id.0,
            face: id.1,
            nodes,
            k: table.stiffness(id),
            depth: table.depth(id),
        });
        self.boxes.push(Aabb {
            min: [0.0; 3],
            max: [0.0; 3],
        });
        self.needed.push(false);
        self.geo.push(FaceGeo::default());
        for n in nodes {
            if self.local[n as usize] == NONE {
                self.local[n as usize] = self.nodes.len() as u32;
                self.nodes.push(n);
            }
        }
        self.link(self.faces.len() - 1);
        true
    }

    /// Boxes of the faces that have none yet, from positions `x_ref`.
    fn box_new_faces(&mut self, x_ref: &[Vec3], margin: f64) {
        for f in self.boxed..self.faces.len() {
            self.boxes[f] = search_box(&self.faces[f], x_ref, margin);
        }
        self.boxed = self.faces.len();
    }

    /// Bounds of the needed faces at the current positions.
    fn update_geometry(&mut self, x: &[Vec3]) {
        let (faces, needed) = (&self.faces, &self.needed);
        self.geo
            .par_iter_mut()
            .enumerate()
            .with_min_len(4 * NODE_CHUNK)
            .for_each(|(f, g)| {
                if needed[f] {
                    let face = &faces[f];
                    g.b = FaceBounds::new(&face.nodes.map(|n| x[n as usize]));
                    g.depth = face.depth;
                }
            });
    }
}

/// The search box of a face at positions `x`: its corners' box grown by
/// `depth + 4 INSIDE_TOL r + 1.1 margin` (module docs).
fn search_box(face: &Face, x: &[Vec3], margin: f64) -> Aabb {
    let p = face.nodes.map(|n| x[n as usize]);
    let c = scale(add(add(p[0], p[1]), add(p[2], p[3])), 0.25);
    let r = p.iter().map(|q| dist2(*q, c)).fold(0.0, f64::max).sqrt();
    Aabb::of_points(&p).inflated(face.depth + 4.0 * INSIDE_TOL * r + 1.1 * margin)
}

/// The result of one node's check.
#[derive(Clone, Copy, Debug)]
struct Hit {
    /// Face index in the face side, or NONE.
    face: u32,
    w: [f64; 4],
    /// Total force on the node (normal + friction).
    f: Vec3,
    /// |f_n|.
    fn_mag: f64,
    /// Stiffness of the face, engaged penetration and offset ([`engagement`]).
    k: f64,
    engaged: f64,
    offset: f64,
}

impl Default for Hit {
    fn default() -> Self {
        Self {
            face: NONE,
            w: [0.0; 4],
            f: [0.0; 3],
            fn_mag: 0.0,
            k: 0.0,
            engaged: 0.0,
            offset: 0.0,
        }
    }
}

/// The nodes of one side against the faces of one side.
#[derive(Clone, Debug)]
struct Pass {
    node_side: usize,
    face_side: usize,
    /// The face side's faces `..base` and the node side's nodes `..nbase`, at the last full
    /// build.
    grid: BucketGrid,
    nbase: usize,
    /// The faces and nodes that joined since (indices relative to `base` and `nbase`).
    extra: BucketGrid,
    /// Candidate faces of each node of the node side, ascending.
    cand: Vec<Vec<u32>>,
    /// Tangential force of the last step, per node of the node side.
    ft: Vec<Vec3>,
    hits: Vec<Hit>,
}

impl Pass {
    fn new(node_side: usize, face_side: usize, nodes: usize) -> Self {
        Self {
            node_side,
            face_side,
            grid: BucketGrid::default(),
            nbase: 0,
            extra: BucketGrid::default(),
            cand: vec![Vec::new(); nodes],
            ft: vec![[0.0; 3]; nodes],
            hits: vec![Hit::default(); nodes],
        }
    }

    /// Node i's candidates from the grids: faces whose box (built from `x_ref`) holds the node's
    /// `x_ref` position and that hold neither the node nor a node tied to it.
    fn query(&mut self, i: usize, ns: &Side, fs: &Side, x_ref: &[Vec3], tie: &[u32]) {
        let s = ns.nodes[i];
        let p = x_ref[s as usize];
        let keep = |f: u32| !fs.faces[f as usize].nodes.iter().any(|&a| tied(s, a, tie));
        let list = &mut self.cand[i];
        list.clear();
        self.grid.faces_at(p, &fs.boxes, keep, list);
        let start = list.len();
        let extra = &fs.boxes[fs.base..];
        self.extra
            .faces_at(p, extra, |f| keep(f + fs.base as u32), list);
        for f in &mut list[start..] {
            *f += fs.base as u32;
        }
    }
}

/// One contact definition.
#[derive(Clone, Debug)]
pub struct Contact {
    /// Deck ordinal.
    pub id: i64,
    pub single_surface: bool,
    pub friction: Friction,
    sides: Vec<Side>,
    passes: Vec<Pass>,
    /// Positions of all model nodes at the last full build.
    x_ref: Vec<Vec3>,
    margin: f64,
    /// A full build is due (first step, ties changed without faces named).
    dirty: bool,
    /// Faces of interfaces that failed since the last step: the nodes near them get new
    /// candidate lists at the next step.
    pending: Vec<FaceId>,
    points: Vec<Vec3>,
    scratch: Vec<u32>,
    region: Vec<Aabb>,
    rebuilds: u64,
    updates: u64,
}

impl Contact {
    fn new(def: &ContactDef, b: &Build) -> Result<Self, String> {
        let nn = b.model.num_nodes();
        let side = |s| -> Result<Side, String> {
            let ids = side_faces(b.model, b.deck_conn, b.origin, b.exterior, s)?;
            Ok(Side::new(
                &ids,
                covered_parts(b.model, s),
                &b.model.conn,
                b.table,
                nn,
            ))
        };
        let mut sides = vec![side(&def.slave)?];
        if !def.single_surface {
            let master = def.master.as_ref().ok_or_else(|| {
                format!("contact {}: surface to surface needs a master side", def.id)
            })?;
            sides.push(side(master)?);
        }
        let pairs: &[(usize, usize)] = if def.single_surface {
            &[(0, 0)]
        } else {
            &[(0, 1), (1, 0)]
        };
        let passes = pairs
            .iter()
            .map(|&(ns, fs)| Pass::new(ns, fs, sides[ns].nodes.len()))
            .collect();
        let (mut sum, mut count) = (0.0, 0usize);
        for s in &sides {
            for f in &s.faces {
                let p = f.nodes.map(|n| b.model.x0[n as usize]);
                sum += crate::element::hex8::quad_area(p[0], p[1], p[2], p[3]).sqrt();
                count += 1;
            }
        }
        let size = if count > 0 {
            sum / count as f64
        } else {
            b.table.mean_size
        };
        Ok(Self {
            id: def.id,
            single_surface: def.single_surface,
            friction: Friction {
                fs: def.fs,
                fd: def.fd,
                dc: def.dc,
            },
            sides,
            passes,
            x_ref: vec![[0.0; 3]; nn],
            margin: MARGIN_FRACTION * size,
            dirty: true,
            pending: Vec::new(),
            points: Vec::new(),
            scratch: Vec::new(),
            region: Vec::new(),
            rebuilds: 0,
            updates: 0,
        })
    }

    /// The faces of side 0 (slave, or the single surface) or 1 (master).
    pub fn faces(&self, side: usize) -> &[Face] {
        &self.sides[side].faces
    }

    /// Number of sides: 1 single surface, 2 surface to surface.
    pub fn num_sides(&self) -> usize {
        self.sides.len()
    }

    /// Full candidate-list builds so far.
    pub fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// Add the faces to the sides that cover their parts (nodes appended, with empty friction
    /// history) and remember them: at the next step the nodes near them are searched again.
    fn activate(
        &mut self,
        ids: &[FaceId],
        elem_part: &[u32],
        conn: &[[u32; 8]],
        table: &FaceTable,
    ) -> usize {
        let mut added = 0;
        for (si, side) in self.sides.iter_mut().enumerate() {
            for &id in ids {
                let part = elem_part[id.0 as usize] as usize;
                if side.parts.get(part).copied().unwrap_or(false) && side.add(id, conn, table) {
                    added += 1;
                }
            }
            let n = side.nodes.len();
            for pass in self.passes.iter_mut().filter(|p| p.node_side == si) {
                pass.cand.resize_with(n, Vec::new);
                pass.ft.resize(n, [0.0; 3]);
                pass.hits.resize(n, Hit::default());
            }
        }
        self.pending.extend_from_slice(ids);
        added
    }

    fn stable_dt(&self, mass: &[f64]) -> f64 {
        let mut dt = f64::INFINITY;
        for p in &self.passes {
            let fs = &self.sides[p.face_side];
            let k_max = fs.faces.iter().map(|f| f.k).fold(0.0, f64::max);
            if k_max.is_nan() || k_max <= 0.0 {
                continue;
            }
            let m_min = self.sides[p.node_side]
                .nodes
                .iter()
                .chain(&fs.nodes)
                .map(|&n| mass[n as usize])
                .filter(|&m| m > 0.0)
                .fold(f64::INFINITY, f64::min);
            dt = dt.min((m_min / k_max).sqrt());
        }
        dt
    }

    /// True when some node of the surfaces (including nodes that joined since the last build)
    /// has moved more than half the margin since the last full build.
    fn moved_too_far(&self, x: &[Vec3]) -> bool {
        let lim2 = 0.25 * self.margin * self.margin;
        let x_ref = &self.x_ref;
        self.sides.iter().any(|s| {
            s.nodes
                .par_iter()
                .with_min_len(4 * NODE_CHUNK)
                .any(|&n| dist2(x[n as usize], x_ref[n as usize]) > lim2)
        })
    }

    /// New candidate lists of every node from the current positions.
    fn rebuild(&mut self, x: &[Vec3], tie: &[u32]) {
        self.x_ref.copy_from_slice(x);
        let m = self.margin;
        for side in &mut self.sides {
            side.base = side.faces.len();
            side.boxed = 0;
            side.box_new_faces(x, m);
            side.needed.iter_mut().for_each(|n| *n = false);
        }
        let Self {
            sides,
            passes,
            points,
            x_ref,
            ..
        } = self;
        for pass in passes.iter_mut() {
            let ns = &sides[pass.node_side];
            let fs = &sides[pass.face_side];
            points.clear();
            points.extend(ns.nodes.iter().map(|&n| x[n as usize]));
            pass.grid.build(&fs.boxes, points);
            pass.nbase = ns.nodes.len();
            pass.extra.build(&[], &[]);
            for i in 0..ns.nodes.len() {
                pass.query(i, ns, fs, x_ref, tie);
            }
        }
        for pass in passes.iter() {
            let needed = &mut sides[pass.face_side].needed;
            for &f in pass.cand.iter().flatten() {
                needed[f as usize] = true;
            }
        }
        self.pending.clear();
        self.dirty = false;
        self.rebuilds += 1;
    }

    /// Faces joined or ties broke around the pending faces: the nodes whose reference position
    /// lies in a pending face's search box get new candidate lists (against the main grid and
    /// a grid of the faces that joined since the last full build), as a full build at that
    /// time would have given them. Returns false (nothing done) when so much has joined that a
    /// full build is better.
    fn update(&mut self, tie: &[u32], conn: &[[u32; 8]], table: &FaceTable) -> bool {
        let too_many = |extra: usize, base: usize| 4 * extra > base.max(256);
        for p in &self.passes {
            let (ns, fs) = (&self.sides[p.node_side], &self.sides[p.face_side]);
            if too_many(fs.faces.len() - fs.base, fs.base)
                || too_many(ns.nodes.len() - p.nbase, p.nbase)
            {
                return false;
            }
        }
        let m = self.margin;
        let Self {
            sides,
            passes,
            x_ref,
            pending,
            points,
            scratch,
            region,
            ..
        } = self;
        for side in sides.iter_mut() {
            side.box_new_faces(x_ref, m);
        }
        region.clear();
        for &id in pending.iter() {
            let face = Face {
                elem: id.0,
                face: id.1,
                nodes: face_nodes(&conn[id.0 as usize], id.1),
                k: 0.0,
                depth: table.depth(id),
            };
            region.push(search_box(&face, x_ref, m));
        }
        for pass in passes.iter_mut() {
            let ns = &sides[pass.node_side];
            let fs = &sides[pass.face_side];
            let nbase = pass.nbase;
            points.clear();
            points.extend(ns.nodes[nbase..].iter().map(|&n| x_ref[n as usize]));
            pass.extra.build(&fs.boxes[fs.base..], points);
            scratch.clear();
            for b in region.iter() {
                pass.grid
                    .points_in(b, |q| x_ref[ns.nodes[q as usize] as usize], scratch);
                let start = scratch.len();
                pass.extra.points_in(b, |q| points[q as usize], scratch);
                for q in &mut scratch[start..] {
                    *q += nbase as u32;
                }
            }
            scratch.sort_unstable();
            scratch.dedup();
            for &i in scratch.iter() {
                pass.query(i as usize, ns, fs, x_ref, tie);
            }
            let needed = &mut sides[pass.face_side].needed;
            for &i in scratch.iter() {
                for &f in &pass.cand[i as usize] {
                    needed[f as usize] = true;
                }
            }
        }
        pending.clear();
        self.updates += 1;
        true
    }

    /// One step of this definition: forces into `acc`; the resultants and whether the
    /// candidates were rebuilt in full.
    fn compute(&mut self, inp: &StepInput, acc: &mut NodalForces) -> (ContactForce, bool) {
        let mut rebuilt = self.dirty || self.moved_too_far(inp.x);
        if !rebuilt && !self.pending.is_empty() && !self.update(inp.tie, inp.conn, inp.table) {
            rebuilt = true;
        }
        if rebuilt {
            self.rebuild(inp.x, inp.tie);
        }
        for side in &mut self.sides {
            side.update_geometry(inp.x);
        }
        let mut out = ContactForce {
            id: self.id,
            ..Default::default()
        };
        let Self {
            sides,
            passes,
            friction,
            ..
        } = self;
        for (p, pass) in passes.iter_mut().enumerate() {
            let ns = &sides[pass.node_side];
            let fs = &sides[pass.face_side];
            let Pass { cand, ft, hits, .. } = pass;
            let ctx = NodeCheck {
                nodes: &ns.nodes,
                node_side_faces: &ns.faces,
                node_faces: &ns.node_faces,
                faces: &fs.faces,
                geo: &fs.geo,
                cand,
                friction: *friction,
                inp,
            };
            hits.par_iter_mut()
                .zip(ft.par_iter_mut())
                .enumerate()
                .with_min_len(NODE_CHUNK)
                .for_each(|(i, (hit, ft))| (*hit, *ft) = ctx.check(i, hit, *ft));
            // NOTE: serial scatter in node order: the sums do not depend on the threads.
            // Pass 0 has the slave nodes; pass 1 the master nodes, whose reactions act on the
            // slave faces.
            let sign = if p == 0 { 1.0 } else { -1.0 };
            for (i, hit) in hits.iter().enumerate() {
                if hit.face == NONE || hit.fn_mag == 0.0 {
                    continue;
                }
                let face = &fs.faces[hit.face as usize];
                acc.add(ns.nodes[i], hit.f);
                for a in 0..4 {
                    acc.add(face.nodes[a], scale(hit.f, -hit.w[a]));
                }
                out.force = add(out.force, scale(hit.f, sign));
                out.normal += hit.fn_mag;
                out.pairs += 1;
            }
        }
        (out, rebuilt)
    }
}

/// What the check of one node reads.
struct NodeCheck<'a> {
    nodes: &'a [u32],
    /// The node side's faces, and the faces of each of its nodes.
    node_side_faces: &'a [Face],
    node_faces: &'a [Vec<u32>],
    faces: &'a [Face],
    geo: &'a [FaceGeo],
    cand: &'a [Vec<u32>],
    friction: Friction,
    inp: &'a StepInput<'a>,
}

impl NodeCheck<'_> {
    /// Unit normal of node `i`'s surface: the sum of its faces' area-weighted normals.
    fn node_normal(&self, i: usize, x: &[Vec3]) -> Vec3 {
        let mut n = [0.0; 3];
        for &f in &self.node_faces[i] {
            let p = self.node_side_faces[f as usize]
                .nodes
                .map(|a| x[a as usize]);
            n = add(n, cross(sub(p[2], p[0]), sub(p[3], p[1])));
        }
        let l = norm(n);
        if l > 0.0 {
            scale(n, 1.0 / l)
        } else {
            n
        }
    }

    /// Contact of node `i` of the node side with its candidate faces, after its hit of the
    /// last step `prev`; returns the hit and the node's new tangential force (zero when out of
    /// contact: the history resets).
    #[inline]
    fn check(&self, i: usize, prev: &Hit, ft_prev: Vec3) -> (Hit, Vec3) {
        let StepInput { x, v, dt_prev, .. } = *self.inp;
        let s = self.nodes[i];
        let xs = x[s as usize];
        let mut best: Option<(u32, Projection)> = None;
        let mut node_normal: Option<Vec3> = None;
        // faces holding the node or a node tied to it are not candidates (see `Pass::query`)
        for &fi in &self.cand[i] {
            let FaceGeo { b, depth } = &self.geo[fi as usize];
            let gap_min = GAP_TOL * b.r;
            if !b.may_touch(xs, *depth, gap_min) {
                continue;
            }
            let face = &self.faces[fi as usize];
            let p = face.nodes.map(|n| x[n as usize]);
            if !off_corners(&p, xs, gap_min) {
                continue;
            }
            let Some(pr) = project(&p, xs) else {
                continue;
            };
            if !(pr.gap < -gap_min && pr.gap > -face.depth) {
                continue;
            }
            // the node's surface must face the face (module docs)
            let n_s = *node_normal.get_or_insert_with(|| self.node_normal(i, x));
            if dot(n_s, pr.normal) > -FACING {
                continue;
            }
            // the nearest surface point: least penetration (module docs)
            if best.is_none_or(|(_, b)| pr.gap > b.gap) {
                best = Some((fi, pr));
            }
        }
        let Some((fi, pr)) = best else {
            return (Hit::default(), [0.0; 3]);
        };
        let face = &self.faces[fi as usize];
        let v_face = (0..4).fold([0.0; 3], |acc, a| {
            add(acc, scale(v[face.nodes[a] as usize], pr.w[a]))
        });
        let v_rel = sub(v[s as usize], v_face);
        // the first step has no motion to explain a penetration: the deck's initial
        // penetrations are pushed out in full
        let approach = if dt_prev > 0.0 {
            (-dot(v_rel, pr.normal)).max(0.0) * dt_prev
        } else {
            f64::INFINITY
        };
        let before = if prev.face == fi {
            Previous::Same {
                offset: prev.offset,
            }
        } else if prev.face == NONE {
            Previous::Free
        } else {
            Previous::Other {
                k: prev.k,
                engaged: prev.engaged,
            }
        };
        let e = engage(before, face.k, pr.gap, approach);

        let f_n = normal_force(face.k, e.engaged, pr.normal);
        let fn_mag = -face.k * e.engaged;
        let mut f_t = [0.0; 3];
        if !self.friction.is_frictionless() && fn_mag > 0.0 {
            let v_t = sub(v_rel, scale(pr.normal, dot(v_rel, pr.normal)));
            let mu = self.friction.coefficient(norm(v_t));
            f_t = tangential_force(ft_prev, pr.normal, scale(v_t, dt_prev), face.k, mu * fn_mag).0;
        }
        let hit = Hit {
            face: fi,
            w: pr.w,
            f: add(f_n, f_t),
            fn_mag,
            k: face.k,
            engaged: e.engaged,
            offset: e.offset,
        };
        (hit, f_t)
    }
}

/// Nodes a and b are tied: the same node, or members of one coincident set.
#[inline]
fn tied(a: u32, b: u32, tie: &[u32]) -> bool {
    a == b || (!tie.is_empty() && tie[a as usize] != NONE && tie[a as usize] == tie[b as usize])
}

#[inline]
fn dist2(a: Vec3, b: Vec3) -> f64 {
    let d = sub(a, b);
    dot(d, d)
}

#[cfg(test)]
mod tests;
