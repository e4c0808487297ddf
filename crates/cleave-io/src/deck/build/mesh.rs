//! Resolving nodes, elements, parts, sections, materials, separation groups, curves and sets.

use cleave_core::curve::Curve;
use cleave_core::element::shape::canonical;
use cleave_core::element::{first_bad_corner, Shape};
use cleave_core::erosion::{ErosionDef, ErosionRule};
use cleave_core::material::{PiecewiseLinear, RateTable};
use cleave_core::math::Vec3;
use cleave_core::model::{
    GivenInertia, HourglassDef, Material, MaterialKind, Model, NodeSet, Part, PartInertia, PartSet,
    Section, SegmentSet, SeparationDef, SolidSet,
};

use super::{Builder, Ids};
use crate::deck::error::DeckError;
use crate::deck::raw::{RawMaterial, RawSet, TableCurves};

impl Builder<'_> {
    /// Fills the mesh, the property tables and the sets; returns the id maps.
    pub fn mesh(&self, m: &mut Model) -> Result<Ids, DeckError> {
        let raw = self.raw;
        let mut ids = Ids {
            nodes: self.index(&raw.nodes, "node", |n| (n.id, &n.src))?,
            sections: self.index(&raw.sections, "section", |s| (s.id, &s.src))?,
            materials: self.index(&raw.materials, "material", |s| (s.id, &s.src))?,
            curves: self.index(&raw.curves, "curve", |c| (c.curve.id, &c.src))?,
            parts: self.index(&raw.parts, "part", |p| (p.id, &p.src))?,
            elems: self.index(&raw.elems, "element", |e| (e.id, &e.src))?,
            ..Ids::default()
        };
        // tables and curves share LS-DYNA's load-curve ids
        self.index::<_, usize>(&raw.tables, "table", |t| (t.id, &t.src))?;
        for t in &raw.tables {
            if let Some(&k) = ids.curves.get(&t.id) {
                let c = &raw.curves[k].src;
                return Err(self.err(
                    &t.src,
                    format!(
                        "table {} has the id of the curve at {}:{} (tables and curves share one set of ids)",
                        t.id, c.file, c.line
                    ),
                ));
            }
        }
        m.node_ids = raw.nodes.iter().map(|n| n.id).collect();
        m.x0 = raw.nodes.iter().map(|n| n.x).collect();
        m.v0 = vec![[0.0; 3]; raw.nodes.len()].into();
        m.curves = raw.curves.iter().map(|c| c.curve.clone()).collect();
        m.sections = raw
            .sections
            .iter()
            .map(|s| Section {
                id: s.id,
                elform: s.elform,
            })
            .collect();
        m.materials = Vec::with_capacity(raw.materials.len());
        for s in &raw.materials {
            m.materials.push(Material {
                id: s.id,
                density: s.density,
                young: s.young,
                poisson: s.poisson,
                kind: self.material_curves(s, &m.curves, &ids)?,
            });
        }
        self.separations(m, &ids)?;
        self.erosion(m, &ids)?;
        // *HOURGLASS: IHQ blank takes *CONTROL_HOURGLASS's form
        let hourglass =
            self.index::<_, usize>(&raw.hourglass, "hourglass definition", |h| (h.id, &h.src))?;
        m.hourglass = (raw.hourglass.iter())
            .map(|h| HourglassDef {
                id: h.id,
                hourglass: h.ihq.unwrap_or(raw.control.hourglass),
                qh: h.qm,
                q1: h.q1,
                q2: h.q2,
            })
            .collect();
        for p in &raw.parts {
            m.parts.push(Part {
                id: p.id,
                title: p.title.clone(),
                section: self.find(&ids.sections, p.secid, &p.src, "SECID", "section")?,
                material: self.find(&ids.materials, p.mid, &p.src, "MID", "material")?,
                hourglass: match p.hgid {
                    Some(h) => {
                        Some(self.find(&hourglass, h, &p.src, "HGID", "hourglass definition")?)
                    }
                    None => None,
                },
            });
        }
        self.equations_of_state(m)?;
        self.elements(m, &ids)?;
        self.sets(m, &mut ids)?;
        self.part_inertia(m, &ids)?;
        Ok(ids)
    }

    /// `*PART_INERTIA`: for rigid parts only (the given properties replace those of its
    /// elements); NODEID's coordinates are the centre.
    fn part_inertia(&self, m: &mut Model, ids: &Ids) -> Result<(), DeckError> {
        for (k, p) in self.raw.parts.iter().enumerate() {
            let Some(g) = &p.inertia else {
                continue;
            };
            let mat = &m.materials[m.parts[k].material];
            if !matches!(mat.kind, MaterialKind::Rigid { .. }) {
                return Err(self
                    .err(
                        &p.src,
                        format!(
                            "*PART_INERTIA on part {}, whose material {} is not *MAT_RIGID: given inertia is for rigid parts only",
                            p.id, mat.id
                        ),
                    )
                    .with_field("MID"));
            }
            let given = self.given_inertia(g, &p.src, "NODEID", m, ids)?;
            m.part_inertia.push(PartInertia { part: k, given });
        }
        Ok(())
    }

    /// The inertia cards resolved: the centre at the node they name, if any.
    pub fn given_inertia(
        &self,
        g: &crate::deck::raw::RawInertia,
        src: &crate::deck::raw::Src,
        node_field: &str,
        m: &Model,
        ids: &Ids,
    ) -> Result<GivenInertia, DeckError> {
        let centre = match g.node {
            Some(id) => m.x0[self.find(&ids.nodes, id, src, node_field, "node")? as usize],
            None => g.centre,
        };
        Ok(GivenInertia {
            centre,
            mass: g.mass,
            inertia: g.inertia,
            velocity: g.velocity,
            omega: g.omega,
        })
    }

    fn separations(&self, m: &mut Model, ids: &Ids) -> Result<(), DeckError> {
        for s in &self.raw.separations {
            let material = self.find(&ids.materials, s.mid, &s.src, "MID", "material")?;
            if matches!(m.materials[material].kind, MaterialKind::Rigid { .. }) {
                return Err(self
                    .err(
                        &s.src,
                        format!("material {} is rigid and cannot separate", s.mid),
                    )
                    .with_field("MID"));
            }
            if m.separations.iter().any(|d| d.material == material) {
                return Err(self
                    .err(
                        &s.src,
                        format!("material {} already has a *MAT_ADD_SEPARATION", s.mid),
                    )
                    .with_field("MID"));
            }
            m.separations.push(SeparationDef {
                material,
                model: s.model,
                sigmax: s.sigmax,
                beta: s.beta,
                gc: s.gc,
                bond: s.bond,
                strength: s.strength,
            });
        }
        Ok(())
    }

    /// The failure rules, one per material: its card's FAIL / FS and its `*MAT_ADD_EROSION`
    /// together. Errors: a rigid material, a material that also separates (erosion and
    /// separation are the two ways to compare, not to combine), two `*MAT_ADD_EROSION` of one
    /// material.
    fn erosion(&self, m: &mut Model, ids: &Ids) -> Result<(), DeckError> {
        for s in &self.raw.erosions {
            let material = self.find(&ids.materials, s.mid, &s.src, "MID", "material")?;
            let bad = |msg: String| Err(self.err(&s.src, msg).with_field("MID"));
            if matches!(m.materials[material].kind, MaterialKind::Rigid { .. }) {
                return bad(format!("material {} is rigid and cannot erode", s.mid));
            }
            if m.separations.iter().any(|d| d.material == material) {
                return bad(format!(
                    "material {} has a *MAT_ADD_SEPARATION: an element either erodes or separates; give it one of the two",
                    s.mid
                ));
            }
            let def = match m.erosion.iter_mut().find(|d| d.material == material) {
                Some(d) => d,
                None => {
                    m.erosion.push(ErosionDef {
                        material,
                        rule: ErosionRule::default(),
                    });
                    m.erosion.last_mut().expect("just pushed")
                }
            };
            if s.from_material {
                if s.rule.plastic_strain.is_some() {
                    def.rule.plastic_strain = s.rule.plastic_strain;
                }
                if s.rule.johnson_cook.is_some() {
                    def.rule.johnson_cook = s.rule.johnson_cook;
                }
            } else if def.rule.criteria() > 0 || def.rule.ncs > 0 {
                return bad(format!("material {} already has a *MAT_ADD_EROSION", s.mid));
            } else {
                def.rule = ErosionRule {
                    plastic_strain: def.rule.plastic_strain,
                    johnson_cook: def.rule.johnson_cook,
                    ..s.rule.clone()
                };
            }
        }
        Ok(())
    }

    /// The material's kind with the curves it names resolved: `*MAT_024`'s LCSS becomes its
    /// hardening points (yield stress against plastic strain), checked.
    fn material_curves(
        &self,
        s: &RawMaterial,
        curves: &[Curve],
        ids: &Ids,
    ) -> Result<MaterialKind, DeckError> {
        let mut kind = s.kind.clone();
        let lcss_err = |m: String| self.err(&s.src, m).with_field("LCSS");
        // the hardening points of curve `k`, checked
        let points = |k: usize| -> Result<Vec<[f64; 2]>, DeckError> {
            let c = &curves[k];
            let pts: Vec<[f64; 2]> = c.t.iter().zip(&c.y).map(|(&x, &y)| [x, y]).collect();
            PiecewiseLinear::check(&pts).map_err(|m| lcss_err(format!("curve {}: {m}", c.id)))?;
            Ok(pts)
        };
        if let MaterialKind::PiecewiseLinear(ref mut p) = kind {
            if let Some(id) = p.lcss {
                match self.raw.tables.iter().find(|t| t.id == id) {
                    None => {
                        let k = self.find(&ids.curves, id, &s.src, "LCSS", "curve or table")?;
                        p.points = points(k)?.into();
                    }
                    Some(t) => {
                        if p.c > 0.0 {
                            return Err(self
                                .err(&s.src, format!("C = {}: the rate effect of a table LCSS ({id}) is in its curves; leave C and P blank", p.c))
                                .with_field("C"));
                        }
                        let n = t.values.len();
                        let ks: Vec<usize> = match &t.curves {
                            TableCurves::Following(k) => {
                                // the reader checked that they follow it
                                (*k..k + n).collect()
                            }
                            TableCurves::Ids(lcids) => lcids
                                .iter()
                                .map(|&c| self.find(&ids.curves, c, &t.src, "LCID", "curve"))
                                .collect::<Result<_, _>>()?,
                        };
                        let mut table_curves = Vec::with_capacity(n);
                        for &k in &ks {
                            table_curves.push((curves[k].id, points(k)?.into()));
                        }
                        let values: Vec<f64> = t.values.iter().map(|v| v.0).collect();
                        let table = RateTable {
                            log: values[0] < 0.0,
                            values,
                            curves: table_curves,
                        };
                        p.points = table.curves[0].1.clone();
                        p.table = Some(table.into());
                    }
                }
            }
        }
        Ok(kind)
    }

    /// Connectivity and part of each element, in the stored layout of its shape
    /// ([`canonical`]); every element must be upright ([`first_bad_corner`]).
    fn elements(&self, m: &mut Model, ids: &Ids) -> Result<(), DeckError> {
        let n = self.raw.elems.len();
        m.elem_ids = Vec::with_capacity(n);
        m.elem_part = Vec::with_capacity(n);
        m.conn = Vec::with_capacity(n);
        for e in &self.raw.elems {
            let part = self.find(&ids.parts, e.pid, &e.src, "PID", "part")?;
            let mut conn = [0u32; 8];
            let nsrc = crate::deck::raw::Src {
                file: e.src.file.clone(),
                keyword: e.src.keyword.clone(),
                line: e.node_line,
            };
            for (k, (c, &nid)) in conn.iter_mut().zip(&e.nodes).enumerate() {
                *c = self.find(&ids.nodes, nid, &nsrc, &format!("N{}", k + 1), "node")?;
            }
            let (conn, shape) = canonical(conn)
                .map_err(|msg| self.err(&nsrc, format!("element {}: {msg}", e.id)))?;
            let elform = m.sections[m.parts[part].section].elform;
            if elform == 2 && shape != Shape::Hex {
                return Err(self.err(
                    &nsrc,
                    format!(
                        "element {} is a {} in part {}, whose section has ELFORM 2 (hexahedra only; give wedges and tetrahedra a section of ELFORM 1, 10 or 13)",
                        e.id,
                        shape.name(),
                        m.parts[part].id
                    ),
                ));
            }
            if (elform == 10 || elform == 13) && shape != Shape::Tet {
                return Err(self.err(
                    &nsrc,
                    format!(
                        "element {} is a {} in part {}, whose section has ELFORM {elform} (tetrahedra only)",
                        e.id,
                        shape.name(),
                        m.parts[part].id
                    ),
                ));
            }
            if elform == 13 && !m.separations.is_empty() {
                return Err(self.err(
                    &nsrc,
                    format!(
                        "part {} has ELFORM 13 in a deck with *MAT_ADD_SEPARATION: the nodal pressure averaging does not work across split nodes yet; use ELFORM 10",
                        m.parts[part].id
                    ),
                ));
            }
            let x: [Vec3; 8] = conn.map(|i| m.x0[i as usize]);
            if let Some((long, short, a, b)) = stretched(&x) {
                return Err(self.err(
                    &e.src,
                    format!(
                        "element {}: its longest edge ({long:.3e}, nodes {} and {}) is more than {MAX_ASPECT:.0e} times its shortest ({short:.3e}): check the node coordinates",
                        e.id,
                        m.node_ids[conn[a] as usize],
                        m.node_ids[conn[b] as usize],
                    ),
                ));
            }
            if let Some((k, j)) = first_bad_corner(shape, &x) {
                let node = m.node_ids[conn[k] as usize];
                return Err(self.err(
                    &e.src,
                    match shape {
                        Shape::Hex => format!(
                            "element {} has a non-positive Jacobian ({j:.3e}) at corner {} (node {node}): check the node order and coordinates",
                            e.id,
                            k + 1,
                        ),
                        _ => format!(
                            "{} {} is inverted or flat (Jacobian {j:.3e} at node {node}): check the node order and coordinates",
                            shape.name(),
                            e.id,
                        ),
                    },
                ));
            }
            m.elem_ids.push(e.id);
            m.elem_part.push(part as u32);
            m.conn.push(conn);
        }
        Ok(())
    }

    /// The indices (in deck order) of the `ids` that fall in a `_GENERATE` set's ranges; a range
    /// that holds none is an error at its line.
    fn in_ranges<T>(
        &self,
        s: &RawSet<T>,
        ids: impl Iterator<Item = i64> + Clone,
        what: &str,
    ) -> Result<impl Iterator<Item = u32>, DeckError> {
        let mut out = Vec::new();
        for &(beg, end, line) in &s.ranges {
            let before = out.len();
            out.extend(
                ids.clone()
                    .enumerate()
                    .filter(|&(_, id)| (beg..=end).contains(&id))
                    .map(|(i, _)| i as u32),
            );
            if out.len() == before {
                let src = crate::deck::raw::Src {
                    file: s.src.file.clone(),
                    keyword: s.src.keyword.clone(),
                    line,
                };
                return Err(self.err(&src, format!("no {what} has an id from {beg} to {end}")));
            }
        }
        Ok(out.into_iter())
    }

    /// The nodes of a `*SET_NODE_GENERAL` (its rules in order; a SET rule names a node set
    /// defined before this one), in ascending order.
    fn general_node_set(
        &self,
        s: &crate::deck::raw::RawSet<i64>,
        m: &Model,
        ids: &Ids,
    ) -> Result<Vec<u32>, DeckError> {
        use crate::deck::raw::RuleKind;
        let mut member = vec![false; m.num_nodes()];
        for rule in &s.general {
            let src = crate::deck::raw::Src {
                file: s.src.file.clone(),
                keyword: s.src.keyword.clone(),
                line: rule.line,
            };
            let mut nodes: Vec<u32> = Vec::new();
            for (&id, &i) in rule.ids.iter().zip(&rule.fields) {
                let field = format!("E{i}");
                match rule.kind {
                    RuleKind::All => {}
                    RuleKind::Node => nodes.push(self.find(&ids.nodes, id, &src, &field, "node")?),
                    RuleKind::Part => {
                        let p = self.find(&ids.parts, id, &src, &field, "part")?;
                        for (e, c) in m.conn.iter().enumerate() {
                            if m.elem_part[e] as usize == p {
                                nodes.extend_from_slice(c);
                            }
                        }
                    }
                    RuleKind::Set => {
                        let set = m.node_sets.iter().find(|n| n.id == id).ok_or_else(|| {
                            self.err(
                                &src,
                                format!("node set {id} is not defined before this one"),
                            )
                            .with_field(&field)
                        })?;
                        nodes.extend_from_slice(&set.nodes);
                    }
                }
            }
            if rule.kind == RuleKind::All {
                nodes = (0..m.num_nodes() as u32).collect();
            }
            for n in nodes {
                member[n as usize] = !rule.delete;
            }
        }
        Ok((0..m.num_nodes() as u32)
            .filter(|&n| member[n as usize])
            .collect())
    }

    /// Node, part and segment sets; members resolved, repeated members dropped.
    fn sets(&self, m: &mut Model, ids: &mut Ids) -> Result<(), DeckError> {
        let raw = self.raw;
        ids.node_sets = self.index(&raw.node_sets, "node set", |s| (s.id, &s.src))?;
        ids.part_sets = self.index(&raw.part_sets, "part set", |s| (s.id, &s.src))?;
        ids.segment_sets = self.index(&raw.segment_sets, "segment set", |s| (s.id, &s.src))?;
        ids.solid_sets = self.index(&raw.solid_sets, "solid set", |s| (s.id, &s.src))?;
        for s in &raw.solid_sets {
            let mut elems = Vec::with_capacity(s.members.len());
            for &(eid, line) in &s.members {
                let src = crate::deck::raw::Src {
                    file: s.src.file.clone(),
                    keyword: s.src.keyword.clone(),
                    line,
                };
                elems.push(self.find(&ids.elems, eid, &src, "K", "element")?);
            }
            let elem_ids = raw.elems.iter().map(|e| e.id);
            elems.extend(self.in_ranges(s, elem_ids, "element")?);
            m.solid_sets.push(SolidSet {
                id: s.id,
                elems: dedup(elems),
            });
        }
        for s in &raw.node_sets {
            let mut nodes = Vec::with_capacity(s.members.len());
            for &(nid, line) in &s.members {
                let src = crate::deck::raw::Src {
                    file: s.src.file.clone(),
                    keyword: s.src.keyword.clone(),
                    line,
                };
                nodes.push(self.find(&ids.nodes, nid, &src, "NID", "node")?);
            }
            let node_ids = raw.nodes.iter().map(|n| n.id);
            nodes.extend(self.in_ranges(s, node_ids, "node")?);
            let nodes = if s.general.is_empty() {
                dedup(nodes)
            } else {
                self.general_node_set(s, m, ids)?
            };
            m.node_sets.push(NodeSet { id: s.id, nodes });
        }
        for s in &raw.part_sets {
            let mut parts = Vec::with_capacity(s.members.len());
            for &(pid, line) in &s.members {
                let src = crate::deck::raw::Src {
                    file: s.src.file.clone(),
                    keyword: s.src.keyword.clone(),
                    line,
                };
                parts.push(self.find(&ids.parts, pid, &src, "PID", "part")?);
            }
            let part_ids = raw.parts.iter().map(|p| p.id);
            parts.extend(self.in_ranges(s, part_ids, "part")?.map(|i| i as usize));
            m.part_sets.push(PartSet {
                id: s.id,
                parts: dedup(parts),
            });
        }
        for s in &raw.segment_sets {
            let mut segments = Vec::with_capacity(s.members.len());
            for &(seg, line) in &s.members {
                let src = crate::deck::raw::Src {
                    file: s.src.file.clone(),
                    keyword: s.src.keyword.clone(),
                    line,
                };
                let mut out = [0u32; 4];
                for (k, (o, nid)) in out.iter_mut().zip(seg).enumerate() {
                    *o = self.find(&ids.nodes, nid, &src, &format!("N{}", k + 1), "node")?;
                }
                segments.push(out);
            }
            m.segment_sets.push(SegmentSet { id: s.id, segments });
        }
        Ok(())
    }
}

/// Drops repeated entries, keeping the first occurrence's position.
pub fn dedup<T: Copy + Eq + std::hash::Hash>(v: Vec<T>) -> Vec<T> {
    let mut seen = std::collections::HashSet::with_capacity(v.len());
    v.into_iter().filter(|x| seen.insert(*x)).collect()
}

/// The largest ratio of an element's longest edge to its shortest that a deck may give: far
/// beyond any mesh (a sliver of 1e6 is already meaningless), and where one node's coordinate
/// has gone astray (a typo, `-1.25e10` for `-0.0125`), which would otherwise make the element's
/// faces span the whole model in the contact search.
pub const MAX_ASPECT: f64 = 1e6;

/// `Some((longest, shortest, a, b))` when the element's edges (of its stored hexahedral
/// layout; the collapsed ones of wedges and tetrahedra left out) differ by more than
/// [`MAX_ASPECT`]; `a`, `b` are the corners of the longest edge.
fn stretched(x: &[Vec3; 8]) -> Option<(f64, f64, usize, usize)> {
    const EDGES: [(usize, usize); 12] = [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ];
    let len = |(a, b): (usize, usize)| cleave_core::math::norm(cleave_core::math::sub(x[a], x[b]));
    let (mut long, mut at) = (0.0, (0, 0));
    let mut short = f64::INFINITY;
    for e in EDGES {
        let l = len(e);
        if l > long {
            (long, at) = (l, e);
        }
        if l > 0.0 && l < short {
            short = l;
        }
    }
    (long > MAX_ASPECT * short).then_some((long, short, at.0, at.1))
}
