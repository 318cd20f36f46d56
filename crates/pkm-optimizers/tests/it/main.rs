//! The integration tests of `pkm-optimizers`, one test binary: each file is a module (one link
//! and one build of the shared code instead of one per file).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod cancellation;
mod compass_search;
mod hock_schittkowski;
mod kkt;
mod levenberg_marquardt;
mod multistart;
mod pareto;
mod properties;
mod scaling;
mod settings;
