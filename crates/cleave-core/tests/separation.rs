//! Element separation: the split mesh, its coincident sets moving with their mean acceleration,
//! behaves exactly as the original mesh while no interface has failed (Gerken et al. 2003,
//! section 3).

use cleave_core::curve::Curve;
use cleave_core::mesh::box_model;
use cleave_core::model::{
    Material, MaterialKind, Model, MotionTarget, Part, PrescribedMotion, RigidWall, SeparationDef,
    Spc, StrengthDist, Vad,
};
use cleave_core::separation::fragments::FragmentSummary;
use cleave_core::separation::interfaces::{face_centroid, Separation, Status};
use cleave_core::separation::split::split_model;
mod common;
use cleave_core::solver::{Observer, Solver};
use common::Obs;

/// Each step's positions, and the largest normal force of the first rigid wall.
struct Record<'a>(&'a mut Vec<Vec<[f64; 3]>>, f64);
impl Observer for Record<'_> {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        self.0.push(s.positions().to_vec());
        self.1 = self.1.max(s.wall_forces[0].normal);
        Ok(())
    }
}

/// A 4x3x3 elastic-plastic block, clamped at x = 0, its far face pushed sideways and along x by
/// prescribed velocities, with an initial spin-like velocity field, its top corner driven into
/// a rigid wall with friction: all the step's stages act (stress, hourglass, bulk viscosity,
/// constraints, prescribed motion, a wall).
fn deck() -> Model {
    let mat = Material {
        id: 1,
        density: 7800.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::PlasticKinematic {
            sigy: 300e6,
            etan: 2e9,
            beta: 0.5,
        },
    };
    let mut m = box_model([4, 3, 3], [0.04, 0.03, 0.03], mat, 1e-4);
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        *v = [5.0 * x[1] / 0.03, -3.0 * x[0] / 0.04, 2.0];
    }
    for node in m.nodes_where(0, 0.0, 1e-12) {
        m.spcs.push(Spc {
            node,
            dof: [true, true, true, false, false, false],
        });
    }
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 1e-5, 1.0],
        y: vec![0.0, 20.0, 20.0],
    });
    for node in m.nodes_where(0, 0.04, 1e-12) {
        for axis in [0, 2] {
            m.prescribed.push(PrescribedMotion {
                window: cleave_core::model::Window::ALWAYS,
                target: MotionTarget::Node(node),
                dof: cleave_core::model::MotionDof::Axis(axis),
                vad: Vad::Velocity,
                curve: 0,
                sf: 1.0,
            });
        }
    }
    // above the block (normal -z): the far face, pushed up at 20 m/s, reaches it at about
    // 30 us of the 100
    m.rigid_walls.push(RigidWall {
        shape: cleave_core::model::WallShape::Plane,
        motion: None,
        extent: None,
        id: 1,
        nodes: None,
        tail: [0.0, 0.0, 0.0305],
        head: [0.0, 0.0, 0.0],
        fric: 0.3,
    });
    m
}

/// Continuity: with every element in a separation group but nothing failing, every copy of a
/// deck node follows the original mesh's node: |x_copy - x_orig| below 1e-9 of the largest
/// displacement, at every step. (Only the order of the force sums differs: round-off.)
#[test]
fn split_mesh_moves_as_the_original_until_failure() {
    let original = deck();
    let mut grouped = deck();
    grouped.separations.push(common::unbreakable(0));
    let split = split_model(&grouped);
    assert_eq!(split.model.num_nodes(), 8 * original.num_elements());

    let mut hist_a = Vec::new();
    let mut a = Solver::new(&original).unwrap();
    let mut rec_a = Record(&mut hist_a, 0.0);
    a.run(&mut rec_a).unwrap();
    let wall_a = rec_a.1;

    let mut hist_b = Vec::new();
    let mut b = Solver::new(&split.model).unwrap();
    b.attach_separation(Separation::new(&split).unwrap());
    let mut rec_b = Record(&mut hist_b, 0.0);
    b.run(&mut rec_b).unwrap();
    let wall_b = rec_b.1;
    // the wall stops each set once, with the set's mass (its copies are one entry)
    eprintln!("largest wall force: {wall_a:.6e} N unsplit, {wall_b:.6e} N split");
    assert!(wall_a > 0.0, "the block reaches the wall");
    assert!((wall_a - wall_b).abs() < 1e-9 * wall_a);

    assert_eq!(hist_a.len(), hist_b.len(), "same number of steps");
    let scale = common::motion_scale(hist_a.last().unwrap(), &original.x0.to_vec());
    assert!(scale > 1e-5, "the block moves: {scale}");
    let worst = common::copy_deviation(&hist_a, &hist_b, &split.origin);
    eprintln!(
        "continuity: max |x_copy - x_orig| = {worst:.3e} m, motion scale {scale:.3e} m, {} steps",
        hist_a.len()
    );
    assert!(
        worst < 1e-9 * scale,
        "split mesh departs from the original: {worst} vs scale {scale}"
    );
    // the energies agree too
    let (ea, eb) = (a.state.energy, b.state.energy);
    assert!((ea.total() - eb.total()).abs() < 1e-9 * ea.total());
    assert!((ea.internal - eb.internal).abs() < 1e-9 * ea.internal.abs().max(1e-30));
}

// ---------------------------------------------------------------------------------------------
// Fracture: a bar pulled from both ends, and a free stretching block
// ---------------------------------------------------------------------------------------------

const RHO: f64 = 7800.0;
const YOUNG: f64 = 200e9;
const BAR_L: f64 = 0.1;
const BAR_N: usize = 40;
const PULL: f64 = 10.0;

/// Wave speed of the bar (Poisson 0: uniaxial strain = uniaxial stress, c = sqrt(E/rho)).
fn bar_c() -> f64 {
    (YOUNG / RHO).sqrt()
}

/// A 40 x 1 x 1 elastic bar (Poisson 0) of length 0.1 m, every element in a separation group,
/// both end faces driven outwards at PULL = 10 m/s from t = 0. Each end sends a tensile wave of
/// stress rho c v; they meet at the middle at L/(2c), where the stress doubles.
/// `ramp` > 0 ramps the end velocity up linearly over that time.
fn pulled_bar(sep: SeparationDef, end_time: f64, ramp: f64) -> Model {
    let h = BAR_L / BAR_N as f64;
    let mat = Material {
        id: 1,
        density: RHO,
        young: YOUNG,
        poisson: 0.0,
        kind: MaterialKind::Elastic,
    };
    let mut m = box_model([BAR_N, 1, 1], [BAR_L, h, h], mat, end_time);
    m.curves.push(if ramp > 0.0 {
        Curve {
            id: 1,
            t: vec![0.0, ramp],
            y: vec![0.0, 1.0],
        }
    } else {
        Curve {
            id: 1,
            t: vec![0.0],
            y: vec![1.0],
        }
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

/// A material that both erodes and separates is refused when the separation is attached (the
/// deck reader refuses such a deck with a message): the crack faces of an eroded element would
/// join the contact with their stiffness.
#[test]
#[should_panic(expected = "element erosion in a separation group's material")]
fn erosion_in_a_separating_material_is_refused() {
    let mut m = pulled_bar(separation(1, 1e8, 0.0), 1e-5, 0.0);
    m.erosion.push(cleave_core::erosion::ErosionDef {
        material: 0,
        rule: cleave_core::erosion::ErosionRule {
            max_pressure: Some(1e9),
            ..Default::default()
        },
    });
    let split = split_model(&m);
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(&split).unwrap());
}

/// Mass, centroid and velocity of each fragment at t^n, largest mass first.
fn fragment_table(s: &Solver) -> Vec<FragmentSummary> {
    let sep = s.separation().unwrap();
    sep.fragments(&s.model.conn, s.model.num_nodes()).summaries(
        &s.model.conn,
        &s.setup.mass,
        s.positions(),
        s.velocities(),
    )
}

/// MODEL 1, rho c v < SIGMAX = 1.5 rho c v < 2 rho c v: the bar breaks where the two waves
/// meet, once they have met: the first interface fails no earlier than L/(2c) and no later than
/// L/(2c) + 2h/c (a wave crossing two elements); every failed interface lies within two
/// elements of the middle; the two largest fragments are equal halves moving apart, and after
/// the break each side's momentum changes only by the impulse of its driven end,
/// -/+ rho c v A (t - t_fail) (the end stress stays rho c v until the unloading wave from the
/// crack arrives, after the end of the run); the total momentum stays zero.
#[test]
fn pulled_bar_breaks_in_the_middle_into_equal_halves() {
    let c = bar_c();
    let rcv = RHO * c * PULL;
    let h = BAR_L / BAR_N as f64;
    let t_end = 0.9 * BAR_L / c;
    let split = split_model(&pulled_bar(separation(1, 1.5 * rcv, 0.0), t_end, 0.0));
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(&split).unwrap());
    let mut t_fail = None;
    let mut p_fail = 0.0; // momentum of the left half when the bar breaks
    s.run(&mut Obs(|s: &Solver| {
        if t_fail.is_none() && s.separation().unwrap().num_failed() > 0 {
            t_fail = Some(s.state.t);
            // every node belongs to one element (the whole bar is split)
            p_fail = (0..BAR_N / 2)
                .flat_map(|e| s.model.conn[e])
                .map(|i| s.setup.mass[i as usize] * s.velocities()[i as usize][0])
                .sum();
        }
    }))
    .unwrap();
    let t_fail = t_fail.expect("the bar breaks");
    let t_meet = BAR_L / (2.0 * c);
    eprintln!(
        "pulled bar: first failure at {:.4} us, waves meet at {:.4} us, + 2 crossings {:.4} us",
        t_fail * 1e6,
        t_meet * 1e6,
        (t_meet + 2.0 * h / c) * 1e6
    );
    assert!(t_fail >= t_meet && t_fail <= t_meet + 2.0 * h / c);
    let sep = s.separation().unwrap();
    for i in sep.failed_interfaces() {
        let xc = face_centroid(&sep.faces()[i], &split.model.x0)[0];
        assert!(
            (xc - BAR_L / 2.0).abs() <= 2.0 * h + 1e-12,
            "failed interface at x = {xc}"
        );
    }
    let frags = fragment_table(&s);
    let (a, b) = (frags[0], frags[1]);
    eprintln!(
        "pulled bar: {} failed interfaces, {} fragments; halves: {} and {} elements, momenta {:.6e} {:.6e}",
        sep.num_failed(),
        frags.len(),
        a.elements,
        b.elements,
        a.mass * a.velocity[0],
        b.mass * b.velocity[0],
    );
    assert_eq!(a.elements, b.elements, "equal halves");
    assert!((a.mass - b.mass).abs() < 1e-12 * a.mass);
    assert!(a.velocity[0] * b.velocity[0] < 0.0, "moving apart");
    // momentum of each side (the halves and any small pieces between them) vs the impulse
    let expect = rcv * h * h * (t_end - t_fail);
    let side = |left: bool| -> f64 {
        frags
            .iter()
            .filter(|f| (f.centroid[0] < BAR_L / 2.0) == left)
            .map(|f| f.mass * f.velocity[0])
            .sum()
    };
    let (pl, pr) = (side(true) - p_fail, side(false) + p_fail);
    eprintln!(
        "pulled bar: side momenta gained after the break {pl:.6e} {pr:.6e}, end impulse -/+ {expect:.6e}"
    );
    assert!((pr - expect).abs() < 0.02 * expect && (pl + expect).abs() < 0.02 * expect);
    let total = s.momentum();
    assert!(total[0].abs() < 1e-10 * expect, "total momentum {total:?}");
}

/// MODEL 3 on the same bar (SIGMAX = 1.5 rho c v, GC = 14.8 kJ/m^2, so delta_c = 2 GC / SIGMAX
/// = 50 um, opened over many steps): once the crack is fully open, the work the cohesive law
/// absorbed (`fracture_energy`) equals GC times the crack area within 2% (the law is linear
/// between evaluations, so the trapezoid work is exact except in the steps holding the onset
/// and the full opening), and the energy balance KE + IE + HG + fracture = E0 + W holds: its
/// error (set before the crack by the drive's jump start, ~5e-4 J) changes by less than 1% of
/// E0 + W from the crack's onset to the end (measured: 2.7e-3 J of 0.48 J, 3% of the energy
/// the crack dissipated, while it opens over a few steps). The cohesive plane is at mid-length: the two middle elements form the
/// group, BOND 0 (a cohesive law under a uniform overstress starts cracks at several planes,
/// and without contact (issue 4) the ones that close again interpenetrate).
#[test]
fn cohesive_bar_dissipates_gc_per_unit_area_and_balances_energy() {
    cohesive_bar(3, 0.0);
}

/// The same bar with MODEL 4, the exponential law (delta_c = GC / (2 SIGMAX) = 12.5 um, fully
/// open at 12 delta_c = 150 um): fracture energy = GC x area within 2% (measured 1.3%: the
/// trapezoid of the work over time steps that are coarse against this delta_c, a quarter of
/// the linear law's), the same balance.
#[test]
fn exponential_cohesive_bar_dissipates_gc_per_unit_area() {
    cohesive_bar(4, 0.0);
}

/// Mixed mode: the bar's ends also slide sideways (y), in opposite directions at 0.6 PULL,
/// so the cohesive plane opens and slides at once (BETA 1): the work is still GC per unit area
/// within 2%, under both laws (T . dd = t d delta on any path; unloading is elastic; measured
/// 0.86% and 1.3%).
#[test]
fn cohesive_bar_in_mixed_mode_dissipates_gc_per_unit_area() {
    for model in [3, 4] {
        cohesive_bar(model, 0.6 * PULL);
    }
}

/// The cohesive bar of the tests above under MODEL `model`, the ends sliding sideways at
/// -/+ `slide` (m/s) besides the pull.
fn cohesive_bar(model: i32, slide: f64) {
    let c = bar_c();
    let rcv = RHO * c * PULL;
    let sigmax = 1.5 * rcv;
    let gc = sigmax * 50e-6 / 2.0;
    let t_end = 1.8 * BAR_L / c;
    let mut bar = pulled_bar(separation(model, sigmax, gc), t_end, 0.0);
    if slide != 0.0 {
        for (x, sf) in [(0.0, -slide), (BAR_L, slide)] {
            for node in bar.nodes_where(0, x, 1e-12) {
                bar.prescribed.push(PrescribedMotion {
                    window: cleave_core::model::Window::ALWAYS,
                    target: MotionTarget::Node(node),
                    dof: cleave_core::model::MotionDof::Axis(1),
                    vad: Vad::Velocity,
                    curve: 0,
                    sf,
                });
            }
        }
    }
    // the cohesive plane: the two middle elements form the group, bonded to the rest (BOND 0)
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
    for e in [BAR_N / 2 - 1, BAR_N / 2] {
        bar.elem_part[e] = 1;
    }
    bar.separations[0].material = 1;
    bar.separations[0].bond = 0;
    let split = split_model(&bar);
    assert_eq!(split.interfaces, 1);
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(&split).unwrap());
    // ledger error E - E0 - W just before the crack starts, and its largest change after
    let (mut before, mut worst) = (0.0, 0.0f64);
    s.run(&mut Obs(|s: &Solver| {
        let en = &s.state.energy;
        let err = en.total() - s.state.initial_energy - en.external_work;
        if s.separation().unwrap().num_failed() == 0 {
            before = err;
        } else {
            worst = worst.max((err - before).abs());
        }
    }))
    .unwrap();
    let sep = s.separation().unwrap();
    let en = s.state.energy;
    let all_free = sep
        .failed_interfaces()
        .all(|i| sep.status(i) == Status::Free);
    eprintln!(
        "cohesive bar, MODEL {model}, slide {slide} m/s: {} failed interfaces (all fully open: {all_free}), fracture energy {:.6e} J vs GC x area {:.6e} J; energy: KE {:.4e} IE {:.4e} fracture {:.4e} W {:.4e}; ledger error before the crack {before:.2e} J, largest change after {worst:.2e} J",
        sep.num_failed(),
        en.fracture,
        gc * sep.crack_area(),
        en.kinetic,
        en.internal,
        en.fracture,
        en.external_work
    );
    assert!(sep.num_failed() >= 1 && all_free);
    assert!((en.fracture - gc * sep.crack_area()).abs() < 0.02 * gc * sep.crack_area());
    assert!(worst < 0.01 * (s.state.initial_energy + en.external_work));
}

/// Conservation through separation: a free 6 x 3 x 3 block, every element in a group (low
/// strength), thrown with a translation, a spin and a stretch along x (v = V + w x r +
/// (300/s (x - xc), 0, 0)), so that it breaks into several pieces; once with MODEL 1 and once
/// with MODELs 3 and 4 (GC 200 J/m^2). No external force acts: the total momentum stays at its initial
/// value to round-off (1e-12 of sum m|v|) at every step, through every release (a set moves
/// with sum f / sum m, which keeps the force sum, also in the step it splits; cohesive forces
/// act in equal and opposite pairs); and KE + IE + HG + fracture stays within 1% of E0.
///
/// The solver keeps positions and velocities once per coincident set
/// ([`cleave_core::node_values`]); run again with an entry for every copy
/// ([`Solver::attach_separation_per_node`]), the members of every set keep equal positions and
/// velocities bit for bit, and every copy moves as in the first run, bit for bit (the same
/// arithmetic on each entry), with the same interfaces failing.
///
/// (A far more violent throw, 2000/s, whose stress overshoots the strength six-fold within the
/// first step, breaks the block into 54 pieces with a 9% energy error, all of it in the two
/// steps where the time step drops to the free-element value; the balance then stays flat.)
#[test]
fn momentum_and_energy_are_conserved_through_fragmentation() {
    for (model, gc) in [(1, 0.0), (3, 200.0), (4, 200.0)] {
        let mat = Material {
            id: 1,
            density: RHO,
            young: YOUNG,
            poisson: 0.3,
            kind: MaterialKind::Elastic,
        };
        let (lx, ly, lz) = (0.06, 0.03, 0.03);
        let mut m = box_model([6, 3, 3], [lx, ly, lz], mat, 30e-6);
        let centre = [lx / 2.0, ly / 2.0, lz / 2.0];
        let wz = 2000.0;
        for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
            let r = [x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]];
            *v = [3.0 - wz * r[1] + 300.0 * r[0], -2.0 + wz * r[0], 1.0];
        }
        m.separations.push(separation(model, 100e6, gc));
        let split = split_model(&m);
        let mut s = Solver::new(&split.model).unwrap();
        s.attach_separation(Separation::new(&split).unwrap());
        let mut watch = MomentumWatch::default();
        let mut de = 0.0f64;
        let mut per_set = Vec::new();
        s.run(&mut Obs(|s: &Solver| {
            per_set.push((s.positions().to_vec(), s.velocities().to_vec()));
            watch.observe(s);
            let en = &s.state.energy;
            de = de.max((en.total() - s.state.initial_energy).abs() / s.state.initial_energy);
        }))
        .unwrap();
        let mut q = Solver::new(&split.model).unwrap();
        q.attach_separation_per_node(Separation::new(&split).unwrap());
        let mut tied_checks = 0usize;
        let mut step = 0;
        q.run(&mut Obs(|s: &Solver| {
            let (x, v) = &per_set[step];
            step += 1;
            assert!(s.positions().iter().eq(x.iter()), "step {}", s.state.step);
            assert!(s.velocities().iter().eq(v.iter()), "step {}", s.state.step);
            // a set's members move as one, bit for bit (one acceleration sum f / sum m)
            for set in s.separation().unwrap().sets().sets() {
                let r = set[0] as usize;
                for &n in &set[1..] {
                    let n = n as usize;
                    assert_eq!(s.positions()[n], s.positions()[r], "step {}", s.state.step);
                    assert_eq!(
                        s.velocities()[n],
                        s.velocities()[r],
                        "step {}",
                        s.state.step
                    );
                    tied_checks += 1;
                }
            }
        }))
        .unwrap();
        assert_eq!(step, per_set.len(), "as many steps");
        let sep = s.separation().unwrap();
        let failed = |s: &Solver| {
            s.separation()
                .unwrap()
                .failed_interfaces()
                .collect::<Vec<_>>()
        };
        assert_eq!(failed(&q), failed(&s));
        let frags = fragment_table(&s);
        eprintln!(
            "fragmenting block, MODEL {model}: {} of {} interfaces failed, {} fragments, fracture energy {:.3e} J; max |P - P0| {:.2e} (sum m|v| {:.3e}); max energy error {de:.2e}",
            sep.num_failed(),
            sep.num_interfaces(),
            frags.len(),
            s.state.energy.fracture,
            watch.dp,
            watch.scale
        );
        assert!(frags.len() >= 3, "the block breaks up");
        assert!(tied_checks > 0);
        assert!(watch.dp < 1e-12 * watch.scale);
        assert!(de < 0.01);
        if model >= 3 {
            assert!(s.state.energy.fracture > 0.0);
        }
    }
}

/// A cohesive law must not create energy, also when it slides stiffly: the fragmenting block
/// above in alumina (E 370 GPa), thrown with a spin of 2000/s and a stretch of 300/s, MODEL 3,
/// SIGMAX 100 MPa, GC 40 J/m^2, BETA 8 (shear strength 800 MPa, sliding slope 64 times the
/// normal one), TSSFAC 0.2. Every interface that fails opens fully within a few microseconds,
/// so the fracture energy must come to GC times the failed area (the work to full opening is the
/// envelope's area, whatever the path); and on the way it never falls below minus the elastic
/// stretch the faces held at release, SIGMAX^2 / (2 k_max) per unit area
/// ([`cleave_core::separation::cohesive::CohesiveLaw::traction`]). Before the cohesive time
/// step ([`Separation::cohesive_time_step`]) the sliding springs rang unstably and the block
/// booked -2.7e-3 J against GC x area 0.196 J; measured now 0.1813 J against 0.180 J (45
/// interfaces, all open).
#[test]
fn stiff_sliding_cohesive_law_books_gc_and_creates_no_energy() {
    let mat = Material {
        id: 1,
        density: 3900.0,
        young: 370e9,
        poisson: 0.22,
        kind: MaterialKind::Elastic,
    };
    let (lx, ly, lz) = (0.06, 0.03, 0.03);
    let mut m = box_model([6, 3, 3], [lx, ly, lz], mat, 20e-6);
    m.control.tssfac = 0.2;
    let centre = [lx / 2.0, ly / 2.0, lz / 2.0];
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        let r = [x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]];
        *v = [-2000.0 * r[1] + 300.0 * r[0], 2000.0 * r[0], 0.0];
    }
    let (sigmax, gc) = (100e6, 40.0);
    m.separations.push(SeparationDef {
        beta: 8.0,
        ..separation(3, sigmax, gc)
    });
    // the stretch at release, SIGMAX / k_max, k_max = E / (2 h TSSFAC^2) on cubes of 10 mm
    let k_max = cleave_core::separation::cohesive::stable_slope(370e9, 0.01, 0.2);
    let stretch_energy = sigmax * sigmax / (2.0 * k_max);
    let split = split_model(&m);
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(&split).unwrap());
    let mut lowest = f64::INFINITY;
    s.run(&mut Obs(|s: &Solver| {
        let area = s.separation().unwrap().crack_area();
        lowest = lowest.min(s.state.energy.fracture + stretch_energy * area);
    }))
    .unwrap();
    let sep = s.separation().unwrap();
    let (fracture, expected) = (s.state.energy.fracture, gc * sep.crack_area());
    let all_open = sep
        .failed_interfaces()
        .all(|i| sep.status(i) == Status::Free);
    eprintln!(
        "BETA 8 block: {} interfaces failed (all open: {all_open}), fracture energy {fracture:.4e} J vs GC x area {expected:.4e} J; lowest fracture energy + stretch {lowest:.3e} J",
        sep.num_failed()
    );
    assert!(sep.num_failed() > 10 && all_open);
    assert!(lowest >= 0.0);
    assert!((fracture - expected).abs() < 0.03 * expected);
}

// ---------------------------------------------------------------------------------------------
// A group beside other materials: deck nodes kept outside the group in coincident sets
// ---------------------------------------------------------------------------------------------

/// Largest |P - P0| over a run (P the momentum at each step), against `sum m |v|` at the start,
/// and the number of failed interfaces at the end.
fn momentum_drift(model: &Model) -> (f64, f64, usize) {
    let split = split_model(model);
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(&split).unwrap());
    let mut watch = MomentumWatch::default();
    s.run(&mut Obs(|s: &Solver| watch.observe(s))).unwrap();
    (watch.dp, watch.scale, s.separation().unwrap().num_failed())
}

/// The largest drift of the momentum from its first value, and `sum m |v|` at the first step.
#[derive(Default)]
struct MomentumWatch {
    p0: Option<[f64; 3]>,
    dp: f64,
    scale: f64,
}

impl MomentumWatch {
    fn observe(&mut self, s: &Solver) {
        let p = s.momentum();
        let p0 = *self.p0.get_or_insert(p);
        if self.scale == 0.0 {
            self.scale = (0..s.model.num_nodes())
                .map(|i| s.setup.mass[i] * cleave_core::math::norm(s.velocities()[i]))
                .sum();
        }
        for d in 0..3 {
            self.dp = self.dp.max((p[d] - p0[d]).abs());
        }
    }
}

/// Element `e`'s centroid.
fn centroid(m: &Model, e: usize) -> [f64; 3] {
    m.conn[e].iter().fold([0.0; 3], |c, &n| {
        let x = m.x0[n as usize];
        [c[0] + x[0] / 8.0, c[1] + x[1] / 8.0, c[2] + x[2] / 8.0]
    })
}

/// Part 2, of material 1 (the group's), section 0.
fn group_part() -> Part {
    Part {
        id: 2,
        title: "group".into(),
        section: 0,
        material: 1,
        hourglass: None,
    }
}

fn elastic(id: i64) -> Material {
    Material {
        id,
        density: RHO,
        young: YOUNG,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    }
}

/// An L of three elements, only its upper-left one in a group, pulled apart: the corner node
/// on the re-entrant edge is a deck node of both lower elements, but only the lower-left one
/// has a face on the group. When the interface fails, the node's piece must get the forces of
/// both lower elements (the one without a face on the group too), or momentum drifts (it did,
/// found in review: by 9.5e-3 kg m/s, 0.19 of sum m|v|).
#[test]
fn a_split_at_a_re_entrant_corner_conserves_momentum() {
    let mut m = box_model([2, 1, 2], [0.02, 0.01, 0.02], elastic(1), 20e-6);
    m.materials.push(elastic(2));
    m.parts.push(group_part());
    let upper_right = (0..m.conn.len())
        .find(|&e| centroid(&m, e)[0] > 0.01 && centroid(&m, e)[2] > 0.01)
        .unwrap();
    m.conn.remove(upper_right);
    m.elem_part.remove(upper_right);
    m.elem_ids.remove(upper_right);
    for e in 0..m.conn.len() {
        let c = centroid(&m, e);
        if c[0] < 0.01 && c[2] > 0.01 {
            m.elem_part[e] = 1;
        }
    }
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        *v = [1.0, 0.0, 300.0 * (x[2] - 0.01)];
    }
    m.separations.push(separation(1, 20e6, 0.0));
    m.separations[0].material = 1;
    let (dp, scale_p, failed) = momentum_drift(&m);
    eprintln!("L: {failed} failed, max |P - P0| {dp:.2e} of sum m|v| {scale_p:.2e}");
    assert!(failed > 0, "the group's interface fails");
    assert!(dp < 1e-12 * scale_p, "{dp} against {scale_p}");
}

/// A rigid element bonded (BOND 0) to an elastic group element, the two thrown apart: the rigid
/// body's node in each coincident set gives its body only its share `m_i sum f / sum m` of the
/// set's force (with all of it, momentum drifted by 3x sum m|v|, found in review).
#[test]
fn a_rigid_body_bonded_to_a_group_conserves_momentum() {
    let rigid = Material {
        kind: MaterialKind::Rigid {
            cmo: 0,
            con1: 0,
            con2: 0,
        },
        ..elastic(1)
    };
    let mut m = box_model([2, 1, 1], [0.02, 0.01, 0.01], rigid, 8e-6);
    m.materials.push(elastic(2));
    m.parts.push(group_part());
    for e in 0..m.conn.len() {
        if centroid(&m, e)[0] > 0.01 {
            m.elem_part[e] = 1;
        }
    }
    for (x, v) in m.x0.iter().zip(m.v0.iter_mut()) {
        *v = [100.0 * (x[0] - 0.01), 0.0, 0.0];
    }
    m.separations.push(SeparationDef {
        material: 1,
        bond: 0,
        ..separation(1, 1e30, 0.0)
    });
    let (dp, scale_p, _) = momentum_drift(&m);
    eprintln!("rigid bond: max |P - P0| {dp:.2e} of sum m|v| {scale_p:.2e}");
    assert!(dp < 1e-12 * scale_p, "{dp} against {scale_p}");
}

// ---------------------------------------------------------------------------------------------
// Random strength: the weakest link
// ---------------------------------------------------------------------------------------------

/// Stops a run at the first failure, keeping the stress of the step before and at it.
struct FirstFailure {
    before: f64,
    at: Option<f64>,
}

impl Observer for FirstFailure {
    fn observe(&mut self, s: &Solver) -> std::io::Result<()> {
        let sxx = s.state.stress[0][0];
        if s.separation().unwrap().num_failed() > 0 {
            self.at = Some(sxx);
            return Err(std::io::Error::other("first failure"));
        }
        self.before = sxx;
        Ok(())
    }
}

/// Weibull strengths and the weakest-link size effect, through the solver: bars of N = 10, 40
/// and 160 interfaces (N + 1 elements of 2.5 mm, Poisson 0, MODEL 1, strengths Weibull of scale
/// S = 100 MPa and modulus m = 8, a different seed for each bar) stretched homogeneously at a
/// uniform strain rate (v = eps_dot (x - L/2), the ends driven at the same speed: the exact
/// solution has no waves, every element carries the same stress sigma(t)). Each bar breaks
/// first at its weakest interface (with any other whose strength the same step passed), in the
/// step where sigma(t) passes that interface's strength: the weakest link sets the failure
/// stress to within one step's increment (~0.3%). The
/// mean failure stress of 48 bars of each length is S N^(-1/m) Gamma(1 + 1/m) within 4
/// standard errors (the minimum of N Weibull draws is Weibull of scale S N^(-1/m)), and the
/// slope of ln(mean) against ln N between the shortest and longest bars is -1/m within 4
/// standard errors: the weakest-link size effect (L_ref / L)^(1/m).
#[test]
fn weibull_bars_follow_the_weakest_link_size_effect() {
    let (scale, m, h) = (100e6, 8.0, 2.5e-3);
    // Gamma(1 + 1/8) (Abramowitz and Stegun, table 6.1: Gamma(1.125) = 0.9417426998)
    let gamma = 0.941_742_699_8;
    let rate = 2.0; // 1/s: failure after about 500 steps
    let bars = 48;
    let mut points = Vec::new();
    for n in [10usize, 40, 160] {
        let mat = Material {
            id: 1,
            density: RHO,
            young: YOUNG,
            poisson: 0.0,
            kind: MaterialKind::Elastic,
        };
        let len = (n + 1) as f64 * h;
        let mut failure = Vec::new();
        for k in 0..bars {
            let mut bar = box_model([n + 1, 1, 1], [len, h, h], mat.clone(), 1e-2);
            for (x, v) in bar.x0.iter().zip(bar.v0.iter_mut()) {
                *v = [rate * (x[0] - 0.5 * len), 0.0, 0.0];
            }
            bar.curves.push(Curve {
                id: 1,
                t: vec![0.0],
                y: vec![1.0],
            });
            for (x, sf) in [(0.0, -0.5 * rate * len), (len, 0.5 * rate * len)] {
                for node in bar.nodes_where(0, x, 1e-12) {
                    bar.prescribed.push(PrescribedMotion {
                        window: cleave_core::model::Window::ALWAYS,
                        target: MotionTarget::Node(node),
                        dof: cleave_core::model::MotionDof::Axis(0),
                        vad: Vad::Velocity,
                        curve: 0,
                        sf,
                    });
                }
            }
            let mut sep = separation(1, scale, 0.0);
            sep.strength = StrengthDist::Weibull {
                m,
                aref: 0.0,
                smin: 0.0,
                seed: (1000 * n + k) as u64,
            };
            bar.separations.push(sep);
            let split = split_model(&bar);
            let weakest = split.faces[..split.interfaces]
                .iter()
                .enumerate()
                .min_by(|a, b| a.1.strength.total_cmp(&b.1.strength))
                .map(|(i, f)| (i, f.strength))
                .unwrap();
            let mut s = Solver::new(&split.model).unwrap();
            s.attach_separation(Separation::new(&split).unwrap());
            let mut obs = FirstFailure {
                before: 0.0,
                at: None,
            };
            assert!(s.run(&mut obs).is_err(), "the bar breaks before the end");
            let at = obs.at.unwrap();
            let sep = s.separation().unwrap();
            // the weakest fails, with any other whose strength the same step passed
            assert!(sep.released().contains(&weakest.0), "N {n}, bar {k}");
            for &i in sep.released() {
                assert!(split.faces[i].strength <= at, "N {n}, bar {k}");
            }
            assert!(
                obs.before < weakest.1 && at >= weakest.1 && at < 1.01 * weakest.1,
                "N {n}, bar {k}: stress {} then {at}, weakest strength {}",
                obs.before,
                weakest.1
            );
            failure.push(at);
        }
        let mean = failure.iter().sum::<f64>() / bars as f64;
        let sd =
            (failure.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (bars - 1) as f64).sqrt();
        let se = sd / (bars as f64).sqrt();
        let expect = scale * (n as f64).powf(-1.0 / m) * gamma;
        eprintln!(
            "Weibull bars, N = {n}: mean failure stress {:.2} MPa (se {:.2}), weakest link {:.2} MPa",
            mean / 1e6,
            se / 1e6,
            expect / 1e6
        );
        assert!((mean - expect).abs() < 4.0 * se, "N {n}");
        points.push(((n as f64).ln(), mean.ln(), se / mean));
    }
    let slope = (points[2].1 - points[0].1) / (points[2].0 - points[0].0);
    let err = (points[0].2.powi(2) + points[2].2.powi(2)).sqrt() / (points[2].0 - points[0].0);
    eprintln!(
        "Weibull bars: slope of ln(mean) against ln N {slope:.4} (se {err:.4}), -1/m = {:.4}",
        -1.0 / m
    );
    assert!((slope + 1.0 / m).abs() < 4.0 * err);
}
