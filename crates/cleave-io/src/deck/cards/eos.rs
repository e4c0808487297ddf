//! `*EOS_LINEAR_POLYNOMIAL` and `*EOS_GRUNEISEN` (LS-DYNA Keyword Manual Vol. II), referred
//! to by a part's EOSID; the formulas are in `cleave_core::material::Eos`.

use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::W10;
use crate::deck::raw::{RawDeck, RawEos};
use cleave_core::material::Eos;

/// `*EOS_LINEAR_POLYNOMIAL`: card 1 `EOSID C0 C1 C2 C3 C4 C5 C6`, card 2 `E0 V0` (optional;
/// E0 blank 0, V0 blank or 0: 1). C1, the bulk modulus, must be positive.
pub fn linear_polynomial(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c1 = r.required(W10, "EOSID C0 C1 C2 C3 C4 C5 C6")?;
    let id = c1.id(0, "EOSID")?;
    let mut c = [0.0; 7];
    for (k, v) in c.iter_mut().enumerate() {
        *v = c1.f64_or(k + 1, &format!("C{k}"), 0.0)?;
    }
    if c[1].is_nan() || c[1] <= 0.0 {
        return Err(c1.field_err("C1", format!("{}: the bulk modulus must be positive", c[1])));
    }
    let (e0, v0) = initial(r)?;
    deck.eos.push(RawEos {
        src: r.src(c1.line),
        id,
        eos: Eos::LinearPolynomial { c, e0, v0 },
    });
    Ok(())
}

/// `*EOS_GRUNEISEN`: card 1 `EOSID C S1 S2 S3 GAMAO A E0`, card 2 `V0 ...` (optional; V0 blank
/// or 0: 1; the unloading-curve field LCID after it must be blank). C must be positive.
pub fn gruneisen(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c1 = r.required(W10, "EOSID C S1 S2 S3 GAMAO A E0")?;
    let id = c1.id(0, "EOSID")?;
    let c = c1.positive(1, "C")?;
    let s = [
        c1.f64_or(2, "S1", 0.0)?,
        c1.f64_or(3, "S2", 0.0)?,
        c1.f64_or(4, "S3", 0.0)?,
    ];
    let gamma0 = c1.f64_or(5, "GAMAO", 0.0)?;
    let a = c1.f64_or(6, "A", 0.0)?;
    let e0 = c1.f64_or(7, "E0", 0.0)?;
    let mut v0 = 1.0;
    if let Some(c2) = r.next(W10)? {
        v0 = relative_volume(c2.f64_or(0, "V0", 0.0)?).map_err(|m| c2.field_err("V0", m))?;
        if c2.opt_f64(1, "LCID")?.is_some_and(|v| v != 0.0) {
            return Err(c2.field_err(
                "LCID",
                "an unloading curve is not supported; leave it blank",
            ));
        }
    }
    deck.eos.push(RawEos {
        src: r.src(c1.line),
        id,
        eos: Eos::Gruneisen {
            c,
            s,
            gamma0,
            a,
            rho0: f64::NAN, // the material's RO, when attached
            e0,
            v0,
        },
    });
    Ok(())
}

/// The optional card `E0 V0`.
fn initial(r: &mut Reader<'_>) -> Result<(f64, f64), DeckError> {
    let Some(c2) = r.next(W10)? else {
        return Ok((0.0, 1.0));
    };
    let e0 = c2.f64_or(0, "E0", 0.0)?;
    let v0 = relative_volume(c2.f64_or(1, "V0", 0.0)?).map_err(|m| c2.field_err("V0", m))?;
    Ok((e0, v0))
}

/// V0 blank or 0 means 1; otherwise it must be positive.
fn relative_volume(v0: f64) -> Result<f64, String> {
    if v0 == 0.0 {
        Ok(1.0)
    } else if v0 > 0.0 && v0.is_finite() {
        Ok(v0)
    } else {
        Err(format!(
            "{v0}: the initial relative volume must be positive"
        ))
    }
}
