//! The driver that runs a [`Scheme`] over an interval and samples it.

use nalgebra::SVector;
use pkm_traits::{IntegrationError, Progress, VectorField};

use crate::{OutputTimes, Scheme, Solution, Stats, require_finite_state};

/// Steps between two cancellation checks.
const CHECK_EVERY: usize = 64;

/// Integrates $\dot z = f(t, z)$ from $z(t_0) = z_0$ to $t_1 > t_0$ and records the state at
/// `output`.
///
/// Methods with dense output ([`crate::DormandPrince54`]) step freely and interpolate the
/// samples; fixed-step methods shorten a step only to land exactly on the next sample time, so
/// that a step size dividing the sample spacing gives step-aligned samples. Allocation happens
/// only for the returned vectors (reserved once), not per step. `progress` receives one unit per
/// sample and is checked for cancellation every 64 steps.
///
/// # Errors
/// [`IntegrationError::InvalidSetting`] for a span that is not finite and increasing or invalid
/// output times; [`IntegrationError::TooManySteps`] when the method's step budget runs out;
/// [`IntegrationError::Cancelled`] when `progress` asks to stop; any error of the method's
/// steps (vector field failure, non-finite state, step-size underflow).
pub fn integrate<const M: usize, F, S>(
    field: &F,
    scheme: &mut S,
    t_span: (f64, f64),
    z0: &SVector<f64, M>,
    output: &OutputTimes,
    progress: &dyn Progress,
) -> Result<Solution<M>, IntegrationError>
where
    F: VectorField<M> + ?Sized,
    S: Scheme<M>,
{
    let (t0, t1) = t_span;
    if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
        return Err(IntegrationError::InvalidSetting {
            setting: "t1",
            value: t1,
            requirement: "t0 and t1 must be finite with t1 > t0",
        });
    }
    require_finite_state(t0, z0)?;
    let targets = output.resolve(t0, t1)?;
    let mut recorder = Recorder::new(targets);
    progress.start("integrate", recorder.expected() as u64);
    let start = scheme.start(field, t0, z0, t1)?;
    let mut stats = Stats {
        evaluations: start.evaluations,
        ..Stats::default()
    };
    let (mut t, mut z, mut h) = (t0, *z0, start.h);
    recorder.record_up_to(t, &z, None, progress);
    let dense = scheme.has_dense_output();
    while t < t1 {
        if stats.steps >= scheme.max_steps() {
            return Err(IntegrationError::TooManySteps {
                steps: stats.steps,
                t,
            });
        }
        if stats.steps % CHECK_EVERY == 0 {
            progress.check()?;
        }
        let stop = if dense {
            t1
        } else {
            recorder.next_time().unwrap_or(t1)
        };
        // Stretch by at most 1e-9 relative rather than leave a sliver step before `stop`.
        let clipped = t + h * (1.0 + 1e-9) >= stop;
        let h_try = if clipped { stop - t } else { h };
        let report = scheme.step(field, t, &mut z, h_try)?;
        stats.record(&report);
        t = if clipped && report.h_taken.to_bits() == h_try.to_bits() {
            stop
        } else {
            t + report.h_taken
        };
        h = report.h_next;
        recorder.record_up_to(t, &z, scheme.dense_output(), progress);
    }
    progress.finish();
    Ok(recorder.finish(stats))
}

/// Collects samples as the run passes their times.
struct Recorder<const M: usize> {
    /// Requested times, or `None` to record every step.
    targets: Option<Vec<f64>>,
    next: usize,
    times: Vec<f64>,
    states: Vec<SVector<f64, M>>,
}

impl<const M: usize> Recorder<M> {
    fn new(targets: Option<Vec<f64>>) -> Self {
        let capacity = targets.as_ref().map_or(1024, Vec::len);
        Self {
            targets,
            next: 0,
            times: Vec::with_capacity(capacity),
            states: Vec::with_capacity(capacity),
        }
    }

    fn expected(&self) -> usize {
        self.targets.as_ref().map_or(0, Vec::len)
    }

    fn next_time(&self) -> Option<f64> {
        self.targets
            .as_ref()
            .and_then(|times| times.get(self.next).copied())
    }

    /// Records every pending sample at or before `t` (the current state `z`), interpolating
    /// with `dense` when a sample lies strictly inside the last step.
    fn record_up_to(
        &mut self,
        t: f64,
        z: &SVector<f64, M>,
        dense: Option<&crate::DenseSegment<M>>,
        progress: &dyn Progress,
    ) {
        if self.targets.is_none() {
            self.times.push(t);
            self.states.push(*z);
            return;
        }
        let mut recorded = 0;
        while let Some(target) = self.next_time().filter(|&target| target <= t) {
            let state = match dense {
                Some(segment) if target < t => segment.evaluate(target),
                _ => *z,
            };
            self.times.push(target);
            self.states.push(state);
            self.next += 1;
            recorded += 1;
        }
        if recorded > 0 {
            progress.advance(recorded);
        }
    }

    fn finish(self, stats: Stats) -> Solution<M> {
        Solution {
            times: self.times,
            states: self.states,
            stats,
        }
    }
}
