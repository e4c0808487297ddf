//! Johnson-Cook plasticity (`*MAT_JOHNSON_COOK`, `*MAT_SIMPLIFIED_JOHNSON_COOK`): von Mises
//! yield with power-law hardening, logarithmic rate sensitivity and thermal softening
//! (Johnson and Cook, 7th International Symposium on Ballistics, 1983):
//!
//! ```text
//! sigma_y = min(A + B eps_p^N, SIGMAX) (1 + C ln(max(eps_dot / EPSO, 1))) (1 - T*^M),
//!           capped at SIGSAT
//! T*      = (T - TR) / (TM - TR), clipped to [0, 1]
//! ```
//!
//! - eps_dot is the plastic strain rate d eps_p / dt of the step, found with d eps_p in the
//!   return (LS-DYNA's viscoplastic form, VP = 1). Below EPSO the rate has no effect. (The
//!   total strain rate of the step, LS-DYNA's VP = 0, is known before the return but follows
//!   every ripple of the motion: one element stretched at 100/s saw its rate factor swing its
//!   flow stress by 2% from step to step, where the plastic rate is smooth.)
//! - T = TR + the adiabatic temperature rise: all the plastic work sigma_y d eps_p of the
//!   material point heats it, d T = sigma_y d eps_p / (RO CP) (no conduction: impacts last
//!   microseconds, heat diffuses over millimetres in seconds). The temperature of the step's
//!   start sets its thermal factor; the step's heat is its flow stress times d eps_p.
//! - Radial return with the hardening and the rate implicit ([`super::return_map`]; the
//!   hardening slope N B eps_p^(N-1) is unbounded at eps_p = 0 for N < 1).
//!
//! Without thermal softening (`t_melt` infinite) and rate (C = 0) it is isotropic power-law
//! hardening.

use super::return_map::radial_return;
use super::{Eos, EosState, History};
use crate::math::Sym3;

/// The Johnson-Cook parameters (SI or any consistent units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JohnsonCook {
    /// Yield stress A, hardening modulus B (Pa), hardening exponent N.
    pub a: f64,
    pub b: f64,
    pub n: f64,
    /// Rate coefficient C and the quasi-static threshold rate EPSO (1/s).
    pub c: f64,
    pub eps0: f64,
    /// Thermal softening exponent M, melting and room temperatures TM, TR (K); TM infinite:
    /// no thermal softening.
    pub m: f64,
    pub t_melt: f64,
    pub t_room: f64,
    /// Heat capacity per unit volume RO CP (J/(m^3 K)); infinite: no heating.
    pub rho_cp: f64,
    /// Cap of the work hardening A + B eps_p^N (SIGMAX of `*MAT_098`), and of the whole flow
    /// stress (SIGSAT); infinite when absent.
    pub sig_max: f64,
    pub sig_sat: f64,
    /// The equation of state of the pressure (`*EOS_...` on the part); `None`: linear
    /// elasticity, `p` from the bulk modulus.
    pub eos: Option<Eos>,
}

impl JohnsonCook {
    /// 4340 steel (Johnson and Cook, Engineering Fracture Mechanics 21, 1985): A 792 MPa,
    /// B 510 MPa, N 0.26, C 0.014 at EPSO 1/s, M 1.03, TM 1793 K, TR 294 K, with RO CP =
    /// 7830 kg/m^3 x 477 J/(kg K); no caps.
    pub const STEEL_4340: JohnsonCook = JohnsonCook {
        a: 792e6,
        b: 510e6,
        n: 0.26,
        c: 0.014,
        eps0: 1.0,
        m: 1.03,
        t_melt: 1793.0,
        t_room: 294.0,
        rho_cp: 7830.0 * 477.0,
        sig_max: f64::INFINITY,
        sig_sat: f64::INFINITY,
        eos: None,
    };

    /// The rate factor 1 + C ln(max(eps_dot / EPSO, 1)).
    pub fn rate_factor(&self, eps_dot: f64) -> f64 {
        if self.c == 0.0 || eps_dot <= self.eps0 {
            1.0
        } else {
            1.0 + self.c * (eps_dot / self.eps0).ln()
        }
    }

    /// The thermal factor 1 - T*^M at the temperature rise `heat` (K) over TR.
    pub fn thermal_factor(&self, heat: f64) -> f64 {
        if !self.t_melt.is_finite() || heat <= 0.0 {
            return 1.0;
        }
        let t_star = (heat / (self.t_melt - self.t_room)).min(1.0);
        1.0 - t_star.powf(self.m)
    }

    /// The work hardening min(A + B eps_p^N, SIGMAX) and its slope in eps_p.
    fn hardening(&self, eps_p: f64) -> (f64, f64) {
        let pow = if eps_p > 0.0 { eps_p.powf(self.n) } else { 0.0 };
        let h = self.a + self.b * pow;
        if h >= self.sig_max {
            return (self.sig_max, 0.0);
        }
        let slope = if eps_p > 0.0 {
            self.n * self.b * pow / eps_p
        } else {
            f64::INFINITY
        };
        (h, slope)
    }

    /// The flow stress (Pa) at plastic strain `eps_p`, strain rate `eps_dot` (1/s) and
    /// temperature rise `heat` (K).
    pub fn flow_stress(&self, eps_p: f64, eps_dot: f64, heat: f64) -> f64 {
        let k = self.rate_factor(eps_dot) * self.thermal_factor(heat);
        (self.hardening(eps_p).0 * k).min(self.sig_sat)
    }
}

/// Radial-return update of `sigma` and `hist` (plastic strain, temperature rise) for the strain
/// increment `d_eps` over the time `dt` (s), with Lame's lambda and the shear modulus `g`.
#[inline]
pub fn update_johnson_cook(
    lambda: f64,
    g: f64,
    jc: &JohnsonCook,
    sigma: &mut Sym3,
    d_eps: &Sym3,
    dt: f64,
    hist: &mut History,
) {
    let theta = jc.thermal_factor(hist.heat);
    // the flow stress and its slope at eps_p + x, with the rate x / dt
    let flow = |x: f64| {
        let (h, h_slope) = jc.hardening(hist.eps_p + x);
        let rate = if dt > 0.0 { x / dt } else { 0.0 };
        let r = jc.rate_factor(rate);
        let r_slope = if r > 1.0 { jc.c / x } else { 0.0 };
        let y = h * r * theta;
        if y >= jc.sig_sat {
            (jc.sig_sat, 0.0)
        } else {
            (y, (h_slope * r + h * r_slope) * theta)
        }
    };
    let Some(eos) = &jc.eos else {
        if let Some((x, y)) = radial_return(lambda, g, sigma, d_eps, flow) {
            book_plastic(jc, hist, x, y);
        }
        return;
    };
    // with an equation of state: the deviator returns on its own, the pressure follows the EOS
    let p_old = -(sigma[0] + sigma[1] + sigma[2]) / 3.0;
    let dv = d_eps[0] + d_eps[1] + d_eps[2];
    let dev_eps = crate::math::deviator(d_eps);
    let old = crate::math::deviator(sigma);
    let mut s = old;
    let plastic = radial_return(0.0, g, &mut s, &dev_eps, flow);
    let avg: Sym3 = std::array::from_fn(|i| 0.5 * (old[i] + s[i]));
    let w_dev = crate::math::ddot(&avg, &dev_eps);
    let p = EosState {
        ln_j: &mut hist.ln_j,
        energy: &mut hist.energy,
    }
    .step(eos, dv, w_dev, p_old);
    *sigma = [s[0] - p, s[1] - p, s[2] - p, s[3], s[4], s[5]];
    if let Some((x, y)) = plastic {
        book_plastic(jc, hist, x, y);
    }
}

/// The heat and plastic strain of a return that took the plastic increment `x` at the flow
/// stress `y`.
#[inline]
fn book_plastic(jc: &JohnsonCook, hist: &mut History, x: f64, y: f64) {
    // the plastic work of the increment, at the flow stress it ends on
    if jc.rho_cp.is_finite() {
        hist.heat += y * x / jc.rho_cp;
    }
    hist.eps_p += x;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::von_mises;

    const E: f64 = 200e9;
    const NU: f64 = 0.3;

    fn lame() -> (f64, f64) {
        let g = E / (2.0 * (1.0 + NU));
        (E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU)), g)
    }

    fn steel() -> JohnsonCook {
        JohnsonCook::STEEL_4340
    }

    /// Isochoric uniaxial straining (d_eps = r (1, -1/2, -1/2)) at 1000/s to an equivalent
    /// strain of 0.2: the von Mises stress after yield is the flow stress at the accumulated
    /// plastic strain, the rate factor of the plastic rate and the thermal factor of the heat
    /// booked (1e-9); plastic plus elastic strain make up the total (1e-9); and the temperature rise
    /// is the plastic work over RO CP, against the ODE dT/d eps_p = sigma_y(eps_p, T) / (RO CP)
    /// integrated on 20,000 midpoint steps (1e-3: the law takes each step's thermal factor at
    /// its start, 2000 steps).
    #[test]
    fn isochoric_stretch_follows_the_flow_stress() {
        let (lambda, g) = lame();
        let jc = steel();
        let (rate, dt) = (1e3, 1e-7);
        let r = rate * dt;
        let d = [r, -0.5 * r, -0.5 * r, 0.0, 0.0, 0.0];
        let (mut s, mut h) = ([0.0; 6], History::default());
        let (mut heat_before, mut eps_p_before) = (0.0, 0.0);
        for _ in 0..2000 {
            (heat_before, eps_p_before) = (h.heat, h.eps_p);
            update_johnson_cook(lambda, g, &jc, &mut s, &d, dt, &mut h);
        }
        // total equivalent strain 0.2, elastic part sigma_y / 3G; the step's thermal factor is
        // that of its start, its rate the plastic one (within 0.1% of the total here)
        let q = von_mises(&s);
        let plastic_rate = (h.eps_p - eps_p_before) / dt;
        assert!((plastic_rate / rate - 1.0).abs() < 1e-3, "{plastic_rate}");
        let expect = jc.flow_stress(h.eps_p, plastic_rate, heat_before);
        assert!((q - expect).abs() < 1e-9 * q, "{q} vs {expect}");
        assert!((h.eps_p + q / (3.0 * g) - 0.2).abs() < 1e-9);
        assert!((jc.rate_factor(rate) - (1.0 + 0.014 * 1e3f64.ln())).abs() < 1e-15);
        // the heat is the plastic work over RO CP: integral of sigma_y d eps_p, here within the
        // trapezoid's error of the flow stress over the small steps (1e-4)
        let (mut work, mut t) = (0.0, 0.0);
        let (steps, total_p) = (20_000, h.eps_p);
        for k in 0..steps {
            let ep = (k as f64 + 0.5) / steps as f64 * total_p;
            work += jc.flow_stress(ep, rate, t) * total_p / steps as f64;
            t = work / jc.rho_cp;
        }
        assert!((h.heat - t).abs() < 1e-3 * t, "heat {} vs {t}", h.heat);
        assert!(h.heat > 10.0, "{}", h.heat);
    }

    /// The rate and thermal factors and the caps of `*MAT_098`.
    #[test]
    fn factors_and_caps() {
        let mut jc = steel();
        assert_eq!(jc.rate_factor(0.5), 1.0);
        assert!(
            (jc.thermal_factor(0.5 * (1793.0 - 294.0)) - (1.0 - 0.5f64.powf(1.03))).abs() < 1e-15
        );
        assert_eq!(jc.thermal_factor(1e4), 0.0);
        jc.sig_max = 1000e6;
        assert_eq!(jc.flow_stress(1.0, 0.0, 0.0), 1000e6);
        jc.sig_sat = 900e6;
        assert_eq!(jc.flow_stress(1.0, 1e6, 0.0), 900e6);
    }

    /// A purely elastic step leaves the history alone; a step that yields lands on the flow
    /// surface even from the steep start of N < 1 hardening (eps_p = 0).
    #[test]
    fn first_yield_lands_on_the_surface() {
        let (lambda, g) = lame();
        let mut jc = steel();
        jc.c = 0.0;
        jc.t_melt = f64::INFINITY;
        jc.rho_cp = f64::INFINITY;
        let mut s = [0.0; 6];
        let mut h = History::default();
        update_johnson_cook(
            lambda,
            g,
            &jc,
            &mut s,
            &[1e-3, -5e-4, -5e-4, 0.0, 0.0, 0.0],
            1e-6,
            &mut h,
        );
        assert_eq!(h, History::default());
        update_johnson_cook(
            lambda,
            g,
            &jc,
            &mut s,
            &[1e-2, -5e-3, -5e-3, 0.0, 0.0, 0.0],
            1e-6,
            &mut h,
        );
        let q = von_mises(&s);
        assert!(h.eps_p > 0.0);
        assert!((q - (jc.a + jc.b * h.eps_p.powf(jc.n))).abs() < 1e-9 * q);
        assert!(
            (q / (3.0 * g) + h.eps_p - 1.1e-2).abs() < 1e-12,
            "consistency"
        );
        assert_eq!(h.heat, 0.0);
    }

    /// Uniaxial strain (a plate impact's state: d_eps = (-r, 0, 0) dt) of 4340 steel with a
    /// Mie-Gruneisen EOS, to 20% compression in 4000 steps:
    /// - without the energy term (GAMMA0 = A = 0) the pressure is the EOS's curve at the
    ///   volume reached, rho0 C^2 eta / (1 - S1 eta)^2 with eta = 1 - V (1e-9), and the
    ///   deviator is on the flow surface (von Mises = the flow stress, 1e-9);
    /// - with GAMMA0 = 1.67 the energy the history books is the work of the stress, the running
    ///   sum of J_mid sigma_avg : d_eps (trapezoid, J = V/V_start) to 1e-9 of it, and the
    ///   pressure is the EOS at that energy and volume (1e-9).
    #[test]
    fn uniaxial_strain_follows_the_gruneisen_eos() {
        let (lambda, g) = lame();
        for gamma0 in [0.0, 1.67] {
            let eos = Eos::Gruneisen {
                c: 4578.0,
                s: [1.33, 0.0, 0.0],
                gamma0,
                a: 0.0,
                rho0: 7830.0,
                e0: 0.0,
                v0: 1.0,
            };
            // no rate or heat: the flow stress is the hardening curve's
            let jc = JohnsonCook {
                eos: Some(eos),
                rho_cp: f64::INFINITY,
                c: 0.0,
                ..steel()
            };
            let n = 4000;
            let de = (0.8f64).ln() / n as f64; // tr d_eps per step (log strain)
            let (mut s, mut h, mut work) = ([0.0; 6], History::default(), 0.0);
            for _ in 0..n {
                let old = s;
                let j_old = h.ln_j.exp();
                let d = [de, 0.0, 0.0, 0.0, 0.0, 0.0];
                update_johnson_cook(lambda, g, &jc, &mut s, &d, 1e-7, &mut h);
                let j_mid = 0.5 * (j_old + h.ln_j.exp());
                work += j_mid * 0.5 * (old[0] + s[0]) * de;
            }
            let v = h.ln_j.exp();
            assert!((v - 0.8).abs() < 1e-12);
            let p = -(s[0] + s[1] + s[2]) / 3.0;
            let q = von_mises(&s);
            let flow = jc.flow_stress(h.eps_p, 0.0, 0.0);
            assert!((q - flow).abs() < 1e-9 * q, "{q} vs {flow}");
            if gamma0 == 0.0 {
                let eta = 1.0 - v;
                let want = 7830.0 * 4578.0f64.powi(2) * eta / (1.0 - 1.33 * eta).powi(2);
                assert!((p - want).abs() < 1e-9 * want, "{p} vs {want}");
            } else {
                assert!(
                    (h.energy - work).abs() < 1e-9 * work,
                    "{} vs {work}",
                    h.energy
                );
                let want = eos.pressure(v, h.energy);
                assert!((p - want).abs() < 1e-9 * want, "{p} vs {want}");
            }
        }
    }
}
