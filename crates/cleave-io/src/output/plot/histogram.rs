//! Histograms of a sample (e.g. fragment masses), on a linear or logarithmic x axis.

use super::axis::{short_sci, Axis};
use super::{color, draw_error, font, PlotError, FONT, PLOT_WIDTH, SIZE};
use plotters::prelude::*;
use std::path::Path;

/// Plots a histogram of `values` with `bins` equal-width bins into the PNG at `path`.
///
/// The bins span the finite values (a single or constant value gets a range around it); with
/// `log_x` the bins are equal in log10 of the value, the x axis is logarithmic, and values
/// that are not positive are left out (their count is added to the title). `bins == 0` picks
/// ceil(sqrt(n)) bins. Non-finite values are skipped. See [the module page](super) for the
/// image format.
pub fn plot_histogram(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    values: &[f64],
    bins: usize,
    log_x: bool,
) -> Result<(), PlotError> {
    font::ensure()?;
    let err = draw_error(path);
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    // Work in log10 space on a log axis: bins and ticks are equal there.
    let sample: Vec<f64> = if log_x {
        finite
            .iter()
            .filter(|&&v| v > 0.0)
            .map(|v| v.log10())
            .collect()
    } else {
        finite.clone()
    };
    let left_out = finite.len() - sample.len();
    let bins = if bins == 0 {
        ((sample.len() as f64).sqrt().ceil() as usize).max(1)
    } else {
        bins
    };
    let x = Axis::fit(sample.iter().copied(), 0.0);
    let counts = count(&sample, x, bins);
    let top = counts.iter().copied().max().unwrap_or(0).max(1) as f64 * 1.1;
    let y = Axis::new(0.0, top);

    let caption = if left_out > 0 {
        format!("{title} ({left_out} values <= 0 not shown)")
    } else {
        title.to_string()
    };
    let x_desc = if log_x {
        format!("{x_label} (log scale)")
    } else {
        x_label.to_string()
    };
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, (FONT, 28))
        .margin(20)
        .margin_right(50)
        .x_label_area_size(70)
        .y_label_area_size(120)
        .build_cartesian_2d(x.chart_range(), y.chart_range())
        .map_err(&err)?;
    let x_tick = |v: &f64| {
        if log_x {
            short_sci(10f64.powf(x.value(*v)))
        } else {
            x.label(*v)
        }
    };
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_label)
        .x_labels(if log_x {
            10
        } else {
            x.labels_fitting(PLOT_WIDTH)
        })
        .x_label_formatter(&x_tick)
        .y_label_formatter(&|v| y.label(*v))
        .label_style((FONT, 18))
        .axis_desc_style((FONT, 22))
        .draw()
        .map_err(&err)?;
    let width = (x.hi - x.lo) / bins as f64;
    let c = color(0);
    let bar = |k: usize, n: usize| {
        let a = x.lo + k as f64 * width;
        [
            (x.chart_of(a), 0.0),
            (x.chart_of(a + width), y.chart_of(n as f64)),
        ]
    };
    let nonzero = || counts.iter().enumerate().filter(|(_, &n)| n > 0);
    chart
        .draw_series(nonzero().map(|(k, &n)| Rectangle::new(bar(k, n), c.mix(0.6).filled())))
        .map_err(&err)?;
    chart
        .draw_series(nonzero().map(|(k, &n)| Rectangle::new(bar(k, n), c.stroke_width(1))))
        .map_err(&err)?;
    root.present().map_err(&err)
}

/// Counts of `sample` in `bins` equal bins spanning `x` (the top edge belongs to the last bin).
fn count(sample: &[f64], x: Axis, bins: usize) -> Vec<usize> {
    let mut counts = vec![0; bins];
    for v in sample {
        let k = ((v - x.lo) / (x.hi - x.lo) * bins as f64).floor();
        counts[(k.max(0.0) as usize).min(bins - 1)] += 1;
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::{count, Axis};

    #[test]
    fn counts_every_value_once() {
        let x = Axis::new(0.0, 1.0);
        assert_eq!(count(&[0.0, 0.1, 0.5, 0.99, 1.0], x, 2), vec![2, 3]);
        assert_eq!(count(&[], x, 3), vec![0, 0, 0]);
    }
}
