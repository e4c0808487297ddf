//! What a restart file keeps of the contact: every definition's search state (sides, passes,
//! candidate schedules, closed cracks, reference positions) and the contact forces of the last
//! step, so that a continued run searches and pushes exactly as the uninterrupted one. The face
//! table and the threads' bounds caches are rebuilt (the caches hold nothing a check's result
//! depends on: [`super::bounds_cache`]).

use serde::{Deserialize, Serialize};

use super::{Contact, ContactForce, ContactSet, NodalForces};

/// The contact's state, borrowed for writing.
#[derive(Serialize)]
pub(crate) struct SavedRef<'a> {
    contacts: &'a [Contact],
    nodal: &'a NodalForces,
    forces: &'a [ContactForce],
}

/// The contact's state, read back.
#[derive(Deserialize)]
pub(crate) struct Saved {
    contacts: Vec<Contact>,
    nodal: NodalForces,
    forces: Vec<ContactForce>,
}

impl ContactSet<'_> {
    /// The state a restart file keeps.
    pub(crate) fn saved(&self) -> SavedRef<'_> {
        SavedRef {
            contacts: &self.contacts,
            nodal: &self.nodal,
            forces: &self.forces,
        }
    }

    /// Take up a saved state (of a contact set built from the same model).
    pub(crate) fn restore(&mut self, s: Saved) -> Result<(), String> {
        let ids = |c: &[Contact]| c.iter().map(|c| c.id).collect::<Vec<_>>();
        if ids(&s.contacts) != ids(&self.contacts) || s.forces.len() != self.forces.len() {
            return Err("its contact definitions are not the deck's".into());
        }
        self.contacts = s.contacts;
        self.nodal = s.nodal;
        self.forces = s.forces;
        // the threads' bounds caches are made room for again at the next step
        self.reserved = 0;
        Ok(())
    }
}
