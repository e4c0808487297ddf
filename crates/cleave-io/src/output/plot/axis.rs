//! Axis ranges that survive degenerate data, and tick labels that stay short.

/// A plotted range of values and how to label its ticks.
///
/// plotters draws in *chart units*, the values divided by `scale`, a power of ten that brings
/// the range's magnitude into [1, 10): its tick placement fails for magnitudes far from 1 (a
/// range around 1e-30 gets a single tick). Labels convert back to true values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Axis {
    pub lo: f64,
    pub hi: f64,
    scale: f64,
}

/// Largest magnitude kept for a range, so `hi - lo` never overflows.
const LIMIT: f64 = 1e300;

impl Axis {
    /// The range `lo..hi` (true values, `lo < hi`).
    pub fn new(lo: f64, hi: f64) -> Axis {
        let magnitude = lo.abs().max(hi.abs());
        let scale = if magnitude.is_normal() {
            10f64.powi(magnitude.log10().floor() as i32)
        } else {
            1.0
        };
        Axis { lo, hi, scale }
    }

    /// The range plotters draws in, in chart units.
    pub fn chart_range(&self) -> std::ops::Range<f64> {
        self.lo / self.scale..self.hi / self.scale
    }

    /// The chart coordinate of the true value `v`.
    pub fn chart_of(&self, v: f64) -> f64 {
        v / self.scale
    }

    /// The true value at chart coordinate `c`.
    pub fn value(&self, c: f64) -> f64 {
        c * self.scale
    }

    /// The tick label at chart coordinate `c` (see [`Axis::label_value`]).
    pub fn label(&self, c: f64) -> String {
        self.label_value(self.value(c))
    }

    /// The range of the finite `values`, widened by `pad` (a fraction of the span) on each side.
    /// No value gives [0, 1]; a single value (or a span below 1e-12 of the magnitude) gives
    /// that value +- 5 % (+- 1 for zero).
    pub fn fit(values: impl IntoIterator<Item = f64>, pad: f64) -> Axis {
        let (lo, hi) = values
            .into_iter()
            .filter(|v| v.is_finite())
            .map(|v| v.clamp(-LIMIT, LIMIT))
            .fold(None, |acc: Option<(f64, f64)>, v| match acc {
                None => Some((v, v)),
                Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
            })
            .unwrap_or((0.0, 1.0));
        let magnitude = lo.abs().max(hi.abs());
        if hi - lo <= 1e-12 * magnitude {
            let half = if magnitude > 0.0 {
                0.05 * magnitude
            } else {
                1.0
            };
            let mid = 0.5 * (lo + hi);
            return Axis::new(mid - half, mid + half);
        }
        let margin = pad * (hi - lo);
        Axis::new(lo - margin, hi + margin)
    }

    /// The tick label of the true value `v`: decimal, or scientific (`1.25e-4`) when the axis magnitude is below
    /// 1e-3 or at least 1e5, with enough decimals for ticks a twentieth of the span apart (more
    /// than plotters' spacing, so neighbours never look alike) and trailing zeros removed.
    pub fn label_value(&self, v: f64) -> String {
        let step = (self.hi - self.lo) / 20.0;
        let step_exp = step.log10().floor() as i32;
        if v.abs() < 1e-9 * step {
            return "0".to_string();
        }
        let magnitude = self.lo.abs().max(self.hi.abs());
        if (1e-3..1e5).contains(&magnitude) {
            let decimals = (-step_exp).clamp(0, 10) as usize;
            trim_zeros(&format!("{v:.decimals$}"))
        } else {
            let v_exp = v.abs().log10().floor() as i32;
            let decimals = (v_exp - step_exp).clamp(0, 12) as usize;
            trim_zeros(&format!("{v:.decimals$e}"))
        }
    }
}

impl Axis {
    /// How many tick labels fit along `pixels` of a horizontal axis without overlapping
    /// (labels of an offset range such as 1e9 .. 1e9 + 100 are long): between 2 and 10.
    pub fn labels_fitting(&self, pixels: u32) -> usize {
        let mid = 0.5 * (self.lo + self.hi) + 0.013 * (self.hi - self.lo);
        let chars = [self.lo, mid, self.hi]
            .iter()
            .map(|&v| self.label_value(v).len())
            .max()
            .unwrap_or(1);
        // DejaVu Sans at 18 px: about 11 px per character, plus a gap of 3 characters.
        (pixels as usize / ((chars + 3) * 11)).clamp(2, 10)
    }
}

/// `text` (a decimal or scientific number) without trailing zeros after its decimal point.
fn trim_zeros(text: &str) -> String {
    let (mantissa, exp) = match text.split_once('e') {
        Some((m, e)) => (m, Some(e)),
        None => (text, None),
    };
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.')
    } else {
        mantissa
    };
    match exp {
        Some(e) => format!("{mantissa}e{e}"),
        None => mantissa.to_string(),
    }
}

/// `v` in scientific notation with at most 3 significant digits and no trailing zeros
/// (`2e-3`, `3.16e2`), for logarithmic axes.
pub(super) fn short_sci(v: f64) -> String {
    trim_zeros(&format!("{v:.2e}"))
}

#[cfg(test)]
mod tests {
    use super::{short_sci, Axis};

    #[test]
    fn degenerate_ranges_are_widened() {
        assert_eq!(Axis::fit([], 0.0), Axis::new(0.0, 1.0));
        assert_eq!(Axis::fit([0.0, 0.0], 0.1), Axis::new(-1.0, 1.0));
        let a = Axis::fit([f64::NAN, 10.0, f64::INFINITY], 0.0);
        assert!((a.lo - 9.5).abs() < 1e-12 && (a.hi - 10.5).abs() < 1e-12);
        let c = Axis::fit([1e-30, 3e-30], 0.0);
        let r = c.chart_range();
        assert!((r.start - 1.0).abs() < 1e-12 && (r.end - 3.0).abs() < 1e-12);
        assert_eq!(c.label(2.0), "2e-30");
        assert_eq!(c.value(c.chart_of(2.5e-30)), 2.5e-30);
        let b = Axis::fit([-1e308, 1e308], 0.05);
        assert!(b.lo.is_finite() && b.hi.is_finite() && b.lo < b.hi);
    }

    #[test]
    fn labels_are_short() {
        let a = Axis::new(0.0, 1.0);
        assert_eq!(a.label_value(0.3), "0.3");
        assert_eq!(a.label_value(0.5), "0.5");
        let t = Axis::new(0.0, 2e-4);
        assert_eq!(t.label_value(1.2e-4), "1.2e-4");
        assert_eq!(t.label_value(1e-4), "1e-4");
        let ms = Axis::new(0.0, 1e-3);
        assert_eq!(ms.label_value(1e-3), "0.001");
        assert_eq!(ms.label_value(2.5e-4), "0.00025");
        assert_eq!(t.label_value(1e-20), "0");
        let e = Axis::new(1.0e9, 1.2e9);
        assert_eq!(e.label_value(1.02e9), "1.02e9");
        let d = Axis::new(0.0, 300.0);
        assert_eq!(d.label_value(150.0), "150");
        assert_eq!(d.label_value(15.0), "15");
        assert_eq!(short_sci(0.002), "2e-3");
        assert_eq!(a.labels_fitting(800), 10);
        let offset = Axis::new(1e9, 1e9 + 100.0);
        assert!(offset.labels_fitting(800) < 6);
        assert_eq!(short_sci(316.2), "3.16e2");
    }
}
