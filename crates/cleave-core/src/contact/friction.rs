//! Coulomb friction of a contact pair, as LS-DYNA defines it (theory manual, friction in
//! contact; keyword manual, `*CONTACT` card 2 FS, FD, DC).
//!
//! Coefficient: `mu = FD + (FS - FD) exp(-DC |v_rel|)`, with v_rel the tangential relative
//! velocity of the node and the face's contact point.
//!
//! Force: an elastic trial `f* = f_prev - k du_t`, where f_prev is the node's tangential force
//! of the previous step rotated into the current tangent plane (magnitude kept), k the pair's
//! penalty stiffness (`super::surface::FaceTable::pair_stiffness`) and du_t the tangential relative displacement over the step. When
//! `|f*| <= mu |f_n|` the pair sticks and `f_t = f*`; otherwise it slides and
//! `f_t = mu |f_n| f* / |f*|`.

use crate::math::{dot, norm, scale, sub, Vec3};

/// Friction coefficients of a contact definition.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Friction {
    /// Static coefficient FS.
    pub fs: f64,
    /// Dynamic coefficient FD.
    pub fd: f64,
    /// Exponential decay coefficient DC (time per length).
    pub dc: f64,
}

impl Friction {
    /// `mu = FD + (FS - FD) exp(-DC |v_rel|)` at tangential relative speed `speed`.
    #[inline]
    pub fn coefficient(&self, speed: f64) -> f64 {
        self.fd + (self.fs - self.fd) * (-self.dc * speed).exp()
    }

    /// True when FS = FD = 0: no tangential force at all.
    #[inline]
    pub fn is_frictionless(&self) -> bool {
        self.fs == 0.0 && self.fd == 0.0
    }
}

/// The tangential force of a pair this step, and whether it slides.
///
/// `ft_prev`: last step's tangential force on the node (zero when it was not in contact);
/// `n`: current unit normal; `du_t`: tangential relative displacement of the node with respect
/// to the face over the step; `k`: penalty stiffness; `f_max = mu |f_n|`.
#[inline]
pub fn tangential_force(ft_prev: Vec3, n: Vec3, du_t: Vec3, k: f64, f_max: f64) -> (Vec3, bool) {
    let mag = norm(ft_prev);
    let mut p = sub(ft_prev, scale(n, dot(ft_prev, n)));
    let pm = norm(p);
    p = if pm > 0.0 {
        scale(p, mag / pm)
    } else {
        [0.0; 3]
    };
    let trial = sub(p, scale(du_t, k));
    let t = norm(trial);
    if t > f_max {
        let s = if t > 0.0 { f_max / t } else { 0.0 };
        (scale(trial, s), true)
    } else {
        (trial, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// mu = FD + (FS - FD) e^(-DC v): FS at rest, FD when fast, the mean at v = ln 2 / DC.
    #[test]
    fn coefficient_formula() {
        let fr = Friction {
            fs: 0.5,
            fd: 0.3,
            dc: 10.0,
        };
        assert_eq!(fr.coefficient(0.0), 0.5);
        assert!((fr.coefficient(std::f64::consts::LN_2 / 10.0) - 0.4).abs() < 1e-15);
        assert!((fr.coefficient(100.0) - 0.3).abs() < 1e-15);
        let no_decay = Friction { dc: 0.0, ..fr };
        assert_eq!(no_decay.coefficient(100.0), 0.5);
    }

    /// Sticking: the force is the elastic -k du (plus the carried force); sliding: mu |f_n|
    /// against the slip direction.
    #[test]
    fn stick_and_slide() {
        let n = [0.0, 0.0, 1.0];
        let k = 1.0e6;
        let f_max = 0.4 * 200.0; // mu |f_n|
                                 // small slip: sticks, f = -k du
        let (f, slide) = tangential_force([0.0; 3], n, [2e-5, -1e-5, 0.0], k, f_max);
        assert!(!slide);
        assert!((f[0] + 20.0).abs() < 1e-12 && (f[1] - 10.0).abs() < 1e-12);
        // the carried force adds up; still below 80
        let (f2, slide) = tangential_force(f, n, [2e-5, -1e-5, 0.0], k, f_max);
        assert!(!slide && (f2[0] + 40.0).abs() < 1e-12 && (f2[1] - 20.0).abs() < 1e-12);
        // large slip: slides at 80 against the slip
        let (f3, slide) = tangential_force(f2, n, [1e-3, 0.0, 0.0], k, f_max);
        assert!(slide);
        assert!((norm(f3) - 80.0).abs() < 1e-12);
        assert!(f3[0] < 0.0);
    }

    /// The carried force is rotated into the new tangent plane with its magnitude kept.
    #[test]
    fn carried_force_is_rotated() {
        let a: f64 = 0.1;
        let n = [-a.sin(), 0.0, a.cos()]; // the face tilted by 0.1 rad about y
        let (f, slide) = tangential_force([5.0, 0.0, 0.0], n, [0.0; 3], 1.0, 100.0);
        assert!(!slide);
        assert!((norm(f) - 5.0).abs() < 1e-14);
        assert!(dot(f, n).abs() < 1e-14);
    }
}
