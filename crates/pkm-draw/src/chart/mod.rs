//! Charts: heat maps with a colour bar, line plots and scatter plots, with labelled markers,
//! as one plain model ([`Chart`]) and one SVG renderer ([`render_svg`]).
//!
//! A chart is data, not drawing instructions: a title, the [`Quantity`] of each axis (name and
//! unit), a [`Plot`] (a [`Heatmap`] or a list of [`Series`]) and [`Marker`]s. Every front end
//! (the papers' reproductions, the `pkm` command, `cargo xtask`) builds the same model, so a
//! figure means the same thing wherever it is drawn, and [`Chart::to_csv`] writes the data
//! behind it.
//!
//! **Undefined values.** A heat-map cell is `Option<f64>`: `None` is a cell without a value
//! (outside a workspace, an infeasible design) and is left blank. A NaN or infinite cell, point
//! or marker is not a way to say "undefined": [`Chart::validate`] refuses it with a typed
//! [`ChartError`] naming the cell or point, so a NaN computed by mistake is never drawn as a
//! gap. Every number must also be at most [`MAX_VALUE`] in magnitude, which keeps every axis
//! range and its padding finite.
//!
//! **Determinism.** The same chart gives the same SVG, byte for byte.

mod csv;
#[cfg(feature = "render")]
mod render;
#[cfg(feature = "render")]
mod scale;
mod validate;

#[cfg(feature = "render")]
pub use render::render_svg;
pub use validate::{ChartError, MAX_ITEMS, MAX_VALUE};

/// Above this many points a [`SeriesStyle::Points`] series is a cloud, drawn with smaller dots so
/// that the cloud's shape stays visible.
pub const CLOUD: usize = 1000;

use serde::{Deserialize, Serialize};
use std::fmt;

/// A chart: a title, the two axes, what is plotted on them and the marked points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Chart {
    /// Caption above the chart.
    pub title: String,
    /// What the horizontal axis measures.
    pub x_axis: Quantity,
    /// What the vertical axis measures.
    pub y_axis: Quantity,
    /// What is drawn in the plane of the axes.
    pub plot: Plot,
    /// Labelled points drawn over the plot (a design, an optimum), in the axes' coordinates.
    pub markers: Vec<Marker>,
    /// Where the legend of the series goes (unused by a heat map).
    pub legend: LegendPosition,
}

impl Chart {
    /// A heat map `map` over the axes `x_axis` × `y_axis`, without markers.
    pub fn heatmap(
        title: impl Into<String>,
        x_axis: impl Into<Quantity>,
        y_axis: impl Into<Quantity>,
        map: Heatmap,
    ) -> Self {
        Self::new(title, x_axis, y_axis, Plot::Heatmap(map))
    }

    /// The curves or point clouds `series` over the axes `x_axis` × `y_axis`, without markers.
    pub fn series(
        title: impl Into<String>,
        x_axis: impl Into<Quantity>,
        y_axis: impl Into<Quantity>,
        series: Vec<Series>,
    ) -> Self {
        Self::new(title, x_axis, y_axis, Plot::Series(series))
    }

    fn new(
        title: impl Into<String>,
        x_axis: impl Into<Quantity>,
        y_axis: impl Into<Quantity>,
        plot: Plot,
    ) -> Self {
        Self {
            title: title.into(),
            x_axis: x_axis.into(),
            y_axis: y_axis.into(),
            plot,
            markers: Vec::new(),
            legend: LegendPosition::default(),
        }
    }

    /// The chart with `markers` added after its own.
    #[must_use]
    pub fn with_markers(mut self, markers: impl IntoIterator<Item = Marker>) -> Self {
        self.markers.extend(markers);
        self
    }

    /// The chart with its legend at `legend`.
    #[must_use]
    pub fn with_legend(self, legend: LegendPosition) -> Self {
        Self { legend, ..self }
    }

    /// Checks what [`render_svg`] needs; see the [module docs](self) for what is refused.
    ///
    /// # Errors
    /// The first problem found, as a [`ChartError`].
    pub fn validate(&self) -> Result<(), ChartError> {
        validate::chart(self)
    }

    /// The data behind the chart as CSV (numbers in shortest round-trip form, labels quoted
    /// when they hold a comma, a quote or a line break):
    /// - a heat map: `x,y,z`, one row per cell (x fastest), `z` empty for a cell without value;
    /// - series: `series,x,y`, one row per point of every series, in order;
    /// - with markers, a last column `marker`: the rows above with it empty, then one row per
    ///   marker with only its position and label (`x,y,,label` for a heat map,
    ///   `,x,y,label` for series).
    pub fn to_csv(&self) -> String {
        csv::chart(self)
    }
}

/// What an axis (or a colour bar) measures: a name and a unit.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Quantity {
    /// Its name (`"t"`, `"β"`, `"1/κ"`).
    pub name: String,
    /// Its unit (`"s"`, `"deg"`); empty for a dimensionless quantity or when the name already
    /// says it.
    pub unit: String,
}

impl Quantity {
    /// The quantity `name` in `unit`.
    pub fn new(name: impl Into<String>, unit: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            unit: unit.into(),
        }
    }
}

/// `name (unit)`, or `name` alone without a unit: the text written on the axis.
impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.unit.is_empty() {
            f.write_str(&self.name)
        } else {
            write!(f, "{} ({})", self.name, self.unit)
        }
    }
}

/// A quantity whose name is the whole text (any unit written in it).
impl From<&str> for Quantity {
    fn from(name: &str) -> Self {
        Self::new(name, "")
    }
}

/// A quantity whose name is the whole text (any unit written in it).
impl From<String> for Quantity {
    fn from(name: String) -> Self {
        Self::new(name, "")
    }
}

/// What a chart draws in the plane of its axes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Plot {
    /// A scalar field on a grid, as colours, with a colour bar.
    Heatmap(Heatmap),
    /// Curves and point clouds, with a legend.
    Series(Vec<Series>),
}

/// A scalar field $z(x, y)$ on the grid `x × y` of cell centres, drawn as one coloured
/// rectangle per defined cell (viridis, from the smallest to the largest defined value).
///
/// The cells' edges lie halfway between neighbouring centres, and half a step beyond the first
/// and last centres (±0.5 around a lone centre).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Heatmap {
    /// What the colours measure: the colour bar's label and unit.
    pub colour_axis: Quantity,
    /// Cell centres along x, strictly increasing.
    pub x: Vec<f64>,
    /// Cell centres along y, strictly increasing.
    pub y: Vec<f64>,
    /// `values[iy * x.len() + ix]`; `None` where the field has no value (drawn blank).
    pub values: Vec<Option<f64>>,
}

/// One curve or point cloud.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Series {
    /// Legend entry; none when empty.
    pub label: String,
    /// How the points are drawn.
    pub style: SeriesStyle,
    /// The colour.
    pub colour: Colour,
    /// `(x, y)` points, in order.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A solid line through `points`, coloured by its place in the chart.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::styled(label, SeriesStyle::Line, points)
    }

    /// A dot at each of `points`, coloured by its place in the chart.
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::styled(label, SeriesStyle::Points, points)
    }

    /// `points` drawn in `style`, coloured by its place in the chart.
    pub fn styled(label: impl Into<String>, style: SeriesStyle, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            style,
            colour: Colour::Auto,
            points,
        }
    }

    /// The series in `colour`.
    #[must_use]
    pub fn with_colour(self, colour: Colour) -> Self {
        Self { colour, ..self }
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SeriesStyle {
    /// A solid polyline through the points.
    Line,
    /// A thin dashed polyline (a reference drawn under a solid one).
    Dashed,
    /// A dot per point (radius 3 pixels; 2 in a cloud of more than [`CLOUD`] points).
    Points,
    /// A solid polyline with a larger dot (radius 4 pixels) at each point: a front drawn over
    /// a cloud.
    LineAndPoints,
}

/// The colour of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Colour {
    /// The palette colour of the series' index in the chart.
    #[default]
    Auto,
    /// A colour of the 99-colour palette, by index (wrapping around), so that related series
    /// (a quantity by two methods) can share one.
    Palette(usize),
    /// An RGB colour.
    Rgb([u8; 3]),
}

/// A labelled point drawn over a chart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// The label written beside the point.
    pub label: String,
    /// Horizontal coordinate.
    pub x: f64,
    /// Vertical coordinate.
    pub y: f64,
}

impl Marker {
    /// The point `(x, y)` labelled `label`.
    pub fn new(label: impl Into<String>, x: f64, y: f64) -> Self {
        Self {
            label: label.into(),
            x,
            y,
        }
    }
}

/// Where the legend of a chart's series is drawn, inside the plot area.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LegendPosition {
    /// Upper left corner.
    UpperLeft,
    /// Upper right corner.
    UpperRight,
    /// Middle of the right side.
    #[default]
    MiddleRight,
    /// Lower left corner.
    LowerLeft,
    /// Lower right corner.
    LowerRight,
}
