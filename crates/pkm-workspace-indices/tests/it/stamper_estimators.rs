//! Samplers, the hemisphere estimators and the closed-form 3×3 condition number.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{Matrix3, Vector3};
use pkm_traits::Silent;
use pkm_workspace_indices::{
    IndexError, Sampler, hemisphere_estimate, inverse_condition_number,
    inverse_condition_number_3x3,
};
use proptest::prelude::*;
use std::f64::consts::PI;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn closed_form_condition_matches_svd(e in prop::array::uniform9(-3.0f64..3.0)) {
        let j = Matrix3::from_row_slice(&e);
        let svd = inverse_condition_number(&j);
        prop_assert!((inverse_condition_number_3x3(&j) - svd).abs() < 1e-9, "{j}");
    }

    #[test]
    fn hemisphere_points_lie_in_the_unit_hemisphere(i in 0u64..1_000_000, seed in 0u64..100) {
        for s in [Sampler::MonteCarlo { seed }, Sampler::Sobol { seed }] {
            let p = s.in_unit_hemisphere(i);
            prop_assert!(p.norm() <= 1.0 + 1e-12 && p.z >= 0.0);
            prop_assert_eq!(p, s.in_unit_hemisphere(i));
        }
    }
}

#[test]
fn near_singular_matrix_keeps_relative_accuracy() {
    let j = Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1e-9);
    assert!((inverse_condition_number_3x3(&j) / 1e-9 - 1.0).abs() < 1e-6);
    assert!(inverse_condition_number_3x3(&Matrix3::zeros()).abs() < 1e-300);
}

/// Ball of radius 0.5 centred at (0, 0, 0.5) inside the hemisphere of radius 1: W = π/6.
fn ball(p: &Vector3<f64>) -> Option<f64> {
    ((p - Vector3::new(0.0, 0.0, 0.5)).norm() <= 0.5).then_some(2.0)
}

#[test]
fn volume_of_a_ball_within_four_standard_errors() {
    for sampler in [Sampler::MonteCarlo { seed: 3 }, Sampler::Sobol { seed: 3 }] {
        let points = sampler.unit_hemisphere_points(50_000).unwrap();
        let e = hemisphere_estimate(&points, 1.0, &Silent, ball).unwrap();
        assert!(
            (e.volume - PI / 6.0).abs() < 4.0 * e.volume_se,
            "{sampler:?} {e:?}"
        );
        // f = 2 inside: eta = 2 W exactly, and its standard error is twice W's.
        assert!((e.eta - 2.0 * e.volume).abs() < 1e-12);
        assert!((e.eta_se - 2.0 * e.volume_se).abs() < 1e-12);
        // GCI = η/W is the mean of f over the workspace: 2.
        assert!((e.gci().unwrap() - 2.0).abs() < 1e-12);
    }
}

#[test]
fn sobol_beats_monte_carlo_on_the_ball() {
    let n = 1 << 14;
    let err = |s: Sampler| {
        let points = s.unit_hemisphere_points(n).unwrap();
        (hemisphere_estimate(&points, 1.0, &Silent, ball)
            .unwrap()
            .volume
            - PI / 6.0)
            .abs()
    };
    let qmc = err(Sampler::Sobol { seed: 11 });
    let mc: f64 = (0..8)
        .map(|s| err(Sampler::MonteCarlo { seed: s }))
        .sum::<f64>()
        / 8.0;
    assert!(qmc < mc, "sobol {qmc} vs mean monte carlo {mc}");
}

#[test]
fn grid_sampler_covers_the_box() {
    let s = Sampler::Grid { per_axis: 4 };
    let lo = Vector3::new(-1.0, 0.0, 2.0);
    let hi = Vector3::new(1.0, 1.0, 3.0);
    let mean: Vector3<f64> = (0..64).map(|i| s.in_box(i, &lo, &hi)).sum::<Vector3<f64>>() / 64.0;
    assert!((mean - Vector3::new(0.0, 0.5, 2.5)).amax() < 1e-12);
}

#[test]
fn bad_input_is_a_typed_error() {
    let s = Sampler::MonteCarlo { seed: 1 };
    assert!(matches!(
        s.unit_hemisphere_points(0),
        Err(IndexError::EmptySample { .. })
    ));
    let points = s.unit_hemisphere_points(10).unwrap();
    assert!(hemisphere_estimate(&points, f64::NAN, &Silent, ball).is_err());
    assert!(hemisphere_estimate(&points, -1.0, &Silent, ball).is_err());
    assert!(hemisphere_estimate(&[], 1.0, &Silent, ball).is_err());
}
