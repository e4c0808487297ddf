//! The 4-node constant-strain tetrahedron (LS-DYNA ELFORM 10): geometry and force kernel.
//!
//! Linear shape functions N1 = 1 - xi - eta - zeta, N2 = xi, N3 = eta, N4 = zeta, so the
//! map x(xi) has the constant Jacobian `J = [x2 - x1 | x3 - x1 | x4 - x1]` (the edge matrix),
//! the volume is `det J / 6` and the gradients `b_a = dN_a/dx` are constant: the rows of
//! `J^-1` for nodes 2-4 and minus their sum for node 1. A linear velocity field is reproduced
//! exactly and there are no hourglass modes.
//!
//! The step is the hexahedron's ([`super::kernel::hex8_step`]) without part 6: velocity
//! gradient `L = J_v J_mid^-1` at the mid-step geometry, Hughes-Winget rotation, the material
//! update, bulk viscosity with `l = V^(1/3)`, corner forces `f_a = -V (sigma - q I) b_a`, and
//! the stable step with the characteristic length of the minimum altitude, `3 V / A_max`
//! (LS-DYNA theory manual, time step of the 4-node tetrahedron).

use super::kernel::{
    stable_dt, stress_forces, update_stress, ElementStep, InvertedElement, KernelControls,
};
use crate::material::{History, SolidParams};
use crate::math::{cross, det, inverse, norm, sub, Mat3, Sym3, Vec3};

/// The edge matrix `J[i][k] = (x_(k+1) - x_0)[i]`.
#[inline(always)]
pub fn edge_matrix(x: &[Vec3; 4]) -> Mat3 {
    let mut j = [[0.0; 3]; 3];
    for k in 0..3 {
        for i in 0..3 {
            j[i][k] = x[k + 1][i] - x[0][i];
        }
    }
    j
}

/// Volume `det J / 6` (negative when inverted).
#[inline]
pub fn volume(x: &[Vec3; 4]) -> f64 {
    det(&edge_matrix(x)) / 6.0
}

/// The 4 faces as node indices, each ordered so that its normal by the right-hand rule
/// points out of the element.
pub const FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];

/// Largest face area.
#[inline]
pub fn max_face_area(x: &[Vec3; 4]) -> f64 {
    let mut c2max: f64 = 0.0;
    for f in FACES {
        let c = cross(sub(x[f[1]], x[f[0]]), sub(x[f[2]], x[f[0]]));
        c2max = c2max.max(crate::math::dot(c, c));
    }
    0.5 * c2max.sqrt()
}

/// Volume and gradients `b_a`; `None` if the volume is not positive and finite.
#[inline]
pub fn gradients(x: &[Vec3; 4]) -> Option<(f64, [Vec3; 4])> {
    let j = edge_matrix(x);
    let d = det(&j);
    if d.is_nan() || d <= 0.0 || !d.is_finite() {
        return None;
    }
    let jinv = inverse(&j)?;
    Some((d / 6.0, gradients_from_inverse(&jinv)))
}

/// `b_(k+1) = row k of J^-1`, `b_0 = -(b_1 + b_2 + b_3)`.
#[inline(always)]
fn gradients_from_inverse(jinv: &Mat3) -> [Vec3; 4] {
    let (b1, b2, b3) = (jinv[0], jinv[1], jinv[2]);
    let b0 = [
        -(b1[0] + b2[0] + b3[0]),
        -(b1[1] + b2[1] + b3[1]),
        -(b1[2] + b2[2] + b3[2]),
    ];
    [b0, b1, b2, b3]
}

/// The mid-step volume and volumetric strain increment `tr(J_v J_mid^-1) dt` of a
/// tetrahedron at positions `x` (t^n) and velocities `v` (t^(n-1/2)), as its step takes them
/// (`None` if inverted at mid-step; `(0, 0)`-like zeros when `dt` is 0 are fine to average).
pub fn volume_increment(x: &[Vec3; 4], v: &[Vec3; 4], dt: f64) -> Option<(f64, f64)> {
    let jn = edge_matrix(x);
    let jv = edge_matrix(v);
    let mut jm = jn;
    for i in 0..3 {
        for k in 0..3 {
            jm[i][k] -= 0.5 * dt * jv[i][k];
        }
    }
    let d = det(&jm);
    if d.is_nan() || d <= 0.0 || !d.is_finite() {
        return None;
    }
    let inv = inverse(&jm)?;
    let l = crate::math::mat_mul(&jv, &inv);
    Some((d / 6.0, (l[0][0] + l[1][1] + l[2][2]) * dt))
}

/// The element phase for one tetrahedron (the arguments as [`super::kernel::hex8_step`]'s,
/// without hourglass forces; `theta_bar` the averaged volumetric strain increment of ELFORM 13,
/// [`super::nodal_pressure`], `None` for the element's own); writes the 4 corner forces to `f`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn tet4_step(
    x: &[Vec3; 4],
    v: &[Vec3; 4],
    theta_bar: Option<f64>,
    dt_prev: f64,
    mat: &SolidParams,
    ctl: &KernelControls,
    sigma: &mut Sym3,
    hist: &mut History,
    q_prev: &mut f64,
    f: &mut [Vec3; 4],
) -> Result<ElementStep, InvertedElement> {
    let jn = edge_matrix(x);
    let (vol, b) = gradients(x).ok_or(InvertedElement)?;
    let l_vol = crate::math::cbrt(vol);
    let jv = edge_matrix(v);
    let (de_internal, q, eps_v_rate) = update_stress(
        &jn,
        &jv,
        1.0 / 6.0,
        l_vol,
        theta_bar,
        dt_prev,
        mat,
        ctl,
        sigma,
        hist,
        q_prev,
    )?;
    stress_forces(vol, &b, sigma, q, f);
    let dt_crit = stable_dt(
        3.0 * vol / max_face_area(x),
        mat.step_speed,
        eps_v_rate,
        ctl,
    );
    Ok(ElementStep {
        dt_crit,
        volume: vol,
        de_internal,
        de_hourglass: 0.0,
    })
}

/// The corner forces at x^n from the state the last [`tet4_step`] left: the same arithmetic,
/// so the same forces bit for bit.
pub fn tet4_corner_forces(
    x: &[Vec3; 4],
    sigma: &Sym3,
    q: f64,
    f: &mut [Vec3; 4],
) -> Result<(), InvertedElement> {
    let (vol, b) = gradients(x).ok_or(InvertedElement)?;
    stress_forces(vol, &b, sigma, q, f);
    Ok(())
}

/// Area of a triangle.
pub fn triangle_area(p0: Vec3, p1: Vec3, p2: Vec3) -> f64 {
    0.5 * norm(cross(sub(p1, p0), sub(p2, p0)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Hourglass, Material, MaterialKind};

    fn distorted() -> [Vec3; 4] {
        [
            [0.1, -0.05, 0.02],
            [1.2, 0.1, -0.1],
            [0.3, 0.9, 0.15],
            [0.2, 0.25, 1.1],
        ]
    }

    #[test]
    #[allow(clippy::needless_range_loop)] // i, k index a tensor
    fn gradients_reproduce_linear_fields() {
        let x = distorted();
        let (v, b) = gradients(&x).unwrap();
        assert!((v - volume(&x)).abs() < 1e-15 && v > 0.0);
        for i in 0..3 {
            for k in 0..3 {
                let s: f64 = (0..4).map(|a| x[a][i] * b[a][k]).sum();
                assert!((s - if i == k { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
        // the unit tetrahedron: V = 1/6, faces 1/2 and sqrt(3)/2
        let u = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!((volume(&u) - 1.0 / 6.0).abs() < 1e-16);
        assert!((max_face_area(&u) - 3f64.sqrt() / 2.0).abs() < 1e-15);
        // faces point outwards
        let c = [0.25; 3];
        for f in FACES {
            let n = cross(sub(u[f[1]], u[f[0]]), sub(u[f[2]], u[f[0]]));
            assert!(crate::math::dot(n, sub(u[f[0]], c)) > 0.0);
        }
    }

    /// A uniform stretch rate d on a distorted tetrahedron: after one step the stress is the
    /// elastic one, sigma = lambda tr(eps) I + 2 G eps with eps = d dt (exact for a constant
    /// strain element), and the corner forces are V sigma times the face area vectors / 3.
    #[test]
    fn uniform_stretch_gives_the_elastic_stress() {
        let mat = SolidParams::from_material(&Material {
            id: 1,
            density: 7800.0,
            young: 200e9,
            poisson: 0.3,
            kind: MaterialKind::Elastic,
        })
        .unwrap();
        let ctl = KernelControls {
            hourglass: Hourglass::Viscous,
            qh: 0.1,
            q1: 0.0,
            q2: 0.0,
        };
        let rate = [[1.0, 0.2, 0.0], [0.2, -0.5, 0.1], [0.0, 0.1, 0.3]];
        let dt = 1e-7;
        let x = distorted();
        let v: [Vec3; 4] = x.map(|p| crate::math::mat_vec(&rate, p));
        // positions at t^n from the mid-step geometry x - dt/2 v ... here x^n itself
        let (mut s, mut h, mut q) = ([0.0; 6], History::default(), 0.0);
        let mut f = [[0.0; 3]; 4];
        let r = tet4_step(&x, &v, None, dt, &mat, &ctl, &mut s, &mut h, &mut q, &mut f).unwrap();
        let eps = [
            rate[0][0] * dt,
            rate[1][1] * dt,
            rate[2][2] * dt,
            rate[0][1] * dt,
            rate[1][2] * dt,
            rate[2][0] * dt,
        ];
        let tr = eps[0] + eps[1] + eps[2];
        let want: [f64; 6] = std::array::from_fn(
            |i| if i < 3 { mat.lambda * tr } else { 0.0 } + 2.0 * mat.shear * eps[i],
        );
        let scale = want.iter().fold(0.0f64, |m, w| m.max(w.abs()));
        for i in 0..6 {
            // L is taken at the mid-step geometry x - dt/2 v: rate (I - dt/2 rate)^-1, which
            // differs from the rate by O(dt |rate|) = 1e-7 relative
            assert!(
                (s[i] - want[i]).abs() <= 1e-6 * scale,
                "{i}: {} vs {}",
                s[i],
                want[i]
            );
        }
        // forces sum to zero and the time step is the minimum altitude over c
        for i in 0..3 {
            let sum: f64 = f.iter().map(|fa| fa[i]).sum();
            assert!(sum.abs() < 1e-9 * f[0][i].abs().max(1.0));
        }
        let alt = 3.0 * volume(&x) / max_face_area(&x);
        assert!((r.dt_crit - alt / mat.step_speed).abs() < 1e-12 * r.dt_crit);
        // the same forces again, bit for bit
        let mut g = [[0.0; 3]; 4];
        tet4_corner_forces(&x, &s, q, &mut g).unwrap();
        assert_eq!(f, g);
    }

    #[test]
    fn inverted_tetrahedron_is_reported() {
        let mut x = distorted();
        x.swap(1, 2);
        let mat = SolidParams::from_material(&Material {
            id: 1,
            density: 1.0,
            young: 1.0,
            poisson: 0.0,
            kind: MaterialKind::Elastic,
        })
        .unwrap();
        let ctl = KernelControls {
            hourglass: Hourglass::Viscous,
            qh: 0.1,
            q1: 1.5,
            q2: 0.06,
        };
        let (mut s, mut h, mut q) = ([0.0; 6], History::default(), 0.0);
        let mut f = [[0.0; 3]; 4];
        let r = tet4_step(
            &x, &x, None, 0.0, &mat, &ctl, &mut s, &mut h, &mut q, &mut f,
        );
        assert_eq!(r, Err(InvertedElement));
    }
}
