//! The solver's part of element erosion ([`crate::erosion`]): which elements may erode, and
//! the check after each element pass.

use rayon::prelude::*;

use super::Solver;
use crate::contact::surface::FaceId;
use crate::element::hex8::jacobian_at;
use crate::erosion::{principal_log_strains, ErosionRule};
use crate::math::{inverse, Mat3, Vec3};
use crate::model::Model;

/// The elements that may erode and, when the model has contact, the face neighbours whose
/// faces an eroded element exposes.
#[derive(Clone, Debug)]
pub(super) struct Erosion {
    /// Index into `Model::erosion` of each element's rule, or `u32::MAX`.
    rule: Vec<u32>,
    /// The elements with a rule, ascending.
    candidates: Vec<u32>,
    /// [`crate::topology::face_neighbours`], when the model has contact (else empty).
    neighbours: Vec<[(u32, u8); 6]>,
    /// Some rule accumulates Johnson-Cook damage.
    damage: bool,
    /// Per element, the inverse of its reference Jacobian at the centre, when some rule has a
    /// strain criterion (else empty): F = J(x) J(x0)^-1 ([`crate::erosion::principal_log_strains`]).
    ref_inv: Vec<Mat3>,
}

const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl Erosion {
    /// `None` when no material of `model` erodes.
    pub(super) fn new(model: &Model) -> Option<Self> {
        if model.erosion.is_empty() {
            return None;
        }
        let rule: Vec<u32> = model
            .elem_part
            .iter()
            .map(|&p| {
                let m = model.parts[p as usize].material;
                model
                    .erosion
                    .iter()
                    .position(|d| d.material == m)
                    .map_or(u32::MAX, |i| i as u32)
            })
            .collect();
        let candidates = (0..rule.len() as u32)
            .filter(|&e| rule[e as usize] != u32::MAX)
            .collect();
        let neighbours = if model.contacts.is_empty() {
            Vec::new()
        } else {
            crate::topology::face_neighbours(model)
        };
        let damage = model.erosion.iter().any(|d| d.rule.johnson_cook.is_some());
        let ref_inv = if model.erosion.iter().any(|d| d.rule.needs_strain()) {
            model
                .conn
                .iter()
                .map(|c| {
                    let x0: [Vec3; 8] = c.map(|n| model.x0[n as usize]);
                    // an element with a singular reference Jacobian is refused when the deck
                    // is read; the identity keeps the strain finite regardless
                    inverse(&jacobian_at(&x0, [0.0; 3])).unwrap_or(IDENTITY)
                })
                .collect()
        } else {
            Vec::new()
        };
        Some(Self {
            rule,
            candidates,
            neighbours,
            damage,
            ref_inv,
        })
    }

    fn rule_of<'a>(&self, model: &'a Model, e: u32) -> &'a ErosionRule {
        &model.erosion[self.rule[e as usize] as usize].rule
    }
}

/// Johnson-Cook damage of the step ([`crate::erosion::JcDamage`]): each live element whose rule
/// has it adds its plastic strain increment over the failure strain at its stress, rate and
/// temperature.
fn accumulate_damage(er: &Erosion, model: &Model, st: &mut crate::state::State) {
    let dt = st.dt_prev;
    let (stress, eroded, hist) = (&st.stress, &st.eroded, &st.hist);
    st.damage
        .par_iter_mut()
        .enumerate()
        .with_min_len(1024)
        .for_each(|(k, dmg)| {
            let r = er.rule[k];
            if r == u32::MAX || eroded[k] {
                return;
            }
            let def = &model.erosion[r as usize];
            let Some(d) = def.rule.johnson_cook else {
                return;
            };
            let crate::model::MaterialKind::JohnsonCook(jc) = &model.materials[def.material].kind
            else {
                return;
            };
            let h = &hist[k];
            let dep = h.eps_p - dmg[1];
            if dep > 0.0 {
                let rate = if dt > 0.0 { dep / dt } else { 0.0 };
                dmg[0] += dep / d.failure_strain(jc, &stress[k], rate, h.heat);
                dmg[1] = h.eps_p;
            }
        });
}

impl Solver<'_> {
    /// After the element pass of step n: the live elements whose rule holds for their stress
    /// and plastic strain at t^n erode. Their forces of this step stand; from the next step
    /// on the element pass skips them. Their energy is booked as eroded, their stress,
    /// hourglass forces and bulk viscosity are zeroed (for output), and the contact drops
    /// their faces and takes the live neighbours' faces they covered.
    pub(super) fn erode_elements(&mut self) {
        let Some(er) = &mut self.erosion else {
            return;
        };
        let model = self.model;
        if er.damage {
            accumulate_damage(er, model, &mut self.state);
        }
        let st = &self.state;
        let strain = |k: usize| {
            let x: [Vec3; 8] = model.conn[k].map(|n| st.x[n as usize]);
            principal_log_strains(&jacobian_at(&x, [0.0; 3]), &er.ref_inv[k])
        };
        let failed: Vec<u32> = er
            .candidates
            .par_iter()
            .copied()
            .filter(|&e| {
                let k = e as usize;
                let h = &st.hist[k];
                !st.eroded[k]
                    && (st.damage.get(k).is_some_and(|d| d[0] >= 1.0)
                        || er
                            .rule_of(model, e)
                            .fails(&st.stress[k], h.eps_p, st.t, || strain(k)))
            })
            .collect();
        if failed.is_empty() {
            return;
        }
        let st = &mut self.state;
        for &e in &failed {
            let k = e as usize;
            st.eroded[k] = true;
            st.energy.eroded += st.hist[k].work;
            st.stress[k] = [0.0; 6];
            st.hg[k] = [0.0; 12];
            st.bulk_q[k] = 0.0;
        }
        self.erode_contact(&failed);
    }

    /// The contact after elements `failed` eroded (marked eroded here if they are not yet):
    /// their faces stop pushing and the faces of the live neighbours they covered join the
    /// surfaces ([`ContactSet::erode`]). The CPU step calls it as elements erode; a stepper
    /// that erodes elsewhere (the GPU's) calls it with the ones that eroded there.
    ///
    /// [`ContactSet::erode`]: crate::contact::ContactSet::erode
    pub fn erode_contact(&mut self, failed: &[u32]) {
        let (Some(er), Some(c)) = (&self.erosion, &mut self.contact) else {
            return;
        };
        let st = &mut self.state;
        for &e in failed {
            st.eroded[e as usize] = true;
        }
        let mut exposed: Vec<FaceId> = Vec::new();
        for &e in failed {
            for &(n, f) in &er.neighbours[e as usize] {
                if n != u32::MAX && !st.eroded[n as usize] {
                    exposed.push((n, f));
                }
            }
        }
        c.erode(&st.eroded, &exposed);
    }

    /// Elements eroded so far.
    pub fn eroded_count(&self) -> usize {
        self.state.eroded.iter().filter(|&&e| e).count()
    }
}
