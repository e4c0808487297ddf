//! `*DEFINE_CURVE` (LS-DYNA Keyword Manual, Vol. I): card 1 `LCID SIDR SFA SFO OFFA OFFO
//! DATTYP LCINT` in 10-character fields, then one point per card, `A1 O1` in 20+20.
//! The stored curve has (SFA a + OFFA, SFO o + OFFO); SFA, SFO blank or 0 mean 1.
//! `*DEFINE_TABLE`: card 1 `TBID SFA OFFA`, then one value per card (20 characters); its
//! curves are the `*DEFINE_CURVE`s that follow it in the deck, one per value, in order.
//! `*DEFINE_TABLE_2D`: the same card 1, then `VALUE LCID` per card (20 + 20): the curves
//! named. Values are scaled (SFA VALUE + OFFA) and must increase.

use cleave_core::curve::Curve;

use super::control::warn_ignored;
use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::W10;
use crate::deck::raw::{RawCurve, RawDeck, RawTable, TableCurves};

const POINT: &[usize] = &[20, 20];

/// Reads one curve; abscissae must be strictly increasing after scaling and there must be
/// at least one point.
pub fn define_curve(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.required(W10, "LCID SIDR SFA SFO OFFA OFFO DATTYP")?;
    let id = c.id(0, "LCID")?;
    let sidr = c.code(1, "SIDR", 0, 0, 2)?;
    if sidr == 1 {
        deck.warnings.push(format!(
            "{}:{}: {}: curve {id}: SIDR = 1 (dynamic relaxation) is not supported; the curve is used in the transient only",
            c.file, c.line, c.keyword
        ));
    }
    let sfa = c.f64_nz(2, "SFA", 1.0)?;
    let sfo = c.f64_nz(3, "SFO", 1.0)?;
    let offa = c.f64_or(4, "OFFA", 0.0)?;
    let offo = c.f64_or(5, "OFFO", 0.0)?;
    warn_ignored(
        &c,
        6,
        "DATTYP",
        "curves are plain abscissa-ordinate pairs",
        deck,
    )?;
    let mut curve = Curve {
        id,
        t: Vec::new(),
        y: Vec::new(),
    };
    while let Some(p) = r.next_nonblank(POINT)? {
        let a = sfa * p.f64_or(0, "A", 0.0)? + offa;
        let o = sfo * p.f64_or(1, "O", 0.0)? + offo;
        if !a.is_finite() || !o.is_finite() {
            return Err(p.err(format!("curve {id}: scaled point is not finite")));
        }
        if let Some(&prev) = curve.t.last() {
            if a <= prev {
                return Err(p.field_err(
                    "A",
                    format!("curve {id}: abscissa {a} is not greater than the previous one ({prev}); abscissae must be strictly increasing"),
                ));
            }
        }
        curve.t.push(a);
        curve.y.push(o);
    }
    if curve.t.is_empty() {
        return Err(c.err(format!("curve {id} has no points")));
    }
    deck.curves.push(RawCurve {
        src: r.src(c.line),
        curve,
    });
    Ok(())
}

const VALUE: &[usize] = &[20, 20];

/// Reads a table (`two_d`: `*DEFINE_TABLE_2D`, each value with its curve's id).
pub fn define_table(r: &mut Reader<'_>, deck: &mut RawDeck, two_d: bool) -> Result<(), DeckError> {
    let c = r.required(W10, "TBID SFA OFFA")?;
    let id = c.id(0, "TBID")?;
    let sfa = c.f64_nz(1, "SFA", 1.0)?;
    let offa = c.f64_or(2, "OFFA", 0.0)?;
    let mut values: Vec<(f64, usize)> = Vec::new();
    let mut ids = Vec::new();
    while let Some(p) = r.next_nonblank(VALUE)? {
        let v = sfa * p.f64_or(0, "VALUE", 0.0)? + offa;
        if let Some(&(prev, _)) = values.last() {
            if v <= prev {
                return Err(p.field_err(
                    "VALUE",
                    format!("table {id}: value {v} is not greater than the previous one ({prev}); values must increase"),
                ));
            }
        }
        if two_d {
            ids.push(p.id(1, "LCID")?);
        }
        values.push((v, p.line));
    }
    if values.is_empty() {
        return Err(c.err(format!("table {id} has no values")));
    }
    deck.tables.push(RawTable {
        src: r.src(c.line),
        id,
        values,
        curves: if two_d {
            TableCurves::Ids(ids)
        } else {
            TableCurves::Following(deck.curves.len())
        },
    });
    Ok(())
}
