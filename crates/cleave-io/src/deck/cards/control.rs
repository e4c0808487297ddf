//! `*CONTROL_...` and `*DATABASE_...` keywords (LS-DYNA Keyword Manual, Vol. I).

use cleave_core::model::{Hourglass, PenaltyRule};

use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{RawDeck, RawHourglass};

/// Records a warning if field `i` is set (non-blank, non-zero): it is read but not used.
pub fn warn_ignored(
    c: &Card<'_>,
    i: usize,
    name: &str,
    what: &str,
    deck: &mut RawDeck,
) -> Result<(), DeckError> {
    // a value that is not a number is an error even here: it is most likely a card laid out
    // in other columns, whose other fields are then misread too
    if c.opt_f64(i, name)?.is_some_and(|v| v != 0.0) {
        deck.warnings.push(format!(
            "{}:{}: {}: field {name} = {} ignored ({what})",
            c.file,
            c.line,
            c.keyword,
            c.raw(i)
        ));
    }
    Ok(())
}

/// A real that must be blank or 0: the feature it switches on (`what`) is not modelled, and
/// a deck that sets it would run different physics.
pub fn unsupported(c: &Card<'_>, i: usize, name: &str, what: &str) -> Result<(), DeckError> {
    let v = c.f64_or(i, name, 0.0)?;
    if v != 0.0 {
        return Err(c.field_err(
            name,
            format!("{v}: {what} is not supported; leave it blank or 0"),
        ));
    }
    Ok(())
}

/// A non-negative real (blank: 0).
pub fn non_negative(c: &Card<'_>, i: usize, name: &str) -> Result<f64, DeckError> {
    let v = c.f64_or(i, name, 0.0)?;
    if v < 0.0 {
        return Err(c.field_err(name, format!("{v} must not be negative")));
    }
    Ok(v)
}

/// `*CONTROL_` keywords that only switch output, bookkeeping or parallel options in LS-DYNA:
/// cleave always computes every energy it reports, runs on every core it is given, and reads
/// the deck as a whole, so they are read past with a warning. (`*CONTROL_` keywords that would
/// change the physics, such as dynamic relaxation, mass scaling or shells, stay errors.)
const NOTHING_FOR_CLEAVE: &[&str] = &[
    "*CONTROL_ENERGY",
    "*CONTROL_OUTPUT",
    "*CONTROL_CPU",
    "*CONTROL_PARALLEL",
    "*CONTROL_DEBUG",
    "*CONTROL_REMOVE_ADDITIONAL_DATA",
];

/// Reads past the keyword's cards with the warning `KEYWORD: note` at its line.
fn read_past(r: &mut Reader<'_>, deck: &mut RawDeck, note: &str) -> Result<(), DeckError> {
    deck.warnings.push(format!(
        "{}:{}: {}: {note}",
        r.file,
        r.line_of_keyword(),
        r.keyword
    ));
    r.ignore_rest();
    Ok(())
}

/// A card whose first field `field` switches on an analysis cleave does not run: 0 (blank) is
/// read past with the warning `note`, any other value is an error, `refusal` saying why.
fn zero_or_refuse(
    r: &mut Reader<'_>,
    deck: &mut RawDeck,
    field: &str,
    note: &str,
    refusal: &str,
) -> Result<(), DeckError> {
    let c = r.card_or_defaults(W10)?;
    match c.i64_or(0, field, 0)? {
        0 => read_past(r, deck, note),
        v => Err(c.field_err(field, format!("{v}: {refusal}"))),
    }
}

/// Dispatches the `*CONTROL_` and `*DATABASE_` keywords.
pub fn control_or_database(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    match r.keyword {
        "*CONTROL_TERMINATION" => termination(r, deck),
        "*CONTROL_TIMESTEP" => timestep(r, deck),
        "*CONTROL_HOURGLASS" => hourglass(r, deck),
        "*CONTROL_BULK_VISCOSITY" => bulk_viscosity(r, deck),
        "*CONTROL_CONTACT" => contact(r, deck),
        "*DATABASE_GLSTAT"
        | "*DATABASE_NODOUT"
        | "*DATABASE_ELOUT"
        | "*DATABASE_RWFORC"
        | "*DATABASE_RCFORC"
        | "*DATABASE_BINARY_D3PLOT" => interval(r, deck),
        "*DATABASE_HISTORY_NODE" | "*DATABASE_HISTORY_SOLID" | "*DATABASE_HISTORY_SOLID_SET" => {
            history(r, deck)
        }
        "*CONTROL_SOLID" => solid(r, deck),
        // SOLN NLQ ISNAN LCINT: SOLN 0 is a structural analysis, all cleave does
        "*CONTROL_SOLUTION" => zero_or_refuse(
            r,
            deck,
            "SOLN",
            "SOLN 0 (structural), ignored",
            "thermal and coupled analyses are not supported (cleave is structural: SOLN 0)",
        ),
        "*CONTROL_SHELL" => read_past(
            r,
            deck,
            "shell settings, ignored (cleave has solid elements only)",
        ),
        "*CONTROL_ACCURACY" => read_past(
            r,
            deck,
            "cleave's stress update is always objective and second order (OSU 1); invariant node numbering (INN) is not applied, ignored",
        ),
        // IMFLAG 0 (blank) is an explicit run; any other (an implicit or a switching analysis)
        // is an error: cleave is an explicit code
        "*CONTROL_IMPLICIT_GENERAL" => zero_or_refuse(
            r,
            deck,
            "IMFLAG",
            "IMFLAG 0, an explicit run; ignored",
            "implicit analysis is not supported (cleave integrates explicitly in time); set IMFLAG 0 or remove the *CONTROL_IMPLICIT_ cards",
        ),
        k if k.starts_with("*CONTROL_IMPLICIT_") => read_past(
            r,
            deck,
            "implicit solver settings, ignored (cleave runs explicit dynamics; *CONTROL_IMPLICIT_GENERAL with IMFLAG 1 is an error)",
        ),
        k if NOTHING_FOR_CLEAVE.contains(&k) || k.starts_with("*CONTROL_MPP_") => {
            read_past(r, deck, "changes nothing cleave computes, ignored")
        }
        k if k.starts_with("*DATABASE_") => {
            read_past(r, deck, "output request not supported, ignored")
        }
        k => Err(DeckError::at(
            r.file,
            r.line_of_keyword(),
            Some(k),
            "keyword not supported (see the supported keyword list in the README)",
        )),
    }
}

/// `*CONTROL_TERMINATION`: ENDTIM ENDCYC DTMIN ENDENG ENDMAS NOSOL. ENDTIM must be positive;
/// DTMIN in [0, 1) (blank or 0: cleave's default floor, `cleave_core::model::DEFAULT_DTMIN`).
fn termination(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.card_or_defaults(W10)?;
    deck.control.end_time = c.positive(0, "ENDTIM")?;
    deck.termination = Some(r.src(c.line));
    let dtmin = c.f64_or(2, "DTMIN", 0.0)?;
    if !(0.0..1.0).contains(&dtmin) {
        return Err(c.field_err("DTMIN", format!("{dtmin} must lie in [0, 1)")));
    }
    if dtmin > 0.0 {
        deck.control.dt_min = dtmin;
    }
    for (i, name) in [(1, "ENDCYC"), (3, "ENDENG"), (4, "ENDMAS")] {
        warn_ignored(&c, i, name, "only ENDTIM and DTMIN end a run", deck)?;
    }
    Ok(())
}

/// `*CONTROL_TIMESTEP`: DTINIT TSSFAC ISDO TSLIMT DT2MS LCTM ERODE MS1ST; an optional second
/// card is ignored. TSSFAC blank or 0 means 0.9; LCTM, a curve of the largest time step
/// against time.
fn timestep(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.card_or_defaults(W10)?;
    deck.control.dt_init = non_negative(&c, 0, "DTINIT")?;
    let tssfac = c.f64_nz(1, "TSSFAC", 0.9)?;
    if tssfac <= 0.0 || tssfac > 1.0 {
        return Err(c.field_err("TSSFAC", format!("{tssfac} must lie in (0, 1]")));
    }
    deck.control.tssfac = tssfac;
    warn_ignored(&c, 4, "DT2MS", "mass scaling is not supported", deck)?;
    if let Some(id) = c.ref_id(5, "LCTM")? {
        deck.lctm = Some((id, r.src(c.line)));
    }
    r.ignore(1);
    Ok(())
}

/// `*CONTROL_HOURGLASS`: IHQ QH. IHQ 0, 1, 2, 3 (blank: 1) are the viscous form, 4 and 5 the
/// stiffness form; QH blank or 0 means 0.1.
fn hourglass(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.card_or_defaults(W10)?;
    deck.control.hourglass = match c.i64_or(0, "IHQ", 1)? {
        0..=3 => Hourglass::Viscous,
        4 | 5 => Hourglass::Stiffness,
        v => {
            return Err(c.field_err(
                "IHQ",
                format!("{v} not supported (1, 2, 3: viscous; 4, 5: stiffness)"),
            ))
        }
    };
    let qh = c.f64_nz(1, "QH", 0.1)?;
    if qh < 0.0 {
        return Err(c.field_err("QH", format!("{qh} must not be negative")));
    }
    deck.control.qh = qh;
    Ok(())
}

/// `*HOURGLASS` (`_TITLE`): `HGID IHQ QM IBQ Q1 Q2 QB/VDC QW`, the hourglass control and bulk
/// viscosity of the parts naming HGID. IHQ blank or 0: the `*CONTROL_HOURGLASS` form; 1, 2, 3
/// the viscous form, 4 and 5 the stiffness form (as `*CONTROL_HOURGLASS`); QM blank or 0:
/// 0.1; Q1, Q2 blank or 0: 1.5 and 0.06 (the card's defaults in LS-DYNA, not those of
/// `*CONTROL_BULK_VISCOSITY`). IBQ, QB/VDC and QW concern shells and are not read.
pub fn hourglass_def(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while !r.at_end() {
        let c = r.required(W10, "HGID")?;
        let id = c.id(0, "HGID")?;
        let ihq = match c.i64_or(1, "IHQ", 0)? {
            0 => None,
            1..=3 => Some(Hourglass::Viscous),
            4 | 5 => Some(Hourglass::Stiffness),
            v => {
                return Err(c.field_err(
                    "IHQ",
                    format!(
                    "{v} not supported (1, 2, 3: viscous; 4, 5: stiffness; 0: *CONTROL_HOURGLASS)"
                ),
                ))
            }
        };
        let (qm, q1, q2) = (
            c.f64_nz(2, "QM", 0.1)?,
            c.f64_nz(4, "Q1", 1.5)?,
            c.f64_nz(5, "Q2", 0.06)?,
        );
        for (v, name) in [(qm, "QM"), (q1, "Q1"), (q2, "Q2")] {
            if v < 0.0 {
                return Err(c.field_err(name, format!("{v} must not be negative")));
            }
        }
        deck.hourglass.push(RawHourglass {
            src: r.src(c.line),
            id,
            ihq,
            qm,
            q1,
            q2,
        });
    }
    Ok(())
}

/// `*CONTROL_BULK_VISCOSITY`: Q1 Q2 TYPE. Q1 blank or 0 means 1.5, Q2 blank or 0 means 0.06.
fn bulk_viscosity(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.card_or_defaults(W10)?;
    deck.control.q1 = c.f64_nz(0, "Q1", 1.5)?;
    deck.control.q2 = c.f64_nz(1, "Q2", 0.06)?;
    for (v, name) in [(deck.control.q1, "Q1"), (deck.control.q2, "Q2")] {
        if v < 0.0 {
            return Err(c.field_err(name, format!("{v} must not be negative")));
        }
    }
    Ok(())
}

/// `*CONTROL_CONTACT`: SLSFAC RWPNAL ISLCHK SHLTHK PENOPT THKCHG ORIEN ENMASS; SLSFAC blank
/// or 0 means 0.1; PENOPT 0 or 1 (blank: 1) the smaller of the face's and the node's
/// stiffness, 2 the face's (3 to 5 are the shell and slave-node variants: errors). The other
/// fields and the optional further cards are ignored.
fn contact(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.card_or_defaults(W10)?;
    let v = c.f64_nz(0, "SLSFAC", 0.1)?;
    if v < 0.0 {
        return Err(c.field_err("SLSFAC", format!("{v} must not be negative")));
    }
    deck.control.slsfac = v;
    deck.control.penalty = match c.i64_or(4, "PENOPT", 1)? {
        0 | 1 => PenaltyRule::Smaller,
        2 => PenaltyRule::Face,
        v => {
            return Err(c.field_err(
                "PENOPT",
                format!("{v} not supported (0, 1: the smaller of face and node; 2: the face's)"),
            ))
        }
    };
    r.ignore_rest();
    Ok(())
}

/// `*DATABASE_{GLSTAT,NODOUT,ELOUT,RWFORC,RCFORC}`: DT BINARY LCUR IOOPT;
/// `*DATABASE_BINARY_D3PLOT`: DT LCDT BEAM NPLTC PSETID (optional card 2 ignored).
fn interval(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.card_or_defaults(W10)?;
    let dt = non_negative(&c, 0, "DT")?;
    let o = &mut deck.output;
    match r.keyword {
        "*DATABASE_GLSTAT" => o.glstat_dt = dt,
        "*DATABASE_NODOUT" => o.nodout_dt = dt,
        "*DATABASE_ELOUT" => o.elout_dt = dt,
        "*DATABASE_RWFORC" => o.rwforc_dt = dt,
        "*DATABASE_RCFORC" => o.rcforc_dt = dt,
        _ => {
            o.d3plot_dt = dt;
            r.ignore(1);
        }
    }
    Ok(())
}

/// `*DATABASE_HISTORY_NODE` / `_SOLID` / `_SOLID_SET`: ids (of nodes, elements, solid sets),
/// 8 per card in 10-character fields (0 skipped).
fn history(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let solid = r.keyword == "*DATABASE_HISTORY_SOLID";
    let solid_set = r.keyword == "*DATABASE_HISTORY_SOLID_SET";
    while let Some(c) = r.next_nonblank(W10)? {
        for i in 0..8 {
            let name = format!("ID{}", i + 1);
            if let Some(id) = c.ref_id(i, &name)? {
                let src = r.src(c.line);
                if solid_set {
                    deck.history_solid_sets.push((id, src));
                } else if solid {
                    deck.history_solids.push((id, src));
                } else {
                    deck.history_nodes.push((id, src));
                }
            }
        }
    }
    Ok(())
}

/// `*CONTROL_SOLID`: `ESORT FMATRX NIPTETS SWLOCL PSFAIL T10JTOL ICOH TET13K`, then optional
/// cards (the ELFORM 16/17 node permutation `PM1..PM10`, ...). cleave always treats degenerate
/// hexahedra as tetrahedra and wedges (what ESORT 1 asks for), so ESORT and the fields that
/// only concern elements or output cleave does not have (FMATRX, NIPTETS, SWLOCL, T10JTOL,
/// ICOH) are ignored with one warning naming those that are set; PSFAIL (erosion of solids
/// by a failure criterion) and TET13K (another ELFORM 13 formulation) would change what cleave
/// computes and are errors when non-zero. Further cards warn.
fn solid(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let c = r.card_or_defaults(W10)?;
    let esort = c.code(0, "ESORT", 0, 0, 2)?;
    unsupported(
        &c,
        4,
        "PSFAIL",
        "erosion of solid elements (a part set to fail)",
    )?;
    unsupported(&c, 7, "TET13K", "the alternative ELFORM 13 formulation")?;
    let mut set = Vec::new();
    for (i, name) in [
        (1, "FMATRX"),
        (2, "NIPTETS"),
        (3, "SWLOCL"),
        (5, "T10JTOL"),
        (6, "ICOH"),
    ] {
        let s = c.raw(i);
        if !s.is_empty() && !crate::deck::fields::parse_f64(s).is_ok_and(|v| v == 0.0) {
            set.push(format!("{name} = {s}"));
        }
    }
    let set = if set.is_empty() {
        String::new()
    } else {
        format!("; ignored: {}", set.join(", "))
    };
    deck.warnings.push(format!(
        "{}:{}: *CONTROL_SOLID: ESORT {esort}: cleave always treats degenerate hexahedra as tetrahedra and wedges (ESORT 1){set}",
        c.file, c.line
    ));
    r.skip_blank();
    if !r.at_end() {
        deck.warnings.push(format!(
            "{}:{}: *CONTROL_SOLID: the cards after the first (node permutations of ELFORM 16/17, ...) concern no element cleave has, ignored",
            c.file, c.line
        ));
        r.ignore_rest();
    }
    Ok(())
}
