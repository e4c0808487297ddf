//! Element erosion, as LS-DYNA deletes elements: an element whose material's failure rule
//! holds at the end of a step stops carrying stress from the next step on.
//!
//! - **Rules** (LS-DYNA Keyword Manual, Vol. II): `*MAT_PIECEWISE_LINEAR_PLASTICITY` FAIL,
//!   `*MAT_PLASTIC_KINEMATIC` and `*MAT_ELASTIC_PLASTIC_HYDRO` FS, `*MAT_SIMPLIFIED_JOHNSON_COOK`
//!   PSFAIL, the effective plastic strain at failure; `*MAT_JOHNSON_COOK`'s damage
//!   ([`JcDamage`], accumulated by the solver); `*MAT_ADD_EROSION` MXEPS, MNEPS, EFFEPS and
//!   VOLEPS on the element's logarithmic strain ([`principal_log_strains`]), and
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

use crate::math::{mat_mul, mat_to_sym, principal_values, trace, transpose, von_mises, Mat3, Sym3};

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
    /// MXEPS: fails when the largest principal (logarithmic) strain reaches this.
    pub max_principal_strain: Option<f64>,
    /// MNEPS: fails when the smallest principal strain falls to this (compression negative).
    pub min_principal_strain: Option<f64>,
    /// EFFEPS: fails when the effective strain `sqrt(2/3 e':e')` of the strain's deviator
    /// reaches this.
    pub effective_strain: Option<f64>,
    /// VOLEPS: fails when the volumetric strain `ln(V/V0)` reaches this: at or above a positive
    /// value (tension), at or below a negative one (compression).
    pub volumetric_strain: Option<f64>,
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

/// The principal logarithmic strains, ascending, of an element whose Jacobian at its centre is
/// `j` now and `j0` in the reference configuration: `F = j j0^-1` (exact for a homogeneous
/// deformation of any shape, the Jacobian being linear in the nodes), `B = F F^T`, and
/// `ln(lambda_i) = 1/2 ln(b_i)` of B's eigenvalues b_i.
pub fn principal_log_strains(j: &Mat3, j0_inv: &Mat3) -> [f64; 3] {
    let f = mat_mul(j, j0_inv);
    let b = mat_to_sym(&mat_mul(&f, &transpose(&f)));
    principal_values(&b).map(|v| 0.5 * v.max(f64::MIN_POSITIVE).ln())
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
            self.max_principal_strain,
            self.min_principal_strain,
            self.effective_strain,
            self.volumetric_strain,
        ]
        .iter()
        .flatten()
        .count()
    }

    /// Whether a strain criterion is given (the solver then works out the element's strain).
    pub fn needs_strain(&self) -> bool {
        self.max_principal_strain.is_some()
            || self.min_principal_strain.is_some()
            || self.effective_strain.is_some()
            || self.volumetric_strain.is_some()
    }

    /// Whether the rule has anything to check.
    pub fn is_empty(&self) -> bool {
        self.plastic_strain.is_none() && self.criteria() == 0 && self.johnson_cook.is_none()
    }

    /// Whether an element with stress `s`, effective plastic strain `eps_p` at time `t` fails
    /// (Johnson-Cook damage is checked by the solver, which accumulates it); `strain` gives the
    /// element's principal logarithmic strains, ascending, when a strain criterion asks.
    pub fn fails(&self, s: &Sym3, eps_p: f64, t: f64, strain: impl FnOnce() -> [f64; 3]) -> bool {
        if self.plastic_strain.is_some_and(|f| eps_p >= f) {
            return true;
        }
        if self.criteria() == 0 {
            return false;
        }
        let p = -trace(s) / 3.0;
        let e = if self.needs_strain() {
            strain()
        } else {
            [0.0; 3]
        };
        let vol = e[0] + e[1] + e[2];
        let eff = {
            let d = e.map(|x| x - vol / 3.0);
            (2.0 / 3.0 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2])).sqrt()
        };
        let held = [
            self.max_pressure.map(|v| p >= v),
            self.min_pressure.map(|v| p <= v),
            self.max_principal.map(|v| principal_values(s)[2] >= v),
            self.max_von_mises.map(|v| von_mises(s) >= v),
            self.failure_time.map(|v| t >= v),
            self.max_principal_strain.map(|v| e[2] >= v),
            self.min_principal_strain.map(|v| e[0] <= v),
            self.effective_strain.map(|v| eff >= v),
            self.volumetric_strain
                .map(|v| if v > 0.0 { vol >= v } else { vol <= v }),
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
        assert!(r(|r| r.plastic_strain = Some(0.2)).fails(&s, 0.2, 0.0, || [0.0; 3]));
        assert!(!r(|r| r.plastic_strain = Some(0.2)).fails(&s, 0.1999, 0.0, || [0.0; 3]));
        assert!(r(|r| r.min_pressure = Some(-33.0)).fails(&s, 0.0, 0.0, || [0.0; 3]));
        assert!(!r(|r| r.min_pressure = Some(-34.0)).fails(&s, 0.0, 0.0, || [0.0; 3]));
        assert!(!r(|r| r.max_pressure = Some(1.0)).fails(&s, 0.0, 0.0, || [0.0; 3]));
        assert!(r(|r| r.max_principal = Some(99.0)).fails(&s, 0.0, 0.0, || [0.0; 3]));
        assert!(!r(|r| r.max_principal = Some(101.0)).fails(&s, 0.0, 0.0, || [0.0; 3]));
        assert!(r(|r| r.max_von_mises = Some(100.0)).fails(&s, 0.0, 0.0, || [0.0; 3]));
        assert!(r(|r| r.failure_time = Some(1.0)).fails(&s, 0.0, 1.0, || [0.0; 3]));
        assert!(!r(|r| r.failure_time = Some(1.0)).fails(&s, 0.0, 0.5, || [0.0; 3]));
        // two criteria, one holding: fails with NCS 1, not with NCS 2
        let mut two = r(|r| {
            r.max_von_mises = Some(50.0);
            r.failure_time = Some(1.0);
        });
        assert!(two.fails(&s, 0.0, 0.0, || [0.0; 3]));
        two.ncs = 2;
        assert!(!two.fails(&s, 0.0, 0.0, || [0.0; 3]));
        assert!(two.fails(&s, 0.0, 2.0, || [0.0; 3]));
        assert!(!ErosionRule::default().fails(&s, 1e9, 1e9, || [0.0; 3]));
    }

    /// A stretch (1.2, 0.9, 1.05) turned by 40 degrees about an oblique axis: the log strains
    /// are ln 0.9, ln 1.05, ln 1.2 whatever the turn (1e-14), from any reference Jacobian.
    #[test]
    fn log_strains_ignore_rotation() {
        let r = crate::math::rotation_from_vector(crate::math::scale(
            [1.0, 2.0, 2.0],
            40f64.to_radians() / 3.0,
        ));
        let u = [[1.2, 0.0, 0.0], [0.0, 0.9, 0.0], [0.0, 0.0, 1.05]];
        let f = mat_mul(&r, &u);
        let j0 = [[0.5, 0.1, 0.0], [0.0, 0.7, 0.2], [0.1, 0.0, 0.4]];
        let j = mat_mul(&f, &j0);
        let e = principal_log_strains(&j, &crate::math::inverse(&j0).unwrap());
        for (x, want) in e.iter().zip([0.9f64.ln(), 1.05f64.ln(), 1.2f64.ln()]) {
            assert!((x - want).abs() < 1e-14, "{e:?}");
        }
        // and the strain criteria on them: MXEPS, MNEPS, EFFEPS, VOLEPS
        let s = [0.0; 6];
        fn rule(f: impl FnOnce(&mut ErosionRule)) -> ErosionRule {
            let mut r = ErosionRule {
                ncs: 1,
                ..Default::default()
            };
            f(&mut r);
            r
        }
        assert!(rule(|r| r.max_principal_strain = Some(0.18)).fails(&s, 0.0, 0.0, || e));
        assert!(!rule(|r| r.max_principal_strain = Some(0.19)).fails(&s, 0.0, 0.0, || e));
        assert!(rule(|r| r.min_principal_strain = Some(-0.1)).fails(&s, 0.0, 0.0, || e));
        assert!(!rule(|r| r.min_principal_strain = Some(-0.11)).fails(&s, 0.0, 0.0, || e));
        let vol: f64 = e.iter().sum();
        assert!(rule(|r| r.volumetric_strain = Some(vol - 1e-9)).fails(&s, 0.0, 0.0, || e));
        assert!(!rule(|r| r.volumetric_strain = Some(-0.5)).fails(&s, 0.0, 0.0, || e));
        let d = e.map(|x| x - vol / 3.0);
        let eff = (2.0 / 3.0 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2])).sqrt();
        assert!(rule(|r| r.effective_strain = Some(eff - 1e-9)).fails(&s, 0.0, 0.0, || e));
        assert!(!rule(|r| r.effective_strain = Some(eff + 1e-9)).fails(&s, 0.0, 0.0, || e));
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
