//! The integration tests of `pkm-workspace-indices`, one test binary: each file is a module (one link
//! and one build of the shared code instead of one per file).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod lane_estimators;
mod lane_kernels;
mod local_indices;
mod properties;
mod section_indices;
mod stamper_estimators;
mod stewart_constant_orientation;
mod workspace_estimator;
