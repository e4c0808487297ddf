//! Two curves sharing an x axis, one on a left and one on a right y axis.

use super::axis::Axis;
use super::lines::line_parts;
use super::{color, draw_error, finite_runs, font, PlotError, FONT, PLOT_WIDTH, SIZE};
use plotters::prelude::*;
use std::path::Path;

/// Plots `left` (y-axis title, points) against the left axis and `right` against the right
/// axis, into the PNG at `path`; the axis titles double as legend entries (e.g. crack area and
/// fragment count over time).
///
/// The x axis spans the finite x values of both curves. Non-finite points are skipped as in
/// [`plot_lines`](super::plot_lines); see [the module page](super) for the image format.
pub fn plot_two_axes(
    path: &Path,
    title: &str,
    x_label: &str,
    left: (&str, &[(f64, f64)]),
    right: (&str, &[(f64, f64)]),
) -> Result<(), PlotError> {
    font::ensure()?;
    let err = draw_error(path);
    let finite = |points| finite_runs(points).into_iter().flatten().copied();
    let x = Axis::fit(finite(left.1).chain(finite(right.1)).map(|p| p.0), 0.0);
    let yl = Axis::fit(finite(left.1).map(|p| p.1), 0.05);
    let yr = Axis::fit(finite(right.1).map(|p| p.1), 0.05);
    let (cl, cr) = (color(0), color(1));

    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 28))
        .margin(20)
        .margin_right(50)
        .x_label_area_size(70)
        .y_label_area_size(120)
        .right_y_label_area_size(120)
        .build_cartesian_2d(x.chart_range(), yl.chart_range())
        .map_err(&err)?
        .set_secondary_coord(x.chart_range(), yr.chart_range());
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(left.0)
        .x_labels(x.labels_fitting(PLOT_WIDTH))
        .x_label_formatter(&|v| x.label(*v))
        .y_label_formatter(&|v| yl.label(*v))
        .label_style((FONT, 18))
        .axis_desc_style((FONT, 22))
        .draw()
        .map_err(&err)?;
    chart
        .configure_secondary_axes()
        .y_desc(right.0)
        .y_label_formatter(&|v| yr.label(*v))
        .label_style((FONT, 18))
        .axis_desc_style((FONT, 22))
        .draw()
        .map_err(&err)?;

    let legend = |c: RGBColor| {
        move |(px, py): (i32, i32)| {
            PathElement::new(vec![(px, py), (px + 24, py)], c.stroke_width(3))
        }
    };
    let (lines, dots) = line_parts(left.1, cl, (x, yl));
    chart
        .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
        .map_err(&err)?
        .label(format!("{} (left)", left.0))
        .legend(legend(cl));
    chart.draw_series(lines).map_err(&err)?;
    chart.draw_series(dots).map_err(&err)?;
    let (lines, dots) = line_parts(right.1, cr, (x, yr));
    chart
        .draw_secondary_series(std::iter::empty::<PathElement<(f64, f64)>>())
        .map_err(&err)?
        .label(format!("{} (right)", right.0))
        .legend(legend(cr));
    chart.draw_secondary_series(lines).map_err(&err)?;
    chart.draw_secondary_series(dots).map_err(&err)?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((FONT, 18))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(&err)?;
    root.present().map_err(&err)
}
