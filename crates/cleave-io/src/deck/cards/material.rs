//! `*MAT_ELASTIC`, `*MAT_PLASTIC_KINEMATIC`, `*MAT_RIGID` (LS-DYNA Keyword Manual, Vol. II)
//! and this project's `*MAT_ADD_SEPARATION` (see the interface page).

use cleave_core::model::MaterialKind;

use super::control::warn_ignored;
use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{RawDeck, RawMaterial, RawSeparation};

/// MID, RO, E, PR from fields 0..4, with the checks every deformable material needs:
/// RO > 0, E > 0, -1 < PR < 0.5.
fn common(c: &Card<'_>, rigid: bool) -> Result<(i64, f64, f64, f64), DeckError> {
    let mid = c.id(0, "MID")?;
    let ro = c.positive(1, "RO")?;
    let (e, pr) = if rigid {
        (c.f64_or(2, "E", 0.0)?, c.f64_or(3, "PR", 0.0)?)
    } else {
        let pr = c.f64_or(3, "PR", 0.0)?;
        if !(pr > -1.0 && pr < 0.5) {
            return Err(c.field_err("PR", format!("{pr} must lie in (-1, 0.5)")));
        }
        (c.positive(2, "E")?, pr)
    };
    Ok((mid, ro, e, pr))
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
        let m = common(&c, false)?;
        push(r, deck, &c, m, MaterialKind::Elastic);
    }
    Ok(())
}

/// `*MAT_PLASTIC_KINEMATIC` / `*MAT_003`: card 1 `MID RO E PR SIGY ETAN BETA`; optional
/// card 2 `SRC SRP FS VP` (strain-rate effects and erosion are not supported: SRC, SRP and FS
/// must be blank or 0). SIGY > 0, 0 <= ETAN < E, 0 <= BETA <= 1 (default 0, kinematic).
pub fn plastic_kinematic(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "MID RO E PR SIGY ETAN BETA")?;
    let m = common(&c, false)?;
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
            (2, "FS", "element erosion"),
        ] {
            if c2.f64_or(i, name, 0.0)? != 0.0 {
                return Err(c2.field_err(name, format!("{what} not supported; leave it blank")));
            }
        }
        warn_ignored(&c2, 3, "VP", "rate formulation not used", deck);
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
/// coded 0..7); optional card 3 (alignment) ignored. E and PR are only used for contact
/// stiffness, so they are not checked beyond being numbers.
pub fn rigid(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "MID RO E PR")?;
    let m = common(&c, true)?;
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

/// `*MAT_ADD_SEPARATION`, one card per material: `MID MODEL SIGMAX BETA GC BOND`.
/// MODEL 1, 2 or 3; SIGMAX > 0; BETA blank or 0 means 1; GC > 0 for MODEL 3; BOND 0 or 1
/// (blank: 1).
pub fn separation(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let mid = c.id(0, "MID")?;
        let model = match c.opt_i64(1, "MODEL")? {
            None => return Err(c.field_err("MODEL", "missing (1, 2 or 3)")),
            Some(v @ 1..=3) => v as i32,
            Some(v) => return Err(c.field_err("MODEL", format!("{v} is not one of 1, 2, 3"))),
        };
        let sigmax = c.positive(2, "SIGMAX")?;
        let beta = c.f64_nz(3, "BETA", 1.0)?;
        if beta <= 0.0 {
            return Err(c.field_err("BETA", format!("{beta} must be positive")));
        }
        let gc = if model == 3 {
            c.positive(4, "GC")?
        } else {
            c.f64_or(4, "GC", 0.0)?
        };
        let bond = c.code(5, "BOND", 1, 0, 1)?;
        deck.separations.push(RawSeparation {
            src: r.src(c.line),
            mid,
            model,
            sigmax,
            beta,
            gc,
            bond,
        });
    }
    Ok(())
}
