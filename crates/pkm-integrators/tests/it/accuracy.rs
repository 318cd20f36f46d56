//! Accuracy and conservation of the integrators against closed forms: observed orders of
//! convergence, tolerance proportionality of Dormand–Prince, dense output, long-run energy.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use nalgebra::{SVector, Vector1};
use pkm_integrators::test_problems::{ExponentialDecay, HarmonicOscillator, Pendulum};
use pkm_integrators::{
    AdaptiveSettings, DormandPrince54, ImplicitMidpoint, OutputTimes, Rk4, integrate,
};
use pkm_traits::{Integrator, Silent, VectorField};
use std::f64::consts::TAU;

/// Takes `n` steps of size `h` from `(0, z)` with `step` and returns the final state.
fn fixed_steps<const M: usize, F: VectorField<M>, I: Integrator<M>>(
    field: &F,
    integrator: &mut I,
    z0: SVector<f64, M>,
    h: f64,
    n: usize,
) -> SVector<f64, M> {
    let mut z = z0;
    for i in 0..n {
        integrator.step(field, i as f64 * h, &mut z, h).unwrap();
    }
    z
}

/// Least-squares slope of log(error) against log(h).
fn observed_order(hs: &[f64], errors: &[f64]) -> f64 {
    let x: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let y: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// Global errors at t = `t_end` for `n = n0, 2 n0, 4 n0, 8 n0` steps on both canonical problems.
fn errors_on_canonical<I1: Integrator<1>, I2: Integrator<2>>(
    make_1: impl Fn() -> I1,
    make_2: impl Fn() -> I2,
    n0: usize,
) -> [(Vec<f64>, Vec<f64>); 2] {
    let decay = ExponentialDecay::new(1.0).unwrap();
    let oscillator = HarmonicOscillator::new(1.0).unwrap();
    let (mut hs, mut decay_errors, mut oscillator_errors) = (vec![], vec![], vec![]);
    for n in [n0, 2 * n0, 4 * n0, 8 * n0] {
        let y0 = Vector1::new(1.0);
        let h = 1.0 / n as f64;
        let y = fixed_steps(&decay, &mut make_1(), y0, h, n);
        decay_errors.push((y - decay.exact(1.0, &y0)).norm());
        let z0 = oscillator.initial_state();
        let h_osc = TAU / n as f64;
        let z = fixed_steps(&oscillator, &mut make_2(), z0, h_osc, n);
        oscillator_errors.push((z - oscillator.exact(TAU, &z0)).norm());
        hs.push(h);
    }
    [(hs.clone(), decay_errors), (hs, oscillator_errors)]
}

#[track_caller]
fn assert_order(errors: &[(Vec<f64>, Vec<f64>); 2], expected: f64, tolerance: f64) {
    for (name, (hs, e)) in ["decay", "oscillator"].iter().zip(errors) {
        let p = observed_order(hs, e);
        eprintln!("{name}: observed order {p:.3} (expected {expected})");
        assert!(
            (p - expected).abs() <= tolerance,
            "{name}: order {p:.3}, errors {e:?}"
        );
    }
}

#[test]
fn rk4_converges_with_order_4() {
    let errors = errors_on_canonical(|| Rk4::new(1.0).unwrap(), || Rk4::new(1.0).unwrap(), 10);
    assert_order(&errors, 4.0, 0.15);
}

#[test]
fn dormand_prince_solution_converges_with_order_5() {
    // Tolerances so loose that every step is accepted: the pair runs as a fixed-step method.
    let loose = AdaptiveSettings::default()
        .with_rtol(1e6)
        .unwrap()
        .with_atol(1e6)
        .unwrap();
    let errors = errors_on_canonical(
        || DormandPrince54::new(loose),
        || DormandPrince54::new(loose),
        8,
    );
    assert_order(&errors, 5.0, 0.3);
}

#[test]
fn implicit_midpoint_converges_with_order_2() {
    let errors = errors_on_canonical(
        || ImplicitMidpoint::new(1.0).unwrap(),
        || ImplicitMidpoint::new(1.0).unwrap(),
        20,
    );
    assert_order(&errors, 2.0, 0.05);
}

#[test]
fn dormand_prince_meets_rtol_on_the_oscillator() {
    let oscillator = HarmonicOscillator::new(TAU).unwrap();
    let z0 = oscillator.initial_state();
    let mut previous_error = f64::INFINITY;
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let settings = AdaptiveSettings::default()
            .with_rtol(rtol)
            .unwrap()
            .with_atol(rtol * 1e-3)
            .unwrap();
        let mut dopri = DormandPrince54::new(settings);
        let run = integrate(
            &oscillator,
            &mut dopri,
            (0.0, 1.0),
            &z0,
            &OutputTimes::Uniform(1e-2),
            &Silent,
        )
        .unwrap();
        let max_error = run
            .times
            .iter()
            .zip(&run.states)
            .map(|(&t, z)| (z - oscillator.exact(t, &z0)).amax() / oscillator.omega().max(1.0))
            .fold(0.0, f64::max);
        // Global error over one period, relative to the amplitude of p (= ω): within 10 rtol.
        assert!(
            max_error <= 10.0 * rtol,
            "rtol {rtol:e}: max error {max_error:.3e}"
        );
        assert!(max_error < previous_error, "error does not fall with rtol");
        previous_error = max_error;
        let stats = run.stats;
        // FSAL: 6 evaluations per attempt, plus 2 for the automatic first step.
        assert_eq!(stats.evaluations, 6 * (stats.steps + stats.rejections) + 2);
    }
}

#[test]
fn dense_output_agrees_with_a_step_aligned_solution() {
    let oscillator = HarmonicOscillator::new(TAU).unwrap();
    let z0 = oscillator.initial_state();
    let settings = AdaptiveSettings::default()
        .with_rtol(1e-9)
        .unwrap()
        .with_atol(1e-12)
        .unwrap();
    let mut dopri = DormandPrince54::new(settings);
    let dense = integrate(
        &oscillator,
        &mut dopri,
        (0.0, 1.0),
        &z0,
        &OutputTimes::Uniform(1e-3),
        &Silent,
    )
    .unwrap();
    let mut rk4 = Rk4::new(1e-3).unwrap();
    let aligned = integrate(
        &oscillator,
        &mut rk4,
        (0.0, 1.0),
        &z0,
        &OutputTimes::Uniform(1e-3),
        &Silent,
    )
    .unwrap();
    assert_eq!(dense.times.len(), 1001);
    assert_eq!(aligned.stats.steps, 1000);
    assert!(dense.stats.steps < 200, "{} steps", dense.stats.steps);
    let max_difference = dense
        .states
        .iter()
        .zip(&aligned.states)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    // RK4 at 1 ms is accurate to ~1e-10 here; the dense output must match to the run's tolerance.
    assert!(max_difference < 1e-7, "max difference {max_difference:.3e}");
}

#[test]
fn dense_output_matches_the_step_ends() {
    let oscillator = HarmonicOscillator::new(3.0).unwrap();
    let mut dopri = DormandPrince54::new(AdaptiveSettings::default());
    let mut z = oscillator.initial_state();
    let z_start = z;
    let report = dopri.step(&oscillator, 0.5, &mut z, 0.1).unwrap();
    let segment = pkm_integrators::Scheme::<2>::dense_output(&dopri).unwrap();
    assert!((segment.evaluate(0.5) - z_start).amax() < 1e-15);
    assert!((segment.evaluate(0.5 + report.h_taken) - z).amax() < 1e-14);
}

#[test]
fn implicit_midpoint_conserves_the_quadratic_invariant() {
    let oscillator = HarmonicOscillator::new(1.0).unwrap();
    let z0 = oscillator.initial_state();
    let e0 = oscillator.energy(&z0);
    let h = TAU / 20.0;
    let mut midpoint = ImplicitMidpoint::new(h).unwrap();
    let periods = 10_000.0;
    let run = integrate(
        &oscillator,
        &mut midpoint,
        (0.0, periods * TAU),
        &z0,
        &OutputTimes::Steps,
        &Silent,
    )
    .unwrap();
    let max_drift = run
        .states
        .iter()
        .map(|z| (oscillator.energy(z) - e0).abs())
        .fold(0.0, f64::max);
    // Each step conserves E up to the stage tolerance (1e-13 relative) and round-off, so the
    // drift over N steps stays below N × tolerance (measured: 1.2e-9 after 2e5 steps).
    let bound = run.stats.steps as f64 * midpoint.tolerance() * e0;
    assert!(
        max_drift <= bound,
        "energy drift {max_drift:.3e} over {} steps",
        run.stats.steps
    );
}

#[test]
fn implicit_midpoint_keeps_pendulum_energy_bounded_where_rk4_drifts() {
    let pendulum = Pendulum::new(1.0).unwrap();
    let z0 = SVector::<f64, 2>::new(1.0, 0.0);
    let e0 = pendulum.energy(&z0);
    let h = 0.2;
    let t_end = 10_000.0 * TAU; // ≈ 1e4 periods (the 1 rad pendulum's period is ≈ 6.7 s)
    let energy_errors = |states: &[SVector<f64, 2>]| {
        let errors: Vec<f64> = states
            .iter()
            .map(|z| (pendulum.energy(z) - e0).abs() / e0)
            .collect();
        let early = errors[..errors.len() / 100]
            .iter()
            .copied()
            .fold(0.0, f64::max);
        let late = errors[errors.len() - errors.len() / 100..]
            .iter()
            .copied()
            .fold(0.0, f64::max);
        (early, late)
    };
    let mut midpoint = ImplicitMidpoint::new(h).unwrap();
    let symplectic = integrate(
        &pendulum,
        &mut midpoint,
        (0.0, t_end),
        &z0,
        &OutputTimes::Steps,
        &Silent,
    )
    .unwrap();
    let (early, late) = energy_errors(&symplectic.states);
    // Bounded: the last 1 % of the run errs no more than 1.5 × the first 1 %.
    assert!(
        late <= 1.5 * early && late < 1e-2,
        "midpoint: early {early:.3e}, late {late:.3e}"
    );
    let mut rk4 = Rk4::new(h).unwrap();
    let classical = integrate(
        &pendulum,
        &mut rk4,
        (0.0, t_end),
        &z0,
        &OutputTimes::Steps,
        &Silent,
    )
    .unwrap();
    let (rk4_early, rk4_late) = energy_errors(&classical.states);
    // RK4 dissipates energy secularly: its late error exceeds its early error tenfold.
    assert!(
        rk4_late > 10.0 * rk4_early,
        "rk4: early {rk4_early:.3e}, late {rk4_late:.3e}"
    );
}

/// Six uncoupled oscillators in Miller's state layout $z = (p, x)$, 6 momenta then 6 coordinates.
struct SixOscillators;

impl SixOscillators {
    fn omega(i: usize) -> f64 {
        5.0 + 7.0 * i as f64
    }
}

impl VectorField<12> for SixOscillators {
    fn rhs(
        &self,
        _t: f64,
        z: &SVector<f64, 12>,
        dz: &mut SVector<f64, 12>,
    ) -> Result<(), pkm_traits::RhsError> {
        for i in 0..6 {
            dz[i] = -Self::omega(i).powi(2) * z[6 + i];
            dz[6 + i] = z[i];
        }
        Ok(())
    }
}

#[test]
fn twelve_state_cycle_is_sampled_every_millisecond() {
    let mut z0 = SVector::<f64, 12>::zeros();
    z0.fixed_rows_mut::<6>(6).fill(1.0);
    let settings = AdaptiveSettings::default()
        .with_rtol(1e-8)
        .unwrap()
        .with_atol(1e-10)
        .unwrap();
    let mut dopri = DormandPrince54::<12>::new(settings);
    let run = integrate(
        &SixOscillators,
        &mut dopri,
        (0.0, 0.5),
        &z0,
        &OutputTimes::Uniform(1e-3),
        &Silent,
    )
    .unwrap();
    assert_eq!(run.times.len(), 501);
    assert!((run.times[500] - 0.5).abs() < 1e-15);
    for (&t, z) in run.times.iter().zip(&run.states) {
        for i in 0..6 {
            let w = SixOscillators::omega(i);
            assert!((z[6 + i] - (w * t).cos()).abs() < 1e-6, "x_{i}({t})");
            assert!((z[i] + w * (w * t).sin()).abs() < 1e-6 * w, "p_{i}({t})");
        }
    }
}
