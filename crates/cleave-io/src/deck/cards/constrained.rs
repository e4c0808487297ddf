//! `*CONSTRAINED_NODAL_RIGID_BODY` (with its `_SPC` and `_INERTIA` options),
//! `*CONSTRAINED_EXTRA_NODES_NODE` / `_SET`, and the inertia cards they share with
//! `*PART_INERTIA` (LS-DYNA Keyword Manual, Vol. I).

use super::control::warn_ignored;
use super::Reader;
use crate::deck::error::DeckError;
use crate::deck::fields::{Card, W10};
use crate::deck::raw::{RawDeck, RawExtraNodes, RawInertia, RawNodalRigid};

/// Dispatches the `*CONSTRAINED_` keywords cleave reads; the others are errors (they tie,
/// weld or join: the physics would change without them).
pub fn constrained(r: &mut Reader<'_>, deck: &mut RawDeck) -> Result<(), DeckError> {
    let kw = r.keyword;
    match kw {
        "*CONSTRAINED_EXTRA_NODES_NODE" => extra_nodes(r, deck, false),
        "*CONSTRAINED_EXTRA_NODES_SET" => extra_nodes(r, deck, true),
        _ => match kw.strip_prefix("*CONSTRAINED_NODAL_RIGID_BODY") {
            Some(opts) => {
                let (spc, inertia) = match opts {
                    "" => (false, false),
                    "_SPC" => (true, false),
                    "_INERTIA" => (false, true),
                    "_SPC_INERTIA" | "_INERTIA_SPC" => (true, true),
                    _ => {
                        return Err(DeckError::at(
                            r.file,
                            r.line_of_keyword(),
                            Some(kw),
                            "option not supported (*CONSTRAINED_NODAL_RIGID_BODY takes _SPC and _INERTIA)",
                        ))
                    }
                };
                nodal_rigid_body(r, deck, spc, inertia)
            }
            None => Err(DeckError::at(
                r.file,
                r.line_of_keyword(),
                Some(kw),
                "keyword not supported (of the *CONSTRAINED_ keywords cleave reads *CONSTRAINED_NODAL_RIGID_BODY[_SPC][_INERTIA] and *CONSTRAINED_EXTRA_NODES_NODE / _SET)",
            )),
        },
    }
}

/// `*CONSTRAINED_NODAL_RIGID_BODY`: per body, card 1 `PID CID NSID PNODE IPRT DRFLAG RRFLAG`;
/// `_SPC`: card 2 `CMO CON1 CON2` (as `*MAT_RIGID`); `_INERTIA`: the cards `XC YC ZC TM NID`,
/// `IXX IXY IXZ IYY IYZ IZZ`, `VTX VTY VTZ VRX VRY VRZ` (the tensor in global axes).
///
/// CID (a local system for the body's output) warns, except with `_INERTIA`, where it would
/// turn the tensor: an error. IPRT (printing) warns. PNODE (a node LS-DYNA moves onto the
/// centre of mass), DRFLAG and RRFLAG (releasing degrees of freedom) are errors.
fn nodal_rigid_body(
    r: &mut Reader<'_>,
    deck: &mut RawDeck,
    spc: bool,
    inertia: bool,
) -> Result<(), DeckError> {
    while let Some(c) = r.next_nonblank(W10)? {
        let id = c.i64_or(0, "PID", 0)?;
        if id < 0 {
            return Err(c.field_err("PID", format!("{id} is not a valid id")));
        }
        let nsid = c.id(2, "NSID")?;
        if c.ref_id(1, "CID")?.is_some() {
            if inertia {
                return Err(c.field_err(
                    "CID",
                    "a local coordinate system for the inertia tensor is not supported; give the tensor in global axes and leave CID blank",
                ));
            }
            warn_ignored(
                &c,
                1,
                "CID",
                "output in a local system is not written",
                deck,
            )?;
        }
        if c.ref_id(3, "PNODE")?.is_some() {
            return Err(c.field_err(
                "PNODE",
                "a node placed at the centre of mass is not supported (cleave does not move nodes); leave it blank or put the node in NSID",
            ));
        }
        warn_ignored(&c, 4, "IPRT", "rigid body output is not written", deck)?;
        for (i, name) in [(5, "DRFLAG"), (6, "RRFLAG")] {
            if c.i64_or(i, name, 0)? != 0 {
                return Err(c.field_err(
                    name,
                    "releasing degrees of freedom of a nodal rigid body is not supported; leave it blank or 0",
                ));
            }
        }
        let (mut cmo, mut con1, mut con2) = (0, 0, 0);
        if spc {
            let s = r.required(W10, "CMO CON1 CON2")?;
            cmo = s.code(0, "CMO", 0, -1, 1)?;
            if cmo == -1 {
                return Err(s.field_err(
                    "CMO",
                    "-1 (constraints in a local system) is not supported; use 1 (global) or 0",
                ));
            }
            con1 = s.code(1, "CON1", 0, 0, 7)?;
            con2 = s.code(2, "CON2", 0, 0, 7)?;
        }
        let given = if inertia {
            Some(inertia_cards(r, false)?)
        } else {
            None
        };
        deck.nodal_rigid.push(RawNodalRigid {
            src: r.src(c.line),
            id,
            nsid,
            cmo,
            con1,
            con2,
            inertia: given,
        });
    }
    Ok(())
}

/// `*CONSTRAINED_EXTRA_NODES_NODE` / `_SET`: one card each, `PID NID|NSID IFLAG` (IFLAG 1:
/// with `*PART_INERTIA` on the part, the nodes' masses are added to the given ones).
fn extra_nodes(r: &mut Reader<'_>, deck: &mut RawDeck, set: bool) -> Result<(), DeckError> {
    let field = if set { "NSID" } else { "NID" };
    while let Some(c) = r.next_nonblank(W10)? {
        let pid = c.id(0, "PID")?;
        let id = c.id(1, field)?;
        let iflag = c.code(2, "IFLAG", 0, 0, 1)? == 1;
        deck.extra_nodes.push(RawExtraNodes {
            src: r.src(c.line),
            pid,
            id,
            set,
            iflag,
        });
    }
    Ok(())
}

/// The inertia cards: `XC YC ZC TM IRCS NODEID` (`XC YC ZC TM NID` without `ircs`),
/// `IXX IXY IXZ IYY IYZ IZZ`, `VTX VTY VTZ VRX VRY VRZ` and, with IRCS 1, `XL YL ZL XLIP YLIP
/// ZLIP CID`: the tensor is then given in the local axes x = XL, z = XL x XLIP, y = z x x
/// (CID, a `*DEFINE_COORDINATE_...`, is an error). TM must be positive and the tensor positive
/// definite. IXY, IXZ, IYZ are the tensor's components (products of inertia with their sign).
pub fn inertia_cards(r: &mut Reader<'_>, ircs: bool) -> Result<RawInertia, DeckError> {
    let c1 = r.required(W10, "XC YC ZC TM")?;
    let centre = [
        c1.f64_or(0, "XC", 0.0)?,
        c1.f64_or(1, "YC", 0.0)?,
        c1.f64_or(2, "ZC", 0.0)?,
    ];
    let mass = c1.positive(3, "TM")?;
    let (irc, node) = if ircs {
        (c1.code(4, "IRCS", 0, 0, 1)?, c1.ref_id(5, "NODEID")?)
    } else {
        (0, c1.ref_id(4, "NID")?)
    };
    let c2 = r.required(W10, "IXX IXY IXZ IYY IYZ IZZ")?;
    let names = ["IXX", "IXY", "IXZ", "IYY", "IYZ", "IZZ"];
    let mut v = [0.0; 6];
    for (k, name) in names.iter().enumerate() {
        v[k] = c2.f64_or(k, name, 0.0)?;
    }
    let mut tensor = [[v[0], v[1], v[2]], [v[1], v[3], v[4]], [v[2], v[4], v[5]]];
    let c3 = r.required(W10, "VTX VTY VTZ VRX VRY VRZ")?;
    let mut w = [0.0; 6];
    for (k, name) in ["VTX", "VTY", "VTZ", "VRX", "VRY", "VRZ"]
        .iter()
        .enumerate()
    {
        w[k] = c3.f64_or(k, name, 0.0)?;
    }
    if irc == 1 {
        let c4 = r.required(W10, "XL YL ZL XLIP YLIP ZLIP CID")?;
        tensor = local_to_global(&c4, &tensor)?;
    }
    if !positive_definite(&tensor) {
        return Err(c2.err(
            "the inertia tensor is not positive definite (IXX, IYY, IZZ and the products of inertia IXY, IXZ, IYZ, with their sign)",
        ));
    }
    Ok(RawInertia {
        centre,
        mass,
        node,
        inertia: tensor,
        velocity: [w[0], w[1], w[2]],
        omega: [w[3], w[4], w[5]],
    })
}

/// The tensor given in the local axes of card 4 (`XL YL ZL XLIP YLIP ZLIP CID`), in global axes.
fn local_to_global(c: &Card<'_>, t: &[[f64; 3]; 3]) -> Result<[[f64; 3]; 3], DeckError> {
    use cleave_core::math::{cross, norm, scale};
    if c.ref_id(6, "CID")?.is_some() {
        return Err(c.field_err(
            "CID",
            "a *DEFINE_COORDINATE_ system is not supported; give the axes by XL, YL, ZL and XLIP, YLIP, ZLIP",
        ));
    }
    let mut f = [0.0; 6];
    for (k, name) in ["XL", "YL", "ZL", "XLIP", "YLIP", "ZLIP"]
        .iter()
        .enumerate()
    {
        f[k] = c.f64_or(k, name, 0.0)?;
    }
    let xl = [f[0], f[1], f[2]];
    let ip = [f[3], f[4], f[5]];
    let z = cross(xl, ip);
    if norm(xl) == 0.0 || norm(z) <= 1e-12 * norm(xl) * norm(ip) {
        return Err(c.err(
            "the local x axis (XL, YL, ZL) and the in-plane vector (XLIP, YLIP, ZLIP) must be non-zero and not parallel",
        ));
    }
    let e1 = scale(xl, 1.0 / norm(xl));
    let e3 = scale(z, 1.0 / norm(z));
    let e2 = cross(e3, e1);
    let q = [e1, e2, e3]; // rows: the local axes in global components
    let mut g = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for a in 0..3 {
                for b in 0..3 {
                    g[i][j] += q[a][i] * t[a][b] * q[b][j];
                }
            }
        }
    }
    Ok(g)
}

/// Sylvester's criterion.
fn positive_definite(t: &[[f64; 3]; 3]) -> bool {
    let d1 = t[0][0];
    let d2 = t[0][0] * t[1][1] - t[0][1] * t[1][0];
    let d3 = t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1])
        - t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0])
        + t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0]);
    d1 > 0.0 && d2 > 0.0 && d3 > 0.0 && d3.is_finite()
}
