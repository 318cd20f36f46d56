//! The integration tests of `pkm-study`, one test binary: each file is a module (one link
//! and one build of the shared code instead of one per file).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod adding_a_mechanism;
mod assembly;
mod dynamics;
mod grid_studies;
mod module_graph;
mod optimize;
mod papers;
mod presets;
mod robot_file;
mod robot_file_dynamics;
mod task;
mod task_space;
mod variables;
mod workspace;
