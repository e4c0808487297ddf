//! The explicit time-step loop (central differences), in the order of
//! `shared/design/architecture.md`:
//!
//! ```text
//! element pass   stress update and corner forces at x^n, stable time step;   (elements)
//!                assembled as they come: f_r = body loads + sum of corner forces
//! interfaces     failure check of intact interfaces on the new stresses; release  (faces)
//! cohesive       softening interfaces' tractions on their 8 nodes            (faces)
//! contact        faces of failed interfaces join; penalty and friction forces (nodes, faces)
//! velocities     v^(n+1/2) = v^(n-1/2) + f_r/M (dt^(n-1/2) + dt^(n+1/2)) / 2   (nodes)
//! rigid bodies   F, M summed over each body; 6-dof update; nodes placed
//! constraints    SPC, prescribed motion, rigid walls; their reactions' work
//! energies       at t^n, with v^n between the half steps
//! [observer]     output at t^n
//! positions      x^(n+1) = x^n + dt^(n+1/2) v^(n+1/2); t += dt
//! ```
//!
//! Coincident sets (a split model, the paper's equations 1-4): every force on a node, from an
//! element, a cohesive face or the contact, is added into its set's *slot* r
//! ([`CoincidentSets::slots`]: one entry per set and per node in no set, not one per copy), so
//! f_r is the set's sum f, and each member moves with `a = f_r / M`, M the set's `sum m`
//! ([`CoincidentSets::masses`], also per slot). Without separation r is the node itself and M
//! its mass. The members of a set so move as one, as the deck node they came from, and no pass
//! gathers them; their position and velocity are kept once, in the slot too
//! ([`crate::node_values`]: the velocity, energy and position passes run over the slots, and
//! the readers by node go through the slot map), unless a rigid body's node is in a set (then
//! every copy has its entry, [`Solver::attach_separation`]). When a set splits, its new slots
//! start with its position and velocity. The element pass writes the slots
//! safely because its colours are those of the deck's nodes ([`Colouring::with_classes`],
//! classes the representatives with every interface intact) and a slot only ever holds a
//! piece of the set it started with (each new representative checked to be of its node's
//! class when the sets split). In a step where sets split, each piece's sum is made again from
//! its members' elements (`Solver::sum_split_sets`) before the cohesive and contact forces
//! come in.
//!
//! [`CoincidentSets::slots`]: crate::separation::coincident::CoincidentSets::slots
//! [`CoincidentSets::masses`]: crate::separation::coincident::CoincidentSets::masses
//!
//! Every sum over elements or nodes is done in fixed chunks whose partial results are added in
//! chunk order, and the element pass adds its corner forces colour by colour (each node in a
//! fixed order, [`crate::element::colouring`]), so the numbers do not depend on the number of
//! threads.

use std::time::Instant;

use crate::awake::KeepAwake;

use rayon::prelude::*;

use crate::contact::{ContactSet, Crack};
use crate::element::colouring::{Colouring, Scatter};
use crate::element::kernel::KernelControls;
use crate::element::nodal_pressure::NodalPressure;
use crate::element::sri::{sri_corner_forces, SriElements};
use crate::element::{element_corner_forces, element_step, Shape};
use crate::error::SolverError;
use crate::loads::Loads;
use crate::math::{add, cross, dot, norm, scale, sub, Vec3};
use crate::model::{Model, MotionTarget, Vad};
use crate::node_values::NodeValues;
use crate::rigid::NOT_RIGID;
use crate::separation::interfaces::Separation;
use crate::setup::Setup;
use crate::state::{Energies, RigidState, State};

mod erosion;
mod restart;
mod tied;

/// The hourglass control and bulk viscosity of each part: its `*HOURGLASS` (HGID), else the
/// `*CONTROL_HOURGLASS` and `*CONTROL_BULK_VISCOSITY` values.
pub fn kernel_controls(model: &Model) -> Vec<KernelControls> {
    let c = &model.control;
    let global = KernelControls {
        hourglass: c.hourglass,
        qh: c.qh,
        q1: c.q1,
        q2: c.q2,
    };
    (model.parts.iter())
        .map(|p| {
            p.hourglass.map_or(global, |h| {
                let h = &model.hourglass[h];
                KernelControls {
                    hourglass: h.hourglass,
                    qh: h.qh,
                    q1: h.q1,
                    q2: h.q2,
                }
            })
        })
        .collect()
}

/// Each parallel task of the element pass spans at least this many elements' worth of chunks
/// before the colour filter (so about `ELEM_CHUNK / colours` elements of work); the chunks of
/// the sums are the colouring's, fixed by the mesh, for deterministic sums.
const ELEM_CHUNK: usize = 256;
/// Nodes per chunk of the nodal passes.
const NODE_CHUNK: usize = 1024;

/// Elements a task of [`Solver::sum_split_sets`]' corner forces takes at least.
const ELEMS_PER_TASK: usize = 16;

/// Wall-clock seconds spent in each phase of the step so far (for benchmarks and profiles).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseTimes {
    /// Element pass: stresses, corner forces and their assembly into the nodes (with the body
    /// loads), element time step.
    pub elements: f64,
    /// Failure check of the interfaces (with their release and the split of their sets:
    /// [`crate::separation::interfaces::Separation::release_seconds`], and `split_sums`).
    pub interfaces: f64,
    /// Of `interfaces`: the split sets' masses and forces summed again.
    pub split_sums: f64,
    /// Contact search and forces.
    pub contact: f64,
    /// Everything else of `advance_to_half_step` (cohesive forces, velocities, rigid bodies,
    /// constraints, energies) and the position update.
    pub nodal: f64,
}

impl PhaseTimes {
    pub fn total(&self) -> f64 {
        self.elements + self.interfaces + self.contact + self.nodal
    }
}

/// Resultant force of a rigid wall at t^n (on the model).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct WallForce {
    /// Force along the wall normal (positive pushes the nodes away from the wall).
    pub normal: f64,
    pub force: Vec3,
}

/// Work of this step's impulses on the model: the part up to t^n and the part after it.
#[derive(Clone, Copy, Debug, Default)]
struct Work {
    now: f64,
    later: f64,
}

impl std::ops::AddAssign for Work {
    fn add_assign(&mut self, o: Work) {
        self.now += o.now;
        self.later += o.later;
    }
}

/// Partial results of one chunk of the element pass.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug)]
struct ElemChunkSum {
    dt_min: f64,
    dt_elem: u32,
    de_internal: f64,
    de_hourglass: f64,
    inverted: u32,
}

impl Default for ElemChunkSum {
    fn default() -> Self {
        Self {
            dt_min: f64::INFINITY,
            dt_elem: 0,
            de_internal: 0.0,
            de_hourglass: 0.0,
            inverted: u32::MAX,
        }
    }
}

/// What an observer is shown each step.
pub trait Observer {
    /// Called once per step with the state at t^n (positions x^n, velocities `v_n`, stresses).
    fn observe(&mut self, solver: &Solver) -> std::io::Result<()>;

    /// The earliest time at which [`Self::observe`] has something to do. A backend that does
    /// not stop every step (the GPU step of cleave-gpu) shows the observer only the first step
    /// at or after it (within 1e-12 of it), and the last. The default, 0, asks for every step.
    fn next_due(&self) -> f64 {
        0.0
    }

    /// Told the time and step between the states it is shown, by a backend that does not
    /// stop every step (`solver.state.t`, `step`, `dt` and the energies are current; the
    /// nodal and element values are those of the last [`Self::observe`]). For a progress bar.
    fn tick(&mut self, _solver: &Solver) {}

    /// Called after each step's position update with the state the next step starts from
    /// (x^(n+1), v^(n+1/2), t^(n+1)): where a restart file is saved ([`Solver::save_state`]).
    /// `Ok(true)` stops the run there, unfinished ([`Solver::is_finished`] false).
    fn between_steps(&mut self, _solver: &Solver) -> std::io::Result<bool> {
        Ok(false)
    }
}

/// Why a run stopped early.
#[derive(Debug)]
pub enum RunError {
    /// The model's numerics failed (an inverted element, a non-finite value, ...).
    Solver(SolverError),
    /// The output could not be written.
    Output(std::io::Error),
    /// The device another stepper runs the step on failed (a GPU lost or reporting an
    /// error), or its state no longer agrees with the host's: neither the model's fault nor
    /// the output's.
    Device(String),
}

/// The solver: model, derived setup, state and scratch.
pub struct Solver<'m> {
    pub model: &'m Model,
    pub setup: Setup,
    pub state: State,
    /// Rigid wall resultants at t^n.
    pub wall_forces: Vec<WallForce>,
    /// Hourglass control and bulk viscosity of each part ([`kernel_controls`]).
    ctl: Vec<KernelControls>,
    /// Colours of the element chunks, with the connectivity the element pass reads (private:
    /// checked proper once, its writes are race-free only so).
    colouring: Colouring<'m>,
    /// Nodal forces; with separation, one entry per slot of the coincident sets (each the sum
    /// over its set, [`crate::separation::coincident::CoincidentSets::slots`]).
    f: Vec<Vec3>,
    /// With separation, the mass of each slot's set (a node's own when in none); empty
    /// without.
    set_mass: Vec<f64>,
    /// With separation, (node, element) for the nodes of several elements that are in a
    /// coincident set (deck nodes kept outside the groups), sorted: the elements whose forces
    /// such a node's set sums when it splits. (A copy's one element is its set's `owner`.)
    shared_elems: Vec<(u32, u32)>,
    /// Scratch of [`Self::sum_split_sets`]: the nodes of the sets split this step (sorted)
    /// and their elements.
    split_nodes: Vec<u32>,
    split_elems: Vec<u32>,
    /// Scratch: the corner forces of `split_elems`, worked out in parallel.
    split_fe: Vec<[Vec3; 8]>,
    chunk_sums: Vec<ElemChunkSum>,
    node_sums: Vec<[f64; 4]>,
    finished: bool,
    /// Work of this step's impulses that falls after t^n, booked at the next step.
    pending_work: f64,
    /// Interfaces and coincident node sets of a split model (element separation).
    separation: Option<Separation>,
    /// The state's positions and velocities are kept per slot of the coincident sets, not per
    /// node ([`crate::node_values`]): with separation, unless a rigid body's node is in a set.
    per_slot: bool,
    /// Scratch of the rigid walls: the entries a wall has already stopped this step.
    wall_seen: Vec<bool>,
    wall_marked: Vec<u32>,
    /// Contact definitions of the model.
    contact: Option<ContactSet<'m>>,
    /// Scratch: this step's failed interfaces (faces and node pairs), for the contact.
    new_cracks: Vec<Crack>,
    /// Stable time step of the contact penalty springs (infinite without contact).
    dt_contact: f64,
    /// The time step floor, DTMIN times the first step.
    dt_floor: f64,
    /// The nodal averaging of the ELFORM 13 tetrahedra, if any.
    nodal_pressure: Option<NodalPressure>,
    /// Concentrated and pressure loads, with their forces of the last step.
    loads: Loads,
    /// The ELFORM 2 hexahedra, if any, with their Gauss points.
    sri: Option<SriElements>,
    /// Element erosion, when a material erodes.
    erosion: Option<erosion::Erosion>,
    /// The slave nodes of tied contacts and the face points they follow ([`crate::tied`]).
    ties: Vec<crate::tied::Tie>,
    /// Time spent in each phase.
    pub times: PhaseTimes,
}

impl<'m> Solver<'m> {
    /// Prepare a model for running: setup, initial state (x0, v0, zero stress).
    pub fn new(model: &'m Model) -> Result<Self, SolverError> {
        let setup = Setup::new(model).map_err(SolverError::Setup)?;
        let ne = model.num_elements();
        let nn = model.num_nodes();
        let ctl = kernel_controls(model);
        let hg = vec![[0.0; 12]; ne];
        let rigid: Vec<RigidState> = setup
            .rigid
            .iter()
            .map(|b| b.initial_state(&model.x0, &model.v0, &setup.mass))
            .collect();
        let mut v = model.v0.to_vec();
        for (body, st) in setup.rigid.iter().zip(&rigid) {
            for &n in &body.nodes {
                let r = sub(model.x0[n as usize], st.x_cm);
                v[n as usize] = add(st.v_cm, cross(st.omega, r));
            }
        }
        let state = State {
            t: 0.0,
            step: 0,
            dt_prev: 0.0,
            dt: 0.0,
            x: model.x0.to_vec(),
            v_n: v.clone(),
            v,
            stress: vec![[0.0; 6]; ne],
            hist: vec![Default::default(); ne],
            hg,
            bulk_q: vec![0.0; ne],
            rigid,
            energy: Energies::default(),
            initial_energy: 0.0,
            dt_element: 0,
            eroded: if model.erosion.is_empty() {
                Vec::new()
            } else {
                vec![false; ne]
            },
            damage: if model.erosion.iter().any(|d| d.rule.johnson_cook.is_some()) {
                vec![[0.0; 2]; ne]
            } else {
                Vec::new()
            },
        };
        let nodal_pressure = NodalPressure::new(
            &model.conn,
            |e| {
                setup.elem_shape[e] == Shape::Tet
                    && model.sections[model.parts[model.elem_part[e] as usize].section].elform == 13
            },
            nn,
        );
        let sri = SriElements::new(ne, |e| {
            setup.elem_shape[e] == Shape::Hex
                && model.sections[model.parts[model.elem_part[e] as usize].section].elform == 2
        });
        let colouring = Colouring::new(&model.conn, nn);
        // the element pass's parallel writes are race-free only with a proper colouring
        assert!(
            colouring.is_proper(nn),
            "element chunk colouring has a clash"
        );
        let chunk_sums = vec![ElemChunkSum::default(); colouring.chunks()];
        let mut solver = Self {
            model,
            setup,
            state,
            wall_forces: vec![WallForce::default(); model.rigid_walls.len()],
            ctl,
            colouring,
            f: vec![[0.0; 3]; nn],
            set_mass: Vec::new(),
            shared_elems: Vec::new(),
            split_nodes: Vec::new(),
            split_elems: Vec::new(),
            split_fe: Vec::new(),
            chunk_sums,
            node_sums: Vec::with_capacity(nn.div_ceil(NODE_CHUNK)),
            finished: false,
            pending_work: 0.0,
            separation: None,
            per_slot: false,
            wall_seen: Vec::new(),
            wall_marked: Vec::new(),
            contact: None,
            new_cracks: Vec::new(),
            dt_contact: f64::INFINITY,
            dt_floor: 0.0,
            nodal_pressure,
            loads: Loads::default(),
            sri,
            erosion: erosion::Erosion::new(model),
            ties: Vec::new(),
            times: PhaseTimes::default(),
        };
        solver.set_up_ties()?;
        Ok(solver)
    }

    /// Run a split model with its interfaces: each step the intact ones are checked for
    /// failure, and each coincident set moves with its mean acceleration `sum f / sum m` (the
    /// paper's equations 1-4; module docs), before constraints act. The interfaces must all be
    /// intact (as [`Separation::new`] makes them): the element chunks are coloured again by
    /// the sets' representatives, which stand for the deck nodes.
    ///
    /// The positions and velocities are then kept once per slot of the coincident sets
    /// ([`crate::node_values`]; read them by node with [`Self::positions`]), unless a rigid
    /// body's node is in a set: the body places its node while the copies tied to it move
    /// with the set, so each copy keeps an entry of its own.
    ///
    /// Panics on a material that both erodes and separates, or on ELFORM 13 (the deck reader
    /// refuses both with a message).
    pub fn attach_separation(&mut self, separation: Separation) {
        let tied = separation.sets().node_sets();
        let rigid_tied = (0..self.model.num_nodes())
            .any(|i| self.setup.node_rigid[i] != NOT_RIGID && tied[i] != u32::MAX);
        self.attach(separation, !rigid_tied);
    }

    /// [`Self::attach_separation`], with an entry of its own for every copy's position and
    /// velocity even where the sets could share one (as with a rigid body bonded to a group):
    /// the same motion, bit for bit, with 72 bytes more for each copy (tests compare the two).
    pub fn attach_separation_per_node(&mut self, separation: Separation) {
        self.attach(separation, false);
    }

    fn attach(&mut self, separation: Separation, per_slot: bool) {
        assert!(
            self.nodal_pressure.is_none(),
            "ELFORM 13 tetrahedra with element separation: the deck reader refuses this model"
        );
        // an element either erodes or separates: the crack faces of an eroded element would
        // join the contact with their stiffness (erosion in the other materials runs)
        let m = self.model;
        assert!(
            !m.erosion
                .iter()
                .any(|d| m.separations.iter().any(|s| s.material == d.material)),
            "element erosion in a separation group's material: the deck reader refuses this model"
        );
        assert_eq!(
            separation.num_failed(),
            0,
            "attach the separation before any failure"
        );
        let nn = self.model.num_nodes();
        let sets = separation.sets();
        let reps = (0..nn as u32).map(|n| sets.rep(n)).collect();
        self.colouring = Colouring::with_classes(&self.model.conn, nn, reps);
        // the element pass's parallel writes are race-free only with a proper colouring
        assert!(
            self.colouring.is_proper(nn),
            "element chunk colouring has a clash"
        );
        self.chunk_sums = vec![ElemChunkSum::default(); self.colouring.chunks()];
        sets.masses(&self.setup.mass, &mut self.set_mass);
        self.f = vec![[0.0; 3]; sets.num_slots()];
        let mut valence = vec![0u32; nn];
        for c in &self.model.conn {
            for &n in c {
                valence[n as usize] += 1;
            }
        }
        let tied = sets.node_sets();
        self.shared_elems = (self.model.conn.iter().enumerate())
            .flat_map(|(e, c)| c.iter().map(move |&n| (n, e as u32)))
            .filter(|&(n, _)| valence[n as usize] > 1 && tied[n as usize] != u32::MAX)
            .collect();
        self.shared_elems.sort_unstable();
        self.shared_elems.dedup();
        self.per_slot = per_slot;
        if per_slot {
            // every member of a set starts where its representative is, as fast
            let slots = sets.slots();
            let reps: Vec<usize> = (0..nn)
                .filter(|&i| sets.rep(i as u32) == i as u32)
                .collect();
            let gather = |a: &mut Vec<Vec3>| {
                let mut out = vec![[0.0; 3]; sets.num_slots()];
                for &i in &reps {
                    out[slots[i] as usize] = a[i];
                }
                *a = out;
            };
            gather(&mut self.state.x);
            gather(&mut self.state.v);
            gather(&mut self.state.v_n);
            self.wall_seen = vec![false; sets.num_slots()];
        }
        self.separation = Some(separation);
    }

    /// Where node i's position and velocity are stored: its set's slot when they are kept per
    /// slot, else its own entry.
    fn kin_slots(&self) -> Option<&[u32]> {
        match &self.separation {
            Some(sep) if self.per_slot => Some(sep.sets().slots()),
            _ => None,
        }
    }

    /// The entry of node i in the state's positions and velocities.
    #[inline]
    fn entry(&self, i: usize) -> usize {
        self.positions().entry_of(i)
    }

    /// The mass that moves with entry k ([`Self::entry_masses`]).
    #[inline]
    fn entry_mass(&self, k: usize) -> f64 {
        self.entry_masses()[k]
    }

    /// The mass that moves with each entry: its set's when the entries are slots, else its
    /// node's.
    fn entry_masses(&self) -> &[f64] {
        if self.per_slot {
            &self.set_mass
        } else {
            &self.setup.mass
        }
    }

    /// Positions x^n of every node.
    pub fn positions(&self) -> NodeValues<'_, Vec3> {
        NodeValues::new(&self.state.x, self.kin_slots())
    }

    /// Velocities v^n of every node (at t^n: valid after the velocity update, as the observer
    /// sees them).
    pub fn velocities(&self) -> NodeValues<'_, Vec3> {
        NodeValues::new(&self.state.v_n, self.kin_slots())
    }

    /// Velocities v^(n-1/2) of every node before the velocity update, v^(n+1/2) after.
    pub fn half_step_velocities(&self) -> NodeValues<'_, Vec3> {
        NodeValues::new(&self.state.v, self.kin_slots())
    }

    /// The interfaces of a split model, if any.
    pub fn separation(&self) -> Option<&Separation> {
        self.separation.as_ref()
    }

    /// The interfaces, for a backend that steps the softening faces itself (the GPU) to hand
    /// back their state ([`Separation::cohesive_faces_mut`]).
    pub fn separation_mut(&mut self) -> Option<&mut Separation> {
        self.separation.as_mut()
    }

    /// Run with contact: each step, after the element and cohesive forces and before the
    /// coincident sets are tied, the contact forces are added; the two faces of every interface
    /// that fails join the contact surfaces in the step it fails.
    ///
    /// The time step is `TSSFAC min(element step, contact step)`, the contact step being
    /// [`ContactSet::stable_dt`] of the initial surfaces: with the default SLSFAC the elements
    /// control it; a stiffer penalty shortens it (see [`Solver::contact_time_step`]).
    pub fn attach_contact(&mut self, contact: ContactSet<'m>) {
        if contact.is_empty() {
            return;
        }
        // a node of a rigid body moves with the body: its mass against a spring is the body's
        let mass: Vec<f64> = (0..self.setup.mass.len())
            .map(|i| match self.setup.node_rigid[i] {
                crate::rigid::NOT_RIGID => self.setup.mass[i],
                b => self.setup.rigid[b as usize].mass,
            })
            .collect();
        self.dt_contact = contact.stable_dt(&mass);
        self.contact = Some(contact);
    }

    /// The stable time step of the contact penalty springs, before TSSFAC (infinite without
    /// contact).
    pub fn contact_time_step(&self) -> f64 {
        self.dt_contact
    }

    /// The contact definitions, if any.
    pub fn contact(&self) -> Option<&ContactSet<'m>> {
        self.contact.as_ref()
    }

    /// The contact definitions, for a stepper that runs them elsewhere (the GPU's) and puts
    /// back their resultants.
    pub fn contact_mut(&mut self) -> Option<&mut ContactSet<'m>> {
        self.contact.as_mut()
    }

    /// Bring the contact's bookkeeping up to the coincident sets as they are now, for a stepper
    /// that runs the checks itself ([`ContactSet::settle`]; `pending`: only the copies of the
    /// faces activated since the last settle regrouped, [`ContactSet::settle_pending`]).
    /// Nothing without contact.
    pub fn settle_contact(&mut self, pending: bool) {
        let Some(c) = &mut self.contact else {
            return;
        };
        let tie = (self.separation.as_ref()).map_or(&[][..], |s| s.sets().node_sets());
        match pending {
            true => c.settle_pending(tie),
            false => c.settle(tie),
        }
    }

    /// True once the state at the end time has been computed and observed.
    pub fn is_finished(&self) -> bool {
        self.finished
    }

    /// Run to the end time, showing the state to `obs` at every step. In a rayon pool of
    /// several threads, the other workers poll for the step's jobs until the run ends instead
    /// of sleeping between its loops ([`KeepAwake`]).
    pub fn run(&mut self, obs: &mut dyn Observer) -> Result<(), RunError> {
        let _awake = KeepAwake::start();
        loop {
            self.advance_to_half_step().map_err(RunError::Solver)?;
            obs.observe(self).map_err(RunError::Output)?;
            if self.finished {
                return Ok(());
            }
            self.update_positions().map_err(RunError::Solver)?;
            if obs.between_steps(self).map_err(RunError::Output)? {
                return Ok(());
            }
        }
    }

    /// The first part of a step: forces at t^n, the new time step, v^(n+1/2), energies at t^n.
    pub fn advance_to_half_step(&mut self) -> Result<(), SolverError> {
        let t0 = Instant::now();
        let (dt_crit, dt_elem) = self.compute_element_forces()?;
        if dt_crit == 0.0 || dt_crit.is_nan() {
            // an element that allows no step at all: stop before the contact searches a mesh
            // it has made degenerate (a node at 1e300 puts every face in one search cell)
            return Err(self.bad_time_step(dt_crit, dt_elem));
        }
        self.average_nodal_pressure();
        // after the pressure averaging, which reads the step's stresses of the elements that
        // erode now (their forces of this step stand)
        self.erode_elements();
        self.add_loads();
        let t1 = Instant::now();
        self.check_interfaces();
        let t2 = Instant::now();
        self.add_cohesive_forces();
        let t3 = Instant::now();
        self.add_contact_forces();
        self.transfer_tied_forces();
        let t4 = Instant::now();
        let dt_new = self.next_time_step(dt_crit, dt_elem)?;
        let dt_mid = 0.5 * (self.state.dt_prev + dt_new);
        self.state.dt = dt_new;
        let load_now = self.load_work(dt_mid);
        self.update_velocities(dt_mid);
        let load_later = self.load_work(dt_mid);
        let mut work = self.update_rigid_bodies(dt_mid, dt_new);
        work += self.apply_constraints(dt_new);
        work += self.apply_rigid_walls(dt_mid, dt_new);
        self.move_tied_nodes();
        let body_work = self.record_kinetic_energy()?;
        // NOTE: an impulse J of this step changes v^(n+1/2), which the kinetic energy at t^n
        // (1/2 m v^(n-1/2).v^(n+1/2)) and at t^(n+1) both contain: its work is booked as
        // 1/2 J.v^(n-1/2) now and 1/2 J.v^(n+1/2) at the next step.
        self.state.energy.external_work += self.pending_work + work.now + body_work + load_now;
        self.pending_work = work.later + load_later;
        if self.state.step == 0 {
            // E0 + W = the total at t = 0 (W holds the first half of the first impulses)
            self.state.initial_energy = self.state.energy.total() - self.state.energy.external_work;
        }
        self.check_energies()?;
        let t5 = Instant::now();
        let tm = &mut self.times;
        tm.elements += (t1 - t0).as_secs_f64();
        tm.interfaces += (t2 - t1).as_secs_f64();
        tm.contact += (t4 - t3).as_secs_f64();
        tm.nodal += (t3 - t2).as_secs_f64() + (t5 - t4).as_secs_f64();
        Ok(())
    }

    /// The error for a non-finite velocity: the node where the failure started, that is a node
    /// of the first element whose stress is not finite (NaN spreads from an element to its
    /// nodes in the step it appears, and to their other elements only in the next), else the
    /// first node whose velocity is not finite.
    fn non_finite_node(&self) -> SolverError {
        let v = self.half_step_velocities();
        let bad = |i: usize| !v[i].iter().all(|c| c.is_finite());
        let elem = (0..self.model.num_elements())
            .find(|&k| !self.state.stress[k].iter().all(|c| c.is_finite()));
        let node = elem
            .and_then(|k| {
                self.model.conn[k]
                    .iter()
                    .map(|&n| n as usize)
                    .find(|&i| bad(i))
            })
            .or_else(|| (0..self.model.num_nodes()).find(|&i| bad(i)))
            .unwrap_or(0);
        SolverError::NonFinite {
            node: self.model.node_ids[node],
            element: elem.map(|k| self.model.elem_ids[k]),
            time: self.state.t,
            step: self.state.step,
        }
    }

    /// Every energy of the ledger is finite, or the run stops naming the energy and, where
    /// it can be found, the element, rigid body or node it came from (a figure that is not a
    /// number must not end a run with success).
    fn check_energies(&self) -> Result<(), SolverError> {
        let e = &self.state.energy;
        let ledger = [
            ("initial energy", self.state.initial_energy),
            ("kinetic energy", e.kinetic),
            ("internal energy", e.internal),
            ("hourglass energy", e.hourglass),
            ("contact energy", e.contact),
            ("fracture energy", e.fracture),
            ("external work", e.external_work),
        ];
        let Some(&(energy, _)) = ledger.iter().find(|(_, v)| !v.is_finite()) else {
            return Ok(());
        };
        let finite = |a: &[f64]| a.iter().all(|x| x.is_finite());
        let bad_elem = (0..self.model.num_elements())
            .find(|&k| !finite(&self.state.stress[k]) || !finite(&self.state.hg[k]));
        let bad_body = self.state.rigid.iter().position(|r| {
            !(finite(&r.x_cm) && finite(&r.v_cm) && finite(&r.omega) && finite(&r.ang_mom))
        });
        let bad_node = (0..self.model.num_nodes())
            .find(|&i| !(finite(&self.positions()[i]) && finite(&self.half_step_velocities()[i])));
        let at = if let Some(k) = bad_elem {
            format!("element {} has a non-finite stress", self.model.elem_ids[k])
        } else if let Some(b) = bad_body {
            let body = &self.setup.rigid[b];
            match body.of {
                crate::rigid::BodyOf::Part(p) => format!(
                    "rigid part {} has a non-finite motion",
                    self.model.parts[p].id
                ),
                crate::rigid::BodyOf::Nodal(_) => {
                    format!("nodal rigid body {} has a non-finite motion", body.id)
                }
            }
        } else if let Some(i) = bad_node {
            format!(
                "node {} has a non-finite position or velocity",
                self.model.node_ids[i]
            )
        } else {
            String::new()
        };
        Err(SolverError::NonFiniteEnergy {
            energy,
            at,
            time: self.state.t,
            step: self.state.step,
        })
    }

    /// Element pass and assembly: stresses at x^n, and `f_i = m_i g(t) + sum of the corner
    /// forces of node i` (with separation, at each coincident set's representative r:
    /// `f_r = M g(t) + sum of the corner forces of the set's members`), the corner forces added
    /// colour by colour ([`Colouring`]: a node gets them in a fixed order whatever the thread
    /// count); returns the smallest element time step and its element.
    fn compute_element_forces(&mut self) -> Result<(f64, u32), SolverError> {
        let g = self.body_acceleration(self.state.t);
        if let Some(np) = &mut self.nodal_pressure {
            // ELFORM 13: the volume change averaged over the nodes, before the material update
            let (x, v) = (&self.state.x, &self.state.v);
            let eroded = &self.state.eroded;
            np.average_volume_change(
                |n| x[n as usize],
                |n| v[n as usize],
                self.state.dt_prev,
                eroded,
            );
        }
        self.step_sri_elements();
        let Self {
            model,
            setup,
            state,
            ctl,
            colouring,
            f,
            set_mass,
            chunk_sums,
            separation,
            per_slot,
            ..
        } = self;
        // where node n's forces go (its set's slot, whose members are of n's class), and the
        // masses of the entries: each gets its body load
        let (slots, mass) = sets_view(separation.as_ref(), set_mass, &setup.mass);
        // the positions and velocities are read there too when they are kept per slot
        let per_slot = *per_slot;
        f.par_iter_mut()
            .zip(mass.par_iter())
            .with_min_len(NODE_CHUNK)
            .for_each(|(fi, &m)| *fi = scale(g, m));
        let x = &state.x;
        let v = &state.v;
        let dt_prev = state.dt_prev;
        let (ctl, elem_part) = (&ctl[..], &model.elem_part);
        // the colouring's connectivity: the nodes written are those it was checked for
        let conn = colouring.conn();
        let (size, colour, colours) = (colouring.size(), colouring.colour(), colouring.colours());
        let loose = separation.as_ref().map(|s| s.loose_elements());
        let eroded = &state.eroded;
        let np = self.nodal_pressure.as_ref();
        let sri = self.sri.as_ref();
        let sink = Scatter::new(f);
        let process = |c: usize,
                       sc: &mut [crate::math::Sym3],
                       hc: &mut [crate::material::History],
                       qc: &mut [f64],
                       gc: &mut [[f64; 12]],
                       out: &mut ElemChunkSum| {
            let e0 = c * size;
            let mut acc = ElemChunkSum::default();
            for k in 0..sc.len() {
                let e = e0 + k;
                if eroded.get(e).is_some_and(|&d| d) {
                    continue;
                }
                let params = match loose {
                    Some(l) if l[e] => &setup.loose_params,
                    _ if setup.lone[e] => &setup.loose_params,
                    _ => &setup.params,
                };
                let Some(p) = &params[setup.elem_mat[e] as usize] else {
                    continue;
                };
                let ids = &conn[e];
                let to: [u32; 8] = match slots {
                    Some(s) => ids.map(|n| s[n as usize]),
                    None => *ids,
                };
                let at = if per_slot { &to } else { ids };
                // (filled in place: `from_fn` built each on the stack and copied it, a call
                // to memcpy per array and element)
                let (mut xe, mut ve) = ([[0.0; 3]; 8], [[0.0; 3]; 8]);
                for a in 0..8 {
                    xe[a] = x[at[a] as usize];
                    ve[a] = v[at[a] as usize];
                }
                let mut fe = [[0.0; 3]; 8];
                // ELFORM 2 elements were stepped before the pass (`step_sri_elements`)
                let step = match sri.and_then(|s| s.position(e)) {
                    Some(i) => {
                        let (forces, r, sigma, q, eps_p) = sri.map(|s| s.result(i)).unwrap_or((
                            &fe,
                            Err(crate::element::kernel::InvertedElement),
                            [0.0; 6],
                            0.0,
                            0.0,
                        ));
                        fe = *forces;
                        sc[k] = sigma;
                        qc[k] = q;
                        // the element's history for output: the points' mean plastic strain
                        hc[k].eps_p = eps_p;
                        r
                    }
                    None => element_step(
                        setup.elem_shape[e],
                        &xe,
                        &ve,
                        np.and_then(|n| n.theta_bar(e)),
                        dt_prev,
                        p,
                        &ctl[elem_part[e] as usize],
                        &mut sc[k],
                        &mut hc[k],
                        &mut qc[k],
                        Some(&mut gc[k]),
                        &mut fe,
                    ),
                };
                match step {
                    Ok(r) => {
                        for (&to, fa) in to.iter().zip(fe) {
                            // SAFETY: this runs for the chunks of one colour at a time (the
                            // loop below) of a colouring checked proper in `Solver::new` or
                            // `attach_separation`, and the members of slot `to` are of its
                            // node's class (a piece of a set of that class, checked when the
                            // sets split, `sum_split_sets`): no other thread adds to it
                            // meanwhile
                            unsafe { sink.add(to, fa) };
                        }
                        acc.de_internal += r.de_internal;
                        acc.de_hourglass += r.de_hourglass;
                        hc[k].work += r.de_internal + r.de_hourglass;
                        if r.dt_crit < acc.dt_min {
                            acc.dt_min = r.dt_crit;
                            acc.dt_elem = e as u32;
                        }
                    }
                    Err(_) => {
                        if acc.inverted == u32::MAX {
                            acc.inverted = e as u32;
                        }
                    }
                }
            }
            *out = acc;
        };
        // NOTE: one colour at a time: the chunks of a colour share no node (`Scatter`)
        for k in 0..colours as u32 {
            state
                .stress
                .par_chunks_mut(size)
                .zip(state.hist.par_chunks_mut(size))
                .zip(state.bulk_q.par_chunks_mut(size))
                .zip(state.hg.par_chunks_mut(size))
                .zip(chunk_sums.par_iter_mut())
                .enumerate()
                .with_min_len((ELEM_CHUNK / size).max(1))
                .filter(|(c, _)| colour[*c] == k)
                .for_each(|(c, ((((sc, hc), qc), gc), out))| process(c, sc, hc, qc, gc, out));
        }
        let mut dt_min = f64::INFINITY;
        let mut dt_elem = 0;
        for s in chunk_sums.iter() {
            if s.inverted != u32::MAX {
                return Err(SolverError::InvertedElement {
                    element: model.elem_ids[s.inverted as usize],
                    time: state.t,
                    step: state.step,
                });
            }
            state.energy.internal += s.de_internal;
            state.energy.hourglass += s.de_hourglass;
            if s.dt_min < dt_min {
                dt_min = s.dt_min;
                dt_elem = s.dt_elem;
            }
        }
        Ok((dt_min, dt_elem))
    }

    /// ELFORM 2: the step of the selectively reduced hexahedra, in parallel over them, before
    /// the coloured pass that scatters their forces ([`SriElements::step_all`]).
    fn step_sri_elements(&mut self) {
        let Some(sri) = &mut self.sri else {
            return;
        };
        let st = &self.state;
        let kin = match &self.separation {
            Some(sep) if self.per_slot => Some(sep.sets().slots()),
            _ => None,
        };
        let x = NodeValues::new(&st.x, kin);
        let v = NodeValues::new(&st.v, kin);
        let conn = &self.model.conn;
        let setup = &self.setup;
        let loose = self.separation.as_ref().map(|s| s.loose_elements());
        sri.step_all(
            |e| {
                let c = &conn[e];
                (c.map(|n| x[n as usize]), c.map(|n| v[n as usize]))
            },
            |e| {
                let params = match loose {
                    Some(l) if l[e] => &setup.loose_params,
                    _ if setup.lone[e] => &setup.loose_params,
                    _ => &setup.params,
                };
                params[setup.elem_mat[e] as usize].as_ref()
            },
            |e| st.bulk_q[e],
            st.dt_prev,
            |e| self.ctl[self.model.elem_part[e] as usize],
        );
    }

    /// ELFORM 13: the corner forces of the averaging tetrahedra carry the nodal mean of their
    /// pressures ([`NodalPressure::correct_forces`]); nothing without such elements. (The model
    /// has no separation: [`Self::attach_separation`] refuses one with ELFORM 13.)
    fn average_nodal_pressure(&mut self) {
        let Some(np) = &mut self.nodal_pressure else {
            return;
        };
        let (x, f) = (&self.state.x, &mut self.f);
        np.correct_forces(
            |n| x[n as usize],
            &self.state.stress,
            |n, df| {
                f[n as usize] = add(f[n as usize], df);
            },
        );
    }

    /// The concentrated and pressure loads at t^n into the forces (a node's into its set's
    /// slot, [`Loads::apply`]).
    fn add_loads(&mut self) {
        if !Loads::any(self.model) {
            return;
        }
        let Self {
            model,
            state,
            separation,
            per_slot,
            set_mass,
            setup,
            f,
            loads,
            ..
        } = self;
        let (slots, _) = sets_view(separation.as_ref(), set_mass, &setup.mass);
        let kin = slots.filter(|_| *per_slot);
        let x = NodeValues::new(&state.x, kin);
        loads.apply(
            model,
            state.t,
            |n| x[n as usize],
            |n, fv| {
                let k = slots.map_or(n as usize, |s| s[n as usize] as usize);
                f[k] = add(f[k], fv);
            },
        );
    }

    /// Half the work of the loads' impulse on the half-step velocities as they stand
    /// ([`Loads::work`]); 0 without loads.
    fn load_work(&self, dt_mid: f64) -> f64 {
        if !Loads::any(self.model) {
            return 0.0;
        }
        let v = self.half_step_velocities();
        self.loads.work(|n| v[n as usize], dt_mid)
    }

    /// Check every intact interface on the stresses at t^n; release the failed ones. The sets
    /// they split get their new masses and their forces summed again
    /// ([`Self::sum_split_sets`]), so the pieces part in this very step, as in the paper
    /// (failure check, then one acceleration for each set that remains).
    fn check_interfaces(&mut self) {
        let Some(sep) = &mut self.separation else {
            return;
        };
        let s = &self.state;
        if sep
            .check_failure(s.t, (&s.x, &s.v, self.per_slot), &s.stress, &s.hist)
            .is_empty()
        {
            return;
        }
        let began = Instant::now();
        self.grow_split_sets();
        self.sum_split_sets();
        self.times.split_sums += began.elapsed().as_secs_f64();
    }

    /// Release the interfaces another backend (the GPU) found failed in the step at t^n:
    /// (failure index, interface) of each intact interface whose index reached 1, as
    /// [`Self::check_interfaces`] would (at most one per element, [`Separation::release_found`]).
    /// The state (positions, stresses) must be this step's. The split sets get their masses and
    /// their new slots (at their set's position and velocity); their forces are not summed
    /// again (the backend gathers its own). Returns how many were released.
    pub fn release_interfaces(&mut self, found: &[(f32, u32)]) -> Result<usize, String> {
        let Some(sep) = &mut self.separation else {
            return Err("the model has no element separation".into());
        };
        let s = &self.state;
        let n = sep
            .release_found(found, (&s.x, self.per_slot), &s.stress)?
            .len();
        if n > 0 {
            self.grow_split_sets();
        }
        Ok(n)
    }

    /// After sets split: their masses, and an entry for each new slot (the force, and when
    /// positions are kept per slot, its position and velocities, those of the set it split
    /// from).
    fn grow_split_sets(&mut self) {
        let Some(sep) = &self.separation else {
            return;
        };
        let sets = sep.sets();
        sets.reweigh_changed(&self.setup.mass, &mut self.set_mass);
        self.f.resize(sets.num_slots(), [0.0; 3]);
        if self.per_slot {
            // the new slots start where the set they split from is, as fast
            let st = &mut self.state;
            for &(new, from) in sets.born() {
                debug_assert_eq!(new as usize, st.x.len(), "slots are numbered on");
                let from = from as usize;
                st.x.push(st.x[from]);
                st.v.push(st.v[from]);
                st.v_n.push(st.v_n[from]);
            }
            self.wall_seen.resize(sets.num_slots(), false);
        }
    }

    /// The element pass summed the forces of each set as it was before this step's failures:
    /// each piece of a set that split gets its own sum again, `M g` and the corner forces of
    /// its members' elements ([`element_corner_forces`], from the state the pass left: the same
    /// forces bit for bit), elements in ascending order. Each new representative is checked to
    /// be of its node's class. Runs before the cohesive and contact forces are added.
    fn sum_split_sets(&mut self) {
        let g = self.body_acceleration(self.state.t);
        let Some(sep) = &self.separation else {
            return;
        };
        let sets = sep.sets();
        let slots = sets.slots();
        let (nodes, elems) = (&mut self.split_nodes, &mut self.split_elems);
        nodes.clear();
        nodes.extend(sets.changed_nodes());
        nodes.sort_unstable();
        nodes.dedup();
        elems.clear();
        for &n in nodes.iter() {
            let r = sets.rep(n);
            // what the element pass's writes rely on (module docs)
            assert!(
                self.colouring.same_class(r, n),
                "node {n}: its representative left its class"
            );
            let s = slots[n as usize] as usize;
            self.f[s] = scale(g, self.set_mass[s]);
            let at = self.shared_elems.partition_point(|p| p.0 < n);
            let around = self.shared_elems[at..].iter().take_while(|p| p.0 == n);
            let before = elems.len();
            elems.extend(around.map(|p| p.1));
            if elems.len() == before {
                // a node of one element: the element of the faces that tied it
                elems.extend(sets.owner(n));
            }
        }
        elems.sort_unstable();
        elems.dedup();
        let conn = self.colouring.conn();
        let st = &self.state;
        let x = NodeValues::new(&st.x, self.per_slot.then_some(slots));
        let (setup, sri) = (&self.setup, self.sri.as_ref());
        // the element pass skips an element without parameters: its forces are not summed
        elems.retain(|&e| setup.params[setup.elem_mat[e as usize] as usize].is_some());
        // the corner forces on every thread, then added in ascending element order
        let fes = &mut self.split_fe;
        fes.clear();
        fes.resize(elems.len(), [[0.0; 3]; 8]);
        fes.par_iter_mut()
            .zip(elems.par_iter())
            .with_min_len(ELEMS_PER_TASK)
            .for_each(|(fe, &e)| {
                let e = e as usize;
                let xe: [Vec3; 8] = std::array::from_fn(|a| x[conn[e][a] as usize]);
                // the element pass found every element upright at these positions
                let shape = setup.elem_shape[e];
                match sri.and_then(|s| s.position(e).map(|k| (s, k))) {
                    Some((s, k)) => sri_corner_forces(&xe, &s.pts[k], st.bulk_q[e], fe),
                    None => element_corner_forces(
                        shape,
                        &xe,
                        &st.stress[e],
                        st.bulk_q[e],
                        &st.hg[e],
                        fe,
                    ),
                }
                .expect("an element upright in this step's element pass");
            });
        for (&e, fe) in elems.iter().zip(fes.iter()) {
            for (&n, &fa) in conn[e as usize].iter().zip(fe) {
                if nodes.binary_search(&n).is_ok() {
                    let s = slots[n as usize] as usize;
                    self.f[s] = add(self.f[s], fa);
                }
            }
        }
    }

    /// Cohesive tractions of softening interfaces; their work goes to the fracture energy.
    fn add_cohesive_forces(&mut self) {
        if let Some(sep) = &mut self.separation {
            let x = (&self.state.x[..], self.per_slot);
            // the masses of the sets, per slot (sets_view)
            let mass = &self.set_mass;
            self.state.energy.fracture += sep.add_cohesive_forces(x, mass, &mut self.f);
        }
    }

    /// Contact: the faces of the interfaces released this step join the surfaces (and the
    /// candidate lists around them are renewed, since their ties broke); then the penalty and
    /// friction forces at x^n are added, each node's at its set's representative (so the set
    /// shares the contact force of any member). Their work over the last step goes to the
    /// contact energy. Before the rigid bodies gather their nodes' forces.
    fn add_contact_forces(&mut self) {
        self.activate_cracks();
        let Some(contact) = &mut self.contact else {
            return;
        };
        let mut tie: &[u32] = &[];
        let mut slots: &[u32] = &[];
        if let Some(sep) = &self.separation {
            tie = sep.sets().node_sets();
            slots = sep.sets().slots();
        }
        let s = &self.state;
        let kin = self.per_slot.then_some(slots);
        let (x, v) = (NodeValues::new(&s.x, kin), NodeValues::new(&s.v, kin));
        let step = contact.compute_with_slots(x, v, s.dt_prev, tie, slots, &mut self.f);
        self.state.energy.contact += step.energy;
    }

    /// The faces of the interfaces released in this step join the contact surfaces, and the
    /// cracks close ([`ContactSet::activate_cracks`]); the sets split get their watch
    /// ([`ContactSet::sets_split`]). Before the step's contact (the CPU's, or another
    /// stepper's after [`Self::release_interfaces`]).
    pub fn activate_cracks(&mut self) {
        let (Some(contact), Some(sep)) = (&mut self.contact, &self.separation) else {
            return;
        };
        if sep.released().is_empty() {
            return;
        }
        self.new_cracks.clear();
        for &i in sep.released() {
            let face = &sep.faces()[i];
            self.new_cracks.push(Crack {
                faces: [
                    (face.elems[0], face.faces[0]),
                    (face.elems[1], face.faces[1]),
                ],
                nodes: [
                    std::array::from_fn(|k| face.nodes[k]),
                    std::array::from_fn(|k| face.nodes[4 + k]),
                ],
            });
        }
        if self.per_slot {
            contact.sets_split(sep.sets().born());
        }
        contact.activate_cracks(&self.new_cracks);
    }

    /// The force on node i, assembled: with separation, its share `m_i sum f / sum m` of its
    /// coincident set's (for a node in no set `m_i / m_i = 1` exactly: its own force). A rigid
    /// body's node bonded to a group's copies so gives its body only its share; the copies
    /// move with the rest.
    fn node_force(&self, i: usize) -> Vec3 {
        let (slots, set_mass) =
            sets_view(self.separation.as_ref(), &self.set_mass, &self.setup.mass);
        let s = slots.map_or(i, |s| s[i] as usize);
        match slots {
            Some(_) if set_mass[s] > 0.0 => scale(self.f[s], self.setup.mass[i] / set_mass[s]),
            _ => self.f[s],
        }
    }

    /// Base acceleration of all body loads at time t.
    fn body_acceleration(&self, t: f64) -> Vec3 {
        let mut g = [0.0; 3];
        for bl in &self.model.body_loads {
            g[bl.axis] += bl.acceleration(&self.model.curves, t);
        }
        g
    }

    /// dt^(n+1/2) = TSSFAC * min(element time step, contact time step), or the step the
    /// softening cohesive springs take if shorter ([`Separation::cohesive_time_step`], which
    /// holds its own margin); DTINIT caps the first, LCTM's curve (at t^n, [`Curve::step_cap`])
    /// every one after the DTMIN floor is checked, and the step is clamped so the run ends
    /// exactly at ENDTIM.
    ///
    /// [`Curve::step_cap`]: crate::curve::Curve::step_cap
    fn next_time_step(&mut self, dt_crit: f64, dt_elem: u32) -> Result<f64, SolverError> {
        let c = &self.model.control;
        let mut dt = c.tssfac * dt_crit.min(self.dt_contact);
        if let Some(sep) = &self.separation {
            dt = dt.min(sep.cohesive_time_step());
        }
        if !dt_crit.is_finite() && self.state.step > 0 && self.eroded_count() > 0 {
            // every deformable element has eroded: go on with the last step
            dt = dt.min(self.state.dt_prev);
        }
        if c.dt_init > 0.0 && (self.state.step == 0 || !dt_crit.is_finite()) {
            // DTINIT caps the first step, and is the step of a model with no deformable element
            dt = dt.min(c.dt_init);
        }
        let element_id = |e: u32| self.model.elem_ids.get(e as usize).copied().unwrap_or(0);
        if self.state.step == 0 {
            self.dt_floor = c.dt_min * dt;
        } else if dt < self.dt_floor {
            return Err(SolverError::TimeStepTooSmall {
                dt,
                floor: self.dt_floor,
                element: element_id(dt_elem),
                time: self.state.t,
                step: self.state.step,
            });
        }
        if !dt.is_finite() || dt <= 0.0 {
            return Err(self.bad_time_step(dt, dt_elem));
        }
        if let Some(k) = c.dt_max_curve {
            // LCTM: the largest step allowed at this time (after the floor, which guards the
            // elements' own step: a curve asking for a short step is no collapse)
            if let Some(cap) = self.model.curves[k].step_cap(self.state.t) {
                dt = dt.min(cap);
            }
        }
        self.state.dt_element = dt_elem;
        let remaining = c.end_time - self.state.t;
        // a last step of round-off is not taken; a first step longer than the whole run is
        // cut to it (not skipped)
        if remaining <= 1e-9 * dt.min(c.end_time) {
            self.finished = true;
        } else if dt > remaining {
            dt = remaining;
        }
        Ok(dt)
    }

    /// The error for a time step `dt` that cannot be used, controlled by element `e`.
    fn bad_time_step(&self, dt: f64, e: u32) -> SolverError {
        SolverError::BadTimeStep {
            dt,
            element: self.model.elem_ids.get(e as usize).copied().unwrap_or(0),
            time: self.state.t,
            step: self.state.step,
        }
    }

    /// v^(n+1/2) = v^(n-1/2) + f/m dt_mid for every node, and the provisional v^n; with
    /// separation f is the node's set's (at its representative) and m the set's mass.
    fn update_velocities(&mut self, dt_mid: f64) {
        let State {
            v,
            v_n,
            dt_prev,
            dt,
            ..
        } = &mut self.state;
        // v^n = v^(n-1/2) + a dt^(n-1/2)/2: the mean of the half steps when dt is constant,
        // and exactly v0 at the first step.
        let w = if dt_mid > 0.0 {
            0.5 * *dt_prev / (*dt_prev + *dt)
        } else {
            0.0
        };
        let f = &self.f;
        let (slots, mass) = sets_view(self.separation.as_ref(), &self.set_mass, &self.setup.mass);
        // entries kept per slot are the force slots themselves
        let slots = if self.per_slot { None } else { slots };
        v.par_iter_mut()
            .zip(v_n.par_iter_mut())
            .enumerate()
            .for_each(|(i, (vi, vni))| {
                let s = slots.map_or(i, |s| s[i] as usize);
                // massless nodes (in no element) stay as they are
                let (m, fi) = (mass[s], f[s]);
                let dv = if m > 0.0 {
                    scale(fi, dt_mid / m)
                } else {
                    [0.0; 3]
                };
                let new = add(*vi, dv);
                *vni = add(*vi, scale(dv, 2.0 * w));
                *vi = new;
            });
    }

    /// Weight of v^(n+1/2) in v^n = (1 - w) v^(n-1/2) + w v^(n+1/2),
    /// w = dt^(n-1/2) / (dt^(n-1/2) + dt^(n+1/2)). At the first step, 1/2: the first update
    /// v^(1/2) = v^0 + a^0 dt/2 is the second half of a symmetric step from the virtual
    /// v^(-1/2) = v^0 - a^0 dt/2.
    fn half_step_weight(&self) -> f64 {
        let s = &self.state;
        if s.step == 0 {
            0.5
        } else if s.dt_prev + s.dt > 0.0 {
            s.dt_prev / (s.dt_prev + s.dt)
        } else {
            0.0
        }
    }

    /// Change the velocity of node i to `v_new` after the free update; keeps v^n consistent
    /// and returns the work of the implied reaction impulse J = m (v_new - v), split as
    /// 1/2 J.v^(n-1/2) (up to t^n) and 1/2 J.v^(n+1/2) (after t^n): what the leapfrog kinetic
    /// energies at t^n and t^(n+1) gain from the impulse. v^(n-1/2) is recovered from the
    /// invariant v^n = (1 - w) v^(n-1/2) + w v. `k` is the node's entry ([`Self::entry`]:
    /// with the entries kept per slot, the node's whole set moves, with its mass). Setting the
    /// same velocity again does nothing and does no work.
    fn constrain_velocity(&mut self, k: usize, v_new: Vec3) -> Work {
        let w = self.half_step_weight();
        let m = self.entry_mass(k);
        let s = &mut self.state;
        let v_old = scale(sub(s.v_n[k], scale(s.v[k], w)), 1.0 / (1.0 - w));
        let dv = sub(v_new, s.v[k]);
        s.v[k] = v_new;
        s.v_n[k] = add(s.v_n[k], scale(dv, w));
        let j = scale(dv, m);
        Work {
            now: 0.5 * dot(j, v_old),
            later: 0.5 * dot(j, v_new),
        }
    }

    /// Rigid bodies: sum force and moment over their nodes, advance, place the nodes; returns
    /// the work of the constraint reactions (split as in [`Self::constrain_velocity`]).
    fn update_rigid_bodies(&mut self, dt_mid: f64, dt_new: f64) -> Work {
        let mut work = Work::default();
        // the body loads on the mass no node carries (a given inertia), at its centre
        let g = self.body_acceleration(self.state.t);
        for b in 0..self.setup.rigid.len() {
            let body = &self.setup.rigid[b];
            let x_cm = self.state.rigid[b].x_cm;
            let mut force = [0.0; 3];
            let mut moment = [0.0; 3];
            if let Some((c, m)) = body.unlumped_centre(x_cm, &self.state.rigid[b].rot) {
                force = scale(g, m);
                moment = cross(sub(c, x_cm), force);
            }
            for &n in &body.nodes {
                let fi = self.node_force(n as usize);
                force = add(force, fi);
                let xi = self.state.x[self.entry(n as usize)];
                moment = add(moment, cross(sub(xi, x_cm), fi));
            }
            let st = &mut self.state.rigid[b];
            let v_old = st.v_cm;
            let w_old = st.omega;
            st.v_cm = add(st.v_cm, scale(force, dt_mid / body.mass));
            body.update_angular(st, moment, dt_mid, dt_new);
            let (v_free, w_free) = (st.v_cm, st.omega);
            body.apply_constraints(st);
            let t_half = self.state.t + 0.5 * dt_new;
            for (rb, pm) in &self.setup.rigid_motion {
                if *rb != b || !pm.window.holds(t_half) {
                    continue;
                }
                let c = &self.model.curves[pm.curve];
                if pm.dof.is_rotation() {
                    // the angular velocity about the axis (VAD 0 only: the reader refuses angles)
                    st.omega = pm.dof.apply(st.omega, pm.sf * c.eval(t_half));
                    st.ang_mom = crate::math::mat_vec(&body.inertia(&st.rot), st.omega);
                    continue;
                }
                let s = match pm.vad {
                    Vad::Velocity => pm.sf * c.eval(t_half),
                    Vad::Displacement => {
                        let target =
                            pm.dof.component(body.x_cm0) + pm.sf * c.eval(self.state.t + dt_new);
                        (target - pm.dof.component(st.x_cm)) / dt_new
                    }
                };
                st.v_cm = pm.dof.apply(st.v_cm, s);
            }
            // work of the constraint reactions: impulse . mean velocity
            let dp = scale(sub(st.v_cm, v_free), body.mass);
            let inertia = body.inertia(&st.rot);
            let dl = crate::math::mat_vec(&inertia, sub(st.omega, w_free));
            work.now += 0.5 * (dot(dp, v_old) + dot(dl, w_old));
            work.later += 0.5 * (dot(dp, st.v_cm) + dot(dl, st.omega));
            let (x_cm1, rot1) = body.next_placement(st, dt_new);
            let w = self.half_step_weight();
            for &n in &body.nodes {
                let i = n as usize;
                let target = body.place(x_cm1, &rot1, self.model.x0[i]);
                // a body's node is in no coincident set when entries are slots: its own
                let k = self.entry(i);
                let v_new = scale(sub(target, self.state.x[k]), 1.0 / dt_new);
                let dv = sub(v_new, self.state.v[k]);
                self.state.v[k] = v_new;
                self.state.v_n[k] = add(self.state.v_n[k], scale(dv, w));
            }
        }
        work
    }

    /// SPC and prescribed nodal motion; returns the work of their reactions.
    fn apply_constraints(&mut self, dt_new: f64) -> Work {
        let mut work = Work::default();
        for k in 0..self.setup.spc.len() {
            let (n, d) = self.setup.spc[k];
            let i = self.entry(n as usize);
            let mut vn = self.state.v[i];
            for a in 0..3 {
                if d[a] {
                    vn[a] = 0.0;
                }
            }
            work += self.constrain_velocity(i, vn);
        }
        let t = self.state.t;
        for k in 0..self.setup.node_motion.len() {
            let pm = &self.setup.node_motion[k];
            let MotionTarget::Node(n) = pm.target else {
                continue;
            };
            if !pm.window.holds(t + 0.5 * dt_new) {
                continue;
            }
            let k = self.entry(n as usize);
            let c = &self.model.curves[pm.curve];
            let s = match pm.vad {
                Vad::Velocity => pm.sf * c.eval(t + 0.5 * dt_new),
                Vad::Displacement => {
                    let target =
                        pm.dof.component(self.model.x0[n as usize]) + pm.sf * c.eval(t + dt_new);
                    (target - pm.dof.component(self.state.x[k])) / dt_new
                }
            };
            let vn = pm.dof.apply(self.state.v[k], s);
            work += self.constrain_velocity(k, vn);
        }
        work
    }

    /// Stonewalls (planar, spherical, cylindrical; fixed or moving): a node that would cross
    /// the wall's surface during the next step lands on it (relative normal velocity -d^n/dt
    /// for the gap d^n, or 0 if already behind; on a curved wall it lands on the tangent plane
    /// at its nearest surface point); friction removes up to FRIC times the normal impulse
    /// from the tangential velocity relative to the wall (FRIC >= 1: no sliding). Returns the
    /// work of the wall on the model.
    fn apply_rigid_walls(&mut self, dt_mid: f64, dt_new: f64) -> Work {
        let mut work = Work::default();
        for wi in 0..self.model.rigid_walls.len() {
            let wall = &self.model.rigid_walls[wi];
            // where the wall is now and how fast it moves over the step (`_MOTION`)
            let t = self.state.t;
            let off = wall.offset(&self.model.curves, t);
            let tail = if wall.motion.is_some() {
                add(wall.tail, off)
            } else {
                wall.tail
            };
            let wv = scale(
                sub(wall.offset(&self.model.curves, t + dt_new), off),
                1.0 / dt_new,
            );
            let axis = wall.normal();
            let mut total = [0.0; 3];
            let mut normal = 0.0;
            for k in 0..self.setup.wall_nodes[wi].len() {
                let i = self.entry(self.setup.wall_nodes[wi][k] as usize);
                if self.per_slot {
                    // the copies of a set are one entry: stopped once
                    if self.wall_seen[i] {
                        continue;
                    }
                    self.wall_seen[i] = true;
                    self.wall_marked.push(i as u32);
                }
                let x = self.state.x[i];
                let v = self.state.v[i];
                let Some((gap, nrm)) = wall.gap(x, tail, axis) else {
                    continue;
                };
                // the velocity relative to the wall
                let vr = sub(v, wv);
                let vn = dot(vr, nrm);
                if gap + dt_new * vn >= 0.0 {
                    continue;
                }
                // land exactly on the wall (on its tangent plane, for a curved one); a node
                // already behind it only stops
                let vn_new = if gap >= 0.0 { -gap / dt_new } else { 0.0 };
                let dvn = vn_new - vn; // > 0
                let vt = sub(vr, scale(nrm, vn));
                let vt_mag = norm(vt);
                let vt_new = if wall.fric >= 1.0 || vt_mag <= wall.fric * dvn {
                    [0.0; 3]
                } else {
                    scale(vt, 1.0 - wall.fric * dvn / vt_mag)
                };
                let v_rel = add(scale(nrm, vn_new), vt_new);
                let v_new = if wall.motion.is_some() {
                    add(wv, v_rel)
                } else {
                    v_rel
                };
                let m = self.entry_mass(i);
                let impulse = scale(sub(v_new, v), m);
                total = add(total, impulse);
                normal += m * dvn;
                work += self.constrain_velocity(i, v_new);
            }
            for &i in &self.wall_marked {
                self.wall_seen[i as usize] = false;
            }
            self.wall_marked.clear();
            let inv = if dt_mid > 0.0 { 1.0 / dt_mid } else { 0.0 };
            self.wall_forces[wi] = WallForce {
                normal: normal * inv,
                force: scale(total, inv),
            };
        }
        work
    }

    /// Kinetic energy at t^n and the work of body loads since t^(n-1); detects non-finite
    /// velocities. Returns the body-load work.
    ///
    /// The kinetic energy is the leapfrog's, K^n = 1/2 sum m v^(n-1/2) . v^(n+1/2) (at the
    /// first step v^(-1/2) = v^0 - a^0 dt/2, see [`Self::half_step_weight`]): with the trapezoid
    /// work of the forces, K^(n+1) - K^n = 1/2 (f^n + f^(n+1)) . (x^(n+1) - x^n) exactly for a
    /// constant time step, whatever the forces. So the ledger balances even for a fragment of
    /// one element ringing near its stability limit (omega dt near 2), where 1/2 m |v^n|^2 with
    /// the mean velocity v^n would be off by up to (omega dt)^2 / 4 of its energy. The two
    /// differ by 1/8 m |a dt|^2 per node.
    ///
    /// Body loads: the trapezoid 1/2 (g^(n-1) + g^n) . P^(n-1/2) dt^(n-1/2), with P the momentum.
    fn record_kinetic_energy(&mut self) -> Result<f64, SolverError> {
        let mut sums = std::mem::take(&mut self.node_sums);
        let mass = self.entry_masses();
        let vn = &self.state.v_n;
        let vh = &self.state.v;
        let w = self.half_step_weight();
        vn.par_chunks(NODE_CHUNK)
            .zip(vh.par_chunks(NODE_CHUNK))
            .enumerate()
            .map(|(c, (chunk, half))| {
                let mut s = [0.0; 4];
                for (k, (v, u)) in chunk.iter().zip(half).enumerate() {
                    let m = mass[c * NODE_CHUNK + k];
                    // v^(n-1/2) from v^n = (1 - w) v^(n-1/2) + w v^(n+1/2)
                    let old = scale(sub(*v, scale(*u, w)), 1.0 / (1.0 - w));
                    s[0] += 0.5 * m * dot(old, *u);
                    for d in 0..3 {
                        s[1 + d] += m * old[d];
                    }
                }
                s
            })
            .collect_into_vec(&mut sums);
        self.node_sums = sums;
        let mut s = [0.0; 4];
        for p in &self.node_sums {
            for k in 0..4 {
                s[k] += p[k];
            }
        }
        if !s[0].is_finite() {
            return Err(self.non_finite_node());
        }
        // the mass of the bodies with a given inertia, which no node carries
        let first = self.state.step == 0;
        for (body, st) in self.setup.rigid.iter().zip(&self.state.rigid) {
            if body.unlumped.is_some() {
                let (ke, p_old, _) =
                    body.unlumped_motion(st, self.state.dt_prev, self.state.dt, first);
                s[0] += ke;
                for d in 0..3 {
                    s[1 + d] += p_old[d];
                }
            }
        }
        self.state.energy.kinetic = s[0];
        let dt = self.state.dt_prev;
        if self.model.body_loads.is_empty() || dt == 0.0 {
            return Ok(0.0);
        }
        let g = add(
            self.body_acceleration(self.state.t - dt),
            self.body_acceleration(self.state.t),
        );
        Ok(0.5 * dot(g, [s[1], s[2], s[3]]) * dt)
    }

    /// x^(n+1) = x^n + dt v^(n+1/2); rigid bodies commit their placement; t += dt.
    pub fn update_positions(&mut self) -> Result<(), SolverError> {
        let t0 = Instant::now();
        let dt = self.state.dt;
        let State { x, v, .. } = &mut self.state;
        x.par_iter_mut().zip(v.par_iter()).for_each(|(xi, vi)| {
            *xi = add(*xi, scale(*vi, dt));
        });
        for (b, body) in self.setup.rigid.iter().enumerate() {
            let st = &mut self.state.rigid[b];
            let (x_cm, rot) = body.next_placement(st, dt);
            st.prev_x_cm = st.x_cm;
            st.prev_rot = st.rot;
            st.x_cm = x_cm;
            st.rot = rot;
        }
        self.state.t += dt;
        self.state.dt_prev = dt;
        self.state.step += 1;
        self.times.nodal += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// Replace the positions x^n and the velocities v^(n+1/2) and v^n of every node (one entry
    /// per node; with separation one per slot of the coincident sets, [`Self::slot_masses`]),
    /// and say whether the state is the last: for a backend that steps elsewhere (the GPU) and
    /// shows its state through this solver.
    pub fn set_kinematics(&mut self, x: Vec<Vec3>, v: Vec<Vec3>, v_n: Vec<Vec3>) {
        assert!(
            x.len() == self.state.x.len() && (self.separation.is_none() || self.per_slot),
            "set_kinematics takes one entry per node, or per slot of the coincident sets"
        );
        self.state.x = x;
        self.state.v = v;
        self.state.v_n = v_n;
    }

    /// With separation and the positions kept per slot of the coincident sets (no rigid body's
    /// node in a set), the mass that moves with each slot: its set's `sum m`, a lone node's
    /// own; `None` otherwise.
    pub fn slot_masses(&self) -> Option<&[f64]> {
        (self.separation.is_some() && self.per_slot).then_some(&self.set_mass[..])
    }

    /// Mark the state as the last (or not): see [`Self::set_kinematics`].
    pub fn set_finished(&mut self, finished: bool) {
        self.finished = finished;
    }

    /// The tied contacts' slave nodes and the face points they follow ([`crate::tied`]).
    pub fn ties(&self) -> &[crate::tied::Tie] {
        &self.ties
    }

    /// Momentum sum m v^n over all nodes (at t^n).
    pub fn momentum(&self) -> Vec3 {
        let mut p = [0.0; 3];
        for (m, v) in self.entry_masses().iter().zip(&self.state.v_n) {
            p = add(p, scale(*v, *m));
        }
        // the mass of the bodies with a given inertia: the same mean of the half steps
        let w = self.half_step_weight();
        let s = &self.state;
        for (body, st) in self.setup.rigid.iter().zip(&s.rigid) {
            if body.unlumped.is_some() {
                let (_, p_old, p_new) = body.unlumped_motion(st, s.dt_prev, s.dt, s.step == 0);
                p = add(p, add(scale(p_old, 1.0 - w), scale(p_new, w)));
            }
        }
        p
    }
}

/// Where each node's forces are summed and the mass that divides them: with separation, the
/// slots of the coincident sets ([`crate::separation::coincident::CoincidentSets::slots`]) and
/// the masses of the slots' sets; without, the nodes themselves (`None`) and their own
/// masses.
fn sets_view<'a>(
    separation: Option<&'a Separation>,
    set_mass: &'a [f64],
    mass: &'a [f64],
) -> (Option<&'a [u32]>, &'a [f64]) {
    match separation {
        Some(sep) => (Some(sep.sets().slots()), set_mass),
        None => (None, mass),
    }
}
