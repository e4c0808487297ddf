//! Crack length and speed over time, for crack.csv, crack.png and summary.json.
//!
//! - **Origin**: the mean reference position (x0) of the centroids of the interfaces that had
//!   failed at the first output row with any failure (for a notched specimen, the notch tip).
//! - **Length** `L(t)`: the largest distance, in the reference configuration, from the origin
//!   to the centroid of an interface no longer intact. For one crack growing from a notch this
//!   is its length along the (straight) ligament, counted from where it started; with several
//!   cracks it is the reach of the farthest. Reference positions, so the opening and the
//!   beam's bending do not count as growth.
//! - **Thickness axis**: when the model's bounding box is thinner along one axis than half its
//!   size along each of the others (a beam or plate with a through-thickness crack), distances
//!   leave that axis out: a crack front spreading through the thickness is not growth. The
//!   three-point-bend beam (200 x 75 x 25 mm) is measured in its x-y plane; the ball in 3D.
//! - **Speed**: the least-squares slope of L over the rows within the last `window` of time
//!   (crack.csv's `crack_speed`); a crack advances an element row at a time, so the window must
//!   hold several rows' advances (the run uses ENDTIM/30).
//! - **Mean speed** (summary.json): the least-squares slope of L over the rows where L lies
//!   between 10% and 90% of its final value: the growth after the slow start, as the paper
//!   reports it ("about 700 m/s for about 0.1 ms").

use cleave_core::math::{add, norm, scale, sub, Vec3};

/// The crack history of a run.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct CrackGrowth {
    origin: Option<Vec3>,
    /// (t, L) of every row.
    rows: Vec<(f64, f64)>,
    initiation: Option<f64>,
    window: f64,
    /// 1 for the axes distances count, 0 for the thickness axis.
    weights: Vec3,
}

impl CrackGrowth {
    /// Speeds are slopes over the last `window` of time; `thickness`: the axis left out of
    /// distances, if any ([`thickness_axis`]).
    pub fn new(window: f64, thickness: Option<usize>) -> Self {
        let mut weights = [1.0; 3];
        if let Some(a) = thickness {
            weights[a] = 0.0;
        }
        Self {
            window,
            weights,
            ..Default::default()
        }
    }

    /// Record a row at time `t`, given the reference centroids of the failed interfaces;
    /// returns (length, speed).
    pub fn record(&mut self, t: f64, failed: &[Vec3]) -> (f64, f64) {
        if self.origin.is_none() && !failed.is_empty() {
            let sum = failed.iter().fold([0.0; 3], |a, c| add(a, *c));
            self.origin = Some(scale(sum, 1.0 / failed.len() as f64));
            self.initiation = Some(t);
        }
        let w = self.weights;
        let length = self.origin.map_or(0.0, |o| {
            failed
                .iter()
                .map(|c| {
                    let d = sub(*c, o);
                    norm([d[0] * w[0], d[1] * w[1], d[2] * w[2]])
                })
                .fold(0.0, f64::max)
        });
        self.rows.push((t, length));
        // rows are in time order: the window is a tail of them
        let from = t - self.window * (1.0 + 1e-9);
        let start = self.rows.partition_point(|r| r.0 < from);
        (length, slope(&self.rows[start..]).unwrap_or(0.0))
    }

    /// Time of the first row with a failed interface.
    pub fn initiation(&self) -> Option<f64> {
        self.initiation
    }

    /// Mean speed after the slow start (see the module docs); `None` without enough growth.
    pub fn mean_speed(&self) -> Option<f64> {
        let last = self.rows.last()?.1;
        if last <= 0.0 {
            return None;
        }
        let band: Vec<(f64, f64)> = self
            .rows
            .iter()
            .copied()
            .filter(|r| r.1 >= 0.1 * last && r.1 <= 0.9 * last)
            .collect();
        slope(&band)
    }

    /// (t, L) of every row.
    pub fn lengths(&self) -> &[(f64, f64)] {
        &self.rows
    }
}

/// The axis along which the box of `points` is thinner than half its size along each other
/// axis, if there is one.
pub fn thickness_axis<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> Option<usize> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let size: Vec<f64> = (0..3).map(|d| hi[d] - lo[d]).collect();
    (0..3).find(|&a| (0..3).all(|b| b == a || size[a] < 0.5 * size[b]))
}

/// Least-squares slope of y(x); `None` with fewer than 2 distinct x.
pub fn slope(p: &[(f64, f64)]) -> Option<f64> {
    if p.len() < 2 {
        return None;
    }
    let n = p.len() as f64;
    let mx = p.iter().map(|q| q.0).sum::<f64>() / n;
    let my = p.iter().map(|q| q.1).sum::<f64>() / n;
    let sxx: f64 = p.iter().map(|q| (q.0 - mx) * (q.0 - mx)).sum();
    let sxy: f64 = p.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_crack_growing_at_constant_speed_after_a_pause() {
        // starts at t = 1, grows by 0.5 per unit time from t = 3
        let mut g = CrackGrowth::new(2.0, None);
        let mut last = (0.0, 0.0);
        for k in 0..=20 {
            let t = k as f64 * 0.5;
            let failed: Vec<Vec3> = if t < 1.0 {
                vec![]
            } else {
                let l = if t < 3.0 { 0.0 } else { 0.5 * (t - 3.0) };
                vec![[0.0, 0.0, 0.0], [0.0, l, 0.0]]
            };
            last = g.record(t, &failed);
        }
        assert_eq!(g.initiation(), Some(1.0));
        assert!((last.0 - 3.5).abs() < 1e-12);
        assert!((last.1 - 0.5).abs() < 1e-12);
        assert!((g.mean_speed().unwrap() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn spreading_through_the_thickness_is_not_growth() {
        let beam = [[0.0, 0.0, 0.0], [0.2, 0.075, 0.025]];
        assert_eq!(thickness_axis(&beam), Some(2));
        assert_eq!(thickness_axis(&[[0.0; 3], [1.0, 1.0, 0.6]]), None);
        let mut g = CrackGrowth::new(1.0, Some(2));
        g.record(0.0, &[[0.0, 0.025, 0.0]]);
        let (l, _) = g.record(
            1.0,
            &[[0.0, 0.025, 0.0], [0.0, 0.025, 0.01], [0.0, 0.03, 0.0]],
        );
        assert!((l - 0.005).abs() < 1e-15);
    }

    #[test]
    fn no_crack_no_speed() {
        let mut g = CrackGrowth::new(1.0, None);
        assert_eq!(g.record(0.0, &[]), (0.0, 0.0));
        assert_eq!(g.record(1.0, &[]), (0.0, 0.0));
        assert_eq!(g.initiation(), None);
        assert_eq!(g.mean_speed(), None);
        assert_eq!(slope(&[(1.0, 2.0)]), None);
    }
}
