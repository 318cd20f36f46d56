use criterion::Criterion;
use pkm::integrators::test_problems::HarmonicOscillator;
use pkm::integrators::{AdaptiveSettings, DormandPrince54, OutputTimes, Rk4, integrate};
use pkm_traits::Silent;
use std::f64::consts::TAU;
use std::hint::black_box;

/// Ten periods of the unit harmonic oscillator, sampled at 1 000 points per period.
pub(crate) fn harmonic_oscillator(c: &mut Criterion) {
    let oscillator = HarmonicOscillator::new(1.0).unwrap_or_else(|e| unreachable!("{e}"));
    let z0 = oscillator.initial_state();
    let span = (0.0, 10.0 * TAU);
    let output = OutputTimes::Uniform(TAU / 1000.0);
    let settings = AdaptiveSettings::default()
        .with_rtol(1e-9)
        .and_then(|s| s.with_atol(1e-12))
        .unwrap_or_else(|e| unreachable!("{e}"));
    let mut group = c.benchmark_group("integrators/harmonic_oscillator_10_periods");
    group.sample_size(20);
    group.bench_function("dormand_prince54_rtol_1e-9", |b| {
        b.iter(|| {
            let mut dopri = DormandPrince54::new(settings);
            integrate(
                &oscillator,
                &mut dopri,
                span,
                black_box(&z0),
                &output,
                &Silent,
            )
        })
    });
    group.bench_function("rk4_h_period_over_1000", |b| {
        b.iter(|| {
            let mut rk4 = Rk4::new(TAU / 1000.0).unwrap_or_else(|e| unreachable!("{e}"));
            integrate(
                &oscillator,
                &mut rk4,
                span,
                black_box(&z0),
                &output,
                &Silent,
            )
        })
    });
    group.finish();
}
