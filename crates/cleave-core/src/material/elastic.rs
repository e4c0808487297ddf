//! Isotropic linear elasticity in rate form: d sigma = lambda tr(d eps) I + 2 G d eps.

use crate::math::Sym3;

/// Hypoelastic update: sigma += lambda tr(d_eps) I + 2 G d_eps.
#[inline]
pub fn update_elastic(lambda: f64, g: f64, sigma: &mut Sym3, d_eps: &Sym3) {
    let lt = lambda * (d_eps[0] + d_eps[1] + d_eps[2]);
    let g2 = 2.0 * g;
    sigma[0] += lt + g2 * d_eps[0];
    sigma[1] += lt + g2 * d_eps[1];
    sigma[2] += lt + g2 * d_eps[2];
    sigma[3] += g2 * d_eps[3];
    sigma[4] += g2 * d_eps[4];
    sigma[5] += g2 * d_eps[5];
}
