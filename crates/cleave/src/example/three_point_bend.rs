//! The paper's section 4.2: a notched steel beam under impact, after the drop-weight
//! experiments of Pandolfi, Guduru, Ortiz and Rosakis (C300 maraging steel). The paper does not
//! give the specimen's dimensions; these are of the order of that experiment's:
//!
//! - Beam: length 200 mm (x in [-100, 100] mm), height 75 mm (y in [0, 75] mm), thickness
//!   25 mm (z in [-12.5, 12.5] mm). The impactor moves at a constant speed, so the response
//!   per unit thickness hardly depends on the thickness; 4 elements through it (6.25 mm).
//! - Pre-notch: a zero-width slit at mid-span (x = 0) from the bottom to a third of the height
//!   (25 mm): the nodes on x = 0 below the notch tip are duplicated, the elements on either
//!   side having their own, so the notch faces are free; the tip line (y = 25 mm) is shared.
//! - Mesh: 84 x 48 x 4 = 16128 hexahedra. Along the height 48 rows of 1.5625 mm (the notch
//!   is 16 rows, the ligament 32). Along the length 1.4 mm columns within 14 mm of the
//!   centre-line (10 each side), then 32 columns each side growing geometrically (ratio about
//!   1.037) to 4.5 mm at the ends. So the mesh along the centre-line is 1.4 mm x 1.56 mm, the
//!   paper's "approximately 1.4 mm x 1.6 mm". With the impactor and supports the deck has
//!   16408 hexahedra (the paper's Figure 6: 16384).
//! - Steel: `*MAT_PLASTIC_KINEMATIC` E 200 GPa, nu 0.3, rho 7830 kg/m^3, SIGY 1.9 GPa, ETAN
//!   50 GPa, isotropic hardening (BETA 1; the loading is monotonic where it yields).
//! - Separation group: a second material with the same steel properties, in a strip of two
//!   element columns either side of the centre plane (|x| < 2.8 mm) from the notch tip to the
//!   top: 4 x 32 x 4 = 512 elements. `*MAT_ADD_SEPARATION` MODEL 1 SIGMAX 2 GPa (the paper's
//!   normal-stress criterion, at the maximum cohesive stress of Pandolfi et al.), BOND 1 (the
//!   strip's faces to the plain steel may fail too). With `--model 3` the same onset followed
//!   by a linear-softening cohesive law that dissipates GC = K_Ic^2 (1 - nu^2) / E = 4.55e4
//!   J/m^2 (K_Ic = 100 MPa sqrt(m), a C300-steel-like toughness; BETA 1).
//! - Impactor: a rigid steel cylinder (the tup) of radius 5 mm along z, 31.25 mm long (longer
//!   than the beam is thick, so its ends do not meet the beam's edges), its lowest line 0.01 mm
//!   above the top at mid-span, driven at a constant 10 m/s downwards by
//!   `*BOUNDARY_PRESCRIBED_MOTION_RIGID` (x, z and the rotations fixed by CON1 6 and CON2 7;
//!   it also starts at 10 m/s, so contact begins after 1 us).
//! - Supports: two fixed rigid cylinders (radius 5 mm, CON1 7, CON2 7) under the beam at
//!   x = +-90 mm (a span of 180 mm), 0.01 mm below it. In the drop-weight test inertia
//!   dominates until well after crack initiation, and the beam may lift off its supports: the
//!   supports act through contact only, never holding the beam down.
//! - Contact: `*CONTACT_AUTOMATIC_SINGLE_SURFACE` over all parts, frictionless (impactor,
//!   supports, the notch faces and the crack faces).
//! - 0.3 ms (the paper's crack runs from 0.134 ms for about 0.1 ms); glstat, histories and
//!   contact force every T/300 (1 us), 60 ParaView states. History nodes: the top of the
//!   mid-span, the two faces of the notch mouth and the notch tip (at mid-thickness); history
//!   solids: the two strip elements at the notch tip.

use cleave_core::curve::Curve;
use cleave_core::mesh::{extrude, ogrid_disc, Assembly, BoxMesh};
use cleave_core::model::{
    ContactDef, Material, MaterialKind, Model, MotionTarget, OutputRequests, PrescribedMotion,
    SeparationDef, Vad,
};

/// Default end time (s).
pub const END_TIME: f64 = 0.3e-3;
/// Beam length, height and thickness (m); the notch is NOTCH_ROWS of the NY rows deep.
pub const LENGTH: f64 = 0.2;
pub const HEIGHT: f64 = 0.075;
pub const THICKNESS: f64 = 0.025;
/// Element columns and rows of the beam, and layers through the thickness.
pub const NX: usize = 84;
pub const NY: usize = 48;
pub const NZ: usize = 4;
/// Width of the centre-line columns (m) and how many of them each side of the centre plane.
const H_CENTRE: f64 = 1.4e-3;
const N_CENTRE: usize = 10;
/// Rows below the notch tip, and strip columns each side of the centre plane.
pub const NOTCH_ROWS: usize = 16;
pub const STRIP_COLUMNS: usize = 2;
/// Support positions (x = +-SPAN/2), cylinder radii, and the initial gaps (m).
pub const SPAN: f64 = 0.18;
const R_CYL: f64 = 0.005;
const GAP: f64 = 1e-5;
/// Impactor speed (m/s).
pub const SPEED: f64 = 10.0;
/// Fracture energy for MODEL 3: K_Ic^2 (1 - nu^2) / E with K_Ic = 100 MPa sqrt(m).
pub const GC: f64 = 1e16 * (1.0 - 0.09) / 200e9;

/// The node planes along x: 1.4 mm columns near the centre, graded geometrically to the ends.
fn x_planes() -> Vec<f64> {
    let half = NX / 2;
    let graded = half - N_CENTRE;
    let rest = LENGTH / 2.0 - N_CENTRE as f64 * H_CENTRE;
    // sizes H_CENTRE r^k, k = 1..graded, summing to `rest`: bisection on r
    let sum = |r: f64| {
        (1..=graded)
            .map(|k| H_CENTRE * r.powi(k as i32))
            .sum::<f64>()
    };
    let (mut lo, mut hi) = (1.0, 2.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if sum(mid) < rest {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let r = 0.5 * (lo + hi);
    let mut right = vec![0.0];
    for k in 1..=half {
        let h = if k <= N_CENTRE {
            H_CENTRE
        } else {
            H_CENTRE * r.powi((k - N_CENTRE) as i32)
        };
        right.push(right[k - 1] + h);
    }
    right[half] = LENGTH / 2.0;
    let mut xs: Vec<f64> = right.iter().rev().map(|&x| -x).collect();
    xs.pop();
    xs.extend(right);
    xs
}

/// The beam: the structured block with the notch's nodes duplicated for the elements right
/// of the centre plane. Returns the mesh and, per original notch node, its duplicate.
fn beam_mesh() -> (BoxMesh, Vec<(u32, u32)>) {
    let xs = x_planes();
    let ys: Vec<f64> = (0..=NY).map(|j| HEIGHT * j as f64 / NY as f64).collect();
    let zs: Vec<f64> = (0..=NZ)
        .map(|k| -THICKNESS / 2.0 + THICKNESS * k as f64 / NZ as f64)
        .collect();
    let mut mesh = BoxMesh::from_coords(&xs, &ys, &zs);
    let ic = NX / 2;
    let node = |i: usize, j: usize, k: usize| (i + (NX + 1) * (j + (NY + 1) * k)) as u32;
    let mut twin = vec![u32::MAX; mesh.x.len()];
    let mut pairs = Vec::new();
    for k in 0..=NZ {
        for j in 0..NOTCH_ROWS {
            let n = node(ic, j, k);
            let d = mesh.x.len() as u32;
            mesh.x.push(mesh.x[n as usize]);
            twin[n as usize] = d;
            pairs.push((n, d));
        }
    }
    for (e, c) in mesh.conn.iter_mut().enumerate() {
        if e % NX >= ic {
            for n in c.iter_mut() {
                if twin[*n as usize] != u32::MAX {
                    *n = twin[*n as usize];
                }
            }
        }
    }
    (mesh, pairs)
}

/// Whether beam element `e` (in [`BoxMesh`] order) is in the separation strip.
pub fn in_strip(e: usize) -> bool {
    let (i, j) = (e % NX, (e / NX) % NY);
    let ic = NX / 2;
    j >= NOTCH_ROWS && i + STRIP_COLUMNS >= ic && i < ic + STRIP_COLUMNS
}

/// A rigid cylinder of radius R_CYL along z, longer than the beam by a quarter of its
/// thickness, its axis through (x, y).
fn cylinder(n: usize, m: usize, x: f64, y: f64) -> BoxMesh {
    let (pts, quads) = ogrid_disc(R_CYL, n, m);
    let length = THICKNESS * 1.25;
    let mut c = extrude(&pts, &quads, length, 5);
    c.translate([x, y, -length / 2.0]);
    c
}

/// The three-point-bend model with separation MODEL `model` (1, 3 or 4) and end time
/// `end_time`.
pub fn three_point_bend(model: i32, end_time: f64) -> Result<Model, String> {
    if ![1, 3, 4].contains(&model) {
        return Err(format!(
            "--model {model}: three-point-bend has MODEL 1 (normal stress), 3 (linear cohesive) or 4 (exponential cohesive)"
        ));
    }
    let mut a = Assembly::new(
        &format!(
            "Three-point bend: notched steel beam 200x75x25 mm, tup at 10 m/s, strip MODEL {model}"
        ),
        end_time,
    );
    let steel = Material {
        id: 0,
        density: 7830.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::PlasticKinematic {
            sigy: 1.9e9,
            etan: 50e9,
            beta: 1.0,
        },
    };
    let rigid = |con1| Material {
        id: 0,
        density: 7830.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::Rigid {
            cmo: 1,
            con1,
            con2: 7,
        },
    };
    let plain = a.material(steel.clone());
    let strip = a.material(steel);
    let tup = a.material(rigid(6));
    let fixed = a.material(rigid(7));
    let beam_part = a.part("steel beam", plain);
    let strip_part = a.part("steel crack strip (separation)", strip);
    let tup_part = a.part("rigid impactor", tup);
    let support_part = a.part("rigid supports", fixed);

    let (beam, notch_pairs) = beam_mesh();
    a.mesh(beam, |e| if in_strip(e) { strip_part } else { beam_part });
    let (tup_nodes, _) = a.mesh(cylinder(4, 1, 0.0, HEIGHT + R_CYL + GAP), |_| tup_part);
    for x in [-SPAN / 2.0, SPAN / 2.0] {
        a.mesh(cylinder(2, 1, x, -R_CYL - GAP), |_| support_part);
    }

    let mut m = a.finish();
    for i in tup_nodes {
        m.v0[i as usize] = [0.0, -SPEED, 0.0];
    }
    m.curves = vec![Curve {
        id: 1,
        t: vec![0.0, end_time],
        y: vec![1.0, 1.0],
    }];
    m.prescribed = vec![PrescribedMotion {
        window: cleave_core::model::Window::ALWAYS,
        target: MotionTarget::Rigid(tup_part),
        dof: cleave_core::model::MotionDof::Axis(1),
        vad: Vad::Velocity,
        curve: 0,
        sf: -SPEED,
    }];
    m.separations = vec![SeparationDef {
        material: strip,
        model,
        sigmax: 2e9,
        beta: 1.0,
        gc: if model >= 3 { GC } else { 0.0 },
        bond: 1,
        strength: Default::default(),
    }];
    m.contacts = vec![ContactDef::single_surface_all(0.0, 0.0)];
    // history at mid-thickness (node plane k = NZ/2)
    let ic = NX / 2;
    let node = |i: usize, j: usize| (i + (NX + 1) * (j + (NY + 1) * (NZ / 2))) as u32;
    let mouth = node(ic, 0);
    let mouth_twin = notch_pairs
        .iter()
        .find(|p| p.0 == mouth)
        .map_or(mouth, |p| p.1);
    let elem = |i: usize, j: usize| (i + NX * (j + NY * (NZ / 2))) as u32;
    let dt = end_time / 300.0;
    m.output = OutputRequests {
        glstat_dt: dt,
        nodout_dt: dt,
        elout_dt: dt,
        rwforc_dt: 0.0,
        rcforc_dt: dt,
        d3plot_dt: end_time / 60.0,
        history_nodes: vec![node(ic, NY), mouth, mouth_twin, node(ic, NOTCH_ROWS)],
        history_solids: vec![elem(ic - 1, NOTCH_ROWS), elem(ic, NOTCH_ROWS)],
    };
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use cleave_core::mesh::quality;

    #[test]
    fn x_planes_are_symmetric_and_graded() {
        let xs = x_planes();
        assert_eq!(xs.len(), NX + 1);
        assert_eq!(xs[NX / 2], 0.0);
        assert_eq!((xs[0], xs[NX]), (-LENGTH / 2.0, LENGTH / 2.0));
        for (a, b) in xs.iter().zip(xs.iter().rev()) {
            assert!((a + b).abs() < 1e-15);
        }
        let h: Vec<f64> = xs.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(h.iter().all(|&h| h > 0.0));
        assert!((h[NX / 2] - H_CENTRE).abs() < 1e-12);
        assert!(h[0] < 4.6e-3 && h[0] > 4.4e-3, "end column {}", h[0]);
        // neighbouring columns differ by at most the grading ratio
        for w in h.windows(2) {
            assert!(w[0].max(w[1]) / w[0].min(w[1]) < 1.04);
        }
    }

    #[test]
    fn beam_quality() {
        let (beam, pairs) = beam_mesh();
        assert_eq!(beam.conn.len(), NX * NY * NZ);
        assert_eq!(pairs.len(), NOTCH_ROWS * (NZ + 1));
        let q = quality(&beam);
        eprintln!("beam: {q:?}");
        assert!(q.min_scaled_jacobian > 0.999);
    }
}
