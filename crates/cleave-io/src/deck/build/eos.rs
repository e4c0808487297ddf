//! Attaching each part's `*EOS_...` (its EOSID) to the material: cleave keeps the equation of
//! state with the `*MAT_JOHNSON_COOK` parameters, so every part of a material must name the
//! same one (or none). With an EOS, the material's elastic constants (for the wave speed, the
//! time step, contact stiffness) come from G and the EOS's reference bulk modulus K0 (C1, or
//! rho0 C^2): `E = 9 K0 G / (3 K0 + G)`, `nu = (3 K0 - 2 G) / (2 (3 K0 + G))`, whatever PR or E
//! the card gave; the Gruneisen form takes rho0 from the material's RO.

use cleave_core::material::Eos;
use cleave_core::model::{MaterialKind, Model};

use super::Builder;
use crate::deck::error::DeckError;

impl Builder<'_> {
    /// Resolves the parts' EOSIDs (after the parts and materials are built).
    pub fn equations_of_state(&self, m: &mut Model) -> Result<(), DeckError> {
        let raw = self.raw;
        let ids = self.index::<_, usize>(&raw.eos, "equation of state", |e| (e.id, &e.src))?;
        // per material: the EOS of the first part that uses it, and that part
        let mut chosen: Vec<Option<(Option<usize>, usize)>> = vec![None; m.materials.len()];
        for (pi, rp) in raw.parts.iter().enumerate() {
            let mat = m.parts[pi].material;
            let eos = match rp.eosid {
                Some(id) => Some(self.find(&ids, id, &rp.src, "EOSID", "equation of state")?),
                None => None,
            };
            match chosen[mat] {
                None => chosen[mat] = Some((eos, pi)),
                Some((first, pj)) if first != eos => {
                    let name = |e: Option<usize>| {
                        e.map_or("no EOS".to_string(), |k| format!("EOS {}", raw.eos[k].id))
                    };
                    return Err(self
                        .err(
                            &rp.src,
                            format!(
                                "part {} gives material {} {}, part {} gave it {}: cleave keeps the equation of state with the material; give these parts materials of their own",
                                rp.id,
                                m.materials[mat].id,
                                name(eos),
                                raw.parts[pj].id,
                                name(first)
                            ),
                        )
                        .with_field("EOSID"));
                }
                Some(_) => {}
            }
        }
        for (mi, choice) in chosen.iter().enumerate() {
            let rm = &raw.materials[mi];
            let mat = &mut m.materials[mi];
            match (choice.and_then(|c| c.0), &mut mat.kind) {
                (Some(k), MaterialKind::JohnsonCook(jc)) => {
                    let mut eos = raw.eos[k].eos;
                    if let Eos::Gruneisen { rho0, .. } = &mut eos {
                        *rho0 = mat.density;
                    }
                    jc.eos = Some(eos);
                    let g = rm.shear_only.unwrap_or_else(|| mat.shear_modulus());
                    let k0 = eos.bulk_modulus();
                    mat.young = 9.0 * k0 * g / (3.0 * k0 + g);
                    mat.poisson = (3.0 * k0 - 2.0 * g) / (2.0 * (3.0 * k0 + g));
                }
                (Some(_), _) => {
                    let pi = choice.map_or(0, |c| c.1);
                    return Err(self
                        .err(
                            &raw.parts[pi].src,
                            format!(
                                "part {}: an equation of state applies to *MAT_JOHNSON_COOK only (material {} is another kind)",
                                raw.parts[pi].id, mat.id
                            ),
                        )
                        .with_field("EOSID"));
                }
                (None, _) if rm.shear_only.is_some() => {
                    return Err(self
                        .err(
                            &rm.src,
                            format!(
                                "material {}: PR (or E) is missing, or the material is *MAT_ELASTIC_PLASTIC_HYDRO, and no part gives it an *EOS (EOSID): the bulk modulus comes from one of them",
                                mat.id
                            ),
                        )
                        .with_field("PR"));
                }
                _ => {}
            }
        }
        Ok(())
    }
}
