//! Progress on the terminal and cooperative cancellation on Ctrl-C: `pkm-term`'s
//! [`Spinner`] and [`CancelFlag`], shared with `cargo xtask reproduce`.

pub use pkm_term::{CancelFlag, Spinner};
