//! What a run returns: the sampled states and its statistics.

use nalgebra::SVector;
use pkm_traits::{IntegrationError, InvalidInput, StepReport};

/// Most samples one run records: they are allocated up front, so more are refused (a typed
/// error) before the run starts. 2²³ states of 12 components take 800 MB.
pub const MAX_SAMPLES: usize = 1 << 23;

/// Where [`crate::integrate`] records the state.
#[derive(Debug, Clone, PartialEq)]
pub enum OutputTimes {
    /// At $t_0$ and after every accepted step.
    Steps,
    /// At $t_0 + i\,\Delta t$ for $i = 0, 1, \dots$ while $\le t_1$ (within $10^{-9}\Delta t$,
    /// so $t_1$ is included when the span is a multiple of $\Delta t$). Each time is computed
    /// as $t_0 + i\,\Delta t$, without accumulating round-off.
    Uniform(f64),
    /// At the given times: non-decreasing, inside $[t_0, t_1]$.
    Times(Vec<f64>),
}

impl OutputTimes {
    /// The requested times inside `[t0, t1]`, or `None` for [`OutputTimes::Steps`].
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] for a `Uniform` step that is not finite and positive,
    /// `Times` that are not finite, not sorted or outside the span, or more than [`MAX_SAMPLES`]
    /// samples.
    pub fn resolve(&self, t0: f64, t1: f64) -> Result<Option<Vec<f64>>, IntegrationError> {
        match self {
            Self::Steps => Ok(None),
            Self::Uniform(dt) => {
                let dt = InvalidInput::require_positive("output dt", *dt)?;
                let count = ((t1 - t0) / dt + 1e-9).floor();
                if !(count < MAX_SAMPLES as f64) {
                    return Err(InvalidInput::new(
                        "output dt",
                        dt,
                        "must give at most MAX_SAMPLES samples over the span",
                    )
                    .into());
                }
                // `count` is a non-negative integer below MAX_SAMPLES, so the cast is exact.
                let n = count as usize;
                Ok(Some(
                    (0..=n).map(|i| (t0 + i as f64 * dt).min(t1)).collect(),
                ))
            }
            Self::Times(times) => {
                if times.len() > MAX_SAMPLES {
                    return Err(InvalidInput::new(
                        "output times",
                        times.len() as f64,
                        "at most MAX_SAMPLES output times",
                    )
                    .into());
                }
                let mut previous = t0;
                for &t in times {
                    if !(t >= previous && t <= t1) {
                        return Err(InvalidInput::new(
                            "output time",
                            t,
                            "must be non-decreasing and inside [t0, t1]",
                        )
                        .into());
                    }
                    previous = t;
                }
                Ok(Some(times.clone()))
            }
        }
    }
}

/// Work done by a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected attempts.
    pub rejections: usize,
    /// Right-hand-side evaluations, rejected attempts and step-size selection included.
    pub evaluations: usize,
}

impl Stats {
    /// Adds one accepted step.
    pub fn record(&mut self, report: &StepReport) {
        self.steps += 1;
        self.rejections += report.rejections;
        self.evaluations += report.evaluations;
    }
}

/// States sampled by [`crate::integrate`], with the run's statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution<const M: usize> {
    /// Sample times, non-decreasing.
    pub times: Vec<f64>,
    /// State at each sample time.
    pub states: Vec<SVector<f64, M>>,
    /// Work done.
    pub stats: Stats,
}
