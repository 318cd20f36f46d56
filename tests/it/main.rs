//! Cross-crate integration tests: quick reproductions, determinism, tidy checks.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

mod cross_checks;
mod design_index_kernels;
mod determinism;
mod hostile;
mod reproduce_quick;
mod six_mechanisms;
mod tidy;
