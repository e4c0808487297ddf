//! Local coordinate systems (LS-DYNA Keyword Manual, Vol. I, `*DEFINE_COORDINATE_...`), read
//! for the fields that name one (CID):
//!
//! - `*DEFINE_COORDINATE_SYSTEM`: card 1 `CID XO YO ZO XL YL ZL CIDL`, card 2 `XP YP ZP`. The
//!   local x axis points from the origin O to L; P lies in the local x-y plane: `z = x × (P - O)`
//!   and `y = z × x`, each normalised.
//! - `*DEFINE_COORDINATE_VECTOR`: one card `CID XX YX ZX XV YV ZV NID`: x along (XX, YX, ZX),
//!   (XV, YV, ZV) in the local x-y plane, the axes built as above.
//! - `*DEFINE_COORDINATE_NODES`: `CID N1 N2 N3 FLAG DIR`, a system that follows three nodes;
//!   recorded, so that a field naming it gets a clear error (it is not supported).
//!
//! - `*DEFINE_VECTOR`: one card `VID XT YT ZT XH YH ZH CID`, the direction from the tail T to
//!   the head H (in system CID, if given), for the VID of a prescribed motion (DOF 4 and 8).
//!
//! CIDL (points given in another local system) and NID (a system that turns with a node) must
//! be blank. A system whose points span no plane is an error only where a field names it (an
//! unused one changes nothing). Where a system is used is the build's business (`build::conditions`): a
//! concentrated load acts along its axes; other CID fields accept a system whose axes are the
//! global ones (what ANSYS Workbench writes for its loads).

use cleave_core::math::{cross, norm, scale, sub, Vec3};

use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{RawDeck, RawFrame, RawVector};

/// The unit axes (rows: local x, y, z in global components) of the system whose x axis is
/// along `x` and whose x-y plane holds `v`; `None` where they do not span a plane.
pub fn axes(x: Vec3, v: Vec3) -> Option<[Vec3; 3]> {
    let z = cross(x, v);
    let (lx, lz) = (norm(x), norm(z));
    // `v` parallel to `x` (to round-off of the inputs): no plane
    if !(lx > 0.0 && lz > 1e-12 * lx * norm(v) && lz.is_finite()) {
        return None;
    }
    let (ex, ez) = (scale(x, 1.0 / lx), scale(z, 1.0 / lz));
    Some([ex, cross(ez, ex), ez])
}

fn point(c: &Card<'_>, first: usize, names: [&str; 3]) -> Result<Vec3, DeckError> {
    Ok([
        c.f64_or(first, names[0], 0.0)?,
        c.f64_or(first + 1, names[1], 0.0)?,
        c.f64_or(first + 2, names[2], 0.0)?,
    ])
}

fn blank(c: &Card<'_>, i: usize, name: &str, what: &str) -> Result<(), DeckError> {
    match c.ref_id(i, name)? {
        None => Ok(()),
        Some(id) => Err(c.field_err(
            name,
            format!("{id}: {what} is not supported; leave it blank"),
        )),
    }
}

fn push(
    r: &Reader<'_>,
    c: &Card<'_>,
    deck: &mut RawDeck,
    axes: Result<[Vec3; 3], &'static str>,
) -> Result<(), DeckError> {
    deck.frames.push(RawFrame {
        src: r.src(c.line),
        id: c.id(0, "CID")?,
        axes,
    });
    Ok(())
}

/// Why a system built from points has no axes.
const NO_PLANE: &str = "has a zero x axis or its plane point on the x axis";

/// `*DEFINE_COORDINATE_SYSTEM`, two cards per system.
pub fn system(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let o = point(&c, 1, ["XO", "YO", "ZO"])?;
        let l = point(&c, 4, ["XL", "YL", "ZL"])?;
        blank(&c, 7, "CIDL", "points in another local system")?;
        let c2 = r.required(W10, "XP YP ZP")?;
        let p = point(&c2, 0, ["XP", "YP", "ZP"])?;
        push(r, &c, deck, axes(sub(l, o), sub(p, o)).ok_or(NO_PLANE))?;
    }
    Ok(())
}

/// `*DEFINE_COORDINATE_VECTOR`, one card per system.
pub fn vector(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let x = point(&c, 1, ["XX", "YX", "ZX"])?;
        let v = point(&c, 4, ["XV", "YV", "ZV"])?;
        blank(&c, 7, "NID", "a system that turns with a node")?;
        push(r, &c, deck, axes(x, v).ok_or(NO_PLANE))?;
    }
    Ok(())
}

/// `*DEFINE_VECTOR`, one card per vector: its unit direction (turned to global axes by its
/// CID at the build); a vector of zero length is an error.
pub fn direction(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let t = point(&c, 1, ["XT", "YT", "ZT"])?;
        let h = point(&c, 4, ["XH", "YH", "ZH"])?;
        let d = sub(h, t);
        let l = norm(d);
        if !(l > 0.0 && l.is_finite()) {
            return Err(c.field_err(
                "XH",
                "the head (XH, YH, ZH) is the tail (XT, YT, ZT): the vector has no direction",
            ));
        }
        deck.vectors.push(RawVector {
            src: r.src(c.line),
            id: c.id(0, "VID")?,
            dir: d.map(|x| x / l),
            cid: c.ref_id(7, "CID")?,
        });
    }
    Ok(())
}

/// `*DEFINE_COORDINATE_NODES`, one card per system: recorded by id only.
pub fn nodes(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        push(
            r,
            &c,
            deck,
            Err("follows nodes (*DEFINE_COORDINATE_NODES), which is not supported; use *DEFINE_COORDINATE_SYSTEM or _VECTOR"),
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_are_right_handed_and_unit() {
        let a = axes([2.0, 2.0, 0.0], [0.0, 5.0, 0.0]).unwrap();
        let s = 0.5f64.sqrt();
        let expect = [[s, s, 0.0], [-s, s, 0.0], [0.0, 0.0, 1.0]];
        for (r, e) in a.iter().zip(&expect) {
            for (x, y) in r.iter().zip(e) {
                assert!((x - y).abs() < 1e-15, "{a:?}");
            }
        }
        assert!(axes([1.0, 0.0, 0.0], [3.0, 0.0, 0.0]).is_none());
        assert!(axes([0.0; 3], [0.0, 1.0, 0.0]).is_none());
    }
}
