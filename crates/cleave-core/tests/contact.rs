//! Contact verification (issue 4): Hertz impact of an elastic sphere on a rigid wall and on a
//! rigid plate through automatic contact, Coulomb friction of a sliding block, a head-on
//! collision of two blocks, and the contact of new crack faces.
//!
//! Every test prints its numbers next to the expected ones
//! (`cargo test --release -p cleave-core --test contact -- --nocapture`).

use cleave_core::contact::ContactSet;
use cleave_core::math::{add, norm, scale};
use cleave_core::mesh::{ogrid_sphere, Assembly, BoxMesh};
use cleave_core::model::{
    ContactDef, ContactSurface, Hourglass, Material, MaterialKind, Model, RigidWall,
};
mod common;
use cleave_core::solver::Solver;
use common::{run, Obs};

fn steel() -> Material {
    Material {
        id: 0,
        density: 7800.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    }
}

fn rigid(young: f64) -> Material {
    Material {
        id: 0,
        density: 7800.0,
        young,
        poisson: 0.3,
        kind: MaterialKind::Rigid {
            cmo: 1,
            con1: 7,
            con2: 7,
        },
    }
}

fn contact(slave: ContactSurface, master: Option<ContactSurface>, fs: f64, fd: f64) -> ContactDef {
    ContactDef {
        id: 1,
        single_surface: master.is_none(),
        one_way: false,
        slave,
        master,
        fs,
        fd,
        dc: 0.0,
    }
}

// ---------------------------------------------------------------------------------------------
// Hertz
// ---------------------------------------------------------------------------------------------

/// Hertz impact of a sphere (mass m, radius r) on a rigid flat at speed v, effective modulus
/// `e_star = E / (1 - nu^2)`: the force-approach law `F = 4/3 E* sqrt(r) d^(3/2)` integrated
/// over the impact (Johnson, Contact Mechanics, section 11.4) gives
/// - the largest approach `d_max = (15 m v^2 / (16 E* sqrt(r)))^(2/5)`,
/// - the peak force `F_max = 4/3 E* sqrt(r) d_max^(3/2)`,
/// - the contact duration `t_c = 2.9432 d_max / v`.
struct HertzTheory {
    f_max: f64,
    t_c: f64,
    a_max: f64,
}

fn hertz(m: f64, r: f64, e_star: f64, v: f64) -> HertzTheory {
    let d = (15.0 * m * v * v / (16.0 * e_star * r.sqrt())).powf(0.4);
    HertzTheory {
        f_max: 4.0 / 3.0 * e_star * r.sqrt() * d.powf(1.5),
        t_c: 2.9432 * d / v,
        a_max: (r * d).sqrt(),
    }
}

/// What a sphere impact measured.
#[derive(Debug)]
struct Impact {
    f_max: f64,
    t_c: f64,
    /// Kinetic energy of the sphere's mean motion after / before.
    rebound: f64,
    /// Largest penetration of a sphere node below the plate's surface.
    penetration: f64,
}

/// Radius, impact speed and O-grid of the Hertz sphere. At 10 m/s the contact radius is
/// a = 1.07 mm = 0.11 R, about one surface element (tangential size pi R / (2 n) = 0.98 mm)
/// and 1.3 radial layers (2 R / (n + 2 m) = 0.83 mm).
///
/// Measured (this mesh, wall / plate): peak force +3.3% / +1.9%, duration +2.0% / +6.3%.
/// Meshes with 16..32 core elements at 10..80 m/s gave peak forces 2-9% above Hertz and
/// durations 1-6% below (at 40 m/s: +7.4% and -4.7% on both 24 and 32 core elements, so the
/// difference there is no mesh error: a/R = 0.19 strains Hertz's small-contact assumption);
/// hence the 10% tolerance and the low speed.
const R: f64 = 0.01;
const V: f64 = 10.0;
const GRID: (usize, usize) = (16, 4);

/// The sphere of steel at speed V towards -y, its lowest point at y = 0.2 mm; returns the
/// assembly, the sphere's nodes and part.
fn sphere() -> (Assembly, std::ops::Range<u32>) {
    let mut a = Assembly::new("Hertz sphere", 1.0);
    let mat = a.material(steel());
    let part = a.part("sphere", mat);
    let mut ball = ogrid_sphere(R, GRID.0, GRID.1);
    ball.translate([0.0, R + 2e-4, 0.0]);
    let (nodes, _) = a.mesh(ball, |_| part);
    (a, nodes)
}

/// Run a sphere model through the impact; `force(s)` is the contact force on the sphere
/// along +y.
fn impact(mut m: Model, nodes: std::ops::Range<u32>, force: impl Fn(&Solver) -> f64) -> Impact {
    for i in nodes.clone() {
        m.v0[i as usize] = [0.0, -V, 0.0];
    }
    let mass: f64 = 7800.0 * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3);
    let th = hertz(mass, R, 200e9 / (1.0 - 0.09), V);
    m.control.end_time = 1.4 * th.t_c + 2e-4 / V;
    m.control.hourglass = Hourglass::Stiffness;
    let (mut f_max, mut t_on, mut t_off, mut pen) = (0.0f64, f64::NAN, 0.0, 0.0f64);
    let mut sm = 0.0;
    let s = run(&m, |s| {
        if sm == 0.0 {
            sm = nodes.clone().map(|i| s.setup.mass[i as usize]).sum();
        }
        let f = force(s);
        if f > 1e-3 * f_max.max(1.0) {
            if t_on.is_nan() {
                t_on = s.state.t;
            }
            t_off = s.state.t;
        }
        f_max = f_max.max(f);
        for i in nodes.clone() {
            pen = pen.max(-s.positions()[i as usize][1]);
        }
    });
    let p = nodes.clone().fold([0.0; 3], |p, i| {
        add(
            p,
            scale(s.velocities()[i as usize], s.setup.mass[i as usize]),
        )
    });
    let v_out = scale(p, 1.0 / sm);
    println!(
        "{} steps, element dt {:.3e} s, contact dt {:.3e} s",
        s.state.step,
        s.state.dt,
        s.contact_time_step()
    );
    let got = Impact {
        f_max,
        t_c: t_off - t_on,
        rebound: (norm(v_out) / V).powi(2),
        penetration: pen,
    };
    println!(
        "Hertz: F_max {:.4e} N (theory {:.4e}), t_c {:.4e} s (theory {:.4e}), a_max {:.2} mm, rebound energy {:.4}, penetration {:.3e} m",
        got.f_max,
        th.f_max,
        got.t_c,
        th.t_c,
        th.a_max * 1e3,
        got.rebound,
        got.penetration
    );
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    assert!(rel(got.f_max, th.f_max) < 0.10, "peak force {got:?}");
    assert!(rel(got.t_c, th.t_c) < 0.10, "duration {got:?}");
    assert!(
        got.rebound > 0.95 && got.rebound < 1.0 + 1e-3,
        "rebound {got:?}"
    );
    got
}

/// Hertz against a stonewall at y = 0 (a kinematic constraint: no penalty compliance).
///
/// Tolerances: 10% on peak force and duration (the issue's), for a mesh whose contact patch
/// is a few elements wide; rebound energy above 95%.
#[test]
fn hertz_sphere_on_rigid_wall() {
    let (a, nodes) = sphere();
    let mut m = a.finish();
    m.rigid_walls.push(RigidWall {
        shape: cleave_core::model::WallShape::Plane,
        motion: None,
        extent: None,
        id: 1,
        nodes: None,
        tail: [0.0; 3],
        head: [0.0, 1.0, 0.0],
        fric: 0.0,
    });
    let got = impact(m, nodes, |s| s.wall_forces[0].normal);
    assert!(got.penetration < 1e-9);
}

/// Hertz against a rigid plate through surface-to-surface contact (slave: the sphere).
///
/// A pair's spring is the smaller of the face's stiffness `SLSFAC K A^2 / V` and the node's
/// (PENOPT 1, the default): here the sphere's nodes, the rigid plate (10 E) being stiffer.
/// SLSFAC = 2 keeps the penalty's penetration at an eighth of the Hertz approach (measured
/// 14 um of 115 um). Measured: peak force +1.9%, duration +6.3%, rebound energy 99.6%; the
/// springs' stable step, 4.2e-8 s, sets the time step (the elements': 6.5e-8 s). Before PENOPT
/// was read (the plate's faces' stiffness, as PENOPT 2) SLSFAC 1 gave +2.9% and +5.7% with a
/// contact step of 1.5e-8 s: the light nodes of the sphere against the plate's stiff faces.
#[test]
fn hertz_sphere_on_rigid_plate_through_contact() {
    let (mut a, nodes) = sphere();
    let mat = a.material(rigid(2000e9));
    let part = a.part("plate", mat);
    let mut plate = BoxMesh::new([16, 1, 16], [0.016, 0.002, 0.016]);
    plate.translate([-0.008, -0.002, -0.008]);
    a.mesh(plate, |_| part);
    let mut m = a.finish();
    m.control.slsfac = 2.0;
    m.contacts.push(contact(
        ContactSurface::Part(0),
        Some(ContactSurface::Part(1)),
        0.0,
        0.0,
    ));
    let got = impact(m, nodes, |s| {
        s.contact().map_or(0.0, |c| c.forces()[0].force[1])
    });
    let h = 2.0 * R / (GRID.0 + 2 * GRID.1) as f64;
    println!("penetration / element size {:.4}", got.penetration / h);
    assert!(got.penetration < 0.05 * h);
}

// ---------------------------------------------------------------------------------------------
// Friction
// ---------------------------------------------------------------------------------------------

/// Gravity of the friction tests: large, so the block slides and stops within a millisecond
/// (the stresses it causes, rho g h = 0.4 MPa, stay tiny).
const G: f64 = 1e4;

/// A 10 x 5 x 10 mm steel block (4 x 2 x 4 elements) resting on a fixed rigid plate (y < 0)
/// through surface-to-surface contact (slave: the block), under gravity G along -y plus a
/// sideways acceleration `gx` G along +x (both ramped up, see below), sliding at `v0` along
/// +x at t = 0. Returns the
/// block's mean x velocity over time, (t, v).
fn sliding_block(gx: f64, v0: f64, fs: f64, fd: f64, dc: f64, end_time: f64) -> Vec<(f64, f64)> {
    sliding_block_of(|b| b, gx, v0, fs, fd, dc, end_time)
}

/// [`sliding_block`] with the block's mesh cut by `cut` (into tetrahedra, wedges).
fn sliding_block_of(
    cut: fn(BoxMesh) -> BoxMesh,
    gx: f64,
    v0: f64,
    fs: f64,
    fd: f64,
    dc: f64,
    end_time: f64,
) -> Vec<(f64, f64)> {
    use cleave_core::curve::Curve;
    use cleave_core::model::BodyLoad;
    let mut a = Assembly::new("block on plate", end_time);
    let block_mat = a.material(steel());
    let plate_mat = a.material(rigid(200e9));
    let block_part = a.part("block", block_mat);
    let plate_part = a.part("plate", plate_mat);
    let mut block = BoxMesh::new([4, 2, 4], [0.01, 0.005, 0.01]);
    block.translate([-0.005, 0.0, -0.005]);
    let (nodes, _) = a.mesh(cut(block), |_| block_part);
    let mut plate = BoxMesh::new([10, 1, 4], [0.05, 0.004, 0.02]);
    plate.translate([-0.01, -0.004, -0.01]);
    a.mesh(plate, |_| plate_part);
    let mut m = a.finish();
    for i in nodes.clone() {
        m.v0[i as usize] = [v0, 0.0, 0.0];
    }
    // gravity ramped up over 50 us (6 periods of the block on its penalty springs, so it
    // settles with the normal force within a few % of m g), the pull over 60-110 us
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 5e-5, 1.0],
        y: vec![0.0, 1.0, 1.0],
    });
    m.curves.push(Curve {
        id: 2,
        t: vec![0.0, 6e-5, 1.1e-4, 1.0],
        y: vec![0.0, 0.0, 1.0, 1.0],
    });
    m.body_loads.push(BodyLoad {
        axis: 1,
        curve: Some(0),
        sf: G,
    });
    if gx != 0.0 {
        m.body_loads.push(BodyLoad {
            axis: 0,
            curve: Some(1),
            sf: -gx * G,
        });
    }
    m.contacts.push(ContactDef {
        dc,
        ..contact(
            ContactSurface::Part(block_part),
            Some(ContactSurface::Part(plate_part)),
            fs,
            fd,
        )
    });
    let mut out = Vec::new();
    let mut mass = 0.0;
    run(&m, |s| {
        if mass == 0.0 {
            mass = nodes.clone().map(|i| s.setup.mass[i as usize]).sum();
        }
        let p: f64 = nodes
            .clone()
            .map(|i| s.setup.mass[i as usize] * s.velocities()[i as usize][0])
            .sum();
        out.push((s.state.t, p / mass));
        if std::env::var("FDBG").is_ok() {
            let f = s.contact().unwrap().forces()[0];
            eprintln!(
                "FD {} {} {} {} {}",
                s.state.t,
                f.force[0],
                f.force[1],
                f.pairs,
                mass * G
            );
        }
    });
    out
}

/// Least-squares slope of v(t) over `t0 <= t <= t1`.
fn slope(h: &[(f64, f64)], t0: f64, t1: f64) -> f64 {
    let pts: Vec<_> = h.iter().filter(|p| p.0 >= t0 && p.0 <= t1).collect();
    let n = pts.len() as f64;
    let (mt, mv) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mt) * (p.1 - mv)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mt) * (p.0 - mt)).sum();
    sxy / sxx
}

/// A block sliding at 1 m/s on the plate (FS 0.5, FD 0.3, DC 20 s/m: mu = FD within 1% above
/// 0.25 m/s) decelerates at FD g and then stays at rest. The deceleration is
/// fitted over 0.1-0.25 ms, after the block has settled on the penalty springs (their normal
/// force oscillates about m g; the fit averages it): within 3%.
#[test]
fn sliding_block_decelerates_at_dynamic_mu_g() {
    let fd = 0.3;
    let h = sliding_block(0.0, 1.0, 0.5, fd, 20.0, 0.5e-3);
    let a = slope(&h, 0.1e-3, 0.25e-3);
    let t_stop = 1.0 / (fd * G);
    let v_end = h.last().unwrap().1;
    println!(
        "sliding block: deceleration {:.4e} m/s^2 (mu_d g = {:.4e}), stops at {:.3e} s, v at {:.1e} s: {:.3e} m/s",
        -a,
        fd * G,
        t_stop,
        h.last().unwrap().0,
        v_end
    );
    assert!((-a / (fd * G) - 1.0).abs() < 0.03);
    assert!(
        v_end.abs() < 0.01,
        "at rest after {t_stop:.2e} s: v = {v_end}"
    );
}

/// The sliding block of tetrahedra: its contact faces are triangles (friction acts on each
/// node against the triangle it slides on); the same deceleration within 3%.
#[test]
fn sliding_tetrahedral_block_decelerates_at_dynamic_mu_g() {
    let fd = 0.3;
    let h = sliding_block_of(|b| b.split_tets(), 0.0, 1.0, 0.5, fd, 20.0, 0.3e-3);
    let a = slope(&h, 0.1e-3, 0.25e-3);
    println!(
        "sliding tetrahedral block: deceleration {:.4e} m/s^2 (mu_d g = {:.4e})",
        -a,
        fd * G
    );
    assert!((-a / (fd * G) - 1.0).abs() < 0.03);
}

/// Static against dynamic friction under a sideways pull of 0.4 g and 0.6 g (FS 0.5, FD 0.3,
/// DC 20 s/m, so mu = FS at rest and FD once sliding faster than ~0.2 m/s), from rest: at
/// 0.4 g < FS g the block sticks (its mean speed once pulled stays below 1% of what sliding
/// with FD would give, (0.4 - 0.3) g t / 2; with mu = FD it would slide); at 0.6 g > FS g it
/// slides and, once sliding, accelerates at (0.6 - FD) g within 3%.
#[test]
fn static_friction_holds_below_fs_and_dynamic_friction_acts_above() {
    let (fs, fd) = (0.5, 0.3);
    let end = 0.3e-3;
    let stuck = sliding_block(0.4, 0.0, fs, fd, 20.0, end);
    // the block's mean speed (its displacement over the time): it rings on the sticking
    // friction springs (+-0.01 m/s) but does not creep
    let after: Vec<f64> = stuck.iter().filter(|p| p.0 > 1.1e-4).map(|p| p.1).collect();
    let v_stuck = after.iter().sum::<f64>() / after.len() as f64;
    let v_if_sliding = 0.5 * (0.4 - fd) * G * (end - 1.1e-4);
    let slides = sliding_block(0.6, 0.0, fs, fd, 20.0, end);
    let a = slope(&slides, 0.15e-3, end);
    println!(
        "pull 0.4 g: mean speed {v_stuck:.3e} m/s (sliding with FD: {v_if_sliding:.3e}); pull 0.6 g: acceleration {a:.4e} m/s^2 (expected {:.4e})",
        (0.6 - fd) * G
    );
    assert!(v_stuck.abs() < 0.01 * v_if_sliding);
    assert!((a / ((0.6 - fd) * G) - 1.0).abs() < 0.03);
}

// ---------------------------------------------------------------------------------------------
// Head-on collision
// ---------------------------------------------------------------------------------------------

/// Two equal steel blocks (20 x 10 x 10 mm, 8 x 4 x 4 elements, Poisson 0.3) meet head on
/// through single-surface contact at 10 m/s, the right one at rest.
/// - The total momentum is the initial one to round-off (the contact forces on a node and on
///   the face it touches are equal and opposite): 1e-9 relative.
/// - The blocks exchange their momentum: afterwards the left moves at under 10% and the right
///   at over 90% of the impact speed (1D bars would exchange it exactly; lateral inertia of
///   the short blocks keeps some vibration), and no kinetic energy is created.
/// - The largest penetration of the facing surfaces stays below 5% of the element size (the
///   penalty's estimate: contact stress rho c v / 2 over SLSFAC K / h, 1.7%).
#[test]
fn head_on_blocks_exchange_momentum_without_penetrating() {
    head_on("hexahedra", |b| b, false);
}

/// The same collision through `*CONTACT_AUTOMATIC_NODES_TO_SURFACE`, the left block's nodes
/// (slave) against the right block's faces (master) only: the same pins, and at most the 25
/// nodes of the left block's front face are ever in contact (a surface-to-surface or single
/// surface contact also checks the right block's nodes, up to 50 pairs).
#[test]
fn head_on_blocks_through_nodes_to_surface() {
    let pairs = head_on("hexahedra, nodes to surface", |b| b, true);
    assert!(pairs > 0 && pairs <= 25, "{pairs} pairs");
    let both = head_on("hexahedra", |b| b, false);
    assert!(both > 25, "{both} pairs both ways");
}

/// The head-on collision of blocks of tetrahedra and of wedges: the contact surfaces are
/// triangles (every face of the tetrahedra; the wedges' faces on y = const), with the same
/// pins as for hexahedra.
#[test]
fn head_on_blocks_of_tetrahedra_and_wedges() {
    head_on("tetrahedra", |b| b.split_tets(), false);
    head_on("wedges", |b| b.split_wedges(), false);
}

/// Returns the most node-face pairs in contact at a step.
fn head_on(name: &str, cut: fn(BoxMesh) -> BoxMesh, one_way: bool) -> usize {
    let v0 = 10.0;
    let (l, n) = (0.02, 8);
    let h = l / n as f64;
    let c = (200e9 / 7800.0f64).sqrt();
    let mut a = Assembly::new("head on", 6.0 * l / c);
    let mat = a.material(steel());
    let left = a.part("left", mat);
    let right = a.part("right", mat);
    let mut bl = BoxMesh::new([n, 4, 4], [l, 0.01, 0.01]);
    bl.translate([-l - 1e-5, 0.0, 0.0]);
    let (ln, _) = a.mesh(cut(bl), |_| left);
    let (rn, _) = a.mesh(cut(BoxMesh::new([n, 4, 4], [l, 0.01, 0.01])), |_| right);
    let mut m = a.finish();
    for i in ln.clone() {
        m.v0[i as usize] = [v0, 0.0, 0.0];
    }
    m.contacts.push(if one_way {
        ContactDef {
            one_way: true,
            ..contact(
                ContactSurface::Part(left),
                Some(ContactSurface::Part(right)),
                0.0,
                0.0,
            )
        }
    } else {
        contact(ContactSurface::All, None, 0.0, 0.0)
    });
    let mut pairs = 0;
    let face_l: Vec<u32> = ln
        .clone()
        .filter(|&i| m.x0[i as usize][0] > -2e-5)
        .collect();
    let face_r: Vec<u32> = rn.clone().filter(|&i| m.x0[i as usize][0] < 1e-9).collect();
    let mut pen = 0.0f64;
    let mut e0 = 0.0;
    let s = run(&m, |s| {
        let xl = face_l
            .iter()
            .map(|&i| s.positions()[i as usize][0])
            .fold(f64::MIN, f64::max);
        let xr = face_r
            .iter()
            .map(|&i| s.positions()[i as usize][0])
            .fold(f64::MAX, f64::min);
        pen = pen.max(xl - xr);
        if s.state.step == 0 {
            e0 = s.state.energy.kinetic;
        }
        pairs = pairs.max(s.contact().map_or(0, |c| c.forces()[0].pairs));
    });
    let momentum = |r: &std::ops::Range<u32>| -> f64 {
        r.clone()
            .map(|i| s.setup.mass[i as usize] * s.velocities()[i as usize][0])
            .sum()
    };
    let mass: f64 = ln.clone().map(|i| s.setup.mass[i as usize]).sum();
    let (vl, vr) = (momentum(&ln) / mass, momentum(&rn) / mass);
    let p0 = mass * v0;
    let p = s.momentum()[0];
    let e = &s.state.energy;
    println!(
        "head on, {name}: after, left {vl:.4} m/s, right {vr:.4} m/s; momentum error {:.2e}; kinetic {:.4e} J of {e0:.4e} J, contact {:.3e} J; largest penetration {:.3e} m = {:.4} h",
        (p - p0).abs() / p0,
        e.kinetic,
        e.contact,
        pen,
        pen / h
    );
    assert!((p - p0).abs() < 1e-9 * p0);
    assert!(vl.abs() < 0.1 * v0 && vr > 0.9 * v0);
    assert!(e.kinetic <= e0 * (1.0 + 1e-6));
    assert!(pen < 0.05 * h);
    pairs
}

// ---------------------------------------------------------------------------------------------
// New surfaces
// ---------------------------------------------------------------------------------------------

/// A 40-element bar (Poisson 0, 100 mm) whose elements are all in a separation group (MODEL 1,
/// SIGMAX 1.5 rho c v) is pulled at both ends at 10 m/s until 15 us: the tensile waves meet
/// at the middle at 9.9 us and break it there. Then both ends are pushed back at 10 m/s: the
/// compression waves reach the crack at about 25 us and close it within a few us. Returns the largest interpenetration of
/// the two faces of any failed interface after they first touch, over the element size, and
/// the number of failed interfaces.
fn bar_pushed_back(with_contact: bool) -> (f64, usize) {
    use cleave_core::curve::Curve;
    use cleave_core::mesh::box_model;
    use cleave_core::model::{MotionTarget, PrescribedMotion, SeparationDef, Vad};
    use cleave_core::separation::interfaces::Separation;
    use cleave_core::separation::split::split_model;
    let (l, n, v) = (0.1, 40, 10.0);
    let h = l / n as f64;
    let mat = Material {
        poisson: 0.0,
        ..steel()
    };
    let c = (200e9 / 7800.0f64).sqrt();
    let mut m = box_model([n, 1, 1], [l, h, h], mat, 70e-6);
    m.curves.push(Curve {
        id: 1,
        t: vec![0.0, 15e-6, 16e-6, 1.0],
        y: vec![1.0, 1.0, -1.0, -1.0],
    });
    for (x, sf) in [(0.0, -v), (l, v)] {
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
    m.separations.push(SeparationDef {
        material: 0,
        model: 1,
        sigmax: 1.5 * 7800.0 * c * v,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    });
    if with_contact {
        m.contacts
            .push(contact(ContactSurface::All, None, 0.0, 0.0));
    }
    let split = split_model(&m);
    let mut s = Solver::new(&split.model).unwrap();
    s.attach_separation(Separation::new(&split).unwrap());
    if with_contact {
        s.attach_contact(ContactSet::new(&split.model, Some(&split.origin)).unwrap());
    }
    let mut worst = 0.0f64;
    s.run(&mut Obs(|s: &Solver| {
        let sep = s.separation().unwrap();
        for i in sep.failed_interfaces() {
            let f = &sep.faces()[i];
            // nodes 0..4 are on elems[0]'s face, 4..8 on elems[1]'s: which is on the left is
            // read from the reference positions (the current ones flip when they pass)
            let cx = |e: u32| {
                s.model.conn[e as usize]
                    .iter()
                    .map(|&a| s.model.x0[a as usize][0])
                    .sum::<f64>()
            };
            let (left, right) = if cx(f.elems[0]) < cx(f.elems[1]) {
                (0, 4)
            } else {
                (4, 0)
            };
            for k in 0..4 {
                let gap = s.positions()[f.nodes[right + k] as usize][0]
                    - s.positions()[f.nodes[left + k] as usize][0];
                worst = worst.max(-gap);
            }
        }
    }))
    .unwrap();
    (worst / h, s.separation().unwrap().num_failed())
}

/// The faces of the crack joined the contact surface when it broke, so when the bar is pushed
/// back together the crack closes without interpenetration: below 5% of the element size.
/// The penalty's own estimate: the faces close at 60 m/s (each free face doubles the 20 m/s
/// jump of the compression wave, against -10 m/s), so the contact stress is rho c 30 m/s =
/// 1.2 GPa, held by the corner springs SLSFAC K h per h^2 / 4: g = sigma h / (4 SLSFAC K) =
/// 4.4% of h. Without contact the same run lets the pieces pass through each other (over 10%
/// of h: measured a whole element), so the test can tell.
#[test]
fn crack_faces_contact_when_a_broken_bar_is_pushed_back() {
    let (with, failed) = bar_pushed_back(true);
    let (without, failed_without) = bar_pushed_back(false);
    println!(
        "broken bar pushed back: largest interpenetration of the crack faces / h: {with:.4} with contact ({failed} failed interfaces), {without:.4} without ({failed_without})"
    );
    assert!(failed > 0 && failed_without > 0);
    assert!(with < 0.05, "crack faces interpenetrate by {with} h");
    assert!(
        without > 0.1,
        "the test must see interpenetration without contact: {without}"
    );
}

// ---------------------------------------------------------------------------------------------
// Split meshes
// ---------------------------------------------------------------------------------------------

/// A split model in contact behaves as the same mesh unsplit until an interface fails: a
/// 648-element steel sphere (every element in a separation group of infinite strength, so
/// 8 copies of each interior node, 4 of a node on a face of the surface) hits a rigid plate
/// at 10 m/s through single-surface contact with friction. Every copy follows its deck node
/// and the contact force on the plate is the unsplit one, within round-off (1e-9 of the
/// motion and of the peak force), at every step. Only one copy per coincident set is checked
/// (the contact module's docs): a spring per copy would make the split sphere's contact up to
/// four times as stiff.
#[test]
fn split_sphere_hits_the_plate_as_the_unsplit_one() {
    use cleave_core::separation::interfaces::Separation;
    use cleave_core::separation::split::split_model;
    let mut a = Assembly::new("split sphere", 1.0);
    let mat = a.material(steel());
    let part = a.part("sphere", mat);
    let mut ball = ogrid_sphere(R, 6, 2);
    ball.translate([0.0, R + 2e-4, 0.0]);
    let (nodes, _) = a.mesh(ball, |_| part);
    let pmat = a.material(rigid(200e9));
    let ppart = a.part("plate", pmat);
    let mut plate = BoxMesh::new([4, 1, 4], [0.016, 0.002, 0.016]);
    plate.translate([-0.008, -0.002, -0.008]);
    a.mesh(plate, |_| ppart);
    let mut deck = a.finish();
    for i in nodes.clone() {
        deck.v0[i as usize] = [0.0, -V, 0.0];
    }
    deck.control.end_time = 1e-4;
    deck.contacts
        .push(contact(ContactSurface::All, None, 0.5, 0.3));
    let mut grouped = deck.clone();
    grouped.separations.push(common::unbreakable(0));
    let split = split_model(&grouped);
    assert!(split.model.num_nodes() > 4 * deck.num_nodes());

    // positions and the plate's contact force (the force on the sphere's nodes, along y)
    type History = Vec<(Vec<[f64; 3]>, f64)>;
    let record = |s: &Solver, sphere: &dyn Fn(u32) -> bool| {
        let f = s.contact().map_or(0.0, |c| {
            c.nodal_forces()
                .filter(|&(i, _)| sphere(i))
                .map(|(_, f)| f[1])
                .sum::<f64>()
        });
        (s.positions().to_vec(), f)
    };
    let mut hist_a: History = Vec::new();
    run(&deck, |s| hist_a.push(record(s, &|i| nodes.contains(&i))));

    let origin = &split.origin;
    let mut hist_b: History = Vec::new();
    let mut b = Solver::new(&split.model).unwrap();
    b.attach_separation(Separation::new(&split).unwrap());
    b.attach_contact(ContactSet::new(&split.model, Some(origin)).unwrap());
    b.run(&mut Obs(|s: &Solver| {
        hist_b.push(record(s, &|i| nodes.contains(&origin[i as usize])))
    }))
    .unwrap();

    assert_eq!(hist_a.len(), hist_b.len(), "same number of steps");
    let f_peak = hist_a.iter().map(|h| h.1).fold(0.0, f64::max);
    let scale = common::motion_scale(&hist_a.last().unwrap().0, &deck.x0.to_vec());
    let dx = common::copy_deviation(
        hist_a.iter().map(|h| &h.0),
        hist_b.iter().map(|h| &h.0),
        origin,
    );
    let df = hist_a
        .iter()
        .zip(&hist_b)
        .map(|(a, b)| (b.1 - a.1).abs())
        .fold(0.0, f64::max);
    println!(
        "split sphere: {} steps, peak contact force {f_peak:.4e} N, max |f_split - f| {df:.3e} N, max |x_copy - x| {dx:.3e} m of motion {scale:.3e} m",
        hist_a.len()
    );
    assert!(f_peak > 1e3, "the sphere hits the plate: {f_peak}");
    assert!(df < 1e-9 * f_peak, "{df} vs {f_peak}");
    assert!(dx < 1e-9 * scale, "{dx} vs {scale}");
}
