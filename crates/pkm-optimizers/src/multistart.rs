//! Seeded, deterministic multistart over any local solver, keeping every outcome.
//!
//! [`Multistart`] gives the start points (the caller's own first, then seeded uniform points
//! in the box); [`multistart`] runs a local solver from each in parallel and returns a
//! [`MultistartRun`]: every start with what it ended with, the local result or its typed
//! failure, in start order. [`MultistartRun::best`] then applies the one rule of
//! [`Sense::best`]: the best value in the sense of the search, NaN never best, a tie to the
//! lowest start. Nothing depends on the thread count.

use crate::OptimizeError;
use crate::sense::Sense;
use crate::termination::Termination;
use pkm_traits::{Bounds, CancelOnly, InvalidInput, ObjectiveError, Progress};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Most start points of one multistart: the starts are allocated up front.
pub const MAX_STARTS: usize = 1 << 20;

/// `n_starts` points drawn uniformly in the box `bounds`; start `k` is a pure function of
/// `(seed, k)`, so adding starts never changes the earlier ones.
///
/// # Errors
/// [`OptimizeError::Invalid`] for more than [`MAX_STARTS`] starts (refused before
/// allocating).
///
/// # Example
/// ```
/// use pkm_optimizers::uniform_start_points;
/// use pkm_traits::Bounds;
/// let b = [Bounds::new(0.0, 1.0).unwrap(), Bounds::new(-2.0, 2.0).unwrap()];
/// let starts = uniform_start_points(&b, 8, 42).unwrap();
/// assert_eq!(starts.len(), 8);
/// assert!(starts.iter().all(|p| b[0].contains(p[0]) && b[1].contains(p[1])));
/// assert_eq!(starts[..4], uniform_start_points(&b, 4, 42).unwrap()[..]);
/// assert!(uniform_start_points(&b, usize::MAX, 42).is_err());
/// ```
pub fn uniform_start_points(
    bounds: &[Bounds],
    n_starts: usize,
    seed: u64,
) -> Result<Vec<Vec<f64>>, OptimizeError> {
    InvalidInput::require_count_at_most(
        "n_starts",
        n_starts,
        MAX_STARTS,
        "at most MAX_STARTS start points",
    )?;
    Ok((0..n_starts)
        .map(|k| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(k as u64);
            bounds
                .iter()
                .map(|b| b.lower() + b.width() * rng.random::<f64>())
                .collect()
        })
        .collect())
}

/// The starts of a multistart: `count` seeded uniform points in the box
/// ([`uniform_start_points`] with `seed`) after the `extra` starts given, which run first.
/// In a study file: `count`, `seed` and `extra` (default none), e.g. `[optimize.starts]`.
///
/// # Example
/// ```
/// use pkm_optimizers::Multistart;
/// use pkm_traits::Bounds;
/// let m = Multistart::new(32, 7).with_extra_starts(vec![vec![0.0, 1.0]]);
/// assert_eq!(m.total(), 33);
/// let bounds = [Bounds::new(-1.0, 1.0).unwrap(); 2];
/// let starts = m.start_points(&bounds).unwrap();
/// assert_eq!((starts.len(), &starts[0]), (33, &vec![0.0, 1.0]));
/// assert!(Multistart::new(0, 7).validate().is_err());
/// assert!(Multistart::new(usize::MAX, 7).validate().is_err());
/// // An extra start must have one finite value per variable.
/// assert!(Multistart::new(1, 7).with_extra_starts(vec![vec![0.0]]).start_points(&bounds).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub struct Multistart {
    /// Number of seeded uniform starts.
    pub count: usize,
    /// Seed of the uniform starts (start `k` is a pure function of `(seed, k)`).
    pub seed: u64,
    /// Starts given by the caller, run before the seeded ones, each a finite value per design
    /// variable.
    #[serde(default)]
    pub extra: Vec<Vec<f64>>,
}

impl Multistart {
    /// `count` seeded uniform starts and no extra ones.
    pub fn new(count: usize, seed: u64) -> Self {
        Self {
            count,
            seed,
            extra: Vec::new(),
        }
    }

    /// The same with `extra` starts run first.
    #[must_use]
    pub fn with_extra_starts(mut self, extra: Vec<Vec<f64>>) -> Self {
        self.extra = extra;
        self
    }

    /// Starts in all (saturating).
    pub fn total(&self) -> usize {
        self.count.saturating_add(self.extra.len())
    }

    /// Checks the counts (the extra starts are checked against the box by
    /// [`Multistart::start_points`]).
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] (name `"count"`) for no start at all or more than
    /// [`MAX_STARTS`].
    pub fn validate(&self) -> Result<(), OptimizeError> {
        let total = self.total();
        if total == 0 {
            return Err(InvalidInput::new("count", 0.0, "at least one start in all").into());
        }
        InvalidInput::require_count_at_most(
            "count",
            total,
            MAX_STARTS,
            "count + extra starts at most MAX_STARTS",
        )?;
        Ok(())
    }

    /// The start points in the box `bounds`: the extra ones, then the seeded uniform ones.
    ///
    /// # Errors
    /// As [`Multistart::validate`]; [`OptimizeError::Invalid`] (name `"extra"`) for an extra
    /// start without one finite value per bound.
    pub fn start_points(&self, bounds: &[Bounds]) -> Result<Vec<Vec<f64>>, OptimizeError> {
        self.validate()?;
        for start in &self.extra {
            if start.len() != bounds.len() {
                return Err(InvalidInput::new(
                    "extra",
                    start.len() as f64,
                    "an extra start has one value per design variable",
                )
                .into());
            }
            if let Some(&v) = start.iter().find(|v| !v.is_finite()) {
                return Err(InvalidInput::new("extra", v, "start values must be finite").into());
            }
        }
        let mut starts = self.extra.clone();
        starts.extend(uniform_start_points(bounds, self.count, self.seed)?);
        Ok(starts)
    }
}

/// What a local solver returns, as a multistart compares and reports it.
pub trait LocalResult {
    /// The design reached.
    fn design(&self) -> &[f64];
    /// The objective value there (the quantity the sense of the search applies to).
    fn value(&self) -> f64;
    /// Why the solver stopped.
    fn termination(&self) -> Termination;
}

/// Every start of a multistart and what it ended with, in start order.
#[derive(Debug, Clone, PartialEq)]
pub struct MultistartRun<R> {
    /// The start points.
    pub starts: Vec<Vec<f64>>,
    /// The local solver's result from each start, or its typed failure.
    pub outcomes: Vec<Result<R, OptimizeError>>,
}

impl<R: LocalResult> MultistartRun<R> {
    /// The best start by [`Sense::best`] over the successful starts (NaN never best, a tie to
    /// the lowest start), with its result.
    ///
    /// # Errors
    /// When no start succeeded: the first failure that is not an infeasible design, else
    /// [`OptimizeError::NoFeasibleDesign`] with the last infeasible start's reason.
    pub fn best(&self, sense: Sense) -> Result<(usize, &R), OptimizeError> {
        let values = self.outcomes.iter().map(|o| o.as_ref().ok().map(R::value));
        if let Some((k, _)) = sense.best(values)
            && let Some(Ok(result)) = self.outcomes.get(k)
        {
            return Ok((k, result));
        }
        let failures = self.outcomes.iter().filter_map(|o| o.as_ref().err());
        if let Some(e) = failures.clone().find(|e| !e.is_infeasible()) {
            return Err(e.clone());
        }
        Err(OptimizeError::NoFeasibleDesign {
            evaluations: self.starts.len(),
            last_reason: match failures.last() {
                Some(OptimizeError::Objective(ObjectiveError::Infeasible { reason, .. })) => {
                    reason.clone()
                }
                _ => "no start reached a value".to_owned(),
            },
        })
    }

    /// Starts that ended on an infeasible design.
    pub fn infeasible(&self) -> usize {
        self.outcomes
            .iter()
            .filter(|o| o.as_ref().is_err_and(OptimizeError::is_infeasible))
            .count()
    }
}

/// Runs `local` from every start in parallel and keeps every outcome, in start order.
///
/// `local(start, progress)` is a local solver run from `start`; the progress it gets forwards
/// only the cancellation of `progress` ([`CancelOnly`]), so parallel runs do not interleave
/// their reports. `progress` hears one task (`"multistart"`) of one unit per start, advanced
/// as each start finishes, and is asked for cancellation before each start: once it is
/// cancelled no further start begins.
///
/// # Errors
/// [`OptimizeError::Cancelled`] when `progress` was cancelled or a start returned
/// [`OptimizeError::Cancelled`]: a cancelled multistart returns no outcome at all. Every other
/// failure of a start is kept as its outcome.
///
/// # Example
/// Levenberg–Marquardt from eight seeded starts on a function with two minima,
/// $f = (x^2 - 1)^2$ on $[-2, 2]$: every start is kept, and the best is the first start that
/// reached the lowest value.
/// ```
/// use pkm_optimizers::{LmSettings, Multistart, Sense, levenberg_marquardt, multistart};
/// use pkm_traits::{Bounds, Objective, ObjectiveError, Residuals, Silent};
/// struct DoubleWell([Bounds; 1]);
/// impl Objective for DoubleWell {
///     fn dimension(&self) -> usize { 1 }
///     fn bounds(&self) -> &[Bounds] { &self.0 }
///     fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> { self.sum_of_squares(p) }
/// }
/// impl Residuals for DoubleWell {
///     fn n_residuals(&self) -> usize { 1 }
///     fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
///         r[0] = p[0] * p[0] - 1.0;
///         Ok(())
///     }
/// }
/// let problem = DoubleWell([Bounds::new(-2.0, 2.0)?]);
/// let starts = Multistart::new(8, 1).start_points(problem.bounds())?;
/// let settings = LmSettings::default();
/// let run = multistart(starts, &Silent, |s, p| {
///     levenberg_marquardt(&problem, Sense::Minimise, s, &settings, p)
/// })?;
/// assert_eq!(run.outcomes.len(), 8);
/// let (k, best) = run.best(Sense::Minimise)?;
/// assert!(best.value < 1e-20 && (best.design[0].abs() - 1.0).abs() < 1e-10);
/// assert!(run.outcomes[..k].iter().all(|o| o.as_ref().is_ok_and(|r| r.value > best.value)));
/// # Ok::<(), pkm_optimizers::OptimizeError>(())
/// ```
pub fn multistart<R, F>(
    starts: Vec<Vec<f64>>,
    progress: &dyn Progress,
    local: F,
) -> Result<MultistartRun<R>, OptimizeError>
where
    R: Send,
    F: Fn(&[f64], &dyn Progress) -> Result<R, OptimizeError> + Sync,
{
    progress.start("multistart", starts.len() as u64);
    let cancel = CancelOnly(progress);
    let outcomes: Vec<Result<R, OptimizeError>> = starts
        .par_iter()
        .map(|start| {
            progress.check()?;
            let outcome = local(start, &cancel);
            progress.advance(1);
            outcome
        })
        .collect();
    progress.finish();
    if progress.is_cancelled()
        || outcomes
            .iter()
            .any(|o| matches!(o, Err(OptimizeError::Cancelled)))
    {
        return Err(OptimizeError::Cancelled);
    }
    Ok(MultistartRun { starts, outcomes })
}
