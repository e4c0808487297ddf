//! Equations of state for the pressure of `*MAT_JOHNSON_COOK` (LS-DYNA Keyword Manual Vol. II,
//! `*EOS_LINEAR_POLYNOMIAL` and `*EOS_GRUNEISEN`). Both are linear in the internal energy:
//!
//! ```text
//! p = A(mu) + B(mu) E,   mu = 1/V - 1,   V = V0 exp(ln J) the relative volume,
//! ```
//!
//! E the internal energy per unit reference volume (E0 at the start).
//!
//! - Linear polynomial: `A = C0 + C1 mu + C2 mu^2 + C3 mu^3`, `B = C4 + C5 mu + C6 mu^2`, the
//!   C2 and C6 terms dropped in tension (mu < 0).
//! - Mie-Gruneisen: in compression
//!   `A = rho0 C^2 mu (1 + (1 - GAMMA0/2) mu - (A/2) mu^2) / (1 - (S1 - 1) mu - S2 mu^2/(mu + 1) - S3 mu^3/(mu + 1)^2)^2`,
//!   in tension `A = rho0 C^2 mu`; `B = GAMMA0 + A mu` (the first-order volume correction A).
//!
//! The update ([`EosState::step`]) books the work of each step into E and solves the energy
//! term implicitly, as LS-DYNA does: with `dV` the change of relative volume and `E*` the energy
//! before the step plus the deviatoric work minus `p_old dV/2`,
//! `p_new = (A + B E*) / (1 + B dV/2)`, `E_new = E* - p_new dV/2` (trapezoidal `-p dV`).

/// An equation of state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Eos {
    /// `*EOS_LINEAR_POLYNOMIAL`: C0..C6 (Pa), E0 (Pa), V0.
    LinearPolynomial { c: [f64; 7], e0: f64, v0: f64 },
    /// `*EOS_GRUNEISEN`: bulk sound speed C (m/s), slopes S1..S3, GAMMA0, the volume correction
    /// A, the reference density rho0 (the material's RO), E0 (Pa), V0.
    Gruneisen {
        c: f64,
        s: [f64; 3],
        gamma0: f64,
        a: f64,
        rho0: f64,
        e0: f64,
        v0: f64,
    },
}

impl Eos {
    /// `(A(mu), B(mu))` of `p = A + B E`.
    pub fn coefficients(&self, mu: f64) -> (f64, f64) {
        match *self {
            Eos::LinearPolynomial { c, .. } => {
                let (c2, c6) = if mu < 0.0 { (0.0, 0.0) } else { (c[2], c[6]) };
                (
                    c[0] + mu * (c[1] + mu * (c2 + mu * c[3])),
                    c[4] + mu * (c[5] + mu * c6),
                )
            }
            Eos::Gruneisen {
                c,
                s,
                gamma0,
                a,
                rho0,
                ..
            } => {
                let k = rho0 * c * c;
                let b = gamma0 + a * mu;
                if mu <= 0.0 {
                    return (k * mu, b);
                }
                let m1 = mu + 1.0;
                let den =
                    1.0 - (s[0] - 1.0) * mu - s[1] * mu * mu / m1 - s[2] * mu * mu * mu / (m1 * m1);
                let num = k * mu * (1.0 + (1.0 - 0.5 * gamma0) * mu - 0.5 * a * mu * mu);
                (num / (den * den), b)
            }
        }
    }

    /// The bulk modulus at the reference state, `dp/dmu` at mu = 0: C1 or rho0 C^2.
    pub fn bulk_modulus(&self) -> f64 {
        match *self {
            Eos::LinearPolynomial { c, .. } => c[1],
            Eos::Gruneisen { c, rho0, .. } => rho0 * c * c,
        }
    }

    /// E0 and V0.
    pub fn initial(&self) -> (f64, f64) {
        match *self {
            Eos::LinearPolynomial { e0, v0, .. } | Eos::Gruneisen { e0, v0, .. } => (e0, v0),
        }
    }

    /// The pressure at relative volume `v` and energy `e` (per reference volume).
    pub fn pressure(&self, v: f64, e: f64) -> f64 {
        let (a, b) = self.coefficients(1.0 / v - 1.0);
        a + b * e
    }
}

/// The EOS part of a material point's history: `ln J` (the log of the volume ratio since the
/// start, so the relative volume is `V0 exp(ln J)`) and the internal energy per unit reference
/// volume less E0.
pub struct EosState<'h> {
    pub ln_j: &'h mut f64,
    pub energy: &'h mut f64,
}

impl EosState<'_> {
    /// One step: the volumetric strain increment `dv` (tr d_eps), the deviatoric work per unit
    /// current volume `w_dev` (s_avg : dev d_eps) and the pressure before the step; returns the
    /// new pressure, updating ln J and the energy.
    pub fn step(&mut self, eos: &Eos, dv: f64, w_dev: f64, p_old: f64) -> f64 {
        let (e0, v0) = eos.initial();
        let v_old = v0 * self.ln_j.exp();
        *self.ln_j += dv;
        let v_new = v0 * self.ln_j.exp();
        let d_v = v_new - v_old;
        let e_star = e0 + *self.energy + 0.5 * (v_old + v_new) * w_dev - 0.5 * p_old * d_v;
        let (a, b) = eos.coefficients(1.0 / v_new - 1.0);
        let p = (a + b * e_star) / (1.0 + 0.5 * b * d_v);
        *self.energy = e_star - 0.5 * p * d_v - e0;
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn copper() -> Eos {
        // OFHC copper (Steinberg): C 3940 m/s, S1 1.489, GAMMA0 2.02, A 0.47
        Eos::Gruneisen {
            c: 3940.0,
            s: [1.489, 0.0, 0.0],
            gamma0: 2.02,
            a: 0.47,
            rho0: 8930.0,
            e0: 0.0,
            v0: 1.0,
        }
    }

    /// The Hugoniot of a linear us-up material: with GAMMA0 = A = 0 the pressure is the
    /// energy-free curve rho0 C^2 mu (1 + mu) / (1 - (S1 - 1) mu)^2, which equals the shock
    /// relation p = rho0 us up with us = C + S1 up, up = us (1 - V) (1e-12 relative).
    #[test]
    fn gruneisen_without_energy_is_the_linear_hugoniot() {
        let (c, s1, rho0) = (3940.0, 1.489, 8930.0);
        let e = Eos::Gruneisen {
            c,
            s: [s1, 0.0, 0.0],
            gamma0: 0.0,
            a: 0.0,
            rho0,
            e0: 0.0,
            v0: 1.0,
        };
        for v in [0.95, 0.9, 0.8, 0.75] {
            // us = C / (1 - S1 (1 - V)), up = us (1 - V)
            let eta = 1.0 - v;
            let us = c / (1.0 - s1 * eta);
            let p_hug = rho0 * us * us * eta;
            let p = e.pressure(v, 0.0);
            assert!((p - p_hug).abs() < 1e-12 * p_hug, "V {v}: {p} vs {p_hug}");
        }
        // tension: linear
        assert!((e.pressure(1.0 / 0.99, 0.0) + rho0 * c * c * 0.01).abs() < 1e-6 * rho0 * c * c);
    }

    /// The energy the steps book is the work -p dV (trapezoid) and the pressure is the EOS of
    /// the energy and volume reached: compress copper by 10% in 1000 steps and back, with
    /// Gruneisen's energy term on; at every step p = A(mu) + B(mu) E (1e-12), and E equals the
    /// running sum of -1/2 (p_old + p_new) dV (1e-12 of the largest E). Back at V = 1 the energy
    /// left is what the cycle dissipated: zero to 1e-6 of its peak (the energy term only makes
    /// the curve path-dependent through E, which returns).
    #[test]
    fn steps_book_the_work_and_follow_the_eos() {
        let eos = copper();
        let (mut ln_j, mut energy) = (0.0f64, 0.0f64);
        let (mut p, mut work, mut peak) = (0.0, 0.0f64, 0.0f64);
        let n = 1000;
        let dv = (0.9f64).ln() / n as f64;
        for k in 0..2 * n {
            let d = if k < n { dv } else { -dv };
            let v_old = ln_j.exp();
            let p_new = EosState {
                ln_j: &mut ln_j,
                energy: &mut energy,
            }
            .step(&eos, d, 0.0, p);
            let v_new = ln_j.exp();
            work -= 0.5 * (p + p_new) * (v_new - v_old);
            p = p_new;
            peak = peak.max(energy);
            let want = eos.pressure(v_new, energy);
            assert!((p - want).abs() <= 1e-12 * want.abs().max(1.0), "{k}");
            assert!((energy - work).abs() <= 1e-12 * peak.max(1.0), "{k}");
        }
        assert!(ln_j.abs() < 1e-12);
        assert!(energy.abs() < 1e-6 * peak, "{energy} of {peak}");
    }

    #[test]
    fn linear_polynomial_drops_c2_and_c6_in_tension() {
        let e = Eos::LinearPolynomial {
            c: [1e5, 1e11, 5e11, 2e11, 0.5, 0.1, 0.3],
            e0: 0.0,
            v0: 1.0,
        };
        let (a, b) = e.coefficients(0.1);
        assert!((a - (1e5 + 1e10 + 5e9 + 2e8)).abs() < 1e-3);
        assert!((b - (0.5 + 0.01 + 0.003)).abs() < 1e-15);
        let (a, b) = e.coefficients(-0.1);
        assert!((a - (1e5 - 1e10 - 2e8)).abs() < 1e-3);
        assert!((b - (0.5 - 0.01)).abs() < 1e-15);
        assert_eq!(e.bulk_modulus(), 1e11);
    }
}
