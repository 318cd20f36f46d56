//! Cross-crate integration tests: quick reproductions, determinism, tidy checks.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

mod cross_checks;
mod design_index_kernels;
mod determinism;
mod hostile;
mod linear_delta_study;
mod reproduce_quick;
mod six_mechanisms;
mod study_grid;
mod task_space;
mod tidy;
