//! Rigid parts (`*MAT_RIGID`, with their extra nodes) and nodal rigid bodies
//! (`*CONSTRAINED_NODAL_RIGID_BODY`) as 6-dof rigid bodies.
//!
//! Mass, centre of mass and inertia come from the lumped nodal masses of the body's nodes, so
//! the kinetic energy summed over nodes equals the body's; a body with a given inertia
//! (`*PART_INERTIA`) adds the card's mass, whose kinetic energy and momentum the body books
//! itself ([`RigidBody::unlumped_motion`]). Each step:
//! - force and moment about the centre of mass are summed over the body's nodes;
//! - v_cm += F/M dt, angular momentum L += M dt (spatial frame), and the step's rotation
//!   R^(n+1) = cay(omega dt) R^n by the implicit mid-point rule (see [`RigidBody::update_angular`]);
//! - constraints (CON1/CON2 with CMO = 1) and prescribed motion fix components of v_cm and omega;
//! - the nodes are placed exactly: x_i^(n+1) = x_cm^(n+1) + R^(n+1) (X_i - X_cm), and given
//!   the velocity (x^(n+1) - x^n)/dt.

use crate::element::kernel::hughes_winget;
use crate::math::{
    add, cross, dot, inverse, mat_mul, mat_vec, norm, scale, sub, transpose, Mat3, Vec3,
};
use crate::model::{GivenInertia, MaterialKind, Model, PerNode};
use crate::state::RigidState;

/// What a rigid body is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyOf {
    /// A rigid part (part index): the nodes of its elements and its extra nodes
    /// (`*CONSTRAINED_EXTRA_NODES_...`).
    Part(usize),
    /// A nodal rigid body (index into `Model::nodal_rigid`): the nodes of its node set.
    Nodal(usize),
}

/// The mass of a body that none of its nodes carries (given on a card, `*PART_INERTIA`): its
/// mass, its centre and its second moment `J = sum m r r^T = tr(I)/2 1 - I` about the centre, in
/// the reference configuration. Its kinetic energy and momentum are the body's own terms
/// ([`RigidBody::unlumped_motion`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Unlumped {
    pub mass: f64,
    pub centre: Vec3,
    pub second_moment: Mat3,
}

/// What never changes about a rigid body.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidBody {
    pub of: BodyOf,
    /// Deck id: the part's, or the nodal rigid body's PID (0: none).
    pub id: i64,
    /// The body's nodes (sorted).
    pub nodes: Vec<u32>,
    /// Total mass: the nodes' lumped masses and the unlumped mass.
    pub mass: f64,
    /// Reference centre of mass.
    pub x_cm0: Vec3,
    /// Inertia tensor about the centre of mass in the reference configuration.
    pub inertia0: Mat3,
    /// Constrained translations x, y, z.
    pub fix_v: [bool; 3],
    /// Constrained rotations about x, y, z.
    pub fix_w: [bool; 3],
    /// Mass given on a card and carried by no node.
    pub unlumped: Option<Unlumped>,
    /// Initial velocity of the centre of mass and angular velocity given on a card (else
    /// from the nodal initial velocities).
    pub initial: Option<(Vec3, Vec3)>,
}

/// Sentinel for "not a rigid node".
pub const NOT_RIGID: u32 = u32::MAX;

/// One body to build: what it is, its id, its nodes, the nodes whose mass stays with them
/// under a given inertia, the given inertia and the CMO, CON1, CON2 constraint codes.
struct Def<'a> {
    of: BodyOf,
    id: i64,
    nodes: Vec<u32>,
    keep_mass: Vec<u32>,
    given: Option<&'a GivenInertia>,
    codes: (i32, i32, i32),
}

/// Build the rigid bodies of a model: one per part with a rigid material (the nodes of its
/// elements and its extra nodes) and one per nodal rigid body. Returns the bodies and, per
/// node, the index of its body or [`NOT_RIGID`].
///
/// A body with a given inertia (`*PART_INERTIA`, `_INERTIA`) takes the card's mass, centre and
/// inertia: its nodes' lumped masses are set to zero in `mass` (LS-DYNA: the given properties
/// hold them), except those of extra nodes with IFLAG 1, which are added to the given ones.
pub fn build_rigid_bodies(
    model: &Model,
    mass: &mut [f64],
) -> Result<(Vec<RigidBody>, Vec<u32>), String> {
    let mut defs: Vec<Def<'_>> = Vec::new();
    let mut part_def = vec![usize::MAX; model.parts.len()];
    for (p, part) in model.parts.iter().enumerate() {
        let mat = &model.materials[part.material];
        let MaterialKind::Rigid { cmo, con1, con2 } = mat.kind else {
            continue;
        };
        part_def[p] = defs.len();
        defs.push(Def {
            of: BodyOf::Part(p),
            id: part.id,
            nodes: Vec::new(),
            keep_mass: Vec::new(),
            given: None,
            codes: (cmo, con1, con2),
        });
    }
    for (e, conn) in model.conn.iter().enumerate() {
        let d = part_def[model.elem_part[e] as usize];
        if d != usize::MAX {
            defs[d].nodes.extend_from_slice(conn);
        }
    }
    for x in &model.extra_nodes {
        let d = part_def[x.part];
        if d == usize::MAX {
            return Err(format!(
                "extra nodes on part {}, which is not rigid",
                model.parts[x.part].id
            ));
        }
        defs[d].nodes.extend_from_slice(&x.nodes);
        if x.iflag {
            defs[d].keep_mass.extend_from_slice(&x.nodes);
        }
    }
    for pi in &model.part_inertia {
        let d = part_def[pi.part];
        if d == usize::MAX {
            return Err(format!(
                "*PART_INERTIA on part {}, which is not rigid",
                model.parts[pi.part].id
            ));
        }
        defs[d].given = Some(&pi.given);
    }
    for (k, nb) in model.nodal_rigid.iter().enumerate() {
        defs.push(Def {
            of: BodyOf::Nodal(k),
            id: nb.id,
            nodes: model.node_sets[nb.set].nodes.clone(),
            keep_mass: Vec::new(),
            given: nb.inertia.as_ref(),
            codes: (nb.cmo, nb.con1, nb.con2),
        });
    }

    let mut node_body = vec![NOT_RIGID; model.num_nodes()];
    let mut bodies: Vec<RigidBody> = Vec::new();
    let name = |of: BodyOf, id: i64| match of {
        BodyOf::Part(_) => format!("rigid part {id}"),
        BodyOf::Nodal(_) => format!("nodal rigid body {id}"),
    };
    for mut def in defs {
        def.nodes.sort_unstable();
        def.nodes.dedup();
        if def.nodes.is_empty() {
            continue; // a rigid part with no elements and no extra nodes: nothing to move
        }
        let b = bodies.len() as u32;
        for &n in &def.nodes {
            let nb = node_body[n as usize];
            if nb != NOT_RIGID {
                let other = &bodies[nb as usize];
                return Err(format!(
                    "node {} belongs to two rigid bodies ({} and {}); merging rigid bodies is not supported",
                    model.node_ids[n as usize],
                    name(other.of, other.id),
                    name(def.of, def.id)
                ));
            }
            node_body[n as usize] = b;
        }
        if def.given.is_some() {
            def.keep_mass.sort_unstable();
            for &n in &def.nodes {
                if def.keep_mass.binary_search(&n).is_err() {
                    mass[n as usize] = 0.0;
                }
            }
        }
        let nodes = def.nodes;
        let m_nodes: f64 = nodes.iter().map(|&n| mass[n as usize]).sum();
        let m_given = def.given.map_or(0.0, |g| g.mass);
        let m = m_nodes + m_given;
        if m <= 0.0 || !m.is_finite() {
            return Err(format!("{} has no mass", name(def.of, def.id)));
        }
        let mut xc = def.given.map_or([0.0; 3], |g| scale(g.centre, g.mass));
        for &n in &nodes {
            xc = add(xc, scale(model.x0[n as usize], mass[n as usize]));
        }
        xc = scale(xc, 1.0 / m);
        let mut inertia = [[0.0; 3]; 3];
        let mut add_point = |r: Vec3, mi: f64| {
            // a massless node (an extra node off the mesh) adds nothing, however far it lies
            if mi == 0.0 {
                return;
            }
            let rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
            for i in 0..3 {
                for j in 0..3 {
                    let d = if i == j { rr } else { 0.0 };
                    inertia[i][j] += mi * (d - r[i] * r[j]);
                }
            }
        };
        for &n in &nodes {
            add_point(sub(model.x0[n as usize], xc), mass[n as usize]);
        }
        let mut unlumped = None;
        let mut initial = None;
        if let Some(g) = def.given {
            add_point(sub(g.centre, xc), g.mass);
            for (row, given) in inertia.iter_mut().zip(&g.inertia) {
                for (a, b) in row.iter_mut().zip(given) {
                    *a += b;
                }
            }
            let half_trace = 0.5 * (g.inertia[0][0] + g.inertia[1][1] + g.inertia[2][2]);
            let mut j = g.inertia.map(|row| row.map(|v| -v));
            for (i, row) in j.iter_mut().enumerate() {
                row[i] += half_trace;
            }
            unlumped = Some(Unlumped {
                mass: g.mass,
                centre: g.centre,
                second_moment: j,
            });
            // the card's velocities are those of its centre
            let v_cm = add(g.velocity, cross(g.omega, sub(xc, g.centre)));
            initial = Some((v_cm, g.omega));
        }
        // a node or a given centre so far out that the second moments overflow
        if !(xc.iter().all(|v| v.is_finite()) && inertia.iter().flatten().all(|v| v.is_finite())) {
            return Err(format!(
                "{} has a non-finite centre of mass or inertia (centre {xc:?}): its nodes or its given centre of mass lie too far apart",
                name(def.of, def.id)
            ));
        }
        let (cmo, con1, con2) = def.codes;
        let (fix_v, fix_w) = if cmo == 1 {
            (crate::model::dof_code(con1), crate::model::dof_code(con2))
        } else {
            ([false; 3], [false; 3])
        };
        bodies.push(RigidBody {
            of: def.of,
            id: def.id,
            nodes,
            mass: m,
            x_cm0: xc,
            inertia0: inertia,
            fix_v,
            fix_w,
            unlumped,
            initial,
        });
    }
    Ok((bodies, node_body))
}

/// The skew matrix of `w`: `skew(w) r = w x r`.
fn skew(w: Vec3) -> Mat3 {
    [[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]]
}

/// `tr(A J B^T)`.
fn trace_ajb(a: &Mat3, j: &Mat3, b: &Mat3) -> f64 {
    let aj = mat_mul(a, j);
    let mut t = 0.0;
    for i in 0..3 {
        for k in 0..3 {
            t += aj[i][k] * b[i][k];
        }
    }
    t
}

impl RigidBody {
    /// Spatial inertia I = R I0 R^T.
    pub fn inertia(&self, rot: &Mat3) -> Mat3 {
        mat_mul(&mat_mul(rot, &self.inertia0), &transpose(rot))
    }

    /// Initial state from the nodal initial velocities: v_cm the mass-weighted mean and
    /// omega = I^-1 L with L the angular momentum of the nodal velocities about the centre.
    pub fn initial_state(
        &self,
        x0: &PerNode<Vec3>,
        v0: &PerNode<Vec3>,
        mass: &[f64],
    ) -> RigidState {
        // the given velocities (`*PART_INERTIA`), else those of the nodes
        let (v_cm, omega, ang_mom) = match self.initial {
            Some((v_cm, omega)) => (v_cm, omega, mat_vec(&self.inertia0, omega)),
            None => {
                let mut p = [0.0; 3];
                for &n in &self.nodes {
                    p = add(p, scale(v0[n as usize], mass[n as usize]));
                }
                let v_cm = scale(p, 1.0 / self.mass);
                let mut l = [0.0; 3];
                for &n in &self.nodes {
                    let r = sub(x0[n as usize], self.x_cm0);
                    l = add(
                        l,
                        scale(cross(r, sub(v0[n as usize], v_cm)), mass[n as usize]),
                    );
                }
                let omega = inverse(&self.inertia0).map_or([0.0; 3], |inv| mat_vec(&inv, l));
                (v_cm, omega, l)
            }
        };
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mut st = RigidState {
            x_cm: self.x_cm0,
            v_cm,
            rot: id,
            ang_mom,
            omega,
            prev_x_cm: self.x_cm0,
            prev_rot: id,
            v0: v_cm,
            omega0: omega,
        };
        self.apply_constraints(&mut st);
        st.v0 = st.v_cm;
        st.omega0 = st.omega;
        st
    }

    /// Zero the constrained components of v_cm and omega (and make L consistent).
    pub fn apply_constraints(&self, st: &mut RigidState) {
        for i in 0..3 {
            if self.fix_v[i] {
                st.v_cm[i] = 0.0;
            }
        }
        if self.fix_w.iter().any(|&f| f) {
            for i in 0..3 {
                if self.fix_w[i] {
                    st.omega[i] = 0.0;
                }
            }
            st.ang_mom = mat_vec(&self.inertia(&st.rot), st.omega);
        }
    }

    /// Advance the angular momentum by the moment `m` over `dt_mid` and find the angular
    /// velocity omega of the step `dt` (t^n to t^(n+1)).
    ///
    /// Implicit mid-point rule for Euler's equations in the body frame (Pi = R^T L,
    /// Omega = I0^-1 Pi): Omega = I0^-1 (Pi^n + Pi^(n+1)) / 2 with R^(n+1) = R^n cay(dt Omega),
    /// i.e. in the spatial frame omega = I(R^n)^-1 (L + Q^T L) / 2, Q = cay(omega dt), solved by
    /// fixed-point iteration. It conserves |L| and the rotational kinetic energy
    /// L . I(R)^-1 L / 2 of a torque-free body exactly. (The explicit omega = I(R^n)^-1 L used
    /// before is first order: a tumbling body's kinetic energy drifted in proportion to dt,
    /// 5e-4 of the rotational energy over 1.5 turns at omega dt = 1.6e-3.)
    pub fn update_angular(&self, st: &mut RigidState, moment: Vec3, dt_mid: f64, dt: f64) {
        st.ang_mom = add(st.ang_mom, scale(moment, dt_mid));
        let Some(inv) = inverse(&self.inertia(&st.rot)) else {
            st.omega = [0.0; 3];
            return;
        };
        let l = st.ang_mom;
        let mut omega = mat_vec(&inv, l);
        for _ in 0..50 {
            let q = cayley(scale(omega, dt));
            let next = mat_vec(&inv, scale(add(l, mat_vec(&transpose(&q), l)), 0.5));
            let change = norm(sub(next, omega));
            omega = next;
            if change <= 1e-15 * norm(omega) {
                break;
            }
        }
        st.omega = omega;
    }

    /// Position of node with reference position `x_ref` for the rigid placement (`x_cm`, `rot`).
    #[inline]
    pub fn place(&self, x_cm: Vec3, rot: &Mat3, x_ref: Vec3) -> Vec3 {
        add(x_cm, mat_vec(rot, sub(x_ref, self.x_cm0)))
    }

    /// The unlumped mass's share of the leapfrog kinetic energy at t^n and its momenta at
    /// t^(n-1/2) and t^(n+1/2), for a body placed at t^n by `st` (its velocities those of the
    /// step `dt` after t^n), at `(prev_x_cm, prev_rot)` at t^(n-1) (`dt_prev` before). As the
    /// nodes' `K^n = 1/2 sum m v^(n-1/2) . v^(n+1/2)` with `v = dx/dt`, for a mass M at the
    /// centre c with second moment J: `1/2 M c'^- . c'^+ + 1/2 tr(R'^- J R'^+^T)`, the rates
    /// the differences of the placements over their steps. At the first step (`first`) the
    /// rate before t^0 is `2 r'^0 - r'^+` (`r'^0` from the initial velocities), as for nodes.
    /// Zero for a body without an unlumped mass.
    pub fn unlumped_motion(
        &self,
        st: &RigidState,
        dt_prev: f64,
        dt: f64,
        first: bool,
    ) -> (f64, Vec3, Vec3) {
        let Some(u) = &self.unlumped else {
            return (0.0, [0.0; 3], [0.0; 3]);
        };
        if dt <= 0.0 {
            return (0.0, [0.0; 3], [0.0; 3]);
        }
        let (x1, r1) = self.next_placement(st, dt);
        let arm = sub(u.centre, self.x_cm0);
        let centre = |x: Vec3, r: &Mat3| add(x, mat_vec(r, arm));
        let c0 = centre(st.x_cm, &st.rot);
        let rate = |a: &Mat3, b: &Mat3, h: f64| -> Mat3 {
            std::array::from_fn(|i| std::array::from_fn(|k| (a[i][k] - b[i][k]) / h))
        };
        let c_new = scale(sub(centre(x1, &r1), c0), 1.0 / dt);
        let a_new = rate(&r1, &st.rot, dt);
        let (c_old, a_old) = if first || dt_prev <= 0.0 {
            let c_init = add(st.v0, cross(st.omega0, mat_vec(&st.rot, arm)));
            let a_init = mat_mul(&skew(st.omega0), &st.rot);
            (
                sub(scale(c_init, 2.0), c_new),
                std::array::from_fn(|i| std::array::from_fn(|k| 2.0 * a_init[i][k] - a_new[i][k])),
            )
        } else {
            let cp = centre(st.prev_x_cm, &st.prev_rot);
            (
                scale(sub(c0, cp), 1.0 / dt_prev),
                rate(&st.rot, &st.prev_rot, dt_prev),
            )
        };
        let ke =
            0.5 * u.mass * dot(c_old, c_new) + 0.5 * trace_ajb(&a_old, &u.second_moment, &a_new);
        (ke, scale(c_old, u.mass), scale(c_new, u.mass))
    }

    /// The centre of the unlumped mass for the placement (`x_cm`, `rot`), if the body has one.
    pub fn unlumped_centre(&self, x_cm: Vec3, rot: &Mat3) -> Option<(Vec3, f64)> {
        self.unlumped
            .as_ref()
            .map(|u| (self.place(x_cm, rot, u.centre), u.mass))
    }

    /// The placement at t^(n+1) after a step `dt` with the half-step velocities:
    /// R^(n+1) = cay(omega dt) R^n (the Cayley transform, matching `update_angular`).
    pub fn next_placement(&self, st: &RigidState, dt: f64) -> (Vec3, Mat3) {
        let rot = mat_mul(&cayley(scale(st.omega, dt)), &st.rot);
        (add(st.x_cm, scale(st.v_cm, dt)), rot)
    }
}

/// Cayley transform cay(a) = (I - A/2)^-1 (I + A/2) of the rotation vector `a`: a rotation
/// about a by 2 atan(|a|/2) (the Hughes-Winget rotation of the element kernel).
#[inline]
fn cayley(a: Vec3) -> Mat3 {
    hughes_winget(scale(a, 0.5))
}
