//! MODEL 2 (and the onset of MODELs 3 and 4): the effective traction of Camacho and Ortiz
//! (1996), `t_eff = sqrt(<sn>^2 + (tau / BETA)^2)`, reaches the strength (SIGMAX). `<sn>` is
//! the tensile part of the normal traction (compression does not count), tau the magnitude of
//! the shear traction, BETA the shear-to-normal weight.

use super::{Criterion, InterfaceSample};
use crate::math::Sym3;

/// The effective traction.
#[derive(Clone, Copy, Debug)]
pub struct EffectiveStress {
    /// Shear-to-normal weight (BETA > 0).
    pub beta: f64,
}

impl Criterion for EffectiveStress {
    fn stress(&self, s: &InterfaceSample) -> f64 {
        let (sn, tau) = s.normal_and_shear();
        let sn = sn.max(0.0);
        let ts = tau / self.beta;
        (sn * sn + ts * ts).sqrt()
    }

    /// `sqrt(<sn>^2 + (tau/BETA)^2) <= |t| max(1, 1/BETA)`, with [`super::traction_bound`]
    /// for |t|.
    fn bound(&self, a: &Sym3, b: &Sym3) -> f64 {
        (1.0f64).max(1.0 / self.beta) * super::traction_bound(a, b)
    }
}
