//! Resolving constraints, prescribed motion, initial velocities, loads, rigid walls, contacts
//! and history requests.

use std::collections::BTreeMap;

use cleave_core::math::{cross, sub, Vec3};
use cleave_core::model::{
    BodyLoad, ContactDef, ContactSurface, ExtraNodes, MaterialKind, Model, MotionDof, MotionTarget,
    NodalRigidBody, NodeLoad, PrescribedMotion, PressureLoad, RigidWall, SegmentSet, Spc, TiedDef,
    TiedSlave, WallMotion,
};

use super::mesh::dedup;
use super::{Builder, Ids};
use crate::deck::error::DeckError;
use crate::deck::raw::{RawDof, RawSurface, Src, Target};

impl Builder<'_> {
    /// `*LOAD_NODE_...` (sets expanded, one load per node) and `*LOAD_SEGMENT...` (one per
    /// segment); a segment whose nodes repeat other than as a triangle `N1 N2 N3 N3` is an
    /// error.
    fn loads(&self, m: &mut Model, ids: &Ids) -> Result<(), DeckError> {
        let raw = self.raw;
        let frames = self.frames()?;
        for l in &raw.node_loads {
            let curve = self.find(&ids.curves, l.lcid, &l.src, "LCID", "curve")?;
            let nodes = if l.set {
                let s = self.find(&ids.node_sets, l.id, &l.src, "NSID", "node set")?;
                m.node_sets[s].nodes.clone()
            } else {
                vec![self.find(&ids.nodes, l.id, &l.src, "NID", "node")?]
            };
            // along a local axis: one load per global component it has (SF times the
            // component), so the force is SF curve(t) times the local axis
            let parts: Vec<(usize, f64)> = match l.cid {
                None => vec![(l.axis, l.sf)],
                Some(cid) => {
                    let axes = self.frame(&frames, cid, &l.src, "CID")?;
                    (0..3)
                        .filter(|&a| axes[l.axis][a] != 0.0)
                        .map(|a| (a, l.sf * axes[l.axis][a]))
                        .collect()
                }
            };
            for node in nodes {
                for &(axis, sf) in &parts {
                    m.node_loads.push(NodeLoad {
                        node,
                        axis,
                        curve,
                        sf,
                    });
                }
            }
        }
        for p in &raw.pressures {
            let curve = self.find(&ids.curves, p.lcid, &p.src, "LCID", "curve")?;
            let segments = match (p.segment, p.ssid) {
                (Some(seg), _) => {
                    let mut nodes = [0u32; 4];
                    for (k, (n, &id)) in nodes.iter_mut().zip(&seg).enumerate() {
                        *n = self.find(&ids.nodes, id, &p.src, &format!("N{}", k + 1), "node")?;
                    }
                    let distinct = (0..4)
                        .filter(|&a| (0..a).all(|b| nodes[b] != nodes[a]))
                        .count();
                    let triangle = nodes[2] == nodes[3] && distinct == 3;
                    if distinct != 4 && !triangle {
                        return Err(self.err(
                            &p.src,
                            format!(
                                "segment {} {} {} {}: repeated nodes (a triangle is N1 N2 N3 N3)",
                                seg[0], seg[1], seg[2], seg[3]
                            ),
                        ));
                    }
                    vec![nodes]
                }
                (None, Some(ssid)) => {
                    let s = self.find(&ids.segment_sets, ssid, &p.src, "SSID", "segment set")?;
                    m.segment_sets[s].segments.clone()
                }
                (None, None) => Vec::new(),
            };
            for nodes in segments {
                m.pressure_loads.push(PressureLoad {
                    nodes,
                    curve,
                    sf: p.sf,
                    at: p.at,
                });
            }
        }
        Ok(())
    }

    /// `*CONSTRAINED_NODAL_RIGID_BODY` and `*CONSTRAINED_EXTRA_NODES_...`. A nodal rigid
    /// body's PID may not be a `*PART`'s or another nodal rigid body's; extra nodes join
    /// rigid parts only.
    fn rigid_bodies(&self, m: &mut Model, ids: &Ids) -> Result<(), DeckError> {
        for b in &self.raw.nodal_rigid {
            if b.id != 0 {
                if ids.parts.contains_key(&b.id) {
                    return Err(self
                        .err(
                            &b.src,
                            format!(
                                "PID {} is a *PART's id: a nodal rigid body's PID must be its own",
                                b.id
                            ),
                        )
                        .with_field("PID"));
                }
                if m.nodal_rigid.iter().any(|o| o.id == b.id) {
                    return Err(self
                        .err(
                            &b.src,
                            format!("nodal rigid body {} is defined twice", b.id),
                        )
                        .with_field("PID"));
                }
            }
            let set = self.find(&ids.node_sets, b.nsid, &b.src, "NSID", "node set")?;
            let inertia = match &b.inertia {
                None => None,
                Some(g) => Some(self.given_inertia(g, &b.src, "NID", m, ids)?),
            };
            m.nodal_rigid.push(NodalRigidBody {
                id: b.id,
                set,
                cmo: b.cmo,
                con1: b.con1,
                con2: b.con2,
                inertia,
            });
        }
        for x in &self.raw.extra_nodes {
            let part = self.find(&ids.parts, x.pid, &x.src, "PID", "part")?;
            let mat = &m.materials[m.parts[part].material];
            if !matches!(mat.kind, MaterialKind::Rigid { .. }) {
                return Err(self
                    .err(
                        &x.src,
                        format!(
                            "part {} is not rigid (its material {} is not *MAT_RIGID): extra nodes join rigid parts",
                            x.pid, mat.id
                        ),
                    )
                    .with_field("PID"));
            }
            let (set, nodes) = if x.set {
                let s = self.find(&ids.node_sets, x.id, &x.src, "NSID", "node set")?;
                (Some(s), m.node_sets[s].nodes.clone())
            } else {
                (
                    None,
                    vec![self.find(&ids.nodes, x.id, &x.src, "NID", "node")?],
                )
            };
            m.extra_nodes.push(ExtraNodes {
                part,
                set,
                nodes,
                iflag: x.iflag,
            });
        }
        Ok(())
    }

    pub fn conditions(&self, m: &mut Model, ids: &Ids) -> Result<(), DeckError> {
        self.rigid_bodies(m, ids)?;
        let part_nodes = part_nodes(m);
        self.spcs(m, ids, &part_nodes)?;
        self.motions(m, ids, &part_nodes)?;
        self.initial_velocities(m, ids, &part_nodes)?;
        let raw = self.raw;
        for b in &raw.body_loads {
            let curve = match b.lcid {
                None => None,
                Some(id) => Some(self.find(&ids.curves, id, &b.src, "LCID", "curve")?),
            };
            m.body_loads.push(BodyLoad {
                axis: b.axis,
                curve,
                sf: b.sf,
            });
        }
        self.loads(m, ids)?;
        for (k, w) in raw.walls.iter().enumerate() {
            let nodes = match w.nsid {
                None => None,
                Some(id) => {
                    let s = self.find(&ids.node_sets, id, &w.src, "NSID", "node set")?;
                    Some(m.node_sets[s].nodes.clone())
                }
            };
            m.rigid_walls.push(RigidWall {
                id: k as i64 + 1,
                nodes,
                tail: w.tail,
                head: w.head,
                fric: w.fric,
                extent: w.extent,
                shape: w.shape,
                motion: match w.motion {
                    None => None,
                    Some((lcid, displacement, dir)) => Some(WallMotion {
                        curve: self.find(&ids.curves, lcid, &w.src, "LCID", "curve")?,
                        displacement,
                        dir,
                    }),
                },
            });
        }
        for (k, c) in raw.contacts.iter().enumerate() {
            if c.tied {
                let slave = if c.slave.typ == 4 {
                    let id = c.slave.id.unwrap_or(0);
                    TiedSlave::NodeSet(self.find(&ids.node_sets, id, &c.src, "SSID", "node set")?)
                } else {
                    TiedSlave::Surface(self.surface(&c.slave, &c.src, ids)?)
                };
                let master = match &c.master {
                    Some(s) => self.surface(s, &c.src, ids)?,
                    None => ContactSurface::All,
                };
                if !m.separations.is_empty() {
                    return Err(self.err(
                        &c.src,
                        "tied contact in a deck with *MAT_ADD_SEPARATION is not supported yet (the split nodes would need ties of their own)",
                    ));
                }
                m.tied.push(TiedDef {
                    id: k as i64 + 1,
                    slave,
                    master,
                });
                continue;
            }
            let slave = if c.slave.typ == 4 {
                self.node_set_surface(m, c, ids)?
            } else {
                self.surface(&c.slave, &c.src, ids)?
            };
            let master = match &c.master {
                None => None,
                Some(s) => Some(self.surface(s, &c.src, ids)?),
            };
            m.contacts.push(ContactDef {
                id: k as i64 + 1,
                single_surface: c.single_surface,
                one_way: c.one_way,
                slave,
                master,
                fs: c.fs,
                fd: c.fd,
                dc: c.dc,
            });
        }
        let mut hn = Vec::with_capacity(raw.history_nodes.len());
        for (id, src) in &raw.history_nodes {
            hn.push(self.find(&ids.nodes, *id, src, "ID", "node")?);
        }
        let mut he = Vec::with_capacity(raw.history_solids.len());
        for (id, src) in &raw.history_solids {
            he.push(self.find(&ids.elems, *id, src, "ID", "element")?);
        }
        for (id, src) in &raw.history_solid_sets {
            let s = self.find(&ids.solid_sets, *id, src, "ID", "solid set")?;
            he.extend_from_slice(&m.solid_sets[s].elems);
        }
        m.output = raw.output.clone();
        m.output.history_nodes = dedup(hn);
        m.output.history_solids = dedup(he);
        Ok(())
    }

    /// The nodes a target covers (parts: the nodes of their elements).
    fn target_nodes(
        &self,
        t: Target,
        src: &Src,
        field: &str,
        m: &Model,
        ids: &Ids,
        part_nodes: &[Vec<u32>],
    ) -> Result<Vec<u32>, DeckError> {
        Ok(match t {
            Target::All => (0..m.num_nodes() as u32).collect(),
            Target::Node(id) => vec![self.find(&ids.nodes, id, src, field, "node")?],
            Target::NodeSet(id) => {
                let s = self.find(&ids.node_sets, id, src, field, "node set")?;
                m.node_sets[s].nodes.clone()
            }
            Target::Part(id) => part_nodes[self.find(&ids.parts, id, src, field, "part")?].clone(),
            Target::PartSet(id) => {
                let s = self.find(&ids.part_sets, id, src, field, "part set")?;
                let mut v: Vec<u32> = m.part_sets[s]
                    .parts
                    .iter()
                    .flat_map(|&p| part_nodes[p].iter().copied())
                    .collect();
                v.sort_unstable();
                v.dedup();
                v
            }
        })
    }

    /// `*NODE` TC/RC and `*BOUNDARY_SPC_*`, merged per node by OR, sorted by node index.
    fn spcs(&self, m: &mut Model, ids: &Ids, part_nodes: &[Vec<u32>]) -> Result<(), DeckError> {
        let mut map: BTreeMap<u32, [bool; 6]> = BTreeMap::new();
        let mut add = |node: u32, dof: [bool; 6]| {
            let e = map.entry(node).or_insert([false; 6]);
            for (a, b) in e.iter_mut().zip(dof) {
                *a |= b;
            }
        };
        for (i, n) in self.raw.nodes.iter().enumerate() {
            if n.tc != 0 || n.rc != 0 {
                let (t, r) = (
                    cleave_core::model::dof_code(n.tc),
                    cleave_core::model::dof_code(n.rc),
                );
                add(i as u32, [t[0], t[1], t[2], r[0], r[1], r[2]]);
            }
        }
        for s in &self.raw.spcs {
            let field = if matches!(s.target, Target::Node(_)) {
                "NID"
            } else {
                "NSID"
            };
            for node in self.target_nodes(s.target, &s.src, field, m, ids, part_nodes)? {
                add(node, s.dof);
            }
        }
        m.spcs = map
            .into_iter()
            .filter(|(_, d)| d.iter().any(|&b| b))
            .map(|(node, dof)| Spc { node, dof })
            .collect();
        Ok(())
    }

    /// `*BOUNDARY_PRESCRIBED_MOTION_*`, sets expanded to one entry per node.
    fn motions(&self, m: &mut Model, ids: &Ids, part_nodes: &[Vec<u32>]) -> Result<(), DeckError> {
        let vectors: std::collections::HashMap<i64, usize> =
            self.index(&self.raw.vectors, "vector", |v| (v.id, &v.src))?;
        let frames = if self
            .raw
            .vectors
            .iter()
            .any(|v| v.cid.is_some_and(|c| c != 0))
        {
            Some(self.frames()?)
        } else {
            None
        };
        for p in &self.raw.motions {
            let curve = self.find(&ids.curves, p.lcid, &p.src, "LCID", "curve")?;
            let dof = match p.dof {
                RawDof::Axis(a) => MotionDof::Axis(a),
                RawDof::Rotation(a) => {
                    let mut dir = [0.0; 3];
                    dir[a] = 1.0;
                    MotionDof::Rotation { dir, only: false }
                }
                RawDof::Vector {
                    vid,
                    only,
                    rotation,
                } => {
                    let v = &self.raw.vectors[self.find(&vectors, vid, &p.src, "VID", "vector")?];
                    // a vector given in a local system: its direction in global axes
                    let dir = match (v.cid, &frames) {
                        (Some(cid), Some(frames)) if cid != 0 => {
                            let ax = self.frame(frames, cid, &v.src, "CID")?;
                            [0, 1, 2].map(|j| (0..3).map(|i| v.dir[i] * ax[i][j]).sum::<f64>())
                        }
                        _ => v.dir,
                    };
                    if rotation {
                        MotionDof::Rotation { dir, only }
                    } else {
                        MotionDof::Along { dir, only }
                    }
                }
            };
            let mk = |target| PrescribedMotion {
                window: p.window,
                target,
                dof,
                vad: p.vad,
                curve,
                sf: p.sf,
            };
            match p.target {
                Target::Part(id) if !ids.parts.contains_key(&id) => {
                    // LS-DYNA lets the PID of a nodal rigid body be named here
                    match m.nodal_rigid.iter().position(|b| b.id == id) {
                        Some(k) => m.prescribed.push(mk(MotionTarget::NodalRigid(k))),
                        None => {
                            return Err(self
                                .err(
                                    &p.src,
                                    format!("part {id} is not defined (nor a nodal rigid body)"),
                                )
                                .with_field("PID"))
                        }
                    }
                }
                Target::Part(id) => {
                    let part = self.find(&ids.parts, id, &p.src, "PID", "part")?;
                    let mat = &m.materials[m.parts[part].material];
                    if !matches!(mat.kind, MaterialKind::Rigid { .. }) {
                        return Err(self
                            .err(
                                &p.src,
                                format!(
                                    "part {id} is not rigid (its material {} is not *MAT_RIGID)",
                                    mat.id
                                ),
                            )
                            .with_field("PID"));
                    }
                    m.prescribed.push(mk(MotionTarget::Rigid(part)));
                }
                t => {
                    let field = if matches!(t, Target::Node(_)) {
                        "NID"
                    } else {
                        "NSID"
                    };
                    for node in self.target_nodes(t, &p.src, field, m, ids, part_nodes)? {
                        m.prescribed.push(mk(MotionTarget::Node(node)));
                    }
                }
            }
        }
        Ok(())
    }

    /// `*INITIAL_VELOCITY_*` in deck order (a later card overrides an earlier one per node):
    /// v = v_t + omega n x (x - c).
    fn initial_velocities(
        &self,
        m: &mut Model,
        ids: &Ids,
        part_nodes: &[Vec<u32>],
    ) -> Result<(), DeckError> {
        for iv in &self.raw.init_vel {
            let field = match (iv.target, iv.src.keyword.as_ref()) {
                (Target::Node(_), _) => "NID",
                (_, "*INITIAL_VELOCITY") => "NSID",
                _ => "ID",
            };
            for node in self.target_nodes(iv.target, &iv.src, field, m, ids, part_nodes)? {
                let i = node as usize;
                let w: Vec3 = iv.axis.map(|a| a * iv.omega);
                let rot = cross(w, sub(m.x0[i], iv.centre));
                m.v0[i] = [iv.v[0] + rot[0], iv.v[1] + rot[1], iv.v[2] + rot[2]];
            }
        }
        Ok(())
    }

    /// The slave side of a nodes-to-surface contact given as a node set (SSTYP 4): the exterior
    /// faces all of whose nodes are in the set, as a segment set of its own (the next free id),
    /// so the set's surface nodes are checked with their faces' normals (a
    /// node's facing test needs its surface). A set node on no such face (inside the body, or
    /// on a face the set covers only in part) is not checked: a warning counts them, and a
    /// set with no such face at all is an error.
    fn node_set_surface(
        &self,
        m: &mut Model,
        c: &crate::deck::raw::RawContact,
        ids: &Ids,
    ) -> Result<ContactSurface, DeckError> {
        use cleave_core::contact::surface::{exterior_faces, face_nodes};
        let id = c.slave.id.unwrap_or(0);
        let set = self.find(&ids.node_sets, id, &c.src, "SSID", "node set")?;
        let mut in_set = vec![false; m.num_nodes()];
        for &n in &m.node_sets[set].nodes {
            in_set[n as usize] = true;
        }
        let mut on_face = vec![false; m.num_nodes()];
        let mut segments = Vec::new();
        for (e, f) in exterior_faces(&m.conn, |_| true) {
            let nodes = face_nodes(&m.conn[e as usize], f);
            if nodes.iter().all(|&n| in_set[n as usize]) {
                for n in nodes {
                    on_face[n as usize] = true;
                }
                segments.push(nodes);
            }
        }
        if segments.is_empty() {
            return Err(self
                .err(
                    &c.src,
                    format!("node set {id}: no exterior face has all its nodes in the set, so no node of it can be checked for contact; give the slave side as parts or a segment set"),
                )
                .with_field("SSID"));
        }
        let off = m.node_sets[set]
            .nodes
            .iter()
            .filter(|&&n| !on_face[n as usize])
            .count();
        if off > 0 {
            self.warn(format!(
                "{}:{}: {}: {off} of node set {id}'s nodes lie on no exterior face whose nodes are all in the set, and are not checked for contact",
                c.src.file, c.src.line, c.src.keyword
            ));
        }
        // an id of its own, past the deck's (the writer writes it as a segment set)
        let id = m
            .segment_sets
            .iter()
            .map(|s| s.id)
            .max()
            .unwrap_or(0)
            .max(0)
            + 1;
        m.segment_sets.push(SegmentSet { id, segments });
        Ok(ContactSurface::SegmentSet(m.segment_sets.len() - 1))
    }

    fn surface(&self, s: &RawSurface, src: &Src, ids: &Ids) -> Result<ContactSurface, DeckError> {
        let Some(id) = s.id else {
            return Ok(ContactSurface::All);
        };
        Ok(match s.typ {
            0 => ContactSurface::SegmentSet(self.find(
                &ids.segment_sets,
                id,
                src,
                s.field,
                "segment set",
            )?),
            2 => {
                ContactSurface::PartSet(self.find(&ids.part_sets, id, src, s.field, "part set")?)
            }
            _ => ContactSurface::Part(self.find(&ids.parts, id, src, s.field, "part")?),
        })
    }
}

/// The sorted nodes of each part's elements.
fn part_nodes(m: &Model) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); m.parts.len()];
    for (c, &p) in m.conn.iter().zip(&m.elem_part) {
        out[p as usize].extend_from_slice(c);
    }
    for v in &mut out {
        v.sort_unstable();
        v.dedup();
    }
    out
}
