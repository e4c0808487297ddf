//! `*MAT_ELASTIC`, `*MAT_PLASTIC_KINEMATIC`, `*MAT_RIGID` (LS-DYNA Keyword Manual, Vol. II)
//! and this project's `*MAT_ADD_SEPARATION` (see the interface page).

use cleave_core::model::{MaterialKind, StrengthDist};

use super::control::warn_ignored;
use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{RawDeck, RawMaterial, RawSeparation};

/// MID, RO, E, PR from fields 0..4, with the checks every material needs, rigid ones too
/// (a rigid part's E and PR set the stiffness of its contact penalty springs and so the
/// contact time step): RO > 0, E > 0, -1 < PR < 0.5 (blank PR: 0).
fn common(c: &Card<'_>) -> Result<(i64, f64, f64, f64), DeckError> {
    let mid = c.id(0, "MID")?;
    let ro = c.positive(1, "RO")?;
    let pr = c.f64_or(3, "PR", 0.0)?;
    if !(pr > -1.0 && pr < 0.5) {
        return Err(c.field_err("PR", format!("{pr} must lie in (-1, 0.5)")));
    }
    Ok((mid, ro, c.positive(2, "E")?, pr))
}

fn push(
    r: &Reader<'_>,
    deck: &mut RawDeck,
    c: &Card<'_>,
    m: (i64, f64, f64, f64),
    kind: MaterialKind,
) {
    deck.materials.push(RawMaterial {
        src: r.src(c.line),
        id: m.0,
        density: m.1,
        young: m.2,
        poisson: m.3,
        kind,
        shear_only: None,
    });
}

/// `*MAT_ELASTIC` / `*MAT_001` (`_TITLE`: a title line before each): `MID RO E PR DA DB K`.
pub fn elastic(r: &mut Reader<'_>, deck: &mut RawDeck, titled: bool) -> Result<(), DeckError> {
    let mut first = true;
    while !r.at_end() {
        if titled && !first {
            r.title()?;
        }
        first = false;
        let c = r.required(W10, "MID RO E PR")?;
        let m = common(&c)?;
        push(r, deck, &c, m, MaterialKind::Elastic);
    }
    Ok(())
}

/// `*MAT_PLASTIC_KINEMATIC` / `*MAT_003`: card 1 `MID RO E PR SIGY ETAN BETA`; optional
/// card 2 `SRC SRP FS VP` (strain-rate effects are not supported: SRC and SRP must be blank
/// or 0; FS > 0 erodes the element at that effective plastic strain, [`cleave_core::erosion`]). SIGY > 0, 0 <= ETAN < E, 0 <= BETA <= 1 (default 0, kinematic).
pub fn plastic_kinematic(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "MID RO E PR SIGY ETAN BETA")?;
    let m = common(&c)?;
    let sigy = c.positive(4, "SIGY")?;
    let etan = c.f64_or(5, "ETAN", 0.0)?;
    if etan < 0.0 || etan >= m.2 {
        return Err(c.field_err(
            "ETAN",
            format!("{etan} must lie in [0, E) with E = {}", m.2),
        ));
    }
    let beta = c.f64_or(6, "BETA", 0.0)?;
    if !(0.0..=1.0).contains(&beta) {
        return Err(c.field_err("BETA", format!("{beta} must lie in [0, 1]")));
    }
    if let Some(c2) = r.next(W10)? {
        for (i, name, what) in [
            (0, "SRC", "strain-rate effects"),
            (1, "SRP", "strain-rate effects"),
        ] {
            if c2.f64_or(i, name, 0.0)? != 0.0 {
                return Err(c2.field_err(name, format!("{what} not supported; leave it blank")));
            }
        }
        let fs = c2.f64_or(2, "FS", 0.0)?;
        if fs < 0.0 {
            return Err(c2.field_err(
                "FS",
                format!("{fs}: a failure strain below 0 (LS-DYNA's *MAT_ADD_EROSION forms) is not supported; give the plastic strain at failure"),
            ));
        }
        if fs > 0.0 {
            let mid = c.id(0, "MID")?;
            super::erosion::plastic_strain(r, deck, &c2, mid, fs);
        }
        warn_ignored(&c2, 3, "VP", "rate formulation not used", deck)?;
    }
    push(
        r,
        deck,
        &c,
        m,
        MaterialKind::PlasticKinematic { sigy, etan, beta },
    );
    Ok(())
}

/// `*MAT_RIGID` / `*MAT_020`: card 1 `MID RO E PR N COUPLE M ALIAS`; optional card 2
/// `CMO CON1 CON2` (CMO 0 none, 1 global constraints; CON1 translations and CON2 rotations
/// coded 0..7); optional card 3 (alignment) ignored. RO, E and PR are checked as on every
/// material ([`common`]): E and PR set the contact stiffness of the part.
pub fn rigid(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "MID RO E PR")?;
    let m = common(&c)?;
    let (mut cmo, mut con1, mut con2) = (0, 0, 0);
    if let Some(c2) = r.next(W10)? {
        let v = c2.f64_or(0, "CMO", 0.0)?;
        cmo = if v == 0.0 {
            0
        } else if v == 1.0 {
            1
        } else {
            return Err(c2.field_err(
                "CMO",
                format!("{v} not supported (0: none, 1: global constraints)"),
            ));
        };
        if cmo == 1 {
            con1 = c2.code(1, "CON1", 0, 0, 7)?;
            con2 = c2.code(2, "CON2", 0, 0, 7)?;
        }
    }
    r.ignore(1);
    push(r, deck, &c, m, MaterialKind::Rigid { cmo, con1, con2 });
    Ok(())
}

/// `*MAT_ADD_SEPARATION`, per material card 1 `MID MODEL SIGMAX BETA GC BOND DIST SEED` and,
/// when DIST is 1 or 2, card 2 `SMIN SMAX M AREF`.
///
/// MODEL 1, 2, 3 or 4; SIGMAX > 0 (blank for DIST 1, where it is not used); BETA blank or 0
/// means 1; GC > 0 for MODELs 3 and 4; BOND 0 or 1 (blank: 1). DIST 0 (blank): every interface
/// has the strength SIGMAX; 1: uniform between SMIN and SMAX (0 <= SMIN < SMAX); 2: Weibull of
/// scale SIGMAX, modulus M > 0 and threshold SMIN >= 0, at the reference area AREF (blank or
/// 0: no size scaling; SMAX must be blank). SEED: any integer (blank: 0).
pub fn separation(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let mid = c.id(0, "MID")?;
        let model = match c.opt_i64(1, "MODEL")? {
            None => return Err(c.field_err("MODEL", "missing (1, 2, 3 or 4)")),
            Some(v @ 1..=4) => v as i32,
            Some(v) => return Err(c.field_err("MODEL", format!("{v} is not one of 1, 2, 3, 4"))),
        };
        let dist = c.code(6, "DIST", 0, 0, 2)?;
        let sigmax = if dist == 1 {
            c.f64_or(2, "SIGMAX", 0.0)?
        } else {
            c.positive(2, "SIGMAX")?
        };
        let beta = c.f64_nz(3, "BETA", 1.0)?;
        if beta <= 0.0 {
            return Err(c.field_err("BETA", format!("{beta} must be positive")));
        }
        let gc = if model >= 3 {
            c.positive(4, "GC")?
        } else {
            c.f64_or(4, "GC", 0.0)?
        };
        let bond = c.code(5, "BOND", 1, 0, 1)?;
        let seed = c.i64_or(7, "SEED", 0)? as u64;
        let strength = match dist {
            0 => StrengthDist::Constant,
            _ => strength_card(&r.required(W10, "SMIN SMAX M AREF")?, dist, seed)?,
        };
        deck.separations.push(RawSeparation {
            src: r.src(c.line),
            mid,
            model,
            sigmax,
            beta,
            gc,
            bond,
            strength,
        });
    }
    Ok(())
}

/// Card 2 of `*MAT_ADD_SEPARATION`, `SMIN SMAX M AREF`, for DIST 1 (uniform) or 2 (Weibull).
fn strength_card(c: &Card<'_>, dist: i32, seed: u64) -> Result<StrengthDist, DeckError> {
    let smin = c.f64_or(0, "SMIN", 0.0)?;
    if smin.is_nan() || smin < 0.0 {
        return Err(c.field_err("SMIN", format!("{smin} must be at least 0")));
    }
    if dist == 1 {
        let smax = c.positive(1, "SMAX")?;
        if smax <= smin {
            return Err(c.field_err("SMAX", format!("{smax} must exceed SMIN = {smin}")));
        }
        for (i, name) in [(2, "M"), (3, "AREF")] {
            if c.f64_or(i, name, 0.0)? != 0.0 {
                return Err(c.field_err(name, "applies to DIST 2 (Weibull) only; leave it blank"));
            }
        }
        return Ok(StrengthDist::Uniform { smin, smax, seed });
    }
    if c.f64_or(1, "SMAX", 0.0)? != 0.0 {
        return Err(c.field_err("SMAX", "applies to DIST 1 (uniform) only; leave it blank"));
    }
    let m = c.positive(2, "M")?;
    let aref = c.f64_or(3, "AREF", 0.0)?;
    if !(aref >= 0.0 && aref.is_finite()) {
        return Err(c.field_err(
            "AREF",
            format!("{aref} must be 0 (no size scaling) or positive"),
        ));
    }
    Ok(StrengthDist::Weibull {
        m,
        aref,
        smin,
        seed,
    })
}
