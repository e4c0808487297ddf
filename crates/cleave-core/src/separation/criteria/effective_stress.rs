//! MODEL 2 (and the onset of MODEL 3): the effective traction of Camacho and Ortiz (1996),
//! `t_eff = sqrt(<sn>^2 + (tau / BETA)^2)`, reaches SIGMAX. `<sn>` is the tensile part of the
//! normal traction (compression does not count), tau the magnitude of the shear traction, BETA
//! the shear-to-normal weight.

use super::{Criterion, InterfaceSample};

/// Effective traction over strength.
#[derive(Clone, Copy, Debug)]
pub struct EffectiveStress {
    /// Tensile strength (Pa).
    pub sigmax: f64,
    /// Shear-to-normal weight (BETA > 0).
    pub beta: f64,
}

impl Criterion for EffectiveStress {
    fn failure_index(&self, s: &InterfaceSample) -> f64 {
        let (sn, tau) = s.normal_and_shear();
        let sn = sn.max(0.0);
        let ts = tau / self.beta;
        (sn * sn + ts * ts).sqrt() / self.sigmax
    }

    /// `sqrt(<sn>^2 + (tau/BETA)^2) <= |t| max(1, 1/BETA)`.
    fn reachable(&self, traction_bound: f64) -> bool {
        traction_bound * (1.0f64).max(1.0 / self.beta) >= self.sigmax
    }
}
