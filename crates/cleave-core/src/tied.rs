//! Tied contact (`*CONTACT_TIED_SURFACE_TO_SURFACE`, `*CONTACT_TIED_NODES_TO_SURFACE`), in
//! LS-DYNA's constraint form without offset: a slave node that lies on a master face at the
//! start is moved onto it and from then on moves with it. It joins meshes that do not match
//! across an interface (a fine part on a coarse one).
//!
//! - **Search**, once: for each slave node that is not itself a node of a master face, the
//!   master face nearest to it. The point is projected onto the face's bilinear surface
//!   `x(xi, eta) = sum_a N_a(xi, eta) x_a` by Gauss-Newton from the centre. The node is tied to
//!   the face when the projection lies on it (`|xi|, |eta| <= 1 + 1e-6`) within [`TOLERANCE`]
//!   of its shorter diagonal. A slave node that finds no face stays free; the count is
//!   reported (`Ties::untied`). Each slave node is tested against every master face's box
//!   (slaves times faces box tests, once per run: fine for interfaces of thousands of faces;
//!   much larger ones would want a spatial grid).
//! - **Constraint** (kinematic, [`crate::solver::Solver`]): the slave node's mass goes to the
//!   face's nodes with the weights `N_a(xi, eta)` (`m_a += N_a m_s`, `m_s = 0`), and so does
//!   its force after each force assembly (`f_a += N_a f_s`). After the velocity update its
//!   velocity is the face's at the point, `v_s = sum_a N_a v_a`. Placed on the face at the
//!   start, it stays there exactly (`x_s = sum_a N_a x_a` is kept by the linear update). The
//!   constraint does no work: `sum_a N_a f_s . v_a = f_s . v_s`.
//! - A slave node may carry no SPC, prescribed motion or rigid body of its own, nor may the
//!   face's nodes belong to a rigid body (errors naming the node); separation is refused where
//!   it is set up. The GPU step runs the same constraint (cleave-gpu, `tied` in step.wgsl).

use crate::contact::surface::{exterior_faces, side_faces, FaceId};
use crate::element::shape::face_corners;
use crate::math::{add, dot, norm, scale, sub, Vec3};
use crate::model::{Model, TiedDef, TiedSlave};

/// A slave node is tied when it lies within this fraction of the face's shorter diagonal
/// from it (LS-DYNA's tolerances are of the same order; the deck's SST/MST are not read).
pub const TOLERANCE: f64 = 0.05;

/// One slave node and the face point it follows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tie {
    pub slave: u32,
    pub masters: [u32; 4],
    pub weights: [f64; 4],
}

/// The ties of all tied contacts of a model.
#[derive(Clone, Debug, Default)]
pub struct Ties {
    pub ties: Vec<Tie>,
    /// Per definition (deck order): its id and how many slave nodes found no face.
    pub untied: Vec<(i64, usize)>,
}

/// Bilinear shape functions of a face at (xi, eta), corners in order around it.
fn shape(xi: f64, eta: f64) -> [f64; 4] {
    [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ]
}

/// The projection of `p` onto the bilinear face `x`: (xi, eta) and the distance.
fn project(x: &[Vec3; 4], p: Vec3) -> (f64, f64, f64) {
    let (mut xi, mut eta) = (0.0, 0.0);
    for _ in 0..30 {
        let n = shape(xi, eta);
        let at = (0..4).fold([0.0; 3], |s, a| add(s, scale(x[a], n[a])));
        let r = sub(at, p);
        // dx/dxi and dx/deta
        let gx = add(
            scale(sub(x[1], x[0]), 0.25 * (1.0 - eta)),
            scale(sub(x[2], x[3]), 0.25 * (1.0 + eta)),
        );
        let ge = add(
            scale(sub(x[3], x[0]), 0.25 * (1.0 - xi)),
            scale(sub(x[2], x[1]), 0.25 * (1.0 + xi)),
        );
        let (a, b, c) = (dot(gx, gx), dot(gx, ge), dot(ge, ge));
        let det = a * c - b * b;
        if det <= 0.0 {
            break;
        }
        let (rx, re) = (dot(gx, r), dot(ge, r));
        let dxi = -(c * rx - b * re) / det;
        let deta = -(a * re - b * rx) / det;
        xi = (xi + dxi).clamp(-2.0, 2.0);
        eta = (eta + deta).clamp(-2.0, 2.0);
        if dxi.abs() + deta.abs() < 1e-14 {
            break;
        }
    }
    let n = shape(xi, eta);
    let at = (0..4).fold([0.0; 3], |s, a| add(s, scale(x[a], n[a])));
    (xi, eta, norm(sub(at, p)))
}

/// The nodes of faces `faces`, in face order around each.
fn face_nodes(model: &Model, f: FaceId) -> [u32; 4] {
    let c = &model.conn[f.0 as usize];
    face_corners(c, f.1 as usize).map(|k| c[k])
}

impl Ties {
    /// The ties of `model`'s tied contacts at positions `x` (the model's own).
    pub fn new(model: &Model) -> Result<Self, String> {
        let mut out = Ties::default();
        if model.tied.is_empty() {
            return Ok(out);
        }
        let exterior = exterior_faces(&model.conn, |_| true);
        let mut is_slave = vec![false; model.num_nodes()];
        for def in &model.tied {
            let (ties, untied) = tie(model, def, &exterior)?;
            for t in &ties {
                if is_slave[t.slave as usize] {
                    return Err(format!(
                        "tied contact {}: node {} is tied twice (in two tied contacts)",
                        def.id, model.node_ids[t.slave as usize]
                    ));
                }
                is_slave[t.slave as usize] = true;
            }
            out.ties.extend(ties);
            out.untied.push((def.id, untied));
        }
        // a master node that is itself a slave would chain constraints
        for t in &out.ties {
            if let Some(&m) = t.masters.iter().find(|&&m| is_slave[m as usize]) {
                return Err(format!(
                    "node {} is a slave node of a tied contact and a node of the face node {} is tied to: chained ties are not supported",
                    model.node_ids[m as usize], model.node_ids[t.slave as usize]
                ));
            }
        }
        Ok(out)
    }
}

/// The ties of one definition, and how many slave nodes found no face.
fn tie(model: &Model, def: &TiedDef, exterior: &[FaceId]) -> Result<(Vec<Tie>, usize), String> {
    let master = side_faces(model, &model.conn, None, exterior, &def.master)
        .map_err(|e| format!("tied contact {}: {e}", def.id))?;
    let mut on_master = vec![false; model.num_nodes()];
    let faces: Vec<[u32; 4]> = master.iter().map(|&f| face_nodes(model, f)).collect();
    faces
        .iter()
        .flatten()
        .for_each(|&n| on_master[n as usize] = true);
    let mut slaves: Vec<u32> = match &def.slave {
        TiedSlave::NodeSet(s) => model.node_sets[*s].nodes.clone(),
        TiedSlave::Surface(side) => {
            let f = side_faces(model, &model.conn, None, exterior, side)
                .map_err(|e| format!("tied contact {}: {e}", def.id))?;
            f.iter().flat_map(|&f| face_nodes(model, f)).collect()
        }
    };
    slaves.sort_unstable();
    slaves.dedup();
    slaves.retain(|&n| !on_master[n as usize]);
    let x = &model.x0;
    // each face's corners, shorter diagonal and box widened by the tolerance
    let geo: Vec<([Vec3; 4], f64, [Vec3; 2])> = faces
        .iter()
        .map(|f| {
            let p = f.map(|n| x[n as usize]);
            let d = norm(sub(p[2], p[0])).min(norm(sub(p[3], p[1])));
            let tol = TOLERANCE * d;
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for q in &p {
                for k in 0..3 {
                    lo[k] = lo[k].min(q[k] - tol);
                    hi[k] = hi[k].max(q[k] + tol);
                }
            }
            (p, d, [lo, hi])
        })
        .collect();
    let mut ties = Vec::with_capacity(slaves.len());
    let mut untied = 0;
    for &s in &slaves {
        let p = x[s as usize];
        let mut best: Option<(f64, usize, f64, f64)> = None;
        for (k, (corners, diag, bx)) in geo.iter().enumerate() {
            if (0..3).any(|i| p[i] < bx[0][i] || p[i] > bx[1][i]) {
                continue;
            }
            let (xi, eta, dist) = project(corners, p);
            let inside = xi.abs() <= 1.0 + 1e-6 && eta.abs() <= 1.0 + 1e-6;
            if inside && dist <= TOLERANCE * diag && best.is_none_or(|b| dist < b.0) {
                best = Some((dist, k, xi, eta));
            }
        }
        match best {
            Some((_, k, xi, eta)) => ties.push(Tie {
                slave: s,
                masters: faces[k],
                weights: shape(xi.clamp(-1.0, 1.0), eta.clamp(-1.0, 1.0)),
            }),
            None => untied += 1,
        }
    }
    Ok((ties, untied))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_onto_a_warped_face() {
        // a unit square lifted at one corner; the point above (0.25, 0.5) at height 0.01
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.1],
            [0.0, 1.0, 0.0],
        ];
        let (xi, eta, d) = project(&x, [0.25, 0.5, 0.5 * 0.25 * 0.1 + 0.01]);
        let n = shape(xi, eta);
        let at = (0..4).fold([0.0; 3], |s, a| add(s, scale(x[a], n[a])));
        // the point is near (0.25, 0.5) on the surface, 0.01 off it
        assert!(
            (at[0] - 0.25).abs() < 2e-3 && (at[1] - 0.5).abs() < 2e-3,
            "{at:?}"
        );
        assert!((d - 0.01).abs() < 1e-3, "{d}");
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        // a point beyond an edge projects outside [-1, 1]
        let (xi, _, _) = project(&x, [1.5, 0.5, 0.0]);
        assert!(xi > 1.0, "{xi}");
    }
}
