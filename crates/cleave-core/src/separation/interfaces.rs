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
use super::criteria::{criterion_for, traction_bound, Criterion, InterfaceSample};
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
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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
#[derive(Clone, Debug)]
struct CohesiveFace {
    interface: u32,
    /// The law with the interface's own strength.
    law: CohesiveLaw,
    /// Per point, the largest opening past the peak ([`CohesiveLaw::traction`]).
    softened: [f64; 4],
    /// Traction at onset (from the mean stress): the face's elastic stretch at release.
    t0: Vec3,
    /// The stiffest slope the face takes (Pa/m), from the thinner, stiffer side.
    k_max: f64,
    /// Opening x_b - x_a and force on side a at the previous evaluation (for the work).
    d_prev: [Vec3; 4],
    f_prev: [Vec3; 4],
}

/// The interfaces of a split model at run time.
pub struct Separation {
    faces: Vec<SharedFace>,
    interfaces: usize,
    status: Vec<Status>,
    /// Per face: whether it ties its node pairs (bonds always; interfaces while intact).
    ties: Vec<bool>,
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
    // scratch
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
            fails: vec![0.0f32; n],
            touched: vec![false; m.num_elements()],
            candidates: Vec::new(),
            chunk_fails: vec![0; n.div_ceil(CHUNK)],
            released: Vec::new(),
            failed: 0,
            crack_area: 0.0,
        })
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
                    let bound = traction_bound(&stress[ea], &stress[eb]);
                    if criterion.bound_factor() * bound < face.strength {
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
        self.select_releases();
        if !self.released.is_empty() {
            for k in 0..self.released.len() {
                self.release(self.released[k], (x, per_slot), stress);
            }
            self.mark_loose();
            self.sets
                .split_after_failure(&self.faces, &self.ties, &self.released);
        }
        &self.released
    }

    /// Choose which of the interfaces that reached their criterion are released this step: in
    /// order of decreasing failure index (then ascending number), at most one per element. The
    /// others are checked again next step, on stresses that the released crack has begun to
    /// relieve: an element whose stress carried two of its faces over the strength in one step
    /// was resolved too coarsely in time to say which face cracks first, and releasing both
    /// would cut it loose as a one-element fragment ringing at its highest frequency.
    fn select_releases(&mut self) {
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

    /// Add the cohesive forces of the softening interfaces to `f` (positions x^n), each node's
    /// into its coincident set's slot ([`CoincidentSets::slots`]), and return the
    /// work they absorbed since the last call, the trapezoid 1/2 (f_prev + f) . (d - d_prev)
    /// over the openings (the same rule as the element energies). An interface whose four
    /// points are fully open becomes free. `x` as in [`Self::check_failure`].
    pub fn add_cohesive_forces(&mut self, (x, per_slot): (&[Vec3], bool), f: &mut [Vec3]) -> f64 {
        let mut work = 0.0;
        let Self {
            faces,
            status,
            cohesive,
            sets,
            ..
        } = self;
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
            // sliding: the tangential part of the mean opening (the faces' relative translation)
            let d_mean = if points == 4 {
                scale(add(add(d[0], d[1]), add(d[2], d[3])), 0.25)
            } else {
                scale(add(add(d[0], d[1]), d[2]), 1.0 / 3.0)
            };
            let ds = sub(d_mean, scale(n, dot(d_mean, n)));
            for k in 0..points {
                let (a, b) = (face.nodes[k] as usize, face.nodes[4 + k] as usize);
                let d_law = add(scale(n, dot(d[k], n)), ds);
                let fa = scale(law.traction(d_law, n, c.t0, c.k_max, &mut c.softened[k]), w);
                let d = d[k];
                let (ra, rb) = (slot[a] as usize, slot[b] as usize);
                f[ra] = add(f[ra], fa);
                f[rb] = sub(f[rb], fa);
                // force on b is -fa and b - a opens by d - d_prev: work absorbed = fa . dd
                work += 0.5 * dot(add(c.f_prev[k], fa), sub(d, c.d_prev[k]));
                c.d_prev[k] = d;
                c.f_prev[k] = fa;
                open &= law.is_open(c.softened[k]);
            }
            if open {
                status[c.interface as usize] = Status::Free;
            }
        }
        cohesive.retain(|c| status[c.interface as usize] == Status::Softening);
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
