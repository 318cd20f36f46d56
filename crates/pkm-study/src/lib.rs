#![doc = include_str!("../README.md")]

pub mod assembly;
pub mod dynamics;
mod error;
mod estimate;
pub mod files;
pub mod grid;
pub mod indices;
mod infeasible;
pub mod load;
pub mod merge;
pub mod optimize;
pub mod outcome;
pub mod pareto;
mod parse;
pub mod registry;
pub mod scene;
pub mod schema;
mod starts;
pub mod sweep;
pub mod task;
pub mod task_space;
pub mod workspace;

pub use assembly::{AssemblyResult, AssemblyStudy, assembly};
pub use dynamics::{DynamicsResult, DynamicsStudy, dynamics};
pub use error::{Key, KeyPath, StudyError};
pub use grid::{GridRun, Shard, ShardResult};
pub use infeasible::Infeasible;
pub use merge::{GridKind, MergeError, Merged, merge};
pub use optimize::{OptimizeResult, OptimizeStudy, optimize};
pub use outcome::{Artifact, Cell, Outcome, Table, short};
pub use pareto::{ParetoResult, ParetoStudy, pareto};
pub use parse::{from_deserializer, from_json_str, from_toml_str};
pub use registry::{Actuation, StudyMechanism, Unit, Variable};
pub use schema::grid::GridStudy;
pub use schema::mechanism::MechanismSpec;
pub use sweep::{SweepResult, SweepStudy, sweep};
pub use task::{TaskMechanism, TaskResult, TaskStudy, task};
pub use workspace::{WorkspaceResult, WorkspaceStudy, workspace};

pub use pkm_robot_file::UrdfExport;

/// A robot file's text as URDF plus its loop closures
/// ([`pkm_robot_file::RobotModel::to_urdf`]): what `pkm urdf` calls.
///
/// # Errors
/// [`StudyError::Invalid`] at the key path of the refused value within the robot file
/// ([`files::locate`] finds its line), at the root for text that does not parse (its message
/// has the line and column).
pub fn urdf(text: &str) -> Result<UrdfExport, StudyError> {
    pkm_robot_file::RobotModel::from_toml(text)
        .map(|model| model.to_urdf())
        .map_err(|e| schema::robot_file::located_under("", e))
}

/// A robot file's text as MuJoCo's MJCF ([`pkm_robot_file::RobotModel::to_mjcf`]): what
/// `pkm mjcf` calls.
///
/// # Errors
/// As [`urdf`].
pub fn mjcf(text: &str) -> Result<String, StudyError> {
    pkm_robot_file::RobotModel::from_toml(text)
        .map(|model| model.to_mjcf())
        .map_err(|e| schema::robot_file::located_under("", e))
}

/// What the registry macros need from this crate's dependencies, so that a crate which
/// declares its own mechanisms needs only `pkm-study`.
#[doc(hidden)]
pub mod __private {
    pub use nalgebra;
    pub use pkm_design_problems;
    pub use pkm_mechanisms;
    pub use pkm_traits;
    pub use pkm_workspace_indices;
}
