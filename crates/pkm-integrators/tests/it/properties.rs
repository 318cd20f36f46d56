//! Property tests: linear systems with random coefficients against their closed form, time
//! reversal of the symmetric implicit midpoint rule, the order of RK4 on random decay rates.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use nalgebra::{Vector1, Vector2};
use pkm_integrators::test_problems::{ExponentialDecay, Pendulum, RotatingDecay};
use pkm_integrators::{
    AdaptiveSettings, DormandPrince54, ImplicitMidpoint, OutputTimes, Rk4, integrate,
};
use pkm_traits::{Integrator, Silent};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// DP54 at rtol 1e-9 tracks $e^{at} R(bt) z_0$ at 20 dense samples within 1e-6 relative.
    #[test]
    fn dormand_prince_follows_random_linear_systems(
        a in -1.0..1.0f64, b in -5.0..5.0f64, q0 in -2.0..2.0f64, p0 in -2.0..2.0f64, t1 in 0.1..2.0f64,
    ) {
        let system = RotatingDecay::new(a, b).unwrap();
        let z0 = Vector2::new(q0, p0);
        let settings = AdaptiveSettings::default().with_rtol(1e-9).unwrap().with_atol(1e-12).unwrap();
        let mut dopri = DormandPrince54::new(settings);
        let run = integrate(&system, &mut dopri, (0.0, t1), &z0, &OutputTimes::Uniform(t1 / 20.0), &Silent)
            .unwrap();
        prop_assert_eq!(run.times.len(), 21);
        for (&t, z) in run.times.iter().zip(&run.states) {
            let exact = system.exact(t, &z0);
            let error = (z - exact).amax();
            prop_assert!(error <= 1e-6 * exact.amax().max(1e-3), "t = {}: error {:.3e}", t, error);
        }
    }

    /// Implicit midpoint is symmetric: n steps of h then n steps of −h return to z0 (up to the
    /// stage tolerance and round-off).
    #[test]
    fn implicit_midpoint_is_time_reversible(
        theta0 in -2.0..2.0f64, p0 in -1.0..1.0f64, h in 0.01..0.2f64, n in 1usize..200,
    ) {
        let pendulum = Pendulum::new(1.5).unwrap();
        let z0 = Vector2::new(theta0, p0);
        let mut midpoint = ImplicitMidpoint::new(h).unwrap();
        let mut z = z0;
        for i in 0..n {
            midpoint.step(&pendulum, i as f64 * h, &mut z, h).unwrap();
        }
        for i in (0..n).rev() {
            midpoint.step(&pendulum, (i + 1) as f64 * h, &mut z, -h).unwrap();
        }
        let error = (z - z0).amax();
        prop_assert!(error <= 1e-10, "returned with error {:.3e} after {} steps", error, n);
    }

    /// RK4's error ratio between steps h and h/2 on $\dot y = -\lambda y$ is $2^4$ within 10 %.
    #[test]
    fn rk4_halving_the_step_divides_the_error_by_16(lambda in 0.5..3.0f64) {
        let decay = ExponentialDecay::new(lambda).unwrap();
        let y0 = Vector1::new(1.0);
        let error = |n: usize| {
            let h = 1.0 / n as f64;
            let mut y = y0;
            for i in 0..n {
                Rk4::new(h).unwrap().step(&decay, i as f64 * h, &mut y, h).unwrap();
            }
            (y - decay.exact(1.0, &y0)).norm()
        };
        let ratio = error(20) / error(40);
        prop_assert!((ratio / 16.0 - 1.0).abs() < 0.1, "ratio {:.3}", ratio);
    }

    /// The dense output reproduces both ends of every accepted step.
    #[test]
    fn dense_segment_interpolates_the_step_ends(a in -1.0..1.0f64, b in -5.0..5.0f64, h in 1e-3..0.5f64) {
        let system = RotatingDecay::new(a, b).unwrap();
        let mut dopri = DormandPrince54::new(AdaptiveSettings::default());
        let mut z = Vector2::new(1.0, -0.5);
        let z_start = z;
        let report = dopri.step(&system, 0.3, &mut z, h).unwrap();
        let segment = pkm_integrators::Scheme::<2>::dense_output(&dopri).unwrap();
        prop_assert!((segment.evaluate(0.3) - z_start).amax() <= 1e-15);
        prop_assert!((segment.evaluate(0.3 + report.h_taken) - z).amax() <= 1e-14);
    }
}
