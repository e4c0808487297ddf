//! The paper's section 4.1: a ceramic ball fragmenting on a rigid plate.
//!
//! - Ball: diameter 10 mm, centred at the origin, an O-grid hexahedral sphere
//!   ([`ogrid_sphere`]) of one of the paper's six sizes (Table II: 256, 425, 648, 2800, 8775,
//!   20000 elements with 321, 520, 779, 3137, 9504, 21271 nodes), or one of two larger ones
//!   of the same family for scaling runs ([`LARGE_BALL_SIZES`]: 160,000 and 1,097,440).
//! - Alumina (Table I): `*MAT_ELASTIC` E 366 GPa, rho 3960 kg/m^3, nu 0.22, with
//!   `*MAT_ADD_SEPARATION` MODEL 1 SIGMAX 310 MPa (the tensile strength): an interface fails
//!   when the normal stress across it reaches 310 MPa.
//! - Initial velocity (0, -75, +50) m/s: 75 m/s towards the plate (-y), 50 m/s along it (+z).
//! - Plate: 0.02 x 0.02 x 0.01 m (x, z, and y its thickness) of 5 x 1 x 5 = 25 bricks,
//!   centred under the ball, its top face 0.1 mm below the ball's lowest node (contact after
//!   1.3 us);
//!   `*MAT_RIGID` with steel's E 200 GPa, nu 0.3, rho 7850 kg/m^3 (so the contact stiffness
//!   is steel's), fully constrained (CMO 1, CON1 7, CON2 7).
//! - `*CONTACT_AUTOMATIC_SINGLE_SURFACE` over all parts, FS 0.5, FD 0.1 (so every surface,
//!   the fragments' new ones included, is in contact), SLSFAC 0.2 ([`SLSFAC`]).
//! - 10 ms; glstat, history and contact force every min(1 us, T/200) (a Hertz estimate of the
//!   contact gives about 7 us, so 1 us resolves it), 50 ParaView states; history nodes at
//!   the ball's bottom and top, history solids at the bottom and the centre.

use cleave_core::mesh::BoxMesh;
use cleave_core::mesh::{ogrid_sphere, Assembly};
use cleave_core::model::{
    ContactDef, Material, MaterialKind, Model, OutputRequests, SeparationDef,
};

/// The paper's meshes: (elements, nodes, n, m) of [`ogrid_sphere`].
pub const BALL_SIZES: [(usize, usize, usize, usize); 6] = [
    (256, 321, 4, 2),
    (425, 520, 5, 2),
    (648, 779, 6, 2),
    (2800, 3137, 10, 3),
    (8775, 9504, 15, 4),
    (20000, 21271, 20, 5),
];
/// Larger balls of the same O-grid family as the paper's 20000 (n = 4 m), for measuring how
/// fragmenting runs scale on many cores (issue 34): m = 10 gives 160,000 elements, m = 19 the
/// first size of the family past a million, 1,097,440. Elements `n^3 + 6 n^2 m`, nodes
/// `(n + 1)^3 + m (6 n^2 + 2)`.
pub const LARGE_BALL_SIZES: [(usize, usize, usize, usize); 2] =
    [(160_000, 164_941, 40, 10), (1_097_440, 1_115_035, 76, 19)];
pub const DEFAULT_ELEMENTS: usize = 2800;
/// The paper's simulated time.
pub const END_TIME: f64 = 10e-3;
/// Ball radius (m).
pub const RADIUS: f64 = 0.005;
/// Penalty scale of the contact (`*CONTROL_CONTACT` SLSFAC; LS-DYNA's default is 0.1).
///
/// A pair's spring is the smaller of its face's and its node's (`*CONTROL_CONTACT` PENOPT 1,
/// LS-DYNA's default): against the plate, the ball's nodes (k = SLSFAC K A^2/V of their
/// elements, softer than the plate's 4 mm bricks), and with SLSFAC 0.1 these springs are much
/// softer than the alumina behind them. Measured without separation, 2800 elements, 50 us
/// (`cleave example ball-impact`, `cleave run --end-time 50e-6 --no-separation`, the contact
/// force every 0.25 us), the peak contact force against Hertz's 83.4 kN (rigid plate,
/// E* = E/(1 - nu^2)): 51.1 kN at 0.1, 57.5 kN at 0.2, 62.7 kN at 0.3, 78.1 kN at 1.0. With
/// separation, the 2800-element ball at 0.1 stays whole (100 interfaces fail by 50 us, no
/// piece comes off); at 0.2 it breaks up (README; 1633 interfaces, 11 pieces), at 0.3 too
/// (2050, 10 pieces). The elements set the time step at 0.2 (2265 steps to 50 us); at 0.3 the
/// springs do from the start (2.48e-8 s before TSSFAC, the elements 2.90e-8 s; the summary
/// says so; 2287 steps). The coarse balls are softer still: at 0.2 the 648-element one cracks (136
/// interfaces by 40 us) but stays whole.
pub const SLSFAC: f64 = 0.2;
/// Gap between the ball and the plate (m).
pub const GAP: f64 = 1e-4;

/// Every ball size: the paper's six, then the large ones.
fn all_sizes() -> impl Iterator<Item = &'static (usize, usize, usize, usize)> {
    BALL_SIZES.iter().chain(LARGE_BALL_SIZES.iter())
}

/// The ball-impact model with a ball of `elements` elements (one of [`BALL_SIZES`] or
/// [`LARGE_BALL_SIZES`]) and the end time `end_time`; an error message for any other size.
pub fn ball_impact(elements: usize, end_time: f64) -> Result<Model, String> {
    let Some(&(_, _, n, m)) = all_sizes().find(|s| s.0 == elements) else {
        let allowed: Vec<String> = all_sizes().map(|s| s.0.to_string()).collect();
        return Err(format!(
            "--elements {elements}: ball-impact has meshes of {} elements only",
            allowed.join(", ")
        ));
    };
    let mut a = Assembly::new(
        &format!(
            "Ball impact: alumina D 10 mm, {elements} elements, v (0,-75,50) m/s, rigid plate"
        ),
        end_time,
    );
    let alumina = a.material(Material {
        id: 0,
        density: 3960.0,
        young: 366e9,
        poisson: 0.22,
        kind: MaterialKind::Elastic,
    });
    let steel = a.material(Material {
        id: 0,
        density: 7850.0,
        young: 200e9,
        poisson: 0.3,
        kind: MaterialKind::Rigid {
            cmo: 1,
            con1: 7,
            con2: 7,
        },
    });
    let ball_part = a.part("alumina ball", alumina);
    let plate_part = a.part("rigid steel plate", steel);

    let ball = ogrid_sphere(RADIUS, n, m);
    // the lowest node: the south pole for even n, a little higher for odd n
    let bottom = ball.x.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let (ball_nodes, ball_elems) = a.mesh(ball, |_| ball_part);
    let mut plate = BoxMesh::new([5, 1, 5], [0.02, 0.01, 0.02]);
    plate.translate([-0.01, bottom - GAP - 0.01, -0.01]);
    a.mesh(plate, |_| plate_part);

    let mut model = a.finish();
    for i in ball_nodes.clone() {
        model.v0[i as usize] = [0.0, -75.0, 50.0];
    }
    model.separations = vec![SeparationDef {
        material: alumina,
        model: 1,
        sigmax: 310e6,
        beta: 1.0,
        gc: 0.0,
        bond: 1,
        strength: Default::default(),
    }];
    model.contacts = vec![ContactDef::single_surface_all(0.5, 0.1)];
    model.control.slsfac = SLSFAC;

    // history: the ball's lowest and highest node (ties: the first), the element with the
    // lowest centroid and the one nearest the centre
    let x = &model.x0;
    let extreme = |sign: f64| {
        ball_nodes
            .clone()
            .min_by(|&p, &q| (sign * x[p as usize][1]).total_cmp(&(sign * x[q as usize][1])))
            .unwrap_or(0)
    };
    let (bottom, top) = (extreme(1.0), extreme(-1.0));
    let centroid = |e: u32| -> [f64; 3] {
        let c = &model.conn[e as usize];
        std::array::from_fn(|d| c.iter().map(|&i| x[i as usize][d]).sum::<f64>() / 8.0)
    };
    let lowest = ball_elems
        .clone()
        .min_by(|&p, &q| centroid(p)[1].total_cmp(&centroid(q)[1]))
        .unwrap_or(0);
    let r2 = |c: [f64; 3]| c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    let centre = ball_elems
        .clone()
        .min_by(|&p, &q| r2(centroid(p)).total_cmp(&r2(centroid(q))))
        .unwrap_or(0);
    let dt = (end_time / 200.0).min(1e-6);
    model.output = OutputRequests {
        glstat_dt: dt,
        nodout_dt: dt,
        elout_dt: dt,
        rwforc_dt: 0.0,
        rcforc_dt: dt,
        d3plot_dt: end_time / 50.0,
        history_nodes: vec![bottom, top],
        history_solids: vec![lowest, centre],
    };
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every listed size is what the O-grid builds: n^3 + 6 n^2 m elements and
    /// (n + 1)^3 + m (6 n^2 + 2) nodes, and the large ones keep the family's n = 4 m.
    #[test]
    fn listed_sizes_are_what_the_mesh_builds() {
        for &(elements, nodes, n, m) in all_sizes() {
            let s = ogrid_sphere(RADIUS, n, m);
            assert_eq!(s.conn.len(), elements, "n={n} m={m}");
            assert_eq!(s.x.len(), nodes, "n={n} m={m}");
        }
        for &(_, _, n, m) in &LARGE_BALL_SIZES {
            assert_eq!(n, 4 * m);
        }
    }

    #[test]
    fn other_sizes_are_refused_with_the_list() {
        let Err(e) = ball_impact(1_000_000, 1e-6) else {
            panic!("1,000,000 is not a listed size")
        };
        assert!(e.contains("160000, 1097440"), "{e}");
    }
}
