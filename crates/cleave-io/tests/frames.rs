//! Local coordinate systems (`*DEFINE_COORDINATE_SYSTEM` / `_VECTOR`) in the CID fields: a
//! concentrated load along a turned axis, the global-axes systems that ANSYS Workbench writes
//! for its loads and constraints, and the systems and uses cleave refuses.

use cleave_core::solver::{Observer, Solver};
use cleave_io::deck::parse_deck;

mod blocks;
use blocks::hex_block;

/// Records every node's velocity at the end.
struct Last(Vec<[f64; 3]>);
impl Observer for Last {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.0 = s.velocities().iter().copied().collect();
        Ok(())
    }
}

/// A free steel block of 2 x 2 x 2 hexahedra of 10 mm, 20 us, with `extra` cards.
fn block(extra: &str) -> String {
    let (n, e) = hex_block(1, 1, 1, [2, 2, 2], 0.01, [0.0; 3]);
    format!(
        "*KEYWORD\n*CONTROL_TERMINATION\n2.0e-5\n*PART\nblock\n1, 1, 1\n*SECTION_SOLID\n1, 1\n\
         *MAT_ELASTIC\n1, 7800., 2.0e11, 0.3\n*NODE\n{n}*ELEMENT_SOLID\n{e}\
         *DEFINE_CURVE\n7\n0., 1.\n1., 1.\n{extra}*END\n"
    )
}

/// A constant force of 1 kN on one corner node along the local y axis of a system whose x
/// axis is (1, 2, 2)/3 and whose x-y plane holds the global z axis: the block's momentum after
/// 20 us is the impulse, F t = 0.02 N s along the local y axis (the exact direction: the
/// momentum of a free body is the impulse of its external forces, to round-off).
#[test]
fn a_load_acts_along_the_local_axis() {
    let systems = [
        // by points: origin (1, 1, 1), x towards (2, 3, 3), the plane through (1, 1, 2)
        "*DEFINE_COORDINATE_SYSTEM\n5, 1., 1., 1., 2., 3., 3.\n1., 1., 2.\n",
        // the same axes by vectors (with a title)
        "*DEFINE_COORDINATE_VECTOR_TITLE\nturned\n5, 1., 2., 2., 0., 0., 1.\n",
    ];
    // local y = z x x with z = x cross (0, 0, 1), normalised
    let x: [f64; 3] = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    let z = {
        let c = [x[1], -x[0], 0.0];
        let l = (c[0] * c[0] + c[1] * c[1]).sqrt();
        [c[0] / l, c[1] / l, 0.0]
    };
    let y = [
        z[1] * x[2] - z[2] * x[1],
        z[2] * x[0] - z[0] * x[2],
        z[0] * x[1] - z[1] * x[0],
    ];
    for sys in systems {
        let deck = block(&format!("{sys}*LOAD_NODE_POINT\n1, 2, 7, 1000., 5\n"));
        let model = parse_deck(&deck, "b.k").unwrap().model;
        // one load per global component the axis has
        assert_eq!(model.node_loads.len(), 3, "{sys}");
        let mut s = Solver::new(&model).unwrap();
        let mut last = Last(Vec::new());
        s.run(&mut last).unwrap();
        let t = s.state.t;
        let mass = &s.setup.mass;
        let v = &last.0;
        let p: Vec<f64> = (0..3)
            .map(|d| (0..mass.len()).map(|i| mass[i] * v[i][d]).sum())
            .collect();
        // the impulse of the last half step is in v^(n+1/2), not yet in t
        let impulse = 1000.0 * t;
        for d in 0..3 {
            let want = impulse * y[d];
            assert!(
                (p[d] - want).abs() <= 0.05 * impulse,
                "{sys}: momentum {p:?} against {want} along {d}"
            );
        }
        // the direction to round-off: p parallel to y
        let pl = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let along: f64 = (0..3).map(|d| p[d] * y[d]).sum::<f64>() / pl;
        assert!((along - 1.0).abs() < 1e-12, "{sys}: cos {along}");
    }
}

/// What ANSYS Workbench writes: a system with the global axes, named by the CID of a load, a
/// constraint and a body load; read as the global axes.
#[test]
fn a_system_with_the_global_axes_is_the_global_frame() {
    let global = "*DEFINE_COORDINATE_SYSTEM\n23, 0, 0, 0, 1, 0, 0\n0, 1, 0\n";
    let with = block(&format!(
        "{global}*LOAD_NODE_POINT\n1, 2, 7, 1000., 23\n*BOUNDARY_SPC_NODE\n27, 23, 1, 1, 1\n\
         *LOAD_BODY_Z\n7, 9.81, 0, 0., 0., 0., 23\n"
    ));
    let without = block(
        "*LOAD_NODE_POINT\n1, 2, 7, 1000.\n*BOUNDARY_SPC_NODE\n27, 0, 1, 1, 1\n\
         *LOAD_BODY_Z\n7, 9.81\n",
    );
    let a = parse_deck(&with, "a.k").unwrap().model;
    let b = parse_deck(&without, "b.k").unwrap().model;
    assert_eq!(a.node_loads, b.node_loads);
    assert_eq!(a.spcs, b.spcs);
    assert_eq!(a.body_loads, b.body_loads);
}

/// A system no field names changes nothing, even one whose points span no plane.
#[test]
fn an_unused_system_changes_nothing() {
    let extra = "*DEFINE_COORDINATE_SYSTEM\n5, 0., 0., 0., 0., 0., 0.\n0., 0., 0.\n";
    let a = parse_deck(&block(extra), "a.k").unwrap().model;
    let b = parse_deck(&block(""), "b.k").unwrap().model;
    assert_eq!(a.x0, b.x0);
    assert_eq!(a.node_loads, b.node_loads);
}

#[test]
fn systems_cleave_cannot_use_are_refused_by_name() {
    let turned = "*DEFINE_COORDINATE_VECTOR\n5, 1., 1., 0., 0., 0., 1.\n";
    let cases = [
        (
            format!("{turned}*BOUNDARY_SPC_NODE\n1, 5, 1, 0, 0\n"),
            "coordinate system 5: its axes are turned from the global ones",
        ),
        (
            "*LOAD_NODE_POINT\n1, 2, 7, 1000., 8\n".to_string(),
            "coordinate system 8 is not defined",
        ),
        (
            "*DEFINE_COORDINATE_NODES\n6, 1, 2, 3\n*LOAD_NODE_POINT\n1, 2, 7, 1000., 6\n"
                .to_string(),
            "coordinate system 6 follows nodes",
        ),
        (
            "*DEFINE_COORDINATE_VECTOR\n5, 1., 1., 0., 2., 2., 0.\n*LOAD_NODE_POINT\n1, 2, 7, 1000., 5\n"
                .to_string(),
            "coordinate system 5 has a zero x axis or its plane point on the x axis",
        ),
        (
            "*DEFINE_COORDINATE_SYSTEM\n5, 0., 0., 0., 1., 0., 0., 3\n0., 1., 0.\n".to_string(),
            "CIDL",
        ),
        (
            format!("{turned}*DEFINE_COORDINATE_SYSTEM\n5, 0., 0., 0., 1., 0., 0.\n0., 1., 0.\n"),
            "coordinate system 5 is defined twice",
        ),
    ];
    for (extra, want) in cases {
        let e = parse_deck(&block(&extra), "b.k").unwrap_err().to_string();
        assert!(e.contains(want), "{extra}: {e}");
    }
}
