//! `*SET_NODE_LIST`, `*SET_PART_LIST`, `*SET_SEGMENT`, `*SET_SOLID` and the
//! `*SET_NODE_LIST_GENERATE`, `*SET_PART_LIST_GENERATE` and `*SET_SOLID_GENERATE` forms (LS-DYNA Keyword Manual, Vol. I). Card 1 is
//! `SID DA1 DA2 DA3 DA4 SOLVER` (only SID is used); `_TITLE` puts a title line first. Also
//! `*SET_NODE_GENERAL` ([`node_general`]).

use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::W10;
use crate::deck::raw::{RawDeck, RawSet, RuleKind, SetRule};

fn sid(r: &mut Reader<'_>) -> Result<(i64, usize), DeckError> {
    let c = r.required(W10, "SID DA1 DA2 DA3 DA4")?;
    Ok((c.id(0, "SID")?, c.line))
}

/// Members 8 per card in 10-character fields; blank and 0 entries are skipped.
fn members(r: &mut Reader<'_>, name: &str) -> Result<Vec<(i64, usize)>, DeckError> {
    let mut out = Vec::new();
    while let Some(c) = r.next_nonblank(W10)? {
        for i in 0..8 {
            if let Some(id) = c.ref_id(i, &format!("{name}{}", i + 1))? {
                out.push((id, c.line));
            }
        }
    }
    Ok(out)
}

/// `*SET_NODE_LIST`: card 1, then node ids NID1..NID8 per card.
pub fn node_list(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let (id, line) = sid(r)?;
    let members = members(r, "NID")?;
    deck.node_sets.push(RawSet {
        src: r.src(line),
        id,
        members,
        ranges: Vec::new(),
        general: Vec::new(),
    });
    Ok(())
}

/// `*SET_PART_LIST`: card 1, then part ids PID1..PID8 per card.
pub fn part_list(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let (id, line) = sid(r)?;
    let members = members(r, "PID")?;
    deck.part_sets.push(RawSet {
        src: r.src(line),
        id,
        members,
        ranges: Vec::new(),
        general: Vec::new(),
    });
    Ok(())
}

/// `*SET_SEGMENT`: card 1, then one segment per card, `N1 N2 N3 N4 A1 A2 A3 A4`
/// (N4 blank or 0: a triangle, stored with N3 repeated; A1..A4 ignored).
pub fn segment(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let (id, line) = sid(r)?;
    let mut members = Vec::new();
    while let Some(c) = r.next_nonblank(W10)? {
        let n1 = c.id(0, "N1")?;
        let n2 = c.id(1, "N2")?;
        let n3 = c.id(2, "N3")?;
        let n4 = c.ref_id(3, "N4")?.unwrap_or(n3);
        members.push(([n1, n2, n3, n4], c.line));
    }
    deck.segment_sets.push(RawSet {
        ranges: Vec::new(),
        general: Vec::new(),
        src: r.src(line),
        id,
        members,
    });
    Ok(())
}

/// `_GENERATE`: card 1, then ranges `B1BEG B1END .. B4BEG B4END` per card; every defined id
/// from BnBEG to BnEND (inclusive) is a member (ids missing in between are skipped: meshes are
/// often numbered with gaps). A range with BEG > END is an error; so is one that holds no
/// defined id (when the deck is built).
fn ranges(r: &mut Reader<'_>) -> Result<Vec<(i64, i64, usize)>, DeckError> {
    let mut out = Vec::new();
    while let Some(c) = r.next_nonblank(W10)? {
        for k in 0..4 {
            let (b, e) = (format!("B{}BEG", k + 1), format!("B{}END", k + 1));
            let beg = c.ref_id(2 * k, &b)?;
            let end = c.ref_id(2 * k + 1, &e)?;
            match (beg, end) {
                (None, None) => {}
                (Some(beg), Some(end)) if beg <= end => out.push((beg, end, c.line)),
                (Some(beg), Some(end)) => {
                    return Err(c.field_err(&e, format!("{end} is below {b} = {beg}")))
                }
                _ => return Err(c.field_err(&e, "a range needs both its ends")),
            }
        }
    }
    Ok(out)
}

/// `*SET_NODE_LIST_GENERATE`.
pub fn node_generate(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let (id, line) = sid(r)?;
    let ranges = ranges(r)?;
    deck.node_sets.push(RawSet {
        src: r.src(line),
        id,
        members: Vec::new(),
        ranges,
        general: Vec::new(),
    });
    Ok(())
}

/// `*SET_PART_LIST_GENERATE`.
pub fn part_generate(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let (id, line) = sid(r)?;
    let ranges = ranges(r)?;
    deck.part_sets.push(RawSet {
        src: r.src(line),
        id,
        members: Vec::new(),
        ranges,
        general: Vec::new(),
    });
    Ok(())
}

/// `*SET_SOLID` (also `*SET_SOLID_LIST`): card 1 `SID SOLVER`, then element ids K1..K8 per
/// card.
pub fn solid_list(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let (id, line) = sid(r)?;
    let members = members(r, "K")?;
    deck.solid_sets.push(RawSet {
        src: r.src(line),
        id,
        members,
        ranges: Vec::new(),
        general: Vec::new(),
    });
    Ok(())
}

/// `*SET_SOLID_GENERATE` (also `*SET_SOLID_LIST_GENERATE`): card 1, then element id ranges.
pub fn solid_generate(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let (id, line) = sid(r)?;
    let ranges = ranges(r)?;
    deck.solid_sets.push(RawSet {
        src: r.src(line),
        id,
        members: Vec::new(),
        ranges,
        general: Vec::new(),
    });
    Ok(())
}

/// `*SET_NODE_GENERAL`: card 1, then cards `OPTION E1 .. E7` (OPTION in the first 10
/// columns), applied in the order written: ALL (every node), NODE (node ids), PART (the nodes
/// of the parts' elements), SET (the members of node sets defined before this one), and DNODE,
/// DPART, DSET to take them out again. Other options (BOX, SEG, SHELL, ...) are errors naming
/// the option.
pub fn node_general(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let (id, line) = sid(r)?;
    let mut general = Vec::new();
    while let Some(c) = r.next_nonblank(W10)? {
        let option = c.raw(0).trim().to_ascii_uppercase();
        let (delete, kind) = match option.as_str() {
            "ALL" => (false, RuleKind::All),
            "NODE" => (false, RuleKind::Node),
            "PART" => (false, RuleKind::Part),
            "SET" => (false, RuleKind::Set),
            "DNODE" => (true, RuleKind::Node),
            "DPART" => (true, RuleKind::Part),
            "DSET" => (true, RuleKind::Set),
            other => {
                return Err(c.field_err(
                    "OPTION",
                    format!("'{other}' not supported (ALL, NODE, PART, SET, DNODE, DPART, DSET)"),
                ))
            }
        };
        let mut ids = Vec::new();
        let mut fields = Vec::new();
        for i in 1..8 {
            if let Some(v) = c.ref_id(i, &format!("E{i}"))? {
                ids.push(v);
                fields.push(i as u8);
            }
        }
        if ids.is_empty() && !matches!(kind, RuleKind::All) {
            return Err(c.field_err("E1", format!("{option} names no ids")));
        }
        general.push(SetRule {
            line: c.line,
            delete,
            kind,
            ids,
            fields,
        });
    }
    deck.node_sets.push(RawSet {
        src: r.src(line),
        id,
        members: Vec::new(),
        ranges: Vec::new(),
        general,
    });
    Ok(())
}
