//! What the GPU step does not run yet: a deck that asks for it is refused by name.
//!
//! Runs on the GPU: one-point hexahedra and wedges (ELFORM 1) with viscous or stiffness
//! hourglass control, fully integrated selectively reduced hexahedra (ELFORM 2), constant-strain tetrahedra (ELFORM 1 and 10) and tetrahedra with nodal
//! pressure averaging (ELFORM 13), bulk viscosity (global or
//! each part's `*HOURGLASS`), `*MAT_ELASTIC`, `*MAT_PLASTIC_KINEMATIC`, `*MAT_JOHNSON_COOK` /
//! `*MAT_SIMPLIFIED_JOHNSON_COOK` (with their equations of state),
//! `*MAT_PIECEWISE_LINEAR_PLASTICITY` (curve or table), rigid bodies (`*MAT_RIGID` parts with
//! their extra nodes, `*CONSTRAINED_NODAL_RIGID_BODY`, their constraints and prescribed
//! motion, a given inertia: `*PART_INERTIA`, `_INERTIA`), the time step (TSSFAC, DTINIT, DTMIN, ENDTIM),
//! `*LOAD_BODY`, `*LOAD_NODE_...` and `*LOAD_SEGMENT...`, SPC and
//! `*BOUNDARY_PRESCRIBED_MOTION_NODE`/`_SET`, up to 8 rigid walls (`*RIGIDWALL_PLANAR`, `_FINITE`, `*RIGIDWALL_GEOMETRIC_...` fixed or moving), tied contact
//! (`*CONTACT_TIED_...`), automatic contact (`*CONTACT_AUTOMATIC_...`, `*CONTACT_ERODING_...`,
//! with friction; with element separation, the crack faces joining the surfaces and closed
//! cracks: `crate::contact`), element erosion
//! (every rule: FAIL, FS, PSFAIL, Johnson-Cook damage, `*MAT_ADD_EROSION`), element separation
//! with every MODEL (with rigid bodies whose nodes are in no separation group, and with erosion
//! in other materials: `crate::separation`), the
//! energy ledger, and every output (states and histories are read back at their times).

use cleave_core::element::Shape;
use cleave_core::model::{MaterialKind, Model};
use cleave_core::rigid::NOT_RIGID;
use cleave_core::setup::Setup;
use cleave_core::solver::Solver;

/// The first feature of `model` that the GPU step does not run, as a phrase for the message
/// "`--gpu` does not run X yet"; `None` when the whole deck runs on the GPU.
pub fn unsupported(model: &Model, setup: &Setup) -> Option<String> {
    if model.num_elements() == 0 {
        return Some("a model without solid elements".into());
    }
    if !model.separations.is_empty() {
        let with = |what: &str| Some(format!("{what} together with element separation"));
        if !model.tied.is_empty() {
            return with("tied contact");
        }
        // a rigid body's node on an element of a group (the deck as written; in the split model
        // the copies are tied to it: `unsupported_split`)
        let grouped: Vec<usize> = model.separations.iter().map(|s| s.material).collect();
        for (e, c) in model.conn.iter().enumerate() {
            let part = &model.parts[model.elem_part[e] as usize];
            if !grouped.contains(&part.material) {
                continue;
            }
            if let Some(&n) = c
                .iter()
                .find(|&&n| setup.node_rigid[n as usize] != NOT_RIGID)
            {
                return Some(bonded(model, n as usize));
            }
        }
    }
    if model.rigid_walls.len() > crate::layout::MAX_WALLS {
        return Some(format!(
            "more than {} rigid walls (*RIGIDWALL_PLANAR)",
            crate::layout::MAX_WALLS
        ));
    }
    for (e, shape) in setup.elem_shape.iter().enumerate() {
        let part = &model.parts[model.elem_part[e] as usize];
        let elform = model.sections[part.section].elform;
        // hexahedra run the one-point hexahedron (ELFORM 1) or the selectively reduced one
        // (ELFORM 2), wedges the one-point one, tetrahedra the constant-strain one (ELFORM 1
        // and 10 alike, as on the CPU) or ELFORM 13
        let runs = match shape {
            Shape::Hex => elform == 1 || elform == 2,
            Shape::Wedge => elform == 1,
            Shape::Tet => matches!(elform, 1 | 10 | 13),
        };
        if !runs {
            return Some(format!(
                "ELFORM {elform} on {} (part {}; the GPU runs ELFORM 1, on hexahedra 2, on tetrahedra 10 and 13)",
                shape.plural(),
                part.id
            ));
        }
        let m = &model.materials[part.material];
        match m.kind {
            MaterialKind::Elastic
            | MaterialKind::PlasticKinematic { .. }
            | MaterialKind::JohnsonCook(_)
            | MaterialKind::PiecewiseLinear(_) => {}
            MaterialKind::Rigid { .. } => {}
        }
    }
    None
}

/// What the GPU step does not run in a split model as its solver holds it: the GPU steps each
/// coincident set as one slot, so the solver must keep its positions per slot
/// ([`Solver::slot_masses`]); it does not where a rigid body's node is tied to the copies of a
/// separation group (`Solver::attach_separation`, named by the node), nor when attached with
/// `attach_separation_per_node`. `None` otherwise.
pub fn unsupported_split(solver: &Solver) -> Option<String> {
    let tied = solver.separation()?.sets().node_sets();
    let rigid = &solver.setup.node_rigid;
    if let Some(n) = (tied.iter().zip(rigid)).position(|(&t, &r)| t != u32::MAX && r != NOT_RIGID) {
        return Some(bonded(solver.model, n));
    }
    solver
        .slot_masses()
        .is_none()
        .then(|| "element separation with a position kept for every node copy".into())
}

/// The refusal of a rigid body whose node `n` (an index) is a separation group's.
fn bonded(model: &Model, n: usize) -> String {
    format!(
        "a rigid body bonded to the nodes of a separation group (node {})",
        model.node_ids[n]
    )
}
