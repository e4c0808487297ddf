//! The interfaces at run time: their status, the failure check of every intact interface each
//! step, the cohesive forces of softening ones, and the coincident sets they tie.
//!
//! An interface is *intact* (its node pairs belong to coincident sets), *softening* (MODEL 3,
//! between onset and full opening: no longer tied, the cohesive law pulls its faces together)
//! or *free*. Status only moves forward. Failure flips one entry, shrinks the coincident sets
//! holding the interface's nodes and reports the interface so that contact can take in its two
//! faces; nothing is remeshed (the solver's per-slot arrays get an entry for each new slot,
//! [`crate::node_values`]).

use std::ops::Index;

use rayon::prelude::*;

use super::cohesive::{stable_slope, CohesiveLaw, CohesiveParams};
use super::coincident::CoincidentSets;
use super::criteria::{criterion_for, Criterion, InterfaceSample};
use super::fragments::{components, Fragments};
use super::split::{FaceKind, SharedFace, SplitModel};
use crate::element::characteristic_length;
use crate::element::hex8::quad_normal_area;
use crate::element::shape::{face_points, shape_of};
use crate::material::History;
use crate::math::{add, dot, scale, sub, sym_mul_vec, Sym3, Vec3};
use crate::model::Model;
use crate::node_values::NodeValues;

/// Interfaces per chunk of the parallel failure check.
const CHUNK: usize = 1024;

/// Status of one interface.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Intact,
    Softening,
    Free,
}

/// A softening interface: the cohesive law at the face's 4 node pairs (nodal quadrature, each
/// pair weighted by a quarter of the reference area). Each point opens normally by its own
/// d_k . n (so the law resists relative rotation of the faces) and slides by the tangential
/// part of the face's mean opening: the faces' relative translation. (The tangential
/// differences between the points are the two elements' different in-plane stretching, not
/// sliding; taken as sliding they would turn the full strength sideways at near-zero opening.)
///
/// Its fields are public for a backend that steps the softening faces itself (the GPU):
/// [`Separation::cohesive_faces`], [`Separation::cohesive_faces_mut`].
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub struct CohesiveFace {
    pub interface: u32,
    /// The law with the interface's own strength.
    pub law: CohesiveLaw,
    /// Per point, the largest opening past the peak ([`CohesiveLaw::traction`]).
    pub softened: [f64; 4],
    /// Traction at onset (from the mean stress): the face's elastic stretch at release.
    pub t0: Vec3,
    /// The stiffest slope the face takes (Pa/m), from the thinner, stiffer side.
    pub k_max: f64,
    /// Opening x_b - x_a and force on side a at the previous evaluation (for the work).
    pub d_prev: [Vec3; 4],
    pub f_prev: [Vec3; 4],
}

/// The interfaces of a split model at run time.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct Separation {
    /// Wall-clock seconds spent releasing failed interfaces and splitting their sets so far
    /// (`cleave bench ball` prints them); not saved in a restart file.
    #[serde(skip)]
    pub release_seconds: f64,
    faces: Vec<SharedFace>,
    interfaces: usize,
    status: Vec<Status>,
    /// Per face: whether it ties its node pairs (bonds always; interfaces while intact).
    ties: Vec<bool>,
    /// Failure criteria per separation group: built from the model, not saved in a restart file.
    #[serde(skip)]
    criteria: Vec<Box<dyn Criterion>>,
    /// Per group: its cohesive law but the strength (MODELs 3 and 4).
    laws: Vec<Option<CohesiveParams>>,
    /// Per element: whether an interface failure has touched its nodes' coincident sets (it then
    /// steps with the free-element speed).
    loose: Vec<bool>,
    /// Per element: the stable cohesive unloading slope E / (2 h), h = V / (largest face area).
    elem_slope: Vec<f64>,
    sets: CoincidentSets,
    cohesive: Vec<CohesiveFace>,
    /// The step the softening interfaces' springs allow ([`Self::cohesive_time_step`]).
    cohesive_dt: f64,
    // scratch
    /// Per slot, the sum of the stiffest cohesive springs on it (zero between calls).
    slot_stiffness: Vec<f64>,
    /// Failure index of each interface that reached 1 this step (0 otherwise; single precision
    /// is plenty to order the releases).
    fails: Vec<f32>,
    /// Elements that lost an interface in this step's release.
    touched: Vec<bool>,
    candidates: Vec<(f32, usize)>,
    chunk_fails: Vec<u32>,
    released: Vec<usize>,
    failed: usize,
    crack_area: f64,
}

impl Separation {
    /// All interfaces intact; one criterion (and cohesive law for MODELs 3 and 4) per
    /// separation group.
    /// Copies the interface table; [`Self::from_parts`] takes it over.
    pub fn new(split: &SplitModel) -> Result<Self, String> {
        Self::from_parts(&split.model, split.faces.clone(), split.interfaces)
    }

    /// As [`Self::new`], from the split model, its shared faces and the number of interfaces
    /// among them (they come first).
    pub fn from_parts(
        m: &Model,
        faces: Vec<SharedFace>,
        interfaces: usize,
    ) -> Result<Self, String> {
        let defs = &m.separations;
        let criteria = defs
            .iter()
            .map(criterion_for)
            .collect::<Result<Vec<_>, _>>()?;
        let laws = defs
            .iter()
            .map(|d| CohesiveParams::of_model(d.model, d.beta, d.gc))
            .collect();
        let elem_slope = (0..m.num_elements())
            .map(|e| {
                let c = &m.conn[e];
                let xe: [Vec3; 8] = std::array::from_fn(|a| m.x0[c[a] as usize]);
                let h = shape_of(c).map_or(0.0, |s| characteristic_length(s, &xe));
                stable_slope(m.element_material(e).young, h, m.control.tssfac)
            })
            .collect();
        let ties = vec![true; faces.len()];
        let sets = CoincidentSets::build(m.num_nodes(), &faces, &ties);
        let n = interfaces;
        Ok(Self {
            release_seconds: 0.0,
            faces,
            interfaces: n,
            status: vec![Status::Intact; n],
            ties,
            criteria,
            laws,
            elem_slope,
            loose: vec![false; m.num_elements()],
            sets,
            cohesive: Vec::new(),
            cohesive_dt: f64::INFINITY,
            slot_stiffness: Vec::new(),
            fails: vec![0.0f32; n],
            touched: vec![false; m.num_elements()],
            candidates: Vec::new(),
            chunk_fails: vec![0; n.div_ceil(CHUNK)],
            released: Vec::new(),
            failed: 0,
            crack_area: 0.0,
        })
    }

    /// Take up the state of a restart file (`saved`, read back without its criteria) in place
    /// of this one, built from the same model: every face's status, the coincident sets as they
    /// have split, the cohesive faces and the counts; the criteria stay this one's.
    pub(crate) fn restore(&mut self, mut saved: Separation) -> Result<(), String> {
        if saved.faces.len() != self.faces.len() || saved.interfaces != self.interfaces {
            return Err(format!(
                "it has {} interfaces and {} shared faces, the deck {} and {}",
                saved.interfaces,
                saved.faces.len(),
                self.interfaces,
                self.faces.len()
            ));
        }
        saved.criteria = std::mem::take(&mut self.criteria);
        *self = saved;
        Ok(())
    }

    /// Number of interfaces that may fail.
    pub fn num_interfaces(&self) -> usize {
        self.interfaces
    }
    /// Interfaces no longer intact (softening or free).
    pub fn num_failed(&self) -> usize {
        self.failed
    }
    /// Reference area of the interfaces no longer intact.
    pub fn crack_area(&self) -> f64 {
        self.crack_area
    }
    /// Every shared face (interfaces first, then bonds).
    pub fn faces(&self) -> &[SharedFace] {
        &self.faces
    }
    /// Status of interface `i`.
    pub fn status(&self, i: usize) -> Status {
        self.status[i]
    }
    /// The coincident node sets.
    pub fn sets(&self) -> &CoincidentSets {
        &self.sets
    }
    /// The softening faces, in the order they were released. On the CPU a face leaves the list
    /// when it opens fully ([`Self::add_cohesive_forces`]); a backend that steps them itself
    /// keeps every face in place and marks the open ones free ([`Self::mark_open`]).
    pub fn cohesive_faces(&self) -> &[CohesiveFace] {
        &self.cohesive
    }
    /// The softening faces, to take up their state from a backend that steps them itself.
    pub fn cohesive_faces_mut(&mut self) -> &mut [CohesiveFace] {
        &mut self.cohesive
    }
    /// A backend found the softening interface `i` fully open: it is free from now on.
    pub fn mark_open(&mut self, i: usize) {
        if self.status[i] == Status::Softening {
            self.status[i] = Status::Free;
        }
    }

    /// Interfaces released by the last [`Self::check_failure`] (ascending).
    pub fn released(&self) -> &[usize] {
        &self.released
    }
    /// Indices of the interfaces no longer intact, ascending.
    pub fn failed_interfaces(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.interfaces).filter(|&i| self.status[i] != Status::Intact)
    }

    /// Check every intact interface against its group's criterion on the stresses at t^n;
    /// release those whose failure index reached 1 (softening under MODELs 3 and 4, else free) and
    /// split the coincident sets they tied. Returns the released interfaces, ascending.
    ///
    /// `x` and `v` hold an entry per node, or per slot of the sets when `per_slot`
    /// ([`crate::node_values`]).
    pub fn check_failure(
        &mut self,
        time: f64,
        (x, v, per_slot): (&[Vec3], &[Vec3], bool),
        stress: &[Sym3],
        history: &[History],
    ) -> &[usize] {
        let Self {
            faces,
            status,
            criteria,
            fails,
            chunk_fails,
            sets,
            ..
        } = self;
        let kin = per_slot.then(|| sets.slots());
        let (xv, vv) = (NodeValues::new(x, kin), NodeValues::new(v, kin));
        fails
            .par_chunks_mut(CHUNK)
            .zip(chunk_fails.par_iter_mut())
            .enumerate()
            .for_each(|(c, (fl, count))| {
                *count = 0;
                for (k, out) in fl.iter_mut().enumerate() {
                    let i = c * CHUNK + k;
                    *out = 0.0;
                    if status[i] != Status::Intact {
                        continue;
                    }
                    let face = &faces[i];
                    let [ea, eb] = face.elems.map(|e| e as usize);
                    let criterion = &criteria[face.group as usize];
                    // the cheap bound first; the slack covers the rounding of the full
                    // sample (its normal and sums, ~1e-15 of the stresses) far beyond any
                    // stress a strength bears
                    let bound = criterion.bound(&stress[ea], &stress[eb]);
                    if bound < face.strength * (1.0 - 1e-9) {
                        continue;
                    }
                    let sample = InterfaceSample {
                        time,
                        face,
                        normal: face_normal(face, xv),
                        stress: [&stress[ea], &stress[eb]],
                        history: [&history[ea], &history[eb]],
                        x: xv,
                        v: vv,
                    };
                    let index = criterion.stress(&sample) / face.strength;
                    if index >= 1.0 {
                        *out = index as f32;
                        *count += 1;
                    }
                }
            });
        self.candidates.clear();
        for (c, &count) in self.chunk_fails.iter().enumerate() {
            if count == 0 {
                continue;
            }
            let end = ((c + 1) * CHUNK).min(self.interfaces);
            self.candidates.extend(
                (c * CHUNK..end)
                    .filter(|&i| self.fails[i] > 0.0)
                    .map(|i| (self.fails[i], i)),
            );
        }
        self.release_candidates((x, per_slot), stress)
    }

    /// The second half of [`Self::check_failure`] for a backend that evaluated the criteria
    /// itself (the GPU): `found` holds each intact interface whose failure index reached 1,
    /// with that index (in any order). Releases them as [`Self::check_failure`] does and
    /// returns the released interfaces, ascending. An interface that is not intact is an
    /// error (the backend's view of the interfaces is out of date).
    pub fn release_found(
        &mut self,
        found: &[(f32, u32)],
        (x, per_slot): (&[Vec3], bool),
        stress: &[Sym3],
    ) -> Result<&[usize], String> {
        self.candidates.clear();
        for &(index, i) in found {
            let i = i as usize;
            if i >= self.interfaces || self.status[i] != Status::Intact {
                return Err(format!("interface {i} is not an intact interface"));
            }
            self.candidates.push((index, i));
        }
        Ok(self.release_candidates((x, per_slot), stress))
    }

    /// Release the candidates (failure index, interface) of this step
    /// ([`Self::select_releases`]) and split the sets they tied.
    fn release_candidates(&mut self, (x, per_slot): (&[Vec3], bool), stress: &[Sym3]) -> &[usize] {
        let began = std::time::Instant::now();
        self.select_releases();
        if !self.released.is_empty() {
            for k in 0..self.released.len() {
                self.release(self.released[k], (x, per_slot), stress);
            }
            self.mark_loose();
            self.sets
                .split_after_failure(&self.faces, &self.ties, &self.released);
        }
        self.release_seconds += began.elapsed().as_secs_f64();
        &self.released
    }

    /// Choose which of the interfaces that reached their criterion (`candidates`) are released
    /// this step: in order of decreasing failure index (then ascending number), at most one per
    /// element. The others are checked again next step, on stresses that the released crack has
    /// begun to relieve: an element whose stress carried two of its faces over the strength in
    /// one step was resolved too coarsely in time to say which face cracks first, and releasing
    /// both would cut it loose as a one-element fragment ringing at its highest frequency.
    fn select_releases(&mut self) {
        self.candidates
            .sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        self.released.clear();
        for &(_, i) in &self.candidates {
            let [ea, eb] = self.faces[i].elems.map(|e| e as usize);
            if self.touched[ea] || self.touched[eb] {
                continue;
            }
            self.touched[ea] = true;
            self.touched[eb] = true;
            self.released.push(i);
        }
        for &i in &self.released {
            for e in self.faces[i].elems {
                self.touched[e as usize] = false;
            }
        }
        self.released.sort_unstable();
    }

    /// Mark the elements owning the members of every set the released interfaces held (before
    /// the sets split), and the interfaces' own elements.
    fn mark_loose(&mut self) {
        for &i in &self.released {
            let face = &self.faces[i];
            for e in face.elems {
                self.loose[e as usize] = true;
            }
            for &n in &face.nodes {
                if let Some(set) = self.sets.set_of(n) {
                    for &m in set {
                        if let Some(e) = self.sets.owner(m) {
                            self.loose[e as usize] = true;
                        }
                    }
                }
            }
        }
    }

    /// Per element: whether it steps with the free-element speed.
    pub fn loose_elements(&self) -> &[bool] {
        &self.loose
    }

    /// Interface `i` stops tying its nodes: softening if its group has a cohesive law.
    fn release(&mut self, i: usize, (x, per_slot): (&[Vec3], bool), stress: &[Sym3]) {
        let x = NodeValues::new(x, per_slot.then(|| self.sets.slots()));
        let face = &self.faces[i];
        self.ties[i] = false;
        self.failed += 1;
        self.crack_area += face.area0;
        if let Some(params) = self.laws[face.group as usize] {
            let law = params.law(face.strength);
            self.status[i] = Status::Softening;
            let [ea, eb] = face.elems.map(|e| e as usize);
            let mean: Sym3 = std::array::from_fn(|k| 0.5 * (stress[ea][k] + stress[eb][k]));
            let n = face_normal(face, x);
            let t0 = law.onset_traction(sym_mul_vec(&mean, n), n);
            let d_prev = std::array::from_fn(|k| {
                sub(x[face.nodes[4 + k] as usize], x[face.nodes[k] as usize])
            });
            self.cohesive.push(CohesiveFace {
                interface: i as u32,
                law,
                softened: [0.0; 4],
                t0,
                k_max: self.elem_slope[ea].min(self.elem_slope[eb]),
                d_prev,
                f_prev: [[0.0; 3]; 4],
            });
        } else {
            self.status[i] = Status::Free;
        }
    }

    /// The longest time step the cohesive springs of the softening interfaces take, after their
    /// last [`Self::add_cohesive_forces`] (infinite when none softens): `sqrt(2 / omega^2)`
    /// with `omega^2 = max 2 K / m` over the coincident sets their points join (Gershgorin's
    /// bound for springs between masses), K the sum of the stiffest springs on a set,
    /// `k = max(1, BETA^2) c w` for each point of a face (c the face's largest secant,
    /// [`CohesiveLaw::stiffest_slope`], w the point's area), m the set's mass. A single spring
    /// between equal masses m so has `omega^2 = 2 k / m`, its own; a node copy held by
    /// several faces (a tetrahedron's corner by 3) adds theirs. That is the budget
    /// [`stable_slope`] gives a normal spring, `omega dt <= sqrt(2)` (half of the central
    /// difference limit `omega^2 dt^2 <= 4`, the other half left to the elements): for
    /// BETA <= 1 and one softening face on a node copy it is longer than the elements' step on
    /// hexahedra (the fragmenting bar and the notched beam take the same steps with it); it
    /// binds where the law's sliding stiffness BETA^2 c makes it (at BETA 8 right after
    /// release, 8 times shorter than for a normal spring) or where several softening faces
    /// hold one node copy. The solver's step is the
    /// least of this and TSSFAC times the element and contact steps (this one already holds
    /// the budget, so TSSFAC does not scale it).
    ///
    /// Without it, a sliding spring of BETA^2 k_max rang unstably (omega dt up to 8 sqrt(2)):
    /// the opening alternated in sign and grew by tens each step until the point opened
    /// fully, and the last trapezoid 1/2 f_prev . (d - d_prev), over a jump of the alternating
    /// opening against the force that had held it, booked a negative work that the node
    /// kept as kinetic energy. A thrown BETA 8 block so booked a negative fracture energy
    /// (`tests/separation.rs`); with the sliding tractions that had no potential
    /// ([`face_tractions`]) the Brazilian disc (BETA 8) booked -46 J by 150 us, against GC x
    /// area 1.0 J; counting one spring per point instead of their sum on a node copy, it
    /// still dipped to -0.055 J.
    pub fn cohesive_time_step(&self) -> f64 {
        self.cohesive_dt
    }

    /// Add the cohesive forces of the softening interfaces to `f` (positions x^n), each node's
    /// into its coincident set's slot ([`CoincidentSets::slots`]), and return the
    /// work they absorbed since the last call, the trapezoid 1/2 (f_prev + f) . (d - d_prev)
    /// over the openings (the same rule as the element energies). An interface whose four
    /// points are fully open becomes free. `x` as in [`Self::check_failure`]; `mass`: the
    /// mass of each slot's set, for [`Self::cohesive_time_step`], which this updates.
    pub fn add_cohesive_forces(
        &mut self,
        (x, per_slot): (&[Vec3], bool),
        mass: &[f64],
        f: &mut [Vec3],
    ) -> f64 {
        let mut work = 0.0;
        let mut omega2_max = 0.0f64;
        let Self {
            faces,
            status,
            cohesive,
            sets,
            slot_stiffness,
            ..
        } = self;
        if slot_stiffness.len() < mass.len() {
            // grows only in the steps that split sets
            slot_stiffness.resize(mass.len(), 0.0);
        }
        let slot = sets.slots();
        let x = NodeValues::new(x, per_slot.then_some(slot));
        for c in cohesive.iter_mut() {
            let face = &faces[c.interface as usize];
            let law = c.law;
            let n = face_normal(face, x);
            // a quadrilateral's 4 points or a triangle's 3 share the area equally
            let points = face_points(&std::array::from_fn(|k| face.nodes[k]));
            let w = face.area0 / points as f64;
            let mut open = true;
            let d: [Vec3; 4] = std::array::from_fn(|k| {
                sub(x[face.nodes[4 + k] as usize], x[face.nodes[k] as usize])
            });
            let t = face_tractions(&law, &d[..points], n, c.t0, c.k_max, &mut c.softened);
            // the face's stiffest slope (its points share the mean sliding)
            let slope = (0..points)
                .map(|k| law.stiffest_slope(c.softened[k], c.k_max))
                .fold(0.0, f64::max);
            for k in 0..points {
                let (a, b) = (face.nodes[k] as usize, face.nodes[4 + k] as usize);
                let fa = scale(t[k], w);
                let d = d[k];
                let (ra, rb) = (slot[a] as usize, slot[b] as usize);
                f[ra] = add(f[ra], fa);
                f[rb] = sub(f[rb], fa);
                // force on b is -fa and b - a opens by d - d_prev: work absorbed = fa . dd
                work += 0.5 * dot(add(c.f_prev[k], fa), sub(d, c.d_prev[k]));
                c.d_prev[k] = d;
                c.f_prev[k] = fa;
                open &= law.is_open(c.softened[k]);
                // the point's stiffest spring between its two sets (none within one set)
                if ra != rb {
                    slot_stiffness[ra] += slope * w;
                    slot_stiffness[rb] += slope * w;
                }
            }
            if open {
                status[c.interface as usize] = Status::Free;
            }
        }
        for c in cohesive.iter() {
            let face = &faces[c.interface as usize];
            for k in 0..face_points(&std::array::from_fn(|k| face.nodes[k])) {
                for node in [face.nodes[k], face.nodes[4 + k]] {
                    let r = slot[node as usize] as usize;
                    if slot_stiffness[r] > 0.0 && mass[r] > 0.0 {
                        omega2_max = omega2_max.max(2.0 * slot_stiffness[r] / mass[r]);
                    }
                    slot_stiffness[r] = 0.0;
                }
            }
        }
        cohesive.retain(|c| status[c.interface as usize] == Status::Softening);
        self.cohesive_dt = if omega2_max > 0.0 {
            (2.0 / omega2_max).sqrt()
        } else {
            f64::INFINITY
        };
        work
    }

    /// Fragments: connected components of elements through shared nodes and through every
    /// shared face that still holds (bonds, intact and softening interfaces).
    pub fn fragments(&self, conn: &[[u32; 8]], num_nodes: usize) -> Fragments {
        let holding = self
            .faces
            .iter()
            .enumerate()
            .filter(|(i, face)| face.kind == FaceKind::Bond || self.status[*i] != Status::Free);
        let ties = holding.flat_map(|(_, face)| (0..4).map(|k| (face.nodes[k], face.nodes[4 + k])));
        components(conn, num_nodes, ties)
    }
}

/// The tractions at the points of a softening face (its first `d.len()` of 4) whose points
/// open by `d` (x_b - x_a, normal `n`), pulling each point's side b towards side a
/// ([`CohesiveLaw::traction`]; `softened` updated as there).
///
/// Each point opens normally by its own d_k . n and slides by the face's mean sliding ds (the
/// tangential part of the mean opening: the faces' relative translation). Its traction splits
/// into a normal part, which acts at the point, and a sliding part, which is the slope of its
/// energy along ds; and ds moves with every point's opening, by 1/points of it. So the sliding
/// part that acts at each point is the mean of the points' sliding parts: then the forces are
/// the gradient of the sum of the points' energies (at fixed n and history), and the law does
/// no work around a closed path. With each point's own sliding part at that point (the law
/// before), points of different secants (c_k, one of them softened further than the others)
/// did work `sum_k c_k BETA^2 ds . de_k` on the differences e_k of their sliding from the mean,
/// which has no potential: a closed path of sliding and in-plane stretching gained energy each
/// time round, 64 times more at BETA 8 than at BETA 1 (see the tests), and the Brazilian disc
/// (BETA 8) booked -14 J of fracture energy by 124 us with the cohesive step limit alone.
fn face_tractions(
    law: &CohesiveLaw,
    d: &[Vec3],
    n: Vec3,
    t0: Vec3,
    k_max: f64,
    softened: &mut [f64; 4],
) -> [Vec3; 4] {
    let points = d.len();
    let inv = 1.0 / points as f64;
    let d_mean = scale(d.iter().fold([0.0; 3], |s, &dk| add(s, dk)), inv);
    let ds = sub(d_mean, scale(n, dot(d_mean, n)));
    let mut t = [[0.0; 3]; 4];
    let mut ts_mean = [0.0; 3];
    for k in 0..points {
        let d_law = add(scale(n, dot(d[k], n)), ds);
        let tk = law.traction(d_law, n, t0, k_max, &mut softened[k]);
        let tn = scale(n, dot(tk, n));
        ts_mean = add(ts_mean, scale(sub(tk, tn), inv));
        t[k] = tn;
    }
    for tk in t.iter_mut().take(points) {
        *tk = add(*tk, ts_mean);
    }
    t
}

/// Current unit normal of a shared face, out of its first element: the diagonal cross product
/// of the mid-points of its 4 node pairs.
pub fn face_normal(face: &SharedFace, x: NodeValues<Vec3>) -> Vec3 {
    let p: [Vec3; 4] = std::array::from_fn(|k| {
        scale(
            add(x[face.nodes[k] as usize], x[face.nodes[4 + k] as usize]),
            0.5,
        )
    });
    quad_normal_area(p[0], p[1], p[2], p[3]).0
}

/// Current centroid of a shared face (mean of its 8 nodes; of its 6 for a triangle).
///
/// `x`: the positions of the nodes (a slice, or a model's `x0`).
pub fn face_centroid(face: &SharedFace, x: &(impl Index<usize, Output = Vec3> + ?Sized)) -> Vec3 {
    let points = face_points(&std::array::from_fn(|k| face.nodes[k]));
    let mut c = [0.0; 3];
    for k in 0..points {
        c = add(
            c,
            add(x[face.nodes[k] as usize], x[face.nodes[4 + k] as usize]),
        );
    }
    scale(c, 0.5 / points as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::separation::cohesive::Envelope;

    /// The tractions of a face whose 4 points have softened unequally (secants c_k from k_max
    /// down), taken round a closed path in their unloading range at BETA 8: the faces slide
    /// round a circle (ds) while the points' sliding differs from the mean round another
    /// circle, a quarter turn behind (in-plane stretching e_k, sum zero), at fixed normal
    /// openings. The law does no work round the path (trapezoid over 4000 steps a turn, 5
    /// turns: 2e-18), and no point softens further. With each point's own sliding traction
    /// at that point (the law before), the same path gives out energy each turn, 5 times the
    /// energy of the face's springs (`sum_k c_k BETA^2 ds . de_k` has no potential): that work
    /// is measured here too (-1.008 over the 5 turns).
    #[test]
    fn sliding_tractions_do_no_work_round_a_closed_path() {
        let law = CohesiveLaw::new(Envelope::Linear, 100.0, 8.0, 1.0); // delta_c = 0.02
        let (k_max, n) = (2e4, [0.0, 0.0, 1.0]); // delta_e = 0.005
        let t0 = [0.0, 0.0, 100.0];
        let soft0 = [0.0, 0.004, 0.008, 0.012];
        // the points' secants, unequal
        let c: Vec<f64> = soft0
            .iter()
            .map(|&s| law.stiffest_slope(s, k_max) / 64.0)
            .collect();
        assert!(c[0] > 1.5 * c[3], "{c:?}");
        // normal openings: the shifted dn* = dn + 0.005 stays in [0.002, 0.003]
        let dn = [-0.003, -0.0025, -0.002, -0.0028];
        let (r, r2) = (2.5e-4, 1.5e-4);
        // in-plane stretching: points 0 and 2 one way, 1 and 3 the other (sum zero)
        let sign = [-1.0, 1.0, -1.0, 1.0];
        let path = |th: f64| -> [Vec3; 4] {
            let ds = [r * th.cos(), r * th.sin(), 0.0];
            std::array::from_fn(|k| {
                let e = [
                    sign[k] * r2 * (th - 0.5 * std::f64::consts::PI).cos(),
                    sign[k] * r2 * (th - 0.5 * std::f64::consts::PI).sin(),
                    0.0,
                ];
                add(add(ds, e), [0.0, 0.0, dn[k]])
            })
        };
        let (turns, steps) = (5, 4000);
        let work = |own: bool| -> (f64, [f64; 4]) {
            let mut soft = soft0;
            let mut w = 0.0;
            let mut d_prev = path(0.0);
            let mut t_prev = [[0.0; 3]; 4];
            for i in 0..=turns * steps {
                let th = 2.0 * std::f64::consts::PI * i as f64 / steps as f64;
                let d = path(th);
                let t = if own {
                    // the law before: each point's own traction, sliding by the mean
                    let dm = scale(d.iter().fold([0.0; 3], |s, &x| add(s, x)), 0.25);
                    let ds = sub(dm, scale(n, dot(dm, n)));
                    std::array::from_fn(|k| {
                        let dl = add(scale(n, dot(d[k], n)), ds);
                        law.traction(dl, n, t0, k_max, &mut soft[k])
                    })
                } else {
                    face_tractions(&law, &d, n, t0, k_max, &mut soft)
                };
                if i > 0 {
                    for k in 0..4 {
                        w += 0.5 * dot(add(t_prev[k], t[k]), sub(d[k], d_prev[k]));
                    }
                }
                d_prev = d;
                t_prev = t;
            }
            (w, soft)
        };
        let (w_new, soft_new) = work(false);
        let (w_old, soft_old) = work(true);
        eprintln!(
            "work round {turns} turns: {w_new:.3e} (mean sliding traction), {w_old:.3e} (each point's own); per turn, against the energy of the face's springs {:.3e}",
            0.5 * 64.0 * c[0] * r * r
        );
        assert_eq!(soft_new, soft0, "unloading only");
        assert_eq!(soft_old, soft0, "unloading only");
        // measured: -1.008 over the 5 turns, 5 times the springs' energy 0.04 each turn
        assert!(w_old < -0.5 * 64.0 * c[0] * r * r * turns as f64, "{w_old}");
        assert!(w_new.abs() < 1e-9 * w_old.abs(), "{w_new} vs {w_old}");
    }

    /// The stiffest slope: BETA^2 k_max at release (the sliding secant), falling as the point
    /// softens; zero once open; BETA below 1 leaves the normal secant.
    #[test]
    fn stiffest_slope_is_the_sliding_secant() {
        let k_max = 2e4;
        let law = CohesiveLaw::new(Envelope::Linear, 100.0, 8.0, 1.0);
        assert!((law.stiffest_slope(0.0, k_max) - 64.0 * k_max).abs() < 1e-9 * k_max);
        // softened 0.005: 75 / 0.01
        assert!((law.stiffest_slope(0.005, k_max) - 64.0 * 7500.0).abs() < 1e-6);
        assert_eq!(law.stiffest_slope(0.02, k_max), 0.0);
        let soft = CohesiveLaw::new(Envelope::Linear, 100.0, 0.5, 1.0);
        assert!((soft.stiffest_slope(0.0, k_max) - k_max).abs() < 1e-9 * k_max);
    }
}
