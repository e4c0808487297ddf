//! `*RIGIDWALL_PLANAR` (`_FINITE`, `_ID`) and `*CONTACT_AUTOMATIC_{SINGLE_SURFACE,SURFACE_TO_SURFACE}`
//! (LS-DYNA Keyword Manual, Vol. I).

use cleave_core::math::Vec3;
use cleave_core::math::{dot, norm, scale, sub};
use cleave_core::model::{WallExtent, WallShape};

use super::control::warn_ignored;
use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{RawContact, RawDeck, RawSurface, RawWall};

/// Errors if field `i` holds a non-zero id (a feature that is not supported).
fn must_be_blank(c: &Card<'_>, i: usize, name: &str, what: &str) -> Result<(), DeckError> {
    if c.f64_or(i, name, 0.0)? != 0.0 {
        return Err(c.field_err(name, format!("{what} not supported; leave it blank")));
    }
    Ok(())
}

/// `*RIGIDWALL_PLANAR`, `_ID` and `_FINITE`: with `_ID` a first card `RWID HEADING` (read
/// past: rwforc.csv numbers the walls in deck order); card 1 `NSID NSIDEX BOXID OFFSET BIRTH
/// DEATH RWKSF` (NSID 0: every node); card 2 `XT YT ZT XH YH ZH FRIC WVEL`; with `_FINITE` a
/// card `XHEV YHEV ZHEV LENL LENM`: the edge vector l from the tail to (XHEV, YHEV, ZHEV)
/// (its part along the normal dropped), the wall covering LENL along l and LENM along n x l.
/// The wall is a fixed stonewall whose normal points from tail to head. The options `_ORTHO`
/// (orthotropic friction), `_MOVING` (a wall with mass) and `_FORCES` (force segments) are
/// errors naming them.
pub fn rigidwall_planar(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let kw = r.keyword.trim_end_matches("_TITLE");
    let (kw, titled) = match kw.strip_suffix("_ID") {
        Some(k) => (k, true),
        None => (kw, false),
    };
    let finite = match kw.strip_prefix("*RIGIDWALL_PLANAR").unwrap_or(kw) {
        "" => false,
        "_FINITE" => true,
        other => {
            let what = if other.contains("MOVING") {
                "a moving wall with a mass (_MOVING)"
            } else if other.contains("ORTHO") {
                "orthotropic friction (_ORTHO)"
            } else if other.contains("FORCES") {
                "wall force segments (_FORCES)"
            } else {
                "this option"
            };
            return Err(r.error_at_keyword(format!(
                "{what} is not supported (cleave reads *RIGIDWALL_PLANAR with _FINITE and _ID)"
            )));
        }
    };
    if titled {
        r.title()?;
    }
    let c = r.required(W10, "NSID NSIDEX BOXID OFFSET BIRTH DEATH RWKSF")?;
    let nsid = wall_nodes(&c, 4)?;
    warn_ignored(
        &c,
        3,
        "OFFSET",
        "nodes are captured at the wall plane",
        deck,
    )?;
    warn_ignored(&c, 6, "RWKSF", "the wall is a kinematic constraint", deck)?;
    let c2 = r.required(W10, "XT YT ZT XH YH ZH FRIC WVEL")?;
    let (tail, head, fric) = wall_points(&c2)?;
    warn_ignored(&c2, 7, "WVEL", "wall failure is not modelled", deck)?;
    let extent = if finite {
        let c3 = r.required(W10, "XHEV YHEV ZHEV LENL LENM")?;
        Some(finite_extent(&c3, tail, head)?)
    } else {
        None
    };
    deck.walls.push(RawWall {
        src: r.src(c.line),
        nsid,
        tail,
        head,
        fric,
        extent,
        shape: WallShape::Plane,
        motion: None,
    });
    Ok(())
}

/// The rectangle of a finite plane from its card `XHEV YHEV ZHEV LENL LENM`: l from the tail
/// towards (XHEV, YHEV, ZHEV), less its part along the normal, as a unit vector.
fn finite_extent(c3: &Card<'_>, tail: Vec3, head: Vec3) -> Result<WallExtent, DeckError> {
    let hev = [
        c3.f64_or(0, "XHEV", 0.0)?,
        c3.f64_or(1, "YHEV", 0.0)?,
        c3.f64_or(2, "ZHEV", 0.0)?,
    ];
    let len_l = length(c3, 3, "LENL")?;
    let len_m = length(c3, 4, "LENM")?;
    let d = sub(head, tail);
    let n = scale(d, 1.0 / norm(d));
    let e = sub(hev, tail);
    let l = sub(e, scale(n, dot(e, n)));
    let ll = norm(l);
    if ll.is_nan() || ll <= 1e-9 * norm(e).max(norm(d)) {
        return Err(c3.field_err(
            "XHEV",
            "the edge vector from the tail to (XHEV, YHEV, ZHEV) is zero or along the wall's normal",
        ));
    }
    Ok(WallExtent {
        l: l.map(|x| x / ll),
        len_l,
        len_m,
    })
}

/// A rigid wall's first card, `NSID NSIDEX BOXID` and BIRTH, DEATH at `birth` and `birth + 1`:
/// NSID (blank: every node); an exclusion set, a box, a birth or a death time are errors.
fn wall_nodes(c: &Card<'_>, birth: usize) -> Result<Option<i64>, DeckError> {
    let nsid = c.ref_id(0, "NSID")?;
    must_be_blank(c, 1, "NSIDEX", "an exclusion node set is")?;
    must_be_blank(c, 2, "BOXID", "a box is")?;
    must_be_blank(c, birth, "BIRTH", "a birth time is")?;
    let death = c.f64_or(birth + 1, "DEATH", 0.0)?;
    if death != 0.0 && death < 1.0e20 {
        return Err(c.field_err("DEATH", "a death time is not supported; leave it blank"));
    }
    Ok(nsid)
}

/// The tail, head and FRIC card of a rigid wall (`XT YT ZT XH YH ZH FRIC ...`): the head must
/// differ from the tail and FRIC must not be negative.
fn wall_points(c2: &Card<'_>) -> Result<(Vec3, Vec3, f64), DeckError> {
    let tail = [
        c2.f64_or(0, "XT", 0.0)?,
        c2.f64_or(1, "YT", 0.0)?,
        c2.f64_or(2, "ZT", 0.0)?,
    ];
    let head = [
        c2.f64_or(3, "XH", 0.0)?,
        c2.f64_or(4, "YH", 0.0)?,
        c2.f64_or(5, "ZH", 0.0)?,
    ];
    if tail == head {
        return Err(c2.field_err(
            "XH",
            "the head (XH, YH, ZH) equals the tail (XT, YT, ZT): the wall has no normal",
        ));
    }
    let fric = c2.f64_or(6, "FRIC", 0.0)?;
    if fric < 0.0 {
        return Err(c2.field_err("FRIC", format!("{fric} must not be negative")));
    }
    Ok((tail, head, fric))
}

/// A positive, finite length field.
fn length(c: &Card<'_>, i: usize, name: &str) -> Result<f64, DeckError> {
    let v = c.f64_or(i, name, 0.0)?;
    if !(v > 0.0 && v.is_finite()) {
        return Err(c.field_err(name, format!("{v}: must be positive")));
    }
    Ok(v)
}

/// `*RIGIDWALL_GEOMETRIC_{FLAT,SPHERE,CYLINDER}` with the options `_MOTION`, `_DISPLAY` and
/// `_ID`: (with `_ID` a card `RWID HEADING`, read past) card 1 `NSID NSIDEX BOXID BIRTH
/// DEATH`; card 2 `XT YT ZT XH YH ZH FRIC`; the shape's card: FLAT `XHEV YHEV ZHEV LENL LENM`
/// (as `*RIGIDWALL_PLANAR_FINITE`), SPHERE `RADSPH` (about the tail), CYLINDER `RADCYL LENCYL`
/// (about the axis from the tail towards the head; LENCYL 0 or blank: infinite); `_MOTION`:
/// `LCID OPT VX VY VZ`, the wall translated along (VX, VY, VZ) by the curve, a velocity (OPT
/// 0) or a displacement (OPT 1); `_DISPLAY`: `PID RO E PR`, read past (a picture only). Nodes
/// stay out of the body. PRISM is an error naming it.
pub fn rigidwall_geometric(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let kw = r.keyword.trim_end_matches("_TITLE");
    let rest = kw.strip_prefix("*RIGIDWALL_GEOMETRIC_").unwrap_or("");
    let mut words = rest.split('_');
    let kind = words.next().unwrap_or("");
    let (mut motion, mut display, mut titled) = (false, false, false);
    for w in words {
        match w {
            "MOTION" => motion = true,
            "DISPLAY" => display = true,
            "ID" => titled = true,
            other => {
                return Err(r.error_at_keyword(format!(
                    "the option _{other} is not supported (cleave reads _MOTION, _DISPLAY and _ID)"
                )))
            }
        }
    }
    if !matches!(kind, "FLAT" | "SPHERE" | "CYLINDER") {
        return Err(r.error_at_keyword(format!(
            "{}: cleave reads the geometric walls FLAT, SPHERE and CYLINDER",
            if kind == "PRISM" {
                "a prism wall is not supported"
            } else {
                "unknown shape"
            }
        )));
    }
    if titled {
        r.title()?;
    }
    let c = r.required(W10, "NSID NSIDEX BOXID BIRTH DEATH")?;
    let nsid = wall_nodes(&c, 3)?;
    let c2 = r.required(W10, "XT YT ZT XH YH ZH FRIC")?;
    let (tail, head, fric) = wall_points(&c2)?;
    let mut extent = None;
    let shape = match kind {
        "FLAT" => {
            let c3 = r.required(W10, "XHEV YHEV ZHEV LENL LENM")?;
            extent = Some(finite_extent(&c3, tail, head)?);
            WallShape::Plane
        }
        "SPHERE" => {
            let c3 = r.required(W10, "RADSPH")?;
            WallShape::Sphere {
                radius: length(&c3, 0, "RADSPH")?,
            }
        }
        _ => {
            let c3 = r.required(W10, "RADCYL LENCYL")?;
            let len = c3.f64_or(1, "LENCYL", 0.0)?;
            if len.is_nan() || len < 0.0 {
                return Err(c3.field_err("LENCYL", format!("{len} must not be negative")));
            }
            WallShape::Cylinder {
                radius: length(&c3, 0, "RADCYL")?,
                length: if len == 0.0 { f64::INFINITY } else { len },
            }
        }
    };
    let motion = if motion {
        let c4 = r.required(W10, "LCID OPT VX VY VZ")?;
        let lcid = c4.id(0, "LCID")?;
        let displacement = match c4.i64_or(1, "OPT", 0)? {
            0 => false,
            1 => true,
            v => return Err(c4.field_err("OPT", format!("{v}: 0 (velocity) or 1 (displacement)"))),
        };
        let d = [
            c4.f64_or(2, "VX", 0.0)?,
            c4.f64_or(3, "VY", 0.0)?,
            c4.f64_or(4, "VZ", 0.0)?,
        ];
        let l = norm(d);
        if !(l > 0.0 && l.is_finite()) {
            return Err(c4.field_err("VX", "the direction (VX, VY, VZ) is zero"));
        }
        Some((lcid, displacement, d.map(|x| x / l)))
    } else {
        None
    };
    if display {
        r.ignore(1);
    }
    deck.walls.push(RawWall {
        src: r.src(c.line),
        nsid,
        tail,
        head,
        fric,
        extent,
        shape,
        motion,
    });
    Ok(())
}

fn surface(
    c: &Card<'_>,
    id_field: usize,
    typ_field: usize,
    names: [&'static str; 2],
) -> Result<RawSurface, DeckError> {
    let id = c.ref_id(id_field, names[0])?;
    let typ = c.i64_or(typ_field, names[1], 0)?;
    if !matches!(typ, 0 | 2 | 3) {
        return Err(c.field_err(
            names[1],
            format!("{typ} not supported (0 segment set, 2 part set, 3 part)"),
        ));
    }
    Ok(RawSurface {
        id,
        typ: typ as i32,
        field: names[0],
    })
}

/// `*CONTACT_AUTOMATIC_SINGLE_SURFACE` / `_SURFACE_TO_SURFACE` / `_NODES_TO_SURFACE`
/// (`one_way`: only the slave side's nodes are checked against the master side's faces): card 1
/// `SSID MSID SSTYP MSTYP SBOXID MBOXID SPR MPR` (types 0 segment set, 2 part set, 3 part; id
/// 0: everything; a nodes-to-surface slave given as parts or segments stands for their surface
/// nodes, as only those can touch; a node set, SSTYP 4, for the exterior faces whose nodes are
/// all in it, `build::conditions`); optional
/// card 2 `FS FD DC VC VDC PENCHK BT DT` (blank: 0); further optional cards ignored.
pub fn contact(
    r: &mut Reader<'_>,
    deck: &mut RawDeck,
    single_surface: bool,
    one_way: bool,
) -> Result<(), DeckError> {
    contact_cards(r, deck, single_surface, one_way, false)
}

/// `*CONTACT_TIED_SURFACE_TO_SURFACE` / `*CONTACT_TIED_NODES_TO_SURFACE`: card 1 as for the
/// automatic contacts, the slave side also a node set (SSTYP 4); the friction card and the
/// further ones are not used (a tied node does not slide).
pub fn tied(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    contact_cards(r, deck, false, true, true)
}

fn contact_cards(
    r: &mut Reader<'_>,
    deck: &mut RawDeck,
    single_surface: bool,
    one_way: bool,
    tied: bool,
) -> Result<(), DeckError> {
    let c = r.required(W10, "SSID MSID SSTYP MSTYP SBOXID MBOXID SPR MPR")?;
    let slave = if (tied || one_way) && c.i64_or(2, "SSTYP", 0)? == 4 {
        RawSurface {
            id: Some(c.id(0, "SSID")?),
            typ: 4,
            field: "SSID",
        }
    } else {
        surface(&c, 0, 2, ["SSID", "SSTYP"])?
    };
    let master = if single_surface {
        warn_ignored(
            &c,
            1,
            "MSID",
            "a single-surface contact has no master side",
            deck,
        )?;
        None
    } else {
        Some(surface(&c, 1, 3, ["MSID", "MSTYP"])?)
    };
    must_be_blank(&c, 4, "SBOXID", "a box is")?;
    must_be_blank(&c, 5, "MBOXID", "a box is")?;
    let (mut fs, mut fd, mut dc) = (0.0, 0.0, 0.0);
    if let Some(c2) = r.next(W10).map(|c| c.filter(|_| !tied))? {
        fs = c2.f64_or(0, "FS", 0.0)?;
        fd = c2.f64_or(1, "FD", 0.0)?;
        dc = c2.f64_or(2, "DC", 0.0)?;
        for (v, name) in [(fs, "FS"), (fd, "FD"), (dc, "DC")] {
            if v < 0.0 {
                return Err(c2.field_err(name, format!("{v} must not be negative")));
            }
        }
        warn_ignored(&c2, 3, "VC", "viscous friction is not modelled", deck)?;
        warn_ignored(&c2, 4, "VDC", "contact damping is not modelled", deck)?;
        warn_ignored(&c2, 6, "BT", "contact is active for the whole run", deck)?;
        let dt = c2.f64_or(7, "DT", 0.0)?;
        if dt != 0.0 && dt < 1.0e20 {
            warn_ignored(&c2, 7, "DT", "contact is active for the whole run", deck)?;
        }
    }
    r.ignore_rest();
    deck.contacts.push(RawContact {
        src: r.src(c.line),
        single_surface,
        one_way,
        tied,
        slave,
        master,
        fs,
        fd,
        dc,
    });
    Ok(())
}
