//! Initial and boundary conditions and body loads (LS-DYNA Keyword Manual, Vol. I):
//! `*INITIAL_VELOCITY_GENERATION`, `*INITIAL_VELOCITY_NODE`, `*BOUNDARY_SPC_{NODE,SET}`,
//! `*BOUNDARY_PRESCRIBED_MOTION_{NODE,SET,RIGID}`, `*LOAD_BODY_{X,Y,Z}`.

use cleave_core::model::{Vad, Window};

use super::control::warn_ignored;
use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{
    GlobalFrameUse, RawBodyLoad, RawDeck, RawDof, RawInitVel, RawMotion, RawNodeLoad, RawPressure,
    RawSpc, Target,
};

/// A coordinate-system field (CID, ICID) that cleave reads in global axes: blank, 0, or a
/// system whose axes are the global ones (checked in the build, where every system is known).
fn global_only(
    r: &Reader<'_>,
    c: &Card<'_>,
    i: usize,
    name: &'static str,
    deck: &mut RawDeck,
) -> Result<(), DeckError> {
    if let Some(cid) = c.ref_id(i, name)? {
        deck.global_frames.push(GlobalFrameUse {
            src: r.src(c.line),
            field: name,
            cid,
        });
    }
    Ok(())
}

/// `*INITIAL_VELOCITY_GENERATION`, pairs of cards:
/// card 1 `ID STYP OMEGA VX VY VZ IVATN ICID` (STYP 1 part set, 2 part, 3 node set; ID 0: all
/// nodes); card 2 `XC YC ZC NX NY NZ PHASE IRIGID`. The velocity of a node at x is
/// (VX, VY, VZ) + OMEGA n x (x - c), n the unit vector along (NX, NY, NZ).
pub fn velocity_generation(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let id = c.ref_id(0, "ID")?;
        let styp = match c.opt_i64(1, "STYP")? {
            Some(v @ 1..=3) => v,
            Some(v) => {
                return Err(c.field_err(
                    "STYP",
                    format!("{v} is not one of 1 (part set), 2 (part), 3 (node set)"),
                ))
            }
            None => return Err(c.field_err("STYP", "missing (1 part set, 2 part, 3 node set)")),
        };
        let target = match (id, styp) {
            (None, _) => Target::All,
            (Some(i), 1) => Target::PartSet(i),
            (Some(i), 2) => Target::Part(i),
            (Some(i), _) => Target::NodeSet(i),
        };
        let omega = c.f64_or(2, "OMEGA", 0.0)?;
        let v = [
            c.f64_or(3, "VX", 0.0)?,
            c.f64_or(4, "VY", 0.0)?,
            c.f64_or(5, "VZ", 0.0)?,
        ];
        warn_ignored(
            &c,
            6,
            "IVATN",
            "slave nodes of rigid bodies are treated as any node",
            deck,
        )?;
        global_only(r, &c, 7, "ICID", deck)?;
        let c2 = r.required(W10, "XC YC ZC NX NY NZ PHASE IRIGID")?;
        let centre = [
            c2.f64_or(0, "XC", 0.0)?,
            c2.f64_or(1, "YC", 0.0)?,
            c2.f64_or(2, "ZC", 0.0)?,
        ];
        let axis = [
            c2.f64_or(3, "NX", 0.0)?,
            c2.f64_or(4, "NY", 0.0)?,
            c2.f64_or(5, "NZ", 0.0)?,
        ];
        let len = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        if omega != 0.0 && (len == 0.0 || !len.is_finite()) {
            return Err(c2.field_err(
                "NX",
                "OMEGA is not zero but the rotation axis (NX, NY, NZ) is zero",
            ));
        }
        let axis = if len > 0.0 && len.is_finite() {
            [axis[0] / len, axis[1] / len, axis[2] / len]
        } else {
            [0.0; 3]
        };
        warn_ignored(&c2, 6, "PHASE", "velocities are set at time 0", deck)?;
        warn_ignored(
            &c2,
            7,
            "IRIGID",
            "rigid parts take the nodal velocities",
            deck,
        )?;
        deck.init_vel.push(RawInitVel {
            src: r.src(c.line),
            target,
            omega,
            v,
            centre,
            axis,
        });
    }
    Ok(())
}

/// `*INITIAL_VELOCITY_NODE`: one card per node, `NID VX VY VZ VXR VYR VZR` (rotations ignored:
/// solid nodes have none).
pub fn velocity_node(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let nid = c.id(0, "NID")?;
        let v = [
            c.f64_or(1, "VX", 0.0)?,
            c.f64_or(2, "VY", 0.0)?,
            c.f64_or(3, "VZ", 0.0)?,
        ];
        for (i, name) in [(4, "VXR"), (5, "VYR"), (6, "VZR")] {
            warn_ignored(&c, i, name, "solid nodes have no rotations", deck)?;
        }
        deck.init_vel.push(RawInitVel {
            src: r.src(c.line),
            target: Target::Node(nid),
            omega: 0.0,
            v,
            centre: [0.0; 3],
            axis: [0.0; 3],
        });
    }
    Ok(())
}

/// `*INITIAL_VELOCITY`: card 1 `NSID NSIDEX BOXID IRIGID ICID` (NSID blank or 0: every
/// node), card 2 `VX VY VZ VXR VYR VZR` (rotations ignored: solid nodes have none). An exempted
/// set NSIDEX, a box BOXID and a local system ICID are errors (the velocity would go where
/// cleave cannot tell); IRIGID warns.
pub fn velocity(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    // the first card 1 may be blank (every node); further pairs start at a non-blank line
    let mut first = true;
    loop {
        let c = if first {
            r.next(W10)?
        } else {
            r.next_nonblank(W10)?
        };
        let Some(c) = c else { break };
        first = false;
        let target = match c.ref_id(0, "NSID")? {
            Some(id) => Target::NodeSet(id),
            None => Target::All,
        };
        for (i, name, what) in [(1, "NSIDEX", "an exempted node set"), (2, "BOXID", "a box")] {
            if let Some(id) = c.ref_id(i, name)? {
                return Err(c.field_err(
                    name,
                    format!("{id}: {what} is not supported; leave it blank"),
                ));
            }
        }
        warn_ignored(
            &c,
            3,
            "IRIGID",
            "rigid parts take their nodes' velocities",
            deck,
        )?;
        global_only(r, &c, 4, "ICID", deck)?;
        let v_card = r.required(W10, "VX VY VZ VXR VYR VZR")?;
        let v = [
            v_card.f64_or(0, "VX", 0.0)?,
            v_card.f64_or(1, "VY", 0.0)?,
            v_card.f64_or(2, "VZ", 0.0)?,
        ];
        for (i, name) in [(3, "VXR"), (4, "VYR"), (5, "VZR")] {
            warn_ignored(&v_card, i, name, "solid nodes have no rotations", deck)?;
        }
        deck.init_vel.push(RawInitVel {
            src: r.src(c.line),
            target,
            omega: 0.0,
            v,
            centre: [0.0; 3],
            axis: [0.0; 3],
        });
    }
    Ok(())
}

/// `*BOUNDARY_SPC_NODE` / `_SET`: one card each, `NID|NSID CID DOFX DOFY DOFZ DOFRX DOFRY
/// DOFRZ` (each DOF 0 free, 1 fixed; CID blank or a system with the global axes).
pub fn spc(r: &mut Reader<'_>, deck: &mut RawDeck, set: bool) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let id = c.id(0, if set { "NSID" } else { "NID" })?;
        global_only(r, &c, 1, "CID", deck)?;
        let mut dof = [false; 6];
        for (k, name) in ["DOFX", "DOFY", "DOFZ", "DOFRX", "DOFRY", "DOFRZ"]
            .iter()
            .enumerate()
        {
            dof[k] = c.code(2 + k, name, 0, 0, 1)? == 1;
        }
        deck.spcs.push(RawSpc {
            src: r.src(c.line),
            target: if set {
                Target::NodeSet(id)
            } else {
                Target::Node(id)
            },
            dof,
        });
    }
    Ok(())
}

/// `*BOUNDARY_PRESCRIBED_MOTION_{NODE,SET,RIGID}`: one card each,
/// `ID DOF VAD LCID SF VID DEATH BIRTH`. ID is a node, node set or (rigid) part id; DOF 1, 2,
/// 3 (x, y, z), 4 (along `*DEFINE_VECTOR` VID, the motion normal to it free) and -4 (normal
/// motion held at zero); on rigid bodies also 5, 6, 7 (angular velocity about x, y, z through
/// the centre of mass), 8 and -8 (about VID; -8 holds the other rotations); VAD 0 velocity, 2
/// displacement (translations only); SF blank or 0 means 1; DEATH (blank, 0 or 1e28: never)
/// and BIRTH bound when it acts ([`Window`]; a birth time only with VAD 0). (LS-DYNA Keyword
/// Manual, `*BOUNDARY_PRESCRIBED_MOTION`.)
pub fn prescribed(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    // the variant, without the `_ID` or `_TITLE` option
    let kw = r.keyword.trim_end_matches("_ID").trim_end_matches("_TITLE");
    while let Some(c) = r.next_nonblank(W10)? {
        let (name, mk): (&str, fn(i64) -> Target) = if kw.ends_with("_SET") {
            ("NSID", Target::NodeSet)
        } else if kw.ends_with("_RIGID") {
            ("PID", Target::Part)
        } else {
            ("NID", Target::Node)
        };
        let id = c.id(0, name)?;
        let rigid = kw.ends_with("_RIGID");
        let vid = || -> Result<i64, DeckError> {
            c.ref_id(5, "VID")?.ok_or_else(|| {
                c.field_err(
                    "VID",
                    "missing: DOF 4 and 8 move along a vector (*DEFINE_VECTOR)",
                )
            })
        };
        let dof = match c.opt_i64(1, "DOF")? {
            Some(v @ 1..=3) => RawDof::Axis(v as usize - 1),
            Some(v @ (4 | -4)) => RawDof::Vector {
                vid: vid()?,
                only: v < 0,
                rotation: false,
            },
            Some(v @ (5..=7 | 8 | -8)) if rigid => match v {
                5..=7 => RawDof::Rotation(v as usize - 5),
                _ => RawDof::Vector {
                    vid: vid()?,
                    only: v < 0,
                    rotation: true,
                },
            },
            Some(v @ (5..=8 | -8)) => {
                return Err(c.field_err(
                    "DOF",
                    format!("{v}: a rotation, and the nodes of solid elements have no rotational degrees of freedom (rotate a rigid body: *BOUNDARY_PRESCRIBED_MOTION_RIGID)"),
                ))
            }
            Some(v) => {
                return Err(c.field_err(
                    "DOF",
                    format!("{v} not supported: 1-3 (x, y, z), 4 and -4 (along VID), and on rigid bodies 5-7 (rotation about x, y, z), 8 and -8 (about VID)"),
                ))
            }
            None => return Err(c.field_err("DOF", "missing (1, 2 or 3)")),
        };
        let vad = match c.i64_or(2, "VAD", 0)? {
            0 => Vad::Velocity,
            2 => Vad::Displacement,
            v => {
                return Err(c.field_err(
                    "VAD",
                    format!("{v} not supported (0: velocity, 2: displacement)"),
                ))
            }
        };
        let rotates = matches!(
            dof,
            RawDof::Rotation(_) | RawDof::Vector { rotation: true, .. }
        );
        if rotates && vad == Vad::Displacement {
            return Err(c.field_err(
                "VAD",
                "2 (an angle) for a rotation is not supported: give the angular velocity (VAD 0)",
            ));
        }
        let lcid = c.id(3, "LCID")?;
        let sf = c.f64_nz(4, "SF", 1.0)?;
        // DEATH blank or 0: never (LS-DYNA's default 1e28)
        let death = match c.f64_or(6, "DEATH", 0.0)? {
            d if d == 0.0 || d >= 1e28 => f64::INFINITY,
            d => d,
        };
        let birth = c.f64_or(7, "BIRTH", 0.0)?;
        if !(birth >= 0.0 && birth < death) {
            return Err(c.field_err(
                "BIRTH",
                format!("{birth}: the birth time must be at least 0 and before DEATH"),
            ));
        }
        if birth > 0.0 && vad == Vad::Displacement {
            return Err(c.field_err(
                "BIRTH",
                "a displacement (VAD 2) from a birth time is not supported (from where it is measured then is not settled): give a velocity (VAD 0) or no BIRTH",
            ));
        }
        deck.motions.push(RawMotion {
            src: r.src(c.line),
            target: mk(id),
            window: Window { birth, death },
            dof,
            vad,
            lcid,
            sf,
        });
    }
    Ok(())
}

/// `*LOAD_BODY_{X,Y,Z}`: `LCID SF LCIDDR XC YC ZC CID`. LCID 0: a constant 1; SF blank or 0
/// means 1.
pub fn body(r: &mut Reader<'_>, deck: &mut RawDeck, axis: usize) -> Result<(), DeckError> {
    let c = r.required(W10, "LCID SF")?;
    let lcid = c.ref_id(0, "LCID")?;
    let sf = c.f64_nz(1, "SF", 1.0)?;
    warn_ignored(&c, 2, "LCIDDR", "dynamic relaxation is not supported", deck)?;
    global_only(r, &c, 6, "CID", deck)?;
    deck.body_loads.push(RawBodyLoad {
        src: r.src(c.line),
        axis,
        lcid,
        sf,
    });
    Ok(())
}

/// `*LOAD_NODE_POINT` / `*LOAD_NODE_SET`: one card each, `NID|NSID DOF LCID SF CID M1 M2 M3`:
/// the force `SF * curve(t)` along DOF 1, 2 or 3 (x, y, z) on the node, or on each node of the
/// set. LCID is required; SF blank or 0 means 1. With a CID the DOF is the local system's axis
/// (`*DEFINE_COORDINATE_...`). DOF 4 (a follower force) and 5 to 8 (moments) are errors (solid
/// elements have no rotations).
pub fn node_load(r: &mut Reader<'_>, deck: &mut RawDeck, set: bool) -> Result<(), DeckError> {
    let what = if set { "NSID" } else { "NID" };
    while let Some(c) = r.next_nonblank(W10)? {
        let id = c.id(0, what)?;
        let dof = c.i64_or(1, "DOF", 0)?;
        let axis = match dof {
            1..=3 => dof as usize - 1,
            v => {
                return Err(c.field_err(
                    "DOF",
                    format!("{v}: only forces along x, y or z (DOF 1, 2, 3) act on solids"),
                ))
            }
        };
        let lcid = c.id(2, "LCID")?;
        let sf = c.f64_nz(3, "SF", 1.0)?;
        let cid = c.ref_id(4, "CID")?;
        deck.node_loads.push(RawNodeLoad {
            src: r.src(c.line),
            id,
            set,
            axis,
            cid,
            lcid,
            sf,
        });
    }
    Ok(())
}

/// `*LOAD_SEGMENT`: one card per segment, `LCID SF AT N1 N2 N3 N4` (N5..N8 of quadratic
/// segments must be blank; a triangle repeats N3 as N4): the pressure `SF * curve(t)` from the
/// birth time AT on, pushing against the segment's normal by the right-hand rule N1 N2 N3.
/// SF blank or 0 means 1.
pub fn segment_load(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let lcid = c.id(0, "LCID")?;
        let sf = c.f64_nz(1, "SF", 1.0)?;
        let at = c.f64_or(2, "AT", 0.0)?;
        let mut seg = [0i64; 4];
        for (k, n) in seg.iter_mut().enumerate() {
            *n = c.id(3 + k, &format!("N{}", k + 1))?;
        }
        for k in 4..8 {
            if c.ref_id(3 + k, &format!("N{}", k + 1))?.is_some() {
                return Err(c.field_err(
                    &format!("N{}", k + 1),
                    "quadratic segments are not supported; leave N5..N8 blank",
                ));
            }
        }
        deck.pressures.push(RawPressure {
            src: r.src(c.line),
            segment: Some(seg),
            ssid: None,
            lcid,
            sf,
            at,
        });
    }
    Ok(())
}

/// `*LOAD_SEGMENT_SET`: one card per set, `SSID LCID SF AT`: the pressure of `*LOAD_SEGMENT` on
/// every segment of the set.
pub fn segment_set_load(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let ssid = c.id(0, "SSID")?;
        let lcid = c.id(1, "LCID")?;
        let sf = c.f64_nz(2, "SF", 1.0)?;
        let at = c.f64_or(3, "AT", 0.0)?;
        deck.pressures.push(RawPressure {
            src: r.src(c.line),
            segment: None,
            ssid: Some(ssid),
            lcid,
            sf,
            at,
        });
    }
    Ok(())
}
