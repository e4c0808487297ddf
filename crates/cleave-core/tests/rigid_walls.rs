//! `*RIGIDWALL_PLANAR_FINITE`: a stonewall that covers a rectangle of its plane, against where
//! each node lands worked out by hand.

use cleave_core::math::cross;
use cleave_core::mesh::box_model;
use cleave_core::model::{Material, MaterialKind, RigidWall, WallExtent};
mod common;
use common::run;

fn soft() -> Material {
    Material {
        id: 1,
        density: 1000.0,
        young: 1e7,
        poisson: 0.3,
        kind: MaterialKind::Elastic,
    }
}

/// `covers` against the rectangle drawn by hand: a wall in the plane z = 0 (normal +z) from
/// the tail (1, 2, 0), l along (1, 1, 0)/sqrt(2) for 2, m = n x l = (-1, 1, 0)/sqrt(2) for 1.
#[test]
fn a_finite_wall_covers_its_rectangle() {
    let s = 0.5f64.sqrt();
    let w = RigidWall {
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
            assert_eq!(w.covers(at(a, b, z), n), inside, "({a}, {b}, {z})");
        }
    }
    let mut unbounded = w.clone();
    unbounded.extent = None;
    assert!(unbounded.covers(at(5.0, -3.0, 1.0), n));
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
