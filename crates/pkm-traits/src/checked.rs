//! Checked helpers shared by every crate: the edges of `f64` and of memory, closed once.
//!
//! - *Comparisons that let NaN or ∞ through.* `a <= b` is true for `a = b = +∞`, and
//!   [`f64::min`]/[`f64::max`] drop a NaN. Membership and constraint tests start with
//!   [`all_finite`]; reductions that must not lose a NaN use [`min_propagating_nan`].
//! - *Results that overflowed.* [`finite_or`] turns a non-finite result into the caller's typed
//!   error, so that no `Ok` carries an infinity or a NaN.
//! - *Allocations.* [`MEMORY_BUDGET_BYTES`] is the most one call may allocate for a result or a
//!   scratch buffer; [`InvalidInput::require_within_budget`] refuses a larger request before
//!   anything is allocated.

use crate::InvalidInput;

/// The most memory one call may allocate for its output or working set: 4 GiB, half of the
/// 8 GiB of the smallest machine the project runs on (CI, 2 cores), so that a request refused
/// here is one that would have failed or swapped anyway. Counts are compared with
/// `budget / bytes per item` in integers, before allocating.
pub const MEMORY_BUDGET_BYTES: usize = 1 << 32;

/// Whether every value is finite (not NaN, not ±∞).
///
/// # Example
/// ```
/// use pkm_traits::checked::all_finite;
/// assert!(all_finite(&[1.0, -2.0]));
/// assert!(!all_finite(&[1.0, f64::NAN]));
/// ```
pub fn all_finite<'a>(values: impl IntoIterator<Item = &'a f64>) -> bool {
    values.into_iter().all(|v| v.is_finite())
}

/// The smaller of `a` and `b`, NaN if either is NaN ([`f64::min`] would return the other).
///
/// # Example
/// ```
/// use pkm_traits::checked::min_propagating_nan;
/// assert_eq!(min_propagating_nan(1.0, 2.0), 1.0);
/// assert!(min_propagating_nan(1.0, f64::NAN).is_nan());
/// ```
pub fn min_propagating_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.min(b)
    }
}

/// `Ok(value)` when `value` is finite, else `Err(error(value))`.
///
/// # Errors
/// `error(value)` for a NaN or infinite `value`.
///
/// # Example
/// ```
/// use pkm_traits::checked::finite_or;
/// assert_eq!(finite_or(2.0, |v| v), Ok(2.0));
/// assert!(finite_or(f64::INFINITY, |v| v).is_err());
/// ```
pub fn finite_or<E>(value: f64, error: impl FnOnce(f64) -> E) -> Result<f64, E> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(error(value))
    }
}

impl InvalidInput {
    /// Checks that `count` items of `bytes_each` bytes fit in [`MEMORY_BUDGET_BYTES`], before
    /// they are allocated.
    ///
    /// # Errors
    /// An [`InvalidInput`] naming `name` otherwise.
    ///
    /// # Example
    /// ```
    /// use pkm_traits::InvalidInput;
    /// assert!(InvalidInput::require_within_budget("points", 1000, 24).is_ok());
    /// assert!(InvalidInput::require_within_budget("points", usize::MAX, 24).is_err());
    /// ```
    pub fn require_within_budget(
        name: &'static str,
        count: usize,
        bytes_each: usize,
    ) -> Result<usize, Self> {
        let most = MEMORY_BUDGET_BYTES / bytes_each.max(1);
        Self::require_count_at_most(
            name,
            count,
            most,
            "must fit in the memory budget (MEMORY_BUDGET_BYTES)",
        )
    }
}
