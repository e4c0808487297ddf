//! Helpers shared by the core's integration tests.

#![allow(dead_code)] // each test file uses its own subset of the helpers

use cleave_core::contact::ContactSet;
use cleave_core::model::Model;
use cleave_core::solver::{Observer, Solver};

/// An observer from a closure.
pub struct Obs<F: FnMut(&Solver)>(pub F);

impl<F: FnMut(&Solver)> Observer for Obs<F> {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        (self.0)(s);
        Ok(())
    }
}

/// Run `m` (with its contact definitions, if any) to its end time, calling `f` with the state
/// at every step t^n.
pub fn run(m: &Model, f: impl FnMut(&Solver)) -> Solver<'_> {
    let mut s = Solver::new(m).expect("setup");
    if !m.contacts.is_empty() {
        s.attach_contact(ContactSet::new(m, None).expect("contact"));
    }
    s.run(&mut Obs(f)).expect("run");
    s
}
