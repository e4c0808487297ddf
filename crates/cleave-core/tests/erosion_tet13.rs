//! Erosion of ELFORM 13 tetrahedra: an eroded tetrahedron leaves the nodal pressure averaging
//! (it neither weighs in the node means nor gets a pressure correction), so the energy balance
//! holds through the erosion of half the mesh.

use cleave_core::erosion::{ErosionDef, ErosionRule};
use cleave_core::mesh::{single_part_model, BoxMesh};
use cleave_core::model::{Material, MaterialKind, Part, Section};

/// A 4 x 2 x 2 box of 10 mm hexahedra cut into 96 ELFORM 13 tetrahedra of steel, stretched
/// by the velocity field v_x = 200/s x (0.8 m/s at the far end); the half at x > 20 mm is a
/// second material that erodes at FAILTM = `fail_time`.
fn model(fail_time: f64) -> cleave_core::model::Model {
    let steel = Material {
        id: 1,
        density: 7800.0,
        young: 2.0e11,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    };
    let mesh = BoxMesh::new([4, 2, 2], [0.04, 0.02, 0.02]).split_tets();
    let mut m = single_part_model(mesh, steel.clone(), 4.0e-5);
    m.sections = vec![Section { id: 1, elform: 13 }];
    m.materials.push(Material { id: 2, ..steel });
    m.parts.push(Part {
        id: 2,
        title: "eroding half".into(),
        section: 0,
        material: 1,
        hourglass: None,
    });
    for e in 0..m.conn.len() {
        let cx: f64 = (0..8).map(|a| m.x0[m.conn[e][a] as usize][0]).sum::<f64>() / 8.0;
        if cx > 0.02 {
            m.elem_part[e] = 1;
        }
    }
    for k in 0..m.x0.len() {
        m.v0[k] = [200.0 * m.x0[k][0], 0.0, 0.0];
    }
    m.erosion = vec![ErosionDef {
        material: 1,
        rule: ErosionRule {
            failure_time: Some(fail_time),
            ncs: 1,
            ..Default::default()
        },
    }];
    m
}

/// Half the tetrahedra erode at 15 us, mid-vibration. The nodes that only eroded tetrahedra
/// hold then fly on: their velocities stay the same bit for bit from the step after on. Were
/// the eroded ones left in the averages, they would take the averaged pressure of their live
/// neighbours and push those nodes (the check fails so: measured). The live half keeps
/// vibrating (its nodes' velocities change), and the eroded ones book their energy.
#[test]
fn eroded_elform_13_tetrahedra_leave_the_averaging() {
    let m = model(1.5e-5);
    // the nodes of eroding elements only
    let mut live = vec![false; m.x0.len()];
    for (e, c) in m.conn.iter().enumerate() {
        if m.elem_part[e] == 0 {
            c.iter().for_each(|&n| live[n as usize] = true);
        }
    }
    let free: Vec<usize> = (0..live.len()).filter(|&k| !live[k]).collect();
    assert!(free.len() >= 9, "{} free nodes", free.len());
    let mut s = cleave_core::solver::Solver::new(&m).expect("setup");
    let (mut last, mut steps_after, mut live_moved) = (None::<Vec<[f64; 3]>>, 0, false);
    while !s.is_finished() {
        s.advance_to_half_step().expect("step");
        let v: Vec<[f64; 3]> = s.half_step_velocities().iter().copied().collect();
        if s.eroded_count() > 0 {
            if let Some(prev) = &last {
                for &k in &free {
                    assert_eq!(v[k], prev[k], "node {k} was pushed after erosion");
                }
                live_moved |= (0..v.len()).any(|k| live[k] && v[k] != prev[k]);
                steps_after += 1;
            }
            last = Some(v);
        }
        s.update_positions().expect("positions");
    }
    let e = s.state.energy;
    assert_eq!(s.eroded_count(), 48);
    assert!(steps_after > 5 && live_moved, "{steps_after}");
    assert!(
        e.eroded > 0.0 && e.eroded < e.internal + e.hourglass,
        "{e:?}"
    );
}
