//! Automatic contact: `*CONTACT_AUTOMATIC_SINGLE_SURFACE` and
//! `*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE`, symmetric node-to-face penalty contact between the
//! exterior faces of hexahedral parts (deformable or rigid), with Coulomb friction, after the
//! LS-DYNA theory manual (penalty method, SOFT = 0; friction).
//!
//! - [`surface`]: exterior faces, the faces of each side, penalty stiffness `k = SLSFAC K A^2/V`
//!   of a face, a node's (its stiffest face), and a pair's (the smaller: PENOPT 1).
//! - [`search`]: the bucket grids that find each node's candidate faces.
//! - [`schedule`]: when each candidate pair is tested again.
//! - [`cand_lists`]: each node's candidates and their schedule, in one buffer per chunk of nodes.
//! - [`penalty`]: closest point on a bilinear face, gap, normal force and its reaction; the
//!   bounds that reject a node before projecting it, and its clearance.
//! - [`friction`]: `mu = FD + (FS - FD) exp(-DC |v_rel|)`, elastic trial force capped at
//!   `mu |f_n|`.
//!
//! # Sides and passes
//! A definition has one side (single surface) or two (surface to surface, slave and master).
//! Each step runs *passes* of node-to-face checks: single surface, the nodes of the surface
//! against its own faces; surface to surface, the slave nodes against the master faces, then
//! the master nodes against the slave faces (symmetric, as LS-DYNA's automatic contacts).
//! A node is never checked against a face that holds it or holds a node tied to it (the
//! coincident copies of a split model: `tie[a] == tie[b] != u32::MAX`), or a copy chained to
//! it across closed cracks (below): such faces are left out of its candidate list when the
//! list is made. Faces of separation groups join the surfaces when their interface fails
//! ([`ContactSet::activate_cracks`]).
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
//! # Coincident copies
//! The copies of a deck node in a split model that are still tied (one coincident set) sit at
//! one point and move as one. Only one of them, the set's *lead* on the side (the member with
//! the lowest model number), is checked against faces; its normal is that of the faces of all
//! the set's members on the side (the deck node's surface), and its force goes to the set
//! through the tie (`a = sum f / sum m`). So until an interface fails, a split model gets
//! exactly the contact forces of the same mesh unsplit: one penalty spring per surface point,
//! not one per copy (a deck node on a face of the ball's surface has four copies there, which
//! would otherwise make its spring four times as stiff), and the work is that of the deck's
//! nodes. When a set splits, each part has its lead. Leads are found again at each search, for
//! the copies at the faces that joined since the last ([`Contact::regroup_pending`]; for every
//! node when ties changed otherwise, [`Contact::regroup`]); a node whose lead changed is
//! searched again, and a new lead takes
//! over the contact history of its set's lead before (the engagement and the friction force:
//! it sits at the same point, on the same faces), so a set that splits, or whose lead changes,
//! while in contact keeps pushing back; a set whose members changed has all its candidates due
//! (its normal changed).
//!
//! Forces: normal `f_n = -k g n` on the node, plus friction `f_t` ([`friction`]); the face's
//! nodes get `-N_a(xi, eta) (f_n + f_t)`, N_a the bilinear shape functions at the contact point.
//! k is the pair's ([`FaceTable::pair_stiffness`]): the smaller of the face's and the node's
//! (PENOPT 1, LS-DYNA's default), or the face's (PENOPT 2, the master segment's).
//!
//! Before projecting, a node is tested against cheap exact bounds of the face
//! ([`penalty::Cull`], from [`penalty::FaceBounds`]: sphere, mean-plane slab, lateral
//! distance), then against the facing bound (below), then off the face's corners; together they
//! reject most candidates. A face's bounds are worked out at the current positions the first
//! time a step tests it, once per thread ([`bounds_cache`]).
//!
//! # Search
//! Candidate faces of each node come from bucket grids ([`search`]) over face boxes inflated by
//! `depth + 4 INSIDE_TOL r + 1.1 margin`, built from the positions x_ref of that moment (a *full
//! build*); of those, a face is kept when the node's x_ref also lies in its search sphere, of
//! radius `E (r + margin) + depth` about its centroid (E = [`penalty::WEIGHT_SUM`], r the
//! largest centroid-corner distance). The lists are reused while the displacements since x_ref
//! have spread by less than the margin: the diagonal of their box over the definition's nodes
//! (the *spread*) bounds how far any node has moved relative to any other. The displacements
//! are watched per entry of the solver's positions ([`crate::node_values`]): once per
//! coincident set, whose copies move as one (the solver gives a set one acceleration,
//! `sum f / sum m`, for all its members), and the set's lead stands for its copies in the
//! checks. An entry is watched from the step after a node of a side is on it (marked when the
//! node joins, [`Contact::watch_new_nodes`], and again from the sides' nodes at each full
//! build; a slot born of a split is watched as its set was, [`Contact::sets_split`]); the
//! tracking reads the watched entries ([`Contact::track`]). Where a rigid body's node is bonded
//! to a group's copies every node has its own entry: the tied copies' entries hold equal values,
//! and the body's node, placed by its body, is watched as any node. Until then a
//! node and a face it may touch have moved less than the margin relative to each other, so the
//! node's x_ref is still in the face's box (the contact point, `sum w_a x_a` with
//! `sum |w_a| <= E`, moved by at most E margin relative to the node; the 1.1 covers that and
//! the tolerance band growing with the face) and in its sphere (`min_w |s - sum w_a x_a|` is
//! below depth at contact and changes by at most E times the relative motion, [`penalty::Cull`]).
//! A translation of everything moves no node relative to another and needs no new build.
//! `margin` = [`MARGIN_FRACTION`] times the mean sqrt(area) of the definition's faces.
//!
//! When interfaces fail ([`ContactSet::activate`]), the search is incremental: the new faces get
//! boxes and spheres from x_ref, a grid that takes each face and node as it joins holds them
//! ([`join_grid`]: none is sorted again at the next search), and only the
//! nodes whose x_ref lies in a failed face's box get new lists (a new face only changes the
//! lists of the nodes within its box), with every copy of its corners' deck nodes: a broken tie
//! or chain changes which faces hold a node tied or chained to each copy, and a copy split off
//! earlier need not lie in the box (on the 20,000-element ball a copy 0.25 mm from a face that
//! had held a copy tied or chained to it lay outside the box of the failure that ended that,
//! and kept a list without the face until the next full build). The lists are then what a
//! full build at x_ref with the new faces and ties would give, and stay valid under the same
//! margin rule (new nodes are watched from x_ref on). When the faces or nodes that joined since
//! the last full build exceed a quarter of those in it, a full build is made instead. The
//! searches of the nodes run in parallel, each writing its own list.
//!
//! # Skipping
//! A candidate pair is not tested every step. A test that finds the node apart from the face
//! returns a *clearance* D: the pair cannot touch while the face's corners move by at most D
//! relative to the node (the distance, below and above bounds of [`penalty::Cull`], and the
//! facing bound below). Each step the definition's *motion bound* grows by the diagonal of the
//! box of its watched entries' displacements over the step, which bounds how far any node moved
//! relative to any other in that step; the pair is due again when the bound has grown by D.
//! [`schedule`] keeps each node's candidates so that those not due cost nothing: the ones due
//! within [`HOT_STEPS`] steps are looked at every step, the others wait in a heap; a node none
//! of whose candidates is due is not looked at (each node's earliest due is kept in a dense
//! array; a node in contact has its face due every step, so a node skipped is out of contact
//! and its hit stays empty). The bound restarts at zero at each full build (a pair kept keeps
//! what is left of its clearance; a pair new to a node's list is first due at its clearance
//! from the face's search sphere, [`first_due`], rather than at once). Pairs stay listed until
//! the next full build, however far they are: a pair dropped when found far was listed again
//! by the next build and tested again. On the fracturing 2800-element ball (`cleave bench
//! ball`, counted for one run) that made 1713 tests a step, 1642 with the first due from the
//! sphere (565 of them ending in a drop), 1262 without drops.
//!
//! The bound is one for the whole definition, so it grows with the fastest relative motion
//! anywhere: on the fracturing 2800-element ball at about 190 m/s over its first 44 us, twice
//! the impact speed, and that is motion inside the breaking ball spread over many nodes, not
//! the ball against the plate (without the plate's nodes the box keeps 83-95% of it, without
//! the 50 most extreme displacements at each end of each axis 86%), while the pairs that get
//! tested mostly move together: on the fracturing 20,000-element ball the pairs tested moved
//! relative to each other at 0.055 of its growth on average. Bounds per node and per cell of
//! space were tried and dropped (Cost, below): the tests they save are the cheap ones.
//!
//! Facing bound: with n_s the node's normal `S / |S|` and n the face's normals (within the cone
//! of [`penalty::FaceBounds`] about n0), `n_s . n >= f0`, f0 the least over the cone
//! (`cos_min n_s.n0` or `n_s.n0` when negative, less `sin_max |n_s x n0|`). A relative motion
//! delta changes each diagonal d of the node's faces by at most delta, each of their cross
//! products by `delta (|d1| + |d2|) + delta^2`, so S by `|S| (a delta + b delta^2)`; the face's
//! normals N by `|N| (kn1 delta + kn2 delta^2)` ([`penalty::FaceBounds`]); and a vector that
//! changes by at most r times its length (r <= 1) turns its direction by a chord of at most
//! `sqrt(2) r`. So while `sqrt(2) ((a + kn1) delta + (b + kn2) delta^2) < f0 + FACING` the
//! node's surface still turns away from every normal of the face (`n_s . n > -FACING`): no
//! contact. That holds while the node's faces stay the same: a node that gets a face has all
//! its candidates due at once.
//!
//! # Energy
//! The contact energy increment of a step is the trapezoid of the work of the contact forces:
//! `dE = -1/2 sum_i (f_i^(n-1) + f_i^n) . (x_i^n - x_i^(n-1))`, with
//! `x^n - x^(n-1) = v^(n-1/2) dt^(n-1/2)`. It holds both the elastic energy of the penalty
//! springs and the frictional dissipation (both positive).
//!
//! # Determinism
//! The per-node contact detection runs in parallel, but each chunk of nodes writes its own list
//! of the nodes in contact (`touching.rs`; a node's nearest face, of equal gaps the lowest
//! index, does not depend on the order its candidates are tested in); the forces are
//! scattered serially in a fixed order: definition by definition, the closed cracks' pairs in
//! the order the cracks closed (on one thread while the searches and checks run on the
//! others), then each pass's nodes in the order they joined the side. A full build puts each side's nodes in space order (Morton order of x_ref:
//! neighbours, which share candidates, are checked one after the other, for the caches) when
//! more than an eighth of them joined since the last ordering; the scatter order, the leads
//! and their member chains (by model number) do not change with it. The results are
//! bit-identical for any number of threads, and to those of testing every candidate every
//! step. After the first steps no buffer grows unless faces are added, the candidate lists
//! get longer, or more nodes of a chunk touch than ever before; the space ordering, which comes
//! only after many nodes joined, allocates its scratch and frees it, and so does an
//! incremental search around many failed faces (its look-ups on every thread). The grids of a
//! search are built on every thread ([`cell_lists`]): each cell lists its faces or nodes
//! ascending, the same lists as the serial counting sort gives.
//!
//! # Closed cracks
//! The two faces of a failed interface start flush, each node on a corner of the face
//! opposite, where the node-to-face search finds no clearance. While they still lie on each
//! other, the crack is *closed* ([`closure`]): its node pairs carry a penalty on their normal
//! opening (with friction), and the search leaves out every face that holds a copy *chained*
//! to the node: tied to it, or joined to it through closed cracks ([`closure::Chains`], which
//! also covers the copies diagonal across an edge, held apart by the closed cracks of the
//! elements between). A crack whose faces slide apart by a fifth of an edge, or turn apart by
//! 30 degrees, is released for good and its faces go back to the search around them
//! ([`ContactSet::activate_cracks`]).
//!
//! # Buried nodes
//! A lead all of whose faces on the side (over its coincident set's members) lie on *tight*
//! closed cracks is *buried*: its deck node sits inside the material, each of its faces held
//! flush against the face it failed from by the closure's pairs. It gets no candidates and is
//! not checked ([`Side::buried`], at each search); its faces stay on the surface for the other
//! nodes (over the 2800 ball's run a node off the closed cracks found its contact on one of
//! their faces 2,144 times). Another body could reach a buried node only by passing between
//! the two faces of one of its cracks, so a crack stops burying its nodes once a pair has
//! opened along the normal by more than [`closure::TIGHT`] (a fifth, as the slip that
//! releases it) of its shortest edge: its faces are then searched around at once, as when an
//! interface fails, and bury their nodes again from their next search when the crack shuts.
//! On the 2800 ball the buried nodes made 69% of the pair tests (counted before the rule), and
//! found no contact; leaving them out keeps the ball's output byte for byte and took the
//! contact's share of the step from 37-41% to 28-30% (one thread).
//!
//! # Cost
//! Where a fragmenting run's contact time goes (the 20,000-element ball of `cleave bench ball`,
//! 50 us, one thread, which prints each phase's seconds from the timers of [`times`];
//! BENCHMARKS.md has the current figures): the node checks 53%, the full builds 20% (240 of
//! them: the faces' boxes, the grids, the nodes' searches), the closed cracks 13% (about 100
//! ns a crack and step, their forces included), the incremental searches 2.5%, motion
//! tracking 2.4%, the forces' sums 2%. The node checks are bound by memory: a check reads the
//! node's schedule and list, the face's bounds and their stamp; a node's frame costs about 160
//! ns and a face's bounds about 120 ns, together about a fifth of the contact. Without separation the contact takes 2-3% of
//! the ball's step.
//!
//! Tried on that ball and dropped, each with the same output bits (the measurements are in the
//! history of BENCHMARKS.md):
//! - A motion bound per node (its own displacement plus the largest of the watched nodes'),
//!   or per cell of space 2.5 face sizes wide (its 27-cell neighbourhood's displacement box):
//!   the pair tests fall by 30-40%, the contact's time by under 4% before the bound's own
//!   pass. The tests saved are the cheap ones, of faces whose bounds the step had worked out
//!   already. Full builds made by a local rule (a cell's neighbourhood spread by the margin)
//!   would still be 153-189 instead of 240: fragments sliding and flying apart move locally
//!   too.
//! - A larger margin (0.2): half the full builds, but the checks grow more (the contact 23.0 to
//!   24.2 s); [`MARGIN_FRACTION`] 0.07-0.1 is the least. Grid cells of 1, 1.5 or 3 per box
//!   instead of 2 (`CELLS_PER_BOX`, search.rs): no gain.
//! - Each node's frame kept with the motion bound it was worked out at, while its facing
//!   clearance exceeds the motion since: 5% fewer frames worked out, for 3.7 MB more.
//! - The closed cracks sorted in space (by their first node) at each full build, for their
//!   step's reads of the positions: no gain.
//!
//! What the node checks test (counted for one run of that ball): 70% of the pair tests end
//! with a clearance below one step's growth of the bound, 28% project and find no contact, 2%
//! find one; they are near-contacts along crack faces lying on or close to each other (a bound
//! per node, above, skipped a third of them but saved under 4% of the time).

pub mod bounds_cache;
mod cand_lists;
mod cell_lists;
pub mod closure;
pub mod engagement;
pub mod friction;
mod join_grid;
mod node_faces;
pub mod penalty;
pub(crate) mod restart;
pub mod schedule;
pub mod search;
pub mod surface;
pub mod times;
mod touching;
pub mod view;

use crate::element::hex8;
use std::collections::hash_map::Entry;
use std::collections::HashMap;

use rayon::prelude::*;

use crate::math::{add, dot, norm, scale, sub, Vec3};
use crate::model::{ContactDef, Model, PenaltyRule};
use crate::node_values::NodeValues;
use bounds_cache::BoundsCache;
use cand_lists::CandLists;
use join_grid::JoinGrid;

/// Positions or velocities of every node, read through the coincident sets' slots when the
/// solver keeps them per slot ([`crate::node_values`]).
pub type Points<'a> = NodeValues<'a, Vec3>;
pub use closure::Crack;
use closure::{Chains, Closure};
use engagement::{engage, Previous};
use friction::{tangential_force, Friction};
use node_faces::NodeFaces;
use penalty::{normal_force, off_corners, project, Cull, CullMore, Projection, INSIDE_TOL};
use schedule::{Cand, Sched};
use search::{Aabb, Aabb32, BucketGrid};
use std::time::Instant;
use surface::{covered_parts, exterior_faces, face_nodes, side_faces, FaceId, FaceTable};
use times::{lap, ContactTimes};
use touching::Touching;

const NONE: u32 = u32::MAX;

/// Search margin as a fraction of the mean face size sqrt(A): candidates are rebuilt when the
/// nodes have moved by more than it relative to each other (module docs, Search). A smaller
/// margin means more full builds but fewer candidates to keep testing: on the fracturing
/// 2800-element ball (`cleave bench ball`, 1 thread) contact took 55-57% of the step at 0.3
/// (35 full builds), 51-54% at 0.2, 48-52% at 0.1 (90), 51-52% at 0.05 (173).
pub const MARGIN_FRACTION: f64 = 0.1;

/// Gaps above `-GAP_TOL r` (r the face's radius) are not contact (see the module docs).
pub const GAP_TOL: f64 = 1e-9;

/// A node contacts a face only if its surface faces the face: `n_s . n < -FACING`, n_s the
/// node's normal (the mean of its faces' normals), n the face's (an angle over 101.5 degrees).
pub const FACING: f64 = 0.2;

/// Nodes per parallel task of the detection.
const NODE_CHUNK: usize = 256;

/// A node's candidates due within about this many steps (at the last step's growth of the
/// motion bound) are looked at every step; the others only when the earliest of them is due
/// (module docs).
pub const HOT_STEPS: f64 = 4.0;

/// A full build is also made when the motion bound exceeds this many margins (nodes vibrating
/// in place), so the f32 `due` values stay fine.
const REBASE: f64 = 1.0e4;

/// An incremental search looks up the nodes in the failed faces' boxes on every thread from
/// this many faces on ([`Contact::update`]; the tasks' lists are allocated and freed at each
/// such search). The unit tests take it from 2 faces, so their searches run it.
const PAR_REGIONS: usize = if cfg!(test) { 2 } else { 64 };

/// A full build puts a side's nodes in space order again once more than 1/REORDER of them
/// joined since the last ordering ([`Contact::reorder`]).
const REORDER: usize = 8;

/// A face of a contact surface.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
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

impl Face {
    /// At positions `x`: the diagonal cross product `d1 x d2` (twice the area-weighted normal,
    /// [`hex8::diagonal_cross`]) and `|d1| + |d2|`, for the normals of its nodes
    /// ([`NodeFrame`]).
    #[inline]
    pub fn normal_terms(&self, x: Points) -> (Vec3, f64) {
        let p = self.nodes.map(|n| x[n as usize]);
        let diagonals = norm(sub(p[2], p[0])) + norm(sub(p[3], p[1]));
        (hex8::diagonal_cross(p[0], p[1], p[2], p[3]), diagonals)
    }
}

/// Resultants of one definition over the last step (for rcforc.csv).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
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
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactStep {
    /// Contact energy increment of the step (add to `Energies::contact`).
    pub energy: f64,
    /// Node-face pairs in contact, all definitions.
    pub pairs: usize,
    /// Whether some definition rebuilt its candidate lists this step.
    pub rebuilt: bool,
}

/// Search statistics.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
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
    /// Closed cracks now, and those released to the search so far ([`closure`]).
    pub closed: usize,
    pub released: u64,
}

/// All contact definitions of a model, with the scratch they share. It borrows the model (the
/// faces that join are made from its elements).
#[derive(Clone, Debug)]
pub struct ContactSet<'m> {
    contacts: Vec<Contact>,
    table: FaceTable<'m>,
    /// The contact forces on the nodes at this step and the last.
    nodal: NodalForces,
    forces: Vec<ContactForce>,
    /// Faces the bounds caches of the pool's threads have room for ([`bounds_cache`]).
    reserved: usize,
    /// Seconds spent making failed interfaces' faces join ([`ContactSet::activate_cracks`]).
    activation: f64,
    /// Seconds spent adding the contact forces into the nodes' and taking their work
    /// ([`ContactSet::compute_with_slots`]).
    sums: f64,
}

impl<'m> ContactSet<'m> {
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
    pub fn new(model: &'m Model, origin: Option<&'m [u32]>) -> Result<Self, String> {
        let deck_conn: Vec<[u32; 8]> = match origin {
            Some(o) => model
                .conn
                .iter()
                .map(|c| c.map(|n| o[n as usize]))
                .collect(),
            None => model.conn.clone(),
        };
        let exterior = if model.contacts.is_empty() {
            Vec::new()
        } else {
            exterior_faces(&deck_conn, |_| true)
        };
        let table = FaceTable::new(model, origin);
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
            table,
            nodal: NodalForces::new(nn),
            forces,
            reserved: 0,
            activation: 0.0,
            sums: 0.0,
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
            added += c.activate(faces, &self.table);
        }
        added
    }

    /// Coincident sets split in this step, and the solver keeps positions per slot
    /// ([`crate::node_values`]): `born` lists each new slot with the slot it split from
    /// ([`crate::separation::coincident::CoincidentSets::born`]). Call before the step's
    /// [`Self::compute_with_slots`].
    pub fn sets_split(&mut self, born: &[(u32, u32)]) {
        for c in &mut self.contacts {
            c.sets_split(born);
        }
    }

    /// Interfaces failed: as [`ContactSet::activate`] with their faces, and each definition
    /// that tests one face's nodes against the other face *closes* the crack: the node pairs
    /// resist interpenetration until the faces slide apart ([`closure`]). Returns what
    /// `activate` returns.
    pub fn activate_cracks(&mut self, cracks: &[Crack]) -> usize {
        let mut t = Instant::now();
        let mut added = 0;
        for crack in cracks {
            added += self.activate(&crack.faces);
            for c in &mut self.contacts {
                c.close(crack, &self.table);
            }
        }
        lap(&mut t, &mut self.activation);
        added
    }

    /// Elements eroded ([`crate::erosion`]): the faces of every element marked in `eroded`
    /// stop pushing (stiffness and depth 0: no node-face pair forms with them, the next
    /// searches leave them out, and node normals no longer count them), a node whose faces
    /// have all eroded is no longer checked (it is *buried*, [`Side::buried`]), and
    /// `exposed`, the faces of live elements that eroded ones covered, join the sides that hold
    /// their parts as failed interfaces' faces do ([`ContactSet::activate`]). Returns what
    /// `activate` returns.
    pub fn erode(&mut self, eroded: &[bool], exposed: &[FaceId]) -> usize {
        for c in &mut self.contacts {
            for side in &mut c.sides {
                for (f, tight) in side.faces.iter_mut().zip(&mut side.tight) {
                    if eroded[f.elem as usize] {
                        f.k = 0.0;
                        f.depth = 0.0;
                        // a node all of whose faces eroded is buried: no longer checked
                        *tight = true;
                    }
                }
            }
        }
        self.activate(exposed)
    }

    /// Ties changed in some other way than by failed interfaces named to
    /// [`ContactSet::activate`]: rebuild all candidate lists at the next `compute`.
    pub fn ties_changed(&mut self) {
        for c in &mut self.contacts {
            c.dirty = true;
            c.chains.touch_all();
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
    /// Call it after assembling the element forces and before the velocity update (so a
    /// coincident set shares the contact force of any of its members), and before the rigid
    /// bodies gather their nodes' forces.
    pub fn compute(
        &mut self,
        x: &[Vec3],
        v: &[Vec3],
        dt_prev: f64,
        tie: &[u32],
        f: &mut [Vec3],
    ) -> ContactStep {
        self.compute_with_slots(x.into(), v.into(), dt_prev, tie, &[], f)
    }

    /// [`Self::compute`], the force on each node i added to `f[slot[i]]` (the solver keeps
    /// the sum of the forces on each coincident set in its slot,
    /// [`crate::separation::coincident::CoincidentSets::slots`]); an empty `slot` adds it to
    /// `f[i]`.
    pub fn compute_with_slots(
        &mut self,
        x: Points,
        v: Points,
        dt_prev: f64,
        tie: &[u32],
        slot: &[u32],
        f: &mut [Vec3],
    ) -> ContactStep {
        let nn = self.nodal.len();
        assert!(x.len() == nn && v.len() == nn);
        assert!(tie.is_empty() || tie.len() == nn);
        assert!(if slot.is_empty() {
            f.len() == nn
        } else {
            slot.len() == nn
        });
        self.nodal.next_step();
        let mut step = ContactStep::default();
        let inp = StepInput {
            x,
            v,
            dt_prev,
            tie,
            table: &self.table,
        };
        // faces join between steps: room in every thread's bounds cache first, so no check
        // allocates
        let faces = self
            .contacts
            .iter()
            .flat_map(|c| &c.sides)
            .map(|s| s.faces.len());
        let need = faces.max().unwrap_or(0);
        if need > self.reserved {
            bounds_cache::reserve_everywhere(need);
            self.reserved = need;
        }
        for (c, out) in self.contacts.iter_mut().zip(self.forces.iter_mut()) {
            let rebuilt;
            (*out, rebuilt) = c.compute(&inp, &mut self.nodal);
            step.pairs += out.pairs;
            step.rebuilt |= rebuilt;
        }
        // NOTE: fixed order: last step's nodes, then this step's, each in insertion order.
        let mut t = Instant::now();
        let mut work = 0.0;
        for (i, fi) in self.nodal.last_step() {
            work += dot(fi, v[i as usize]);
        }
        for (i, fi) in self.nodal.iter() {
            let i = i as usize;
            work += dot(fi, v[i]);
            let r = if slot.is_empty() { i } else { slot[i] as usize };
            f[r] = add(f[r], fi);
        }
        step.energy = -0.5 * dt_prev * work;
        lap(&mut t, &mut self.sums);
        step
    }

    /// Resultants of each definition over the last `compute`, in deck order.
    pub fn forces(&self) -> &[ContactForce] {
        &self.forces
    }

    /// The contact force on each node of the last `compute` (nodes in first-touched order).
    pub fn nodal_forces(&self) -> impl Iterator<Item = (u32, Vec3)> + '_ {
        self.nodal.iter()
    }

    /// A time step the penalty springs are stable with, to compare with the element step.
    ///
    /// PENOPT 1 (the default): `dt = min over the nodes n of sqrt(m_n / k_n)`, k_n the node's
    /// stiffness
    /// ([`FaceTable::node_stiffness`]), over every node that is or may come to be on a
    /// surface (the nodes of the sides' faces, and all nodes of the elements of the parts
    /// whose failed interfaces join a side). Derivation: a pair's spring is at most the
    /// stiffness of its node and of each of its face's nodes (the pair takes the smaller of
    /// the face's and the node's, and a face is one of the faces that set its nodes'
    /// stiffness: [`FaceTable::pair_stiffness`]). A node of mass m in contact is held by its
    /// own spring and, in the symmetric pass, by the spring of the node that penetrates it;
    /// two such masses joined by 2k vibrate at `omega^2 = 2k (1/m_a + 1/m_b) <= 2 k_a/m_a +
    /// 2 k_b/m_b <= 4 max(k/m)`, and central differences need `dt <= 2/omega`. A closed crack's
    /// pair is two such springs ([`closure`]). Infinite when there is no face. `mass` is the
    /// mass each node has against a spring: the solver gives a rigid body's nodes the body's
    /// mass. A node copy of a split model counts with its own mass, the least its coincident
    /// set can be left with. For a cube element of side l (k = SLSFAC K l, m = rho l^3 / 8)
    /// this is `l sqrt(rho / (8 SLSFAC K))`, 1.1 times `l / sqrt(K / rho)` at SLSFAC 0.1, so
    /// longer than the element's step `l / c` for any material (`c^2 = (K + 4G/3) / rho`).
    /// (Against a rigid face the bound could be sqrt(2) larger; tried, the stick of the
    /// friction test then creeps.) PENOPT 2, where any node takes any face's spring:
    /// `dt = sqrt(min m_n / max k_n)` over the same nodes. Each definition on its own; the
    /// least over the definitions.
    pub fn stable_dt(&self, mass: &[f64]) -> f64 {
        self.contacts
            .iter()
            .map(|c| self.springs_dt(c, mass))
            .fold(f64::INFINITY, f64::min)
    }

    /// [`ContactSet::stable_dt`] of one definition.
    fn springs_dt(&self, c: &Contact, mass: &[f64]) -> f64 {
        let model = self.table.model();
        let mut on = vec![false; mass.len()];
        for side in &c.sides {
            for &n in &side.nodes {
                on[n as usize] = true;
            }
            for (e, conn) in model.conn.iter().enumerate() {
                let part = model.elem_part[e] as usize;
                if side.parts.get(part).copied().unwrap_or(false) {
                    conn.iter().for_each(|&n| on[n as usize] = true);
                }
            }
        }
        let springs = (0..mass.len() as u32)
            .filter(|&n| on[n as usize])
            .map(|n| (mass[n as usize], self.table.node_stiffness(n)))
            .filter(|&(m, k)| m > 0.0 && k > 0.0);
        match model.control.penalty {
            PenaltyRule::Smaller => springs
                .map(|(m, k)| (m / k).sqrt())
                .fold(f64::INFINITY, f64::min),
            PenaltyRule::Face => {
                let (m, k) = springs.fold((f64::INFINITY, 0.0f64), |(m0, k0), (m, k)| {
                    (m0.min(m), k0.max(k))
                });
                if k > 0.0 {
                    (m / k).sqrt()
                } else {
                    f64::INFINITY
                }
            }
        }
    }

    /// Search statistics, all definitions.
    pub fn stats(&self) -> ContactStats {
        let mut s = ContactStats::default();
        for c in &self.contacts {
            s.faces += c.sides.iter().map(|sd| sd.faces.len()).sum::<usize>();
            s.nodes += c.passes.iter().map(|p| p.next.len()).sum::<usize>();
            s.candidates += c
                .passes
                .iter()
                .flat_map(|p| p.cand.rooms())
                .map(|(_, room)| room.len())
                .sum::<usize>();
            s.rebuilds += c.rebuilds;
            s.updates += c.updates;
            s.closed += c.closures.len();
            s.released += c.released;
        }
        s
    }

    /// Seconds in each phase of the steps so far, over all definitions
    /// ([`times::ContactTimes`]).
    pub fn times(&self) -> ContactTimes {
        let t = ContactTimes {
            activation: self.activation,
            pair_forces: self.sums,
            ..ContactTimes::default()
        };
        self.contacts.iter().fold(t, |t, c| t.plus(&c.times))
    }
}

/// Sparse nodal forces: the force of each node touched at this step, in the order first
/// touched, and each node's place in that list (4 bytes a node, instead of a dense force array
/// of 24; only the surface nodes in contact are touched); and the same lists of the last step,
/// for the energy's trapezoid.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
struct NodalForces {
    /// Place of each node in `touched` / `f`, or NONE (one array for both steps: the last
    /// step's nodes are only read in sequence).
    slot: Vec<u32>,
    touched: Vec<u32>,
    f: Vec<Vec3>,
    /// The nodes and forces of the last step.
    last_touched: Vec<u32>,
    last_f: Vec<Vec3>,
}

impl NodalForces {
    fn new(n: usize) -> Self {
        Self {
            slot: vec![NONE; n],
            touched: Vec::new(),
            f: Vec::new(),
            last_touched: Vec::new(),
            last_f: Vec::new(),
        }
    }
    /// Number of nodes.
    fn len(&self) -> usize {
        self.slot.len()
    }
    #[inline]
    fn add(&mut self, i: u32, g: Vec3) {
        let k = i as usize;
        if self.slot[k] == NONE {
            self.slot[k] = self.touched.len() as u32;
            self.touched.push(i);
            self.f.push([0.0; 3]);
        }
        let s = self.slot[k] as usize;
        self.f[s] = add(self.f[s], g);
    }
    /// The touched nodes and their forces, in the order first touched.
    fn iter(&self) -> impl Iterator<Item = (u32, Vec3)> + '_ {
        self.touched.iter().copied().zip(self.f.iter().copied())
    }
    /// The same of the last step.
    fn last_step(&self) -> impl Iterator<Item = (u32, Vec3)> + '_ {
        self.last_touched
            .iter()
            .copied()
            .zip(self.last_f.iter().copied())
    }
    /// A new step: this step's forces become the last step's, and none is touched.
    fn next_step(&mut self) {
        for &i in &self.touched {
            self.slot[i as usize] = NONE;
        }
        std::mem::swap(&mut self.touched, &mut self.last_touched);
        std::mem::swap(&mut self.f, &mut self.last_f);
        self.touched.clear();
        self.f.clear();
    }
}

/// What a build of the definitions reads.
struct Build<'a> {
    model: &'a Model,
    deck_conn: &'a [[u32; 8]],
    origin: Option<&'a [u32]>,
    exterior: &'a [FaceId],
    table: &'a FaceTable<'a>,
}

/// What a step reads.
struct StepInput<'a> {
    x: Points<'a>,
    v: Points<'a>,
    dt_prev: f64,
    tie: &'a [u32],
    table: &'a FaceTable<'a>,
}

/// One side of a definition: its faces and their nodes.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
struct Side {
    faces: Vec<Face>,
    /// The faces in `faces`, with their index.
    present: HashMap<FaceId, u32>,
    /// Each face of `faces` lies on a tight closed crack of the definition
    /// ([`closure::Closure::tight`]).
    tight: Vec<bool>,
    /// Parts whose failed interfaces add faces to this side.
    parts: Vec<bool>,
    /// Nodes of the faces: ascending at the start, then in the order their faces joined.
    nodes: Vec<u32>,
    /// Nodes `..marked` have their positions' entry marked in `Contact::watched`; the others
    /// joined since the last step and get it at the next ([`Contact::watch_new_nodes`]).
    marked: usize,
    /// Index of each model node in `nodes`, or NONE.
    local: Vec<u32>,
    /// The faces of each node of `nodes` (indices into `faces`).
    node_faces: NodeFaces,
    /// The *lead* of each node's coincident set on this side (an index into `nodes`: the
    /// member with the lowest model number; the node itself when untied), and the chain of the
    /// other members from each lead (`next`, NONE-terminated), by descending model number:
    /// the lead's normal sums its members' faces along the chain, so the chain must not
    /// depend on the nodes' places (which a full build may or may not change). Only leads
    /// are checked (module docs, Coincident copies); valid after each search.
    group: Vec<u32>,
    next: Vec<u32>,
    /// `group` before the last [`Side::regroup`] (NONE for the nodes new to the side); after a
    /// [`Side::regroup_some`], valid for the nodes it regrouped (the only ones read).
    prev_group: Vec<u32>,
    /// Nodes (indices into `nodes`) that got faces since the last step: their normal changed.
    renewed: Vec<u32>,
    /// The order the nodes joined in: `rank[i]` of node i. A full
    /// build puts `nodes` in space order when many joined ([`Contact::reorder`]: neighbours
    /// next to each other, for the caches);
    /// forces are scattered by rank, so the sums do not depend on that order.
    rank: Vec<u32>,
    /// Number of nodes at the last space ordering ([`Contact::reorder`]).
    ordered: usize,
    /// Search box and search sphere (centre, radius^2) of each face, from the positions of
    /// the last full build.
    boxes: Vec<Aabb32>,
    spheres: Vec<Sphere>,
    /// Faces `..base` are in the passes' main grids; later ones joined since the last full
    /// build. Faces `..boxed` have their box.
    base: usize,
    boxed: usize,
}

impl Side {
    fn new(ids: &[FaceId], parts: Vec<bool>, table: &FaceTable, num_nodes: usize) -> Self {
        let mut s = Self {
            faces: Vec::with_capacity(ids.len()),
            present: HashMap::with_capacity(ids.len()),
            tight: Vec::with_capacity(ids.len()),
            parts,
            nodes: Vec::new(),
            marked: 0,
            local: vec![NONE; num_nodes],
            node_faces: NodeFaces::default(),
            group: Vec::new(),
            next: Vec::new(),
            prev_group: Vec::new(),
            renewed: Vec::new(),
            rank: Vec::new(),
            ordered: 0,
            boxes: Vec::new(),
            spheres: Vec::new(),
            base: 0,
            boxed: 0,
        };
        for &id in ids {
            s.add(id, table);
        }
        s.nodes.sort_unstable();
        for (i, &n) in s.nodes.iter().enumerate() {
            s.local[n as usize] = i as u32;
        }
        s.rank = (0..s.nodes.len() as u32).collect();
        // linked again in the sorted places
        s.node_faces = NodeFaces::default();
        s.node_faces.resize(s.nodes.len());
        for f in 0..s.faces.len() {
            s.link(f);
        }
        s.renewed.clear();
        s
    }

    /// Record face `f` as a face of each of its nodes.
    fn link(&mut self, f: usize) {
        self.node_faces.resize(self.nodes.len());
        for n in self.faces[f].nodes {
            let i = self.local[n as usize];
            self.node_faces.push(i, f as u32);
            self.renewed.push(i);
        }
    }

    /// The leads and member chains of the nodes' coincident sets under `tie` (`set_lead`:
    /// scratch, NONE everywhere, left so); the nodes whose lead changed are pushed to
    /// `changed`, each with its lead before (NONE for a node new to the side). A
    /// [`Side::regroup_some`] of every node (`all`: scratch for their places, in ascending
    /// model number).
    fn regroup(
        &mut self,
        tie: &[u32],
        set_lead: &mut Vec<u32>,
        changed: &mut Vec<(u32, u32)>,
        all: &mut Vec<u32>,
    ) {
        all.clear();
        all.extend(self.local.iter().copied().filter(|&i| i != NONE));
        self.regroup_some(all, tie, set_lead, changed);
    }

    /// The leads and member chains (see `group`) of the nodes `some` only (local indices in
    /// ascending model number, holding every member on the side of each coincident set it
    /// touches, before and after): they come out as a regroup of all nodes would make them,
    /// the other nodes' are left as they are (their sets did not change).
    fn regroup_some(
        &mut self,
        some: &[u32],
        tie: &[u32],
        set_lead: &mut Vec<u32>,
        changed: &mut Vec<(u32, u32)>,
    ) {
        let n = self.nodes.len();
        self.group.resize(n, NONE);
        self.next.resize(n, NONE);
        self.prev_group.resize(n, NONE);
        let set = |i: u32| {
            tie.get(self.nodes[i as usize] as usize)
                .copied()
                .unwrap_or(NONE)
        };
        for &i in some {
            self.prev_group[i as usize] = self.group[i as usize];
            self.next[i as usize] = NONE;
            let t = set(i) as usize;
            if t != NONE as usize {
                if set_lead.len() <= t {
                    set_lead.resize(t + 1, NONE);
                }
                set_lead[t] = set_lead[t].min(self.nodes[i as usize]);
            }
        }
        // NOTE: by ascending model number (each member goes right after its lead, so the
        // chains come out descending), whatever the places: see `group`
        for &i in some {
            let t = set(i);
            let lead = if t == NONE {
                i
            } else {
                self.local[set_lead[t as usize] as usize]
            };
            let iu = i as usize;
            if self.group[iu] != lead {
                changed.push((i, self.group[iu]));
                self.group[iu] = lead;
            }
            if lead != i {
                self.next[iu] = self.next[lead as usize];
                self.next[lead as usize] = i;
            }
        }
        for &i in some {
            let t = set(i);
            if t != NONE {
                set_lead[t as usize] = NONE;
            }
        }
    }

    /// Append to `out` the places of the side's copies of the deck nodes of `faces` (`conn`:
    /// the model's connectivity; none when the model is not split), with repeats: the nodes
    /// whose ties and chains change when those faces' interfaces fail or their cracks close or
    /// open.
    fn copies_at(&self, faces: &[FaceId], conn: &[[u32; 8]], chains: &Chains, out: &mut Vec<u32>) {
        for &(e, f) in faces {
            for n in face_nodes(&conn[e as usize], f) {
                for &c in chains.copies(n) {
                    let k = self.local[c as usize];
                    if k != NONE {
                        out.push(k);
                    }
                }
            }
        }
    }

    /// Lead `i` and the other members of its coincident set on the side ([`Side::next`]).
    fn members(&self, i: u32) -> impl Iterator<Item = u32> + '_ {
        std::iter::successors(Some(i), |&k| {
            Some(self.next[k as usize]).filter(|&n| n != NONE)
        })
    }

    /// Mark `faces` (those of them on this side) as on a tight closed crack, or no longer.
    fn set_tight(&mut self, faces: &[FaceId], tight: bool) {
        for id in faces {
            if let Some(&f) = self.present.get(id) {
                self.tight[f as usize] = tight;
            }
        }
    }

    /// Lead `i` is *buried*: every face of its coincident set's members on the side lies on a
    /// tight closed crack (module docs, Buried nodes).
    fn buried(&self, i: u32) -> bool {
        self.members(i)
            .all(|k| self.node_faces.of(k).all(|f| self.tight[f as usize]))
    }

    /// Lead `i`'s surface at positions `x`: its normal is the sum of the area-weighted normals
    /// of the faces of its coincident set's members on the side (the surface of the deck node
    /// it copies), in the order of the member chain. Worked out when a check first needs it
    /// in a step (a few hundred nodes a step on the 2800 ball, against every face's normal
    /// each step before: 1.2% of the step).
    fn frame(&self, i: usize, x: Points) -> NodeFrame {
        NodeFrame::of(self.members(i as u32).flat_map(|k| {
            self.node_faces
                .of(k)
                .map(|f| &self.faces[f as usize])
                // an eroded element's face no longer shapes the surface
                .filter(|f| f.depth > 0.0)
                .map(|f| f.normal_terms(x))
        }))
    }

    /// Add a face unless present (its new nodes are appended to `nodes`); true when added.
    fn add(&mut self, id: FaceId, table: &FaceTable) -> bool {
        match self.present.entry(id) {
            Entry::Occupied(_) => return false,
            Entry::Vacant(e) => e.insert(self.faces.len() as u32),
        };
        self.tight.push(false);
        let nodes = face_nodes(&table.model().conn[id.0 as usize], id.1);
        let (k, depth) = table.stiffness_and_depth(id);
        self.faces.push(Face {
            elem: id.0,
            face: id.1,
            nodes,
            k,
            depth,
        });
        self.boxes.push(Aabb::of_points(&[[0.0; 3]]).into());
        self.spheres.push(Sphere::new([0.0; 3], 0.0));
        for n in nodes {
            if self.local[n as usize] == NONE {
                self.local[n as usize] = self.nodes.len() as u32;
                self.rank.push(self.nodes.len() as u32);
                self.nodes.push(n);
            }
        }
        self.link(self.faces.len() - 1);
        true
    }

    /// The permutation that puts the nodes in space order (Morton order of their positions
    /// `x`, those of the full build): `order[k].1` is the node to go to place k.
    fn space_order(&self, x: Points) -> Vec<(u64, u32)> {
        // minima and maxima (a -0 for +0 changes no cell below: the cell size is taken as +0
        // when the extent is 0), keys in node order, and a sort of (key, place) pairs, which
        // are distinct: the same order on any number of threads
        let b = Aabb::of_finite(self.nodes.len(), |k| x[self.nodes[k as usize] as usize]);
        let h = (b.extent() + 0.0) / ((1u64 << 21) - 1) as f64;
        let cell = |v: f64, lo: f64| -> u64 {
            let q = ((v - lo) / h).floor();
            if q > 0.0 {
                (q as u64).min((1 << 21) - 1)
            } else {
                0 // also NaN, and h = 0
            }
        };
        let mut order = Vec::with_capacity(self.nodes.len());
        order.par_extend(
            self.nodes
                .par_iter()
                .enumerate()
                .with_min_len(NODE_CHUNK)
                .map(|(k, &n)| {
                    let p = x[n as usize];
                    (
                        morton(std::array::from_fn(|d| cell(p[d], b.min[d]))),
                        k as u32,
                    )
                }),
        );
        order.par_sort_unstable();
        order
    }

    /// Apply `order` (place k gets the node at `order[k].1`, each place once) to the arrays
    /// kept per node: `nodes`, `node_faces`, `rank`, and `group` and `next`, which must hold
    /// model numbers, not places, meanwhile (the callers map them). Each new array is
    /// gathered on every thread: the swaps along the permutation's cycles this replaced were
    /// a serial pass with a random access per node, at each full build that orders the nodes.
    fn permute(&mut self, order: &[(u64, u32)]) {
        fn gather<T: Copy + Send + Sync>(v: &[T], order: &[(u64, u32)]) -> Vec<T> {
            (order.par_iter())
                .with_min_len(NODE_CHUNK)
                .map(|&(_, j)| v[j as usize])
                .collect()
        }
        let n = self.nodes.len();
        self.group.resize(n, NONE);
        self.next.resize(n, NONE);
        self.nodes = gather(&self.nodes, order);
        self.rank = gather(&self.rank, order);
        self.group = gather(&self.group, order);
        self.next = gather(&self.next, order);
        self.node_faces.permute(order, |v| gather(v, order));
    }

    /// Boxes and spheres of the faces that have none yet, from positions `x_ref`.
    fn box_new_faces(&mut self, x_ref: Points, margin: f64) {
        let b = self.boxed;
        self.faces[b..]
            .par_iter()
            .zip(&mut self.boxes[b..])
            .zip(&mut self.spheres[b..])
            .with_min_len(NODE_CHUNK)
            .for_each(|((face, bx), sphere)| {
                *bx = search_box(face, x_ref, margin).into();
                let (c, reach) = search_sphere(face, x_ref, margin);
                *sphere = Sphere::new(c, reach);
            });
        self.boxed = self.faces.len();
    }
}

/// The Morton key of a cell of 2^21 per axis: its coordinates' bits interleaved, x lowest
/// ([`Side::space_order`]).
fn morton(c: [u64; 3]) -> u64 {
    let mut key = 0u64;
    for bit in 0..21 {
        for (d, &cd) in c.iter().enumerate() {
            key |= ((cd >> bit) & 1) << (3 * bit + d);
        }
    }
    key
}

/// The search box of a face at positions `x`: its corners' box grown by
/// `depth + 4 INSIDE_TOL r + 1.1 margin` (module docs).
fn search_box(face: &Face, x: Points, margin: f64) -> Aabb {
    let p = face.nodes.map(|n| x[n as usize]);
    let c = scale(add(add(p[0], p[1]), add(p[2], p[3])), 0.25);
    let r = p.iter().map(|q| dist2(*q, c)).fold(0.0, f64::max).sqrt();
    Aabb::of_points(&p).inflated(face.depth + 4.0 * INSIDE_TOL * r + 1.1 * margin)
}

/// The search sphere of a face at positions `x`: centre c and radius
/// `E (r + margin) + depth` (module docs), grown by 1e-9 for rounding.
fn search_sphere(face: &Face, x: Points, margin: f64) -> (Vec3, f64) {
    let p = face.nodes.map(|n| x[n as usize]);
    let c = scale(add(add(p[0], p[1]), add(p[2], p[3])), 0.25);
    let r = p.iter().map(|q| dist2(*q, c)).fold(0.0, f64::max).sqrt();
    let reach = (penalty::WEIGHT_SUM * (r + margin) + face.depth) * (1.0 + 1e-9);
    (c, reach)
}

/// A search sphere kept in single precision (16 bytes instead of 32): the centre rounded, the
/// radius grown by the centre's rounding and rounded up, so that it holds the sphere it was
/// made from. A larger sphere keeps more candidates and makes them due sooner
/// ([`first_due`]); neither changes what a check finds.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
struct Sphere {
    c: [f32; 3],
    r2: f32,
}

impl Sphere {
    fn new(c: Vec3, reach: f64) -> Self {
        let c32 = c.map(|v| v as f32);
        let moved = dist2(c, c32.map(f64::from)).sqrt();
        let r = crate::math::f32_up(reach + moved);
        Self {
            c: c32,
            r2: crate::math::f32_up(f64::from(r) * f64::from(r)),
        }
    }

    /// Centre and radius^2.
    #[inline]
    fn get(&self) -> (Vec3, f64) {
        (self.c.map(f64::from), f64::from(self.r2))
    }
}

/// The result of one node's check.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug)]
struct Hit {
    /// Face index in the face side, or NONE.
    face: u32,
    w: [f64; 4],
    /// Total force on the node (normal + friction).
    f: Vec3,
    /// Engaged penetration and offset ([`engagement`]); the stiffness is the pair's, of the
    /// node and this face (faces keep their index in a side, so `face` names the same face in
    /// later steps).
    engaged: f64,
    offset: f64,
    /// `|f_n| = -k engaged` (0 without a face), k the pair's ([`FaceTable::pair_stiffness`]),
    /// as the check worked it out: the step's loop and the scatter read it instead of looking
    /// the stiffness up again.
    fn_mag: f64,
}

impl Default for Hit {
    fn default() -> Self {
        Self {
            face: NONE,
            w: [0.0; 4],
            f: [0.0; 3],
            engaged: 0.0,
            offset: 0.0,
            fn_mag: 0.0,
        }
    }
}

/// The nodes of one side against the faces of one side.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
struct Pass {
    node_side: usize,
    face_side: usize,
    /// The face side's faces `..base` and the node side's nodes `..nbase`, at the last full
    /// build.
    grid: BucketGrid,
    nbase: usize,
    /// The faces and nodes that joined since (indices relative to `base` and `nbase`), added
    /// at each incremental search, in cells of `grid`'s smallest size. Not kept in a restart
    /// file: made again from the boxes and positions at the next search.
    #[serde(skip)]
    extra: JoinGrid,
    /// Candidate faces of each node of the node side and their [`Sched`] (a few inline in the
    /// schedule, the others in its room).
    cand: CandLists,
    /// The earliest `due` of each node's candidates ([`Sched::next_due`]), or -inf when the
    /// node must be checked at the next step (its candidates or contact changed outside a
    /// check). A node whose `next` is not due is not looked at: it tests nothing, and it is
    /// out of contact (a node in contact has its face due at every step).
    next: Vec<f32>,
    /// Scratch: the nodes an incremental search renews.
    mark: Vec<bool>,
    /// The hit and the tangential force of the last step of each node in contact.
    touching: Touching,
}

impl Pass {
    fn new(node_side: usize, face_side: usize, nodes: usize) -> Self {
        Self {
            node_side,
            face_side,
            grid: BucketGrid::default(),
            nbase: 0,
            extra: JoinGrid::default(),
            cand: CandLists::new(NODE_CHUNK, nodes),
            next: vec![f32::NEG_INFINITY; nodes],
            mark: vec![false; nodes],
            touching: Touching::new(NODE_CHUNK, nodes),
        }
    }
}

thread_local! {
    /// Scratch of [`Query::run`]: a node's old candidates.
    static OLD: std::cell::RefCell<Vec<Cand>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A full build or an incremental search ([`Query::run`]).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug)]
enum SearchKind {
    /// A full build: the motion bound restarts at zero, so `rebase` (the bound before) is
    /// subtracted from the `due` kept; the faces' spheres are of the current positions, made
    /// with `margin`, so a new pair is first due at its sphere clearance ([`first_due`]).
    Full { rebase: f64, margin: f64 },
    /// An incremental search: a `due` kept stays; a new pair is due at once.
    Incremental,
}

/// What a search for candidates reads.
struct Query<'a> {
    grid: &'a BucketGrid,
    extra: &'a JoinGrid,
    /// The node side's nodes, the face side.
    nodes: &'a [u32],
    /// The lead of each node's coincident set ([`Side::group`]).
    group: &'a [u32],
    ns: &'a Side,
    fs: &'a Side,
    x_ref: Points<'a>,
    tie: &'a [u32],
    chains: &'a Chains,
    /// Full or incremental search.
    kind: SearchKind,
    /// Candidates due by this are hot.
    hot_until: f64,
}

impl Query<'_> {
    /// Node i's candidates from the grids: faces whose box and sphere (built from `x_ref`)
    /// hold the node's `x_ref` position and that hold neither the node nor a node tied to it,
    /// nor a node it is chained to through closed cracks ([`closure::Chains`]).
    /// A face it had keeps its `due` (less the bound before a full build): the bound on a
    /// pair holds whether or not the pair is listed; a new one is due at once, or at a full
    /// build at its sphere clearance (the later of the two for a face it had).
    /// A node that is not its set's lead gets no candidates. The node is checked at the next
    /// step (`next` = -inf, [`Pass::next`]). `sched` and `old` are the node's schedule and
    /// room ([`cand_lists`]); its new candidates are appended to `new` and their schedule
    /// returned.
    fn run(
        &self,
        i: usize,
        mut sched: Sched,
        old: &mut [Cand],
        next: &mut f32,
        new: &mut Vec<Cand>,
    ) -> Sched {
        *next = f32::NEG_INFINITY;
        sched.gather(old);
        if self.group[i] != i as u32 || self.ns.buried(i as u32) {
            return Sched::default();
        }
        let s = self.nodes[i];
        let p = self.x_ref[s as usize];
        let fs = self.fs;
        // the node's coincident set (NONE: untied, then only its own faces are left out)
        let set = self.tie.get(s as usize).copied().unwrap_or(NONE);
        let keep = |f: u32| {
            let (c, r2) = fs.spheres[f as usize].get();
            let held = |a: u32| {
                a == s || (set != NONE && self.tie[a as usize] == set) || self.chains.held(a, s)
            };
            // an eroded element's face (depth 0, `ContactSet::erode`) is no candidate
            let face = &fs.faces[f as usize];
            dist2(p, c) <= r2 && face.depth > 0.0 && !face.nodes.iter().any(|&a| held(a))
        };
        // the old list, by face, in this thread's scratch (sized by the first searches)
        let start = new.len();
        OLD.with_borrow_mut(|sorted| {
            sorted.clear();
            sorted.extend_from_slice(old);
            sorted.sort_unstable_by_key(|c| c.face);
            let cand = |f: u32| Cand {
                face: f,
                due: match self.kind {
                    SearchKind::Full { margin, .. } => {
                        first_due(fs.spheres[f as usize].get(), p, margin)
                    }
                    SearchKind::Incremental => f32::NEG_INFINITY,
                },
            };
            self.grid
                .faces_at(p, &fs.boxes, keep, |f| new.push(cand(f)));
            let base = fs.base as u32;
            self.extra.faces_at(
                p,
                &fs.boxes[fs.base..],
                |f| keep(f + base),
                |f| new.push(cand(f + base)),
            );
            let rebase = match self.kind {
                SearchKind::Full { rebase, .. } => rebase,
                SearchKind::Incremental => 0.0,
            };
            for c in new[start..].iter_mut() {
                if let Ok(j) = sorted.binary_search_by_key(&c.face, |c| c.face) {
                    c.due = c.due.max(schedule::down(sorted[j].due as f64 - rebase));
                }
            }
        });
        sched.split(&mut new[start..], self.hot_until);
        sched
    }
}

/// When a pair listed by a full build is first due: its clearance from the face's search
/// sphere `(c, reach^2)` (made with `margin` at the current positions, [`search_sphere`], as
/// stored, [`Sphere::get`]), 0 (at once) when the node `p` is within its reach less `E margin`.
///
/// A contact point is `sum w_a x_a` with `sum w_a = 1` and `sum |w_a| <= E`
/// ([`penalty::WEIGHT_SUM`]), so it lies within `E r` of the centroid c (r the largest
/// centroid-corner distance), and contact needs the node within `depth` of it: `|p - c| <=
/// E r + depth = reach - E margin`. A motion delta of the corners relative to the node moves
/// the point by at most `E delta`, so the pair stays apart while
/// `delta < (|p - c| - E r - depth) / E` (the sphere part of [`Cull::clearance`]; the same
/// rounding slack). Pairs are tested at once otherwise, so a full build re-tests every pair
/// it lists anew: on the fracturing 2800-element ball that was a third of all the tests.
fn first_due((c, reach2): (Vec3, f64), p: Vec3, margin: f64) -> f32 {
    let e = penalty::WEIGHT_SUM;
    let reach = reach2.sqrt();
    let dist = dist2(p, c).sqrt();
    let clear = (dist - (reach - e * margin)) / e - 2e-7 * (dist + reach);
    if clear > 0.0 {
        schedule::down(clear)
    } else {
        f32::NEG_INFINITY
    }
}

/// One contact definition.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub struct Contact {
    /// Deck ordinal.
    pub id: i64,
    pub single_surface: bool,
    pub friction: Friction,
    sides: Vec<Side>,
    passes: Vec<Pass>,
    /// Positions of all model nodes at the last full build, stored as the solver's positions
    /// are (per slot of the coincident sets, or per node, [`crate::node_values`]; read them
    /// through the step's positions, [`NodeValues::over`]). A slot made since then gets its
    /// set's ([`ContactSet::sets_split`]): its members were there.
    x_ref: Vec<Vec3>,
    /// Positions at the last step, stored as `x_ref` ([`Contact::track`]).
    x_last: Vec<Vec3>,
    /// The entries of the positions that hold a node of a side: the ones whose motion
    /// [`Contact::track`] watches (a slot made since the last step, that of the slot it split
    /// from).
    watched: Vec<bool>,
    margin: f64,
    /// Motion bound: the sum over the steps since the last full build of a bound on how far
    /// any two nodes of the definition moved relative to each other in the step; and that
    /// bound for the last step.
    motion: f64,
    step_motion: f64,
    /// A full build is due (first step, ties changed without faces named).
    dirty: bool,
    /// Faces of interfaces that failed since the last step: the nodes near them get new
    /// candidate lists at the next step.
    pending: Vec<FaceId>,
    /// Closed cracks ([`closure`]), in the order their interfaces failed, and the copies
    /// they chain together.
    closures: Vec<Closure>,
    chains: Chains,
    scratch: Vec<u32>,
    region: Vec<Aabb>,
    /// Scratch of [`Side::regroup`]: the lead of each coincident set, and the nodes whose lead
    /// changed, per side.
    set_lead: Vec<u32>,
    regrouped: Vec<Vec<(u32, u32)>>,
    /// Scratch of [`Contact::regroup_pending`]: the nodes of a side to regroup.
    some: Vec<u32>,
    rebuilds: u64,
    updates: u64,
    released: u64,
    /// Seconds in each phase of the steps (not kept in restart files).
    #[serde(skip)]
    times: ContactTimes,
    /// Test every candidate every step and keep them all (tests compare with it).
    #[cfg(test)]
    exhaustive: bool,
}

/// The box of some displacements: `diag` bounds the distance between any two of them.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug)]
struct Spread {
    min: Vec3,
    max: Vec3,
    finite: bool,
}

impl Default for Spread {
    fn default() -> Self {
        Self {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
            finite: true,
        }
    }
}

impl Spread {
    #[inline]
    fn add(&mut self, d: Vec3) {
        for ((lo, hi), v) in self.min.iter_mut().zip(&mut self.max).zip(d) {
            *lo = lo.min(v);
            *hi = hi.max(v);
        }
        // a NaN or infinite component makes the sum non-finite (min and max skip NaN)
        self.finite &= (d[0] + d[1] + d[2]).is_finite();
    }
    fn join(mut self, o: Self) -> Self {
        for k in 0..3 {
            self.min[k] = self.min[k].min(o.min[k]);
            self.max[k] = self.max[k].max(o.max[k]);
        }
        self.finite &= o.finite;
        self
    }
    /// The box's diagonal (0 when empty, infinite when a displacement was not finite).
    fn diag(&self) -> f64 {
        if !self.finite {
            return f64::INFINITY;
        }
        let mut d2 = 0.0;
        for k in 0..3 {
            if self.max[k] >= self.min[k] {
                d2 += (self.max[k] - self.min[k]) * (self.max[k] - self.min[k]);
            }
        }
        d2.sqrt()
    }
}

impl Contact {
    fn new(def: &ContactDef, b: &Build) -> Result<Self, String> {
        let nn = b.model.num_nodes();
        let side = |s| -> Result<Side, String> {
            let ids = side_faces(b.model, b.deck_conn, b.origin, b.exterior, s)?;
            Ok(Side::new(&ids, covered_parts(b.model, s), b.table, nn))
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
        } else if def.one_way {
            &[(0, 1)]
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
                sum += hex8::quad_area(p[0], p[1], p[2], p[3]).sqrt();
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
            x_ref: Vec::new(),
            x_last: Vec::new(),
            watched: Vec::new(),
            margin: MARGIN_FRACTION * size,
            motion: 0.0,
            step_motion: 0.0,
            dirty: true,
            pending: Vec::new(),
            closures: Vec::new(),
            chains: Chains::new(b.origin, b.model.x0.origin_shared()),
            scratch: Vec::new(),
            region: Vec::new(),
            set_lead: Vec::new(),
            regrouped: Vec::new(),
            some: Vec::new(),
            rebuilds: 0,
            updates: 0,
            released: 0,
            times: ContactTimes::default(),
            #[cfg(test)]
            exhaustive: false,
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
    /// Full candidate-list builds so far.
    pub fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// Add the faces to the sides that cover their parts (nodes appended, with empty friction
    /// history) and remember them: at the next step the nodes near them are searched again.
    fn activate(&mut self, ids: &[FaceId], table: &FaceTable) -> usize {
        let mut added = 0;
        for (si, side) in self.sides.iter_mut().enumerate() {
            let before = side.nodes.len();
            for &id in ids {
                let part = table.model().elem_part[id.0 as usize] as usize;
                if side.parts.get(part).copied().unwrap_or(false) && side.add(id, table) {
                    added += 1;
                }
            }
            let n = side.nodes.len();
            debug_assert!(side.marked <= before);
            for pass in self.passes.iter_mut().filter(|p| p.node_side == si) {
                pass.cand.resize(n);
                pass.next.resize(n, f32::NEG_INFINITY);
                pass.mark.resize(n, false);
                pass.touching.resize(n);
            }
        }
        self.pending.extend_from_slice(ids);
        added
    }

    /// Close a crack whose faces are both on this definition's surfaces where a pass tests
    /// one's nodes against the other ([`closure`]): its node pairs are chained. Call after its
    /// faces were activated. Its deck nodes are relabelled at the next step either way (their
    /// ties broke).
    fn close(&mut self, crack: &Crack, table: &FaceTable) {
        for &n in &crack.nodes[0] {
            self.chains.touch(n);
        }
        let [fa, fb] = crack.faces;
        let tested = self.passes.iter().any(|p| {
            let (ns, fs) = (&self.sides[p.node_side], &self.sides[p.face_side]);
            (ns.present.contains_key(&fa) && fs.present.contains_key(&fb))
                || (ns.present.contains_key(&fb) && fs.present.contains_key(&fa))
        });
        if !tested {
            return;
        }
        // A's nodes in its outward order, each with its partner on B
        let a = face_nodes(&table.model().conn[fa.0 as usize], fa.1);
        let mut b = [NONE; 4];
        for (j, &n) in a.iter().enumerate() {
            if let Some(k) = crack.nodes[0].iter().position(|&m| m == n) {
                b[j] = crack.nodes[1][k];
            }
        }
        if b.contains(&NONE) {
            return; // not the nodes of face A: no pairs to close
        }
        for k in 0..4 {
            self.chains.link(a[k], b[k], true);
        }
        // each pair as the two node-to-face springs at it: a_k against B, b_k against A (the
        // copies of one deck node have the same stiffness; the softest of the four pairs for
        // all)
        let soft = (0..4)
            .min_by(|&i, &j| {
                let (ki, kj) = (table.node_stiffness(a[i]), table.node_stiffness(a[j]));
                ki.total_cmp(&kj)
            })
            .unwrap_or(0);
        let k = table.pair_stiffness(table.stiffness(fb), a[soft])
            + table.pair_stiffness(table.stiffness(fa), b[soft]);
        for side in &mut self.sides {
            side.set_tight(&crack.faces, true);
        }
        self.closures.push(Closure::new(crack.faces, a, b, k));
    }

    /// The closed cracks at this step ([`closure`]), in parallel: those whose faces no longer
    /// lie on each other are released (their faces go back to the search, which renews the
    /// lists around them at this step); the others get their forces. Only a step in which
    /// some crack was released or changed its tightness passes over the list again (most
    /// steps change none: that serial pass would grow with the cracks).
    fn step_closures(&mut self, inp: &StepInput) {
        let Self {
            closures,
            scratch,
            friction,
            ..
        } = self;
        scratch.clear();
        scratch.resize(closures.len(), 0);
        let any = closures
            .par_iter_mut()
            .zip(scratch.par_iter_mut())
            .with_min_len(NODE_CHUNK)
            .map(|(c, out)| {
                let was = c.tight;
                let released = c.step(inp.x, inp.v, inp.dt_prev, friction);
                *out = released as u32 | ((c.tight != was) as u32) << 1;
                *out
            })
            .reduce(|| 0, |a, b| a | b);
        if any == 0 {
            return;
        }
        let flags = std::mem::take(&mut self.scratch);
        self.settle_closures(&flags);
        self.scratch = flags;
    }

    /// What the closed cracks' step found, one flag per crack (bit 0: released, bit 1: its
    /// tightness changed): the released ones leave (their pairs unchained, their faces back
    /// to the search around them), and a crack that opened stops burying its nodes (its faces
    /// are searched around at once, as around a failed face; one that shut buries them from
    /// their next search on).
    fn settle_closures(&mut self, flags: &[u32]) {
        let Self {
            closures,
            chains,
            pending,
            released,
            sides,
            ..
        } = self;
        let mut flags = flags.iter();
        closures.retain(|c| {
            let flag = flags.next().copied().unwrap_or(0);
            if flag & 1 == 0 {
                if flag & 2 != 0 {
                    for side in sides.iter_mut() {
                        side.set_tight(&c.faces, c.tight);
                    }
                    if !c.tight {
                        pending.extend_from_slice(&c.faces);
                    }
                }
                return true;
            }
            for k in 0..4 {
                chains.link(c.a[k], c.b[k], false);
            }
            for side in sides.iter_mut() {
                side.set_tight(&c.faces, false);
            }
            pending.extend_from_slice(&c.faces);
            *released += 1;
            false
        });
    }

    /// One pass over the positions' entries (per slot of the coincident sets, or per node):
    /// the motion bound grows by the diagonal of the box of the watched entries' displacements
    /// over the last step (those of the sides' nodes: a set's members share its entry and move
    /// as one, module docs, Search); returns the diagonal of the box of their displacements
    /// since the last full build. Every entry's last position is then the current one. A slot
    /// made since the last step starts from that of the set it split from
    /// ([`Contact::sets_split`]): its members were there, so its displacement is theirs. The
    /// entries are read in sequence; a pass over the sides' nodes read them by node instead.
    fn track(&mut self, x: Points) -> f64 {
        let e = x.entries();
        // every entry has its last and reference positions ([`Contact::watch_new_nodes`]
        // covered them at this step)
        debug_assert!(self.x_last.len() == e.len() && self.x_ref.len() == e.len());
        const CHUNK: usize = 4 * NODE_CHUNK;
        let (step, since) = e
            .par_chunks(CHUNK)
            .zip(self.x_last.par_chunks_mut(CHUNK))
            .zip(self.x_ref.par_chunks(CHUNK))
            .zip(self.watched.par_chunks(CHUNK))
            .map(|(((p, last), r), w)| {
                let (mut a, mut b) = (Spread::default(), Spread::default());
                for k in 0..p.len() {
                    if w[k] {
                        a.add(sub(p[k], last[k]));
                        b.add(sub(p[k], r[k]));
                    }
                    last[k] = p[k];
                }
                (a, b)
            })
            .reduce(
                || (Spread::default(), Spread::default()),
                |(a1, b1), (a2, b2)| (a1.join(a2), b1.join(b2)),
            );
        // 1e-9: the rounding of the displacements and of the sum, with room to spare
        self.step_motion = step.diag() * (1.0 + 1e-9);
        self.motion += self.step_motion;
        since.diag()
    }

    /// Entries of the positions not yet known (the first step's, and in per-node storage
    /// none after) start where they are, unwatched.
    fn cover(&mut self, e: &[Vec3]) {
        for v in [&mut self.x_last, &mut self.x_ref] {
            if v.len() < e.len() {
                let n = v.len();
                v.extend_from_slice(&e[n..]);
            }
        }
        self.watched.resize(e.len().max(self.watched.len()), false);
    }

    /// The entries of the nodes that joined the sides since the last step are watched from
    /// now on.
    fn watch_new_nodes(&mut self, x: Points) {
        self.cover(x.entries());
        for side in &mut self.sides {
            for &n in &side.nodes[side.marked..] {
                self.watched[x.entry_of(n as usize)] = true;
            }
            side.marked = side.nodes.len();
        }
    }

    /// Coincident sets split after the last step: each new slot `(new, from)`, numbered on
    /// from the last, gets the last position, the reference position and the watch of the
    /// slot it split from (positions stored per slot; a slot already known is left).
    fn sets_split(&mut self, born: &[(u32, u32)]) {
        for &(new, from) in born {
            let (new, from) = (new as usize, from as usize);
            if new == self.x_ref.len() {
                self.x_ref.push(self.x_ref[from]);
            }
            if new == self.x_last.len() {
                self.x_last.push(self.x_last[from]);
            }
            if new == self.watched.len() {
                self.watched.push(self.watched[from]);
            }
        }
    }

    /// New candidate lists of every node from the current positions; the motion bound starts
    /// again at zero. The leads are found again for every node only when the ties changed
    /// otherwise than at the faces pending since the last search (`dirty`); else for the
    /// copies at those faces, as an incremental search would ([`Contact::regroup_pending`];
    /// `conn`: the model's connectivity): the other sets did not change, and a regroup of
    /// every node was a serial pass over them at each full build.
    fn rebuild(&mut self, x: Points, tie: &[u32], conn: &[[u32; 8]]) {
        self.x_ref.clear();
        self.x_ref.extend_from_slice(x.entries());
        // the watched entries again, from the sides' nodes: a slot born of a split is watched
        // as its set was until now, whether or not its nodes are on a side
        self.watched.fill(false);
        for side in &self.sides {
            for &n in &side.nodes {
                self.watched[x.entry_of(n as usize)] = true;
            }
        }
        self.reorder(x);
        if self.dirty {
            self.regroup(tie);
        } else {
            self.regroup_pending(tie, conn);
        }
        let rebase = self.motion;
        self.motion = 0.0;
        let hot_until = HOT_STEPS * self.step_motion;
        let m = self.margin;
        for side in &mut self.sides {
            side.base = side.faces.len();
            side.boxed = 0;
            side.box_new_faces(x, m);
        }
        let Self {
            sides,
            passes,
            x_ref,
            chains,
            ..
        } = self;
        for pass in passes.iter_mut() {
            let ns = &sides[pass.node_side];
            let fs = &sides[pass.face_side];
            let nodes = &ns.nodes;
            pass.grid
                .build_with(&fs.boxes, nodes.len(), |q| x[nodes[q as usize] as usize]);
            pass.nbase = ns.nodes.len();
            pass.extra.reset(pass.grid.cell_size());
            let Pass {
                grid,
                extra,
                cand,
                next,
                ..
            } = pass;
            let q = Query {
                grid,
                extra,
                nodes: &ns.nodes,
                group: &ns.group,
                ns,
                fs,
                x_ref: x.over(x_ref),
                tie,
                chains,
                kind: SearchKind::Full { rebase, margin: m },
                hot_until,
            };
            cand.chunks()
                .zip(next.par_chunks_mut(NODE_CHUNK))
                .enumerate()
                .for_each(|(c, (mut lists, next))| {
                    lists.search_all(|k, sched, old, new| {
                        q.run(c * NODE_CHUNK + k, sched, old, &mut next[k], new)
                    })
                });
        }
        self.pending.clear();
        self.dirty = false;
        self.rebuilds += 1;
    }

    /// The coincident sets' leads of every side under `tie` ([`Side::regroup`]).
    fn regroup(&mut self, tie: &[u32]) {
        self.regroup_where(tie, None);
    }

    /// [`Contact::regroup`] of only the copies of the deck nodes of the pending faces (`conn`:
    /// the model's connectivity) when the model is split: only their ties broke, and the nodes
    /// that joined are among them; of every node otherwise. This rests on two things the
    /// solver keeps: every tie that breaks comes with its interface's faces named to
    /// [`ContactSet::activate`], and a coincident set only holds copies of one deck node (the
    /// `origin` given to [`ContactSet::new`] is that of the split behind `tie`). The unit tests
    /// check each such regroup against a regroup of every node.
    fn regroup_pending(&mut self, tie: &[u32], conn: &[[u32; 8]]) {
        self.regroup_where(tie, Some(conn));
    }

    fn regroup_where(&mut self, tie: &[u32], pending_in: Option<&[[u32; 8]]>) {
        self.regrouped.resize_with(self.sides.len(), Vec::new);
        let Self {
            sides,
            regrouped,
            set_lead,
            some,
            pending,
            chains,
            passes,
            ..
        } = self;
        for (si, (side, changed)) in sides.iter_mut().zip(regrouped.iter_mut()).enumerate() {
            changed.clear();
            match pending_in.filter(|_| chains.is_split()) {
                Some(conn) => {
                    some.clear();
                    side.copies_at(pending, conn, chains, some);
                    // by model number (one place per model number: duplicates stay adjacent)
                    some.sort_unstable_by_key(|&k| side.nodes[k as usize]);
                    some.dedup();
                    #[cfg(test)]
                    let mut full = side.clone();
                    side.regroup_some(some, tie, set_lead, changed);
                    // tests: the same leads and member chains as a regroup of every node
                    #[cfg(test)]
                    {
                        full.regroup(tie, &mut Vec::new(), &mut Vec::new(), &mut Vec::new());
                        assert_eq!(full.group, side.group, "regroup_some: leads");
                        assert_eq!(full.next, side.next, "regroup_some: member chains");
                    }
                }
                None => side.regroup(tie, set_lead, changed, some),
            }
            for &(i, old) in changed.iter() {
                // the set's normal changed: the facing part of its clearances is void
                side.renewed.push(i);
                if old != NONE {
                    side.renewed.push(old);
                }
                if side.group[i as usize] != i {
                    continue;
                }
                // a new lead carries on its set's contact (engagement and friction history):
                // it sits where the set's lead before sat (that of any member that was on the
                // side: the node itself may have just joined), on the same faces
                let Some(from) = side
                    .members(i)
                    .map(|k| side.prev_group[k as usize])
                    .find(|&g| g != NONE)
                else {
                    continue;
                };
                if from != i {
                    for pass in passes.iter_mut().filter(|p| p.node_side == si) {
                        let (hit, ft) = match pass.touching.get(from as usize) {
                            Some(t) => (t.hit, t.ft),
                            None => (Hit::default(), [0.0; 3]),
                        };
                        pass.touching.set(i as usize, hit, ft);
                        pass.next[i as usize] = f32::NEG_INFINITY;
                    }
                }
            }
        }
    }

    /// Put each side's nodes in space order (with everything kept per node; the candidate
    /// lists are dropped, the full build that follows makes them again), when more than
    /// 1/[`REORDER`] of them joined since the last ordering: the nodes move little against each
    /// other between full builds, while an ordering costs a sort and a pass over every array
    /// of the nodes (a fifth of a full build on the 2800 ball). The order is for the caches
    /// and the threads' shares only: forces are summed by rank, leads are the lowest model
    /// numbers and member chains go by model number, so the results do not depend on it
    /// (`member_chains_do_not_depend_on_the_places`).
    fn reorder(&mut self, x: Points) {
        for (si, side) in self.sides.iter_mut().enumerate() {
            let n = side.nodes.len();
            if n == side.ordered || (side.ordered > 0 && n <= side.ordered + side.ordered / REORDER)
            {
                continue;
            }
            side.ordered = n;
            // scratch allocated here and freed at the end: a reordering comes only with a full
            // build after many nodes joined, and keeping its 17 bytes a node took 1.3 MB of the
            // 20,000-element ball's peak
            let order = side.space_order(x);
            // the renewed nodes, the leads and the member chains by model number while the
            // places move
            for i in side.renewed.iter_mut() {
                *i = side.nodes[*i as usize];
            }
            side.group.resize(n, NONE);
            side.next.resize(n, NONE);
            for g in (side.group.iter_mut().chain(&mut side.next)).filter(|g| **g != NONE) {
                *g = side.nodes[*g as usize];
            }
            side.permute(&order);
            for pass in self.passes.iter_mut().filter(|p| p.node_side == si) {
                let Pass { cand, touching, .. } = pass;
                // the full build that follows lists every node again; the dues kept would only
                // save tests of pairs found apart before (a new pair is first due at its sphere
                // clearance, [`first_due`], as sound, and sooner)
                cand.forget();
                touching.permute(&order);
            }
            for (k, &n) in side.nodes.iter().enumerate() {
                side.local[n as usize] = k as u32;
            }
            for i in side.renewed.iter_mut() {
                *i = side.local[*i as usize];
            }
            for g in (side.group.iter_mut().chain(&mut side.next)).filter(|g| **g != NONE) {
                *g = side.local[*g as usize];
            }
        }
    }

    /// Faces joined or ties broke around the pending faces: the nodes whose reference position
    /// lies in a pending face's search box get new candidate lists (against the main grid and
    /// a grid of the faces that joined since the last full build), as a full build at that
    /// time would have given them. Returns false (nothing done) when so much has joined that a
    /// full build is better.
    fn update(&mut self, x: Points, tie: &[u32], table: &FaceTable) -> bool {
        let too_many = |extra: usize, base: usize| 4 * extra > base.max(256);
        for p in &self.passes {
            let (ns, fs) = (&self.sides[p.node_side], &self.sides[p.face_side]);
            if too_many(fs.faces.len() - fs.base, fs.base)
                || too_many(ns.nodes.len() - p.nbase, p.nbase)
            {
                return false;
            }
        }
        self.regroup_pending(tie, &table.model().conn);
        let m = self.margin;
        let hot_until = self.motion + HOT_STEPS * self.step_motion;
        let Self {
            sides,
            passes,
            x_ref,
            pending,
            scratch,
            region,
            regrouped,
            chains,
            ..
        } = self;
        let x_ref = x.over(x_ref);
        for side in sides.iter_mut() {
            side.box_new_faces(x_ref, m);
        }
        region.clear();
        for &id in pending.iter() {
            let face = Face {
                elem: id.0,
                face: id.1,
                nodes: face_nodes(&table.model().conn[id.0 as usize], id.1),
                k: 0.0,
                depth: table.depth(id),
            };
            // rounded out as the faces' stored boxes are, so the nodes searched again are
            // those the grids would list
            region.push(Aabb32::from(search_box(&face, x_ref, m)).wide());
        }
        for pass in passes.iter_mut() {
            let ns = &sides[pass.node_side];
            let fs = &sides[pass.face_side];
            let nbase = pass.nbase;
            let new_nodes = &ns.nodes[nbase..];
            let point = |q: u32| x_ref[new_nodes[q as usize] as usize];
            pass.extra.keep_cells(pass.grid.cell_size());
            pass.extra.add_faces(&fs.boxes[fs.base..]);
            pass.extra.add_nodes(new_nodes.len(), point);
            // the nodes in the regions, on every thread where there are many regions (the
            // list is sorted below: its order does not matter)
            let (grid, extra) = (&pass.grid, &pass.extra);
            let nodes_in = |out: &mut Vec<u32>, b: &Aabb| {
                grid.points_in(b, |q| x_ref[ns.nodes[q as usize] as usize], out);
                let start = out.len();
                extra.points_in(b, point, out);
                for q in &mut out[start..] {
                    *q += nbase as u32;
                }
            };
            scratch.clear();
            if region.len() < PAR_REGIONS {
                for b in region.iter() {
                    nodes_in(scratch, b);
                }
            } else {
                let mut found = region
                    .par_iter()
                    .with_min_len(PAR_REGIONS / 2)
                    .fold(Vec::new, |mut out, b| {
                        nodes_in(&mut out, b);
                        out
                    })
                    .reduce(Vec::new, |mut a, b| {
                        a.extend_from_slice(&b);
                        a
                    });
                scratch.append(&mut found);
            }
            // nodes that became or stopped being leads, and every copy of the pending faces'
            // deck nodes: their ties and chains changed, so which faces hold a node tied or
            // chained to them did (`Query::run` leaves those out), and a copy split off
            // earlier need not lie in these faces' boxes (module docs, Search)
            scratch.extend(regrouped[pass.node_side].iter().map(|&(i, _)| i));
            ns.copies_at(pending, &table.model().conn, chains, scratch);
            scratch.sort_unstable();
            scratch.dedup();
            let Pass {
                grid,
                extra,
                cand,
                next,
                mark,
                ..
            } = pass;
            let q = Query {
                grid,
                extra,
                nodes: &ns.nodes,
                group: &ns.group,
                ns,
                fs,
                x_ref,
                tie,
                chains,
                kind: SearchKind::Incremental,
                hot_until,
            };
            if scratch.len() < NODE_CHUNK {
                for &i in scratch.iter() {
                    let i = i as usize;
                    let (mut lists, k) = cand.chunk_of(i);
                    lists.search_one(k, |sched, old, new| q.run(i, sched, old, &mut next[i], new));
                }
            } else {
                for &i in scratch.iter() {
                    mark[i as usize] = true;
                }
                cand.chunks()
                    .zip(next.par_chunks_mut(NODE_CHUNK))
                    .zip(mark.par_chunks_mut(NODE_CHUNK))
                    .enumerate()
                    .for_each(|(c, ((mut lists, next), mark))| {
                        for k in 0..lists.len() {
                            if mark[k] {
                                mark[k] = false;
                                lists.search_one(k, |sched, old, new| {
                                    let i = c * NODE_CHUNK + k;
                                    q.run(i, sched, old, &mut next[k], new)
                                });
                            }
                        }
                    });
            }
        }
        pending.clear();
        self.updates += 1;
        true
    }

    /// Nodes whose faces changed: their normal did, so the facing part of their clearances is
    /// void; all their candidates are due.
    fn renew(&mut self) {
        for (si, side) in self.sides.iter_mut().enumerate() {
            for pass in self.passes.iter_mut().filter(|p| p.node_side == si) {
                for &i in &side.renewed {
                    // (a node without a lead yet gets one, and new lists, at the next search)
                    let i = side.group.get(i as usize).copied().unwrap_or(i) as usize;
                    let (mut lists, k) = pass.cand.chunk_of(i);
                    lists.with(k, |sched, room| sched.renew(room));
                    pass.next[i] = f32::NEG_INFINITY;
                }
            }
            side.renewed.clear();
        }
    }

    /// One step of this definition: forces into `acc`; the resultants and whether the
    /// candidates were rebuilt in full.
    fn compute(&mut self, inp: &StepInput, acc: &mut NodalForces) -> (ContactForce, bool) {
        let mut t = Instant::now();
        self.watch_new_nodes(inp.x);
        let spread = self.track(inp.x);
        lap(&mut t, &mut self.times.tracking);
        self.step_closures(inp);
        lap(&mut t, &mut self.times.closed_cracks);
        let mut out = ContactForce {
            id: self.id,
            ..Default::default()
        };
        // NOTE: the closed cracks' forces go in first, on one thread (serially, in the order
        // the cracks closed), while the searches and the node checks run on the others; then
        // the node-to-face pairs'. The order is the same on any number of threads.
        let closures = std::mem::take(&mut self.closures);
        let frictionless = self.friction.is_frictionless();
        let mut scattered = 0.0;
        let ((), rebuilt) = rayon::join(
            || {
                let mut t = Instant::now();
                scatter_closures(&closures, frictionless, acc, &mut out);
                lap(&mut t, &mut scattered);
            },
            || self.search_and_check(inp, spread),
        );
        self.times.closed_forces += scattered;
        self.closures = closures;
        let mut t = Instant::now();
        self.scatter_pairs(acc, &mut out);
        lap(&mut t, &mut self.times.pair_forces);
        (out, rebuilt)
    }

    /// The searches this step needs (an incremental one around new faces, or a full build)
    /// and the check of every node with a candidate due, each pass's contacts then in its
    /// [`Touching`]; whether the candidates were rebuilt in full.
    fn search_and_check(&mut self, inp: &StepInput, spread: f64) -> bool {
        let mut t = Instant::now();
        self.chains.refresh(inp.tie);
        let mut rebuilt = self.dirty || spread > self.margin || self.motion > REBASE * self.margin;
        if !rebuilt && !self.pending.is_empty() && !self.update(inp.x, inp.tie, inp.table) {
            rebuilt = true;
        }
        lap(&mut t, &mut self.times.incremental);
        if rebuilt {
            self.rebuild(inp.x, inp.tie, &inp.table.model().conn);
            lap(&mut t, &mut self.times.full_builds);
        }
        self.renew();
        #[cfg(test)]
        let exhaustive = self.exhaustive;
        #[cfg(not(test))]
        let exhaustive = false;
        let Self {
            sides,
            passes,
            friction,
            motion,
            step_motion,
            ..
        } = self;
        for pass in passes.iter_mut() {
            let ns = &sides[pass.node_side];
            let fs = &sides[pass.face_side];
            let Pass {
                cand,
                next,
                touching,
                ..
            } = pass;
            // exhaustive: every candidate is due and hot
            let (motion, hot_until) = if exhaustive {
                (f64::INFINITY, f64::INFINITY)
            } else {
                (*motion, *motion + HOT_STEPS * *step_motion)
            };
            let ctx = NodeCheck {
                nodes: &ns.nodes,
                node_side: ns,
                faces: &fs.faces,
                generation: bounds_cache::next_generation(),
                motion,
                hot_until,
                friction: *friction,
                inp,
            };
            // only the nodes with a due candidate (`next`): the others test nothing and keep
            // their entry as it is (empty, unless a search just carried a set's contact over
            // to a new lead and marked it due)
            let chunk = NODE_CHUNK;
            next.par_chunks_mut(chunk)
                .zip(cand.chunks())
                .zip(touching.chunks())
                .enumerate()
                .for_each(|(c, ((next, mut lists), mut touch))| {
                    for (k, due) in next.iter_mut().enumerate() {
                        let old = touch.take(k);
                        if !schedule::is_due(*due, motion) {
                            if let Some(old) = old {
                                touch.keep(old);
                            }
                            continue;
                        }
                        let (mut hit, mut ft) =
                            old.map_or((Hit::default(), [0.0; 3]), |t| (t.hit, t.ft));
                        lists.with(k, |sched, room| {
                            if let Some(new) = ctx.check(c * chunk + k, room, sched, &hit, ft) {
                                (hit, ft) = new;
                            }
                            *due = sched.next_due(room);
                        });
                        touch.put(k, hit, ft, hit.fn_mag != 0.0);
                    }
                });
            touching.swap();
        }
        lap(&mut t, &mut self.times.node_checks);
        rebuilt
    }

    /// The node-to-face pairs' forces into `acc` and `out`.
    ///
    /// NOTE: serial, in the order the nodes joined the side: the sums depend neither on the
    /// threads nor on the nodes' places. Pass 0 has the slave nodes; pass 1 the master nodes,
    /// whose reactions act on the slave faces.
    fn scatter_pairs(&mut self, acc: &mut NodalForces, out: &mut ContactForce) {
        let Self { sides, passes, .. } = self;
        for (p, pass) in passes.iter_mut().enumerate() {
            let ns = &sides[pass.node_side];
            let fs = &sides[pass.face_side];
            let sign = if p == 0 { 1.0 } else { -1.0 };
            for (i, touch) in pass.touching.by_rank(&ns.rank) {
                let hit = &touch.hit;
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
    }
}

/// The closed cracks' forces ([`Closure::force`]) into `acc` and `out`: each pair's on b_k
/// and its opposite on a_k, in the order the cracks closed.
fn scatter_closures(
    closures: &[Closure],
    frictionless: bool,
    acc: &mut NodalForces,
    out: &mut ContactForce,
) {
    for c in closures {
        for k in 0..4 {
            if c.fn_mag[k] > 0.0 {
                let f = c.force(k, frictionless);
                acc.add(c.b[k], f);
                acc.add(c.a[k], scale(f, -1.0));
                out.force = add(out.force, f);
                out.normal += c.fn_mag[k];
                out.pairs += 1;
            }
        }
    }
}

/// What the check of one node reads.
struct NodeCheck<'a> {
    nodes: &'a [u32],
    /// The node side (for the nodes' normals, [`Side::frame`]).
    node_side: &'a Side,
    faces: &'a [Face],
    /// This pass's generation of face bounds ([`bounds_cache`]).
    generation: u64,
    /// The motion bound now; candidates due by `hot_until` stay hot.
    motion: f64,
    hot_until: f64,
    friction: Friction,
    inp: &'a StepInput<'a>,
}

/// A node's surface normal, and how fast it can turn (module docs, facing clearance).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug)]
struct NodeFrame {
    /// Unit normal of the node's surface, n_s = S / |S| with S the sum of its faces'
    /// diagonal cross products (zero when S is).
    n: Vec3,
    /// `sum (|d1| + |d2|) / |S|` and `faces / |S|` over the node's faces (infinite when S = 0).
    a: f64,
    b: f64,
}

impl NodeFrame {
    /// From the node's faces' `(d1 x d2, |d1| + |d2|)` ([`Face::normal_terms`]), in order.
    fn of(faces: impl Iterator<Item = (Vec3, f64)>) -> Self {
        let mut n = [0.0; 3];
        let mut a = 0.0;
        let mut count = 0.0;
        for (nf, len) in faces {
            n = add(n, nf);
            a += len;
            count += 1.0;
        }
        let l = norm(n);
        if l > 0.0 {
            NodeFrame {
                n: scale(n, 1.0 / l),
                a: a / l,
                b: count / l,
            }
        } else {
            NodeFrame {
                n,
                a: f64::INFINITY,
                b: f64::INFINITY,
            }
        }
    }

    /// The facing clearance of the node against a face with bounds `cull` (module docs): 0
    /// unless the node's surface turns away from every normal of the face by a margin.
    #[inline]
    fn facing_clearance(&self, cull: &Cull, more: &CullMore) -> f64 {
        if more.cos_min.is_nan() || more.cos_min <= 0.0 {
            return 0.0;
        }
        let (cos_min, sin_max) = (more.cos_min as f64, more.sin_max as f64);
        let c = dot(self.n, cull.n0());
        let perp = (1.0 - c * c).max(0.0).sqrt();
        let f0 = if c >= 0.0 { cos_min * c } else { c } - sin_max * perp;
        // 1e-6: n0 in f32 and the rounding of the node normal
        let m = (f0 + FACING - 1e-6) / std::f64::consts::SQRT_2;
        if m.is_nan() || m <= 0.0 {
            return 0.0;
        }
        let (l1, l2) = (self.a + more.kn1 as f64, self.b + more.kn2 as f64);
        let d = 2.0 * m / (l1 + (l1 * l1 + 4.0 * l2 * m).sqrt());
        if d > 0.0 {
            d
        } else {
            0.0
        }
    }
}

impl NodeCheck<'_> {
    fn node_frame(&self, i: usize) -> NodeFrame {
        self.node_side.frame(i, self.inp.x)
    }

    /// Node `i` (at `xs`) against face `fi`: a contact nearer than `best` replaces it. Returns
    /// the pair's clearance, the larger of the bounds' ([`Cull`]) and the facing one (module
    /// docs), 0 when the pair was tested in full.
    #[inline]
    fn test(
        &self,
        i: usize,
        fi: u32,
        xs: Vec3,
        best: &mut Option<(u32, Projection)>,
        frame: &mut Option<NodeFrame>,
        bounds: &mut BoundsCache,
    ) -> f64 {
        let x = self.inp.x;
        let (cull, more) = bounds.get(self.generation, fi, self.faces, x);
        let clear = cull.clearance(xs);
        if let Some(d) = clear {
            if d > self.hot_until - self.motion {
                return d;
            }
        }
        let facing = frame
            .get_or_insert_with(|| self.node_frame(i))
            .facing_clearance(cull, more);
        if let Some(d) = clear {
            return d.max(facing);
        }
        if facing > 0.0 {
            return facing;
        }
        let gap_min = more.gap_min;
        let face = &self.faces[fi as usize];
        let p = face.nodes.map(|n| x[n as usize]);
        if !off_corners(&p, xs, gap_min) {
            return 0.0;
        }
        let Some(pr) = project(&p, xs) else {
            return 0.0;
        };
        if !(pr.gap < -gap_min && pr.gap > -face.depth) {
            return 0.0;
        }
        // the node's surface must face the face (module docs)
        let n_s = frame.get_or_insert_with(|| self.node_frame(i)).n;
        if dot(n_s, pr.normal) > -FACING {
            return 0.0;
        }
        // the nearest surface point: least penetration (module docs); of equal ones the
        // lowest face index (the lists are not in face order)
        if best.is_none_or(|(bf, b)| pr.gap > b.gap || (pr.gap == b.gap && fi < bf)) {
            *best = Some((fi, pr));
        }
        0.0
    }

    /// Contact of node `i` of the node side with its candidate faces `list` (those due: see
    /// [`Sched`]; each tested gets its next `due` from its clearance), after its hit of the
    /// last step `prev`; returns the hit and the node's new tangential force (zero when out of
    /// contact: the history resets), or `None` when both stay zero.
    #[inline]
    fn check(
        &self,
        i: usize,
        room: &mut [Cand],
        sched: &mut Sched,
        prev: &Hit,
        ft_prev: Vec3,
    ) -> Option<(Hit, Vec3)> {
        let StepInput {
            x,
            v,
            dt_prev,
            table,
            ..
        } = *self.inp;
        let s = self.nodes[i];
        let mut xs: Option<Vec3> = None;
        let mut best: Option<(u32, Projection)> = None;
        let mut frame: Option<NodeFrame> = None;
        // faces holding the node or a node tied to it are not candidates (see `Query::run`)
        sched.visit(room, self.motion, self.hot_until, |f| {
            let xs = *xs.get_or_insert_with(|| x[s as usize]);
            BoundsCache::with(|bounds| self.test(i, f, xs, &mut best, &mut frame, bounds))
        });
        let Some((fi, pr)) = best else {
            // no contact (the hit and the tangential force are zero already when `prev` is)
            return (prev.face != NONE).then(|| (Hit::default(), [0.0; 3]));
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
                k: table.pair_stiffness(self.faces[prev.face as usize].k, s),
                engaged: prev.engaged,
            }
        };
        let k = table.pair_stiffness(face.k, s);
        let e = engage(before, k, pr.gap, approach);

        let f_n = normal_force(k, e.engaged, pr.normal);
        let fn_mag = -k * e.engaged;
        let mut f_t = [0.0; 3];
        if !self.friction.is_frictionless() && fn_mag > 0.0 {
            let v_t = sub(v_rel, scale(pr.normal, dot(v_rel, pr.normal)));
            let mu = self.friction.coefficient(norm(v_t));
            f_t = tangential_force(ft_prev, pr.normal, scale(v_t, dt_prev), k, mu * fn_mag).0;
        }
        let hit = Hit {
            face: fi,
            w: pr.w,
            f: add(f_n, f_t),
            engaged: e.engaged,
            offset: e.offset,
            fn_mag,
        };
        Some((hit, f_t))
    }
}

#[inline]
fn dist2(a: Vec3, b: Vec3) -> f64 {
    let d = sub(a, b);
    dot(d, d)
}

#[cfg(test)]
mod tests;
