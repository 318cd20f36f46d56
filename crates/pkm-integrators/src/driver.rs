//! The driver that runs a [`Scheme`] over an interval and samples it.

use nalgebra::SVector;
use pkm_traits::{IntegrationError, InvalidInput, Progress, VectorField};

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
/// [`IntegrationError::Invalid`] for a span that is not finite and increasing, invalid
/// output times or more of them than fit in [`pkm_traits::MEMORY_BUDGET_BYTES`] (refused
/// before anything is reserved), more recorded steps than fit in it ([`OutputTimes::Steps`]),
/// a first step that is not finite and positive, or a fixed step so small that the span needs
/// more steps than the method's budget (refused before the run starts);
/// [`IntegrationError::TooManySteps`] when the method's step budget runs out;
/// [`IntegrationError::StepSizeUnderflow`] when a step does not move `t` (`t + h == t`);
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
    if !(t0.is_finite() && t1.is_finite() && t1 > t0 && (t1 - t0).is_finite()) {
        return Err(InvalidInput::new(
            "t1",
            t1,
            "t0 and t1 must be finite with t1 > t0 and a finite span t1 - t0",
        )
        .into());
    }
    require_finite_state(t0, z0)?;
    let targets = output.resolve(t0, t1)?;
    let mut recorder = Recorder::new(targets)?;
    progress.start("integrate", recorder.expected() as u64);
    let start = scheme.start(field, t0, z0, t1)?;
    let dense = scheme.has_dense_output();
    check_start(
        start.h,
        t0,
        t1,
        dense,
        scheme.max_steps(),
        recorder.expected(),
    )?;
    let mut stats = Stats {
        evaluations: start.evaluations,
        ..Stats::default()
    };
    let (mut t, mut z, mut h) = (t0, *z0, start.h);
    // Fixed-step times are `anchor + k·h` from the last time landed on exactly (t0, a sample
    // time, or where the step size changed), not a running sum, so round-off does not
    // accumulate over long runs.
    let (mut anchor, mut k, mut anchor_h) = (t0, 0.0_f64, start.h);
    recorder.record_up_to(t, &z, None, progress)?;
    while t < t1 {
        if stats.steps >= scheme.max_steps() {
            return Err(IntegrationError::TooManySteps {
                steps: stats.steps,
                t,
            });
        }
        if stats.steps.is_multiple_of(CHECK_EVERY) {
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
        let t_next = if clipped && report.h_taken.to_bits() == h_try.to_bits() {
            (anchor, k) = (stop, 0.0);
            stop
        } else if !dense && report.h_taken.to_bits() == h.to_bits() {
            if h.to_bits() != anchor_h.to_bits() {
                (anchor, k, anchor_h) = (t, 0.0, h);
            }
            k += 1.0;
            anchor + k * h
        } else {
            t + report.h_taken
        };
        if !(t_next > t) {
            // A step that does not move t (t + h == t far from 0, or h <= 0) would never end.
            return Err(IntegrationError::StepSizeUnderflow {
                t,
                h: report.h_taken,
                h_min: t.abs() * f64::EPSILON,
            });
        }
        t = t_next;
        h = report.h_next;
        recorder.record_up_to(t, &z, scheme.dense_output(), progress)?;
    }
    progress.finish();
    Ok(recorder.finish(stats))
}

/// Refuses a run that cannot end: a first step that is not finite and positive, or, for a
/// fixed-step method, a span that needs more than `max_steps` steps (counting the shortened
/// steps that land on the `samples` output times).
fn check_start(
    h: f64,
    t0: f64,
    t1: f64,
    dense: bool,
    max_steps: usize,
    samples: usize,
) -> Result<(), IntegrationError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(InvalidInput::new("h", h, "the first step must be finite and > 0").into());
    }
    let needed = ((t1 - t0) / h).ceil() + samples as f64;
    if !dense && !(needed <= max_steps as f64) {
        return Err(InvalidInput::new(
            "h",
            h,
            "the span needs more fixed steps than the method's max_steps",
        )
        .into());
    }
    Ok(())
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
    /// Bytes of one recorded sample: its time and its state.
    const SAMPLE_BYTES: usize = size_of::<f64>() + size_of::<SVector<f64, M>>();

    /// Refuses, before reserving them, more output times than fit in the memory budget.
    fn new(targets: Option<Vec<f64>>) -> Result<Self, IntegrationError> {
        if let Some(times) = &targets {
            InvalidInput::require_within_budget("output times", times.len(), Self::SAMPLE_BYTES)?;
        }
        let capacity = targets.as_ref().map_or(1024, Vec::len);
        Ok(Self {
            targets,
            next: 0,
            times: Vec::with_capacity(capacity),
            states: Vec::with_capacity(capacity),
        })
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
    /// with `dense` when a sample lies strictly inside the last step; with no output times,
    /// every step until the memory budget is full.
    fn record_up_to(
        &mut self,
        t: f64,
        z: &SVector<f64, M>,
        dense: Option<&crate::DenseSegment<M>>,
        progress: &dyn Progress,
    ) -> Result<(), IntegrationError> {
        if self.targets.is_none() {
            InvalidInput::require_within_budget(
                "recorded steps",
                self.times.len() + 1,
                Self::SAMPLE_BYTES,
            )?;
            self.times.push(t);
            self.states.push(*z);
            return Ok(());
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
        Ok(())
    }

    fn finish(self, stats: Stats) -> Solution<M> {
        Solution {
            times: self.times,
            states: self.states,
            stats,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_problems::{Blowup, HarmonicOscillator};
    use crate::{AdaptiveSettings, DormandPrince54, ImplicitMidpoint, Rk4};
    use nalgebra::{Vector1, Vector2};
    use pkm_traits::{RhsError, Silent};

    /// $\dot y = \sqrt{1 - t}$: NaN past t = 1.
    struct SqrtOfRemaining;
    impl VectorField<1> for SqrtOfRemaining {
        fn rhs(&self, t: f64, _: &Vector1<f64>, dz: &mut Vector1<f64>) -> Result<(), RhsError> {
            dz[0] = (1.0 - t).sqrt();
            Ok(())
        }
    }

    /// Fails at t ≥ 0.5.
    struct FailsLate;
    impl VectorField<1> for FailsLate {
        fn rhs(&self, t: f64, _: &Vector1<f64>, dz: &mut Vector1<f64>) -> Result<(), RhsError> {
            if t >= 0.5 {
                return Err(RhsError {
                    t,
                    reason: "past 0.5".into(),
                });
            }
            dz[0] = 1.0;
            Ok(())
        }
    }

    struct CancelledAlready;
    impl Progress for CancelledAlready {
        fn is_cancelled(&self) -> bool {
            true
        }
    }

    fn dopri(settings: AdaptiveSettings) -> DormandPrince54<1> {
        DormandPrince54::new(settings)
    }

    #[test]
    fn blowup_past_its_pole_underflows_h_min() {
        let settings = AdaptiveSettings::default().with_h_min(1e-8).unwrap();
        let y0 = Vector1::new(1.0);
        let result = integrate(
            &Blowup,
            &mut dopri(settings),
            (0.0, 2.0),
            &y0,
            &OutputTimes::Steps,
            &Silent,
        );
        match result {
            Err(IntegrationError::StepSizeUnderflow { t, h, h_min }) => {
                assert!(t > 0.99 && t < 1.0, "t = {t}");
                assert!(
                    h < h_min && h_min.to_bits() == 1e-8f64.to_bits(),
                    "h = {h:e}"
                );
            }
            other => panic!("expected StepSizeUnderflow, got {other:?}"),
        }
    }

    #[test]
    fn blowup_with_a_fixed_step_becomes_non_finite() {
        let y0 = Vector1::new(1.0);
        let result = integrate(
            &Blowup,
            &mut Rk4::new(0.25).unwrap(),
            (0.0, 3.0),
            &y0,
            &OutputTimes::Steps,
            &Silent,
        );
        assert!(
            matches!(result, Err(IntegrationError::NonFinite { t }) if t > 1.0),
            "{result:?}"
        );
    }

    #[test]
    fn nan_derivative_is_a_non_finite_error_for_every_method() {
        let y0 = Vector1::new(0.0);
        let span = (0.0, 2.0);
        let out = OutputTimes::Steps;
        let dp = integrate(
            &SqrtOfRemaining,
            &mut dopri(AdaptiveSettings::default()),
            span,
            &y0,
            &out,
            &Silent,
        );
        let rk = integrate(
            &SqrtOfRemaining,
            &mut Rk4::new(0.3).unwrap(),
            span,
            &y0,
            &out,
            &Silent,
        );
        let mp = integrate(
            &SqrtOfRemaining,
            &mut ImplicitMidpoint::new(0.3).unwrap(),
            span,
            &y0,
            &out,
            &Silent,
        );
        for result in [dp, rk, mp] {
            assert!(
                matches!(result, Err(IntegrationError::NonFinite { t }) if t >= 0.5),
                "{result:?}"
            );
        }
    }

    #[test]
    fn field_failures_and_cancellation_propagate() {
        let y0 = Vector1::new(0.0);
        let result = integrate(
            &FailsLate,
            &mut Rk4::new(0.1).unwrap(),
            (0.0, 1.0),
            &y0,
            &OutputTimes::Steps,
            &Silent,
        );
        assert!(matches!(result, Err(IntegrationError::Rhs(RhsError { t, .. })) if t >= 0.5));
        let result = integrate(
            &FailsLate,
            &mut Rk4::new(0.1).unwrap(),
            (0.0, 0.4),
            &y0,
            &OutputTimes::Steps,
            &CancelledAlready,
        );
        assert_eq!(result, Err(IntegrationError::Cancelled));
    }

    #[test]
    fn step_budget_runs_out() {
        let oscillator = HarmonicOscillator::new(1.0).unwrap();
        let settings = AdaptiveSettings::default().with_max_steps(10).unwrap();
        let mut dp = DormandPrince54::new(settings);
        let z0 = Vector2::new(1.0, 0.0);
        let result = integrate(
            &oscillator,
            &mut dp,
            (0.0, 100.0),
            &z0,
            &OutputTimes::Steps,
            &Silent,
        );
        assert!(
            matches!(
                result,
                Err(IntegrationError::TooManySteps { steps: 10, .. })
            ),
            "{result:?}"
        );
    }

    #[test]
    fn invalid_spans_and_output_times_are_rejected() {
        let z0 = Vector2::new(1.0, 0.0);
        let oscillator = HarmonicOscillator::new(1.0).unwrap();
        let mut rk4 = Rk4::new(0.1).unwrap();
        let mut run =
            |span, out: OutputTimes| integrate(&oscillator, &mut rk4, span, &z0, &out, &Silent);
        for (span, out) in [
            ((1.0, 0.0), OutputTimes::Steps),
            ((0.0, f64::NAN), OutputTimes::Steps),
            ((0.0, 1.0), OutputTimes::Uniform(0.0)),
            ((0.0, 1.0), OutputTimes::Times(vec![0.5, 0.2])),
            ((0.0, 1.0), OutputTimes::Times(vec![0.5, 1.5])),
        ] {
            let result = run(span, out);
            assert!(
                matches!(result, Err(IntegrationError::Invalid(_))),
                "{result:?}"
            );
        }
        assert!(matches!(
            Rk4::new(-0.1),
            Err(IntegrationError::Invalid(InvalidInput { name: "h", .. }))
        ));
        assert!(
            ImplicitMidpoint::new(0.1)
                .unwrap()
                .with_tolerance(0.0)
                .is_err()
        );
        assert!(
            ImplicitMidpoint::new(0.1)
                .unwrap()
                .with_max_iterations(0)
                .is_err()
        );
    }

    #[test]
    fn too_large_implicit_step_does_not_converge() {
        // h ω / 2 = 2 > 1: the fixed-point iteration diverges.
        let oscillator = HarmonicOscillator::new(4.0).unwrap();
        let mut midpoint = ImplicitMidpoint::new(1.0).unwrap();
        let z0 = Vector2::new(1.0, 0.0);
        let result = integrate(
            &oscillator,
            &mut midpoint,
            (0.0, 1.0),
            &z0,
            &OutputTimes::Steps,
            &Silent,
        );
        assert!(
            matches!(
                result,
                Err(IntegrationError::NotConverged { iterations: 50, .. })
                    | Err(IntegrationError::NonFinite { .. })
            ),
            "{result:?}"
        );
    }

    #[test]
    fn samples_land_on_the_requested_times() {
        let oscillator = HarmonicOscillator::new(1.0).unwrap();
        let z0 = Vector2::new(1.0, 0.0);
        let times = vec![0.0, 0.25, 0.25, 0.7, 1.0];
        let mut rk4 = Rk4::new(0.1).unwrap();
        let run = integrate(
            &oscillator,
            &mut rk4,
            (0.0, 1.0),
            &z0,
            &OutputTimes::Times(times.clone()),
            &Silent,
        )
        .unwrap();
        assert_eq!(run.times, times);
        // Steps are shortened at 0.25 and 0.7 only: 0.1 ×2, 0.05, 0.1 ×4, 0.05, 0.1 ×3.
        assert_eq!(run.stats.steps, 11);
        for (t, z) in run.times.iter().zip(&run.states) {
            assert!((z - oscillator.exact(*t, &z0)).amax() < 1e-5);
        }
    }
}
