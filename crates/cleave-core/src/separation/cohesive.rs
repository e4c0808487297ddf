//! The cohesive laws after onset: MODEL 3, the linear softening of Camacho and Ortiz (1996),
//! and MODEL 4, the exponential envelope of Ortiz and Pandolfi (1999). Both are extrinsic here:
//! the interface is rigid until the onset criterion fires at its strength SIGMAX, then opens.
//!
//! Opening of a point pair d = x_b - x_a, split along the current face normal n into
//! dn = d.n and the sliding ds = d - dn n. Effective opening and traction (Ortiz and Pandolfi
//! 1999, eq. 7-9)
//!
//! ```text
//! delta = sqrt(<dn>^2 + BETA^2 |ds|^2)             (compression is left to contact)
//! t     = t_env(delta)                                     loading (delta = delta_max)
//! t     = t_env(delta_max) delta / delta_max               unloading (delta < delta_max)
//! T     = (t / delta) (BETA^2 ds + <dn> n)                 traction pulling b towards a
//! ```
//!
//! Unloading goes back to the origin (irreversible: delta_max never decreases). T . dd = t
//! d delta along any path, so the work of separation per unit area is the area under the
//! envelope, GC, in mode I, in shear and mixed:
//!
//! ```text
//! linear (MODEL 3):       t_env = SIGMAX (1 - delta / delta_c),  delta_c = 2 GC / SIGMAX
//! exponential (MODEL 4):  t_env = SIGMAX (1 + delta / delta_c) exp(-delta / delta_c),
//!                         delta_c = GC / (2 SIGMAX)
//! ```
//!
//! The exponential law is Ortiz and Pandolfi's envelope e SIGMAX (D / delta_c) exp(-D / delta_c)
//! beyond its peak (D = delta_c + delta): their intrinsic law rises from the origin to the peak
//! SIGMAX at D = delta_c, which an extrinsic interface replaces by staying rigid until onset.
//! From the peak on it dissipates 2 SIGMAX delta_c (their law's whole work is e SIGMAX
//! delta_c), hence delta_c = GC / (2 SIGMAX) so that the interface dissipates GC. Its tail
//! never reaches zero: a point counts as fully open at delta = [`EXP_OPEN`] delta_c, where
//! the traction is 8e-5 SIGMAX and the work left out (2 + 12) e^-12 / 2 = 4.3e-5 of GC.
//!
//! In an explicit step the law above is written on an opening shifted by the elastic stretch
//! SIGMAX / k_max of a face of the stiffest slope the step takes ([`stable_slope`],
//! [`CohesiveLaw::traction`]): openings below are measured past that stretch, so "rigid until
//! onset" becomes "as stiff as the step allows", and the law tends to the one above as the
//! step shrinks.
//!
//! That slope bounds the normal secant c = t / delta. Sliding is BETA^2 times stiffer
//! (`T = c (BETA^2 ds + <dn> n)`): at BETA 8, 64 k_max, far past what the step takes, and such a
//! spring rings unstably, its opening alternating in sign and growing until the point opens
//! fully, the last step's work handing energy out. So the solver's step also keeps each
//! softening point's stiffest slope, max(1, BETA^2) c ([`CohesiveLaw::stiffest_slope`]),
//! within the same budget between its nodes' masses
//! ([`super::interfaces::Separation::cohesive_time_step`]): for BETA <= 1 on hexahedra that
//! never binds; at BETA > 1 the step shortens while a face near release slides. On a face,
//! each point opens normally by its own opening and all slide by the face's mean sliding, so
//! the sliding traction that acts at every point is the mean of the points' (the forces are
//! then the gradient of the face's energy: `interfaces.rs`, `face_tractions`).

use crate::math::{add, dot, scale, sub, Vec3};

/// The stiffest slope (Pa/m) a cohesive face between elements of thickness `h` (m, volume
/// over face area) and Young's modulus `young` (Pa) takes in an explicit step of `tssfac`
/// times the elements' own step h / c: E / (2 h TSSFAC^2). A node pair of masses
/// rho A h / 8 joined by a spring of k A / 4 has omega^2 = 4 k / (rho h), so omega dt <= 2 at
/// dt = TSSFAC h / c for k <= rho c^2 / (h TSSFAC^2), at least E / (h TSSFAC^2); half of that
/// leaves room for the elements' own stiffness. As the step shrinks the slope grows and the law
/// tends to the extrinsic one ([`CohesiveLaw::traction`]): at TSSFAC 0.9, 0.62 E / h; at 0.2,
/// 12.5 E / h.
pub fn stable_slope(young: f64, h: f64, tssfac: f64) -> f64 {
    0.5 * young / (h * tssfac * tssfac)
}

/// Where the exponential law counts a point as fully open, in units of its delta_c.
pub const EXP_OPEN: f64 = 12.0;

/// The envelope's shape.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Envelope {
    /// MODEL 3: Camacho and Ortiz's linear softening.
    Linear,
    /// MODEL 4: Ortiz and Pandolfi's exponential envelope beyond its peak.
    Exponential,
}

/// A separation group's cohesive law, all but the strength, which is each interface's own.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct CohesiveParams {
    pub envelope: Envelope,
    /// Shear-to-normal weight BETA.
    pub beta: f64,
    /// Fracture energy GC (J/m^2).
    pub gc: f64,
}

impl CohesiveParams {
    /// The law of a `*MAT_ADD_SEPARATION` MODEL: 3 linear, 4 exponential, `None` for the
    /// models without one.
    pub fn of_model(model: i32, beta: f64, gc: f64) -> Option<Self> {
        let envelope = match model {
            3 => Envelope::Linear,
            4 => Envelope::Exponential,
            _ => return None,
        };
        Some(Self { envelope, beta, gc })
    }

    /// The law of an interface of strength `sigmax` (Pa).
    pub fn law(&self, sigmax: f64) -> CohesiveLaw {
        CohesiveLaw::new(self.envelope, sigmax, self.beta, self.gc)
    }
}

/// Parameters of a cohesive law.
#[derive(serde::Serialize, serde::Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct CohesiveLaw {
    /// Cohesive strength (Pa): the traction at onset.
    pub sigmax: f64,
    /// Shear-to-normal weight.
    pub beta: f64,
    /// Characteristic opening (m): 2 GC / SIGMAX (linear), GC / (2 SIGMAX) (exponential).
    pub delta_c: f64,
    pub envelope: Envelope,
    /// Effective opening at which a point carries no more traction (m).
    delta_open: f64,
}

impl CohesiveLaw {
    /// The law of `envelope` with strength `sigmax`, shear weight `beta` and fracture energy
    /// `gc` (J/m^2).
    pub fn new(envelope: Envelope, sigmax: f64, beta: f64, gc: f64) -> Self {
        let (delta_c, delta_open) = match envelope {
            Envelope::Linear => (2.0 * gc / sigmax, 2.0 * gc / sigmax),
            Envelope::Exponential => (0.5 * gc / sigmax, EXP_OPEN * 0.5 * gc / sigmax),
        };
        Self {
            sigmax,
            beta,
            delta_c,
            envelope,
            delta_open,
        }
    }

    /// The traction on the envelope (Pa) at the effective opening `delta` (m).
    pub fn envelope(&self, delta: f64) -> f64 {
        let x = delta / self.delta_c;
        match self.envelope {
            Envelope::Linear => self.sigmax * (1.0 - x).max(0.0),
            Envelope::Exponential => self.sigmax * (1.0 + x) * (-x).exp(),
        }
    }

    /// Traction T (Pa) pulling side b back towards side a for the opening `d` = x_b - x_a at a
    /// point, with `n` the unit normal from a to b and `t0` the traction at onset
    /// ([`Self::onset_traction`]); `softened` is the point's largest opening past the peak
    /// (m, 0 at onset, updated here).
    ///
    /// The face takes a slope of at most `k_max` (Pa/m, [`stable_slope`]): an extrinsic law's
    /// unloading secant t_env / delta_max grows without bound as delta_max -> 0, more than an
    /// explicit step can take. So the law is written on a shifted opening
    /// `d* = d + (t0n n + t0s / BETA^2) / k_max`, as if the face had stretched elastically by
    /// delta_e = SIGMAX / k_max when it released (the onset traction t0 = k_max times that
    /// stretch, so the traction is continuous at release):
    ///
    /// ```text
    /// delta  = sqrt(<dn*>^2 + BETA^2 |ds*|^2)
    /// delta_max = delta_e + softened,   softened = max over time of (delta - delta_e)
    /// T = (t_env(softened) / delta_max) (BETA^2 ds* + <dn*> n)
    /// ```
    ///
    /// On the envelope (delta = delta_max) |T| follows t_env; below it the face unloads along
    /// the secant to the shifted origin, a linear spring of stiffness c = t_env / delta_max <=
    /// SIGMAX / delta_e = k_max normally and BETA^2 c in sliding (64 k_max at BETA 8, which the
    /// step is shortened for: [`Self::stiffest_slope`]), which is the gradient of a potential (no energy is gained or
    /// lost around a closed path) and goes to zero traction continuously as the face closes:
    /// at the shifted origin, an overlap of up to delta_e, after which contact takes the
    /// compression. (Known limit: at TSSFAC 0.9 a bar whose interfaces break within a few
    /// steps, `cleave bench fragmentation --tssfac 0.9` at 3 eps_dot0 (1, 10, 30 ran),
    /// inverted elements where the law's pull and contact act on the same overlap; at TSSFAC
    /// 0.5 and below it runs, and without contact at 0.9 too.) The work after release is the
    /// envelope's area, GC, as without the shift; a
    /// face that closes all the way gives back the stretch's energy, at most
    /// SIGMAX delta_e / 2 = SIGMAX^2 h / E per unit area with k_max = E / (2 h): h / L0 of GC
    /// for elements of thickness h (5% at 20 elements per cohesive length L0 = E GC / SIGMAX^2).
    ///
    /// (The law this replaces held the onset traction near zero opening and capped the
    /// unloading slope at k_max; its unloading line met zero opening at a traction of up to
    /// SIGMAX that dropped to nothing as the faces overlapped, and faces chattering about zero
    /// opening drew energy out of it: `cleave bench fragmentation` booked 0.72 GC per fully
    /// open area at 3 eps_dot0.) With `k_max` infinite there is no shift: the extrinsic law
    /// itself.
    pub fn traction(&self, d: Vec3, n: Vec3, t0: Vec3, k_max: f64, softened: &mut f64) -> Vec3 {
        let b2 = self.beta * self.beta;
        let delta_e = if k_max.is_finite() {
            self.sigmax / k_max
        } else {
            0.0
        };
        let d = if delta_e > 0.0 {
            let t0n = dot(t0, n);
            let t0s = sub(t0, scale(n, t0n));
            add(
                d,
                scale(add(scale(n, t0n), scale(t0s, 1.0 / b2)), 1.0 / k_max),
            )
        } else {
            d
        };
        let dn = dot(d, n);
        let ds = sub(d, scale(n, dn));
        let dn_plus = dn.max(0.0);
        let delta = (dn_plus * dn_plus + b2 * dot(ds, ds)).sqrt();
        if delta - delta_e > *softened {
            *softened = delta - delta_e;
        }
        let delta_max = delta_e + *softened;
        if delta <= 0.0 || delta_max <= 0.0 || self.is_open(*softened) {
            return [0.0; 3];
        }
        let c = self.envelope(*softened) / delta_max;
        add(scale(ds, b2 * c), scale(n, dn_plus * c))
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

    /// The stiffest slope (Pa/m) a point whose largest opening past the peak is `softened`
    /// takes in any direction under [`Self::traction`] with the slope limit `k_max`: its secant
    /// c = t_env(softened) / (delta_e + softened) <= k_max in the normal direction, BETA^2 c in
    /// the sliding ones (`T = c (BETA^2 ds + <dn> n)`), so max(1, BETA^2) c. On the envelope the
    /// tangent is below the secant, so this bounds every slope of the law at that point until it
    /// softens further (c only falls as `softened` grows). Zero for an open point; infinite
    /// with `k_max` infinite at onset (the extrinsic law's slope is unbounded there).
    ///
    /// [`stable_slope`] bounds c by k_max, but BETA^2 c exceeds it for BETA > 1: at BETA 8 a
    /// sliding point is 64 times stiffer than the step was built for, and its spring rings
    /// unstably (see [`super::interfaces::Separation::cohesive_time_step`]).
    pub fn stiffest_slope(&self, softened: f64, k_max: f64) -> f64 {
        if self.is_open(softened) {
            return 0.0;
        }
        let delta_e = if k_max.is_finite() {
            self.sigmax / k_max
        } else {
            0.0
        };
        let delta_max = delta_e + softened;
        if delta_max <= 0.0 {
            return f64::INFINITY;
        }
        self.beta.powi(2).max(1.0) * self.envelope(softened) / delta_max
    }

    /// The softened opening past the peak at which the law is fully open.
    pub fn delta_open(&self) -> f64 {
        self.delta_open
    }

    /// Whether a point whose largest opening past the peak is `softened` carries no more
    /// traction.
    pub fn is_open(&self, softened: f64) -> bool {
        softened >= self.delta_open
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::norm;

    /// Opening monotonically in pure mode I and integrating T . dd gives GC (the area of the
    /// triangle 1/2 SIGMAX delta_c); with 10^4 steps the trapezoid rule is exact for a linear
    /// law except for the step containing delta_c (error < SIGMAX h / 2 relative 1e-4).
    #[test]
    fn mode_one_work_is_gc() {
        let law = CohesiveLaw::new(Envelope::Linear, 300e6, 1.0, 40.0);
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

    /// The exponential law, opened monotonically along a straight path, in pure mode I and
    /// mixed (opening and sliding with BETA = 2): T . dd integrates to GC (the trapezoid rule
    /// on 2 10^5 steps of a smooth envelope: error 1e-9; the tail past EXP_OPEN delta_c left
    /// out: 4.3e-5), and the point is open at the end, free of traction.
    #[test]
    fn exponential_work_is_gc_in_mode_one_and_mixed() {
        let gc = 40.0;
        for (beta, dir) in [(1.0, [0.0, 0.0, 1.0]), (2.0, [0.0, 0.6, 0.8])] {
            let law = CohesiveLaw::new(Envelope::Exponential, 300e6, beta, gc);
            assert_eq!(law.delta_c, 0.5 * gc / 300e6);
            let n = [0.0, 0.0, 1.0];
            // the path's effective opening per unit length
            let b = (dir[2] * dir[2] + beta * beta * dir[1] * dir[1]).sqrt();
            let steps = 200_000;
            let h = 1.01 * EXP_OPEN * law.delta_c / b / steps as f64;
            let t0 = law.onset_traction(scale(dir, 300e6), n);
            let (mut dmax, mut w) = (0.0, 0.0);
            let mut t_old = t0;
            for k in 1..=steps {
                let s = k as f64 * h;
                let t = law.traction(scale(dir, s), n, t0, f64::INFINITY, &mut dmax);
                w += 0.5 * dot(add(t_old, t), scale(dir, h));
                t_old = t;
            }
            assert!((w - gc).abs() < 1e-4 * gc, "beta {beta}: work {w}");
            assert!(law.is_open(dmax));
            assert_eq!(t_old, [0.0; 3]);
        }
    }

    /// The exponential envelope: SIGMAX at onset with zero slope (a smooth start), 2 e^-1 SIGMAX at delta_c;
    /// unloading from delta_max goes straight back to the origin.
    #[test]
    fn exponential_envelope_and_unloading() {
        let law = CohesiveLaw::new(Envelope::Exponential, 100.0, 1.0, 1.0); // delta_c = 0.005
        assert_eq!(law.envelope(0.0), 100.0);
        assert!((law.envelope(0.005) - 200.0 / std::f64::consts::E).abs() < 1e-12);
        // the secant slope over 1e-9 against the linear law's SIGMAX / delta_c = 2e4: its
        // exact value is -SIGMAX x / (2 delta_c) with x = 2e-7, -0.002
        let slope = (law.envelope(1e-9) - 100.0) / 1e-9;
        assert!(slope.abs() < 1e-6 * 100.0 / 0.005, "slope at onset {slope}");
        let n = [1.0, 0.0, 0.0];
        let mut dmax = 0.0;
        let t1 = law.traction([0.005, 0.0, 0.0], n, T0, f64::INFINITY, &mut dmax)[0];
        assert!((t1 - 200.0 / std::f64::consts::E).abs() < 1e-12);
        let t2 = law.traction([0.002, 0.0, 0.0], n, T0, f64::INFINITY, &mut dmax)[0];
        assert!((t2 - 0.4 * t1).abs() < 1e-12);
        assert_eq!(dmax, 0.005);
    }

    const T0: Vec3 = [100.0, 0.0, 0.0];

    /// At release the traction is the onset traction, whatever its direction (here mixed, with
    /// BETA 2), and a round-off opening in any direction changes it by round-off.
    #[test]
    fn release_keeps_the_onset_traction() {
        let law = CohesiveLaw::new(Envelope::Linear, 100.0, 2.0, 1.0);
        let n = [1.0, 0.0, 0.0];
        let t0 = law.onset_traction([60.0, 80.0, 0.0], n);
        for d in [[0.0; 3], [0.0, 1e-24, 0.0], [-1e-24, 0.0, 1e-24]] {
            let mut soft = 0.0;
            let t = law.traction(d, n, t0, 1e6, &mut soft);
            assert!(
                norm(sub(t, t0)) < 1e-12 * norm(t0),
                "{d:?}: {t:?} vs {t0:?}"
            );
            assert!(soft < 1e-15);
        }
    }

    /// Unloading returns to the origin along the secant, and reloading follows it back to the
    /// envelope without dissipating: the traction at half the largest opening is half the
    /// envelope value there. With a slope limit k_max the origin is shifted by the stretch
    /// SIGMAX / k_max: the traction goes to zero continuously at that overlap, along a secant
    /// no stiffer than k_max.
    #[test]
    fn unloads_towards_origin() {
        let law = CohesiveLaw::new(Envelope::Linear, 100.0, 1.0, 1.0); // delta_c = 0.02
        let n = [1.0, 0.0, 0.0];
        let mut soft = 0.0;
        let t1 = law.traction([0.01, 0.0, 0.0], n, T0, f64::INFINITY, &mut soft)[0];
        assert!((t1 - 50.0).abs() < 1e-12);
        let t2 = law.traction([0.005, 0.0, 0.0], n, T0, f64::INFINITY, &mut soft)[0];
        assert!((t2 - 25.0).abs() < 1e-12);
        assert_eq!(soft, 0.01);
        // compression carries nothing (left to contact)
        assert_eq!(
            law.traction([-0.005, 0.0, 0.0], n, T0, f64::INFINITY, &mut soft),
            [0.0; 3]
        );
        // k_max 2e4: the stretch at release is 0.005; opened by 0.005 more, the envelope gives
        // 100 (1 - 0.005 / 0.02) = 75 at delta_max 0.01
        let (k, mut soft) = (2e4, 0.0);
        let t = |d: f64, soft: &mut f64| law.traction([d, 0.0, 0.0], n, T0, k, soft)[0];
        assert!((t(0.0, &mut soft) - 100.0).abs() < 1e-12);
        assert!((t(0.005, &mut soft) - 75.0).abs() < 1e-9);
        assert_eq!(soft, 0.005);
        // back along the secant 75 / 0.01 = 7500 <= k_max to the shifted origin at -0.005
        assert!((t(0.0, &mut soft) - 37.5).abs() < 1e-9);
        assert!((t(-0.004, &mut soft) - 7.5).abs() < 1e-9);
        assert_eq!(t(-0.005, &mut soft), 0.0);
        assert_eq!(t(-0.006, &mut soft), 0.0);
        // and up again to the envelope, where it softens on
        assert!((t(0.005, &mut soft) - 75.0).abs() < 1e-9);
        assert!((t(0.007, &mut soft) - 100.0 * (1.0 - 0.007 / 0.02)).abs() < 1e-9);
    }

    /// Pure sliding with BETA = 2: delta = 2 |ds| and T = t/delta BETA^2 ds, so |T| = 2 t.
    #[test]
    fn shear_weighting() {
        let law = CohesiveLaw::new(Envelope::Linear, 100.0, 2.0, 1.0);
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
