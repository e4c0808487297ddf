//! Concentrated and pressure loads (`*LOAD_NODE_...`, `*LOAD_SEGMENT...`): the momentum they
//! give a free body is their impulse, and the energy they add is booked as external work.
//! `cargo test --release --test loads -- --nocapture` prints the numbers.

use cleave_core::curve::Curve;
use cleave_core::mesh::{single_part_model, BoxMesh};
use cleave_core::model::{Material, Model, NodeLoad, PressureLoad};
use cleave_core::separation::interfaces::Separation;
use cleave_core::separation::split::split_model;
use cleave_core::solver::Solver;
mod common;
use common::{run, Obs};

fn steel() -> Material {
    common::elastic_steel(0.3)
}

/// A curve rising linearly from 0 to 1 over `ramp`, then constant (`ramp` 0: 1 from the
/// start).
fn ramp(ramp: f64) -> Curve {
    if ramp == 0.0 {
        return Curve {
            id: 1,
            t: vec![0.0],
            y: vec![1.0],
        };
    }
    Curve {
        id: 1,
        t: vec![0.0, ramp, 1.0],
        y: vec![0.0, 1.0, 1.0],
    }
}

/// A free steel block 20 x 10 x 10 mm of 4 x 2 x 2 hexahedra (or each cut into 6 tetrahedra),
/// with a constant pressure `p` from t = 0 on its +x face, the segments in the outward order of
/// the elements' faces, for 20 us.
fn pushed_block(tets: bool, p: f64) -> Model {
    let b = BoxMesh::new([4, 2, 2], [0.02, 0.01, 0.01]);
    let mut segs = Vec::new();
    for c in &b.conn {
        if (b.x[c[1] as usize][0] - 0.02).abs() < 1e-12 {
            segs.push([c[1], c[2], c[6], c[5]]);
        }
    }
    let mesh = if tets { b.split_tets() } else { b };
    let mut m = single_part_model(mesh, steel(), 20e-6);
    m.curves.push(ramp(0.0));
    for nodes in segs {
        m.pressure_loads.push(PressureLoad {
            nodes,
            curve: 0,
            sf: p,
            at: 0.0,
        });
    }
    m
}

/// Pressure 10 MPa on the +x face (area 1e-4 m^2) of a free block, hexahedra and tetrahedra:
/// the momentum along x is -p A t within 1e-3 (the segment's area vector moves with the
/// face; the block's strain, ~1e-4, tilts and stretches it by that order), the other components stay below 1e-3 of it (the same tilt), and the energy balance
/// KE + IE + HG = W (the loads' work) holds within 0.5% of W (measured 0.3% and 0.1%: the
/// internal energy's mid-point rule under the sudden load's waves).
#[test]
fn pressure_pushes_a_free_block_with_its_impulse() {
    let (p, area) = (10e6, 1e-4);
    for tets in [false, true] {
        let m = pushed_block(tets, p);
        let s = run(&m, |_| {});
        let mom = s.momentum();
        let want = -p * area * s.state.t;
        let e = s.state.energy;
        let balance = e.total() - s.state.initial_energy - e.external_work;
        eprintln!(
            "pressure on {}: momentum {:.6e} vs -p A t = {want:.6e} (rel {:.2e}), lateral {:.1e} {:.1e}; W {:.4e} J, KE {:.4e} IE {:.4e}, balance {balance:.2e} J",
            if tets { "tetrahedra" } else { "hexahedra" },
            mom[0],
            (mom[0] - want).abs() / want.abs(),
            mom[1],
            mom[2],
            e.external_work,
            e.kinetic,
            e.internal,
        );
        assert!((mom[0] - want).abs() < 1e-3 * want.abs());
        assert!(mom[1].abs() < 1e-3 * want.abs() && mom[2].abs() < 1e-3 * want.abs());
        assert!(e.external_work > 0.0);
        assert!(balance.abs() < 5e-3 * e.external_work);
    }
}

/// Constant forces of 1 kN along z from t = 0 on the 15 nodes of the block's top face, on
/// tetrahedra: the momentum is their impulse exactly (a fixed direction: round-off, 1e-12),
/// and the energy balance holds within 0.5% of the work (measured 0.12%).
#[test]
fn node_forces_give_their_impulse() {
    let b = BoxMesh::new([4, 2, 2], [0.02, 0.01, 0.01]).split_tets();
    let mut m = single_part_model(b, steel(), 20e-6);
    m.curves.push(ramp(0.0));
    let top = m.nodes_where(2, 0.01, 1e-12);
    for &node in &top {
        m.node_loads.push(NodeLoad {
            node,
            axis: 2,
            curve: 0,
            sf: 1e3,
        });
    }
    let s = run(&m, |_| {});
    let want = top.len() as f64 * 1e3 * s.state.t;
    let mom = s.momentum();
    let e = s.state.energy;
    let balance = e.total() - s.state.initial_energy - e.external_work;
    eprintln!(
        "node forces: momentum {:.9e} vs {want:.9e}; W {:.4e} J, balance {balance:.2e} J",
        mom[2], e.external_work
    );
    assert!((mom[2] - want).abs() < 1e-12 * want);
    assert!(balance.abs() < 5e-3 * e.external_work);
}

/// With separation (every element in a group, nothing failing) the pressure acts on the
/// coincident sets of its segment's nodes: the split block moves as the unsplit one, to
/// round-off (1e-9 of the motion).
#[test]
fn a_split_block_takes_the_pressure_as_the_unsplit_one() {
    let m = pushed_block(false, 10e6);
    let mut grouped = m.clone();
    grouped.separations.push(common::unbreakable(0));
    let split = split_model(&grouped);
    let mut a = Vec::new();
    let mut s = Solver::new(&m).unwrap();
    s.run(&mut Obs(|s: &Solver| a.push(s.positions().to_vec())))
        .unwrap();
    let mut b = Vec::new();
    let mut q = Solver::new(&split.model).unwrap();
    q.attach_separation(Separation::new(&split).unwrap());
    q.run(&mut Obs(|s: &Solver| b.push(s.positions().to_vec())))
        .unwrap();
    let scale = common::motion_scale(a.last().unwrap(), &m.x0.to_vec());
    let worst = common::copy_deviation(&a, &b, &split.origin);
    eprintln!("split block under pressure: deviation {worst:.2e} of motion {scale:.2e}");
    assert!(scale > 0.0);
    assert!(worst < 1e-9 * scale);
}
