//! Rigid bodies made of nodes: `*CONSTRAINED_NODAL_RIGID_BODY` (a node set of a deformable
//! mesh moving as one rigid body), `*CONSTRAINED_EXTRA_NODES` (nodes joined to a rigid part)
//! and `*PART_INERTIA` (a rigid part whose mass, centre, inertia and initial velocity are
//! given). Each test prints its measured numbers (`-- --nocapture`) and asserts them within a
//! tolerance justified in its doc comment.

use std::f64::consts::PI;

use cleave_core::curve::Curve;
use cleave_core::math::{add, cross, dot, mat_vec, norm, scale, sub, Vec3};
use cleave_core::mesh::box_model;
use cleave_core::model::{
    BodyLoad, ExtraNodes, GivenInertia, Material, MaterialKind, MotionTarget, NodalRigidBody,
    NodeSet, PartInertia, PrescribedMotion, Spc, Vad,
};
use cleave_core::setup::Setup;
mod common;
use common::run;

fn elastic(density: f64, young: f64) -> Material {
    Material {
        id: 1,
        density,
        young,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    }
}

fn rigid() -> Material {
    Material {
        id: 2,
        density: 7800.0,
        young: 2e11,
        poisson: 0.3,
        kind: MaterialKind::Rigid {
            cmo: 0,
            con1: 0,
            con2: 0,
        },
    }
}

/// Largest relative change of the distances between the nodes `nodes` from the reference.
fn distance_change(x: impl Fn(usize) -> Vec3, x0: &[Vec3], nodes: &[usize]) -> f64 {
    let mut worst = 0.0f64;
    for (a, &i) in nodes.iter().enumerate() {
        for &j in &nodes[a + 1..] {
            let d0 = norm(sub(x0[i], x0[j]));
            worst = worst.max((norm(sub(x(i), x(j))) - d0).abs() / d0);
        }
    }
    worst
}

/// A nodal rigid body inside a deformable block, spun and thrown.
///
/// A soft elastic block (rho 1000, E 10 MPa, 40 x 30 x 20 mm, 4 x 3 x 2 elements) whose 12
/// nodes of the face x = 0 and 4 nodes of the line x = 20 mm, z = 10 mm inside it (no
/// element has all its nodes in the body) form a `*CONSTRAINED_NODAL_RIGID_BODY`; the whole
/// block starts with v = v_c + omega x (x - c), v_c = (2, -1, 0.5) m/s, omega = (30, 80, 50)
/// rad/s (|omega| dt = 7e-3 with dt = 7.3e-5 s), 70 ms, 1.1 turns, the deformable elements
/// between the body's nodes straining under the centrifugal load.
///
/// Pins:
/// - the body's 16 nodes keep their distances to 1e-12 relative (placed exactly as
///   x_cm + R (X - X_cm); R a product of Cayley rotations, orthogonal to round-off over 960
///   steps; measured 4.5e-15);
/// - the model's momentum sum m v^n is constant to 1e-12 of |p0| (no external force; the
///   element forces are equal and opposite, and the body gathers its nodes' forces whole);
/// - the energy balance (kinetic + internal + hourglass = E0) within 1e-4 of E0 (measured
///   1.0e-5, with up to 6e-5 of E0 exchanged with the elements): the rigid update is not the
///   leapfrog's on its nodes (their velocities are chords of the rotating placement), so the
///   chord kinetic energy differs from the body's by O((omega dt)^2) = 5e-5 of it.
#[test]
fn nodal_rigid_body_in_a_deformable_block_keeps_its_shape() {
    let mut m = box_model([4, 3, 2], [0.04, 0.03, 0.02], elastic(1000.0, 1e7), 0.07);
    let body: Vec<usize> = (0..m.num_nodes())
        .filter(|&i| {
            let x = m.x0[i];
            x[0].abs() < 1e-9 || ((x[0] - 0.02).abs() < 1e-9 && (x[2] - 0.01).abs() < 1e-9)
        })
        .collect();
    assert_eq!(body.len(), 12 + 4);
    m.node_sets.push(NodeSet {
        id: 7,
        nodes: body.iter().map(|&i| i as u32).collect(),
    });
    m.nodal_rigid.push(NodalRigidBody {
        id: 100,
        set: 0,
        cmo: 0,
        con1: 0,
        con2: 0,
        inertia: None,
    });
    let (vc, w, c) = ([2.0, -1.0, 0.5], [30.0, 80.0, 50.0], [0.02, 0.015, 0.01]);
    for i in 0..m.num_nodes() {
        m.v0[i] = add(vc, cross(w, sub(m.x0[i], c)));
    }
    let setup = Setup::new(&m).unwrap();
    assert_eq!(setup.rigid.len(), 1);
    let body_mass: f64 = body.iter().map(|&i| setup.mass[i]).sum();
    assert_eq!(setup.rigid[0].mass, body_mass);
    let x0 = m.x0.to_vec();
    let (mut p0, mut e0) = ([0.0; 3], 0.0);
    let (mut d_err, mut p_err, mut e_err, mut exchanged) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let s = run(&m, |s| {
        let p = s.momentum();
        let e = &s.state.energy;
        let total = e.kinetic + e.internal + e.hourglass;
        if s.state.step == 0 {
            p0 = p;
            e0 = total;
        }
        exchanged = exchanged.max(e.internal + e.hourglass);
        p_err = p_err.max(norm(sub(p, p0)) / norm(p0));
        e_err = e_err.max((total - e0 - e.external_work).abs() / e0);
        if s.state.step % 50 == 0 {
            let pos = s.positions();
            d_err = d_err.max(distance_change(|i| pos[i], &x0, &body));
        }
    });
    let turned = norm(w) * s.state.t / (2.0 * PI);
    eprintln!(
        "nodal rigid body: {} steps, dt {:.2e}, {turned:.2} turns; distances {d_err:.2e}; momentum {p_err:.2e}; energy {e_err:.2e} of E0 {e0:.3e} (internal + hourglass up to {:.2e} of E0)",
        s.state.step,
        s.state.dt,
        exchanged / e0
    );
    assert!(turned > 1.0);
    assert!(d_err < 1e-12, "{d_err}");
    assert!(p_err < 1e-12, "{p_err}");
    assert!(e_err < 1e-4, "{e_err}");
}

/// Prescribed motion on a nodal rigid body (`*BOUNDARY_PRESCRIBED_MOTION_RIGID` naming its
/// PID): the body's nodes move by exactly v t along x (VAD 0, v 1.5 m/s from a constant
/// curve), 2 ms, to 1e-10 of the travel (round-off as for a rigid part: positions accumulate
/// 1e-17 m a step).
#[test]
fn nodal_rigid_body_follows_prescribed_motion() {
    let v = 1.5;
    let mut m = box_model([2, 2, 2], [0.02; 3], elastic(1000.0, 1e7), 2e-3);
    let body: Vec<u32> = (0..m.num_nodes() as u32)
        .filter(|&i| m.x0[i as usize][0].abs() < 1e-9)
        .collect();
    m.node_sets.push(NodeSet {
        id: 1,
        nodes: body.clone(),
    });
    m.nodal_rigid.push(NodalRigidBody {
        id: 5,
        set: 0,
        cmo: 0,
        con1: 0,
        con2: 0,
        inertia: None,
    });
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0],
        y: vec![1.0],
    });
    m.prescribed.push(PrescribedMotion {
        window: cleave_core::model::Window::ALWAYS,
        target: MotionTarget::NodalRigid(0),
        dof: cleave_core::model::MotionDof::Axis(0),
        vad: Vad::Velocity,
        curve: 0,
        sf: v,
    });
    let x0 = m.x0.to_vec();
    let mut u_err = 0.0f64;
    let s = run(&m, |s| {
        let t = s.state.t;
        for &i in &body {
            let d = sub(s.positions()[i as usize], x0[i as usize]);
            u_err = u_err.max(norm(sub(d, [v * t, 0.0, 0.0])) / (v * 2e-3));
        }
    });
    eprintln!(
        "nodal rigid body, prescribed: {} steps; max |u - v t| / (v t_end) {u_err:.2e}",
        s.state.step
    );
    assert!(u_err < 1e-10, "{u_err}");
}

/// Extra nodes follow their rigid part exactly.
///
/// A rigid block (60 x 30 x 10 mm, 3 x 2 x 1 elements) with, as `*CONSTRAINED_EXTRA_NODES`,
/// the 8 nodes of a separate soft elastic cube 10 mm away (their mass joins the body; the
/// cube's element supplies the time step and, all its nodes rigid, never strains) and a node
/// of no element 50 mm off (massless), thrown with v_cm = (1, -2, 0.5) m/s, omega = (3, 10,
/// 20) rad/s, 0.3 s (about a turn).
///
/// Pins: the body's mass is the block's and the cube's lumped masses (exactly); every extra
/// node is at x_cm + R (X - X_cm0) and keeps its distance to each block node, to 1e-12
/// relative; momentum constant to 1e-12; kinetic energy within 1e-6 of the start (torque-free:
/// the implicit mid-point rotation conserves the body's rotational energy exactly; the nodal
/// chord velocities differ from omega x r by O((omega dt)^2), as for a rigid part
/// (`verification.rs`)); the cube's internal energy below 1e-12 of the kinetic.
#[test]
fn extra_nodes_follow_the_rigid_part() {
    let mut m = box_model([1, 1, 1], [0.01; 3], elastic(1000.0, 1.2e7), 0.3);
    for x in &mut m.x0 {
        *x = add(*x, [0.07, 0.0, 0.0]);
    }
    let cube: Vec<u32> = (0..8).collect();
    let (rp, block) = common::append_box(&mut m, [3, 2, 1], [0.06, 0.03, 0.01], [0.0; 3], rigid());
    m.x0.push([0.03, 0.065, 0.0]);
    m.v0.push([0.0; 3]);
    m.node_ids.push(1000);
    let free = m.num_nodes() as u32 - 1;
    m.node_sets.push(NodeSet {
        id: 3,
        nodes: cube.clone(),
    });
    m.extra_nodes.push(ExtraNodes {
        part: rp,
        set: Some(0),
        nodes: cube.clone(),
        iflag: false,
    });
    m.extra_nodes.push(ExtraNodes {
        part: rp,
        set: None,
        nodes: vec![free],
        iflag: false,
    });
    let setup = Setup::new(&m).unwrap();
    let all: Vec<usize> = block
        .clone()
        .chain(cube.iter().map(|&i| i as usize))
        .chain([free as usize])
        .collect();
    let expected: f64 = all.iter().map(|&i| setup.mass[i]).sum();
    assert!((setup.rigid[0].mass - expected).abs() <= 1e-15 * expected);
    assert_eq!(setup.rigid[0].nodes.len(), 24 + 8 + 1);
    let centre = setup.rigid[0].x_cm0;
    let (vc, w) = ([1.0, -2.0, 0.5], [3.0, 10.0, 20.0]);
    for &i in &all {
        m.v0[i] = add(vc, cross(w, sub(m.x0[i], centre)));
    }
    let x0 = m.x0.to_vec();
    let body = setup.rigid[0].clone();
    let extra: Vec<usize> = cube
        .iter()
        .map(|&i| i as usize)
        .chain([free as usize])
        .collect();
    let (mut p0, mut ke0) = ([0.0; 3], 0.0);
    let (mut place_err, mut d_err, mut p_err, mut ke_err, mut strain) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let s = run(&m, |s| {
        let p = s.momentum();
        let ke = s.state.energy.kinetic;
        if s.state.step == 0 {
            p0 = p;
            ke0 = ke;
        }
        p_err = p_err.max(norm(sub(p, p0)) / norm(p0));
        ke_err = ke_err.max((ke - ke0).abs() / ke0);
        strain = strain.max(s.state.energy.internal.abs() / ke0);
        let st = &s.state.rigid[0];
        let pos = s.positions();
        for &i in &extra {
            let want = body.place(st.x_cm, &st.rot, x0[i]);
            place_err = place_err.max(norm(sub(pos[i], want)) / 0.07);
        }
        if s.state.step % 100 == 0 {
            d_err = d_err.max(distance_change(|i| pos[i], &x0, &all));
        }
    });
    eprintln!(
        "extra nodes: {} steps; placement {place_err:.2e}; distances {d_err:.2e}; momentum {p_err:.2e}; KE {ke_err:.2e}; cube internal {strain:.2e} of KE",
        s.state.step
    );
    assert!(norm(w) * 0.3 > 2.0 * PI * 0.9);
    assert!(place_err < 1e-12, "{place_err}");
    assert!(d_err < 1e-12, "{d_err}");
    assert!(p_err < 1e-12, "{p_err}");
    assert!(ke_err < 1e-6, "{ke_err}");
    assert!(strain < 1e-12, "{strain}");
}

/// A `*PART_INERTIA` rigid part tumbles with its given mass, inertia and velocity.
///
/// A rigid block (60 x 30 x 10 mm of steel, 0.14 kg by its elements) given TM 2.5 kg at
/// XC = (0.01, 0.02, 0.0) (off the block's centre), an inertia tensor with products
/// (IXX 4e-3, IYY 6e-3, IZZ 9e-3, IXY -1e-3, IXZ 5e-4, IYZ 2e-4 kg m^2: not the block's) and
/// VT = (1, -2, 0.5) m/s, VR = (3, 10, 20) rad/s; with gravity 9.81 m/s^2 along -z, 0.3 s.
/// A far soft elastic cube, held by SPCs, supplies the time step.
///
/// Pins:
/// - the body's mass is TM and its centre XC exactly (the block's nodal masses are dropped);
/// - its centre follows x_c + VT t - g t^2 / 2 e_z to 1e-10 of the travel (the centre's
///   velocity update is exact for a constant force; positions accumulate round-off);
/// - the angular momentum about the centre stays I VR to 1e-13 relative (gravity acts at the
///   centre: no moment) and the rotational energy L . I(R)^-1 L / 2 to 1e-12 (the implicit
///   mid-point rule conserves it);
/// - the ledger: kinetic (the body's own, from its placements: no node carries its mass) +
///   internal + hourglass = E0 + W (gravity's work) within 1e-6 of E0: the body's chord rates
///   differ from omega x r by O((omega dt)^2) = 3e-6 of its rotational energy, itself a
///   quarter of E0. At the last step, shortened to end at ENDTIM (4.2e-5 s after 7.1e-5 s),
///   the leapfrog's kinetic energy 1/2 M v^(n-1/2) . v^(n+1/2) of a falling mass is off by
///   about M v g (dt^(n+1/2) - dt^(n-1/2)) / 4 (as for any node): 2e-4 of E0 there;
/// - the momentum the solver reports is the body's TM v_c, to 1e-12.
#[test]
fn part_inertia_tumbles_with_the_given_inertia() {
    let g = 9.81;
    let mut m = box_model([1, 1, 1], [0.01; 3], elastic(1000.0, 1.2e7), 0.3);
    for x in &mut m.x0 {
        *x = add(*x, [1.0, 1.0, 1.0]);
    }
    let (rp, _) = common::append_box(&mut m, [3, 2, 1], [0.06, 0.03, 0.01], [0.0; 3], rigid());
    let inertia = [[4e-3, -1e-3, 5e-4], [-1e-3, 6e-3, 2e-4], [5e-4, 2e-4, 9e-3]];
    let (xc, tm, vt, vr) = ([0.01, 0.02, 0.0], 2.5, [1.0, -2.0, 0.5], [3.0, 10.0, 20.0]);
    m.part_inertia.push(PartInertia {
        part: rp,
        given: GivenInertia {
            centre: xc,
            mass: tm,
            inertia,
            velocity: vt,
            omega: vr,
        },
    });
    m.body_loads.push(BodyLoad {
        axis: 2,
        curve: None,
        sf: g,
    });
    // the helper cube is held (a lone soft element falling freely rings up from round-off)
    for node in 0..8 {
        m.spcs.push(Spc {
            node,
            dof: [true; 6],
        });
    }
    let setup = Setup::new(&m).unwrap();
    let body = setup.rigid[0].clone();
    assert_eq!(body.mass, tm);
    assert!(norm(sub(body.x_cm0, xc)) <= 1e-16);
    for (a, b) in body.inertia0.iter().flatten().zip(inertia.iter().flatten()) {
        assert!((a - b).abs() <= 1e-18, "{a} {b}");
    }
    assert!(setup.mass[8..].iter().all(|&m| m == 0.0));
    let l0 = mat_vec(&inertia, vr);
    let (mut e0, mut centre_err, mut l_err, mut rot_err, mut e_err, mut p_err) =
        (0.0, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let erot0 = 0.5 * dot(vr, l0);
    let mut last_err = 0.0f64;
    let s = run(&m, |s| {
        let t = s.state.t;
        let st = &s.state.rigid[0];
        let want = add(add(xc, scale(vt, t)), [0.0, 0.0, -0.5 * g * t * t]);
        centre_err = centre_err.max(norm(sub(st.x_cm, want)) / norm(scale(vt, 0.3)));
        l_err = l_err.max(norm(sub(st.ang_mom, l0)) / norm(l0));
        let inv = cleave_core::math::inverse(&body.inertia(&st.rot)).unwrap();
        let erot = 0.5 * dot(st.ang_mom, mat_vec(&inv, st.ang_mom));
        rot_err = rot_err.max((erot - erot0).abs() / erot0);
        let e = &s.state.energy;
        let total = e.kinetic + e.internal + e.hourglass;
        if s.state.step == 0 {
            e0 = total;
        }
        let le = (total - e0 - e.external_work).abs() / e0;
        if s.is_finished() || s.state.dt < 0.999 * s.state.dt_prev {
            last_err = last_err.max(le);
        } else {
            e_err = e_err.max(le);
        }
        if s.state.step > 0 {
            let body_p = scale([vt[0], vt[1], vt[2] - g * t], tm);
            p_err = p_err.max(norm(sub(s.momentum(), body_p)) / norm(body_p));
        }
    });
    eprintln!(
        "part inertia: {} steps, dt {:.2e}; centre {centre_err:.2e}; L {l_err:.2e}; rotational energy {rot_err:.2e}; ledger {e_err:.2e} of E0 {e0:.3e}, {last_err:.2e} at the shortened last steps; momentum {p_err:.2e}",
        s.state.step, s.state.dt
    );
    assert!(centre_err < 1e-10, "{centre_err}");
    assert!(l_err < 1e-13, "{l_err}");
    assert!(rot_err < 1e-12, "{rot_err}");
    assert!(e_err < 1e-6, "{e_err}");
    assert!(last_err < 2e-4, "{last_err}");
    assert!(p_err < 1e-12, "{p_err}");
}
