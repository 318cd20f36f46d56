//! The commands' figures as `pkm_draw::chart` charts: a scatter of designs with a highlighted
//! front. The commands describe a figure with [`Scatter`]; [`scatter`] turns it into a
//! [`Chart`] and renders it with the one chart renderer, [`render_svg`].
//!
//! A NaN or infinite number is refused with the
//! chart layer's typed error (see `pkm_draw::chart`).

use pkm_draw::chart::{Chart, Colour, LegendPosition, Series, SeriesStyle, render_svg};
use std::path::Path;

pub use pkm_draw::chart::Marker;

/// Points, some highlighted (drawn larger and labelled).
#[derive(Debug, Clone, PartialEq)]
pub struct Scatter {
    /// Title.
    pub title: String,
    /// Axis label.
    pub x_label: String,
    /// Axis label.
    pub y_label: String,
    /// Background points (grey, legend "designs").
    pub background: Vec<(f64, f64)>,
    /// Foreground points (blue, joined by a line in order, legend "non-dominated").
    pub front: Vec<(f64, f64)>,
    /// Labelled points.
    pub markers: Vec<Marker>,
}

impl From<Scatter> for Chart {
    fn from(plot: Scatter) -> Self {
        let series = vec![
            Series::points("designs", plot.background).with_colour(Colour::Rgb([170, 170, 170])),
            Series::styled("non-dominated", SeriesStyle::LineAndPoints, plot.front)
                .with_colour(Colour::Rgb([0, 0, 255])),
        ];
        Chart::series(plot.title, plot.x_label, plot.y_label, series)
            .with_markers(plot.markers)
            .with_legend(LegendPosition::LowerLeft)
    }
}

/// Renders `chart` into the SVG file `path`.
///
/// # Errors
/// The chart layer's or the file system's message.
pub fn render(chart: &Chart, path: &Path) -> Result<(), String> {
    let svg = render_svg(chart).map_err(|e| e.to_string())?;
    std::fs::write(path, svg).map_err(|e| format!("{}: {e}", path.display()))
}

/// Renders `plot` to an SVG file at `path`.
///
/// # Errors
/// As [`render`].
pub fn scatter(plot: &Scatter, path: &Path) -> Result<(), String> {
    render(&plot.clone().into(), path)
}
