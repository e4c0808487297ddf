//! What the GPU step does not run yet: a deck that asks for it is refused by name.
//!
//! Runs on the GPU: one-point hexahedra and wedges (ELFORM 1) with viscous or stiffness
//! hourglass control, fully integrated selectively reduced hexahedra (ELFORM 2), constant-strain tetrahedra (ELFORM 1 and 10) and tetrahedra with nodal
//! pressure averaging (ELFORM 13), bulk viscosity (global or
//! each part's `*HOURGLASS`), `*MAT_ELASTIC`, `*MAT_PLASTIC_KINEMATIC`, `*MAT_JOHNSON_COOK` /
//! `*MAT_SIMPLIFIED_JOHNSON_COOK` (with their equations of state),
//! `*MAT_PIECEWISE_LINEAR_PLASTICITY` (curve or table), rigid bodies (`*MAT_RIGID` parts with
//! their extra nodes, `*CONSTRAINED_NODAL_RIGID_BODY`, their constraints and prescribed
//! motion; not with a given inertia), the time step (TSSFAC, DTINIT, DTMIN, ENDTIM),
//! `*LOAD_BODY`, `*LOAD_NODE_...` and `*LOAD_SEGMENT...`, SPC and
//! `*BOUNDARY_PRESCRIBED_MOTION_NODE`/`_SET`, up to 8 rigid walls (`*RIGIDWALL_PLANAR`, `_FINITE`, `*RIGIDWALL_GEOMETRIC_...` fixed or moving), tied contact
//! (`*CONTACT_TIED_...`), automatic contact (`*CONTACT_AUTOMATIC_...`, `*CONTACT_ERODING_...`,
//! with friction; with element separation, the crack faces joining the surfaces and closed
//! cracks: `crate::contact`), element erosion
//! (every rule: FAIL, FS, PSFAIL, Johnson-Cook damage, `*MAT_ADD_EROSION`), element separation
//! with every MODEL (not with rigid bodies, erosion or tied contact: `crate::separation`), the
//! energy ledger, and every output (states and histories are read back at their times).

use cleave_core::element::Shape;
use cleave_core::model::{MaterialKind, Model};
use cleave_core::setup::Setup;

/// The first feature of `model` that the GPU step does not run, as a phrase for the message
/// "`--gpu` does not run X yet"; `None` when the whole deck runs on the GPU.
pub fn unsupported(model: &Model, setup: &Setup) -> Option<String> {
    if model.num_elements() == 0 {
        return Some("a model without solid elements".into());
    }
    if !model.separations.is_empty() {
        let with = |what: &str| Some(format!("{what} together with element separation"));
        if !setup.rigid.is_empty() {
            return with("rigid bodies");
        }
        if !model.erosion.is_empty() {
            return with("element erosion");
        }
        if !model.tied.is_empty() {
            return with("tied contact");
        }
    }
    if model.rigid_walls.len() > crate::layout::MAX_WALLS {
        return Some(format!(
            "more than {} rigid walls (*RIGIDWALL_PLANAR)",
            crate::layout::MAX_WALLS
        ));
    }
    if let Some(b) = setup.rigid.iter().find(|b| b.unlumped.is_some()) {
        return Some(format!(
            "a rigid body with a given inertia (*PART_INERTIA, _INERTIA; body {})",
            b.id
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
