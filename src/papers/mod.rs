//! The registry of experiments that reproduce the papers pkm is built on.
//!
//! An [`Experiment`] computes results with the library crates and compares each with the value
//! the paper prints ([`Comparison`]). Paper values appear here only as *expected* values; every
//! reported value is computed. `cargo xtask reproduce` runs the experiments in [`Mode::Full`];
//! `cargo test` runs the same functions in [`Mode::Quick`] (`tests/it/reproduce_quick.rs`).
//!
//! Experiment ids and quantity names follow `../shared/spec/README.md`; `docs/reproduce.md` maps
//! every id to the paper's table, figure or equation.

mod comparison;
mod figure;
pub mod miller2004;
pub mod stamper1997;
pub mod wolf2006;

pub use comparison::{Comparison, Source, Verdict};
pub use figure::{Figure, FigureKind, RobotDrawing, Table};

use pkm_traits::Progress;
use serde::Serialize;
use thiserror::Error;

/// How much work an experiment does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Reduced sample sizes and grids, for `cargo test` (seconds per experiment).
    Quick,
    /// The paper's sample sizes and resolutions, for `cargo xtask reproduce`.
    Full,
}

impl Mode {
    /// `quick` when quick, `full` otherwise.
    pub fn pick<T>(self, quick: T, full: T) -> T {
        match self {
            Self::Quick => quick,
            Self::Full => full,
        }
    }
}

/// The three papers, by their file names in `../shared/papers/`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Paper {
    /// Miller 2004: NUWAR vs Delta, the Linear Delta design search, Hamilton's equations.
    Miller2004,
    /// Stamper, Tsai & Walsh 1997: the Tsai translational platform.
    Stamper1997,
    /// Wolf & Shoham: screw theory and task-based design of the Stewart–Gough platform and 3-UPU.
    WolfShoham,
}

impl Paper {
    /// File name of the paper's text in `../shared/papers/`.
    pub fn file(self) -> &'static str {
        match self {
            Self::Miller2004 => "000_3af296716aa60595.txt",
            Self::Stamper1997 => "001_d243aef4a9524698.txt",
            Self::WolfShoham => "003_788af3b033109bd5.txt",
        }
    }
}

/// What an experiment runs with.
#[derive(Clone, Copy)]
pub struct Context<'a> {
    /// Quick (tests) or full (the reproduce command).
    pub mode: Mode,
    /// Where long work reports progress and learns of cancellation.
    pub progress: &'a dyn Progress,
}

impl std::fmt::Debug for Context<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Context")
            .field("mode", &self.mode)
            .finish_non_exhaustive()
    }
}

/// What an experiment produced: comparisons with the paper, data tables and figures.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// One row per reported quantity.
    pub comparisons: Vec<Comparison>,
    /// Series data, written as CSV.
    pub tables: Vec<Table>,
    /// Figures, rendered as SVG by `xtask`.
    pub figures: Vec<Figure>,
}

/// A reproduction of one result (or one group of results) of a paper.
#[derive(Debug, Clone, Copy)]
pub struct Experiment {
    /// Id prefix shared by the comparisons it produces (`stamper1997.max_gci`).
    pub id: &'static str,
    /// The paper it reproduces.
    pub paper: Paper,
    /// One line saying what it reproduces.
    pub title: &'static str,
    /// Computes the outcome.
    pub run: fn(&Context<'_>) -> Result<Outcome, ExperimentError>,
}

impl Experiment {
    /// Whether `--only prefix` selects this experiment: either id is a prefix of the other.
    pub fn matches(&self, prefix: &str) -> bool {
        self.id.starts_with(prefix) || prefix.starts_with(self.id)
    }
}

/// Every registered experiment, in report order.
pub fn all() -> Vec<Experiment> {
    let mut experiments = wolf2006::experiments();
    experiments.extend(stamper1997::experiments());
    experiments.extend(miller2004::experiments());
    experiments
}

/// An experiment could not compute its results.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ExperimentError {
    /// A design given by the paper was rejected.
    #[error(transparent)]
    Design(#[from] pkm_traits::DesignError),
    /// A kinematic computation failed.
    #[error(transparent)]
    Kinematics(#[from] pkm_traits::KinematicsError),
    /// An objective failed.
    #[error(transparent)]
    Objective(#[from] pkm_traits::ObjectiveError),
    /// A workspace constraint was rejected.
    #[error(transparent)]
    Constraint(#[from] pkm_traits::ConstraintError),
    /// An index computation failed.
    #[error(transparent)]
    Index(#[from] pkm_workspace_indices::IndexError),
    /// An optimisation failed.
    #[error(transparent)]
    Optimize(#[from] pkm_optimizers::OptimizeError),
    /// A time integration failed.
    #[error(transparent)]
    Integration(#[from] pkm_traits::IntegrationError),
    /// A screw-theory computation failed.
    #[error(transparent)]
    Screw(#[from] pkm_screw_theory::ScrewError),
    /// A dynamics computation failed.
    #[error(transparent)]
    Dynamics(#[from] pkm_dynamics_hamilton::DynamicsError),
    /// A drawing of a robot could not be made.
    #[error(transparent)]
    Draw(#[from] pkm_draw::DrawError),
    /// The run was cancelled.
    #[error("cancelled")]
    Cancelled,
}

impl From<pkm_traits::Cancelled> for ExperimentError {
    fn from(_: pkm_traits::Cancelled) -> Self {
        Self::Cancelled
    }
}
