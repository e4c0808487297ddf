//! A numerical failure names where it happened: an energy that is not finite names the energy;
//! a non-finite stress names its element and a node of it (not the first node of the mesh
//! whose velocity the NaN has reached).

mod common;

use cleave_core::error::SolverError;
use cleave_core::mesh::box_model;
use cleave_core::model::Model;
use cleave_core::solver::Solver;

/// A 4x2x2 steel block, moving, 2 ms.
fn block() -> Model {
    let mut m = box_model([4, 2, 2], [0.4, 0.2, 0.2], common::elastic_steel(0.3), 2e-3);
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        *v = [5.0 * x[1], 1.0, 0.0];
    }
    m
}

#[test]
fn a_non_finite_energy_stops_the_run_naming_it() {
    let m = block();
    let mut s = Solver::new(&m).unwrap();
    common::steps(&mut s, 3);
    s.state.energy.external_work = f64::NAN;
    let e = s.advance_to_half_step().unwrap_err();
    assert!(
        matches!(
            e,
            SolverError::NonFiniteEnergy {
                energy: "external work",
                step: 3,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.is_numerical());
}

#[test]
fn a_non_finite_stress_names_its_element_and_one_of_its_nodes() {
    let m = block();
    let mut s = Solver::new(&m).unwrap();
    common::steps(&mut s, 3);
    // the last element, far from node 1 (the first node whose velocity a scan would find
    // would be the lowest of its nodes, not node 1)
    let k = m.num_elements() - 1;
    s.state.stress[k][0] = f64::NAN;
    let e = s.advance_to_half_step().unwrap_err();
    let SolverError::NonFinite { node, element, .. } = e.clone() else {
        panic!("{e}");
    };
    assert_eq!(element, Some(m.elem_ids[k]), "{e}");
    let of_elem: Vec<i64> = m.conn[k].iter().map(|&n| m.node_ids[n as usize]).collect();
    assert!(
        of_elem.contains(&node),
        "{e}: node {node} not of element {}",
        m.elem_ids[k]
    );
    assert!(e.to_string().contains("non-finite stress"), "{e}");
}
