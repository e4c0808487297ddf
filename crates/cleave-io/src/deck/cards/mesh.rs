//! `*NODE`, `*ELEMENT_SOLID`, `*PART` and `*SECTION_SOLID` (LS-DYNA Keyword Manual, Vol. I).

use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{blank_beyond, W10};
use crate::deck::raw::{RawDeck, RawElem, RawNode, RawPart, RawSection};

/// `*NODE` field widths: NID X Y Z TC RC.
const NODE: &[usize] = &[8, 16, 16, 16, 8, 8];
/// `*ELEMENT_SOLID` field widths: 10 fields of 8 characters.
const ELEM: &[usize] = &[8; 10];

/// `*NODE`: one card per node, NID X Y Z TC RC (8+16+16+16+8+8). TC and RC are constraint
/// codes 0..7 (0 none, 1 x, 2 y, 3 z, 4 x+y, 5 y+z, 6 z+x, 7 all).
pub fn node(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(NODE)? {
        deck.nodes.push(RawNode {
            src: r.src(c.line),
            id: c.id(0, "NID")?,
            x: [
                c.f64_or(1, "X", 0.0)?,
                c.f64_or(2, "Y", 0.0)?,
                c.f64_or(3, "Z", 0.0)?,
            ],
            tc: c.code(4, "TC", 0, 0, 7)?,
            rc: c.code(5, "RC", 0, 0, 7)?,
        });
    }
    Ok(())
}

/// `*ELEMENT_SOLID`, 8-character fields, each element in either form:
/// one card `EID PID N1..N8`, or two cards `EID PID` / `N1..N10` (N9, N10 blank: only 8-node
/// hexahedra). Fixed format: a first card blank beyond column 16 is the two-card form; free
/// format: 2 values is the two-card form, 10 values the one-card form. N5..N8 all blank (6
/// values in free format) is a 4-node tetrahedron, as LS-PrePost writes it: read as
/// `N1 N2 N3 N4 N4 N4 N4 N4`.
pub fn element_solid(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c1) = r.next_nonblank(ELEM)? {
        let two_card = if c1.free {
            match c1.count() {
                2 => true,
                6 | 10 => false,
                n => {
                    return Err(c1.err(format!(
                        "expected 2 values (EID, PID; nodes on the next card), 10 (EID, PID, N1..N8) or 6 (EID, PID, N1..N4 of a tetrahedron), found {n}"
                    )))
                }
            }
        } else {
            blank_beyond(r.current_text(), r.format.columns(ELEM, 2))
        };
        let eid = c1.id(0, "EID")?;
        let pid = c1.id(1, "PID")?;
        let (nc, first) = if two_card {
            (r.required(ELEM, "N1..N8 of element")?, 0)
        } else {
            (c1.clone(), 2)
        };
        let mut nodes = [0; 8];
        for (k, n) in nodes.iter_mut().enumerate().take(4) {
            *n = nc.id(first + k, &format!("N{}", k + 1))?;
        }
        let mut rest = [None; 4];
        for (k, n) in rest.iter_mut().enumerate() {
            *n = nc.ref_id(first + 4 + k, &format!("N{}", k + 5))?;
        }
        if rest.iter().all(Option::is_none) {
            // N5..N8 blank: the 4-node tetrahedron as LS-PrePost writes it, N4 repeated
            let n4 = nodes[3];
            nodes[4..].fill(n4);
        } else {
            for (k, n) in rest.iter().enumerate() {
                nodes[4 + k] = n.ok_or_else(|| {
                    nc.field_err(
                        &format!("N{}", k + 5),
                        "missing: give N5..N8 (a positive id each), or leave all four blank for a 4-node tetrahedron",
                    )
                })?;
            }
        }
        if two_card {
            for k in 8..10 {
                if nc.ref_id(k, &format!("N{}", k + 1))?.is_some() {
                    return Err(nc.field_err(
                        &format!("N{}", k + 1),
                        "only 8-node hexahedra are supported",
                    ));
                }
            }
        }
        deck.elems.push(RawElem {
            src: r.src(c1.line),
            id: eid,
            pid,
            nodes,
            node_line: nc.line,
        });
    }
    Ok(())
}

/// `*PART`: for each part, a title line (80 characters) then
/// `PID SECID MID EOSID HGID GRAV ADPOPT TMID`. SECID and MID are required; EOSID names an
/// `*EOS_...` (for `*MAT_JOHNSON_COOK` only); HGID a `*HOURGLASS`; TMID must be blank (thermal
/// materials are not supported). `*PART_INERTIA` (`inertia`): the inertia cards follow each part's card
/// ([`super::constrained::inertia_cards`]: `XC YC ZC TM IRCS NODEID`, the tensor, the
/// velocities and, with IRCS 1, the local axes).
pub fn part(r: &mut Reader<'_>, deck: &mut RawDeck, inertia: bool) -> Result<(), DeckError> {
    while !r.at_end() {
        let title = r.title()?;
        let c = r.required(W10, "PID SECID MID")?;
        let id = c.id(0, "PID")?;
        let secid = c
            .ref_id(1, "SECID")?
            .ok_or_else(|| c.field_err("SECID", format!("part {id} has no section")))?;
        let mid = c
            .ref_id(2, "MID")?
            .ok_or_else(|| c.field_err("MID", format!("part {id} has no material")))?;
        let eosid = c.ref_id(3, "EOSID")?;
        let hgid = c.ref_id(4, "HGID")?;
        if c.ref_id(7, "TMID")?.is_some() {
            return Err(c.field_err(
                "TMID",
                "thermal materials not supported; leave it blank".to_string(),
            ));
        }
        let given = if inertia {
            Some(super::constrained::inertia_cards(r, true)?)
        } else {
            None
        };
        deck.parts.push(RawPart {
            src: r.src(c.line),
            id,
            title,
            secid,
            mid,
            eosid,
            hgid,
            inertia: given,
        });
    }
    Ok(())
}

/// `*SECTION_SOLID` (`_TITLE`: a title line before each section):
/// `SECID ELFORM AET ...`. ELFORM blank, 0 or 1: the one-point hexahedron; anything else is
/// an error.
pub fn section_solid(
    r: &mut Reader<'_>,
    deck: &mut RawDeck,
    titled: bool,
) -> Result<(), DeckError> {
    let mut first = true;
    while !r.at_end() {
        if titled && !first {
            r.title()?;
        }
        first = false;
        let c = r.required(W10, "SECID ELFORM")?;
        let id = c.id(0, "SECID")?;
        let elform = match c.i64_or(1, "ELFORM", 1)? {
            0 | 1 => 1,
            2 => 2,
            10 => 10,
            13 => 13,
            e => {
                return Err(c.field_err(
                    "ELFORM",
                    format!(
                        "{e} not supported: 1 (one-point hexahedron with hourglass control; wedges as degenerate hexahedra, tetrahedra as ELFORM 10), 2 (fully integrated selectively reduced hexahedron), 10 (one-point tetrahedron) or 13 (tetrahedron with nodal pressure averaging)"
                    ),
                ))
            }
        };
        deck.sections.push(RawSection {
            src: r.src(c.line),
            id,
            elform,
        });
    }
    Ok(())
}
