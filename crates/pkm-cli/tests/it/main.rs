//! The integration tests of `pkm-cli`, one test binary: each file is a module (one link
//! and one build of the shared code instead of one per file).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod assembly_studies;
mod bad_files;
mod common;
mod drawings;
mod dynamics_studies;
mod examples;
mod papers;
mod robot_file_studies;
mod shards;
mod synthesis_studies;
mod task_space_studies;
mod upu_stewart_studies;
