//! `*MAT_PLASTIC_KINEMATIC`: bilinear von Mises plasticity with mixed hardening.
//!
//! Radial return (Simo and Hughes, Computational Inelasticity, 1998, box 3.2, with mixed
//! hardening as in the LS-DYNA theory manual, material 3):
//! - trial stress sigma* = sigma + C : d_eps, relative stress xi = dev(sigma*) - alpha;
//! - yield function f = sqrt(3/2 xi:xi) - (SIGY + beta Hp eps_p);
//! - if f > 0: d eps_p = f / (3G + Hp), xi is scaled back radially by
//!   (1 - 3G d eps_p / sqrt(3/2 xi:xi)), and alpha += (1 - beta) Hp d eps_p * xi / sqrt(3/2 xi:xi).
//!
//! Hp = E Et / (E - Et) is the plastic modulus, so that in uniaxial stress the slope after
//! yield is the tangent modulus Et (1/Et = 1/E + 1/Hp).

use super::History;
use crate::math::{ddot, Sym3};

/// Radial-return update of `sigma` and `hist` for the strain increment `d_eps`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn update_plastic_kinematic(
    lambda: f64,
    g: f64,
    sigy: f64,
    hp: f64,
    beta: f64,
    sigma: &mut Sym3,
    d_eps: &Sym3,
    hist: &mut History,
) {
    super::update_elastic(lambda, g, sigma, d_eps);
    let p = (sigma[0] + sigma[1] + sigma[2]) / 3.0;
    let a = &hist.back;
    let xi: Sym3 = [
        sigma[0] - p - a[0],
        sigma[1] - p - a[1],
        sigma[2] - p - a[2],
        sigma[3] - a[3],
        sigma[4] - a[4],
        sigma[5] - a[5],
    ];
    let q = (1.5 * ddot(&xi, &xi)).sqrt();
    let sy = sigy + beta * hp * hist.eps_p;
    let f = q - sy;
    if f <= 0.0 {
        return;
    }
    let deps_p = f / (3.0 * g + hp);
    let shrink = 3.0 * g * deps_p / q;
    let dalpha = (1.0 - beta) * hp * deps_p / q;
    for i in 0..6 {
        sigma[i] -= shrink * xi[i];
        hist.back[i] += dalpha * xi[i];
    }
    hist.eps_p += deps_p;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::von_mises;

    /// Uniaxial stress driven by strain increments (lateral strains found by iteration so that
    /// the lateral stresses vanish): the stress-strain curve is bilinear with slope E, then Et.
    #[test]
    fn uniaxial_stress_is_bilinear() {
        let (e, nu, sigy, et) = (200e9, 0.3, 400e6, 20e9);
        let g = e / (2.0 * (1.0 + nu));
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let hp = e * et / (e - et);
        for beta in [0.0, 1.0] {
            let mut s = [0.0; 6];
            let mut h = History::default();
            let deps = 1e-5;
            let n = 600; // total strain 6e-3 = 3 x yield strain
            for _ in 0..n {
                // find lateral increment so that s[1] = s[2] = 0 (secant iteration)
                let mut lat = -nu * deps;
                for _ in 0..50 {
                    let mut s1 = s;
                    let mut h1 = h;
                    update_plastic_kinematic(
                        lambda,
                        g,
                        sigy,
                        hp,
                        beta,
                        &mut s1,
                        &[deps, lat, lat, 0.0, 0.0, 0.0],
                        &mut h1,
                    );
                    // d s_lat / d lat ~ lambda + 2G + lambda ~ bounded; Newton with elastic slope
                    let r = s1[1];
                    if r.abs() < 1e-6 {
                        break;
                    }
                    lat -= r / (2.0 * lambda + 2.0 * g) * 0.9;
                }
                update_plastic_kinematic(
                    lambda,
                    g,
                    sigy,
                    hp,
                    beta,
                    &mut s,
                    &[deps, lat, lat, 0.0, 0.0, 0.0],
                    &mut h,
                );
            }
            let eps = deps * n as f64;
            let expect = sigy + et * (eps - sigy / e);
            assert!(
                (s[0] - expect).abs() / expect < 1e-3,
                "beta {beta}: {} vs {expect}",
                s[0]
            );
            assert!((von_mises(&s) - s[0]).abs() / s[0] < 1e-3);
        }
    }
}
