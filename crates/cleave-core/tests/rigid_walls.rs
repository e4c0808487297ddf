//! `*RIGIDWALL_PLANAR_FINITE`: a stonewall that covers a rectangle of its plane, against where
//! each node lands worked out by hand.

use cleave_core::math::cross;
use cleave_core::mesh::box_model;
use cleave_core::model::{Material, RigidWall, WallExtent, WallMotion, WallShape};
mod common;
use common::run;

fn soft() -> Material {
    common::soft_elastic()
}

/// `covers` against the rectangle drawn by hand: a wall in the plane z = 0 (normal +z) from
/// the tail (1, 2, 0), l along (1, 1, 0)/sqrt(2) for 2, m = n x l = (-1, 1, 0)/sqrt(2) for 1.
#[test]
fn a_finite_wall_covers_its_rectangle() {
    let s = 0.5f64.sqrt();
    let w = RigidWall {
        shape: cleave_core::model::WallShape::Plane,
        motion: None,
        id: 1,
        nodes: None,
        tail: [1.0, 2.0, 0.0],
        head: [1.0, 2.0, 5.0],
        fric: 0.0,
        extent: Some(WallExtent {
            l: [s, s, 0.0],
            len_l: 2.0,
            len_m: 1.0,
        }),
    };
    let n = w.normal();
    assert_eq!(n, [0.0, 0.0, 1.0]);
    assert_eq!(cross(n, [s, s, 0.0]), [-s, s, 0.0]);
    let at = |a: f64, b: f64, z: f64| [1.0 + s * (a - b), 2.0 + s * (a + b), z];
    for (a, b, inside) in [
        (0.1, 0.1, true),
        (1.9, 0.9, true),
        (1.0, 0.5, true),
        (2.1, 0.5, false),
        (-0.1, 0.5, false),
        (1.0, 1.1, false),
        (1.0, -0.1, false),
    ] {
        // the height above or below the plane does not matter
        for z in [-0.3, 0.0, 0.7] {
            assert_eq!(w.covers(at(a, b, z), w.tail, n), inside, "({a}, {b}, {z})");
        }
    }
    let mut unbounded = w.clone();
    unbounded.extent = None;
    assert!(unbounded.covers(at(5.0, -3.0, 1.0), w.tail, n));
}

/// Two separate soft cubes (10 mm) thrown down at 2 m/s from 0.5 mm above the plane z = 0,
/// one over a finite wall's rectangle (x in [0, 30] mm, y in [0, 20] mm; the cube 5 mm inside
/// its edges), one beside it (x from 40 mm): the first's nodes reach the plane and never cross it (the stonewall puts a
/// node that would cross exactly on the plane: z >= -1e-15 m; the cube may bounce off), the
/// second falls through to z = 0.5 mm - 2 m/s t at the end (no force acts on it: to
/// round-off).
#[test]
fn nodes_beside_a_finite_wall_pass_it() {
    let mut m = box_model([1, 1, 1], [0.01; 3], soft(), 2e-3);
    let (_, other) = common::append_box(&mut m, [1, 1, 1], [0.01; 3], [0.04, 0.0, 0.0005], soft());
    // the first cube well inside the rectangle (its nodes spread sideways as it lands)
    for x in m.x0.as_mut_slice()[..8].iter_mut() {
        *x = [x[0] + 0.005, x[1] + 0.005, x[2] + 0.0005];
    }
    for v in m.v0.as_mut_slice() {
        *v = [0.0, 0.0, -2.0];
    }
    m.rigid_walls.push(RigidWall {
        shape: cleave_core::model::WallShape::Plane,
        motion: None,
        id: 1,
        nodes: None,
        tail: [0.0; 3],
        head: [0.0, 0.0, 1.0],
        fric: 0.0,
        extent: Some(WallExtent {
            l: [1.0, 0.0, 0.0],
            len_l: 0.03,
            len_m: 0.02,
        }),
    });
    let x0 = m.x0.to_vec();
    let mut lowest = f64::INFINITY;
    let s = run(&m, |s| {
        let x = s.positions();
        for n in 0..8 {
            lowest = lowest.min(x[n][2]);
        }
    });
    let t = s.state.t;
    let x = s.positions();
    let mut fall_err = 0.0f64;
    for n in other {
        let want = x0[n][2] - 2.0 * t;
        fall_err = fall_err.max((x[n][2] - want).abs());
    }
    eprintln!(
        "finite wall: {} steps to {t:.2e} s; covered cube's lowest z {lowest:.1e} m; the other off free fall by {fall_err:.1e} m",
        s.state.step
    );
    assert!(2.0 * t > 0.002, "the free cube passes the plane");
    assert!((-1e-15..1e-9).contains(&lowest), "{lowest}");
    assert!(fall_err < 1e-15, "{fall_err}");
}

/// A wall of `shape` at `tail` with its axis along +z (the normal of a plane).
fn wall(tail: [f64; 3], shape: WallShape, motion: Option<WallMotion>) -> RigidWall {
    RigidWall {
        id: 1,
        nodes: None,
        tail,
        head: [tail[0], tail[1], tail[2] + 1.0],
        fric: 0.0,
        extent: None,
        shape,
        motion,
    }
}

/// Geometric walls (`*RIGIDWALL_GEOMETRIC_...`), each against a block of 4 x 4 x 2 elements
/// (20 x 20 x 10 mm, E 2 GPa, 600 us) at rest on nothing:
/// - a sphere of radius R = 15 mm driven down at U = 2 m/s (`_MOTION`, a velocity curve) onto
///   the block's top centre, indenting it by 0.7 mm;
/// - a plane (FLAT, finite) driven up under the block by a displacement ramp to 2 mm;
/// - a fixed rod (a cylinder of radius 3 mm along y, over 12 mm of its length) that the block,
///   thrown down at 4 m/s, lands on.
///
/// No node goes into a wall's body: a node that would cross lands on the tangent plane at its
/// nearest surface point, so on a curved wall it ends inside by at most (|v_t| dt)^2 / (2R)
/// for its tangential speed v_t relative to the wall, and stays so, the next steps only
/// stopping its normal motion: over the run at most T max|v_t|^2 max(dt) / (2R), the bound
/// asserted (with 1e-15 m of round-off). Each wall touches the block: some node ends on its
/// surface within that bound. The plane moves exactly as its curve says: the block's bottom
/// nodes it pushes sit on it.
#[test]
fn geometric_walls_keep_nodes_out() {
    let flat = WallShape::Plane;
    let cases = [
        (
            "sphere",
            wall(
                [0.01, 0.01, 0.01 + 0.015 + 0.0005],
                WallShape::Sphere { radius: 0.015 },
                Some(WallMotion {
                    curve: 0,
                    displacement: false,
                    dir: [0.0, 0.0, -1.0],
                }),
            ),
            2.0,
            0.0,
        ),
        (
            "moving plane",
            wall(
                [-0.005, -0.005, -0.0005],
                flat,
                Some(WallMotion {
                    curve: 1,
                    displacement: true,
                    dir: [0.0, 0.0, 1.0],
                }),
            ),
            0.0,
            0.0,
        ),
        (
            "rod",
            wall(
                [0.01, 0.004, -0.0035],
                WallShape::Cylinder {
                    radius: 0.003,
                    length: 0.012,
                },
                None,
            ),
            0.0,
            -4.0,
        ),
    ];
    for (name, mut w, speed, v0) in cases {
        if name == "rod" {
            // the rod's axis along +y
            w.head = [0.01, 1.004, -0.0035];
        }
        if name == "moving plane" {
            w.extent = Some(WallExtent {
                l: [1.0, 0.0, 0.0],
                len_l: 0.03,
                len_m: 0.03,
            });
        }
        // stiffer than `soft` (E 2 GPa), for about 70 steps
        let stiff = Material {
            young: 2e9,
            ..soft()
        };
        let mut m = box_model([4, 4, 2], [0.02, 0.02, 0.01], stiff, 6e-4);
        m.curves.push(cleave_core::curve::Curve {
            id: 1,
            t: vec![0.0],
            y: vec![speed],
        });
        m.curves.push(cleave_core::curve::Curve {
            id: 2,
            t: vec![0.0, 6e-4],
            y: vec![0.0, 0.0025],
        });
        for v in m.v0.as_mut_slice() {
            *v = [0.0, 0.0, v0];
        }
        let radius = match w.shape {
            WallShape::Sphere { radius } | WallShape::Cylinder { radius, .. } => radius,
            WallShape::Plane => f64::INFINITY,
        };
        m.rigid_walls.push(w.clone());
        let (mut deepest, mut vt_max, mut dt_max, mut touch) =
            (0.0f64, 0.0f64, 0.0f64, f64::INFINITY);
        let s = run(&m, |s| {
            let t = s.state.t;
            dt_max = dt_max.max(s.state.dt);
            let tail = cleave_core::math::add(w.tail, w.offset(&s.model.curves, t));
            let wv = cleave_core::math::scale(
                cleave_core::math::sub(
                    w.offset(&s.model.curves, t + 1e-9),
                    w.offset(&s.model.curves, t),
                ),
                1e9,
            );
            let (x, v) = (s.positions(), s.velocities());
            for n in 0..x.len() {
                if let Some((gap, nrm)) = w.gap(x[n], tail, w.normal()) {
                    deepest = deepest.max(-gap);
                    if gap.abs() < 1e-4 {
                        touch = touch.min(gap.abs());
                        let vr = cleave_core::math::sub(v[n], wv);
                        let vn = cleave_core::math::dot(vr, nrm);
                        let vt = cleave_core::math::sub(vr, cleave_core::math::scale(nrm, vn));
                        vt_max = vt_max.max(cleave_core::math::norm(vt));
                    }
                }
            }
        });
        let bound = s.state.t * vt_max * vt_max * dt_max / (2.0 * radius) + 1e-15;
        eprintln!(
            "{name}: {} steps; deepest {deepest:.2e} m (bound {bound:.2e}), nearest {touch:.1e} m",
            s.state.step
        );
        assert!(s.state.step > 20, "{name}");
        assert!(deepest <= bound, "{name}: {deepest} vs {bound}");
        assert!(
            touch <= bound.max(1e-12),
            "{name}: the wall touches ({touch})"
        );
    }
}
