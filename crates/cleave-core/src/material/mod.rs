//! Constitutive laws for solid elements, as pointwise stress updates.
//!
//! Every law is hypoelastic in the Jaumann (Hughes-Winget) sense: the element kernel first
//! rotates the stress and any tensorial history with the incremental rotation, then calls
//! [`SolidParams::update`] with the rate-of-deformation increment `d_eps = D dt` (tensor
//! components, LS-DYNA order xx yy zz xy yz zx).

mod elastic;
mod eos;
mod johnson_cook;
mod piecewise;
mod plastic;
mod return_map;

pub use elastic::update_elastic;
pub use eos::{Eos, EosState};
pub use johnson_cook::{update_johnson_cook, JohnsonCook};
pub use piecewise::{update_piecewise, PiecewiseLinear, RateTable};
pub use plastic::update_plastic_kinematic;

use crate::math::Sym3;
use crate::model::{Material, MaterialKind};

/// Per-element history of a material point: effective plastic strain, back stress,
/// temperature rise, and for a material with an equation of state the log volume ratio and the
/// internal energy ([`EosState`]).
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct History {
    /// Effective (equivalent) plastic strain.
    pub eps_p: f64,
    /// Back stress (kinematic hardening centre), deviatoric.
    pub back: Sym3,
    /// Adiabatic temperature rise from plastic work (K; Johnson-Cook).
    pub heat: f64,
    /// ln(V / V_start) of an equation of state's material point.
    pub ln_j: f64,
    /// Internal energy per unit reference volume less E0 (Pa), for an equation of state.
    pub energy: f64,
    /// The element's energy so far (J): the work of its stresses, bulk viscosity and
    /// hourglass forces, what it takes away when it erodes ([`crate::erosion`]).
    #[serde(default)]
    pub work: f64,
}

/// A material law with its parameters precomputed for the kernel.
#[derive(Clone, Debug, PartialEq)]
pub enum SolidLaw {
    Elastic,
    /// Bilinear plasticity: `sigy` initial yield, `hp` plastic hardening modulus
    /// E Et / (E - Et), `beta` isotropic fraction.
    PlasticKinematic {
        sigy: f64,
        hp: f64,
        beta: f64,
    },
    /// Johnson-Cook plasticity.
    JohnsonCook(JohnsonCook),
    /// Piecewise linear hardening with Cowper-Symonds rate scaling.
    Piecewise(PiecewiseLinear),
}

/// Material parameters the element kernel needs, precomputed once per material.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidParams {
    pub density: f64,
    /// Lame lambda.
    pub lambda: f64,
    /// Shear modulus G.
    pub shear: f64,
    /// Dilatational wave speed sqrt((lambda + 2G)/rho).
    pub wave_speed: f64,
    /// Speed in the element time step l_c / c: the wave speed, or [`free_element_speed`] for an
    /// element of a split mesh that has lost a neighbour.
    pub step_speed: f64,
    pub law: SolidLaw,
}

/// Speed that makes l_c / c a stable time step for a hexahedron that may come loose as a
/// fragment of its own: sqrt(3K/rho) when that exceeds the wave speed (any Poisson ratio > 0).
///
/// A free one-point hex8 of side h with its lumped mass rho V / 8 per corner has the uniform
/// dilatation mode omega^2 = 12 K / (rho h^2) (strain energy 9K/2 (2 delta/h)^2 V for corner
/// offsets delta, kinetic energy 3/2 rho V delta_dot^2), so central differences need
/// dt <= 2/omega = h / sqrt(3K/rho). Inside a mesh the neighbours hold that mode down and
/// h / c_L is the usual step; where interfaces have failed, corners and whole elements come
/// loose, and the element eigenvalue bound (the assembly's highest frequency is at most the
/// highest of its elements) makes the single-element limit the safe one. For Poisson 0.3 the
/// step is 0.73 of h / c_L; for 0.22 (alumina) 0.80. The solver uses it for the elements whose
/// coincident sets an interface failure has touched, so an intact split mesh keeps exactly the
/// time steps of the original mesh.
pub fn free_element_speed(m: &Material) -> f64 {
    (3.0 * m.bulk_modulus() / m.density)
        .sqrt()
        .max(m.wave_speed())
}

impl SolidParams {
    /// Kernel parameters of a deformable material; `None` for a rigid one.
    pub fn from_material(m: &Material) -> Option<Self> {
        let law = match m.kind {
            MaterialKind::Elastic => SolidLaw::Elastic,
            MaterialKind::PlasticKinematic { sigy, etan, beta } => {
                // Plastic hardening modulus: 1/Et = 1/E + 1/Hp.
                let hp = if etan > 0.0 && etan < m.young {
                    m.young * etan / (m.young - etan)
                } else {
                    0.0
                };
                SolidLaw::PlasticKinematic { sigy, hp, beta }
            }
            MaterialKind::JohnsonCook(jc) => SolidLaw::JohnsonCook(jc),
            MaterialKind::PiecewiseLinear(ref p) => SolidLaw::Piecewise(p.clone()),
            MaterialKind::Rigid { .. } => return None,
        };
        Some(Self {
            density: m.density,
            lambda: m.lame_lambda(),
            shear: m.shear_modulus(),
            wave_speed: m.wave_speed(),
            step_speed: m.wave_speed(),
            law,
        })
    }

    /// Update `sigma` (already rotated) with the strain increment `d_eps` over the time `dt`.
    #[inline]
    pub fn update(&self, sigma: &mut Sym3, d_eps: &Sym3, dt: f64, hist: &mut History) {
        match self.law {
            SolidLaw::Elastic => update_elastic(self.lambda, self.shear, sigma, d_eps),
            SolidLaw::PlasticKinematic { sigy, hp, beta } => update_plastic_kinematic(
                self.lambda,
                self.shear,
                sigy,
                hp,
                beta,
                sigma,
                d_eps,
                hist,
            ),
            SolidLaw::JohnsonCook(jc) => {
                update_johnson_cook(self.lambda, self.shear, &jc, sigma, d_eps, dt, hist)
            }
            SolidLaw::Piecewise(ref p) => {
                update_piecewise(self.lambda, self.shear, p, sigma, d_eps, dt, hist)
            }
        }
    }
}
