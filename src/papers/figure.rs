//! Data for tables (CSV) and figures (SVG). Experiments describe *what* to draw; `xtask` renders.

use serde::Serialize;

/// Series data written as `<experiment id>.<name>.csv`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    /// File-name stem, unique within the experiment.
    pub name: String,
    /// Column headers.
    pub columns: Vec<String>,
    /// Rows, each as long as `columns`.
    pub rows: Vec<Vec<f64>>,
}

/// A figure written as `<experiment id>.<name>.svg`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figure {
    /// File-name stem, unique within the experiment.
    pub name: String,
    /// Caption, naming the paper's figure it stands for where there is one.
    pub title: String,
    /// What to draw.
    pub kind: FigureKind,
}

impl Figure {
    /// A drawing of a robot (see [`FigureKind::Robot`]) with coordinates in `unit`.
    pub fn robot(
        name: impl Into<String>,
        title: impl Into<String>,
        scene: pkm_draw::Scene,
        unit: &str,
    ) -> Self {
        Self {
            name: name.into(),
            title: title.into(),
            kind: FigureKind::Robot(RobotDrawing {
                scene,
                unit: unit.to_owned(),
            }),
        }
    }
}

/// The kinds of figure `xtask` renders.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum FigureKind {
    /// Curves or point clouds over shared axes.
    Lines(LinePlot),
    /// A scalar field on a regular grid, as colours.
    Heatmap(Heatmap),
    /// A heatmap with labelled points marked on it (designs, optima).
    AnnotatedHeatmap {
        /// The field.
        map: Heatmap,
        /// The marked points, in the map's coordinates.
        markers: Vec<Marker>,
    },
    /// A robot at a pose in front, side, top and 3-D views (`pkm-draw`), with its axes,
    /// trajectories and workspace points.
    Robot(RobotDrawing),
}

/// A drawing of a robot: what `pkm_draw::render_svg` draws, and the length unit of its
/// coordinates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobotDrawing {
    /// The skeleton and the extra elements.
    pub scene: pkm_draw::Scene,
    /// Length unit of the coordinates (`"m"`, `"cm"`, `"R"`).
    pub unit: String,
}

/// A labelled point drawn on a figure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Marker {
    /// The label written beside the point.
    pub label: String,
    /// Horizontal coordinate.
    pub x: f64,
    /// Vertical coordinate.
    pub y: f64,
}

/// Curves or point clouds over shared axes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinePlot {
    /// Label of the horizontal axis, with unit.
    pub x_label: String,
    /// Label of the vertical axis, with unit.
    pub y_label: String,
    /// The curves.
    pub series: Vec<LineSeries>,
}

/// One curve or point cloud.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LineSeries {
    /// Legend entry.
    pub label: String,
    /// Drawn as a line or as points.
    pub style: SeriesStyle,
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SeriesStyle {
    /// A polyline through the points.
    Line,
    /// A dot per point.
    Points,
}

/// A scalar field $z(x, y)$ on the grid `x × y`, drawn as colours.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Heatmap {
    /// Label of the horizontal axis, with unit.
    pub x_label: String,
    /// Label of the vertical axis, with unit.
    pub y_label: String,
    /// Label of the colour scale, with unit.
    pub z_label: String,
    /// Cell centres along x, increasing.
    pub x: Vec<f64>,
    /// Cell centres along y, increasing.
    pub y: Vec<f64>,
    /// `values[iy * x.len() + ix]`; `None` where the field is undefined (outside a workspace).
    pub values: Vec<Option<f64>>,
}
