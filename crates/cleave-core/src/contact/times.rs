//! Wall-clock seconds of each phase of the contact's steps, for benchmarks and profiles
//! (`cleave bench ball` prints them). A phase's time is taken around it on the thread that
//! runs the step; the closed cracks' forces are summed on one thread while the searches and
//! the node checks run on the others, so on more than one thread their time overlaps those.
//! Taking the times costs a few clock reads a step and changes no result.

use std::time::Instant;

/// Seconds in each phase, summed over the steps and the definitions.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
#[serde(default)]
pub struct ContactTimes {
    /// The motion bound's tracking of the positions (and the watch of new nodes).
    pub tracking: f64,
    /// The closed cracks' step: their pairs' forces worked out, the released ones settled.
    pub closed_cracks: f64,
    /// Their forces summed into the nodes, beside the searches and checks.
    pub closed_forces: f64,
    /// The incremental searches around the faces of failed interfaces, and the relabelling of
    /// the copies whose ties or closed cracks changed (every step some did).
    pub incremental: f64,
    /// The full builds of the candidate lists.
    pub full_builds: f64,
    /// The checks of the nodes with a candidate due (and the renewal of those whose faces
    /// changed).
    pub node_checks: f64,
    /// The node-to-face pairs' forces summed into the nodes, and every contact force added to
    /// the nodal forces with its work.
    pub pair_forces: f64,
    /// The faces of failed interfaces joining the surfaces, their cracks closed.
    pub activation: f64,
}

impl ContactTimes {
    /// The sum of every phase (with the closed cracks' forces, which may overlap others).
    pub fn total(&self) -> f64 {
        self.tracking
            + self.closed_cracks
            + self.closed_forces
            + self.incremental
            + self.full_builds
            + self.node_checks
            + self.pair_forces
            + self.activation
    }

    /// These and `o`'s, phase by phase.
    pub fn plus(&self, o: &Self) -> Self {
        Self {
            tracking: self.tracking + o.tracking,
            closed_cracks: self.closed_cracks + o.closed_cracks,
            closed_forces: self.closed_forces + o.closed_forces,
            incremental: self.incremental + o.incremental,
            full_builds: self.full_builds + o.full_builds,
            node_checks: self.node_checks + o.node_checks,
            pair_forces: self.pair_forces + o.pair_forces,
            activation: self.activation + o.activation,
        }
    }
}

/// Add the seconds since `t` to `phase`, and restart `t`.
#[inline]
pub(super) fn lap(t: &mut Instant, phase: &mut f64) {
    let now = Instant::now();
    *phase += (now - *t).as_secs_f64();
    *t = now;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phases_add_up() {
        let a = ContactTimes {
            tracking: 1.0,
            closed_cracks: 2.0,
            closed_forces: 3.0,
            incremental: 4.0,
            full_builds: 5.0,
            node_checks: 6.0,
            pair_forces: 7.0,
            activation: 8.0,
        };
        assert_eq!(a.total(), 36.0);
        assert_eq!(a.plus(&a).total(), 72.0);
        let mut t = Instant::now();
        let mut p = 0.0;
        std::thread::sleep(std::time::Duration::from_millis(2));
        lap(&mut t, &mut p);
        assert!(p >= 0.002, "{p}");
    }
}
