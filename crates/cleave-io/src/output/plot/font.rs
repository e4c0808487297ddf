//! The bundled font, registered once with plotters' `ab_glyph` font table.

use super::{PlotError, FONT};
use std::sync::OnceLock;

/// DejaVu Sans (see `assets/DejaVuSans-LICENSE.txt`).
static DEJAVU_SANS: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../assets/DejaVuSans.ttf"
));

/// Registers the bundled font as the `sans-serif` family (once per process).
pub(super) fn ensure() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, plotters::style::FontStyle::Normal, DEJAVU_SANS)
                .map_err(|_| "DejaVuSans.ttf is not a valid font".to_string())
        })
        .clone()
        .map_err(PlotError::Font)
}
