//! One-point hexahedron force kernel with Flanagan-Belytschko hourglass control.
//!
//! One call does the whole element phase of a step, gather to scatter, for one element
//! (`x` at t^n, `v` at t^(n-1/2), `dt_prev` = t^n - t^(n-1)):
//!
//! 1. velocity gradient at the mid-step geometry x^(n-1/2) = x^n - dt_prev/2 v:
//!    L = J_v J_mid^-1 with J the centre Jacobian (linear in the nodal values). For a rigid
//!    rotation this L is exactly skew (the Cayley transform of the rotation), so a rigidly
//!    rotating element accrues no strain;
//! 2. objective stress rotation by Hughes and Winget (1980): R = (I - W dt/2)^-1 (I + W dt/2),
//!    sigma <- R sigma R^T, which for the rigid rotation above reproduces the rotation exactly;
//! 3. material update with d_eps = D dt_prev; internal energy by the mid-point rule
//!    dE = V_mid (sigma_old + sigma_new)/2 : d_eps;
//! 4. bulk viscosity (LS-DYNA theory manual, section 18): in compression (eps_v' < 0)
//!    q = rho l (Q1 l eps_v'^2 - Q2 c eps_v'), l = V^(1/3); added as a pressure; its work is
//!    charged as -V (q^(n-1) + q^n)/2 tr(D) dt, q^(n-1) kept per element (`q_prev`);
//! 5. corner forces f_a = -V sigma b_a at x^n (b_a = dN_a/dx at the centre);
//! 6. hourglass forces on the Flanagan-Belytschko vectors
//!    gamma_alpha = Gamma_alpha - sum_i (Gamma_alpha . x_i) b_i (orthogonal to linear fields,
//!    so rigid motion and uniform strain make none), with rates qdot_alpha = sum_a v_a gamma_alpha,a:
//!    viscous (IHQ 1): F_alpha = a_h qdot_alpha, a_h = QH rho c V^(2/3) / 4;
//!    stiffness (IHQ 4/5): F_alpha += k dt qdot_alpha, k = QH (lambda + 2G) V (sum_a b_a.b_a) / 8;
//!    f_a -= sum_alpha F_alpha gamma_alpha,a; F is kept per element (`hg_force`) for both forms;
//! 7. the element's stable time step: dt = l_c / (Q + sqrt(Q^2 + c^2)), l_c = V / A_max,
//!    Q = Q2 c + Q1 l_c |eps_v'| in compression, else 0 (LS-DYNA theory manual, eq. 22.11).

use super::hex8::{centre_jacobian, det_inverse, gradients_from_inverse, max_face_area, GAMMA};
use crate::material::{History, SolidParams};
use crate::math::{Mat3, Sym3, Vec3};
use crate::model::Hourglass;

/// Global controls the kernel needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KernelControls {
    pub hourglass: Hourglass,
    pub qh: f64,
    pub q1: f64,
    pub q2: f64,
}

/// What one element reports back from a step.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct ElementStep {
    /// Stable time step of the element (before TSSFAC).
    pub dt_crit: f64,
    /// Volume at t^n.
    pub volume: f64,
    /// Internal energy increment over [t^(n-1), t^n] (stress and bulk-viscosity work).
    pub de_internal: f64,
    /// Hourglass energy increment over the same interval.
    pub de_hourglass: f64,
}

/// The element has a non-positive or non-finite volume.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
pub struct InvertedElement;

/// The element phase for one hexahedron; writes the 8 corner forces (force on each node) to `f`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn hex8_step(
    x: &[Vec3; 8],
    v: &[Vec3; 8],
    dt_prev: f64,
    mat: &SolidParams,
    ctl: &KernelControls,
    sigma: &mut Sym3,
    hist: &mut History,
    q_prev: &mut f64,
    hg_force: Option<&mut [f64; 12]>,
    // (None: the previous force is taken as zero; tests of a single step use this)
    f: &mut [Vec3; 8],
) -> Result<ElementStep, InvertedElement> {
    let jn = centre_jacobian(x);
    let (detn, jinv) = det_inverse(&jn).ok_or(InvertedElement)?;
    let vol = 8.0 * detn;
    // l = V^(1/3), the length of the bulk viscosity and (squared) of the viscous hourglass
    let l_vol = crate::math::cbrt(vol);
    let b = gradients_from_inverse(&jinv);
    let jv = centre_jacobian(v);

    // 1-4: stress update over the previous interval.
    let (de_internal, q, eps_v_rate) = update_stress(
        &jn, &jv, 8.0, l_vol, None, dt_prev, mat, ctl, sigma, hist, q_prev,
    )?;

    // 5: corner forces from the total stress sigma - q I.
    stress_forces(vol, &b, sigma, q, f);

    // 6: hourglass.
    let gamma = hourglass_vectors(x, &b);
    let mut qdot = [[0.0; 3]; 4];
    for al in 0..4 {
        for a in 0..8 {
            for i in 0..3 {
                qdot[al][i] += v[a][i] * gamma[al][a];
            }
        }
    }
    // The generalized hourglass force F of the previous step is kept in `hg_force`, so the
    // work of each force is charged over its own interval with v^n = mean of the half steps:
    // dE = 1/2 (F^(n-1) + F^n) . qdot^(n-1/2) dt. (Charging F^n . qdot^(n-1/2) dt instead
    // over-counts the dissipation of modes that flip sign every step, as impacts excite.)
    let coef = match ctl.hourglass {
        Hourglass::Stiffness => {
            let bb: f64 = b
                .iter()
                .map(|ba| ba[0] * ba[0] + ba[1] * ba[1] + ba[2] * ba[2])
                .sum();
            ctl.qh * (mat.lambda + 2.0 * mat.shear) * vol * bb / 8.0 * dt_prev
        }
        Hourglass::Viscous => ctl.qh * mat.density * mat.wave_speed * l_vol * l_vol / 4.0,
    };
    let mut de_hourglass = 0.0;
    let mut scratch = [0.0; 12];
    let stored = hg_force.unwrap_or(&mut scratch);
    for al in 0..4 {
        for i in 0..3 {
            let old = stored[3 * al + i];
            let new = match ctl.hourglass {
                Hourglass::Stiffness => old + coef * qdot[al][i],
                Hourglass::Viscous => coef * qdot[al][i],
            };
            stored[3 * al + i] = new;
            de_hourglass += 0.5 * (old + new) * qdot[al][i] * dt_prev;
        }
    }
    hourglass_forces(&gamma, stored, f);

    // 7: stable time step.
    let dt_crit = stable_dt(vol / max_face_area(x), mat.step_speed, eps_v_rate, ctl);

    Ok(ElementStep {
        dt_crit,
        volume: vol,
        de_internal,
        de_hourglass,
    })
}

/// Parts 1-4 of the step for any element whose geometry is one linear map: `jn` and `jv`
/// are the Jacobians of the positions at t^n and of the velocities (the hexahedron's centre
/// Jacobian, the tetrahedron's edge matrix), `vol_per_det` the volume per unit determinant
/// (8 for the hexahedron, 1/6 for the tetrahedron), `l_vol` the bulk-viscosity length,
/// `theta_bar` a volumetric strain increment that replaces the element's own in the material
/// update (the nodal averaging of [`super::nodal_pressure`]; `None`: the element's own).
/// Updates `sigma`, `hist` and `q_prev`; returns the internal energy increment, the bulk
/// viscosity q at t^n and the volumetric strain rate tr(L).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn update_stress(
    jn: &Mat3,
    jv: &Mat3,
    vol_per_det: f64,
    l_vol: f64,
    theta_bar: Option<f64>,
    dt_prev: f64,
    mat: &SolidParams,
    ctl: &KernelControls,
    sigma: &mut Sym3,
    hist: &mut History,
    q_prev: &mut f64,
) -> Result<(f64, f64, f64), InvertedElement> {
    let mut de_internal = 0.0;
    let mut q = 0.0;
    let mut eps_v_rate = 0.0;
    if dt_prev > 0.0 {
        let mut jm = *jn;
        for i in 0..3 {
            for k in 0..3 {
                jm[i][k] -= 0.5 * dt_prev * jv[i][k];
            }
        }
        let (detm, jminv) = det_inverse(&jm).ok_or(InvertedElement)?;
        let vol_mid = vol_per_det * detm;
        let l = crate::math::mat_mul(jv, &jminv);
        let mut d_eps: Sym3 = [
            l[0][0] * dt_prev,
            l[1][1] * dt_prev,
            l[2][2] * dt_prev,
            0.5 * (l[0][1] + l[1][0]) * dt_prev,
            0.5 * (l[1][2] + l[2][1]) * dt_prev,
            0.5 * (l[2][0] + l[0][2]) * dt_prev,
        ];
        if let Some(tb) = theta_bar {
            let shift = (tb - (d_eps[0] + d_eps[1] + d_eps[2])) / 3.0;
            for d in &mut d_eps[..3] {
                *d += shift;
            }
        }
        // half-step spin W dt / 2, as (w_x, w_y, w_z) with W = [[0,-wz,wy],[wz,0,-wx],[-wy,wx,0]]
        let h = 0.25 * dt_prev;
        let w = [
            h * (l[2][1] - l[1][2]),
            h * (l[0][2] - l[2][0]),
            h * (l[1][0] - l[0][1]),
        ];
        let r = hughes_winget(w);
        rotate_sym(&r, sigma);
        if hist.back != [0.0; 6] {
            rotate_sym(&r, &mut hist.back);
        }
        let old = *sigma;
        mat.update(sigma, &d_eps, dt_prev, hist);
        let mut avg = [0.0; 6];
        for i in 0..6 {
            avg[i] = 0.5 * (old[i] + sigma[i]);
        }
        de_internal = vol_mid * crate::math::ddot(&avg, &d_eps);
        eps_v_rate = l[0][0] + l[1][1] + l[2][2];
        if eps_v_rate < 0.0 {
            let lq = l_vol;
            q = mat.density
                * lq
                * (ctl.q1 * lq * eps_v_rate * eps_v_rate - ctl.q2 * mat.wave_speed * eps_v_rate);
        }
        // trapezoid in q for the same reason as the hourglass work below
        de_internal -= vol_mid * 0.5 * (*q_prev + q) * eps_v_rate * dt_prev;
    }
    *q_prev = q;
    Ok((de_internal, q, eps_v_rate))
}

/// Part 7: the stable time step `l_c / (Q + sqrt(Q^2 + c^2))` of an element of
/// characteristic length `lc` and step speed `c`, with `Q = Q2 c + Q1 l_c |tr L|` in
/// compression, else 0 (LS-DYNA theory manual, eq. 22.11).
///
/// Compression means `tr L < -ROUND_OFF_RATE c / l_c`: `Q` jumps from 0 to `Q2 c` (6% of the
/// step with the default Q2) as the rate crosses zero, so a volume-preserving motion (a shear,
/// a rotation), whose rate is zero up to round-off, would have its step set by the sign of
/// the round-off, and two machines that round differently (a GPU fusing a multiply and an add)
/// would take different steps. A rate of `1e-12 c / l_c` compresses the element by a
/// millionth of a millionth of its volume while a wave crosses it: no physics is lost.
#[inline(always)]
pub(super) fn stable_dt(lc: f64, c: f64, eps_v_rate: f64, ctl: &KernelControls) -> f64 {
    let qv = if eps_v_rate * lc < -ROUND_OFF_RATE * c {
        ctl.q2 * c + ctl.q1 * lc * eps_v_rate.abs()
    } else {
        0.0
    };
    lc / (qv + (qv * qv + c * c).sqrt())
}

/// The volumetric strain rate, in units of `c / l_c`, below which [`stable_dt`] counts an
/// element as not compressed (step.wgsl uses the same value).
pub const ROUND_OFF_RATE: f64 = 1e-12;

/// The corner forces of an element at x^n from the state its last [`hex8_step`] left (the
/// stress, the bulk viscosity q, the generalized hourglass forces), without changing it: the
/// same arithmetic as the step's parts 5 and 6, so the same forces bit for bit. The solver
/// uses it to sum the forces of a coincident set again when the set splits in the step.
pub fn hex8_corner_forces(
    x: &[Vec3; 8],
    sigma: &Sym3,
    q: f64,
    hg_force: &[f64; 12],
    f: &mut [Vec3; 8],
) -> Result<(), InvertedElement> {
    let (detn, jinv) = det_inverse(&centre_jacobian(x)).ok_or(InvertedElement)?;
    let b = gradients_from_inverse(&jinv);
    stress_forces(8.0 * detn, &b, sigma, q, f);
    hourglass_forces(&hourglass_vectors(x, &b), hg_force, f);
    Ok(())
}

/// Part 5: `f_a = -V (sigma - q I) b_a`.
#[inline(always)]
pub(super) fn stress_forces<const N: usize>(
    vol: f64,
    b: &[Vec3; N],
    sigma: &Sym3,
    q: f64,
    f: &mut [Vec3; N],
) {
    let s = [
        sigma[0] - q,
        sigma[1] - q,
        sigma[2] - q,
        sigma[3],
        sigma[4],
        sigma[5],
    ];
    for a in 0..N {
        let ba = b[a];
        f[a] = [
            -vol * (s[0] * ba[0] + s[3] * ba[1] + s[5] * ba[2]),
            -vol * (s[3] * ba[0] + s[1] * ba[1] + s[4] * ba[2]),
            -vol * (s[5] * ba[0] + s[4] * ba[1] + s[2] * ba[2]),
        ];
    }
}

/// The Flanagan-Belytschko vectors `gamma_alpha,a = Gamma_alpha,a - (Gamma_alpha . x) . b_a`.
#[inline(always)]
fn hourglass_vectors(x: &[Vec3; 8], b: &[Vec3; 8]) -> [[f64; 8]; 4] {
    let mut gamma = [[0.0; 8]; 4];
    for al in 0..4 {
        let g = &GAMMA[al];
        let mut gx = [0.0; 3];
        for a in 0..8 {
            for i in 0..3 {
                gx[i] += g[a] * x[a][i];
            }
        }
        for a in 0..8 {
            gamma[al][a] = g[a] - (gx[0] * b[a][0] + gx[1] * b[a][1] + gx[2] * b[a][2]);
        }
    }
    gamma
}

/// Part 6's forces: `f_a -= sum_alpha F_alpha gamma_alpha,a`.
#[inline(always)]
fn hourglass_forces(gamma: &[[f64; 8]; 4], hg_force: &[f64; 12], f: &mut [Vec3; 8]) {
    for al in 0..4 {
        for i in 0..3 {
            let new = hg_force[3 * al + i];
            for a in 0..8 {
                f[a][i] -= new * gamma[al][a];
            }
        }
    }
}

/// Hughes-Winget incremental rotation R = (I - S)^-1 (I + S) for the skew matrix S with
/// axial vector `w` (S = W dt / 2). Closed form: with s = |w|^2,
/// R = I + 2/(1+s) (S + S^2).
#[inline]
pub fn hughes_winget(w: Vec3) -> Mat3 {
    let s2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    let c = 2.0 / (1.0 + s2);
    // S = [[0,-wz,wy],[wz,0,-wx],[-wy,wx,0]], S^2 = w w^T - s2 I
    let (x, y, z) = (w[0], w[1], w[2]);
    [
        [1.0 + c * (x * x - s2), c * (-z + x * y), c * (y + x * z)],
        [c * (z + y * x), 1.0 + c * (y * y - s2), c * (-x + y * z)],
        [c * (-y + z * x), c * (x + z * y), 1.0 + c * (z * z - s2)],
    ]
}

/// sigma <- R sigma R^T.
#[inline]
pub fn rotate_sym(r: &Mat3, s: &mut Sym3) {
    let m = crate::math::sym_to_mat(s);
    let rm = crate::math::mat_mul(r, &m);
    let out = crate::math::mat_mul(&rm, &crate::math::transpose(r));
    *s = crate::math::mat_to_sym(&out);
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::element::hex8::CORNERS;
    use crate::math::{mat_vec, rotation_from_vector, sub};
    use crate::model::{Material, MaterialKind};

    /// Elastic steel (7800 kg/m^3, 200 GPa, Poisson 0.3), for the element tests.
    pub(crate) fn steel() -> SolidParams {
        SolidParams::from_material(&Material {
            id: 1,
            density: 7800.0,
            young: 200e9,
            poisson: 0.3,
            kind: MaterialKind::Elastic,
        })
        .unwrap()
    }
    fn ctl() -> KernelControls {
        KernelControls {
            hourglass: Hourglass::Viscous,
            qh: 0.1,
            q1: 1.5,
            q2: 0.06,
        }
    }
    fn cube() -> [Vec3; 8] {
        let mut x = [[0.0; 3]; 8];
        for a in 0..8 {
            for i in 0..3 {
                x[a][i] = 0.5 * (1.0 + CORNERS[a][i]) * 0.01;
            }
        }
        x
    }

    /// Hughes-Winget with the mid-step velocity gradient reproduces a finite rigid rotation
    /// exactly: a pre-stressed element turned by 0.3 rad in one step carries R sigma R^T,
    /// to round-off, and gains no strain energy.
    #[test]
    fn rigid_rotation_rotates_stress_exactly() {
        let x0 = cube();
        let rot = rotation_from_vector([0.1, 0.2, 0.2]);
        let dt = 1e-6;
        let mut x1 = [[0.0; 3]; 8];
        let mut v = [[0.0; 3]; 8];
        for a in 0..8 {
            x1[a] = mat_vec(&rot, x0[a]);
            v[a] = crate::math::scale(sub(x1[a], x0[a]), 1.0 / dt);
        }
        let s0: Sym3 = [1e8, -2e7, 3e7, 4e7, -1e7, 2e7];
        let mut s = s0;
        let mut h = History::default();
        let mut f = [[0.0; 3]; 8];
        let out = hex8_step(
            &x1,
            &v,
            dt,
            &steel(),
            &ctl(),
            &mut s,
            &mut h,
            &mut 0.0,
            None,
            &mut f,
        )
        .unwrap();
        let mut expect = s0;
        rotate_sym(&rot, &mut expect);
        for i in 0..6 {
            assert!(
                (s[i] - expect[i]).abs() < 1e-6 * 1e8,
                "{i}: {} vs {}",
                s[i],
                expect[i]
            );
        }
        assert!(out.de_internal.abs() < 1e-12 * 1e8 * 1e-6);
        // viscous hourglass sees no rigid rotation (the gamma vectors are orthogonal to it)
        assert!(out.de_hourglass.abs() < 1e-9 * out.volume * 1e8 * 1e-9 + 1e-30);
    }

    /// Patch test: a uniform strain rate gives the elastic stress lambda tr(eps) I + 2G eps,
    /// corner forces that sum to zero, and no hourglass force (forces equal V sigma b exactly).
    #[test]
    fn uniform_stretch_gives_elastic_stress_and_balanced_forces() {
        let mut x0 = cube();
        x0[6][0] += 0.002; // distorted element
        x0[3][2] += 0.001;
        let grad = [[1e-3, 2e-4, 0.0], [0.0, -3e-4, 1e-4], [5e-5, 0.0, 2e-4]];
        let dt = 1.0;
        let mut x1 = x0;
        let mut v = [[0.0; 3]; 8];
        for a in 0..8 {
            // x1 = x0 + dt * G x_mid with x_mid = x0 + dt/2 G x_mid (solve by fixed point)
            let mut xm = x0[a];
            for _ in 0..60 {
                let gx = mat_vec(&grad, xm);
                xm = [
                    x0[a][0] + 0.5 * dt * gx[0],
                    x0[a][1] + 0.5 * dt * gx[1],
                    x0[a][2] + 0.5 * dt * gx[2],
                ];
            }
            v[a] = mat_vec(&grad, xm);
            for i in 0..3 {
                x1[a][i] = x0[a][i] + dt * v[a][i];
            }
        }
        let p = steel();
        let mut s = [0.0; 6];
        let mut h = History::default();
        let mut f = [[0.0; 3]; 8];
        hex8_step(
            &x1,
            &v,
            dt,
            &p,
            &KernelControls {
                q1: 0.0,
                q2: 0.0,
                ..ctl()
            },
            &mut s,
            &mut h,
            &mut 0.0,
            None,
            &mut f,
        )
        .unwrap();
        let d = [
            grad[0][0],
            grad[1][1],
            grad[2][2],
            0.5 * (grad[0][1] + grad[1][0]),
            0.5 * (grad[1][2] + grad[2][1]),
            0.5 * (grad[2][0] + grad[0][2]),
        ];
        // the spin is tiny; compare with the unrotated elastic stress to 1e-3 relative
        let tr = d[0] + d[1] + d[2];
        for i in 0..6 {
            let e = if i < 3 {
                p.lambda * tr + 2.0 * p.shear * d[i]
            } else {
                2.0 * p.shear * d[i]
            };
            assert!((s[i] - e).abs() < 1e-3 * 4e8, "{i}: {} vs {e}", s[i]);
        }
        let mut sum = [0.0; 3];
        for fa in f {
            for i in 0..3 {
                sum[i] += fa[i];
            }
        }
        let scale = 4e8 * 1e-4;
        assert!(sum.iter().all(|c| c.abs() < 1e-9 * scale));
    }

    #[test]
    fn time_step_of_a_cube_is_side_over_wave_speed() {
        let x = cube();
        let p = steel();
        let mut f = [[0.0; 3]; 8];
        let out = hex8_step(
            &x,
            &[[0.0; 3]; 8],
            0.0,
            &p,
            &ctl(),
            &mut [0.0; 6],
            &mut History::default(),
            &mut 0.0,
            None,
            &mut f,
        )
        .unwrap();
        assert!((out.dt_crit - 0.01 / p.wave_speed).abs() < 1e-12 * out.dt_crit.max(1e-30) + 1e-18);
    }

    /// The step's bulk-viscosity term: Q = Q2 c + Q1 l_c |tr L| in compression gives
    /// l_c / (Q + sqrt(Q^2 + c^2)); a rate of round-off size (a shear's tr L, 1e-16 c / l_c
    /// either side of zero) gives l_c / c on both sides, so the sign of the round-off does not
    /// choose the step (the GPU, which fuses multiplies and adds, and the CPU round shear rates
    /// to opposite signs).
    #[test]
    fn round_off_rates_do_not_cut_the_step() {
        let (lc, c) = (0.01, 5000.0);
        let k = ctl();
        let bare = lc / c;
        for rate in [0.0, 1e-16 * c / lc, -1e-16 * c / lc, -0.9e-12 * c / lc] {
            assert_eq!(stable_dt(lc, c, rate, &k), bare, "rate {rate:e}");
        }
        for rate in [-1.1e-12 * c / lc, -1e-3 * c / lc, -2.0 * c / lc] {
            let q = k.q2 * c + k.q1 * lc * rate.abs();
            let want = lc / (q + (q * q + c * c).sqrt());
            let got = stable_dt(lc, c, rate, &k);
            assert_eq!(got, want, "rate {rate:e}");
            // Q2 alone shortens the step by 1 - 1/(Q2 + sqrt(1 + Q2^2)), 5.8% at Q2 = 0.06
            assert!(got < 0.95 * bare);
        }
    }

    /// The forces `hex8_corner_forces` works out again from the state a step left are the
    /// step's own, bit for bit: a distorted element squeezed (bulk viscosity on) and twisted
    /// (hourglass modes on), over three steps, both hourglass forms.
    #[test]
    fn corner_forces_again_are_the_steps_bit_for_bit() {
        for hourglass in [Hourglass::Viscous, Hourglass::Stiffness] {
            let c = KernelControls { hourglass, ..ctl() };
            let mut x = cube();
            x[6] = [x[6][0] + 1e-3, x[6][1] - 4e-4, x[6][2] + 2e-4];
            let v: [Vec3; 8] = std::array::from_fn(|a| {
                let p = CORNERS[a];
                // squeeze along z, an hourglass twist x*y*z, a shear
                [3.0 * p[1] + 2.0 * p[0] * p[1] * p[2], -p[0], -20.0 * p[2]]
            });
            let (mut sigma, mut hist, mut q, mut hg) =
                ([0.0; 6], History::default(), 0.0, [0.0; 12]);
            let dt = 1e-7;
            for step in 0..3 {
                let mut f = [[0.0; 3]; 8];
                let r = hex8_step(
                    &x,
                    &v,
                    if step == 0 { 0.0 } else { dt },
                    &steel(),
                    &c,
                    &mut sigma,
                    &mut hist,
                    &mut q,
                    Some(&mut hg),
                    &mut f,
                );
                assert!(r.is_ok());
                let mut again = [[1.0; 3]; 8];
                hex8_corner_forces(&x, &sigma, q, &hg, &mut again).unwrap();
                assert_eq!(again, f, "{hourglass:?}, step {step}");
                if step > 0 {
                    assert!(q > 0.0 && hg.iter().any(|&h| h != 0.0));
                }
                for a in 0..8 {
                    for i in 0..3 {
                        x[a][i] += dt * v[a][i];
                    }
                }
            }
        }
    }

    #[test]
    fn inverted_element_is_reported() {
        let mut x = cube();
        x.swap(0, 6);
        let mut f = [[0.0; 3]; 8];
        let r = hex8_step(
            &x,
            &[[0.0; 3]; 8],
            0.0,
            &steel(),
            &ctl(),
            &mut [0.0; 6],
            &mut History::default(),
            &mut 0.0,
            None,
            &mut f,
        );
        assert_eq!(r, Err(InvertedElement));
    }
}
