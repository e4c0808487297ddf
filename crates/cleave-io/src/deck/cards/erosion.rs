//! Element erosion cards: the FAIL / FS fields of `*MAT_024` / `*MAT_003` (read with their
//! material) and `*MAT_ADD_EROSION` (LS-DYNA Keyword Manual, Vol. II); the rule itself is
//! [`cleave_core::erosion`].

use cleave_core::erosion::ErosionRule;

use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{RawDeck, RawErosion};

/// The material card's failure strain (FAIL, FS) of material `mid`, read on card `c`.
pub fn plastic_strain(r: &Reader<'_>, deck: &mut RawDeck, c: &Card<'_>, mid: i64, eps: f64) {
    deck.erosions.push(RawErosion {
        src: r.src(c.line),
        mid,
        rule: ErosionRule {
            plastic_strain: Some(eps),
            ncs: 1,
            ..Default::default()
        },
        from_material: true,
    });
}

/// A criterion field: `None` when blank, 0 or equal to EXCL (LS-DYNA's exclusion number).
fn criterion(c: &Card<'_>, i: usize, name: &str, excl: f64) -> Result<Option<f64>, DeckError> {
    let v = c.f64_or(i, name, 0.0)?;
    Ok((v != 0.0 && v != excl).then_some(v))
}

/// A criterion cleave does not evaluate: an error when given.
fn refused(c: &Card<'_>, i: usize, name: &str, what: &str, excl: f64) -> Result<(), DeckError> {
    match criterion(c, i, name, excl)? {
        None => Ok(()),
        Some(v) => Err(c.field_err(
            name,
            format!("{v}: {what} is not supported as an erosion criterion (cleave takes MXPRES, MNPRES, SIGP1, SIGVM, FAILTM, MXEPS, MNEPS, EFFEPS and VOLEPS); leave it blank, 0 or EXCL"),
        )),
    }
}

/// `*MAT_ADD_EROSION`: card 1 `MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS`, card 2
/// `MNPRES SIGP1 SIGVM MXEPS EPSSH SIGTH IMPULSE FAILTM`; further cards (damage, forming
/// limits, ...) must be blank. A criterion blank, 0 or equal to EXCL is not used. Taken:
/// MXPRES, MNPRES, SIGP1, SIGVM, FAILTM, the logarithmic-strain criteria MXEPS, MNEPS, EFFEPS,
/// VOLEPS, and NCS (1 to the number of criteria given); the shear strain EPSSH and
/// Tuler-Butcher (SIGTH, IMPULSE) are errors. NUMFIP is not used: a one-point element has one point, and an ELFORM 2
/// element is checked on the mean of its points' stresses.
pub fn add_erosion(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c1 = r.required(W10, "MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS")?;
    let mid = c1.id(0, "MID")?;
    let excl = c1.f64_or(1, "EXCL", 0.0)?;
    let max_pressure = criterion(&c1, 2, "MXPRES", excl)?;
    let min_principal_strain = criterion(&c1, 3, "MNEPS", excl)?;
    let effective_strain = criterion(&c1, 4, "EFFEPS", excl)?;
    let volumetric_strain = criterion(&c1, 5, "VOLEPS", excl)?;
    let ncs = c1.i64_or(7, "NCS", 1)?;
    let c2 = r.card_or_defaults(W10)?;
    let min_pressure = criterion(&c2, 0, "MNPRES", excl)?;
    let max_principal = criterion(&c2, 1, "SIGP1", excl)?;
    let max_von_mises = criterion(&c2, 2, "SIGVM", excl)?;
    let max_principal_strain = criterion(&c2, 3, "MXEPS", excl)?;
    refused(&c2, 4, "EPSSH", "a shear strain", excl)?;
    refused(&c2, 5, "SIGTH", "the Tuler-Butcher threshold", excl)?;
    refused(&c2, 6, "IMPULSE", "the Tuler-Butcher impulse", excl)?;
    let failure_time = criterion(&c2, 7, "FAILTM", excl)?;
    while let Some(c) = r.next(W10)? {
        if let Some(k) = (0..c.count()).find(|&k| {
            let t = c.raw(k).trim();
            !t.is_empty() && !crate::deck::fields::parse_f64(t).is_ok_and(|v| v == 0.0)
        }) {
            return Err(c.err(format!(
                "field {} of a card after the second: damage, forming-limit and other criteria of these cards are not supported; leave them blank",
                k + 1
            )));
        }
    }
    let rule = ErosionRule {
        max_pressure,
        min_pressure,
        max_principal,
        max_von_mises,
        failure_time,
        max_principal_strain,
        min_principal_strain,
        effective_strain,
        volumetric_strain,
        ncs: 1,
        plastic_strain: None,
        johnson_cook: None,
    };
    let n = rule.criteria() as i64;
    if n == 0 {
        deck.warnings.push(format!(
            "{}:{}: {}: no criterion given for material {mid}: nothing erodes",
            c1.file,
            r.line_of_keyword(),
            c1.keyword
        ));
    } else if ncs < 1 || ncs > n {
        return Err(c1.field_err(
            "NCS",
            format!("{ncs}: the number of criteria that must hold at once is 1 to the {n} given"),
        ));
    }
    deck.erosions.push(RawErosion {
        src: r.src(c1.line),
        mid,
        rule: ErosionRule {
            ncs: ncs.max(1) as u32,
            ..rule
        },
        from_material: false,
    });
    Ok(())
}
