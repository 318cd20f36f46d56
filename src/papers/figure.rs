//! Data for tables (CSV) and figures (SVG). Experiments describe *what* to draw: a chart of
//! `pkm_draw::chart` or a robot drawing of `pkm_draw`; `xtask` renders.

use pkm_draw::chart::Chart;
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

/// A figure written as `<experiment id>.<name>.svg`, with its data as
/// `<experiment id>.<name>.csv`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figure {
    /// File-name stem, unique within the experiment.
    pub name: String,
    /// What to draw, with its caption.
    pub kind: FigureKind,
}

impl Figure {
    /// A chart (heat map, lines, points); its title is the caption.
    pub fn chart(name: impl Into<String>, chart: Chart) -> Self {
        Self {
            name: name.into(),
            kind: FigureKind::Chart(chart),
        }
    }

    /// A drawing of a robot (see [`FigureKind::Robot`]) with coordinates in `unit`.
    pub fn robot(
        name: impl Into<String>,
        title: impl Into<String>,
        scene: pkm_draw::Scene,
        unit: &str,
    ) -> Self {
        Self {
            name: name.into(),
            kind: FigureKind::Robot(RobotDrawing {
                title: title.into(),
                scene,
                unit: unit.to_owned(),
            }),
        }
    }

    /// The caption, naming the paper's figure it stands for where there is one.
    pub fn title(&self) -> &str {
        match &self.kind {
            FigureKind::Chart(chart) => &chart.title,
            FigureKind::Robot(drawing) => &drawing.title,
        }
    }
}

/// The kinds of figure `xtask` renders.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum FigureKind {
    /// Curves, point clouds or a heat map, with markers (`pkm_draw::chart`).
    Chart(Chart),
    /// A robot at a pose in front, side, top and 3-D views (`pkm-draw`), with its axes,
    /// trajectories and workspace points.
    Robot(RobotDrawing),
}

/// A drawing of a robot: what `pkm_draw::render_svg` draws, its caption and the length unit of
/// its coordinates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobotDrawing {
    /// Caption, naming the paper's figure it stands for where there is one.
    pub title: String,
    /// The skeleton and the extra elements.
    pub scene: pkm_draw::Scene,
    /// Length unit of the coordinates (`"m"`, `"cm"`, `"R"`).
    pub unit: String,
}
