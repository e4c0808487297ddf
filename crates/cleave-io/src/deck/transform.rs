//! `*INCLUDE_TRANSFORM` applied: the blocks of each transformed include are decoded on their
//! own, their ids offset, their nodes moved by the `*DEFINE_TRANSFORMATION` named, and the
//! result appended to the deck's (LS-DYNA Keyword Manual, Vol. I, `*INCLUDE_TRANSFORM` and
//! `*DEFINE_TRANSFORMATION`).
//!
//! - **Offsets.** Every id an included card defines or refers to is raised by its class's
//!   offset, whether the item it names is in the include or not (as LS-DYNA does): nodes
//!   IDNOFF, elements IDEOFF, parts and nodal rigid bodies IDPOFF, materials and equations of
//!   state IDMOFF, sets IDSOFF, curves IDFOFF, sections and hourglass definitions IDROFF.
//! - **Transformation.** TRANID's steps (SCALE, ROTATE about an axis through a point, TRANSL,
//!   MIRROR) are composed in the order written into one affine map `x -> A x + b` applied to
//!   the included nodes. When it reverses orientation (det A < 0: a mirror, a negative
//!   scale) each included element's connectivity is reversed too, as LS-DYNA does, so that
//!   its volume stays positive: a hexahedron or wedge swaps its N1/N2, N3/N4, N5/N6, N7/N8
//!   (reflecting the first parametric direction), a tetrahedron its N2/N3.
//! - **What cleave refuses inside a transformed include** (an error naming the keyword):
//!   `*CONTROL_`/`*DATABASE_` cards (global settings: put them in the main deck); under a
//!   TRANID, cards holding points (`*RIGIDWALL_`, `*INITIAL_VELOCITY_GENERATION`, the
//!   `_INERTIA` forms), and, when the map turns or scales, cards holding directions (SPC and
//!   prescribed-motion DOFs, initial velocities, nodal and body loads), which cleave would
//!   otherwise leave untransformed. Unit conversion (FCTMAS, FCTTIM, FCTLEN, FCTTEM other
//!   than 1) is refused where the cards are read.

use cleave_core::math::{self, Mat3, Vec3};

use super::cards;
use super::error::DeckError;
use super::lex::Block;
use super::params::Params;
use super::raw::{Offsets, RawDeck, RawIncludeXform, RawTransform, Src, Target};

/// Decodes the whole deck: the blocks of the deck and its plain includes, then each
/// transformed include's, offset, moved and appended.
pub fn read(blocks: &[Block<'_>]) -> Result<RawDeck, DeckError> {
    let params = Params::read(blocks)?;
    let main_blocks: Vec<&Block<'_>> = blocks
        .iter()
        .filter(|b| b.group == 0 || b.keyword == "*INCLUDE_TRANSFORM")
        .collect();
    let mut deck = cards::read_blocks(&main_blocks, &params)?;
    let xforms = deck.include_xforms.clone();
    let mut subs = Vec::with_capacity(xforms.len());
    for x in &xforms {
        let group: Vec<&Block<'_>> = blocks
            .iter()
            .filter(|b| b.group == x.group && b.keyword != "*INCLUDE_TRANSFORM")
            .collect();
        subs.push(cards::read_blocks(&group, &params)?);
    }
    let mut defs: Vec<RawTransform> = deck.transforms.clone();
    for s in &subs {
        defs.extend(s.transforms.iter().cloned());
    }
    for (k, d) in defs.iter().enumerate() {
        if let Some(first) = defs[..k].iter().find(|e| e.id == d.id) {
            return Err(err(
                &d.src,
                format!(
                    "transformation {} is defined twice (first at {}:{})",
                    d.id, first.src.file, first.src.line
                ),
            ));
        }
    }
    for (x, mut sub) in xforms.iter().zip(subs) {
        let map = match x.tranid {
            None => None,
            Some((id, line)) => Some(resolve(&defs, id, x, line)?),
        };
        let group: Vec<&Block<'_>> = blocks
            .iter()
            .filter(|b| b.group == x.group && b.keyword != "*INCLUDE_TRANSFORM")
            .collect();
        check_keywords(&group, map.as_ref())?;
        offset(&mut sub, &x.offsets);
        if let Some(m) = &map {
            move_nodes(&mut sub, m);
        }
        merge(&mut deck, sub);
    }
    Ok(deck)
}

fn err(src: &Src, message: impl Into<String>) -> DeckError {
    DeckError::at(&src.file, src.line, Some(&src.keyword), message)
}

/// An affine map `x -> a x + b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine {
    pub a: Mat3,
    pub b: Vec3,
}

impl Affine {
    const IDENTITY: Affine = Affine {
        a: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        b: [0.0; 3],
    };

    pub fn apply(&self, x: Vec3) -> Vec3 {
        math::add(math::mat_vec(&self.a, x), self.b)
    }

    /// `next` after `self`: `x -> next(self(x))`.
    fn then(self, next: Affine) -> Affine {
        Affine {
            a: math::mat_mul(&next.a, &self.a),
            b: next.apply(self.b),
        }
    }

    fn turns_or_scales(&self) -> bool {
        self.a != Self::IDENTITY.a
    }
}

/// The map of transformation `id`'s steps, composed in order.
fn resolve(
    defs: &[RawTransform],
    id: i64,
    x: &RawIncludeXform,
    line: usize,
) -> Result<Affine, DeckError> {
    let at = Src {
        line,
        ..x.src.clone()
    };
    let d = defs.iter().find(|d| d.id == id).ok_or_else(|| {
        err(
            &at,
            format!("TRANID {id}: no *DEFINE_TRANSFORMATION has this id"),
        )
        .with_field("TRANID")
    })?;
    let mut m = Affine::IDENTITY;
    for (option, a, line) in &d.ops {
        let src = Src {
            line: *line,
            ..d.src.clone()
        };
        m = m.then(step(option, a).map_err(|msg| err(&src, msg))?);
    }
    Ok(m)
}

/// One step `OPTION A1..A7` as a map.
fn step(option: &str, a: &[f64; 7]) -> Result<Affine, String> {
    let p = [a[0], a[1], a[2]];
    let q = [a[3], a[4], a[5]];
    match option {
        "TRANSL" => Ok(Affine {
            b: p,
            ..Affine::IDENTITY
        }),
        "SCALE" => {
            // blank reads as 0 and means 1 (LS-DYNA's default)
            let s = p.map(|v| if v == 0.0 { 1.0 } else { v });
            Ok(Affine {
                a: [[s[0], 0.0, 0.0], [0.0, s[1], 0.0], [0.0, 0.0, s[2]]],
                b: [0.0; 3],
            })
        }
        "ROTATE" => {
            let len = math::norm(p);
            if q == [0.0; 3] && a[6] == 0.0 {
                return Err("ROTATE given by two node ids and an angle (A4-A7 blank) is not supported: give the axis A1-A3, a point on it A4-A6 and the angle A7 in degrees".into());
            }
            if len == 0.0 {
                return Err("ROTATE: the axis A1-A3 is zero".into());
            }
            let w = math::scale(p, a[6].to_radians() / len);
            let r = math::rotation_from_vector(w);
            // about the point q: x -> r (x - q) + q
            Ok(Affine {
                a: r,
                b: math::sub(q, math::mat_vec(&r, q)),
            })
        }
        "MIRROR" => {
            let d = math::sub(q, p);
            let len = math::norm(d);
            if len == 0.0 {
                return Err("MIRROR: the plane's normal, from A1-A3 to A4-A6, is zero".into());
            }
            let n = math::scale(d, 1.0 / len);
            let mut r = Affine::IDENTITY.a;
            for (i, row) in r.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v -= 2.0 * n[i] * n[j];
                }
            }
            Ok(Affine {
                a: r,
                b: math::scale(n, 2.0 * math::dot(p, n)),
            })
        }
        o => Err(format!(
            "option '{o}' not supported (cleave takes SCALE, ROTATE, TRANSL and MIRROR)"
        )),
    }
}

/// Base keyword without `_TITLE`/`_ID`.
fn base(kw: &str) -> &str {
    let k = kw.strip_suffix("_TITLE").unwrap_or(kw);
    k.strip_suffix("_ID").unwrap_or(k)
}

/// The keywords a transformed include may not hold (see the module comment).
fn check_keywords(group: &[&Block<'_>], map: Option<&Affine>) -> Result<(), DeckError> {
    for b in group {
        let k = base(&b.keyword);
        let why = if k.starts_with("*CONTROL_") || k.starts_with("*DATABASE_") {
            Some("a global setting: put it in the main deck")
        } else if k.starts_with("*DEFINE_COORDINATE_") || k.starts_with("*DEFINE_VECTOR") {
            Some("its points and ids are not moved and offset: put it in the main deck")
        } else if map.is_some()
            && (k.starts_with("*RIGIDWALL_")
                || k == "*INITIAL_VELOCITY_GENERATION"
                || k.ends_with("_INERTIA"))
        {
            Some("its points are not moved by the TRANID transformation: put it in the main deck")
        } else if map.is_some_and(Affine::turns_or_scales)
            && (k.starts_with("*BOUNDARY_SPC_")
                || k.starts_with("*BOUNDARY_PRESCRIBED_MOTION_")
                || k.starts_with("*INITIAL_VELOCITY")
                || k.starts_with("*LOAD_NODE_")
                || k.starts_with("*LOAD_BODY_"))
        {
            Some("its directions are not turned by the TRANID transformation: put it in the main deck")
        } else {
            None
        };
        if let Some(why) = why {
            return Err(DeckError::at(
                &b.file,
                b.line,
                Some(&b.keyword),
                format!("not supported in a file read through *INCLUDE_TRANSFORM ({why})"),
            ));
        }
    }
    Ok(())
}

fn add(id: &mut i64, off: i64) {
    *id += off;
}

fn add_opt(id: &mut Option<i64>, off: i64) {
    if let Some(v) = id {
        *v += off;
    }
}

fn add_target(t: &mut Target, o: &Offsets) {
    match t {
        Target::Node(n) => add(n, o.node),
        Target::NodeSet(s) | Target::PartSet(s) => add(s, o.set),
        Target::Part(p) => add(p, o.part),
        Target::All => {}
    }
}

/// Raises every id of `d` by its class's offset. The destructuring is exhaustive, so that a
/// new kind of card cannot be added without deciding its ids' classes here.
fn offset(d: &mut RawDeck, o: &Offsets) {
    let RawDeck {
        title: _,
        hourglass,
        nodes,
        elems,
        parts,
        sections,
        materials,
        eos,
        separations,
        erosions,
        tables,
        curves,
        node_sets,
        part_sets,
        segment_sets,
        solid_sets,
        nodal_rigid,
        extra_nodes,
        spcs,
        motions,
        init_vel,
        body_loads,
        node_loads,
        // a transformed include may not define systems or vectors (`check_keywords`); the
        // CID and VID fields that name the main deck's keep their ids
        frames: _,
        vectors: _,
        global_frames: _,
        pressures,
        walls,
        contacts,
        control: _,
        lctm: _,
        termination: _,
        output: _,
        history_nodes,
        history_solids,
        history_solid_sets,
        transforms: _,
        include_xforms: _,
        warnings: _,
    } = d;
    hourglass.iter_mut().for_each(|h| add(&mut h.id, o.other));
    nodes.iter_mut().for_each(|n| add(&mut n.id, o.node));
    for e in elems {
        add(&mut e.id, o.elem);
        add(&mut e.pid, o.part);
        e.nodes.iter_mut().for_each(|n| add(n, o.node));
    }
    for p in parts {
        add(&mut p.id, o.part);
        add(&mut p.secid, o.other);
        add(&mut p.mid, o.mat);
        add_opt(&mut p.eosid, o.mat);
        add_opt(&mut p.hgid, o.other);
        if let Some(i) = &mut p.inertia {
            add_opt(&mut i.node, o.node);
        }
    }
    sections.iter_mut().for_each(|s| add(&mut s.id, o.other));
    for m in materials {
        add(&mut m.id, o.mat);
        if let cleave_core::model::MaterialKind::PiecewiseLinear(p) = &mut m.kind {
            add_opt(&mut p.lcss, o.curve);
        }
    }
    eos.iter_mut().for_each(|e| add(&mut e.id, o.mat));
    separations.iter_mut().for_each(|s| add(&mut s.mid, o.mat));
    erosions.iter_mut().for_each(|s| add(&mut s.mid, o.mat));
    curves
        .iter_mut()
        .for_each(|c| add(&mut c.curve.id, o.curve));
    for t in tables {
        add(&mut t.id, o.curve);
        if let super::raw::TableCurves::Ids(ids) = &mut t.curves {
            ids.iter_mut().for_each(|c| add(c, o.curve));
        }
    }
    for s in node_sets {
        add(&mut s.id, o.set);
        s.members.iter_mut().for_each(|(n, _)| add(n, o.node));
        for rule in &mut s.general {
            let off = match rule.kind {
                super::raw::RuleKind::All => 0,
                super::raw::RuleKind::Node => o.node,
                super::raw::RuleKind::Part => o.part,
                super::raw::RuleKind::Set => o.set,
            };
            rule.ids.iter_mut().for_each(|i| add(i, off));
        }
        s.ranges.iter_mut().for_each(|(a, b, _)| {
            add(a, o.node);
            add(b, o.node);
        });
    }
    for s in part_sets {
        add(&mut s.id, o.set);
        s.members.iter_mut().for_each(|(p, _)| add(p, o.part));
        s.ranges.iter_mut().for_each(|(a, b, _)| {
            add(a, o.part);
            add(b, o.part);
        });
    }
    for s in segment_sets {
        add(&mut s.id, o.set);
        s.members
            .iter_mut()
            .for_each(|(q, _)| q.iter_mut().for_each(|n| add(n, o.node)));
    }
    for s in solid_sets {
        add(&mut s.id, o.set);
        s.members.iter_mut().for_each(|(e, _)| add(e, o.elem));
        s.ranges.iter_mut().for_each(|(a, b, _)| {
            add(a, o.elem);
            add(b, o.elem);
        });
    }
    for r in nodal_rigid {
        add(&mut r.id, o.part);
        add(&mut r.nsid, o.set);
        if let Some(i) = &mut r.inertia {
            add_opt(&mut i.node, o.node);
        }
    }
    for x in extra_nodes {
        add(&mut x.pid, o.part);
        add(&mut x.id, if x.set { o.set } else { o.node });
    }
    spcs.iter_mut().for_each(|s| add_target(&mut s.target, o));
    for m in motions {
        add_target(&mut m.target, o);
        add(&mut m.lcid, o.curve);
    }
    init_vel
        .iter_mut()
        .for_each(|v| add_target(&mut v.target, o));
    body_loads
        .iter_mut()
        .for_each(|b| add_opt(&mut b.lcid, o.curve));
    for l in node_loads {
        add(&mut l.id, if l.set { o.set } else { o.node });
        add(&mut l.lcid, o.curve);
    }
    for p in pressures {
        if let Some(q) = &mut p.segment {
            q.iter_mut().for_each(|n| add(n, o.node));
        }
        add_opt(&mut p.ssid, o.set);
        add(&mut p.lcid, o.curve);
    }
    walls.iter_mut().for_each(|w| add_opt(&mut w.nsid, o.set));
    for c in contacts {
        for s in std::iter::once(&mut c.slave).chain(c.master.as_mut()) {
            add_opt(&mut s.id, if s.typ == 3 { o.part } else { o.set });
        }
    }
    history_nodes.iter_mut().for_each(|(n, _)| add(n, o.node));
    history_solids.iter_mut().for_each(|(e, _)| add(e, o.elem));
    history_solid_sets
        .iter_mut()
        .for_each(|(s, _)| add(s, o.set));
}

/// Moves the include's nodes by `m`, and reverses its elements' connectivity when `m`
/// reverses orientation.
fn move_nodes(d: &mut RawDeck, m: &Affine) {
    for n in &mut d.nodes {
        n.x = m.apply(n.x);
    }
    if math::det(&m.a) < 0.0 {
        for e in &mut d.elems {
            e.nodes = reversed(e.nodes);
        }
    }
}

/// The connectivity of an `*ELEMENT_SOLID` card (any of its accepted shapes) with its
/// orientation reversed and its shape pattern kept.
pub fn reversed(n: [i64; 8]) -> [i64; 8] {
    let tet = n[3] == n[4] && n[4] == n[5] && n[5] == n[6] && n[6] == n[7];
    if tet {
        [n[0], n[2], n[1], n[3], n[4], n[5], n[6], n[7]]
    } else {
        [n[1], n[0], n[3], n[2], n[5], n[4], n[7], n[6]]
    }
}

/// Appends what a transformed include read to the deck (its global cards were refused by
/// [`check_keywords`]; its title is dropped).
fn merge(d: &mut RawDeck, s: RawDeck) {
    let RawDeck {
        title: _,
        hourglass,
        nodes,
        elems,
        parts,
        sections,
        materials,
        eos,
        separations,
        erosions,
        tables,
        curves,
        node_sets,
        part_sets,
        segment_sets,
        solid_sets,
        nodal_rigid,
        extra_nodes,
        spcs,
        motions,
        init_vel,
        body_loads,
        node_loads,
        frames,
        vectors,
        global_frames,
        pressures,
        walls,
        contacts,
        control: _,
        lctm: _,
        termination: _,
        output: _,
        history_nodes,
        history_solids,
        history_solid_sets,
        transforms: _,
        include_xforms: _,
        warnings,
    } = s;
    d.hourglass.extend(hourglass);
    d.nodes.extend(nodes);
    d.elems.extend(elems);
    d.parts.extend(parts);
    d.sections.extend(sections);
    d.materials.extend(materials);
    d.eos.extend(eos);
    d.separations.extend(separations);
    d.erosions.extend(erosions);
    // a table's following curves are now after the deck's
    let first = d.curves.len();
    d.tables.extend(tables.into_iter().map(|mut t| {
        if let super::raw::TableCurves::Following(k) = &mut t.curves {
            *k += first;
        }
        t
    }));
    d.curves.extend(curves);
    d.node_sets.extend(node_sets);
    d.part_sets.extend(part_sets);
    d.segment_sets.extend(segment_sets);
    d.solid_sets.extend(solid_sets);
    d.nodal_rigid.extend(nodal_rigid);
    d.extra_nodes.extend(extra_nodes);
    d.spcs.extend(spcs);
    d.motions.extend(motions);
    d.init_vel.extend(init_vel);
    d.body_loads.extend(body_loads);
    d.node_loads.extend(node_loads);
    d.frames.extend(frames);
    d.vectors.extend(vectors);
    d.global_frames.extend(global_frames);
    d.pressures.extend(pressures);
    d.walls.extend(walls);
    d.contacts.extend(contacts);
    d.history_nodes.extend(history_nodes);
    d.history_solids.extend(history_solids);
    d.history_solid_sets.extend(history_solid_sets);
    d.warnings.extend(warnings);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12)
    }

    #[test]
    fn steps_map_points_as_the_manual_says() {
        let mut a = [0.0; 7];
        // mirror about the plane x = -4 (normal from (-4,0,0) towards (-5,0,0))
        a[..6].copy_from_slice(&[-4.0, 0.0, 0.0, -5.0, 0.0, 0.0]);
        let m = step("MIRROR", &a).unwrap();
        assert!(close(m.apply([1.0, 2.0, 3.0]), [-9.0, 2.0, 3.0]));
        assert!(math::det(&m.a) < 0.0);
        // a quarter turn about the z axis through (1, 0, 0)
        let r = step("ROTATE", &[0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 90.0]).unwrap();
        assert!(close(r.apply([2.0, 0.0, 5.0]), [1.0, 1.0, 5.0]));
        let t = step("TRANSL", &[1.0, -2.0, 3.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        assert!(close(t.apply([1.0, 1.0, 1.0]), [2.0, -1.0, 4.0]));
        let s = step("SCALE", &[2.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        assert!(close(s.apply([1.0, 1.0, 1.0]), [2.0, 1.0, -1.0]));
        // composition in the order written: translate, then scale
        assert!(close(t.then(s).apply([0.0; 3]), [2.0, -2.0, -3.0]));
        assert!(step("POS6N", &[0.0; 7]).unwrap_err().contains("POS6N"));
        assert!(step("ROTATE", &[1.0, 2.0, 30.0, 0.0, 0.0, 0.0, 0.0]).is_err());
    }

    #[test]
    fn reversal_keeps_the_shape_pattern() {
        assert_eq!(reversed([1, 2, 3, 4, 5, 6, 7, 8]), [2, 1, 4, 3, 6, 5, 8, 7]);
        assert_eq!(reversed([1, 2, 3, 4, 5, 5, 6, 6]), [2, 1, 4, 3, 5, 5, 6, 6]);
        assert_eq!(reversed([1, 2, 3, 4, 4, 4, 4, 4]), [1, 3, 2, 4, 4, 4, 4, 4]);
    }
}
