//! Line plots of several labelled series on one pair of axes.

use super::axis::Axis;
use super::{color, draw_error, finite_runs, font, PlotError, FONT, PLOT_WIDTH, SIZE};
use plotters::prelude::*;
use std::path::Path;

/// Plots `series` (name, points) as lines on shared axes with a legend, into the PNG at `path`.
///
/// The x axis spans the finite x values exactly, the y axis the finite y values plus 5 %.
/// Points with a non-finite coordinate are skipped and break the line; a point with no finite
/// neighbour is drawn as a dot. See [the module page](super) for the image format.
pub fn plot_lines(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, &[(f64, f64)])],
) -> Result<(), PlotError> {
    font::ensure()?;
    let err = draw_error(path);
    let finite = || {
        series
            .iter()
            .flat_map(|(_, points)| finite_runs(points).into_iter().flatten().copied())
    };
    let x = Axis::fit(finite().map(|p| p.0), 0.0);
    let y = Axis::fit(finite().map(|p| p.1), 0.05);

    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 28))
        .margin(20)
        .margin_right(50)
        .x_label_area_size(70)
        .y_label_area_size(120)
        .build_cartesian_2d(x.chart_range(), y.chart_range())
        .map_err(&err)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_labels(x.labels_fitting(PLOT_WIDTH))
        .x_label_formatter(&|v| x.label(*v))
        .y_label_formatter(&|v| y.label(*v))
        .label_style((FONT, 18))
        .axis_desc_style((FONT, 22))
        .draw()
        .map_err(&err)?;
    for (k, (name, points)) in series.iter().enumerate() {
        let c = color(k);
        chart
            .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
            .map_err(&err)?
            .label(*name)
            .legend(move |(px, py)| {
                PathElement::new(vec![(px, py), (px + 24, py)], c.stroke_width(3))
            });
        let (lines, dots) = line_parts(points, c, (x, y));
        chart.draw_series(lines).map_err(&err)?;
        chart.draw_series(dots).map_err(&err)?;
    }
    if !series.is_empty() {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, 18))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(&err)?;
    }
    root.present().map_err(&err)
}

/// Polylines and dots of one series, in chart units.
pub(super) type LineParts = (Vec<PathElement<(f64, f64)>>, Vec<Circle<(f64, f64), i32>>);

/// The polylines (runs of two or more finite points) and dots (isolated finite points) that
/// draw `points` in colour `c`, in the chart units of `axes`.
pub(super) fn line_parts(points: &[(f64, f64)], c: RGBColor, (x, y): (Axis, Axis)) -> LineParts {
    let mut lines = Vec::new();
    let mut dots = Vec::new();
    for run in finite_runs(points) {
        let mut chart = run.iter().map(|&(px, py)| (x.chart_of(px), y.chart_of(py)));
        if run.len() == 1 {
            dots.extend(chart.next().map(|p| Circle::new(p, 4, c.filled())));
        } else {
            lines.push(PathElement::new(
                chart.collect::<Vec<_>>(),
                c.stroke_width(2),
            ));
        }
    }
    (lines, dots)
}
