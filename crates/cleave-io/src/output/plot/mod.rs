//! PNG plots (energy histories, crack growth, fragment distributions) drawn with plotters.
//!
//! Every plot is a 1000 x 700 px RGB PNG on a white background with a title, axis titles and a
//! legend. Text uses DejaVu Sans embedded in the binary (`assets/DejaVuSans.ttf`), so plots work
//! on machines without system fonts. Inputs are forgiving: points with a non-finite coordinate
//! are skipped (a line is broken there), an empty input gives an empty chart with unit axes, a
//! constant input gets a range around its value, and tick labels switch to scientific notation
//! (`1.5e-4`) for magnitudes below 1e-3 or from 1e5 up.

mod axis;
mod font;
mod histogram;
mod lines;
mod two_axes;

pub use self::histogram::plot_histogram;
pub use self::lines::plot_lines;
pub use self::two_axes::plot_two_axes;

use plotters::style::RGBColor;
use std::path::Path;

/// Size of every plot in pixels (width, height).
const SIZE: (u32, u32) = (1000, 700);

/// Approximate width of the plotting area in pixels (image width less the label areas).
const PLOT_WIDTH: u32 = 780;

/// Font family name the bundled font is registered under (plotters' default family).
const FONT: &str = "sans-serif";

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The bundled font could not be loaded (a corrupt build).
    #[error("cannot load the bundled plot font: {0}")]
    Font(String),
    /// Drawing or encoding the PNG failed, or the file could not be written.
    #[error("cannot write plot {path}: {message}")]
    Draw {
        /// The PNG file.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// A closure turning a plotters error into a [`PlotError::Draw`] for `path`.
fn draw_error<E: std::fmt::Display>(path: &Path) -> impl Fn(E) -> PlotError + '_ {
    move |e| PlotError::Draw {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// The colour of the `k`-th series: a fixed, colour-blind friendly cycle (Okabe-Ito).
fn color(k: usize) -> RGBColor {
    const COLORS: [RGBColor; 8] = [
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
        RGBColor(0, 0, 0),
        RGBColor(240, 228, 66),
    ];
    COLORS[k % COLORS.len()]
}

/// The runs of consecutive points of `points` whose coordinates are both finite.
fn finite_runs(points: &[(f64, f64)]) -> Vec<&[(f64, f64)]> {
    points
        .split(|(x, y)| !(x.is_finite() && y.is_finite()))
        .filter(|run| !run.is_empty())
        .collect()
}
