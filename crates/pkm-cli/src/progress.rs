//! Progress on the terminal and cooperative cancellation on Ctrl-C: `pkm-frontend`'s
//! [`Spinner`] and [`CancelFlag`], shared with `cargo xtask reproduce`.

pub use pkm_frontend::{CancelFlag, Spinner};
