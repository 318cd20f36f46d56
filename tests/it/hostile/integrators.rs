//! `pkm-integrators`: every scheme, its settings and the driver.

use super::{all_finite, config, hostile_f64, judge, judge_err};
use nalgebra::Vector2;
use pkm_integrators::test_problems::{
    ExponentialDecay, HarmonicOscillator, Pendulum, RotatingDecay,
};
use pkm_integrators::{
    AdaptiveSettings, DormandPrince54, ImplicitMidpoint, OutputTimes, Rk4, Scheme, Solution,
    integrate,
};
use pkm_traits::{Integrator, Silent};
use proptest::prelude::*;

/// A run is checked when its samples are finite, inside the span and non-decreasing.
fn run_is_checked(run: &Solution<2>, span: (f64, f64)) -> bool {
    run.states.iter().all(|z| all_finite(z.iter()))
        && run.times.len() == run.states.len()
        && run.times.windows(2).all(|w| w[0] <= w[1])
        && run.times.iter().all(|t| *t >= span.0 && *t <= span.1)
}

fn drive<S: Scheme<2>>(
    entry: &'static str,
    scheme: &mut S,
    span: (f64, f64),
    z0: &Vector2<f64>,
    output: &OutputTimes,
) -> Result<(), TestCaseError> {
    let field = HarmonicOscillator::new(3.0).unwrap();
    judge(
        entry,
        || integrate(&field, scheme, span, z0, output, &Silent),
        |run| run_is_checked(run, span),
    )
}

/// Spans: ordinary, inverted, empty, non-finite, and far from zero (where `t + h == t`).
fn span() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        2 => (hostile_f64(), hostile_f64()),
        2 => (0.0..1.0f64, 0.0..2.0f64),
        1 => prop::sample::select(vec![(1e20, 1e20 + 1e5), (-1e300, 1e300), (0.0, 1e-300), (1.0, 1.0)]),
    ]
}

fn output() -> impl Strategy<Value = OutputTimes> {
    prop_oneof![
        Just(OutputTimes::Steps),
        hostile_f64().prop_map(OutputTimes::Uniform),
        (0.01..1.0f64).prop_map(OutputTimes::Uniform),
        prop::collection::vec(hostile_f64(), 0..4).prop_map(OutputTimes::Times),
    ]
}

/// Steps: hostile, and tiny ones bounded so that a correct guard is needed to end quickly.
fn step() -> impl Strategy<Value = f64> {
    prop_oneof![3 => hostile_f64(), 1 => Just(1e-300), 2 => 0.01..0.5f64]
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn test_problems_are_validated(a in hostile_f64(), b in hostile_f64()) {
        judge("ExponentialDecay::new", || ExponentialDecay::new(a), |_| true)?;
        judge("HarmonicOscillator::new", || HarmonicOscillator::new(a), |o| o.omega().is_finite())?;
        judge("Pendulum::new", || Pendulum::new(a), |_| true)?;
        judge("RotatingDecay::new", || RotatingDecay::new(a, b), |_| true)?;
    }

    #[test]
    fn adaptive_settings_are_validated(
        rtol in hostile_f64(), atol in hostile_f64(), h0 in hostile_f64(), h_min in hostile_f64(), h_max in hostile_f64(),
    ) {
        judge("AdaptiveSettings::new", || AdaptiveSettings::new(rtol, atol, h0, h_min, h_max, 2000), |s| {
            s.rtol() > 0.0 && s.atol() > 0.0 && s.h_min() <= s.h_max()
        })?;
    }

    #[test]
    fn fixed_step_schemes_are_validated(h in hostile_f64(), tol in hostile_f64(), iterations in 0..60usize) {
        judge("Rk4::new", || Rk4::new(h), |s| s.step_size() > 0.0 && s.step_size().is_finite())?;
        judge("ImplicitMidpoint::new", || ImplicitMidpoint::new(h), |s| s.step_size() > 0.0 && s.step_size().is_finite())?;
        if let Ok(m) = ImplicitMidpoint::new(0.1) {
            judge("ImplicitMidpoint::with_tolerance", || m.with_tolerance(tol), |s| s.tolerance() > 0.0)?;
            judge("ImplicitMidpoint::with_max_iterations", || m.with_max_iterations(iterations), |s| s.max_iterations() > 0)?;
        }
    }

    #[test]
    fn single_steps_end_typed_or_finite(h in hostile_f64(), t in hostile_f64(), z in (hostile_f64(), hostile_f64())) {
        let field = HarmonicOscillator::new(3.0).unwrap();
        let z0 = Vector2::new(z.0, z.1);
        let mut z1 = z0;
        judge("Rk4::step", || Rk4::new(0.1).unwrap().step(&field, t, &mut z1, h), |r| r.h_taken.is_finite() && r.h_taken != 0.0)?;
        let mut z2 = z0;
        judge("ImplicitMidpoint::step", || ImplicitMidpoint::new(0.1).unwrap().step(&field, t, &mut z2, h), |r| r.h_taken.is_finite() && r.h_taken != 0.0)?;
        let mut z3 = z0;
        let mut dopri = DormandPrince54::new(AdaptiveSettings::default());
        judge("DormandPrince54::step", || dopri.step(&field, t, &mut z3, h), |r| r.h_taken.is_finite() && r.h_taken != 0.0)?;
    }

    #[test]
    fn driver_ends_typed_or_checked(
        span in span(), output in output(), h in step(), z in (hostile_f64(), hostile_f64()),
        rtol in 1e-9..1e-2f64, h_max in hostile_f64(),
    ) {
        let z0 = Vector2::new(z.0, z.1);
        if let Ok(mut rk4) = Rk4::new(h) {
            drive("integrate (Rk4)", &mut rk4, span, &z0, &output)?;
        }
        if let Ok(mut midpoint) = ImplicitMidpoint::new(h) {
            drive("integrate (ImplicitMidpoint)", &mut midpoint, span, &z0, &output)?;
        }
        let settings = AdaptiveSettings::new(rtol, 1e-9, 0.0, 0.0, if h_max > 0.0 { h_max } else { f64::INFINITY }, 5000);
        if let Ok(settings) = settings {
            drive("integrate (DormandPrince54)", &mut DormandPrince54::new(settings), span, &z0, &output)?;
        }
    }
}

/// Steps that cannot advance `t` or would take ~1e300 steps, and output grids that cannot be
/// allocated, end in a typed error at once.
#[test]
fn runs_that_cannot_end_are_refused() {
    let z0 = Vector2::new(1.0, 0.0);
    let field = HarmonicOscillator::new(3.0).unwrap();
    let cases: [(f64, (f64, f64), OutputTimes); 4] = [
        (1e-300, (0.0, 1.0), OutputTimes::Steps),
        (1.0, (1e20, 1e20 + 1e5), OutputTimes::Steps),
        (1e-3, (0.0, 1.0), OutputTimes::Uniform(1e-12)),
        (1e-3, (0.0, 1e6), OutputTimes::Uniform(1e-3)),
    ];
    for (h, span, output) in cases {
        super::expect(judge_err("integrate (Rk4, cannot end)", || {
            integrate(
                &field,
                &mut Rk4::new(h).unwrap(),
                span,
                &z0,
                &output,
                &Silent,
            )
        }));
        super::expect(judge_err(
            "integrate (ImplicitMidpoint, cannot end)",
            || {
                integrate(
                    &field,
                    &mut ImplicitMidpoint::new(h).unwrap(),
                    span,
                    &z0,
                    &output,
                    &Silent,
                )
            },
        ));
    }
}

/// Fixed-step times are `t0 + k·h`, not accumulated sums: 1000 steps of 1e-3 land on 1.0
/// exactly at every thousandth.
#[test]
fn fixed_step_times_do_not_accumulate_round_off() {
    let z0 = Vector2::new(1.0, 0.0);
    let field = HarmonicOscillator::new(3.0).unwrap();
    let run = integrate(
        &field,
        &mut Rk4::new(0.1).unwrap(),
        (0.0, 100.0),
        &z0,
        &OutputTimes::Steps,
        &Silent,
    )
    .unwrap();
    for (k, t) in run.times.iter().enumerate() {
        assert_eq!(
            t.to_bits(),
            (0.1 * k as f64).min(100.0).to_bits(),
            "step {k}: t = {t}"
        );
    }
}
