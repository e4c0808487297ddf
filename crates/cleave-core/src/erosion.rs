//! Element erosion, as LS-DYNA deletes elements: an element whose material's failure rule
//! holds at the end of a step stops carrying stress from the next step on.
//!
//! - **Rules** (LS-DYNA Keyword Manual, Vol. II): `*MAT_PIECEWISE_LINEAR_PLASTICITY` FAIL,
//!   `*MAT_PLASTIC_KINEMATIC` and `*MAT_ELASTIC_PLASTIC_HYDRO` FS, `*MAT_SIMPLIFIED_JOHNSON_COOK`
//!   PSFAIL, the effective plastic strain at failure; `*MAT_JOHNSON_COOK`'s damage
//!   ([`JcDamage`], accumulated by the solver); `*MAT_ADD_EROSION`
//!   MXPRES (pressure p = -tr(sigma)/3 at or above), MNPRES (p at or below), SIGP1 (largest
//!   principal stress at or above), SIGVM (von Mises stress at or above) and FAILTM (time at
//!   or after), of which NCS must hold at once. The stress is the element's Cauchy stress
//!   without bulk viscosity (for ELFORM 2, the mean of its points), checked after the step's
//!   stress update.
//! - **What erosion does** ([`crate::solver::Solver`]): the element is skipped by the element
//!   pass (no force, no time step: a distorted element no longer limits the step), its stress,
//!   hourglass forces and bulk viscosity are zeroed, and the energy it holds (the work of its
//!   stresses, bulk viscosity and hourglass forces, [`crate::material::History::work`]) is
//!   booked as eroded energy ([`crate::state::Energies::eroded`]). That energy stays in the
//!   internal and hourglass energies of the ledger, so the balance holds as before; LS-DYNA's
//!   glstat lists it separately too. The nodes keep their masses and move on freely when all
//!   their elements have eroded (LS-DYNA with `*CONTROL_CONTACT` ENMASS = 1 or 2; its default
//!   removes such nodes from the model), so mass and momentum are conserved.
//! - **Contact**: an eroded element's faces stop pushing, and the faces of its live neighbours
//!   that it covered join the surfaces that hold their parts, in the step it erodes
//!   ([`crate::contact::ContactSet::erode`]): what LS-DYNA's `*CONTACT_ERODING_` contacts do.

use crate::math::{principal_values, trace, von_mises, Sym3};

/// A material's failure rule.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ErosionRule {
    /// FAIL (`*MAT_024`) or FS (`*MAT_003`): effective plastic strain at failure; the element
    /// erodes when this alone holds.
    pub plastic_strain: Option<f64>,
    /// `*MAT_ADD_EROSION` MXPRES: fails at p >= this (Pa).
    pub max_pressure: Option<f64>,
    /// MNPRES: fails at p <= this (tension is negative pressure).
    pub min_pressure: Option<f64>,
    /// SIGP1: fails when the largest principal stress reaches this.
    pub max_principal: Option<f64>,
    /// SIGVM: fails when the von Mises stress reaches this.
    pub max_von_mises: Option<f64>,
    /// FAILTM: fails at this time (s) or after.
    pub failure_time: Option<f64>,
    /// `*MAT_015` D1-D5: Johnson-Cook damage; the element erodes when it reaches 1.
    pub johnson_cook: Option<JcDamage>,
    /// NCS: how many of the `*MAT_ADD_EROSION` criteria must hold at once (1 or more, at most
    /// the number given).
    pub ncs: u32,
}

/// Johnson-Cook damage (Johnson and Cook, Engineering Fracture Mechanics 21, 1985; LS-DYNA
/// `*MAT_015` D1-D5, EFMIN):
///
/// ```text
/// D     = sum d eps_p / eps_f,   the element erodes at D >= 1
/// eps_f = max(EFMIN, (D1 + D2 exp(D3 s*)) (1 + D4 ln max(eps_dot / EPSO, 1)) (1 + D5 T*))
/// s*    = sigma_m / sigma_vm     (mean stress over von Mises stress, positive in tension)
/// ```
///
/// with d eps_p the step's plastic strain increment, eps_dot = d eps_p / dt its rate, and T*
/// the homologous temperature of the Johnson-Cook flow stress (0 without thermal softening).
/// The rate term is clamped below EPSO as the flow stress's is; a negative `eps_f` is floored
/// at EFMIN (LS-DYNA's default 1e-6).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JcDamage {
    pub d: [f64; 5],
    pub efmin: f64,
}

impl JcDamage {
    /// The failure strain at stress `s`, plastic strain rate `eps_dot`, temperature rise
    /// `heat` over TR, for the material `jc`.
    pub fn failure_strain(
        &self,
        jc: &crate::material::JohnsonCook,
        s: &Sym3,
        eps_dot: f64,
        heat: f64,
    ) -> f64 {
        let [d1, d2, d3, d4, d5] = self.d;
        let vm = von_mises(s);
        let triax = if vm > 0.0 { trace(s) / 3.0 / vm } else { 0.0 };
        let rate = if jc.eps0 > 0.0 {
            (eps_dot / jc.eps0).max(1.0).ln()
        } else {
            0.0
        };
        let t_star = if jc.t_melt.is_finite() {
            (heat / (jc.t_melt - jc.t_room)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let f = (d1 + d2 * (d3 * triax).exp()) * (1.0 + d4 * rate) * (1.0 + d5 * t_star);
        f.max(self.efmin)
    }
}

/// The rule of one material.
#[derive(Clone, Debug, PartialEq)]
pub struct ErosionDef {
    /// Index into `Model::materials`.
    pub material: usize,
    pub rule: ErosionRule,
}

impl ErosionRule {
    /// Number of `*MAT_ADD_EROSION` criteria given.
    pub fn criteria(&self) -> usize {
        [
            self.max_pressure,
            self.min_pressure,
            self.max_principal,
            self.max_von_mises,
            self.failure_time,
        ]
        .iter()
        .flatten()
        .count()
    }

    /// Whether the rule has anything to check.
    pub fn is_empty(&self) -> bool {
        self.plastic_strain.is_none() && self.criteria() == 0 && self.johnson_cook.is_none()
    }

    /// Whether an element with stress `s`, effective plastic strain `eps_p` at time `t` fails
    /// (Johnson-Cook damage is checked by the solver, which accumulates it).
    pub fn fails(&self, s: &Sym3, eps_p: f64, t: f64) -> bool {
        if self.plastic_strain.is_some_and(|f| eps_p >= f) {
            return true;
        }
        if self.criteria() == 0 {
            return false;
        }
        let p = -trace(s) / 3.0;
        let held = [
            self.max_pressure.map(|v| p >= v),
            self.min_pressure.map(|v| p <= v),
            self.max_principal.map(|v| principal_values(s)[2] >= v),
            self.max_von_mises.map(|v| von_mises(s) >= v),
            self.failure_time.map(|v| t >= v),
        ]
        .iter()
        .flatten()
        .filter(|&&h| h)
        .count();
        held >= self.ncs.max(1) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_criterion_and_ncs() {
        // uniaxial tension 100: p = -33.3, sigma1 = 100, von Mises 100
        let s = [100.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let r = |f: fn(&mut ErosionRule)| {
            let mut r = ErosionRule {
                ncs: 1,
                ..Default::default()
            };
            f(&mut r);
            r
        };
        assert!(r(|r| r.plastic_strain = Some(0.2)).fails(&s, 0.2, 0.0));
        assert!(!r(|r| r.plastic_strain = Some(0.2)).fails(&s, 0.1999, 0.0));
        assert!(r(|r| r.min_pressure = Some(-33.0)).fails(&s, 0.0, 0.0));
        assert!(!r(|r| r.min_pressure = Some(-34.0)).fails(&s, 0.0, 0.0));
        assert!(!r(|r| r.max_pressure = Some(1.0)).fails(&s, 0.0, 0.0));
        assert!(r(|r| r.max_principal = Some(99.0)).fails(&s, 0.0, 0.0));
        assert!(!r(|r| r.max_principal = Some(101.0)).fails(&s, 0.0, 0.0));
        assert!(r(|r| r.max_von_mises = Some(100.0)).fails(&s, 0.0, 0.0));
        assert!(r(|r| r.failure_time = Some(1.0)).fails(&s, 0.0, 1.0));
        assert!(!r(|r| r.failure_time = Some(1.0)).fails(&s, 0.0, 0.5));
        // two criteria, one holding: fails with NCS 1, not with NCS 2
        let mut two = r(|r| {
            r.max_von_mises = Some(50.0);
            r.failure_time = Some(1.0);
        });
        assert!(two.fails(&s, 0.0, 0.0));
        two.ncs = 2;
        assert!(!two.fails(&s, 0.0, 0.0));
        assert!(two.fails(&s, 0.0, 2.0));
        assert!(!ErosionRule::default().fails(&s, 1e9, 1e9));
    }

    #[test]
    fn principal_values_of_a_turned_tensor() {
        // diag(3, -1, 7) turned by 30 degrees about z, then pure shear
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let (a, b) = (3.0, -1.0);
        let t = [
            a * c * c + b * s * s,
            a * s * s + b * c * c,
            7.0,
            (a - b) * c * s,
            0.0,
            0.0,
        ];
        let p = principal_values(&t);
        for (x, want) in p.iter().zip([-1.0, 3.0, 7.0]) {
            assert!((x - want).abs() < 1e-12, "{p:?}");
        }
        let q = principal_values(&[0.0, 0.0, 0.0, 0.0, 0.0, 5.0]);
        for (x, want) in q.iter().zip([-5.0, 0.0, 5.0]) {
            assert!((x - want).abs() < 1e-12, "{q:?}");
        }
        assert_eq!(principal_values(&[2.0, 2.0, 2.0, 0.0, 0.0, 0.0]), [2.0; 3]);
    }
}
