//! What a command-line front end of pkm needs, and no science: the two pieces the `pkm` command
//! and `cargo xtask` share (as ripgrep keeps its terminal helpers in a library crate beside
//! its binary).
//!
//! - [`progress`]: a terminal [`Spinner`] implementing [`pkm_traits::Progress`] with indicatif,
//!   and the [`CancelFlag`] that the first Ctrl-C sets, so a running computation stops at its
//!   next check (a second Ctrl-C exits at once).
//! - [`output`]: [`write_atomically`] and [`OutputDir`], an output directory checked before any
//!   work starts whose files are each written to a temporary file and renamed into place, so an
//!   interrupted run never leaves a half-written file.
//!
//! Library crates never print; they report through `Progress`. This crate is where a front end
//! turns those reports into a terminal display and a Ctrl-C into cancellation.
#![warn(missing_docs)]

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

pub mod output;
pub mod progress;

pub use output::{OutputDir, OutputError, write_atomically};
pub use progress::{CancelFlag, Spinner};
