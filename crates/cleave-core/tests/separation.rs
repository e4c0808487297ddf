//! Element separation: the split mesh, tied by coincident-set averaging, behaves exactly as
//! the original mesh while no interface has failed (Gerken et al. 2003, section 3).

use cleave_core::curve::Curve;
use cleave_core::mesh::box_model;
use cleave_core::model::{
    Material, MaterialKind, Model, MotionTarget, PrescribedMotion, SeparationDef, Spc, Vad,
};
use cleave_core::separation::coincident::CoincidentSets;
use cleave_core::separation::split::split_model;
use cleave_core::solver::{Observer, Solver};

struct Record<'a>(&'a mut Vec<Vec<[f64; 3]>>);
impl Observer for Record<'_> {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.0.push(s.state.x.clone());
        Ok(())
    }
}

/// A 4x3x3 elastic-plastic block, clamped at x = 0, its far face pushed sideways and along x by
/// prescribed velocities, with an initial spin-like velocity field: all the step's stages act
/// (stress, hourglass, bulk viscosity, constraints, prescribed motion).
fn deck() -> Model {
    let mat = Material {
        id: 1,
        density: 7800.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::PlasticKinematic {
            sigy: 300e6,
            etan: 2e9,
            beta: 0.5,
        },
    };
    let mut m = box_model([4, 3, 3], [0.04, 0.03, 0.03], mat, 1e-4);
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        *v = [5.0 * x[1] / 0.03, -3.0 * x[0] / 0.04, 2.0];
    }
    for node in m.nodes_where(0, 0.0, 1e-12) {
        m.spcs.push(Spc {
            node,
            dof: [true, true, true, false, false, false],
        });
    }
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 1e-5, 1.0],
        y: vec![0.0, 20.0, 20.0],
    });
    for node in m.nodes_where(0, 0.04, 1e-12) {
        for axis in [0, 2] {
            m.prescribed.push(PrescribedMotion {
                target: MotionTarget::Node(node),
                axis,
                vad: Vad::Velocity,
                curve: 0,
                sf: 1.0,
            });
        }
    }
    m
}

/// Continuity: with every element in a separation group but nothing failing, every copy of a
/// deck node follows the original mesh's node: |x_copy - x_orig| below 1e-9 of the largest
/// displacement, at every step. (Only the order of the force sums differs: round-off.)
#[test]
fn split_mesh_moves_as_the_original_until_failure() {
    let original = deck();
    let mut grouped = deck();
    grouped.separations.push(SeparationDef {
        material: 0,
        model: 1,
        sigmax: 1e30,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
    });
    let split = split_model(&grouped);
    assert_eq!(split.model.num_nodes(), 8 * original.num_elements());

    let mut hist_a = Vec::new();
    let mut a = Solver::new(&original).unwrap();
    a.run(&mut Record(&mut hist_a)).unwrap();

    let mut hist_b = Vec::new();
    let mut b = Solver::new(&split.model).unwrap();
    let intact = vec![true; split.faces.len()];
    b.set_coincident_sets(CoincidentSets::build(
        split.model.num_nodes(),
        &split.faces,
        &intact,
    ));
    b.run(&mut Record(&mut hist_b)).unwrap();

    assert_eq!(hist_a.len(), hist_b.len(), "same number of steps");
    let scale = hist_a
        .last()
        .unwrap()
        .iter()
        .zip(&original.x0)
        .map(|(x, x0)| (0..3).map(|d| (x[d] - x0[d]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    assert!(scale > 1e-5, "the block moves: {scale}");
    let mut worst = 0.0f64;
    for (xa, xb) in hist_a.iter().zip(&hist_b) {
        for (i, &o) in split.origin.iter().enumerate() {
            for d in 0..3 {
                worst = worst.max((xb[i][d] - xa[o as usize][d]).abs());
            }
        }
    }
    eprintln!(
        "continuity: max |x_copy - x_orig| = {worst:.3e} m, motion scale {scale:.3e} m, {} steps",
        hist_a.len()
    );
    assert!(
        worst < 1e-9 * scale,
        "split mesh departs from the original: {worst} vs scale {scale}"
    );
    // the energies agree too
    let (ea, eb) = (a.state.energy, b.state.energy);
    assert!((ea.total() - eb.total()).abs() < 1e-9 * ea.total());
    assert!((ea.internal - eb.internal).abs() < 1e-9 * ea.internal.abs().max(1e-30));
}
