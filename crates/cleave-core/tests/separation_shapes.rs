//! Element separation on tetrahedra and wedges: interfaces are shared triangles (and the
//! wedges' quadrilaterals), each element gets a node per distinct corner. The checks of
//! `separation.rs` on these shapes: continuity before failure, the pulled bar's break time
//! and place, GC per unit area under the cohesive law, momentum through fragmentation.
//! Print the numbers with `cargo test --release --test separation_shapes -- --nocapture`.

use cleave_core::curve::Curve;
use cleave_core::element::shape::face_points;
use cleave_core::mesh::{single_part_model, BoxMesh};
use cleave_core::model::{
    Material, Model, MotionTarget, Part, PrescribedMotion, SeparationDef, Spc, Vad,
};
use cleave_core::separation::interfaces::{face_centroid, Separation, Status};
use cleave_core::separation::split::split_model;
use cleave_core::solver::Solver;
mod common;
use common::Obs;

const RHO: f64 = 7800.0;
const YOUNG: f64 = 200e9;
const BAR_L: f64 = 0.1;
const BAR_N: usize = 40;
const PULL: f64 = 10.0;

fn elastic(poisson: f64) -> Material {
    common::elastic_steel(poisson)
}

fn separation(model: i32, sigmax: f64, gc: f64) -> SeparationDef {
    SeparationDef {
        material: 0,
        model,
        sigmax,
        beta: 1.0,
        gc,
        bond: 1,
        strength: Default::default(),
    }
}

/// The two meshes of each test: a structured box cut into tetrahedra and into wedges.
fn cuts(b: &BoxMesh) -> [(&'static str, BoxMesh); 2] {
    [("tetrahedra", b.split_tets()), ("wedges", b.split_wedges())]
}

/// Continuity: every element in a group that never fails, the split tetrahedra and wedges
/// move as the unsplit mesh, to round-off (|x_copy - x_orig| below 1e-9 of the largest
/// displacement at every step; only the order of the force sums differs), with a node per
/// distinct corner (4 per tetrahedron, 6 per wedge). A 4 x 3 x 3 block, clamped at x = 0,
/// with a spinning and stretching initial velocity field and its far face pushed sideways.
#[test]
fn split_tetrahedra_and_wedges_move_as_the_original() {
    let b = BoxMesh::new([4, 3, 3], [0.04, 0.03, 0.03]);
    for (name, mesh) in cuts(&b) {
        let mut m = single_part_model(mesh, elastic(0.3), 20e-6);
        for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
            *v = [
                5.0 - 300.0 * x[1],
                300.0 * x[0] + 100.0 * x[2],
                2.0 * x[0] / 0.04,
            ];
        }
        for node in m.nodes_where(0, 0.0, 1e-9) {
            m.spcs.push(Spc {
                node,
                dof: [true, true, true, false, false, false],
            });
        }
        m.curves.push(Curve {
            id: 1,
            t: vec![0.0],
            y: vec![1.0],
        });
        for node in m.nodes_where(0, 0.04, 1e-9) {
            m.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(node),
                dof: cleave_core::model::MotionDof::Axis(1),
                vad: Vad::Velocity,
                curve: 0,
                sf: 3.0,
            });
        }
        let mut grouped = m.clone();
        grouped.separations.push(common::unbreakable(0));
        let split = split_model(&grouped);
        let per = if name == "tetrahedra" { 4 } else { 6 };
        assert_eq!(split.model.num_nodes(), per * m.num_elements(), "{name}");
        let mut hist_a = Vec::new();
        let mut a = Solver::new(&m).unwrap();
        a.run(&mut Obs(|s: &Solver| hist_a.push(s.positions().to_vec())))
            .unwrap();
        let mut hist_b = Vec::new();
        let mut s = Solver::new(&split.model).unwrap();
        s.attach_separation(Separation::new(&split).unwrap());
        s.run(&mut Obs(|s: &Solver| hist_b.push(s.positions().to_vec())))
            .unwrap();
        assert_eq!(hist_a.len(), hist_b.len(), "{name}: same number of steps");
        let scale = common::motion_scale(hist_a.last().unwrap(), &m.x0.to_vec());
        let worst = common::copy_deviation(&hist_a, &hist_b, &split.origin);
        let (ea, eb) = (a.state.energy, s.state.energy);
        eprintln!(
            "continuity on {name}: {} interfaces, max |x_copy - x_orig| {worst:.3e} m of motion {scale:.3e} m, {} steps; energy {:.6e} vs {:.6e} J",
            split.interfaces,
            hist_a.len(),
            ea.total(),
            eb.total()
        );
        assert!(scale > 1e-5);
        assert!(worst < 1e-9 * scale, "{name}");
        assert!(
            (ea.total() - eb.total()).abs() < 1e-9 * ea.total(),
            "{name}"
        );
    }
}

/// A 40 x 1 x 1-cell elastic bar (Poisson 0) 0.1 m long, cut into 240 tetrahedra or 80
/// wedges, every element in a group, both ends driven outwards at 10 m/s: the tensile waves
/// rho c v meet at the middle at L/(2c), where the stress doubles.
fn pulled_bar(mesh: BoxMesh, sep: SeparationDef, end_time: f64) -> Model {
    let mut m = single_part_model(mesh, elastic(0.0), end_time);
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0],
        y: vec![1.0],
    });
    for (x, sf) in [(0.0, -PULL), (BAR_L, PULL)] {
        for node in m.nodes_where(0, x, 1e-12) {
            m.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(node),
                dof: cleave_core::model::MotionDof::Axis(0),
                vad: Vad::Velocity,
                curve: 0,
                sf,
            });
        }
    }
    m.separations.push(sep);
    m
}

/// MODEL 1 (normal stress), SIGMAX = 1.5 rho c v: as on hexahedra, the bar breaks where the
/// waves meet, once they have met: the first interface fails no earlier than L/(2c) and no
/// later than L/(2c) + 2h/c; every failed interface is within two cells of the middle and
/// faces along x (the cut cells' inner faces carry at most n_x^2 = 1/2 of the axial stress,
/// below the strength); the two largest fragments are equal halves moving apart; the total
/// momentum stays near zero, the ends being driven alike: within 1e-10 of the impulse of one
/// end on the tetrahedra (Kuhn's cut is symmetric about the bar's centre, so the ends'
/// reactions cancel to round-off) and 1e-6 on the wedges (every cell is cut along the same
/// diagonal, which the mirror about the middle turns round: measured 1.6e-7).
#[test]
fn pulled_tetrahedral_and_wedge_bars_break_in_the_middle() {
    let c = (YOUNG / RHO).sqrt();
    let rcv = RHO * c * PULL;
    let h = BAR_L / BAR_N as f64;
    let t_end = 0.9 * BAR_L / c;
    let t_meet = BAR_L / (2.0 * c);
    let b = BoxMesh::new([BAR_N, 1, 1], [BAR_L, h, h]);
    for (name, mesh) in cuts(&b) {
        let split = split_model(&pulled_bar(mesh, separation(1, 1.5 * rcv, 0.0), t_end));
        let mut s = Solver::new(&split.model).unwrap();
        s.attach_separation(Separation::new(&split).unwrap());
        let mut t_fail = None;
        s.run(&mut Obs(|s: &Solver| {
            if t_fail.is_none() && s.separation().unwrap().num_failed() > 0 {
                t_fail = Some(s.state.t);
            }
        }))
        .unwrap();
        let t_fail = t_fail.expect("the bar breaks");
        let sep = s.separation().unwrap();
        for i in sep.failed_interfaces() {
            let face = &sep.faces()[i];
            let xc = face_centroid(face, &split.model.x0)[0];
            assert!(
                (xc - BAR_L / 2.0).abs() <= 2.0 * h + 1e-12,
                "{name}: failed interface at x = {xc}"
            );
            // a face across the bar: all its points at one x
            let pts = face_points(&std::array::from_fn(|k| face.nodes[k]));
            for k in 0..pts {
                let x = split.model.x0[face.nodes[k] as usize][0];
                assert!((x - xc).abs() < 1e-12, "{name}: an inclined face failed");
            }
        }
        let frags = sep.fragments(&s.model.conn, s.model.num_nodes()).summaries(
            &s.model.conn,
            &s.setup.mass,
            s.positions(),
            s.velocities(),
        );
        let (fa, fb) = (frags[0], frags[1]);
        let impulse = rcv * h * h * t_end;
        let p = s.momentum();
        eprintln!(
            "pulled {name} bar: first failure at {:.4} us (waves meet {:.4} us, + 2 crossings {:.4} us); {} failed interfaces, {} fragments, halves {} + {} elements; total momentum {:.2e} of {impulse:.2e}",
            t_fail * 1e6,
            t_meet * 1e6,
            (t_meet + 2.0 * h / c) * 1e6,
            sep.num_failed(),
            frags.len(),
            fa.elements,
            fb.elements,
            p[0]
        );
        assert!(t_fail >= t_meet && t_fail <= t_meet + 2.0 * h / c, "{name}");
        assert_eq!(fa.elements, fb.elements, "{name}: equal halves");
        assert!((fa.mass - fb.mass).abs() < 1e-12 * fa.mass);
        assert!(
            fa.velocity[0] * fb.velocity[0] < 0.0,
            "{name}: moving apart"
        );
        let tol = if name == "tetrahedra" { 1e-10 } else { 1e-6 };
        assert!(p[0].abs() < tol * impulse, "{name}: momentum {p:?}");
    }
}

/// MODEL 3 (linear cohesive law) on the tetrahedral and wedge bars: SIGMAX = 1.5 rho c v,
/// GC = 14.8 kJ/m^2 (delta_c = 50 um). The two middle cells form the group, bonded to the
/// rest (BOND 0), so the crack can only open across the bar's middle plane (2 triangles or
/// one quadrilateral) or inside those two cells. Once fully open, the work the law absorbed
/// equals GC times the crack area within 2% (as on hexahedra: the law is linear between
/// evaluations, the trapezoid work exact but for the steps of the onset and full opening),
/// every failed face lies across the bar, and the crack area is the bar's section.
#[test]
fn cohesive_tetrahedral_and_wedge_bars_dissipate_gc_per_unit_area() {
    let c = (YOUNG / RHO).sqrt();
    let rcv = RHO * c * PULL;
    let sigmax = 1.5 * rcv;
    let gc = sigmax * 50e-6 / 2.0;
    let h = BAR_L / BAR_N as f64;
    let t_end = 1.8 * BAR_L / c;
    let b = BoxMesh::new([BAR_N, 1, 1], [BAR_L, h, h]);
    for (name, mesh) in cuts(&b) {
        let per = mesh.conn.len() / BAR_N;
        let mut bar = pulled_bar(mesh, separation(3, sigmax, gc), t_end);
        bar.materials.push(Material {
            id: 2,
            ..bar.materials[0].clone()
        });
        bar.parts.push(Part {
            id: 2,
            title: "middle".into(),
            section: 0,
            material: 1,
            hourglass: None,
        });
        // the cells' elements are consecutive, `per` to a cell
        for e in (BAR_N / 2 - 1) * per..(BAR_N / 2 + 1) * per {
            bar.elem_part[e] = 1;
        }
        bar.separations[0].material = 1;
        bar.separations[0].bond = 0;
        let split = split_model(&bar);
        let mut s = Solver::new(&split.model).unwrap();
        s.attach_separation(Separation::new(&split).unwrap());
        s.run(&mut Obs(|_: &Solver| {})).unwrap();
        let sep = s.separation().unwrap();
        let en = s.state.energy;
        let all_free = sep
            .failed_interfaces()
            .all(|i| sep.status(i) == Status::Free);
        eprintln!(
            "cohesive {name} bar: {} of {} interfaces failed (all open: {all_free}), crack area {:.4e} m^2 (section {:.4e}); fracture energy {:.6e} J vs GC x area {:.6e} J",
            sep.num_failed(),
            split.interfaces,
            sep.crack_area(),
            h * h,
            en.fracture,
            gc * sep.crack_area()
        );
        assert!(sep.num_failed() >= 1 && all_free, "{name}");
        assert!((sep.crack_area() - h * h).abs() < 1e-9 * h * h, "{name}");
        assert!(
            (en.fracture - gc * sep.crack_area()).abs() < 0.02 * gc * sep.crack_area(),
            "{name}"
        );
    }
}

/// Momentum through fragmentation: a free 6 x 3 x 3-cell block of tetrahedra or wedges,
/// every element in a group of low strength (MODEL 1 and MODEL 3), thrown with a translation,
/// a spin and a stretch so that it breaks up. No external force: the total momentum stays at
/// its first value within 1e-12 of sum m|v| at every step, through every release (a set moves
/// with sum f / sum m; cohesive forces act in equal and opposite pairs), and the energy
/// KE + IE + HG + fracture within 1% of the initial.
#[test]
fn momentum_is_conserved_through_fragmentation_of_tetrahedra_and_wedges() {
    let (lx, ly, lz) = (0.06, 0.03, 0.03);
    let b = BoxMesh::new([6, 3, 3], [lx, ly, lz]);
    for (name, mesh) in cuts(&b) {
        for (model, gc) in [(1, 0.0), (3, 200.0)] {
            let mut m = single_part_model(mesh.clone(), elastic(0.3), 30e-6);
            let centre = [lx / 2.0, ly / 2.0, lz / 2.0];
            for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
                let r = [x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]];
                *v = [
                    3.0 - 2000.0 * r[1] + 300.0 * r[0],
                    -2.0 + 2000.0 * r[0],
                    1.0,
                ];
            }
            m.separations.push(separation(model, 100e6, gc));
            let split = split_model(&m);
            let mut s = Solver::new(&split.model).unwrap();
            s.attach_separation(Separation::new(&split).unwrap());
            let (mut p0, mut dp, mut scale, mut de) = (None, 0.0f64, 0.0, 0.0f64);
            s.run(&mut Obs(|s: &Solver| {
                let p = s.momentum();
                let p0 = *p0.get_or_insert_with(|| {
                    scale = (0..s.setup.mass.len())
                        .map(|i| {
                            let v = s.velocities()[i];
                            s.setup.mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
                        })
                        .sum();
                    p
                });
                dp = dp.max((0..3).map(|k| (p[k] - p0[k]).abs()).fold(0.0, f64::max));
                let en = &s.state.energy;
                de = de.max((en.total() - s.state.initial_energy).abs() / s.state.initial_energy);
            }))
            .unwrap();
            let sep = s.separation().unwrap();
            let frags = sep.fragments(&s.model.conn, s.model.num_nodes());
            let pieces = frags
                .summaries(&s.model.conn, &s.setup.mass, s.positions(), s.velocities())
                .len();
            eprintln!(
                "fragmenting {name} block, MODEL {model}: {} of {} interfaces failed, {pieces} fragments; max |P - P0| {dp:.2e} of {scale:.3e}; energy error {de:.2e}",
                sep.num_failed(),
                sep.num_interfaces(),
            );
            assert!(pieces >= 3, "{name}: the block breaks up");
            assert!(dp < 1e-12 * scale, "{name} MODEL {model}: momentum");
            assert!(de < 0.01, "{name} MODEL {model}: energy");
        }
    }
}
