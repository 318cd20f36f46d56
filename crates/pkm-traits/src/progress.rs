//! Progress reporting and cooperative cancellation.
//!
//! Library crates never print: long computations report through a [`Progress`] and check
//! [`Progress::is_cancelled`] between chunks of work. `xtask` implements it with indicatif and a
//! Ctrl-C flag; tests pass [`Silent`].

/// Receives progress of long computations and may ask them to stop.
pub trait Progress: Sync {
    /// A phase of work without a count begins (`"sampling points"`).
    fn phase(&self, _message: &str) {}
    /// A task with `total` units of work begins.
    fn start(&self, _label: &str, _total: u64) {}
    /// `n` more units of work are done.
    fn advance(&self, _n: u64) {}
    /// The current task is done.
    fn finish(&self) {}
    /// `true` once the user asked to stop; loops then return [`Cancelled`].
    fn is_cancelled(&self) -> bool {
        false
    }
    /// `Err(Cancelled)` once the user asked to stop, for use with `?` between chunks.
    ///
    /// # Errors
    /// [`Cancelled`] when [`Progress::is_cancelled`] is true.
    fn check(&self) -> Result<(), Cancelled> {
        if self.is_cancelled() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }
}

/// A [`Progress`] that reports nothing and never cancels.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {}

/// The computation was cancelled by its [`Progress`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

/// Forwards only the cancellation of another [`Progress`]: for a solver run many times in
/// parallel (one run per start of a multistart), whose own `start`/`advance`/`finish` calls
/// would interleave on the caller's display.
///
/// # Example
/// ```
/// use pkm_traits::{CancelOnly, Progress, Silent};
/// assert!(!CancelOnly(&Silent).is_cancelled());
/// ```
#[derive(Clone, Copy)]
pub struct CancelOnly<'a>(pub &'a dyn Progress);

impl std::fmt::Debug for CancelOnly<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CancelOnly")
            .field("cancelled", &self.0.is_cancelled())
            .finish()
    }
}

impl Progress for CancelOnly<'_> {
    fn is_cancelled(&self) -> bool {
        self.0.is_cancelled()
    }
}
