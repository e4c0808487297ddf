//! The radial return of von Mises plasticity with isotropic hardening that may depend on the
//! increment itself (hardening, plastic strain rate): Simo and Hughes, Computational
//! Inelasticity (1998), box 3.1. The trial stress's von Mises value q* falls by 3 G d eps_p
//! along the radial return, so the increment solves
//!
//! ```text
//! r(x) = q* - 3 G x - sigma_y(x) = 0,     x = d eps_p in (0, q* / 3G]
//! ```
//!
//! r falls with x (sigma_y does not soften with x here), r(0) > 0 when the trial state yields
//! and r(q* / 3G) < 0: Newton's method, kept inside the bracket by bisection where a step
//! would leave it (slopes unbounded at x = 0: power-law hardening from zero plastic strain,
//! the logarithm of a rate).

use super::update_elastic;
use crate::math::{ddot, deviator, Sym3};

/// The whole update: the elastic trial `sigma += C : d_eps`, and, where its von Mises value
/// exceeds `flow(0).0`, the return to the flow surface. `flow(x)` gives the flow stress and its
/// slope at the plastic increment x. Returns the increment and the flow stress it ends on, or
/// `None` for an elastic step.
#[inline]
pub fn radial_return(
    lambda: f64,
    g: f64,
    sigma: &mut Sym3,
    d_eps: &Sym3,
    flow: impl Fn(f64) -> (f64, f64),
) -> Option<(f64, f64)> {
    update_elastic(lambda, g, sigma, d_eps);
    let s = deviator(sigma);
    let q = (1.5 * ddot(&s, &s)).sqrt();
    if q <= flow(0.0).0 {
        return None;
    }
    let x = plastic_increment(q, g, &flow);
    let y = flow(x).0;
    scale_deviator(sigma, &s, q, y);
    Some((x, y))
}

/// The plastic increment x solving q - 3 G x = flow(x).0, where `flow(x)` gives the flow
/// stress and its slope at the increment x, to 1e-12 of q.
pub fn plastic_increment(q: f64, g: f64, flow: impl Fn(f64) -> (f64, f64)) -> f64 {
    let (mut lo, mut hi) = (0.0, q / (3.0 * g));
    let mut x = 0.5 * hi;
    for _ in 0..100 {
        let (y, slope) = flow(x);
        let r = q - 3.0 * g * x - y;
        if r > 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        if r.abs() <= 1e-12 * q || hi - lo <= 1e-15 * hi {
            break;
        }
        let newton = x + r / (3.0 * g + slope);
        x = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    x
}

/// Returns the trial stress `sigma` (deviator `s`, von Mises value `q`) radially to the von
/// Mises value `y`, keeping its pressure.
pub fn scale_deviator(sigma: &mut Sym3, s: &Sym3, q: f64, y: f64) {
    let scale = y / q;
    let p = (sigma[0] + sigma[1] + sigma[2]) / 3.0;
    for i in 0..3 {
        sigma[i] = p + s[i] * scale;
    }
    for i in 3..6 {
        sigma[i] = s[i] * scale;
    }
}
