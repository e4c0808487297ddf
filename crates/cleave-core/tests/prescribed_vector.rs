//! Prescribed motion along a vector and rotations of rigid bodies
//! (`*BOUNDARY_PRESCRIBED_MOTION_...` DOF 4, -4, 5-7, 8, -8 with `*DEFINE_VECTOR`), against
//! the motions they prescribe worked out by hand.

use cleave_core::curve::Curve;
use cleave_core::math::{add, dot, norm, scale, sub, Vec3};
use cleave_core::mesh::box_model;
use cleave_core::model::{
    BodyLoad, Material, Model, MotionDof, MotionTarget, PrescribedMotion, Spc, Vad, Window,
};
mod common;
use common::run;

fn soft() -> Material {
    common::soft_elastic()
}

fn rigid() -> Material {
    common::free_rigid()
}

/// `v` turned by `angle` about the unit axis `a` (Rodrigues).
fn turn(v: Vec3, a: Vec3, angle: f64) -> Vec3 {
    let (s, c) = angle.sin_cos();
    let axv = cleave_core::math::cross(a, v);
    add(
        add(scale(v, c), scale(axv, s)),
        scale(a, dot(a, v) * (1.0 - c)),
    )
}

/// A ramp curve 0 -> `y1` at `t1` (held after).
fn ramp(m: &mut Model, t1: f64, y1: f64) -> usize {
    m.curves.push(Curve {
        id: m.curves.len() as i64 + 1,
        t: vec![0.0, t1],
        y: vec![0.0, y1],
    });
    m.curves.len() - 1
}

/// A soft block (20 mm cube, 2 x 2 x 2 elements) whose 27 nodes are all driven along
/// d = (1, 2, 2)/3 by a displacement ramp to U = 1 mm at the end time, with an initial
/// velocity w = (2, -1, 0) m/s normal to d. Moving as one it never strains, so:
/// - DOF 4 (the motion normal to d free): x = x0 + U t/T d + w t;
/// - DOF -4 (held): x = x0 + U t/T d, the initial velocity's normal part removed.
///
/// The displacement is met each step by v = (goal - x.d)/dt along d, so the node sits on the
/// ramp to round-off (1e-12 of U, with the 1e-3 relative size of U to the positions' 1e-16
/// round-off leaving ample margin).
#[test]
fn nodes_move_along_a_vector() {
    for only in [false, true] {
        let mut m = box_model([2, 2, 2], [0.02; 3], soft(), 2e-3);
        let (u_end, t_end) = (1e-3, 2e-3);
        let c = ramp(&mut m, t_end, u_end);
        let d = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
        let w = [2.0, -1.0, 0.0];
        assert!(dot(d, w).abs() < 1e-15);
        for n in 0..m.num_nodes() {
            m.v0[n] = w;
            m.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(n as u32),
                dof: MotionDof::Along { dir: d, only },
                vad: Vad::Displacement,
                curve: c,
                sf: 1.0,
            });
        }
        let x0 = m.x0.to_vec();
        let mut err = 0.0f64;
        let s = run(&m, |s| {
            let t = s.state.t;
            let normal = if only { [0.0; 3] } else { scale(w, t) };
            let want = add(scale(d, u_end * t / t_end), normal);
            for (n, x) in s.positions().iter().enumerate() {
                err = err.max(norm(sub(sub(*x, x0[n]), want)) / u_end);
            }
        });
        eprintln!(
            "DOF {}: {} steps, max |u - u_exact| / U {err:.2e}",
            if only { -4 } else { 4 },
            s.state.step
        );
        assert!(s.state.step > 10);
        assert!(err < 1e-12, "only {only}: {err}");
    }
}

/// A rigid block (30 x 20 x 10 mm) beside a held soft cube (which sets the time step, as in
/// `nodal_rigid.rs`), under gravity g = 9.81 along -z, driven by
/// - DOF 4 along d = (0, 0.6, 0.8), velocity V = 2 m/s, and DOF 7 (about z), omega = 40
///   rad/s: the centre moves V t d + the free fall's normal part -g t^2/2 (e_z - (e_z.d) d)
///   (the leapfrog integrates a constant acceleration exactly at the step ends), and the body
///   turns about z through its centre;
/// - DOF -4 along d and DOF -8 about a = (2, -1, 2)/3, omega = 40 rad/s: the centre moves
///   V t d only, gravity's normal part held off; the body turns about a only.
///
/// The rotation is a product of Cayley steps, each turning 2 atan(omega dt / 2) instead of
/// omega dt: after 1 rad the angle is short by omega t (omega dt)^2 / 12 = 4.4e-7 rad here
/// (omega dt = 2.3e-3), so the nodes (within 0.6 of the block's length of its centre) are
/// placed within twice that bound of the block's length (measured 2.6e-7); the centre, a
/// translation, to 1e-12 (measured 3e-14).
#[test]
fn rigid_bodies_move_along_and_turn_about_vectors() {
    for only in [false, true] {
        let mut m = box_model([1, 1, 1], [0.01; 3], soft(), 0.0);
        let (rp, nodes) = common::append_box(
            &mut m,
            [3, 2, 1],
            [0.03, 0.02, 0.01],
            [0.05, 0.0, 0.0],
            rigid(),
        );
        for node in 0..8 {
            m.spcs.push(Spc {
                node,
                dof: [true; 6],
            });
        }
        let g = 9.81;
        m.body_loads.push(BodyLoad {
            axis: 2,
            curve: None,
            sf: g,
        });
        let omega = 40.0;
        m.control.end_time = 1.0 / omega;
        m.curves.push(Curve {
            id: 1,
            t: vec![0.0],
            y: vec![1.0],
        });
        let d = [0.0, 0.6, 0.8];
        let v = 2.0;
        let axis = if only {
            [2.0 / 3.0, -1.0 / 3.0, 2.0 / 3.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        m.prescribed.push(PrescribedMotion {
            window: cleave_core::model::Window::ALWAYS,
            target: MotionTarget::Rigid(rp),
            dof: MotionDof::Along { dir: d, only },
            vad: Vad::Velocity,
            curve: 0,
            sf: v,
        });
        m.prescribed.push(PrescribedMotion {
            window: cleave_core::model::Window::ALWAYS,
            target: MotionTarget::Rigid(rp),
            dof: MotionDof::Rotation { dir: axis, only },
            vad: Vad::Velocity,
            curve: 0,
            sf: omega,
        });
        let x0 = m.x0.to_vec();
        let (mut centre_err, mut place_err, mut dt_max) = (0.0f64, 0.0f64, 0.0f64);
        let mut x_cm0 = [0.0; 3];
        let s = run(&m, |s| {
            let t = s.state.t;
            let body = &s.setup.rigid[0];
            x_cm0 = body.x_cm0;
            dt_max = dt_max.max(s.state.dt);
            let ez = [0.0, 0.0, 1.0];
            let fall = if only {
                [0.0; 3]
            } else {
                scale(sub(ez, scale(d, dot(ez, d))), -0.5 * g * t * t)
            };
            let centre = add(add(body.x_cm0, scale(d, v * t)), fall);
            let st = &s.state.rigid[0];
            centre_err = centre_err.max(norm(sub(st.x_cm, centre)) / 0.03);
            let x = s.positions();
            for n in nodes.clone() {
                let want = add(centre, turn(sub(x0[n], body.x_cm0), axis, omega * t));
                place_err = place_err.max(norm(sub(x[n], want)) / 0.03);
            }
        });
        let bound = (omega * dt_max).powi(2) / 12.0;
        eprintln!(
            "DOF {}: {} steps, omega dt {:.1e}; centre {centre_err:.2e}, nodes {place_err:.2e} of the block (Cayley bound {bound:.1e})",
            if only { "-4, -8" } else { "4, 7" },
            s.state.step,
            omega * dt_max
        );
        assert!(s.state.step > 100);
        assert!(centre_err < 1e-12, "{centre_err}");
        assert!(place_err < 2.0 * bound + 1e-12, "{place_err} vs {bound}");
        assert!(place_err > 0.0 && x_cm0[0] > 0.05);
    }
}

/// BIRTH and DEATH: a free soft block (nothing else acts on it) whose 27 nodes get
/// - a velocity V = 3 m/s along x from BIRTH = T/4 on, until the end: the nodes start at rest
///   and are driven from the first step whose middle is past BIRTH, so x(T) = V (T - t_b) with
///   t_b within one step of T/4;
/// - a velocity W = -2 m/s along y from the start until DEATH = T/2: after it the nodes keep
///   moving at W (no force acts on the block);
/// - DOF -4 along z, displacement 0 (VAD 2), applied after them, until DEATH = T/8: while it
///   acts it holds every node where it is (x and y too), so y moves at W only from the first
///   step past T/8 and y(T) = W (T - t_d), t_d within a step of T/8; z stays 0.
#[test]
fn motions_act_between_birth_and_death() {
    let mut m = box_model([2, 2, 2], [0.02; 3], soft(), 2e-3);
    let t_end = m.control.end_time;
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0],
        y: vec![1.0],
    });
    let (v, w) = (3.0, -2.0);
    for n in 0..m.num_nodes() as u32 {
        for (window, dof, vad, sf) in [
            (
                Window {
                    birth: t_end / 4.0,
                    death: f64::INFINITY,
                },
                MotionDof::Axis(0),
                Vad::Velocity,
                v,
            ),
            (
                Window {
                    birth: 0.0,
                    death: t_end / 2.0,
                },
                MotionDof::Axis(1),
                Vad::Velocity,
                w,
            ),
            (
                Window {
                    birth: 0.0,
                    death: t_end / 8.0,
                },
                MotionDof::Along {
                    dir: [0.0, 0.0, 1.0],
                    only: true,
                },
                Vad::Displacement,
                0.0,
            ),
        ] {
            m.prescribed.push(PrescribedMotion {
                window,
                target: MotionTarget::Node(n),
                dof,
                vad,
                curve: 0,
                sf,
            });
        }
    }
    let x0 = m.x0.to_vec();
    let mut dt_max = 0.0f64;
    let mut held = 0.0f64;
    let s = run(&m, |s| {
        dt_max = dt_max.max(s.state.dt);
        if s.state.t <= t_end / 8.0 {
            // the -4 motion holds every node where it was
            for (n, x) in s.positions().iter().enumerate() {
                held = held.max(norm(sub(*x, x0[n])));
            }
        }
    });
    let u = sub(s.positions()[13], x0[13]);
    let (ex, ey) = (
        (u[0] - v * 0.75 * t_end).abs() / (v * dt_max),
        (u[1] - w * 0.875 * t_end).abs() / (w.abs() * dt_max),
    );
    eprintln!(
        "BIRTH/DEATH: {} steps, dt {dt_max:.2e}; held {held:.1e} m; x off by {ex:.2} steps, y by {ey:.2} steps, z {:.1e}",
        s.state.step, u[2]
    );
    assert!(s.state.step > 20);
    assert!(held < 1e-15, "{held}");
    assert!(ex <= 1.0 && ey <= 1.0, "{ex} {ey}");
    assert!(u[2].abs() < 1e-15, "{}", u[2]);
    // every node alike
    for (n, x) in s.positions().iter().enumerate() {
        assert!(norm(sub(sub(*x, x0[n]), u)) <= 1e-12 * norm(u));
    }
}

/// LCTM of `*CONTROL_TIMESTEP`: the largest time step against time. A block at rest with a
/// curve holding the step to 2e-5 s until 1 ms, then (over 1e-12 s) to 1 s, no limit: every
/// step is the smaller of the block's own (7.8e-5 s, constant: nothing moves) and the curve at
/// the step's start, so 50 steps of 2e-5 s, then the block's own.
#[test]
fn a_time_step_curve_bounds_the_step() {
    let mut m = box_model([2, 2, 2], [0.02; 3], soft(), 2e-3);
    // the block's own step (constant: nothing moves)
    let free = {
        let mut first = 0.0;
        run(&m, |s| {
            if s.state.step == 1 {
                first = s.state.t;
            }
        });
        first
    };
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 1e-3, 1e-3 + 1e-12],
        y: vec![2e-5, 2e-5, 1.0],
    });
    m.control.dt_max_curve = Some(0);
    let mut steps: Vec<(f64, f64)> = Vec::new();
    let s = run(&m, |s| steps.push((s.state.t, s.state.dt)));
    let before = steps.iter().filter(|(t, _)| *t < 1e-3).count();
    eprintln!(
        "LCTM: {} steps, {before} before 1 ms; the block's own step {free:.3e}",
        s.state.step
    );
    assert!(free > 3e-5, "{free}");
    // each step the smaller of the block's own and the curve at its start (the last one
    // shortened to end at ENDTIM)
    let curve = &m.curves[0];
    for w in steps.windows(2) {
        let (t, dt) = (w[0].0, w[1].0 - w[0].0);
        if w[1].0 < 2e-3 - 1e-12 {
            let want = free.min(curve.eval(t));
            assert!((dt - want).abs() <= 1e-12 * want, "{t}: {dt} vs {want}");
        }
    }
    assert!(before >= 49, "{before}");
}

/// LCTM past its last abscissa and at 0: the computed step (the LS-DYNA manual's rule); and a
/// curve asking for steps far below DTMIN times the first one does not stop the run (the floor
/// guards the elements' own step).
#[test]
fn a_time_step_curve_ends_and_does_not_trip_the_floor() {
    let mut m = box_model([2, 2, 2], [0.02; 3], soft(), 2e-3);
    // 0 (no limit) until 0.5 ms, 5e-6 s (a fifteenth of the block's own step) until 1.5 ms,
    // nothing after
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 5e-4, 5e-4 + 1e-12, 1.5e-3],
        y: vec![0.0, 0.0, 5e-6, 5e-6],
    });
    m.control.dt_max_curve = Some(0);
    m.control.dt_min = 0.5;
    let mut steps: Vec<(f64, f64)> = Vec::new();
    let s = run(&m, |s| steps.push((s.state.t, s.state.dt)));
    let own = steps[1].0;
    let held = steps
        .windows(2)
        .filter(|w| w[0].0 > 5e-4 + 1e-12 && w[0].0 <= 1.5e-3)
        .count();
    eprintln!(
        "LCTM ends: {} steps, {held} held to 5e-6 s; own step {own:.2e}",
        s.state.step
    );
    for w in steps.windows(2) {
        let (t, dt) = (w[0].0, w[1].0 - w[0].0);
        let want = if t > 5e-4 + 1e-12 && t <= 1.5e-3 {
            5e-6
        } else {
            own
        };
        if w[1].0 < 2e-3 - 1e-12 && !(t > 5e-4 && t < 5e-4 + 1e-11) {
            assert!((dt - want).abs() <= 1e-12 * want, "{t}: {dt} vs {want}");
        }
    }
    assert!(held >= 190, "{held}");
    assert!((s.state.t - 2e-3).abs() < 1e-15);
}
