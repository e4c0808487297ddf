//! The GPU step against the CPU step on the same decks: the same physics to round-off, and the
//! same bits on every GPU run.
//!
//! Needs a device with f64 shaders; on a machine without a GPU, Mesa's software Vulkan
//! (lavapipe, `apt-get install mesa-vulkan-drivers`, which `.ci/run` installs). Without any,
//! each test says SKIPPED and passes.
//!
//! Tolerance: the two steps do the same operations in the same order, but the GPU compiler
//! may fuse a multiply and an add (one rounding instead of two) and the sums of the energy
//! ledger are taken in another order, so results differ by round-off, 1e-16 relative per
//! operation. Over 150 steps of a wave problem the differences grow linearly at most:
//! 1e-10 of the field's largest value bounds them with room (measured: see the test output).

use cleave_core::curve::Curve;
use cleave_core::material::{Eos, JohnsonCook, PiecewiseLinear, RateTable};
use cleave_core::math::{norm, sub, Vec3};
use cleave_core::mesh::BoxMesh;
use cleave_core::model::{
    BodyLoad, ExtraNodes, GivenInertia, Hourglass, HourglassDef, Material, MaterialKind, Model,
    MotionDof, MotionTarget, NodalRigidBody, NodeLoad, NodeSet, Part, PartInertia,
    PrescribedMotion, PressureLoad, RigidWall, Spc, Vad, WallExtent, WallMotion, WallShape,
};
use cleave_core::solver::{Observer, Solver};
use cleave_core::state::RigidState;
mod common;
use cleave_gpu::{Gpu, GpuStepper};
use common::{block, gpu};

/// What a run showed its observer at each state: time, step, energies, positions, velocities,
/// stresses and plastic strains.
#[derive(Default)]
struct Record {
    every: f64,
    next: f64,
    rows: Vec<Row>,
}

#[derive(Clone, Debug, PartialEq)]
struct Row {
    t: f64,
    step: u64,
    energy: [f64; 5],
    x: Vec<Vec3>,
    v: Vec<Vec3>,
    stress: Vec<[f64; 6]>,
    eps_p: Vec<f64>,
}

impl Observer for Record {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        let t = s.state.t;
        if t < self.next * (1.0 - 1e-12) && !s.is_finished() {
            return Ok(());
        }
        self.next = t + self.every;
        let e = s.state.energy;
        self.rows.push(Row {
            t,
            step: s.state.step,
            energy: [
                e.kinetic,
                e.internal,
                e.hourglass,
                e.external_work,
                s.state.initial_energy,
            ],
            x: s.positions().iter().copied().collect(),
            v: s.velocities().iter().copied().collect(),
            stress: s.state.stress.clone(),
            eps_p: s.state.hist.iter().map(|h| h.eps_p).collect(),
        });
        Ok(())
    }
    fn next_due(&self) -> f64 {
        self.next
    }
}

/// A second part, a copy of part 1 changed by `edit`, taking the elements whose stored
/// corners' mean height `z` makes `takes(z)` true.
fn second_part(m: &mut Model, edit: impl FnOnce(&mut Part), takes: impl Fn(f64) -> bool) {
    let mut p = m.parts[0].clone();
    p.id = 2;
    edit(&mut p);
    m.parts.push(p);
    for e in 0..m.num_elements() {
        let zc: f64 = m.conn[e].iter().map(|&n| m.x0[n as usize][2]).sum::<f64>() / 8.0;
        if takes(zc) {
            m.elem_part[e] = 1;
        }
    }
}

fn run_cpu(m: &Model, every: f64) -> Vec<Row> {
    let mut s = Solver::new(m).unwrap();
    let mut r = Record {
        every,
        ..Default::default()
    };
    s.run(&mut r).unwrap();
    r.rows
}

fn run_gpu(g: Gpu, m: &Model, every: f64) -> (Vec<Row>, Gpu) {
    let mut s = Solver::new(m).unwrap();
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let mut r = Record {
        every,
        ..Default::default()
    };
    st.run(&mut s, &mut r).unwrap();
    (r.rows, st.into_gpu())
}

/// Both solvers of model `m` run to the end, the CPU's and the GPU's (outputs every `every`),
/// for a test that looks at state beyond what [`Record`] keeps; and the device back.
fn end_states(g: Gpu, m: &Model, every: f64) -> (Solver<'_>, Solver<'_>, Gpu) {
    let record = || Record {
        every,
        ..Default::default()
    };
    let mut s = Solver::new(m).unwrap();
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    st.run(&mut s, &mut record()).unwrap();
    let mut c = Solver::new(m).unwrap();
    c.run(&mut record()).unwrap();
    (c, s, st.into_gpu())
}

/// Largest |a - b| over the largest |a|, for each field.
fn compare(a: &Row, b: &Row) -> [f64; 4] {
    fn rel<const N: usize>(a: &[[f64; N]], b: &[[f64; N]]) -> f64 {
        let scale = a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let d = (a.iter().flatten().zip(b.iter().flatten()))
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        d / scale.max(f64::MIN_POSITIVE)
    }
    let e_scale = a.energy.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let de = (a.energy.iter().zip(&b.energy)).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    [
        rel(&a.x, &b.x),
        rel(&a.v, &b.v),
        rel(&a.stress, &b.stress),
        de / e_scale,
    ]
}

/// The block of [`block`] with its upper half a part of its own under `*HOURGLASS` (the other
/// form, its own QH, Q1, Q2), and instead of the prescribed motion on the top: a concentrated
/// load down on each top node, a pressure on the top face's quadrilaterals that starts at a
/// birth time, and one triangle `N1 N2 N3 N3` pressed from the side.
fn loaded_block(hourglass: Hourglass) -> Model {
    let mut m = block(hourglass);
    m.prescribed.clear();
    let other = match hourglass {
        Hourglass::Viscous => Hourglass::Stiffness,
        Hourglass::Stiffness => Hourglass::Viscous,
    };
    m.hourglass.push(HourglassDef {
        id: 7,
        hourglass: other,
        qh: 0.08,
        q1: 1.2,
        q2: 0.1,
    });
    second_part(&mut m, |p| p.hourglass = Some(0), |z| z > 0.03);
    let node = |x: f64, y: f64, z: f64| -> u32 {
        (m.x0
            .iter()
            .position(|p| (p[0] - x).abs() + (p[1] - y).abs() + (p[2] - z).abs() < 1e-9))
        .expect("a grid node") as u32
    };
    let h = 0.01;
    let mut loads = Vec::new();
    let mut segments = Vec::new();
    for i in 0..=3 {
        for j in 0..=3 {
            let (x, y) = (i as f64 * h, j as f64 * h);
            loads.push(NodeLoad {
                node: node(x, y, 0.06),
                axis: 2,
                curve: 0,
                sf: -2e4 * (1.0 + i as f64),
            });
            if i < 3 && j < 3 {
                let n = [
                    node(x, y, 0.06),
                    node(x + h, y, 0.06),
                    node(x + h, y + h, 0.06),
                    node(x, y + h, 0.06),
                ];
                segments.push(PressureLoad {
                    nodes: n,
                    curve: 0,
                    sf: 2e8 * (1.0 + j as f64),
                    at: 2e-6,
                });
            }
        }
    }
    // a triangle on the side x = 0, pressing along +x
    segments.push(PressureLoad {
        nodes: [
            node(0.0, 0.0, 0.04),
            node(0.0, 0.01, 0.04),
            node(0.0, 0.0, 0.05),
            node(0.0, 0.0, 0.05),
        ],
        curve: 0,
        sf: 3e8,
        at: 0.0,
    });
    m.node_loads = loads;
    m.pressure_loads = segments;
    m
}

fn check(hourglass: Hourglass) {
    compare_runs(block(hourglass), &format!("{hourglass:?}"));
}

fn compare_runs(m: Model, name: &str) {
    let Some(g) = gpu() else { return };
    let every = m.control.end_time / 7.0;
    let cpu = run_cpu(&m, every);
    let (gpu1, g) = run_gpu(g, &m, every);
    let (gpu2, _) = run_gpu(g, &m, every);
    assert_eq!(gpu1, gpu2, "two GPU runs differ");
    assert_eq!(cpu.len(), gpu1.len(), "the same output times");
    assert!(cpu.len() >= 8);
    let mut worst = [0.0f64; 4];
    for (a, b) in cpu.iter().zip(&gpu1) {
        assert_eq!(a.step, b.step);
        assert!((a.t - b.t).abs() <= 1e-12 * a.t, "t {} vs {}", a.t, b.t);
        let d = compare(a, b);
        for k in 0..4 {
            worst[k] = worst[k].max(d[k]);
        }
    }
    eprintln!("{name}: largest relative differences GPU - CPU: x {:.1e}, v {:.1e}, stress {:.1e}, energies {:.1e}", worst[0], worst[1], worst[2], worst[3]);
    assert!(worst.iter().all(|&d| d < 1e-10), "{worst:?}");
    // the block yields: the plastic branch ran
    let last = cpu.last().unwrap();
    assert!(last.eps_p.iter().any(|&e| e > 0.0));
    let lg = gpu1.last().unwrap();
    let dp = (last.eps_p.iter().zip(&lg.eps_p)).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let pmax = last.eps_p.iter().fold(0.0f64, |m, &a| m.max(a));
    assert!(dp <= 1e-8 * pmax, "plastic strain {dp:e} of {pmax:e}");
}

#[test]
fn viscous_hourglass_matches_the_cpu() {
    check(Hourglass::Viscous);
}

#[test]
fn stiffness_hourglass_matches_the_cpu() {
    check(Hourglass::Stiffness);
}

#[test]
fn loads_and_part_hourglass_match_the_cpu() {
    for hourglass in [Hourglass::Viscous, Hourglass::Stiffness] {
        let m = loaded_block(hourglass);
        // the loads move the block: without them (CPU) the top's velocities differ by more
        // than a tenth of the largest
        let every = m.control.end_time / 7.0;
        let mut bare = m.clone();
        bare.node_loads.clear();
        bare.pressure_loads.clear();
        let (a, b) = (run_cpu(&m, every), run_cpu(&bare, every));
        let d = compare(a.last().unwrap(), b.last().unwrap());
        assert!(
            d[1] > 0.1,
            "the loads change the velocities by {:e} only",
            d[1]
        );
        compare_runs(m, &format!("loads, part {hourglass:?}"));
    }
}

/// The block of [`block`] (viscous hourglass) in each of the other plastic laws: Johnson-Cook
/// (4340 steel, rate and heating) without and with each equation of state, the simplified one
/// with its SIGMAX cap, and `*MAT_024` with a curve and Cowper-Symonds, and with a table of
/// curves by log rate. Each yields (checked in `compare_runs`) and runs on the GPU as on the
/// CPU to round-off; the Johnson-Cook history (temperature rise, ln J, energy) comes back.
#[test]
fn every_plastic_law_matches_the_cpu() {
    let jc = JohnsonCook::STEEL_4340;
    let gruneisen = Eos::Gruneisen {
        c: 4570.0,
        s: [1.49, 0.1, 0.01],
        gamma0: 1.93,
        a: 0.5,
        rho0: 7850.0,
        e0: 1e5,
        v0: 1.0,
    };
    let polynomial = Eos::LinearPolynomial {
        c: [0.0, 1.6e11, 2e11, 1e11, 1.7, 0.5, 0.2],
        e0: 0.0,
        v0: 1.0,
    };
    let curve: std::sync::Arc<[[f64; 2]]> = vec![[0.0, 350e6], [0.05, 420e6], [0.2, 520e6]].into();
    let slow: std::sync::Arc<[[f64; 2]]> = vec![[0.0, 300e6], [0.1, 400e6]].into();
    let fast: std::sync::Arc<[[f64; 2]]> = vec![[0.0, 380e6], [0.1, 470e6], [0.3, 560e6]].into();
    let laws: Vec<(&str, MaterialKind)> = vec![
        ("Johnson-Cook", MaterialKind::JohnsonCook(jc)),
        (
            "Johnson-Cook, Gruneisen",
            MaterialKind::JohnsonCook(JohnsonCook {
                eos: Some(gruneisen),
                ..jc
            }),
        ),
        (
            "Johnson-Cook, linear polynomial",
            MaterialKind::JohnsonCook(JohnsonCook {
                eos: Some(polynomial),
                ..jc
            }),
        ),
        (
            "simplified Johnson-Cook, SIGMAX",
            MaterialKind::JohnsonCook(JohnsonCook {
                sig_max: 900e6,
                m: 1.0,
                t_melt: f64::INFINITY,
                rho_cp: f64::INFINITY,
                ..jc
            }),
        ),
        (
            "MAT_024 curve, Cowper-Symonds",
            MaterialKind::PiecewiseLinear(PiecewiseLinear {
                points: curve,
                c: 40.4,
                p: 5.0,
                lcss: None,
                table: None,
            }),
        ),
        (
            "MAT_024 table by log rate",
            MaterialKind::PiecewiseLinear(PiecewiseLinear {
                points: slow.clone(),
                c: 0.0,
                p: 0.0,
                lcss: None,
                table: Some(std::sync::Arc::new(RateTable {
                    values: vec![-2.0, 3.0, 6.0],
                    log: true,
                    curves: vec![(1, slow.clone()), (2, fast.clone()), (3, fast)],
                })),
            }),
        ),
    ];
    for (name, kind) in laws {
        let mut m = block(Hourglass::Viscous);
        m.materials[0].kind = kind;
        if name.starts_with("Johnson-Cook") {
            // the history the GPU hands back: as the CPU's
            let Some(g) = gpu() else { return };
            let (c, s, _) = end_states(g, &m, m.control.end_time / 7.0);
            let worst = |f: &dyn Fn(&cleave_core::material::History) -> f64| {
                let scale = c
                    .state
                    .hist
                    .iter()
                    .map(|h| f(h).abs())
                    .fold(0.0f64, f64::max);
                let d = (c.state.hist.iter().zip(&s.state.hist))
                    .map(|(a, b)| (f(a) - f(b)).abs())
                    .fold(0.0f64, f64::max);
                (scale, d)
            };
            for (what, f) in [
                (
                    "heat",
                    &(|h: &cleave_core::material::History| h.heat) as &dyn Fn(&_) -> f64,
                ),
                ("ln J", &|h: &cleave_core::material::History| h.ln_j),
                ("energy", &|h: &cleave_core::material::History| h.energy),
            ] {
                let (scale, d) = worst(f);
                assert!(
                    d <= 1e-10 * scale,
                    "{name}: {what} differs by {d:e} of {scale:e}"
                );
            }
            assert!(worst(&|h| h.heat).0 > 0.0, "{name}: the block heats");
        }
        compare_runs(m, name);
    }
}

/// The block of [`block`] cut into tetrahedra (ELFORM 10, and ELFORM 1, which runs the same
/// constant-strain kernel on a tetrahedron; ELFORM 13 with nodal pressure averaging, alone and
/// over a lower half in ELFORM 10) and into wedges (ELFORM 1: the one-point hexahedron on the
/// degenerate corners), the same nodes, loads and constraints, 150 steps: the GPU as the CPU
/// to round-off.
#[test]
fn tetrahedra_and_wedges_match_the_cpu() {
    type Cut = fn(&BoxMesh) -> BoxMesh;
    let cuts: [(&str, Cut, i32); 5] = [
        ("tetrahedra, ELFORM 10", BoxMesh::split_tets, 10),
        ("tetrahedra, ELFORM 1", BoxMesh::split_tets, 1),
        ("wedges, ELFORM 1", BoxMesh::split_wedges, 1),
        ("tetrahedra, ELFORM 13", BoxMesh::split_tets, 13),
        // the upper half ELFORM 13, the lower ELFORM 10: the nodes between average over their
        // ELFORM 13 elements only
        ("tetrahedra, ELFORM 13 over 10", BoxMesh::split_tets, -13),
    ];
    for (name, cut, elform) in cuts {
        let mut m = block(Hourglass::Viscous);
        let mesh = cut(&BoxMesh::new([3, 3, 6], [0.03, 0.03, 0.06]));
        assert_eq!(mesh.x.len(), m.x0.len(), "the same nodes");
        let ne = mesh.conn.len();
        m.conn = mesh.conn;
        m.elem_ids = (1..=ne as i64).collect();
        m.elem_part = vec![0; ne];
        m.sections[0].elform = elform.abs();
        if elform < 0 {
            // part 2 (the lower half) in a section of ELFORM 10
            m.sections
                .push(cleave_core::model::Section { id: 2, elform: 10 });
            second_part(&mut m, |p| p.section = 1, |z| z < 0.03);
        }
        let (dt, _) = cleave_core::setup::estimate_time_step(&m).unwrap();
        m.control.end_time = 150.0 * dt * m.control.tssfac;
        compare_runs(m, name);
    }
}

/// Rigid bodies on the block of [`block`] (viscous hourglass), 150 steps, the GPU as the CPU:
/// - its top layer of elements a `*MAT_RIGID` part, driven down by a prescribed velocity of
///   the part (ramped) while the initial shear and the body load turn and push it;
/// - the same with a prescribed displacement, so the part ends where the curve puts it;
/// - instead, its top nodes a nodal rigid body with constraints (x translation and rotation
///   about x fixed), free otherwise, with a concentrated load on one of its nodes;
/// - the first case on the block cut into ELFORM 13 tetrahedra.
#[test]
fn rigid_bodies_match_the_cpu() {
    for case in [
        "rigid part, velocity",
        "rigid part, displacement",
        "rigid part, velocity along a vector (DOF 4), turned about one (DOF -8)",
        "rigid part, displacement along a vector, its normal held (DOF -4), turned about z (DOF 7)",
        "nodal rigid body",
        "nodes, displacement along a vector (DOF -4 and 4)",
        "rigid part, velocity, ELFORM 13 tetrahedra",
    ] {
        let mut m = block(Hourglass::Viscous);
        if case.ends_with("tetrahedra") {
            // the block cut into ELFORM 13 tetrahedra, rigid ones among them: a rigid
            // tetrahedron takes part in the pressure averages, and its corrections must not
            // pile up in its corner forces from step to step
            let mesh = BoxMesh::new([3, 3, 6], [0.03, 0.03, 0.06]).split_tets();
            let ne = mesh.conn.len();
            m.conn = mesh.conn;
            m.elem_ids = (1..=ne as i64).collect();
            m.elem_part = vec![0; ne];
            m.sections[0].elform = 13;
            let (dt, _) = cleave_core::setup::estimate_time_step(&m).unwrap();
            m.control.end_time = 150.0 * dt * m.control.tssfac;
        }
        m.prescribed.clear();
        let top: Vec<u32> = (0..m.x0.len() as u32)
            .filter(|&n| (m.x0[n as usize][2] - 0.06).abs() < 1e-9)
            .collect();
        if case.starts_with("rigid part") {
            rigid_top(&mut m);
            let vad = if case.contains("velocity") {
                Vad::Velocity
            } else {
                Vad::Displacement
            };
            let sf = if vad == Vad::Velocity { -40.0 } else { -2e-4 };
            let third = 1.0 / 3.0;
            let (dof, turn) = if case.contains("DOF 4") {
                (
                    MotionDof::Along {
                        dir: [third, -2.0 * third, -2.0 * third],
                        only: false,
                    },
                    Some(MotionDof::Rotation {
                        dir: [0.6, 0.0, 0.8],
                        only: true,
                    }),
                )
            } else if case.contains("DOF -4") {
                (
                    MotionDof::Along {
                        dir: [0.0, 0.6, -0.8],
                        only: true,
                    },
                    Some(MotionDof::Rotation {
                        dir: [0.0, 0.0, 1.0],
                        only: false,
                    }),
                )
            } else {
                (MotionDof::Axis(2), None)
            };
            m.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Rigid(1),
                dof,
                vad,
                curve: 0,
                sf,
            });
            if let Some(dof) = turn {
                // the turn stops driving the body halfway (DEATH): it spins on freely
                m.prescribed.push(PrescribedMotion {
                    window: cleave_core::model::Window {
                        birth: 0.0,
                        death: 0.5 * m.control.end_time,
                    },
                    target: MotionTarget::Rigid(1),
                    dof,
                    vad: Vad::Velocity,
                    curve: 0,
                    sf: 300.0,
                });
            }
        } else if case.starts_with("nodes") {
            // the top face pulled along a vector, its normal motion held; one corner free
            // across it
            for (k, &n) in top.iter().enumerate() {
                if k == 0 {
                    // the free corner pushed across from a quarter of the run on (BIRTH)
                    m.prescribed.push(PrescribedMotion {
                        window: cleave_core::model::Window {
                            birth: 0.25 * m.control.end_time,
                            death: f64::INFINITY,
                        },
                        target: MotionTarget::Node(n),
                        dof: MotionDof::Axis(0),
                        vad: Vad::Velocity,
                        curve: 0,
                        sf: 0.5,
                    });
                }
                m.prescribed.push(PrescribedMotion {
                    window: cleave_core::model::Window::ALWAYS,
                    target: MotionTarget::Node(n),
                    dof: MotionDof::Along {
                        dir: [0.0, 0.6, 0.8],
                        only: k > 0,
                    },
                    vad: Vad::Displacement,
                    curve: 0,
                    sf: 2e-4,
                });
            }
            let Some(g) = gpu() else { return };
            let moved = {
                let (c, _, _) = end_states(g, &m, m.control.end_time / 7.0);
                let x = c.positions();
                let u = |n: u32| sub(x[n as usize], m.x0[n as usize]);
                // the held nodes move along the vector only; the free one across it too
                let held = u(top[1]);
                let along = held[1] * 0.6 + held[2] * 0.8;
                assert!(
                    norm(sub(held, [0.0, 0.6 * along, 0.8 * along])) <= 1e-12 * along.abs(),
                    "{case}: {held:?}"
                );
                along
            };
            assert!(moved.abs() > 1e-6, "{case}: the nodes move ({moved})");
            compare_runs(m, case);
            continue;
        } else {
            m.node_sets.push(NodeSet {
                id: 5,
                nodes: top.clone(),
            });
            m.nodal_rigid.push(NodalRigidBody {
                id: 9,
                set: 0,
                cmo: 1,
                con1: 1,
                con2: 1,
                inertia: None,
            });
            m.node_loads.push(NodeLoad {
                node: top[0],
                axis: 2,
                curve: 0,
                sf: -5e5,
            });
        }
        // the body moves and turns: its state comes back as the CPU's
        let Some(g) = gpu() else { return };
        let (c, s, _) = end_states(g, &m, m.control.end_time / 7.0);
        assert_eq!(s.setup.rigid.len(), 1, "{case}");
        let (a, b) = (&c.state.rigid[0], &s.state.rigid[0]);
        let speed = a
            .v_cm
            .iter()
            .chain(&a.omega)
            .fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(speed > 1.0, "{case}: the body moves ({speed})");
        same_placement(a, b, case);
        compare_runs(m, case);
    }
}

/// The block's top layer of elements (above 5 cm) a `*MAT_RIGID` part of its own (part 1,
/// material 1).
fn rigid_top(m: &mut Model) {
    let mut steel = m.materials[0].clone();
    steel.id = 2;
    steel.kind = MaterialKind::Rigid {
        cmo: 0,
        con1: 0,
        con2: 0,
    };
    m.materials.push(steel);
    second_part(m, |p| p.material = 1, |z| z > 0.05);
}

/// A rigid body's placement on the CPU (`a`) and the GPU (`b`): its centre within 1e-12 of the
/// block's 6 cm, its rotation within 1e-12.
fn same_placement(a: &RigidState, b: &RigidState, case: &str) {
    for (x, y) in a.x_cm.iter().zip(&b.x_cm) {
        assert!(
            (x - y).abs() <= 1e-12 * 0.06,
            "{case}: centre {:?} vs {:?}",
            a.x_cm,
            b.x_cm
        );
    }
    for (x, y) in a.rot.iter().flatten().zip(b.rot.iter().flatten()) {
        assert!(
            (x - y).abs() <= 1e-12,
            "{case}: rotation {:?} vs {:?}",
            a.rot,
            b.rot
        );
    }
}

/// A rigid body with a given inertia (`*PART_INERTIA`) on the block of [`block`] (viscous
/// hourglass, its prescribed motion left off), 150 steps, the GPU as the CPU: the block's top
/// layer of elements a `*MAT_RIGID` part given TM 0.5 kg (seven times its elements' mass,
/// which the body then drops) at a centre off its own, two nodes below it its extra nodes with
/// their own mass (IFLAG 1, so the body's centre of mass is not the given centre), an inertia with products and an
/// initial velocity and spin (VT (5, -3, -20) m/s, VR (200, -100, 300) rad/s), under the
/// block's ramped body load, which acts on the given mass at its centre. The given mass
/// carries most of the kinetic energy (the body's own term, from its placements: no node
/// carries it), so the energies compare it, from the first step (whose rate before t^0 comes
/// from the initial velocities) on; its centre, rotation and the momentum the solver reports
/// come back as the CPU's.
#[test]
fn a_given_inertia_matches_the_cpu() {
    let mut m = block(Hourglass::Viscous);
    m.prescribed.clear();
    rigid_top(&mut m);
    m.part_inertia.push(PartInertia {
        part: 1,
        given: GivenInertia {
            centre: [0.02, 0.01, 0.058],
            mass: 0.5,
            inertia: [[4e-5, -1e-5, 5e-6], [-1e-5, 6e-5, 2e-6], [5e-6, 2e-6, 9e-5]],
            velocity: [5.0, -3.0, -20.0],
            omega: [200.0, -100.0, 300.0],
        },
    });
    // two nodes of the layer below the part move with it as extra nodes whose own mass is
    // added to the given one (IFLAG 1): the body's centre of mass then lies off the given
    // centre, and the body load on the given mass turns the body about it
    let below: Vec<u32> = (0..m.x0.len() as u32)
        .filter(|&n| {
            let x = m.x0[n as usize];
            (x[2] - 0.04).abs() < 1e-9 && x[0] < 1e-9
        })
        .take(2)
        .collect();
    m.extra_nodes.push(ExtraNodes {
        part: 1,
        set: None,
        nodes: below,
        iflag: true,
    });
    let Some(g) = gpu() else { return };
    let (c, s, _) = end_states(g, &m, m.control.end_time / 7.0);
    assert_eq!(s.setup.rigid.len(), 1);
    let body = &s.setup.rigid[0];
    let u = body.unlumped.as_ref().unwrap();
    assert!(norm(sub(body.x_cm0, u.centre)) > 1e-4, "{:?}", body.x_cm0);
    let (a, b) = (&c.state.rigid[0], &s.state.rigid[0]);
    same_placement(a, b, "given inertia");
    // the body turned, and its given mass holds most of the kinetic energy
    assert!(a.rot[0][0] < 1.0 - 1e-4, "{:?}", a.rot);
    let ke = c.state.energy.kinetic;
    assert!(ke > 50.0, "kinetic energy {ke}");
    let (pa, pb) = (c.momentum(), s.momentum());
    let dp = norm(sub(pa, pb)) / norm(pa);
    eprintln!("given inertia: kinetic energy {ke:.4} J, momentum {pa:?}, GPU - CPU {dp:.1e}");
    assert!(dp <= 1e-10, "momentum {pa:?} vs {pb:?}");
    compare_runs(m, "given inertia");
}

/// The block of [`block`] in fully integrated, selectively reduced hexahedra (ELFORM 2): with
/// its bilinear plastic steel, with Johnson-Cook and a Mie-Gruneisen equation of state at each
/// Gauss point, and over a lower half in one-point hexahedra (ELFORM 1).
#[test]
fn fully_integrated_hexahedra_match_the_cpu() {
    for case in ["ELFORM 2", "ELFORM 2, Johnson-Cook", "ELFORM 2 over 1"] {
        let mut m = block(Hourglass::Viscous);
        m.sections[0].elform = 2;
        if case.ends_with("Johnson-Cook") {
            m.materials[0].kind = MaterialKind::JohnsonCook(JohnsonCook {
                eos: Some(Eos::Gruneisen {
                    c: 4570.0,
                    s: [1.49, 0.0, 0.0],
                    gamma0: 1.93,
                    a: 0.5,
                    rho0: 7850.0,
                    e0: 0.0,
                    v0: 1.0,
                }),
                ..JohnsonCook::STEEL_4340
            });
        }
        if case.ends_with("over 1") {
            m.sections
                .push(cleave_core::model::Section { id: 2, elform: 1 });
            second_part(&mut m, |p| p.section = 1, |z| z < 0.03);
        }
        compare_runs(m, case);
    }
}

/// Element erosion on the block of [`block`] (viscous hourglass), its rules set so that some
/// elements erode during the run and some do not: FS at half the largest plastic strain the
/// block reaches without erosion; Johnson-Cook damage (4340 steel, D1-D5 scaled so that it
/// reaches 1 in the run); `*MAT_ADD_EROSION` SIGVM and FAILTM with NCS 2; SIGP1, MXEPS or
/// MNEPS, EFFEPS or VOLEPS, each at half the block's largest value without erosion. The GPU erodes the
/// same elements as the CPU, books the same eroded energy, and its fields match to round-off.
#[test]
fn erosion_matches_the_cpu() {
    use cleave_core::erosion::{ErosionDef, ErosionRule, JcDamage};
    let Some(g) = gpu() else { return };
    let plain = block(Hourglass::Viscous);
    let every = plain.control.end_time / 7.0;
    let rows = run_cpu(&plain, every);
    let eps_max = rows
        .last()
        .unwrap()
        .eps_p
        .iter()
        .fold(0.0f64, |m, &e| m.max(e));
    let cases: Vec<(&str, MaterialKind, ErosionRule)> = vec![
        (
            "FS",
            plain.materials[0].kind.clone(),
            ErosionRule {
                plastic_strain: Some(0.5 * eps_max),
                ncs: 1,
                ..Default::default()
            },
        ),
        (
            "Johnson-Cook damage",
            MaterialKind::JohnsonCook(JohnsonCook::STEEL_4340),
            ErosionRule {
                johnson_cook: Some(JcDamage {
                    d: [0.05 * eps_max, 0.1 * eps_max, -1.5, 0.014, 0.6],
                    efmin: 1e-6,
                }),
                ncs: 1,
                ..Default::default()
            },
        ),
        (
            "SIGVM and FAILTM, NCS 2",
            plain.materials[0].kind.clone(),
            ErosionRule {
                max_von_mises: Some(320e6),
                failure_time: Some(0.4 * plain.control.end_time),
                ncs: 2,
                ..Default::default()
            },
        ),
    ];
    // the principal criteria, each at half the largest value the block reaches without
    // erosion: the largest principal stress, and the element's principal log strains
    let mut cpu = Solver::new(&plain).unwrap();
    cpu.run(&mut Record {
        every,
        ..Default::default()
    })
    .unwrap();
    let sig1 = (cpu.state.stress.iter())
        .map(|s| cleave_core::math::principal_values(s)[2])
        .fold(f64::MIN, f64::max);
    let strains: Vec<[f64; 3]> = (plain.conn.iter())
        .map(|c| {
            let x: [[f64; 3]; 8] = c.map(|n| cpu.positions()[n as usize]);
            let x0: [[f64; 3]; 8] = c.map(|n| plain.x0[n as usize]);
            let j = cleave_core::element::hex8::jacobian_at;
            let j0 = cleave_core::math::inverse(&j(&x0, [0.0; 3])).unwrap();
            cleave_core::erosion::principal_log_strains(&j(&x, [0.0; 3]), &j0)
        })
        .collect();
    let top = |f: &dyn Fn(&[f64; 3]) -> f64| strains.iter().map(f).fold(f64::MIN, f64::max);
    let eff = |e: &[f64; 3]| {
        let v = (e[0] + e[1] + e[2]) / 3.0;
        (2.0 / 3.0 * e.iter().map(|x| (x - v) * (x - v)).sum::<f64>()).sqrt()
    };
    let mut cases = cases;
    cases.push((
        "SIGP1",
        plain.materials[0].kind.clone(),
        ErosionRule {
            max_principal: Some(0.5 * sig1),
            ncs: 1,
            ..Default::default()
        },
    ));
    cases.push((
        "MXEPS or MNEPS",
        plain.materials[0].kind.clone(),
        ErosionRule {
            max_principal_strain: Some(0.5 * top(&|e| e[2])),
            min_principal_strain: Some(-0.5 * top(&|e| -e[0])),
            ncs: 1,
            ..Default::default()
        },
    ));
    cases.push((
        "EFFEPS or VOLEPS",
        plain.materials[0].kind.clone(),
        ErosionRule {
            effective_strain: Some(0.5 * top(&eff)),
            volumetric_strain: Some(-0.5 * top(&|e| -(e[0] + e[1] + e[2]))),
            ncs: 1,
            ..Default::default()
        },
    ));
    let mut g = Some(g);
    for (name, kind, rule) in cases {
        let mut m = plain.clone();
        m.materials[0].kind = kind;
        m.erosion = vec![ErosionDef { material: 0, rule }];
        let (c, s, back) = end_states(g.take().unwrap(), &m, every);
        g = Some(back);
        let n = c.eroded_count();
        eprintln!("{name}: {n} of {} elements eroded", m.num_elements());
        assert!(n > 0 && n < m.num_elements(), "{name}: {n} eroded");
        assert_eq!(
            c.state.eroded, s.state.eroded,
            "{name}: the same elements erode"
        );
        let (a, b) = (c.state.energy.eroded, s.state.energy.eroded);
        assert!(
            a > 0.0 && (a - b).abs() <= 1e-10 * a,
            "{name}: eroded energy {a} vs {b}"
        );
        // the end states (the output times and bit-identical reruns are the other tests')
        let rel = |u: Vec<[f64; 3]>, w: Vec<[f64; 3]>| {
            let scale = u.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
            let d = (u.iter().flatten().zip(w.iter().flatten()))
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            d / scale
        };
        let dx = rel(
            c.positions().iter().copied().collect(),
            s.positions().iter().copied().collect(),
        );
        let dv = rel(
            c.velocities().iter().copied().collect(),
            s.velocities().iter().copied().collect(),
        );
        let ds = {
            let scale = c
                .state
                .stress
                .iter()
                .flatten()
                .fold(0.0f64, |m, x| m.max(x.abs()));
            (c.state
                .stress
                .iter()
                .flatten()
                .zip(s.state.stress.iter().flatten()))
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
                / scale
        };
        let e = (c.state.energy.total() - s.state.energy.total()).abs() / c.state.energy.total();
        eprintln!(
            "{name}: GPU - CPU at the end: x {dx:.1e}, v {dv:.1e}, stress {ds:.1e}, energy {e:.1e}"
        );
        assert!(
            dx < 1e-10 && dv < 1e-10 && ds < 1e-10 && e < 1e-10,
            "{name}"
        );
    }
}

/// Tied contact: a block of 3 x 3 x 2 hexahedra tied on a coarser one of 2 x 2 x 1 (the
/// interface's nodes do not match), the lower block clamped at its base, the upper one moving
/// with a shear velocity under a body load and a load on a top corner; 150 steps, the GPU as
/// the CPU, the slave nodes on their faces.
#[test]
fn tied_contact_matches_the_cpu() {
    use cleave_core::mesh::Assembly;
    use cleave_core::model::{ContactSurface, TiedDef, TiedSlave};
    let mut a = Assembly::new("tied blocks", 1.0);
    let steel = a.material(Material {
        id: 0,
        density: 7850.0,
        young: 210e9,
        poisson: 0.3,
        kind: MaterialKind::PlasticKinematic {
            sigy: 300e6,
            etan: 2e9,
            beta: 0.5,
        },
    });
    let lower = a.part("lower", steel);
    let upper = a.part("upper", steel);
    a.mesh(BoxMesh::new([2, 2, 1], [0.02, 0.02, 0.01]), |_| lower);
    let mut top = BoxMesh::new([3, 3, 2], [0.02, 0.02, 0.01]);
    top.translate([0.0, 0.0, 0.01]);
    let (up_nodes, _) = a.mesh(top, |_| upper);
    let mut m = a.finish();
    m.tied = vec![TiedDef {
        id: 1,
        slave: TiedSlave::Surface(ContactSurface::Part(upper)),
        master: ContactSurface::Part(lower),
    }];
    for i in 0..m.x0.len() {
        let x = m.x0[i];
        if x[2] < 1e-9 {
            m.spcs.push(Spc {
                node: i as u32,
                dof: [true, true, true, false, false, false],
            });
        }
    }
    for i in up_nodes.clone() {
        let z = m.x0[i as usize][2];
        m.v0.as_mut_slice()[i as usize] = [20.0 * z / 0.02, 0.0, -5.0];
    }
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 5e-6, 1.0],
        y: vec![0.0, 1.0, 1.0],
    });
    m.body_loads.push(BodyLoad {
        axis: 1,
        curve: Some(0),
        sf: 5e5,
    });
    m.node_loads.push(NodeLoad {
        node: up_nodes.end - 1,
        axis: 0,
        curve: 0,
        sf: 3e4,
    });
    let (dt, _) = cleave_core::setup::estimate_time_step(&m).unwrap();
    m.control.end_time = 150.0 * dt * m.control.tssfac;
    let s = Solver::new(&m).unwrap();
    assert!(
        s.ties().len() >= 9,
        "the interface's slave nodes are tied: {}",
        s.ties().len()
    );
    compare_runs(m, "tied contact");
}

/// `cleave bench --gpu` times each pass over ten steps taken with every pass in a compute pass
/// of its own: those steps are the model's steps (the run goes on from them to the same end
/// state, bit for bit, as a run without them), and the passes' shares add up to one.
#[test]
fn profiled_steps_are_the_same_steps() {
    let Some(g) = gpu() else { return };
    let m = block(Hourglass::Viscous);
    let end = m.control.end_time;
    let (plain, g) = run_gpu(g, &m, end);
    let mut s = Solver::new(&m).unwrap();
    let mut st = GpuStepper::new(g, &mut s).unwrap();
    let shares = st.profile(&mut s, 10);
    let mut r = Record {
        every: end,
        ..Default::default()
    };
    st.run(&mut s, &mut r).unwrap();
    assert_eq!(plain.last(), r.rows.last(), "the end states differ");
    match shares {
        Some(sh) => {
            let total: f64 = sh.iter().map(|(_, f)| f).sum();
            assert!((total - 1.0).abs() < 1e-12, "{sh:?}");
            assert!(sh.iter().all(|&(_, f)| f >= 0.0), "{sh:?}");
            let names: Vec<&str> = sh.iter().map(|(n, _)| *n).collect();
            assert_eq!(names, ["elements", "control", "nodes", "finish"]);
            eprintln!("passes over 10 steps: {sh:?}");
        }
        None => eprintln!("SKIPPED the shares: the device has no timestamp queries"),
    }
}

/// Planar rigid walls with friction: one finite (`_FINITE`: its rectangle turned 45 degrees
/// under the block's bottom, covering part of it) and one unbounded beside the block. The
/// block, thrown down and sideways at 30 and 6 m/s, lands on them and yields as on the CPU.
#[test]
fn rigid_walls_match_the_cpu() {
    let mut m = block(Hourglass::Viscous);
    m.spcs.clear();
    m.prescribed.clear();
    m.body_loads.clear();
    for v in m.v0.as_mut_slice() {
        *v = [6.0, 2.0, -30.0];
    }
    let s = 0.5f64.sqrt();
    m.rigid_walls.push(RigidWall {
        shape: cleave_core::model::WallShape::Plane,
        motion: None,
        id: 1,
        nodes: None,
        tail: [0.0, -0.01, -0.0002],
        head: [0.0, -0.01, 0.9998],
        fric: 0.3,
        extent: Some(WallExtent {
            l: [s, s, 0.0],
            len_l: 0.03,
            len_m: 0.02,
        }),
    });
    m.rigid_walls.push(RigidWall {
        shape: cleave_core::model::WallShape::Plane,
        motion: None,
        id: 2,
        nodes: None,
        tail: [0.0301, 0.0, 0.0],
        head: [-0.9699, 0.0, 0.0],
        fric: 0.0,
        extent: None,
    });
    compare_runs(m, "rigid walls");
}

/// Geometric rigid walls: the block, thrown down at 30 m/s onto a fixed rod (a finite cylinder
/// along x), is hit on its top by a sphere driven down at 40 m/s (a velocity curve) and on its
/// side by a finite plane driven by a displacement curve; as on the CPU.
#[test]
fn geometric_walls_match_the_cpu() {
    let mut m = block(Hourglass::Viscous);
    m.spcs.clear();
    m.prescribed.clear();
    m.body_loads.clear();
    for v in m.v0.as_mut_slice() {
        *v = [0.0, 0.0, -30.0];
    }
    let t_end = m.control.end_time;
    m.curves.push(Curve {
        id: 2,
        t: vec![0.0],
        y: vec![40.0],
    });
    m.curves.push(Curve {
        id: 3,
        t: vec![0.0, t_end],
        y: vec![0.0, 0.004],
    });
    let wall = |tail: [f64; 3], head: [f64; 3], shape, motion| RigidWall {
        id: 1,
        nodes: None,
        tail,
        head,
        fric: 0.2,
        extent: None,
        shape,
        motion,
    };
    m.rigid_walls.push(wall(
        [-0.01, 0.015, -0.0045],
        [1.0, 0.015, -0.0045],
        WallShape::Cylinder {
            radius: 0.004,
            length: 0.03,
        },
        None,
    ));
    m.rigid_walls.push(wall(
        [0.015, 0.015, 0.0805],
        [0.015, 0.015, 1.0],
        WallShape::Sphere { radius: 0.02 },
        Some(WallMotion {
            curve: 1,
            displacement: false,
            dir: [0.0, 0.0, -1.0],
        }),
    ));
    let mut side = wall(
        [0.0305, -0.01, -0.01],
        [-0.9695, -0.01, -0.01],
        WallShape::Plane,
        Some(WallMotion {
            curve: 2,
            displacement: true,
            dir: [-1.0, 0.0, 0.0],
        }),
    );
    side.extent = Some(WallExtent {
        l: [0.0, 1.0, 0.0],
        len_l: 0.05,
        len_m: 0.04,
    });
    m.rigid_walls.push(side);
    compare_runs(m, "geometric walls");
}

/// LCTM of `*CONTROL_TIMESTEP`: a curve of the largest time step, 0 (no limit) at first, then
/// below the block's own step, rising above it, and ending before the run does; the steps and
/// the fields as on the CPU.
#[test]
fn a_time_step_curve_matches_the_cpu() {
    let mut m = block(Hourglass::Viscous);
    let (dt, _) = cleave_core::setup::estimate_time_step(&m).unwrap();
    let own = dt * m.control.tssfac;
    let t_end = m.control.end_time;
    // 0 (no limit) for the first quarter, then below the block's own step, rising above it,
    // and nothing past 0.8 of the run (the computed step)
    m.curves.push(Curve {
        id: 9,
        t: vec![0.0, 0.25 * t_end, 0.26 * t_end, 0.5 * t_end, 0.8 * t_end],
        y: vec![0.0, 0.0, 0.6 * own, 0.6 * own, 2.0 * own],
    });
    m.control.dt_max_curve = Some(m.curves.len() - 1);
    compare_runs(m, "time step curve");
}
