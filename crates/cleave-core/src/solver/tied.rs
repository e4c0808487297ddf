//! The solver's part of tied contact ([`crate::tied`]): the masses and start positions, the
//! force transfer after each assembly, the slave velocities after each update.

use super::Solver;
use crate::error::SolverError;
use crate::math::{add, scale, Vec3};
use crate::model::MotionTarget;
use crate::rigid::NOT_RIGID;
use crate::tied::{Tie, Ties};

/// `sum_a w_a v[m_a]`.
fn interpolate(t: &Tie, v: &[Vec3]) -> Vec3 {
    (0..4).fold([0.0; 3], |s, a| {
        add(s, scale(v[t.masters[a] as usize], t.weights[a]))
    })
}

impl Solver<'_> {
    /// Ties the model's tied contacts: each slave node's mass goes to its face's nodes, and it
    /// starts on the face with the face's velocity. Errors: a slave node with an SPC, a
    /// prescribed motion or a rigid body, a face node of a rigid body.
    pub(super) fn set_up_ties(&mut self) -> Result<(), SolverError> {
        let ties = Ties::new(self.model).map_err(SolverError::Setup)?;
        if ties.ties.is_empty() {
            return Ok(());
        }
        let m = self.model;
        let id = |n: u32| m.node_ids[n as usize];
        // a mask, not a list: a lookup per tie
        let mut constrained = vec![false; m.num_nodes()];
        let moved = self
            .setup
            .node_motion
            .iter()
            .filter_map(|p| match p.target {
                MotionTarget::Node(n) => Some(n),
                _ => None,
            });
        for n in self.setup.spc.iter().map(|s| s.0).chain(moved) {
            constrained[n as usize] = true;
        }
        for t in &ties.ties {
            if constrained[t.slave as usize] {
                return Err(SolverError::Setup(format!(
                    "node {} is a tied contact's slave node and has an SPC or a prescribed motion: constrain the face it is tied to instead",
                    id(t.slave)
                )));
            }
            let rigid = |n: u32| self.setup.node_rigid[n as usize] != NOT_RIGID;
            if let Some(&n) = std::iter::once(&t.slave)
                .chain(&t.masters)
                .find(|&&n| rigid(n))
            {
                return Err(SolverError::Setup(format!(
                    "node {} of a tied contact belongs to a rigid body: tying to or from rigid bodies is not supported yet",
                    id(n)
                )));
            }
        }
        for w in &ties.untied {
            if w.1 > 0 {
                self.setup.warnings.push(format!(
                    "tied contact {}: {} slave node(s) found no master face within {} of its size and stay free",
                    w.0,
                    w.1,
                    crate::tied::TOLERANCE
                ));
            }
        }
        let st = &mut self.state;
        for t in &ties.ties {
            let s = t.slave as usize;
            let ms = self.setup.mass[s];
            for a in 0..4 {
                self.setup.mass[t.masters[a] as usize] += t.weights[a] * ms;
            }
            self.setup.mass[s] = 0.0;
            st.x[s] = interpolate(t, &st.x);
            st.v[s] = interpolate(t, &st.v);
            st.v_n[s] = interpolate(t, &st.v_n);
        }
        self.ties = ties.ties;
        Ok(())
    }

    /// After the force assembly: each slave node's force goes to its face's nodes.
    pub(super) fn transfer_tied_forces(&mut self) {
        for t in &self.ties {
            let fs = std::mem::replace(&mut self.f[t.slave as usize], [0.0; 3]);
            for a in 0..4 {
                let k = t.masters[a] as usize;
                self.f[k] = add(self.f[k], scale(fs, t.weights[a]));
            }
        }
    }

    /// After the velocity update and the constraints: each slave node moves with its face.
    pub(super) fn move_tied_nodes(&mut self) {
        let st = &mut self.state;
        for t in &self.ties {
            st.v[t.slave as usize] = interpolate(t, &st.v);
            st.v_n[t.slave as usize] = interpolate(t, &st.v_n);
        }
    }
}
