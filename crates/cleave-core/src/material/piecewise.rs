//! `*MAT_PIECEWISE_LINEAR_PLASTICITY` (`*MAT_024`): von Mises plasticity with isotropic
//! hardening given as a piecewise linear curve of yield stress against effective plastic
//! strain, scaled by Cowper and Symonds' rate factor (LS-DYNA Keyword Manual, material 24):
//!
//! ```text
//! sigma_y = h(eps_p) (1 + (eps_dot / C)^(1/P))        (no rate effect when C = 0)
//! ```
//!
//! - h interpolates the points (eps_p, sigma_y), the first at eps_p = 0 (the initial yield
//!   stress); past the last point it goes on with the last segment's slope (LS-DYNA
//!   extrapolates the same way). SIGY and ETAN make the two-point curve of slope
//!   E ETAN / (E - ETAN).
//! - eps_dot is the plastic strain rate, solved for in the return as for Johnson-Cook
//!   ([`super::JohnsonCook`]): LS-DYNA's viscoplastic form (VP 1).
//! - With a table of hardening curves by strain rate (LCSS a `*DEFINE_TABLE`, [`RateTable`])
//!   the yield stress interpolates linearly between the curves of the two rates around
//!   eps_dot (in the natural log of the rate when the table's values are log rates), holds the
//!   first and last curves outside their range, and Cowper-Symonds is not applied (as
//!   LS-DYNA).

use std::sync::Arc;

use super::return_map::radial_return;
use super::History;
use crate::math::Sym3;

/// The hardening curve and rate parameters of `*MAT_024`.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear {
    /// (effective plastic strain, yield stress in Pa), the plastic strains increasing from 0.
    pub points: Arc<[[f64; 2]]>,
    /// Cowper-Symonds C (1/s) and P; C = 0: no rate effect.
    pub c: f64,
    pub p: f64,
    /// The deck curve or table (LCSS) the points came from, if any (the writer refers to it
    /// again).
    pub lcss: Option<i64>,
    /// The hardening curves by strain rate when LCSS is a table (`points` is then its first
    /// curve).
    pub table: Option<Arc<RateTable>>,
}

/// Hardening curves by plastic strain rate (`*DEFINE_TABLE` for `*MAT_024` LCSS).
#[derive(Clone, Debug, PartialEq)]
pub struct RateTable {
    /// The table's values, strictly increasing: strain rates (1/s), or their natural logs
    /// when `log` (LS-DYNA reads a table whose first value is negative so).
    pub values: Vec<f64>,
    pub log: bool,
    /// The curve of each value (deck id, points as `PiecewiseLinear::points`).
    pub curves: Vec<(i64, Arc<[[f64; 2]]>)>,
}

impl RateTable {
    /// The yield stress at plastic strain `eps_p` and rate `rate`, with its slopes in eps_p
    /// and in the rate.
    pub fn hardening(&self, eps_p: f64, rate: f64) -> (f64, f64, f64) {
        let v = &self.values;
        let (at, d_at) = if self.log {
            if rate > 0.0 {
                (rate.ln(), 1.0 / rate)
            } else {
                (f64::NEG_INFINITY, 0.0)
            }
        } else {
            (rate, 1.0)
        };
        let h = |k: usize| hardening_of(&self.curves[k].1, eps_p);
        if v.len() == 1 || at <= v[0] {
            let (y, s) = h(0);
            return (y, s, 0.0);
        }
        if at >= v[v.len() - 1] {
            let (y, s) = h(v.len() - 1);
            return (y, s, 0.0);
        }
        let k = v.partition_point(|&x| x <= at).clamp(1, v.len() - 1);
        let w = (at - v[k - 1]) / (v[k] - v[k - 1]);
        let ((a, sa), (b, sb)) = (h(k - 1), h(k));
        (
            (1.0 - w) * a + w * b,
            (1.0 - w) * sa + w * sb,
            (b - a) / (v[k] - v[k - 1]) * d_at,
        )
    }
}

/// The hardening h(eps_p) of the curve `pts` and its slope: interpolated, extrapolated with
/// the last segment's slope past the end, never below 0.
fn hardening_of(pts: &[[f64; 2]], eps_p: f64) -> (f64, f64) {
    if pts.len() == 1 {
        return (pts[0][1], 0.0);
    }
    // the segment holding eps_p, the last one past the end
    let k = pts
        .partition_point(|p| p[0] <= eps_p)
        .clamp(1, pts.len() - 1);
    let (a, b) = (pts[k - 1], pts[k]);
    let slope = (b[1] - a[1]) / (b[0] - a[0]);
    ((a[1] + slope * (eps_p - a[0])).max(0.0), slope)
}

impl PiecewiseLinear {
    /// The curve of SIGY and ETAN for Young's modulus `young`: slope E ETAN / (E - ETAN).
    pub fn bilinear(sigy: f64, etan: f64, young: f64) -> Vec<[f64; 2]> {
        let hp = if etan > 0.0 && etan < young {
            young * etan / (young - etan)
        } else {
            0.0
        };
        vec![[0.0, sigy], [1.0, sigy + hp]]
    }

    /// Checks a hardening curve: at least one point, the first at plastic strain 0, plastic
    /// strains increasing, yield stresses positive.
    pub fn check(points: &[[f64; 2]]) -> Result<(), String> {
        match points.first() {
            None => return Err("the hardening curve has no points".into()),
            Some(p) if p[0] != 0.0 => {
                return Err(format!(
                    "the hardening curve starts at plastic strain {}: it must start at 0 (the initial yield stress)",
                    p[0]
                ))
            }
            _ => {}
        }
        if let Some(w) = points.windows(2).find(|w| w[1][0] <= w[0][0]) {
            return Err(format!(
                "the plastic strains of the hardening curve must increase ({} after {})",
                w[1][0], w[0][0]
            ));
        }
        if let Some(p) = points.iter().find(|p| p[1].is_nan() || p[1] <= 0.0) {
            return Err(format!(
                "yield stress {} at plastic strain {}: it must be positive",
                p[1], p[0]
            ));
        }
        Ok(())
    }

    /// The hardening h(eps_p) of `points` and its slope.
    pub fn hardening(&self, eps_p: f64) -> (f64, f64) {
        hardening_of(&self.points, eps_p)
    }

    /// The rate factor 1 + (rate / C)^(1/P) and its slope in the rate.
    pub fn rate_factor(&self, rate: f64) -> (f64, f64) {
        if self.c <= 0.0 || rate <= 0.0 {
            return (1.0, 0.0);
        }
        let r = (rate / self.c).powf(1.0 / self.p);
        (1.0 + r, r / (self.p * rate))
    }

    /// The flow stress (Pa) at plastic strain `eps_p` and plastic strain rate `rate` (1/s).
    pub fn flow_stress(&self, eps_p: f64, rate: f64) -> f64 {
        match &self.table {
            Some(t) => t.hardening(eps_p, rate).0,
            None => self.hardening(eps_p).0 * self.rate_factor(rate).0,
        }
    }
}

/// Radial-return update of `sigma` and `hist` for the strain increment `d_eps` over `dt`.
#[inline]
pub fn update_piecewise(
    lambda: f64,
    g: f64,
    law: &PiecewiseLinear,
    sigma: &mut Sym3,
    d_eps: &Sym3,
    dt: f64,
    hist: &mut History,
) {
    let flow = |x: f64| {
        let rate = if dt > 0.0 { x / dt } else { 0.0 };
        let per_dt = if dt > 0.0 { 1.0 / dt } else { 0.0 };
        if let Some(t) = &law.table {
            let (h, h_slope, h_rate) = t.hardening(hist.eps_p + x, rate);
            return (h, h_slope + h_rate * per_dt);
        }
        let (h, h_slope) = law.hardening(hist.eps_p + x);
        let (r, r_slope) = law.rate_factor(rate);
        (h * r, h_slope * r + h * r_slope * per_dt)
    };
    if let Some((x, _)) = radial_return(lambda, g, sigma, d_eps, flow) {
        hist.eps_p += x;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::von_mises;

    fn law(points: Vec<[f64; 2]>, c: f64, p: f64) -> PiecewiseLinear {
        PiecewiseLinear {
            points: points.into(),
            c,
            p,
            lcss: None,
            table: None,
        }
    }

    /// 2000 steps of isochoric stretching at `rate` (steps `dt`) of steel (E 210 GPa, PR 0.3)
    /// with `l`: the von Mises stress, the history, the last step's plastic rate and G.
    fn stretch(l: &PiecewiseLinear, rate: f64, dt: f64) -> (f64, History, f64, f64) {
        let (e, nu) = (210e9, 0.3);
        let g = e / (2.0 * (1.0 + nu));
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let r = rate * dt;
        let d = [r, -0.5 * r, -0.5 * r, 0.0, 0.0, 0.0];
        let (mut s, mut h) = ([0.0; 6], History::default());
        let mut before = 0.0;
        for _ in 0..2000 {
            before = h.eps_p;
            update_piecewise(lambda, g, l, &mut s, &d, dt, &mut h);
        }
        (von_mises(&s), h, (h.eps_p - before) / dt, g)
    }

    /// The curve is interpolated, extrapolated with its last slope past the end, and the
    /// checks name what is wrong.
    #[test]
    fn hardening_curve() {
        let l = law(vec![[0.0, 200e6], [0.1, 300e6], [0.3, 350e6]], 0.0, 1.0);
        assert_eq!(l.hardening(0.0), (200e6, 1e9));
        assert!((l.hardening(0.2).0 - 325e6).abs() < 1e-6);
        assert!((l.hardening(0.5).0 - 400e6).abs() < 1e-6);
        assert!((l.hardening(0.5).1 - 2.5e8).abs() < 1e-6);
        assert!(PiecewiseLinear::check(&[[0.01, 1e8]])
            .unwrap_err()
            .contains("start at 0"));
        assert!(PiecewiseLinear::check(&[[0.0, 1e8], [0.0, 2e8]])
            .unwrap_err()
            .contains("increase"));
        assert!(PiecewiseLinear::check(&[[0.0, 0.0]])
            .unwrap_err()
            .contains("positive"));
        let b = PiecewiseLinear::bilinear(400e6, 100e6, 117e9);
        assert!((b[1][1] - 400e6 - 117e9 * 100e6 / (117e9 - 100e6)).abs() < 1e-3);
    }

    /// Isochoric stretching at 1000/s to an equivalent strain of 0.2 with Cowper-Symonds
    /// C 40.4/s, P 5 (mild steel): the von Mises stress is the curve at the plastic strain
    /// times 1 + (rate / C)^(1/P) at the plastic rate (1e-9), and that rate is the total one
    /// but for the elastic part's share, about the hardening slope over 3G (5e-3; measured
    /// 3.4e-3).
    #[test]
    fn isochoric_stretch_follows_curve_and_rate() {
        let l = law(vec![[0.0, 250e6], [0.05, 320e6], [0.5, 450e6]], 40.4, 5.0);
        let rate = 1e3;
        let (q, h, plastic_rate, g) = stretch(&l, rate, 1e-7);
        assert!((plastic_rate / rate - 1.0).abs() < 5e-3, "{plastic_rate}");
        let expect = l.flow_stress(h.eps_p, plastic_rate);
        assert!((q - expect).abs() < 1e-9 * q, "{q} vs {expect}");
        assert!((h.eps_p + q / (3.0 * g) - 0.2).abs() < 1e-9);
        assert!(l.rate_factor(rate).0 > 1.9, "{:?}", l.rate_factor(rate));
    }

    /// A table of three curves by strain rate: between two values the yield stress is the
    /// linear blend of their curves (in the rate, or in its log for a log table), with the
    /// slopes of that blend; outside the range the end curves hold.
    #[test]
    fn rate_table_interpolates_between_curves() {
        let flat = |y: f64, k: f64| -> Arc<[[f64; 2]]> { vec![[0.0, y], [1.0, y + k]].into() };
        let t = RateTable {
            values: vec![1.0, 11.0, 1011.0],
            log: false,
            curves: vec![
                (1, flat(200e6, 100e6)),
                (2, flat(300e6, 100e6)),
                (3, flat(500e6, 300e6)),
            ],
        };
        // at rate 6 and eps_p 0.5: halfway between 250 and 350 MPa
        let (y, dy, dr) = t.hardening(0.5, 6.0);
        assert!(
            (y - 300e6).abs() < 1e-6 && (dy - 100e6).abs() < 1e-6,
            "{y} {dy}"
        );
        assert!((dr - 1e7).abs() < 1e-6, "{dr}");
        assert_eq!(t.hardening(0.5, 0.1).0, 250e6);
        assert_eq!(t.hardening(0.5, 1e6).0, 650e6);
        let log = RateTable {
            values: vec![0.0, 1000f64.ln()],
            log: true,
            curves: t.curves[..2].to_vec(),
        };
        // rate sqrt(1000): halfway in ln rate
        let (y, _, dr) = log.hardening(0.0, 1000f64.sqrt());
        assert!((y - 250e6).abs() < 1e-3, "{y}");
        assert!(
            (dr - 100e6 / 1000f64.ln() / 1000f64.sqrt()).abs() < 1e-6,
            "{dr}"
        );
    }

    /// Isochoric stretching at 100/s with a table of curves at 1/s and 1000/s (in ln rate): the
    /// von Mises stress is the table's yield stress at the plastic strain and plastic rate
    /// (1e-9), between the two curves.
    #[test]
    fn isochoric_stretch_follows_the_table() {
        let slow: Arc<[[f64; 2]]> = vec![[0.0, 250e6], [0.05, 320e6], [0.5, 450e6]].into();
        let fast: Arc<[[f64; 2]]> = vec![[0.0, 350e6], [0.1, 450e6], [0.5, 600e6]].into();
        let l = PiecewiseLinear {
            table: Some(
                RateTable {
                    values: vec![0.0, 1000f64.ln()],
                    log: true,
                    curves: vec![(1, slow.clone()), (2, fast.clone())],
                }
                .into(),
            ),
            ..law(slow.to_vec(), 0.0, 1.0)
        };
        let (q, h, plastic_rate, _) = stretch(&l, 100.0, 1e-6);
        let expect = l.flow_stress(h.eps_p, plastic_rate);
        assert!((q - expect).abs() < 1e-9 * q, "{q} vs {expect}");
        let (a, b) = (
            hardening_of(&slow, h.eps_p).0,
            hardening_of(&fast, h.eps_p).0,
        );
        let w = plastic_rate.ln() / 1000f64.ln();
        assert!((q - ((1.0 - w) * a + w * b)).abs() < 1e-9 * q);
        assert!(q > a && q < b, "{a} < {q} < {b}");
    }
}
