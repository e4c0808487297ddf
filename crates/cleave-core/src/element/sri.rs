//! The fully integrated, selectively reduced hexahedron (LS-DYNA ELFORM 2): 2 x 2 x 2 Gauss
//! points for the deviatoric response, one mean volume change for the pressure (the B-bar
//! method of Hughes, 1980, "Generalization of selective integration procedures to
//! anisotropic and nonlinear media", IJNME 15). It needs no hourglass control and does not
//! lock in nearly incompressible flow.
//!
//! At each Gauss point g (natural coordinates `+-1/sqrt(3)`, weight 1):
//! - the velocity gradient `L_g = J_v(g) J_mid(g)^-1` at the mid-step geometry, its volume
//!   weight `W_g = det J_mid(g)`;
//! - the mean volumetric rate `tr D_bar = sum_g W_g tr L_g / sum_g W_g` replaces the point's own:
//!   `d_eps_g = (sym L_g + (tr D_bar - tr L_g)/3 I) dt`; Hughes-Winget rotation with the spin of
//!   `L_g`; the material update with the point's own history;
//! - corner forces at x^n, with `s_g` the point's deviator, `p_bar` the volume mean of the
//!   points' pressures and `q` the bulk viscosity (from tr D_bar, as the one-point element):
//!   `f_a = -sum_g W_g s_g b_a(g) + (p_bar + q) sum_g W_g b_a(g)`,
//!   the transpose of the power `sum_g W_g (s_g : D_g - p_g tr D_bar)` the stress update books;
//! - the element's stress for output and interface checks is the volume mean of the points'.
//!
//! Time step: `l_c = V / A_max`, as the one-point hexahedron.

use super::hex8::{jacobian_at, max_face_area};
use super::kernel::{
    hughes_winget, rotate_sym, stable_dt, ElementStep, InvertedElement, KernelControls,
};
use crate::material::{History, SolidParams};
use crate::math::{ddot, det, inverse, mat_mul, Mat3, Sym3, Vec3};

/// The state of an element's 8 Gauss points.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct GaussPoints {
    pub stress: [Sym3; 8],
    pub hist: [History; 8],
}

/// The 8 Gauss points, in the order of the hexahedron's corners.
fn points() -> [[f64; 3]; 8] {
    let g = 1.0 / 3f64.sqrt();
    super::hex8::CORNERS.map(|c| [c[0] * g, c[1] * g, c[2] * g])
}

/// `dN_a/dxi` at natural point `p` (the trilinear shape functions).
fn natural_gradients(p: [f64; 3]) -> [Vec3; 8] {
    super::hex8::CORNERS.map(|s| {
        [
            0.125 * s[0] * (1.0 + s[1] * p[1]) * (1.0 + s[2] * p[2]),
            0.125 * s[1] * (1.0 + s[0] * p[0]) * (1.0 + s[2] * p[2]),
            0.125 * s[2] * (1.0 + s[0] * p[0]) * (1.0 + s[1] * p[1]),
        ]
    })
}

/// Weight `det J` and gradients `b_a = J^-T dN_a/dxi` at natural point `p` of geometry `x`.
fn point_gradients(x: &[Vec3; 8], p: [f64; 3]) -> Option<(f64, [Vec3; 8])> {
    let j = jacobian_at(x, p);
    let d = det(&j);
    if d.is_nan() || d <= 0.0 || !d.is_finite() {
        return None;
    }
    let jinv = inverse(&j)?;
    let dn = natural_gradients(p);
    Some((
        d,
        dn.map(|g| {
            std::array::from_fn(|i| g[0] * jinv[0][i] + g[1] * jinv[1][i] + g[2] * jinv[2][i])
        }),
    ))
}

/// The element phase of one ELFORM 2 hexahedron: the Gauss points' stresses and histories
/// `pts` updated over the previous interval, the mean stress into `sigma`, the corner forces
/// into `f`. Arguments otherwise as [`super::kernel::hex8_step`].
#[allow(clippy::too_many_arguments)]
pub fn sri_step(
    x: &[Vec3; 8],
    v: &[Vec3; 8],
    dt_prev: f64,
    mat: &SolidParams,
    ctl: &KernelControls,
    pts: &mut GaussPoints,
    sigma: &mut Sym3,
    q_prev: &mut f64,
    f: &mut [Vec3; 8],
) -> Result<ElementStep, InvertedElement> {
    let gp = points();
    let mut de_internal = 0.0;
    let mut q = 0.0;
    let mut tr_bar = 0.0;
    let vol_n: f64 = {
        let mut s = 0.0;
        for p in gp {
            s += det(&jacobian_at(x, p));
        }
        s
    };
    if vol_n.is_nan() || vol_n <= 0.0 {
        return Err(InvertedElement);
    }
    let l_vol = crate::math::cbrt(vol_n);
    if dt_prev > 0.0 {
        let xm: [Vec3; 8] =
            std::array::from_fn(|a| std::array::from_fn(|i| x[a][i] - 0.5 * dt_prev * v[a][i]));
        let mut ls = [[[0.0; 3]; 3]; 8];
        let mut ws = [0.0; 8];
        let (mut num, mut den) = (0.0, 0.0);
        for (g, p) in gp.iter().enumerate() {
            let jm = jacobian_at(&xm, *p);
            let w = det(&jm);
            if w.is_nan() || w <= 0.0 {
                return Err(InvertedElement);
            }
            let jminv: Mat3 = inverse(&jm).ok_or(InvertedElement)?;
            let l = mat_mul(&jacobian_at(v, *p), &jminv);
            num += w * (l[0][0] + l[1][1] + l[2][2]);
            den += w;
            ls[g] = l;
            ws[g] = w;
        }
        tr_bar = num / den;
        for g in 0..8 {
            let l = &ls[g];
            let shift = (tr_bar - (l[0][0] + l[1][1] + l[2][2])) / 3.0;
            let d_eps: Sym3 = [
                (l[0][0] + shift) * dt_prev,
                (l[1][1] + shift) * dt_prev,
                (l[2][2] + shift) * dt_prev,
                0.5 * (l[0][1] + l[1][0]) * dt_prev,
                0.5 * (l[1][2] + l[2][1]) * dt_prev,
                0.5 * (l[2][0] + l[0][2]) * dt_prev,
            ];
            let h = 0.25 * dt_prev;
            let w = [
                h * (l[2][1] - l[1][2]),
                h * (l[0][2] - l[2][0]),
                h * (l[1][0] - l[0][1]),
            ];
            let r = hughes_winget(w);
            let s = &mut pts.stress[g];
            let hist = &mut pts.hist[g];
            rotate_sym(&r, s);
            if hist.back != [0.0; 6] {
                rotate_sym(&r, &mut hist.back);
            }
            let old = *s;
            mat.update(s, &d_eps, dt_prev, hist);
            let avg: Sym3 = std::array::from_fn(|i| 0.5 * (old[i] + s[i]));
            de_internal += ws[g] * ddot(&avg, &d_eps);
        }
        if tr_bar < 0.0 {
            q = mat.density
                * l_vol
                * (ctl.q1 * l_vol * tr_bar * tr_bar - ctl.q2 * mat.wave_speed * tr_bar);
        }
        de_internal -= den * 0.5 * (*q_prev + q) * tr_bar * dt_prev;
    }
    *q_prev = q;
    *sigma = corner_forces(x, pts, q, f).ok_or(InvertedElement)?;
    let dt_crit = stable_dt(vol_n / max_face_area(x), mat.step_speed, tr_bar, ctl);
    Ok(ElementStep {
        dt_crit,
        volume: vol_n,
        de_internal,
        de_hourglass: 0.0,
    })
}

/// The corner forces at x^n from the points' stresses and the bulk viscosity `q`
/// (the module's formula); returns the volume-mean stress. `None` if a point is inverted.
fn corner_forces(x: &[Vec3; 8], pts: &GaussPoints, q: f64, f: &mut [Vec3; 8]) -> Option<Sym3> {
    let mut bbar = [[0.0; 3]; 8];
    let mut vol = 0.0;
    let mut p_sum = 0.0;
    let mut mean = [0.0; 6];
    *f = [[0.0; 3]; 8];
    for (g, p) in points().iter().enumerate() {
        let (w, b) = point_gradients(x, *p)?;
        let s = &pts.stress[g];
        let pg = -(s[0] + s[1] + s[2]) / 3.0;
        let dev = [s[0] + pg, s[1] + pg, s[2] + pg, s[3], s[4], s[5]];
        for a in 0..8 {
            let ba = b[a];
            f[a][0] -= w * (dev[0] * ba[0] + dev[3] * ba[1] + dev[5] * ba[2]);
            f[a][1] -= w * (dev[3] * ba[0] + dev[1] * ba[1] + dev[4] * ba[2]);
            f[a][2] -= w * (dev[5] * ba[0] + dev[4] * ba[1] + dev[2] * ba[2]);
            for i in 0..3 {
                bbar[a][i] += w * ba[i];
            }
        }
        vol += w;
        p_sum += w * pg;
        for i in 0..6 {
            mean[i] += w * s[i];
        }
    }
    let p_bar = p_sum / vol;
    for a in 0..8 {
        for i in 0..3 {
            f[a][i] += (p_bar + q) * bbar[a][i];
        }
    }
    Some(mean.map(|m| m / vol))
}

/// The corner forces again from the state the last [`sri_step`] left, bit for bit.
pub fn sri_corner_forces(
    x: &[Vec3; 8],
    pts: &GaussPoints,
    q: f64,
    f: &mut [Vec3; 8],
) -> Result<(), InvertedElement> {
    corner_forces(x, pts, q, f)
        .map(|_| ())
        .ok_or(InvertedElement)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::kernel::tests::steel;
    use crate::model::Hourglass;

    /// The mean gradients `sum_g W_g b_a(g)` of a distorted element are dV/dx_a: they sum to
    /// zero and `sum_a x_a (x) B_a = V I` (1e-14), so a uniform stress gives balanced forces.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn mean_gradients_integrate_the_volume() {
        let mut x: [Vec3; 8] = super::super::hex8::CORNERS.map(|c| c.map(|v| 0.5 * (1.0 + v)));
        x[6] = [1.3, 1.1, 1.2];
        x[1][2] -= 0.1;
        let mut bbar = [[0.0; 3]; 8];
        let mut vol = 0.0;
        for p in points() {
            let (w, b) = point_gradients(&x, p).unwrap();
            vol += w;
            for a in 0..8 {
                for i in 0..3 {
                    bbar[a][i] += w * b[a][i];
                }
            }
        }
        assert!((vol - super::super::hex8::volume(&x)).abs() < 1e-14);
        for i in 0..3 {
            for k in 0..3 {
                let s: f64 = (0..8).map(|a| x[a][i] * bbar[a][k]).sum();
                assert!((s - if i == k { vol } else { 0.0 }).abs() < 1e-14);
            }
        }
    }

    /// One step of a linear velocity field on a distorted element: every point gets the
    /// elastic stress of the (exact, uniform) gradient, and the corner forces are those of that
    /// uniform stress on the mean gradients, summing to zero.
    #[test]
    fn linear_field_gives_uniform_stress() {
        let mat = steel();
        let ctl = KernelControls {
            hourglass: Hourglass::Viscous,
            qh: 0.1,
            q1: 0.0,
            q2: 0.0,
        };
        let mut x: [Vec3; 8] = super::super::hex8::CORNERS.map(|c| c.map(|v| 0.5 * (1.0 + v)));
        x[6] = [1.3, 1.1, 1.2];
        let a = [[1.0, 0.3, -0.2], [0.1, -0.6, 0.25], [0.4, -0.15, 0.5]];
        let v = x.map(|p| crate::math::mat_vec(&a, p));
        let mut pts = GaussPoints::default();
        let (mut sigma, mut q) = ([0.0; 6], 0.0);
        let mut f = [[0.0; 3]; 8];
        sri_step(
            &x, &v, 1e-7, &mat, &ctl, &mut pts, &mut sigma, &mut q, &mut f,
        )
        .unwrap();
        for g in 1..8 {
            for i in 0..6 {
                assert!(
                    (pts.stress[g][i] - pts.stress[0][i]).abs() < 1e-9 * pts.stress[0][0].abs()
                );
            }
        }
        for i in 0..3 {
            let s: f64 = f.iter().map(|fa| fa[i]).sum();
            assert!(s.abs() < 1e-9);
        }
        let mut g = [[0.0; 3]; 8];
        sri_corner_forces(&x, &pts, q, &mut g).unwrap();
        assert_eq!(f, g);
    }
}

/// The ELFORM 2 elements of a model with their Gauss points, and the results of the step's
/// pass over them (done before the coloured pass, which scatters their forces).
#[derive(serde::Serialize, serde::Deserialize, Clone, Debug)]
pub struct SriElements {
    /// The elements, ascending; `pos[e]` is element e's place in the list (`u32::MAX`: not
    /// ELFORM 2).
    elems: Vec<u32>,
    pos: Vec<u32>,
    pub pts: Vec<GaussPoints>,
    /// This step's corner forces and results, per listed element.
    forces: Vec<[Vec3; 8]>,
    results: Vec<Result<ElementStep, InvertedElement>>,
    /// This step's mean stress, bulk viscosity and mean plastic strain, per listed element.
    sigma: Vec<Sym3>,
    q: Vec<f64>,
    eps_p: Vec<f64>,
}

impl SriElements {
    /// For the elements `e` with `sri(e)`; `None` if there are none.
    pub fn new(num_elements: usize, sri: impl Fn(usize) -> bool) -> Option<Self> {
        let elems: Vec<u32> = (0..num_elements)
            .filter(|&e| sri(e))
            .map(|e| e as u32)
            .collect();
        if elems.is_empty() {
            return None;
        }
        let mut pos = vec![u32::MAX; num_elements];
        for (k, &e) in elems.iter().enumerate() {
            pos[e as usize] = k as u32;
        }
        let n = elems.len();
        Some(Self {
            elems,
            pos,
            pts: vec![GaussPoints::default(); n],
            forces: vec![[[0.0; 3]; 8]; n],
            results: vec![Err(InvertedElement); n],
            sigma: vec![[0.0; 6]; n],
            q: vec![0.0; n],
            eps_p: vec![0.0; n],
        })
    }

    /// Element e's place in the list, if it is ELFORM 2.
    #[inline]
    pub fn position(&self, e: usize) -> Option<usize> {
        let k = self.pos[e];
        (k != u32::MAX).then_some(k as usize)
    }

    /// The step of every listed element, in parallel: `corners(e)` gives its positions and
    /// velocities, `params(e)` its material (`None`: skipped, as a rigid element), `q_prev(e)`
    /// its bulk viscosity of the last step. Afterwards [`Self::result`] gives each one's forces.
    pub fn step_all<'p>(
        &mut self,
        corners: impl Fn(usize) -> ([Vec3; 8], [Vec3; 8]) + Sync,
        params: impl Fn(usize) -> Option<&'p SolidParams> + Sync,
        q_prev: impl Fn(usize) -> f64 + Sync,
        dt_prev: f64,
        ctl: impl Fn(usize) -> KernelControls + Sync,
    ) {
        use rayon::prelude::*;
        let Self {
            elems,
            pts,
            forces,
            results,
            sigma,
            q,
            eps_p,
            ..
        } = self;
        elems
            .par_iter()
            .zip(pts.par_iter_mut())
            .zip(forces.par_iter_mut())
            .zip(results.par_iter_mut())
            .zip(sigma.par_iter_mut().zip(q.par_iter_mut()))
            .zip(eps_p.par_iter_mut())
            .for_each(|(((((&e, p), f), r), (s, qe)), ep)| {
                let e = e as usize;
                let Some(mat) = params(e) else {
                    return;
                };
                let (x, v) = corners(e);
                *qe = q_prev(e);
                *r = sri_step(&x, &v, dt_prev, mat, &ctl(e), p, s, qe, f);
                *ep = p.hist.iter().map(|h| h.eps_p).sum::<f64>() / 8.0;
            });
    }

    /// Listed element k's forces, result, mean stress, bulk viscosity and mean plastic strain
    /// (for output) of the step.
    #[inline]
    pub fn result(
        &self,
        k: usize,
    ) -> (
        &[Vec3; 8],
        Result<ElementStep, InvertedElement>,
        Sym3,
        f64,
        f64,
    ) {
        (
            &self.forces[k],
            self.results[k],
            self.sigma[k],
            self.q[k],
            self.eps_p[k],
        )
    }
}
