//! `*DEFINE_TRANSFORMATION` and the cards of `*INCLUDE_TRANSFORM` (LS-DYNA Keyword Manual,
//! Vol. I); what they do to the included file is `crate::deck::transform`.

use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::W10;
use crate::deck::include::name_lines;
use crate::deck::raw::{Offsets, RawDeck, RawIncludeXform, RawTransform};

/// `*DEFINE_TRANSFORMATION`: card 1 `TRANID`; then one card per step,
/// `OPTION A1 A2 A3 A4 A5 A6 A7`, applied in the order written (the options themselves are
/// checked when the transformation is used).
pub fn define_transformation(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "TRANID")?;
    let id = c.id(0, "TRANID")?;
    let src = r.src(c.line);
    let mut ops = Vec::new();
    while let Some(c) = r.next_nonblank(W10)? {
        let option = c.raw(0).trim().to_ascii_uppercase();
        let mut a = [0.0; 7];
        for (k, v) in a.iter_mut().enumerate() {
            *v = c.f64_or(k + 1, &format!("A{}", k + 1), 0.0)?;
        }
        ops.push((option, a, c.line));
    }
    if ops.is_empty() {
        return Err(r.error_at_keyword(format!(
            "transformation {id} has no step (cards OPTION A1..A7)"
        )));
    }
    deck.transforms.push(RawTransform { src, id, ops });
    Ok(())
}

/// A unit-conversion factor of `*INCLUDE_TRANSFORM`: blank, 0 or 1 (no conversion) is all
/// cleave takes, the file being read in the main deck's units.
fn unit_factor(c: &crate::deck::fields::Card<'_>, i: usize, name: &str) -> Result<(), DeckError> {
    let f = c.f64_or(i, name, 1.0)?;
    if f != 0.0 && f != 1.0 {
        return Err(c.field_err(
            name,
            format!("{f}: unit conversion of an included file is not supported (cleave reads it in the main deck's units); convert the file or give 1"),
        ));
    }
    Ok(())
}

/// `*INCLUDE_TRANSFORM` (the file itself was read by `include`): card 1 the file name
/// (continued on the next line while it ends with ` +`); card 2
/// `IDNOFF IDEOFF IDPOFF IDMOFF IDSOFF IDFOFF IDDOFF`; card 3 `IDROFF - PREFIX SUFFIX`
/// (the titles' prefix and suffix are not used); card 4
/// `FCTMAS FCTTIM FCTLEN FCTTEM INCOUT1 FCTCHG` (unit factors other than 1 are errors;
/// INCOUT1, which asks for the transformed file to be written, and the charge factor FCTCHG
/// are not used); card 5 `TRANID` (0 or blank: none). Cards 2-5 may be left out.
pub fn include_transform(
    r: &mut Reader<'_>,
    deck: &mut RawDeck,
    group: usize,
) -> Result<(), DeckError> {
    let src = r.src(r.line_of_keyword());
    r.ignore(name_lines(r.remaining()));
    let mut offsets = Offsets::default();
    if let Some(c) = r.next(W10)? {
        let names = [
            "IDNOFF", "IDEOFF", "IDPOFF", "IDMOFF", "IDSOFF", "IDFOFF", "IDDOFF",
        ];
        let mut v = [0i64; 7];
        for (k, (x, n)) in v.iter_mut().zip(names).enumerate() {
            *x = c.i64_or(k, n, 0)?;
            if *x < 0 {
                return Err(c.field_err(n, format!("{x}: an id offset is 0 or more")));
            }
        }
        [
            offsets.node,
            offsets.elem,
            offsets.part,
            offsets.mat,
            offsets.set,
            offsets.curve,
            offsets.define,
        ] = v;
    }
    if let Some(c) = r.next(W10)? {
        offsets.other = c.i64_or(0, "IDROFF", 0)?;
        if offsets.other < 0 {
            return Err(c.field_err("IDROFF", "an id offset is 0 or more"));
        }
    }
    if let Some(c) = r.next(W10)? {
        unit_factor(&c, 0, "FCTMAS")?;
        unit_factor(&c, 1, "FCTTIM")?;
        unit_factor(&c, 2, "FCTLEN")?;
        let tem = c.raw(3).trim();
        if !tem.is_empty() && !crate::deck::fields::parse_f64(tem).is_ok_and(|f| f == 1.0) {
            return Err(c.field_err(
                "FCTTEM",
                format!("'{tem}': temperature conversion of an included file is not supported; leave it blank"),
            ));
        }
    }
    let mut tranid = None;
    if let Some(c) = r.next(W10)? {
        if let Some(t) = c.ref_id(0, "TRANID")? {
            tranid = Some((t, c.line));
        }
    }
    deck.include_xforms.push(RawIncludeXform {
        src,
        group,
        offsets,
        tranid,
    });
    Ok(())
}
