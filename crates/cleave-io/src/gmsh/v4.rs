//! The MSH 4.1 sections cleave reads: `$Entities`, `$Nodes` and `$Elements` (Gmsh reference
//! manual, "MSH file format", version 4.1). `int` values are 4 bytes in binary, `size_t` ones
//! data-size bytes, `double` ones 8; ASCII files hold the same values as text.
//!
//! ```text
//! $Entities
//!   numPoints numCurves numSurfaces numVolumes                            (size_t)
//!   per point:  tag(int) X Y Z(double) numPhysicalTags(size_t) physicalTag(int)...
//!   per curve, surface, volume: tag(int) minX minY minZ maxX maxY maxZ(double)
//!               numPhysicalTags(size_t) physicalTag(int)...
//!               numBoundingEntities(size_t) boundingTag(int)...
//! $Nodes
//!   numEntityBlocks numNodes minNodeTag maxNodeTag                        (size_t)
//!   per block:  entityDim entityTag parametric(int) numNodesInBlock(size_t)
//!               nodeTag(size_t) x numNodesInBlock
//!               x y z(double) [u [v [w]]: entityDim values if parametric] x numNodesInBlock
//! $Elements
//!   numEntityBlocks numElements minElementTag maxElementTag               (size_t)
//!   per block:  entityDim entityTag elementType(int) numElementsInBlock(size_t)
//!               elementTag nodeTag...(size_t) x numElementsInBlock
//! ```

use std::collections::HashMap;

use super::cursor::Cursor;
use super::error::MshError;
use super::raw::{Owner, RawElem, RawNode};
use super::types::elem_type;

type R<T> = Result<T, MshError>;

/// A `size_t` tag as an id.
fn tag(c: &mut Cursor<'_>, what: &str) -> R<i64> {
    let at = c.mark();
    let v = c.size(what)?;
    i64::try_from(v).map_err(|_| c.err_at(at, format!("{what} {v} is too large")))
}

/// An `int` that must be an entity dimension, 0 to 3.
fn dim(c: &mut Cursor<'_>) -> R<u8> {
    let at = c.mark();
    let d = c.int("an entity dimension")?;
    u8::try_from(d)
        .ok()
        .filter(|d| *d <= 3)
        .ok_or_else(|| c.err_at(at, format!("entity dimension {d} is not 0, 1, 2 or 3")))
}

/// `$Entities`: the physical tags of every entity.
pub fn entities(c: &mut Cursor<'_>) -> R<HashMap<(u8, i64), Vec<i64>>> {
    let mut counts = [0u64; 4];
    for (k, what) in ["points", "curves", "surfaces", "volumes"]
        .iter()
        .enumerate()
    {
        counts[k] = c.size(&format!("the number of {what}"))?;
    }
    let mut out = HashMap::new();
    for (d, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let at = c.mark();
            let tag = c.int("an entity tag")?;
            for _ in 0..if d == 0 { 3 } else { 6 } {
                c.float("an entity's coordinates")?;
            }
            let np = c.size("the number of physical tags")?;
            let mut phys = Vec::new();
            for _ in 0..np {
                phys.push(c.int("a physical tag")?);
            }
            if d > 0 {
                let nb = c.size("the number of bounding entities")?;
                for _ in 0..nb {
                    c.int("a bounding entity tag")?;
                }
            }
            if out.insert((d as u8, tag), phys).is_some() {
                return Err(c.err_at(
                    at,
                    format!("entity {tag} of dimension {d} is defined twice"),
                ));
            }
        }
    }
    c.expect_end("$Entities")?;
    Ok(out)
}

/// `$Nodes`.
pub fn nodes(c: &mut Cursor<'_>) -> R<Vec<RawNode>> {
    let head = c.mark();
    let blocks = c.size("the number of node blocks")?;
    let total = c.size("the number of nodes")?;
    c.size("the smallest node tag")?;
    c.size("the largest node tag")?;
    let mut out = Vec::new();
    for _ in 0..blocks {
        let d = dim(c)?;
        c.int("an entity tag")?;
        let at = c.mark();
        let parametric = c.int("the parametric flag")?;
        if parametric != 0 && parametric != 1 {
            return Err(c.err_at(at, format!("parametric flag {parametric} is not 0 or 1")));
        }
        let n = c.size("the number of nodes in the block")?;
        let mut tags = Vec::new();
        for _ in 0..n {
            let at = c.mark();
            tags.push((tag(c, "node tag")?, at));
        }
        let extra = if parametric == 1 { usize::from(d) } else { 0 };
        for (t, at) in tags {
            let start = c.begin_record();
            let x = [
                c.float("a node's x")?,
                c.float("a node's y")?,
                c.float("a node's z")?,
            ];
            for _ in 0..extra {
                c.float("a node's parametric coordinate")?;
            }
            c.record_end(start, &format!("the coordinates of node {t}"))?;
            out.push(RawNode { tag: t, x, pos: at });
        }
    }
    if out.len() as u64 != total {
        return Err(c.err_at(
            head,
            format!(
                "the header says {total} nodes, the blocks hold {}",
                out.len()
            ),
        ));
    }
    c.expect_end("$Nodes")?;
    Ok(out)
}

/// `$Elements`.
pub fn elements(c: &mut Cursor<'_>) -> R<Vec<RawElem>> {
    let head = c.mark();
    let blocks = c.size("the number of element blocks")?;
    let total = c.size("the number of elements")?;
    c.size("the smallest element tag")?;
    c.size("the largest element tag")?;
    let mut out = Vec::new();
    for _ in 0..blocks {
        let at = c.mark();
        let d = dim(c)?;
        let entity = c.int("an entity tag")?;
        let number = c.int("an element type")?;
        let ty = elem_type(number)
            .ok_or_else(|| c.err_at(at, format!("unknown element type {number}")))?;
        if ty.dim != d {
            return Err(c.err_at(
                at,
                format!(
                    "element type {number} ({}) has dimension {}, its block's entity {d}",
                    ty.name, ty.dim
                ),
            ));
        }
        let n = c.size("the number of elements in the block")?;
        for _ in 0..n {
            let pos = c.begin_record();
            let t = tag(c, "element tag")?;
            let mut nodes = Vec::with_capacity(ty.nodes);
            for _ in 0..ty.nodes {
                nodes.push(tag(c, "node tag")?);
            }
            c.record_end(pos, &format!("element {t} ({})", ty.name))?;
            out.push(RawElem {
                tag: t,
                ty,
                owner: Owner::Entity(entity),
                nodes,
                pos,
            });
        }
    }
    if out.len() as u64 != total {
        return Err(c.err_at(
            head,
            format!(
                "the header says {total} elements, the blocks hold {}",
                out.len()
            ),
        ));
    }
    c.expect_end("$Elements")?;
    Ok(out)
}
