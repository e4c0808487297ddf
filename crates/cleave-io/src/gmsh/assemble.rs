//! From the sections as read to a [`Mesh`]: node tags of elements resolved, each solid given
//! its part and its LS-DYNA connectivity (turned the right way out where it was inverted),
//! each physical group its nodes and faces, and the rules of the module doc checked.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use cleave_core::math::Vec3;

use super::cursor::Cursor;
use super::error::MshError;
use super::mapping::{self, SolidKind};
use super::raw::{Owner, RawElem, RawMsh, Version};
use super::{Format, Group, Mesh, Node, Solid};

type R<T> = Result<T, MshError>;

/// `point`, `curve`, `surface` or `volume`.
pub fn dim_name(dim: u8) -> &'static str {
    match dim {
        0 => "point",
        1 => "curve",
        2 => "surface",
        _ => "volume",
    }
}

/// A physical group as it fills up.
#[derive(Default)]
struct Acc {
    nodes: BTreeSet<i64>,
    faces: Vec<(i64, [i64; 4])>,
    elements: usize,
}

/// The physical tags of `e`, by its format's rule.
fn physical(raw: &RawMsh, c: &Cursor<'_>, e: &RawElem) -> R<Vec<i64>> {
    Ok(match e.owner {
        Owner::Entity(t) => match &raw.entities {
            Some(map) => {
                let mut p = map.get(&(e.ty.dim, t)).cloned().ok_or_else(|| {
                    c.err_at(
                        e.pos,
                        format!(
                            "element {}: its entity, {} {t}, is not in $Entities",
                            e.tag,
                            dim_name(e.ty.dim)
                        ),
                    )
                })?;
                p.sort_unstable();
                p.dedup();
                p
            }
            None => Vec::new(),
        },
        Owner::Tags { physical: 0, .. } => Vec::new(),
        Owner::Tags { physical, .. } => vec![physical],
    })
}

/// The geometric entity of `e` (the part of a solid in no physical volume).
fn entity(e: &RawElem) -> Option<i64> {
    match e.owner {
        Owner::Entity(t) => Some(t),
        Owner::Tags { elementary, .. } => elementary,
    }
}

/// Why an element type is not read, for the messages.
fn refusal(e: &RawElem) -> String {
    let what = format!(
        "element {} is a {} (Gmsh type {})",
        e.tag, e.ty.name, e.ty.number
    );
    if e.ty.order >= 2 {
        format!(
            "{what}: second-order elements are not supported: re-mesh with order 1 (Gmsh option Mesh.ElementOrder = 1)"
        )
    } else if e.ty.dim == 3 {
        format!("{what}: cleave reads tetrahedra (type 4), hexahedra (5) and prisms (6) only")
    } else {
        format!(
            "{what}: physical groups of dimension 0 to 2 are read from points (type 15), lines (1), triangles (2) and quadrangles (3) only"
        )
    }
}

pub fn assemble(raw: RawMsh, c: &Cursor<'_>) -> R<Mesh> {
    let mut nodes = Vec::with_capacity(raw.nodes.len());
    let mut index: HashMap<i64, usize> = HashMap::with_capacity(raw.nodes.len());
    for n in &raw.nodes {
        if n.tag <= 0 {
            return Err(c.err_at(n.pos, format!("node tag {} is not positive", n.tag)));
        }
        if !n.x.iter().all(|v| v.is_finite()) {
            return Err(c.err_at(
                n.pos,
                format!(
                    "node {} has a coordinate that is not a finite number",
                    n.tag
                ),
            ));
        }
        if index.insert(n.tag, nodes.len()).is_some() {
            return Err(c.err_at(n.pos, format!("node {} is defined twice", n.tag)));
        }
        nodes.push(Node { tag: n.tag, x: n.x });
    }
    let x_of = |e: &RawElem, t: i64| -> R<Vec3> {
        index.get(&t).map(|&k| nodes[k].x).ok_or_else(|| {
            c.err_at(
                e.pos,
                format!(
                    "element {} refers to node {t}, which $Nodes does not define",
                    e.tag
                ),
            )
        })
    };

    let mut counts: BTreeMap<i64, usize> = BTreeMap::new();
    let mut groups: BTreeMap<(u8, i64), Acc> = BTreeMap::new();
    let mut solids: Vec<Solid> = Vec::new();
    let mut solid_at: HashMap<i64, usize> = HashMap::new();
    let mut same_nodes: HashMap<[i64; 8], usize> = HashMap::new();
    let mut from_entity: BTreeMap<i64, (i64, usize)> = BTreeMap::new();
    let mut reoriented = 0;
    for e in &raw.elems {
        *counts.entry(e.ty.number).or_default() += 1;
        let phys = physical(&raw, c, e)?;
        if e.ty.dim == 3 {
            let kind =
                SolidKind::of_gmsh(e.ty.number).ok_or_else(|| c.err_at(e.pos, refusal(e)))?;
            if e.tag <= 0 {
                return Err(c.err_at(e.pos, format!("element tag {} is not positive", e.tag)));
            }
            let part = match phys[..] {
                [p] => p,
                [] => {
                    let t = entity(e).ok_or_else(|| {
                        c.err_at(
                            e.pos,
                            format!(
                                "element {} has neither a physical nor an elementary tag: it cannot be given a part",
                                e.tag
                            ),
                        )
                    })?;
                    from_entity.entry(t).or_insert((e.tag, e.pos));
                    t
                }
                [p, q, ..] => {
                    return Err(c.err_at(
                        e.pos,
                        format!(
                            "element {} is in physical volumes {p} and {q}: a solid must be in one part, so in at most one physical volume",
                            e.tag
                        ),
                    ))
                }
            };
            if part <= 0 {
                return Err(c.err_at(
                    e.pos,
                    format!("element {}: part id {part} is not positive", e.tag),
                ));
            }
            let mut g = e.nodes.clone();
            let mut x = Vec::with_capacity(g.len());
            for &t in &g {
                x.push(x_of(e, t)?);
            }
            let mut v = mapping::volume(kind, &mapping::to_dyna(kind, &x));
            if v < 0.0 {
                mapping::mirror(kind, &mut g);
                mapping::mirror(kind, &mut x);
                v = mapping::volume(kind, &mapping::to_dyna(kind, &x));
                reoriented += 1;
            }
            if !(v > 0.0 && v.is_finite()) {
                return Err(c.err_at(
                    e.pos,
                    format!(
                        "element {} ({}) has no volume (computed {v:e}): its nodes are flat or repeated",
                        e.tag, e.ty.name
                    ),
                ));
            }
            let conn = mapping::to_dyna(kind, &g);
            if let Some(&k) = solid_at.get(&e.tag) {
                return Err(c.err_at(
                    e.pos,
                    format!(
                        "element tag {} is used twice (a {} and a {})",
                        e.tag,
                        solids[k].kind.name(),
                        kind.name()
                    ),
                ));
            }
            let mut key = conn;
            key.sort_unstable();
            if let Some(&k) = same_nodes.get(&key) {
                let o = &solids[k];
                let why = if o.part != part {
                    format!(
                        ", in parts {} and {}: a solid must be in one part, so in at most one physical volume{}",
                        o.part,
                        part,
                        if raw.version == Version::V22 {
                            " (MSH 2.2 writes an element once per physical group it is in)"
                        } else {
                            ""
                        }
                    )
                } else {
                    String::new()
                };
                return Err(c.err_at(
                    e.pos,
                    format!("elements {} and {} have the same nodes{why}", o.tag, e.tag),
                ));
            }
            same_nodes.insert(key, solids.len());
            solid_at.insert(e.tag, solids.len());
            if !phys.is_empty() {
                let a = groups.entry((3, part)).or_default();
                a.nodes.extend(g.iter().copied());
                a.elements += 1;
            }
            solids.push(Solid {
                tag: e.tag,
                kind,
                nodes: conn,
                part,
            });
        } else if !phys.is_empty() {
            if !matches!(e.ty.number, 1 | 2 | 3 | 15) {
                return Err(c.err_at(e.pos, refusal(e)));
            }
            for &t in &e.nodes {
                x_of(e, t)?;
            }
            for &p in &phys {
                let acc = groups.entry((e.ty.dim, p)).or_default();
                acc.nodes.extend(e.nodes.iter().copied());
                acc.elements += 1;
                if e.ty.dim == 2 {
                    let n = &e.nodes;
                    let face = match n[..] {
                        [a, b, c] => [a, b, c, c],
                        [a, b, c, d] => [a, b, c, d],
                        _ => continue,
                    };
                    acc.faces.push((e.tag, face));
                }
            }
        }
    }

    let names: HashMap<(u8, i64), &str> = raw
        .names
        .iter()
        .map(|n| ((n.dim, n.tag), n.name.as_str()))
        .collect();
    let name = |d: u8, t: i64| names.get(&(d, t)).copied().unwrap_or("").to_string();
    // node sets share one id space: groups of dimension 0 to 2 must not share a tag
    let mut set_ids: BTreeMap<i64, u8> = BTreeMap::new();
    for &(d, t) in groups.keys().filter(|k| k.0 < 3) {
        if t <= 0 {
            return Err(MshError::file(
                c.file(),
                format!(
                    "physical {} {t} \"{}\": the tag must be positive (it is the set id)",
                    dim_name(d),
                    name(d, t)
                ),
            ));
        }
        if let Some(&d0) = set_ids.get(&t) {
            return Err(MshError::file(
                c.file(),
                format!(
                    "physical {} {t} \"{}\" and physical {} {t} \"{}\" share the tag {t}: both would be node set {t} (*SET_NODE_LIST); Gmsh numbers physical groups per dimension, LS-DYNA's sets are not: renumber one of them in Gmsh",
                    dim_name(d0),
                    name(d0, t),
                    dim_name(d),
                    name(d, t)
                ),
            ));
        }
        set_ids.insert(t, d);
    }
    // a part named after an entity must not merge with a physical volume of that tag
    for (&t, &(tag, pos)) in &from_entity {
        if groups.contains_key(&(3, t)) {
            return Err(c.err_at(
                pos,
                format!(
                    "element {tag} is in no physical volume, so its part is its volume entity's tag, {t}; but physical volume {t} \"{}\" is another part: put volume {t} in a physical volume, or renumber in Gmsh",
                    name(3, t)
                ),
            ));
        }
    }

    nodes.sort_by_key(|n| n.tag);
    solids.sort_by_key(|s| s.tag);
    let groups = groups
        .into_iter()
        .map(|((dim, tag), mut a)| {
            a.faces.sort_unstable_by_key(|f| f.1);
            Group {
                dim,
                tag,
                name: name(dim, tag),
                nodes: a.nodes.into_iter().collect(),
                faces: a.faces.into_iter().map(|f| f.1).collect(),
                elements: a.elements,
            }
        })
        .collect();
    Ok(Mesh {
        format: Format {
            version: raw.version,
            binary: raw.binary,
        },
        nodes,
        solids,
        groups,
        element_counts: counts.into_iter().collect(),
        reoriented,
    })
}
