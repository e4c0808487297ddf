//! `*MAT_PIECEWISE_LINEAR_PLASTICITY` (`*MAT_024`), read into [`PiecewiseLinear`]: card 1
//! `MID RO E PR SIGY ETAN FAIL TDEL`, card 2 `C P LCSS LCSR VP LCF`, card 3 `EPS1..EPS8`,
//! card 4 `ES1..ES8` (cards 2 to 4 may be left out).
//!
//! The hardening curve, as LS-DYNA takes it: the curve LCSS (yield stress against effective
//! plastic strain; resolved when the deck is built) if given, else the points EPS/ES (at least
//! two, up to the last non-zero ES), else SIGY with the tangent modulus ETAN. C and P are
//! Cowper and Symonds' rate parameters. VP may be -1, 0 or 1: the rate is always the plastic
//! strain rate (VP 1, see [`PiecewiseLinear`]). FAIL > 0 (below 1e20) erodes the element at
//! that effective plastic strain ([`cleave_core::erosion`]). Not modelled, errors when set:
//! FAIL < 0 (a user subroutine), a rate curve LCSR, LCF; TDEL warns.

use cleave_core::material::PiecewiseLinear;
use cleave_core::model::MaterialKind;

use super::control::{unsupported, warn_ignored};
use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::W10;
use crate::deck::raw::{RawDeck, RawMaterial};

pub fn piecewise_linear(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "MID RO E PR SIGY ETAN FAIL TDEL")?;
    let mid = c.id(0, "MID")?;
    let ro = c.positive(1, "RO")?;
    let e = c.positive(2, "E")?;
    let pr = c.f64_or(3, "PR", 0.0)?;
    if !(pr > -1.0 && pr < 0.5) {
        return Err(c.field_err("PR", format!("{pr} must lie in (-1, 0.5)")));
    }
    let sigy = c.f64_or(4, "SIGY", 0.0)?;
    let etan = c.f64_or(5, "ETAN", 0.0)?;
    if etan < 0.0 || etan >= e {
        return Err(c.field_err("ETAN", format!("{etan} must lie in [0, E) with E = {e}")));
    }
    let fail = c.f64_or(6, "FAIL", 0.0)?;
    if fail < 0.0 {
        return Err(c.field_err(
            "FAIL",
            format!("{fail}: a user failure subroutine is not supported; give the plastic strain at failure or leave it blank"),
        ));
    }
    if fail > 0.0 && fail < 1e20 {
        super::erosion::plastic_strain(r, deck, &c, mid, fail);
    }
    warn_ignored(
        &c,
        7,
        "TDEL",
        "elements are not deleted for their time step",
        deck,
    )?;

    let (mut rate_c, mut rate_p, mut lcss) = (0.0, 0.0, None);
    let mut points: Vec<[f64; 2]> = Vec::new();
    if let Some(c2) = r.next(W10)? {
        rate_c = c2.f64_or(0, "C", 0.0)?;
        rate_p = c2.f64_or(1, "P", 0.0)?;
        if rate_c < 0.0 {
            return Err(c2.field_err("C", format!("{rate_c} must not be negative")));
        }
        if rate_c > 0.0 && rate_p <= 0.0 {
            return Err(c2.field_err("P", format!("{rate_p} must be positive when C is")));
        }
        lcss = c2.ref_id(2, "LCSS")?;
        unsupported(&c2, 3, "LCSR", "a curve of the rate factor")?;
        c2.code(4, "VP", 0, -1, 1)?;
        unsupported(&c2, 5, "LCF", "a failure curve (element erosion)")?;
        let eps = r.next(W10)?;
        let es = r.next(W10)?;
        if let (Some(eps), Some(es)) = (&eps, &es) {
            // every field read (a bad one is an error), the points up to the last non-zero ES
            let mut all = Vec::with_capacity(8);
            for k in 0..8 {
                let x = eps.f64_or(k, &format!("EPS{}", k + 1), 0.0)?;
                let y = es.f64_or(k, &format!("ES{}", k + 1), 0.0)?;
                all.push([x, y]);
            }
            let n = all.iter().rposition(|p| p[1] != 0.0).map_or(0, |k| k + 1);
            points = all[..n].to_vec();
            if lcss.is_none() && n == 1 {
                return Err(es.field_err(
                    "ES2",
                    "a hardening curve of EPS/ES needs at least two points",
                ));
            }
        } else if eps.is_some() {
            return Err(DeckError::at(
                r.file,
                r.line_of_keyword(),
                Some(r.keyword),
                "missing card (ES1..ES8: the yield stresses of EPS1..EPS8)",
            ));
        }
    }
    if lcss.is_none() {
        if points.is_empty() {
            if sigy <= 0.0 {
                return Err(c.field_err(
                    "SIGY",
                    format!("{sigy}: with no LCSS and no EPS/ES points, SIGY must be positive"),
                ));
            }
            points = PiecewiseLinear::bilinear(sigy, etan, e);
        }
        PiecewiseLinear::check(&points).map_err(|m| c.err(m))?;
    } else {
        // the curve's points are filled in when the deck is built
        points.clear();
    }
    deck.materials.push(RawMaterial {
        src: r.src(c.line),
        id: mid,
        density: ro,
        young: e,
        poisson: pr,
        kind: MaterialKind::PiecewiseLinear(PiecewiseLinear {
            points: points.into(),
            c: rate_c,
            p: if rate_c > 0.0 { rate_p } else { 1.0 },
            lcss,
            table: None,
        }),
        shear_only: None,
    });
    Ok(())
}
