//! MODEL 1, the paper's criterion (Gerken, Bennett and Smith, section 3): the interface fails
//! when the normal tensile stress n.s.n on it reaches its strength (SIGMAX), with s the mean
//! Cauchy stress of the two elements and n the current face normal. Shear and compression
//! never fail it.

use super::{Criterion, InterfaceSample};
use crate::math::Sym3;

/// The normal stress n.s.n.
#[derive(Clone, Copy, Debug)]
pub struct NormalStress;

impl Criterion for NormalStress {
    fn stress(&self, s: &InterfaceSample) -> f64 {
        s.normal_and_shear().0
    }

    /// [`super::tension_bound`].
    fn bound(&self, a: &Sym3, b: &Sym3) -> f64 {
        super::tension_bound(a, b)
    }
}
