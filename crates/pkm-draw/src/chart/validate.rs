//! What a chart must satisfy before it is drawn, and the typed errors when it does not.

use super::{Chart, Heatmap, Plot};
use pkm_traits::InvalidInput;
use thiserror::Error;

/// The largest magnitude of any number on a chart: far beyond any physical quantity, and small
/// enough that every axis range, its width and its padding stay finite.
pub const MAX_VALUE: f64 = 1e300;

/// The largest number of heat-map cells, or of series points plus markers, on one chart (the
/// largest grid `pkm-optimizers` evaluates, `MAX_GRID_NODES`).
pub const MAX_ITEMS: usize = 1 << 24;

/// Why a chart cannot be drawn.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ChartError {
    /// A number that cannot be drawn: NaN, infinite, or beyond [`MAX_VALUE`] in magnitude.
    #[error("{what} {index} is {value}: it must be finite and at most 1e300 in magnitude")]
    BadValue {
        /// Which number: `"heat-map cell"`, `"x centre"`, `"y centre"` or `"marker"`.
        what: &'static str,
        /// Its index (for a cell the flat index `iy * nx + ix`).
        index: usize,
        /// The offending number.
        value: f64,
    },
    /// A point of a series is NaN, infinite, or beyond [`MAX_VALUE`] in magnitude.
    #[error(
        "point {point} of series {series} has the coordinate {value}: it must be finite and at most 1e300 in magnitude"
    )]
    BadPoint {
        /// Index of the series in the chart.
        series: usize,
        /// Index of the point in the series.
        point: usize,
        /// The offending coordinate.
        value: f64,
    },
    /// A heat map without cell centres along an axis.
    #[error("the heat map has no cell centres along {axis}")]
    EmptyGrid {
        /// `"x"` or `"y"`.
        axis: &'static str,
    },
    /// Cell centres that do not strictly increase.
    #[error("the heat map's {axis} centres must strictly increase, but centre {index} does not")]
    NotIncreasing {
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// The first centre not above its predecessor.
        index: usize,
    },
    /// A heat map whose value count is not the product of its centre counts.
    #[error("the heat map has {values} values for {nx} × {ny} cells")]
    Shape {
        /// Number of values given.
        values: usize,
        /// Centres along x.
        nx: usize,
        /// Centres along y.
        ny: usize,
    },
    /// A title, axis or legend text with a control character (SVG cannot hold most of them).
    #[error("the {what} {text:?} holds a control character")]
    BadText {
        /// Which text (`"title"`, `"axis label"`, `"series label"`, `"marker label"`).
        what: &'static str,
        /// The text.
        text: String,
    },
    /// A count beyond [`MAX_ITEMS`].
    #[error(transparent)]
    InvalidInput(#[from] InvalidInput),
    /// The SVG backend failed (it writes to memory, so this is not expected).
    #[error("the SVG backend failed: {0}")]
    Backend(String),
}

/// [`Chart::validate`].
pub(super) fn chart(chart: &Chart) -> Result<(), ChartError> {
    text("title", &chart.title)?;
    for axis in [&chart.x_axis, &chart.y_axis] {
        text("axis label", &axis.name)?;
        text("axis label", &axis.unit)?;
    }
    let mut items = chart.markers.len();
    match &chart.plot {
        Plot::Heatmap(map) => heatmap(map)?,
        Plot::Series(series) => {
            for (s, line) in series.iter().enumerate() {
                text("series label", &line.label)?;
                items = items.saturating_add(line.points.len());
                if let Some((point, value)) = first_bad(line.points.iter().flat_map(|p| [p.0, p.1]))
                {
                    return Err(ChartError::BadPoint {
                        series: s,
                        point: point / 2,
                        value,
                    });
                }
            }
        }
    }
    InvalidInput::require_count_at_most(
        "series points and markers",
        items,
        MAX_ITEMS,
        "must be at most MAX_ITEMS (2^24)",
    )?;
    for (k, marker) in chart.markers.iter().enumerate() {
        text("marker label", &marker.label)?;
        if let Some((_, value)) = first_bad([marker.x, marker.y].into_iter()) {
            return Err(ChartError::BadValue {
                what: "marker",
                index: k,
                value,
            });
        }
    }
    Ok(())
}

fn heatmap(map: &Heatmap) -> Result<(), ChartError> {
    text("axis label", &map.colour_axis.name)?;
    text("axis label", &map.colour_axis.unit)?;
    for (axis, what, centres) in [("x", "x centre", &map.x), ("y", "y centre", &map.y)] {
        if centres.is_empty() {
            return Err(ChartError::EmptyGrid { axis });
        }
        if let Some((index, value)) = first_bad(centres.iter().copied()) {
            return Err(ChartError::BadValue { what, index, value });
        }
        if let Some(k) = centres.windows(2).position(|w| !(w[1] > w[0])) {
            return Err(ChartError::NotIncreasing { axis, index: k + 1 });
        }
    }
    let (nx, ny) = (map.x.len(), map.y.len());
    let cells = nx.saturating_mul(ny);
    InvalidInput::require_count_at_most(
        "heat-map cells",
        cells,
        MAX_ITEMS,
        "must be at most MAX_ITEMS (2^24)",
    )?;
    if map.values.len() != cells {
        return Err(ChartError::Shape {
            values: map.values.len(),
            nx,
            ny,
        });
    }
    let defined = map
        .values
        .iter()
        .enumerate()
        .filter_map(|(k, v)| v.map(|v| (k, v)));
    for (index, value) in defined {
        if !drawable(value) {
            return Err(ChartError::BadValue {
                what: "heat-map cell",
                index,
                value,
            });
        }
    }
    Ok(())
}

/// Finite and at most [`MAX_VALUE`] in magnitude.
fn drawable(v: f64) -> bool {
    v.abs() <= MAX_VALUE
}

/// The index and value of the first number of `values` that cannot be drawn.
fn first_bad(values: impl Iterator<Item = f64>) -> Option<(usize, f64)> {
    values.enumerate().find(|(_, v)| !drawable(*v))
}

fn text(what: &'static str, text: &str) -> Result<(), ChartError> {
    if text.chars().any(char::is_control) {
        Err(ChartError::BadText {
            what,
            text: text.to_owned(),
        })
    } else {
        Ok(())
    }
}
