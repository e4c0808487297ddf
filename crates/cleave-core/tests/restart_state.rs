//! The solver's state saved between two steps and taken up by a solver built again from the
//! same model continues bit for bit (the command line's restart files build on this; its
//! tests cover separation, contact and the other element formulations); a state of another
//! model is refused.

mod common;

use cleave_core::mesh::box_model;
use cleave_core::model::Model;
use cleave_core::solver::Solver;

/// A 3x2x2 steel block, spinning and moving, 2 ms.
fn block() -> Model {
    let mut m = box_model([3, 2, 2], [0.3, 0.2, 0.2], common::elastic_steel(0.3), 2e-3);
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        // a shear velocity field: the block deforms and rotates
        *v = [5.0 * x[1], -3.0 * x[0] + 1.0, 2.0 * x[0] * x[2]];
    }
    m
}

#[test]
fn a_restored_state_continues_bit_for_bit() {
    let m = block();
    let mut straight = Solver::new(&m).unwrap();
    common::steps(&mut straight, 70);
    let mut first = Solver::new(&m).unwrap();
    common::steps(&mut first, 30);
    let saved = first.save_state();
    let mut again = Solver::new(&m).unwrap();
    again.restore_state(&saved).unwrap();
    assert_eq!(again.state.step, 30);
    common::steps(&mut again, 40);
    assert_eq!(common::state_bits(&again), common::state_bits(&straight));
    // and the state does change over those steps (the comparison is not of a still block)
    assert_ne!(common::state_bits(&first), common::state_bits(&straight));
}

#[test]
fn a_state_of_another_model_is_refused() {
    let m = block();
    let mut s = Solver::new(&m).unwrap();
    common::steps(&mut s, 3);
    let saved = s.save_state();
    let other = box_model([2, 2, 2], [0.2; 3], common::elastic_steel(0.3), 1e-3);
    let err = Solver::new(&other)
        .unwrap()
        .restore_state(&saved)
        .unwrap_err();
    assert!(err.contains("12 elements, the deck 8"), "{err}");
    let err = Solver::new(&m)
        .unwrap()
        .restore_state(&saved[..saved.len() / 2])
        .unwrap_err();
    assert!(err.contains("unreadable"), "{err}");
}
