//! Terminal helpers for pkm's command-line tools, and no science: the two pieces the `pkm`
//! command and `cargo xtask` share (as ripgrep keeps its terminal helpers in `grep-cli`). The
//! front ends' shared layer is `pkm-study`; the Python package has its own progress bridge.
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

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

pub mod output;
pub mod progress;

pub use output::{OutputDir, OutputError, write_atomically};
pub use progress::{CancelFlag, Spinner};
