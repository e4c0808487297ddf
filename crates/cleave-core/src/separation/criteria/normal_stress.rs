//! MODEL 1, the paper's criterion (Gerken, Bennett and Smith, section 3): the interface fails
//! when the normal tensile stress n.s.n on it reaches the strength SIGMAX, with s the mean
//! Cauchy stress of the two elements and n the current face normal. Shear and compression
//! never fail it.

use super::{Criterion, InterfaceSample};

/// Normal stress over strength: index = (n.s.n) / SIGMAX.
#[derive(Clone, Copy, Debug)]
pub struct NormalStress {
    /// Tensile strength (Pa).
    pub sigmax: f64,
}

impl Criterion for NormalStress {
    fn failure_index(&self, s: &InterfaceSample) -> f64 {
        s.normal_and_shear().0 / self.sigmax
    }

    fn reachable(&self, traction_bound: f64) -> bool {
        traction_bound >= self.sigmax
    }
}
