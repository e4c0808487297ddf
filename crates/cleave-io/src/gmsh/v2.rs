//! The MSH 2.2 sections cleave reads: `$Nodes` and `$Elements` (Gmsh reference manual, "MSH
//! file format version 2"). Counts are ASCII lines in binary files too.
//!
//! ```text
//! $Nodes
//!   number-of-nodes
//!   ASCII:  node-number x y z                                  (one line per node)
//!   binary: node-number(int) x y z(double)                     (per node)
//! $Elements
//!   number-of-elements
//!   ASCII:  elm-number elm-type number-of-tags tag... node-number...   (one line each)
//!   binary: blocks of elm-type number-of-elements-following number-of-tags (int),
//!           then per element elm-number tag... node-number... (int)
//! ```
//!
//! The first tag is the physical group (0: none), the second the elementary (geometric)
//! entity. Gmsh writes an element that is in two physical groups twice, once per group, with
//! two element numbers.

use super::cursor::Cursor;
use super::error::MshError;
use super::raw::{Owner, RawElem, RawNode};
use super::types::{elem_type, ElemType};

type R<T> = Result<T, MshError>;

/// `$Nodes`.
pub fn nodes(c: &mut Cursor<'_>) -> R<Vec<RawNode>> {
    let n = c.ascii_count("the number of nodes")?;
    if c.is_binary() {
        c.rest_of_line();
    }
    let mut out = Vec::new();
    for _ in 0..n {
        let pos = c.begin_record();
        let tag = c.int("a node number")?;
        let x = [
            c.float("a node's x")?,
            c.float("a node's y")?,
            c.float("a node's z")?,
        ];
        c.record_end(pos, &format!("node {tag}"))?;
        out.push(RawNode { tag, x, pos });
    }
    c.expect_end("$Nodes")?;
    Ok(out)
}

/// The element type `number`, or an error at `at`.
fn ty(c: &Cursor<'_>, number: i64, at: usize) -> R<ElemType> {
    elem_type(number).ok_or_else(|| c.err_at(at, format!("unknown element type {number}")))
}

/// The number of tags, checked.
fn ntags(c: &mut Cursor<'_>) -> R<usize> {
    let at = c.mark();
    let n = c.int("the number of tags")?;
    usize::try_from(n)
        .ok()
        .filter(|n| *n <= 64)
        .ok_or_else(|| c.err_at(at, format!("number of tags {n} is not 0 to 64")))
}

/// One element after its type and tag count.
fn element(c: &mut Cursor<'_>, tag: i64, ty: ElemType, ntags: usize, pos: usize) -> R<RawElem> {
    let mut tags = Vec::with_capacity(ntags);
    for _ in 0..ntags {
        tags.push(c.int("an element tag (physical, elementary, ...)")?);
    }
    let mut nodes = Vec::with_capacity(ty.nodes);
    for _ in 0..ty.nodes {
        nodes.push(c.int("a node number")?);
    }
    Ok(RawElem {
        tag,
        ty,
        owner: Owner::Tags {
            physical: tags.first().copied().unwrap_or(0),
            elementary: tags.get(1).copied(),
        },
        nodes,
        pos,
    })
}

/// `$Elements`.
pub fn elements(c: &mut Cursor<'_>) -> R<Vec<RawElem>> {
    let n = c.ascii_count("the number of elements")?;
    let mut out = Vec::new();
    if c.is_binary() {
        c.rest_of_line();
        while (out.len() as u64) < n {
            let at = c.mark();
            let t = c.int("an element type")?;
            let ty = ty(c, t, at)?;
            let follow = c.int("the number of elements in the block")?;
            let nt = ntags(c)?;
            if follow < 0 || out.len() as u64 + follow as u64 > n {
                return Err(c.err_at(
                    at,
                    format!(
                        "a block of {follow} elements after {} of the {n} the count says",
                        out.len()
                    ),
                ));
            }
            for _ in 0..follow {
                let pos = c.mark();
                let tag = c.int("an element number")?;
                out.push(element(c, tag, ty, nt, pos)?);
            }
        }
    } else {
        for _ in 0..n {
            let pos = c.begin_record();
            let tag = c.int("an element number")?;
            let at = c.mark();
            let t = c.int("an element type")?;
            let ty = ty(c, t, at)?;
            let nt = ntags(c)?;
            out.push(element(c, tag, ty, nt, pos)?);
            c.record_end(pos, &format!("element {tag} ({})", ty.name))?;
        }
    }
    c.expect_end("$Elements")?;
    Ok(out)
}
