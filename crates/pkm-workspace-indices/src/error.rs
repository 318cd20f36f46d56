use pkm_traits::{Cancelled, ConstraintError, DesignError, InvalidInput};
use thiserror::Error;

/// Failures of index computations.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum IndexError {
    /// A sample of zero points was asked for.
    #[error("sample size must be at least 1 (got {n_samples})")]
    EmptySample {
        /// The sample size given.
        n_samples: u64,
    },
    /// A region or setting that cannot be used (empty box, non-finite bound).
    #[error(transparent)]
    Invalid(#[from] InvalidInput),
    /// A count that cannot be allocated or computed in reasonable time.
    #[error("too many {what}: {requested} (at most {limit})")]
    TooLarge {
        /// Which count.
        what: &'static str,
        /// The count asked for.
        requested: u64,
        /// The largest accepted.
        limit: u64,
    },
    /// A workspace constraint that cannot be applied.
    #[error(transparent)]
    Constraint(#[from] ConstraintError),
    /// The design itself is invalid.
    #[error(transparent)]
    Design(#[from] DesignError),
    /// A result overflowed (or came out NaN) from finite inputs: an index whose values or
    /// domain are too large for `f64` (e.g. $\eta = V_D \sum f_k / n$ with $f_k \sim 10^{300}$).
    #[error("{what} is not finite ({value}): the inputs overflow f64")]
    NonFinite {
        /// Which result (`"eta"`, `"eta standard error"`).
        what: &'static str,
        /// The value computed.
        value: f64,
    },
    /// The computation was cancelled through [`pkm_traits::Progress`].
    #[error("cancelled")]
    Cancelled,
}

impl From<Cancelled> for IndexError {
    fn from(_: Cancelled) -> Self {
        Self::Cancelled
    }
}
