//! The solver's complete state between two steps, as bytes, for a restart file
//! (`cleave run --checkpoint-every`, `--restart`).
//!
//! Saved after the position update of a step (x^(n+1), v^(n+1/2), t^(n+1), the stresses and
//! histories, the energies, the interfaces with the coincident sets as they have split, the
//! cohesive faces, the contact's search state and last forces, the loads' last forces, and
//! the scratch that carries from one step to the next), and taken up by a solver built again
//! from the same model, which then steps exactly as the uninterrupted one, bit for bit.
//! What the model determines (setup, colouring, criteria, face table) is built, not saved.
//!
//! Format: postcard (serde), floats as their IEEE bits. The caller (the command line) adds a
//! header naming the version and the deck, and refuses a file made by another.

use serde::{Deserialize, Serialize};

use super::{ElemChunkSum, Solver, WallForce};
use crate::contact::restart::{Saved as ContactSaved, SavedRef as ContactSavedRef};
use crate::contact::Crack;
use crate::element::nodal_pressure::NodalPressure;
use crate::element::sri::SriElements;
use crate::loads::Loads;
use crate::math::Vec3;
use crate::separation::interfaces::Separation;
use crate::state::State;

/// The solver's state, borrowed for writing.
#[derive(Serialize)]
struct SavedRef<'a> {
    state: &'a State,
    wall_forces: &'a [WallForce],
    f: &'a [Vec3],
    set_mass: &'a [f64],
    split_nodes: &'a [u32],
    split_elems: &'a [u32],
    chunk_sums: &'a [ElemChunkSum],
    node_sums: &'a [[f64; 4]],
    finished: bool,
    pending_work: f64,
    separation: Option<&'a Separation>,
    per_slot: bool,
    wall_seen: &'a [bool],
    wall_marked: &'a [u32],
    contact: Option<ContactSavedRef<'a>>,
    new_cracks: &'a [Crack],
    dt_contact: f64,
    dt_floor: f64,
    nodal_pressure: Option<&'a NodalPressure>,
    loads: &'a Loads,
    sri: Option<&'a SriElements>,
}

/// The solver's state, read back.
#[derive(Deserialize)]
struct Saved {
    state: State,
    wall_forces: Vec<WallForce>,
    f: Vec<Vec3>,
    set_mass: Vec<f64>,
    split_nodes: Vec<u32>,
    split_elems: Vec<u32>,
    chunk_sums: Vec<ElemChunkSum>,
    node_sums: Vec<[f64; 4]>,
    finished: bool,
    pending_work: f64,
    separation: Option<Separation>,
    per_slot: bool,
    wall_seen: Vec<bool>,
    wall_marked: Vec<u32>,
    contact: Option<ContactSaved>,
    new_cracks: Vec<Crack>,
    dt_contact: f64,
    dt_floor: f64,
    nodal_pressure: Option<NodalPressure>,
    loads: Loads,
    sri: Option<SriElements>,
}

impl Solver<'_> {
    /// The complete state between two steps, as bytes ([module docs](self)).
    pub fn save_state(&self) -> Vec<u8> {
        let s = SavedRef {
            state: &self.state,
            wall_forces: &self.wall_forces,
            f: &self.f,
            set_mass: &self.set_mass,
            split_nodes: &self.split_nodes,
            split_elems: &self.split_elems,
            chunk_sums: &self.chunk_sums,
            node_sums: &self.node_sums,
            finished: self.finished,
            pending_work: self.pending_work,
            separation: self.separation.as_ref(),
            per_slot: self.per_slot,
            wall_seen: &self.wall_seen,
            wall_marked: &self.wall_marked,
            contact: self.contact.as_ref().map(|c| c.saved()),
            new_cracks: &self.new_cracks,
            dt_contact: self.dt_contact,
            dt_floor: self.dt_floor,
            nodal_pressure: self.nodal_pressure.as_ref(),
            loads: &self.loads,
            sri: self.sri.as_ref(),
        };
        postcard::to_stdvec(&s).expect("the solver state serialises (no maps with non-key types)")
    }

    /// Take up a state of [`Self::save_state`]. This solver must be built as the one that saved
    /// it was (the same model, with its separation and contact attached, no step taken); the
    /// error says what does not match.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let s: Saved = postcard::from_bytes(bytes).map_err(|e| format!("unreadable state: {e}"))?;
        let ne = self.model.num_elements();
        if s.state.stress.len() != ne || s.state.hist.len() != ne || s.state.hg.len() != ne {
            return Err(format!(
                "it holds {} elements, the deck {ne}",
                s.state.stress.len()
            ));
        }
        if s.separation.is_some() != self.separation.is_some()
            || s.contact.is_some() != self.contact.is_some()
            || s.sri.is_some() != self.sri.is_some()
            || s.nodal_pressure.is_some() != self.nodal_pressure.is_some()
            || s.wall_forces.len() != self.wall_forces.len()
            || s.state.rigid.len() != self.state.rigid.len()
            || s.per_slot != self.per_slot
        {
            return Err("its model is not the deck's (separation, contact, walls, rigid bodies or element formulations differ)".into());
        }
        if let (Some(mine), Some(saved)) = (&mut self.separation, s.separation) {
            mine.restore(saved)?;
        }
        if let (Some(mine), Some(saved)) = (&mut self.contact, s.contact) {
            mine.restore(saved)?;
        }
        self.state = s.state;
        self.wall_forces = s.wall_forces;
        self.f = s.f;
        self.set_mass = s.set_mass;
        self.split_nodes = s.split_nodes;
        self.split_elems = s.split_elems;
        self.chunk_sums = s.chunk_sums;
        self.node_sums = s.node_sums;
        self.finished = s.finished;
        self.pending_work = s.pending_work;
        self.wall_seen = s.wall_seen;
        self.wall_marked = s.wall_marked;
        self.new_cracks = s.new_cracks;
        self.dt_contact = s.dt_contact;
        self.dt_floor = s.dt_floor;
        self.nodal_pressure = s.nodal_pressure;
        self.loads = s.loads;
        self.sri = s.sri;
        Ok(())
    }
}
