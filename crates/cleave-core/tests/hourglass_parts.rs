//! A part's own hourglass control and bulk viscosity (`*HOURGLASS`, HGID on `*PART`): the part
//! runs exactly as the whole model would with those values in `*CONTROL_HOURGLASS` and
//! `*CONTROL_BULK_VISCOSITY` (bit for bit), and not as with the global ones.

mod common;

use cleave_core::mesh::box_model;
use cleave_core::model::{Hourglass, HourglassDef, Model};
use cleave_core::solver::{kernel_controls, Solver};

/// A 4x2x2 steel block with an hourglass-mode velocity field (x-velocity alternating in sign
/// with y and z) and a compression along x, so that both the hourglass forces and the bulk
/// viscosity act.
fn block() -> Model {
    let mut m = box_model([4, 2, 2], [0.4, 0.2, 0.2], common::elastic_steel(0.3), 1e-3);
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        let s = |c: f64| {
            if (c * 10.0).round() as i64 % 2 == 0 {
                1.0
            } else {
                -1.0
            }
        };
        *v = [3.0 * s(x[1]) * s(x[2]) - 20.0 * x[0], 0.0, 0.0];
    }
    m
}

fn run(m: &Model, steps: usize) -> Vec<u64> {
    let mut s = Solver::new(m).unwrap();
    common::steps(&mut s, steps);
    common::state_bits(&s)
}

#[test]
fn a_part_with_its_own_hourglass_runs_as_with_those_values_everywhere() {
    let own = HourglassDef {
        id: 7,
        hourglass: Hourglass::Stiffness,
        qh: 0.05,
        q1: 1.0,
        q2: 0.1,
    };
    // the part names *HOURGLASS 7; the global controls are the defaults (viscous, 0.1, 1.5, 0.06)
    let mut with_hgid = block();
    with_hgid.hourglass.push(own.clone());
    with_hgid.parts[0].hourglass = Some(0);
    // the same values as the global controls
    let mut global = block();
    global.control.hourglass = own.hourglass;
    global.control.qh = own.qh;
    global.control.q1 = own.q1;
    global.control.q2 = own.q2;
    let ctl = kernel_controls(&with_hgid);
    assert_eq!(
        (ctl[0].hourglass, ctl[0].qh, ctl[0].q1, ctl[0].q2),
        (Hourglass::Stiffness, 0.05, 1.0, 0.1)
    );
    let a = run(&with_hgid, 60);
    assert_eq!(a, run(&global, 60));
    // and not as with the defaults: the part's values are what changed the motion
    assert_ne!(a, run(&block(), 60));
}
