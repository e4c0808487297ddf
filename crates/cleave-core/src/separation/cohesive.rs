//! MODEL 3 after onset: the linear-softening cohesive law of Camacho and Ortiz (1996), an
//! extrinsic law (the interface is rigid until the onset criterion fires, then opens).
//!
//! Opening of a point pair d = x_b - x_a, split along the current face normal n into
//! dn = d.n and the sliding ds = d - dn n. Effective opening and traction
//!
//! ```text
//! delta = sqrt(<dn>^2 + BETA^2 |ds|^2)             (compression is left to contact)
//! t     = SIGMAX (1 - delta_max / delta_c) delta / delta_max   unloading (delta < delta_max)
//! t     = SIGMAX (1 - delta / delta_c)                        loading (delta = delta_max)
//! T     = (t / delta) (BETA^2 ds + <dn> n)                    traction pulling b towards a
//! ```
//!
//! with delta_c = 2 GC / SIGMAX, so the work of separation per unit area is 1/2 SIGMAX delta_c
//! = GC; unloading goes back to the origin (irreversible: delta_max never decreases). A point
//! is fully open when delta_max >= delta_c.

use crate::math::{add, dot, scale, sub, Vec3};

/// Openings below this fraction of delta_c count as closed (the onset traction holds); the
/// work this leaves out is below CLOSED of GC.
pub const CLOSED: f64 = 1e-4;

/// The largest unloading slope (Pa/m) a face between elements of thickness `h` (m, volume over
/// face area) and Young's modulus `young` (Pa) can take in an explicit step: E / (2 h), half
/// the axial stiffness of the thinner element per unit area. (A node pair of masses
/// rho A h / 8 joined by a spring of k A / 4 stays below omega dt = 2 at the elements' own step
/// h / c for k up to about 1.2 E / h.)
pub fn stable_slope(young: f64, h: f64) -> f64 {
    0.5 * young / h
}

/// Parameters of the law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearSoftening {
    /// Cohesive strength (Pa): the traction at onset.
    pub sigmax: f64,
    /// Shear-to-normal weight.
    pub beta: f64,
    /// Critical opening delta_c = 2 GC / SIGMAX (m).
    pub delta_c: f64,
}

impl LinearSoftening {
    /// The law with strength `sigmax`, shear weight `beta` and fracture energy `gc` (J/m^2).
    pub fn new(sigmax: f64, beta: f64, gc: f64) -> Self {
        Self {
            sigmax,
            beta,
            delta_c: 2.0 * gc / sigmax,
        }
    }

    /// Traction T (Pa) pulling side b back towards side a for the opening `d` = x_b - x_a at a
    /// point, with `n` the unit normal from a to b; updates the point's largest effective
    /// opening `delta_max`. `t0` is the traction at onset ([`Self::onset_traction`]): while the
    /// point has opened less than [`CLOSED`] delta_c, T = t0. (The law's direction
    /// (BETA^2 ds + dn n) / delta is undefined at zero opening: a round-off opening of 1e-24 m
    /// would otherwise get the full strength in a random direction.)
    ///
    /// `k_max` (Pa/m) caps the unloading slope: below the envelope
    /// t = max(0, t_env(delta_max) - s (delta_max - delta)) with s = min(t_env / delta_max,
    /// k_max). Unloading towards the origin has the secant slope t_env / delta_max, which grows
    /// without bound as delta_max -> 0 and would make the explicit step unstable for a face that
    /// closes just after onset; the cap (see [`stable_slope`]) only acts while delta_max is
    /// below about SIGMAX / k_max, and the law stays dissipative. The same cap bounds the
    /// secant stiffness t / delta of the sliding part, which is as unbounded when the face has
    /// barely opened.
    pub fn traction(&self, d: Vec3, n: Vec3, t0: Vec3, k_max: f64, delta_max: &mut f64) -> Vec3 {
        let dn = dot(d, n);
        let ds = sub(d, scale(n, dn));
        let dn_plus = dn.max(0.0);
        let b2 = self.beta * self.beta;
        let delta = (dn_plus * dn_plus + b2 * dot(ds, ds)).sqrt();
        if delta > *delta_max {
            *delta_max = delta;
        }
        if *delta_max < CLOSED * self.delta_c {
            // closing faces are left to contact: drop a tensile normal part
            let t0n = dot(t0, n);
            return if dn < 0.0 && t0n > 0.0 {
                sub(t0, scale(n, t0n))
            } else {
                t0
            };
        }
        if delta <= 0.0 || *delta_max >= self.delta_c {
            return [0.0; 3];
        }
        // on the envelope when delta = delta_max; below it, back towards the origin
        let t_env = self.sigmax * (1.0 - *delta_max / self.delta_c);
        let slope = (t_env / *delta_max).min(k_max);
        let t = (t_env - slope * (*delta_max - delta)).max(0.0);
        // the sliding part's secant stiffness t / delta is capped like the unloading slope
        let ks = (t / delta).min(k_max);
        add(scale(ds, b2 * ks), scale(n, dn_plus * t / delta))
    }

    /// The law's traction at zero opening for a face whose traction at onset was `t` (normal
    /// `n`): compression dropped, then scaled to the effective strength,
    /// `sqrt(<tn>^2 + |ts|^2 / BETA^2) = SIGMAX`. Used until the face starts to open, so the
    /// faces feel no jump in traction at release.
    pub fn onset_traction(&self, t: Vec3, n: Vec3) -> Vec3 {
        let tn = dot(t, n);
        let ts = sub(t, scale(n, tn));
        let tn = tn.max(0.0);
        let eff = (tn * tn + dot(ts, ts) / (self.beta * self.beta)).sqrt();
        if eff <= 0.0 {
            return [0.0; 3];
        }
        scale(add(ts, scale(n, tn)), self.sigmax / eff)
    }

    /// Whether a point with largest opening `delta_max` carries no more traction.
    pub fn is_open(&self, delta_max: f64) -> bool {
        delta_max >= self.delta_c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Opening monotonically in pure mode I and integrating T . dd gives GC (the area of the
    /// triangle 1/2 SIGMAX delta_c); with 10^4 steps the trapezoid rule is exact for a linear
    /// law except for the step containing delta_c (error < SIGMAX h / 2 relative 1e-4).
    #[test]
    fn mode_one_work_is_gc() {
        let law = LinearSoftening::new(300e6, 1.0, 40.0);
        let n = [0.0, 0.0, 1.0];
        let steps = 10_000;
        let h = 1.2 * law.delta_c / steps as f64;
        let (mut dmax, mut w, mut t_old) = (0.0, 0.0, 300e6);
        for k in 1..=steps {
            let t = law.traction(
                [0.0, 0.0, k as f64 * h],
                n,
                [0.0, 0.0, 300e6],
                f64::INFINITY,
                &mut dmax,
            )[2];
            w += 0.5 * (t_old + t) * h;
            t_old = t;
        }
        assert!((w - 40.0).abs() < 2e-4 * 40.0, "work {w}");
        assert!(law.is_open(dmax));
    }

    const T0: Vec3 = [100.0, 0.0, 0.0];

    /// A round-off opening in any direction keeps the onset traction.
    #[test]
    fn closed_point_keeps_the_onset_traction() {
        let law = LinearSoftening::new(100.0, 1.0, 1.0);
        let mut dmax = 0.0;
        let t = law.traction(
            [0.0, 1e-24, 0.0],
            [1.0, 0.0, 0.0],
            T0,
            f64::INFINITY,
            &mut dmax,
        );
        assert_eq!(t, T0);
    }

    /// Unloading returns to the origin along the secant, and reloading follows it back to the
    /// envelope without dissipating: the traction at half the largest opening is half the
    /// envelope value there.
    #[test]
    fn unloads_towards_origin() {
        let law = LinearSoftening::new(100.0, 1.0, 1.0); // delta_c = 0.02
        let n = [1.0, 0.0, 0.0];
        let mut dmax = 0.0;
        let t1 = law.traction([0.01, 0.0, 0.0], n, T0, f64::INFINITY, &mut dmax)[0];
        assert!((t1 - 50.0).abs() < 1e-12);
        let t2 = law.traction([0.005, 0.0, 0.0], n, T0, f64::INFINITY, &mut dmax)[0];
        assert!((t2 - 25.0).abs() < 1e-12);
        assert_eq!(dmax, 0.01);
        // a capped slope unloads along it from the envelope value 50 at delta_max = 0.01
        let mut dm = 0.01;
        let t3 = law.traction([0.0095, 0.0, 0.0], n, T0, 1000.0, &mut dm)[0];
        assert!((t3 - (50.0 - 1000.0 * 0.0005)).abs() < 1e-9, "{t3}");
        // compression carries nothing (left to contact)
        assert_eq!(
            law.traction([-0.005, 0.0, 0.0], n, T0, f64::INFINITY, &mut dmax),
            [0.0; 3]
        );
    }

    /// Pure sliding with BETA = 2: delta = 2 |ds| and T = t/delta BETA^2 ds, so |T| = 2 t.
    #[test]
    fn shear_weighting() {
        let law = LinearSoftening::new(100.0, 2.0, 1.0);
        let mut dmax = 0.0;
        let t = law.traction(
            [0.0, 0.005, 0.0],
            [1.0, 0.0, 0.0],
            [100.0, 0.0, 0.0],
            f64::INFINITY,
            &mut dmax,
        );
        assert!((dmax - 0.01).abs() < 1e-15);
        let env = 100.0 * (1.0 - 0.01 / 0.02);
        assert!((t[1] - 2.0 * env).abs() < 1e-9 && t[0] == 0.0);
    }
}
