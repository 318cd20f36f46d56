//! The integration tests of `pkm-mechanisms`, one test binary: each file is a module (one link
//! and one build of the shared code instead of one per file).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod designs;
mod linear_delta;
mod skeleton;
mod stewart_gough_and_three_upu;
mod stewart_orientation;
mod tsai3dof;
