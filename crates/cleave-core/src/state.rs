//! The state: everything a step changes.

use crate::material::History;
use crate::math::{Mat3, Sym3, Vec3};

/// The energy ledger, each value at the current time t^n.
///
/// Balance: kinetic + internal + hourglass + contact + fracture = initial total + external work.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// 1/2 sum m |v^n|^2, with v^n the mean of the half-step velocities on either side.
    pub kinetic: f64,
    /// Work of the element stresses and of bulk viscosity.
    pub internal: f64,
    /// Work done against hourglass forces.
    pub hourglass: f64,
    /// Contact energy, including frictional dissipation.
    pub contact: f64,
    /// Energy dissipated by cohesive laws.
    pub fracture: f64,
    /// Work of prescribed motion, body loads and rigid walls on the model.
    pub external_work: f64,
    /// The energy eroded elements held when they eroded ([`crate::erosion`]); a part of
    /// `internal` and `hourglass`, not added to the total again.
    #[serde(default)]
    pub eroded: f64,
}

impl Energies {
    /// kinetic + internal + hourglass + contact + fracture.
    pub fn total(&self) -> f64 {
        self.kinetic + self.internal + self.hourglass + self.contact + self.fracture
    }
}

/// Motion of one rigid body.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct RigidState {
    /// Centre of mass at t^n.
    pub x_cm: Vec3,
    /// Velocity of the centre of mass at t^(n-1/2) (t^(n+1/2) after the velocity update).
    pub v_cm: Vec3,
    /// Rotation from the reference configuration at t^n.
    pub rot: Mat3,
    /// Angular momentum about the centre of mass, spatial frame, at the half step.
    pub ang_mom: Vec3,
    /// Angular velocity at the half step.
    pub omega: Vec3,
    /// Centre of mass and rotation at t^(n-1) (at t^0 before the first step).
    pub prev_x_cm: Vec3,
    pub prev_rot: Mat3,
    /// Initial velocity of the centre of mass and angular velocity.
    pub v0: Vec3,
    pub omega0: Vec3,
}

/// The solution state.
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug, Default)]
pub struct State {
    /// Time t^n.
    pub t: f64,
    /// Step number n.
    pub step: u64,
    /// dt^(n-1/2) = t^n - t^(n-1) (0 before the first step).
    pub dt_prev: f64,
    /// dt^(n+1/2), known after the element pass of step n.
    pub dt: f64,
    /// Nodal positions x^n, one entry per node, or with separation per slot of the coincident
    /// sets ([`crate::node_values`]; read them by node with
    /// [`crate::solver::Solver::positions`]).
    pub(crate) x: Vec<Vec3>,
    /// Nodal velocities v^(n-1/2) before the velocity update, v^(n+1/2) after (entries as
    /// `x`; [`crate::solver::Solver::half_step_velocities`]).
    pub(crate) v: Vec<Vec3>,
    /// Nodal velocities at t^n (mean of the half steps), valid after the velocity update
    /// (entries as `x`; [`crate::solver::Solver::velocities`]).
    pub(crate) v_n: Vec<Vec3>,
    /// Cauchy stress per element (without bulk viscosity).
    pub stress: Vec<Sym3>,
    /// Material history per element.
    pub hist: Vec<History>,
    /// Generalized hourglass forces per element (4 modes x 3 directions) of the last step.
    pub hg: Vec<[f64; 12]>,
    /// Bulk-viscosity pressure of the last step per element.
    pub bulk_q: Vec<f64>,
    pub rigid: Vec<RigidState>,
    pub energy: Energies,
    /// Total energy at t = 0 (set by the first step).
    pub initial_energy: f64,
    /// Index of the element that controls the current time step.
    pub dt_element: u32,
    /// Per element, whether it has eroded ([`crate::erosion`]); empty when no material
    /// erodes.
    #[serde(default)]
    pub eroded: Vec<bool>,
    /// Per element, its Johnson-Cook damage and the plastic strain that damage has counted
    /// ([`crate::erosion::JcDamage`]); empty when no material accumulates it.
    #[serde(default)]
    pub damage: Vec<[f64; 2]>,
}
