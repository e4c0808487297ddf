//! Preprocessing done once before the first step: lumped masses, per-material kernel
//! parameters, rigid bodies and the constraint lists.

use crate::element::{self, shape::shape_of, Shape};
use crate::material::{free_element_speed, SolidParams};
use crate::math::Vec3;
use crate::model::{Model, MotionTarget, PrescribedMotion};
use crate::rigid::{build_rigid_bodies, BodyOf, RigidBody, NOT_RIGID};

/// Everything derived from the model that the step loop reads.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Lumped nodal mass: each element gives rho V / n to each of its n distinct nodes (V
    /// exact; n = 8, 6, 4 for a hexahedron, a wedge, a tetrahedron); zero at the nodes of a
    /// body with a given inertia (`*PART_INERTIA`: [`build_rigid_bodies`]).
    pub mass: Vec<f64>,
    /// Shape of each element (which kernel runs it).
    pub elem_shape: Vec<Shape>,
    /// Kernel parameters per material (None: rigid).
    pub params: Vec<Option<SolidParams>>,
    /// The same with the free-element step speed, for elements of a split mesh that have lost
    /// a neighbour ([`free_element_speed`]).
    pub loose_params: Vec<Option<SolidParams>>,
    /// Material index of each element.
    pub elem_mat: Vec<u32>,
    /// The hexahedra and wedges that share no face with another element: they run with
    /// `loose_params` from the start ([`crate::topology::lone_elements`]).
    pub lone: Vec<bool>,
    pub rigid: Vec<RigidBody>,
    /// Rigid body of each node, or `NOT_RIGID`.
    pub node_rigid: Vec<u32>,
    /// Per-node translational SPC (only non-rigid nodes with at least one fixed dof).
    pub spc: Vec<(u32, [bool; 3])>,
    /// Prescribed motion on nodes.
    pub node_motion: Vec<PrescribedMotion>,
    /// Prescribed motion on rigid bodies, with the body index as target.
    pub rigid_motion: Vec<(usize, PrescribedMotion)>,
    /// Slave nodes of each rigid wall (rigid-body nodes excluded).
    pub wall_nodes: Vec<Vec<u32>>,
    /// Messages worth showing the user.
    pub warnings: Vec<String>,
}

impl Setup {
    pub fn new(model: &Model) -> Result<Self, String> {
        let nn = model.num_nodes();
        let ne = model.num_elements();
        let mut mass = vec![0.0; nn];
        let mut elem_shape = Vec::with_capacity(ne);
        for (e, conn) in model.conn.iter().enumerate() {
            let shape = shape_of(conn).ok_or_else(|| {
                format!(
                    "element {}: repeated nodes in a pattern that is not a hexahedron, wedge or tetrahedron",
                    model.elem_ids[e]
                )
            })?;
            let xe: [Vec3; 8] = std::array::from_fn(|a| model.x0[conn[a] as usize]);
            let vol = element::volume(shape, &xe);
            if vol.is_nan() || vol <= 0.0 {
                return Err(format!(
                    "element {} has a non-positive volume",
                    model.elem_ids[e]
                ));
            }
            let share = model.element_material(e).density * vol / shape.nodes() as f64;
            for &a in shape.corners() {
                mass[conn[a] as usize] += share;
            }
            elem_shape.push(shape);
        }

        let params: Vec<Option<SolidParams>> = model
            .materials
            .iter()
            .map(SolidParams::from_material)
            .collect();
        let loose_params = model
            .materials
            .iter()
            .map(|m| {
                SolidParams::from_material(m).map(|p| SolidParams {
                    step_speed: free_element_speed(m),
                    ..p
                })
            })
            .collect();
        let elem_mat: Vec<u32> = (0..ne)
            .map(|e| model.parts[model.elem_part[e] as usize].material as u32)
            .collect();
        let (rigid, node_rigid) = build_rigid_bodies(model, &mut mass)?;
        if params
            .iter()
            .enumerate()
            .all(|(k, p)| p.is_none() || !elem_mat.contains(&(k as u32)))
            && model.control.dt_init <= 0.0
        {
            return Err("the model has no deformable element to set the time step: give DTINIT in *CONTROL_TIMESTEP".into());
        }

        let mut warnings = Vec::new();
        let mut spc = Vec::new();
        for s in &model.spcs {
            if node_rigid[s.node as usize] != NOT_RIGID {
                warnings.push(format!(
                    "SPC on node {} ignored: it belongs to a rigid body (use CON1/CON2 of *MAT_RIGID, or the _SPC option of *CONSTRAINED_NODAL_RIGID_BODY)",
                    model.node_ids[s.node as usize]
                ));
                continue;
            }
            let d = [s.dof[0], s.dof[1], s.dof[2]];
            if d.iter().any(|&b| b) {
                spc.push((s.node, d));
            }
        }
        let mut node_motion = Vec::new();
        let mut rigid_motion = Vec::new();
        for pm in &model.prescribed {
            match pm.target {
                MotionTarget::Node(n) => {
                    if node_rigid[n as usize] != NOT_RIGID {
                        return Err(format!(
                            "prescribed motion on node {} which belongs to a rigid body: use *BOUNDARY_PRESCRIBED_MOTION_RIGID",
                            model.node_ids[n as usize]
                        ));
                    }
                    node_motion.push(pm.clone());
                }
                MotionTarget::Rigid(p) => {
                    let b = rigid
                        .iter()
                        .position(|b| b.of == BodyOf::Part(p))
                        .ok_or_else(|| {
                            format!("prescribed rigid motion on part {} which is not a rigid part with nodes", model.parts[p].id)
                        })?;
                    rigid_motion.push((b, pm.clone()));
                }
                MotionTarget::NodalRigid(k) => {
                    let b = rigid
                        .iter()
                        .position(|b| b.of == BodyOf::Nodal(k))
                        .ok_or_else(|| {
                            format!(
                                "prescribed rigid motion on nodal rigid body {} which has no nodes",
                                model.nodal_rigid[k].id
                            )
                        })?;
                    rigid_motion.push((b, pm.clone()));
                }
            }
        }
        let wall_nodes = model
            .rigid_walls
            .iter()
            .map(|w| {
                let all: Vec<u32>;
                let nodes = match &w.nodes {
                    Some(n) => n,
                    None => {
                        all = (0..nn as u32).collect();
                        &all
                    }
                };
                nodes
                    .iter()
                    .copied()
                    .filter(|&n| node_rigid[n as usize] == NOT_RIGID && mass[n as usize] > 0.0)
                    .collect()
            })
            .collect();
        Ok(Self {
            mass,
            elem_shape,
            params,
            loose_params,
            elem_mat,
            lone: crate::topology::lone_elements(model),
            rigid,
            node_rigid,
            spc,
            node_motion,
            rigid_motion,
            wall_nodes,
            warnings,
        })
    }
}

/// The stable time step of the undeformed model at rest (TSSFAC applied) and the element that
/// controls it, or `None` if the model has no deformable element.
pub fn estimate_time_step(model: &Model) -> Option<(f64, usize)> {
    let mut best: Option<(f64, usize)> = None;
    let lone = crate::topology::lone_elements(model);
    for (e, conn) in model.conn.iter().enumerate() {
        let m = model.element_material(e);
        let Some(mut p) = SolidParams::from_material(m) else {
            continue;
        };
        if lone[e] {
            p.step_speed = free_element_speed(m);
        }
        let Some(shape) = shape_of(conn) else {
            continue;
        };
        let xe: [Vec3; 8] = std::array::from_fn(|a| model.x0[conn[a] as usize]);
        let lc = element::characteristic_length(shape, &xe);
        let dt = model.control.tssfac * lc / p.step_speed;
        if best.is_none_or(|(b, _)| dt < b) {
            best = Some((dt, e));
        }
    }
    best
}

/// Number of connected pieces of the mesh (elements joined through shared nodes).
pub fn count_components(model: &Model) -> usize {
    crate::topology::element_components(model).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_model;
    use crate::model::{Material, MaterialKind};

    #[test]
    fn rigid_only_model_needs_dtinit() {
        let rigid = Material {
            id: 1,
            density: 7800.0,
            young: 2e11,
            poisson: 0.3,
            kind: MaterialKind::Rigid {
                cmo: 0,
                con1: 0,
                con2: 0,
            },
        };
        let mut m = box_model([1, 1, 1], [1.0, 1.0, 1.0], rigid, 1.0);
        let err = Setup::new(&m).unwrap_err();
        assert!(err.contains("DTINIT"), "{err}");
        m.control.dt_init = 1e-3;
        assert!(Setup::new(&m).is_ok());
        assert!(estimate_time_step(&m).is_none());
    }
}
