//! The integration tests of `pkm-robot-file`, one test binary: each file is a module (one link
//! and one build of the shared code instead of one per file).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod acceptance;
mod acceptance_modes;
mod agreement;
mod common;
mod conformance;
mod dynamics;
mod files;
mod homotopy;
mod hostile;
mod mode_labels;
mod points;
