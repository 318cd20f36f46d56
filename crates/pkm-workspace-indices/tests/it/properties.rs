//! Properties of pkm-workspace-indices: condition numbers (SVD and closed-form 3×3), the
//! deterministic parallel reduction, and the cross-section means against closed forms.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{Matrix3, Matrix6};
use pkm_traits::{Extents, Silent, SlicedRegion};
use pkm_workspace_indices::{
    Accumulator, GridRule, chunked_reduce, condition_number, inverse_condition_number,
    inverse_condition_number_3x3, mean_by_grid, mean_by_quadrature, space_utilization,
};
use proptest::prelude::*;

fn matrix3() -> impl Strategy<Value = Matrix3<f64>> {
    prop::array::uniform9(-10.0..10.0f64).prop_map(|a| Matrix3::from_row_slice(&a))
}

proptest! {
    #[test]
    fn condition_number_is_at_least_one_and_inverse_in_unit_interval(j in matrix3()) {
        let inv = inverse_condition_number(&j);
        prop_assert!((0.0..=1.0).contains(&inv));
        prop_assert!(condition_number(&j) >= 1.0);
    }

    #[test]
    fn condition_number_is_invariant_under_uniform_scaling(j in matrix3(), s in 1e-3..1e3f64) {
        let a = inverse_condition_number(&j);
        let b = inverse_condition_number(&(j * s));
        prop_assert!((a - b).abs() <= 1e-9 * a.max(1e-300) + 1e-14);
    }

    #[test]
    fn condition_number_is_invariant_under_rotations(j in matrix3(), angle in -3.0..3.0f64) {
        let r = nalgebra::Rotation3::from_euler_angles(angle, 0.3 * angle, -0.7).into_inner();
        let a = inverse_condition_number(&j);
        let b = inverse_condition_number(&(r * j * r.transpose()));
        prop_assert!((a - b).abs() <= 1e-9);
    }

    #[test]
    fn condition_number_of_a_diagonal_matrix_is_its_extreme_ratio(d in prop::array::uniform6(0.1..10.0f64)) {
        let j = Matrix6::from_diagonal(&nalgebra::Vector6::from_row_slice(&d));
        let (lo, hi) = d.iter().fold((f64::MAX, 0.0f64), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
        prop_assert!((condition_number(&j) - hi / lo).abs() <= 1e-12 * hi / lo);
    }
}

#[test]
fn singular_and_non_finite_matrices_have_zero_inverse_condition() {
    let singular = Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 0.0);
    assert!(inverse_condition_number(&singular) < 1e-15);
    assert!(inverse_condition_number(&Matrix3::zeros()).abs() < f64::MIN_POSITIVE);
    let mut nan = Matrix3::identity();
    nan[(1, 2)] = f64::NAN;
    assert!(inverse_condition_number(&nan).abs() < f64::MIN_POSITIVE);
    assert!(condition_number(&nan).is_infinite());
}

#[derive(Default)]
struct Sum(f64);

impl Accumulator for Sum {
    fn merge(&mut self, later: Self) {
        self.0 += later.0;
    }
}

fn harmonic_noise(n: u64) -> f64 {
    chunked_reduce(n, &Silent, |acc: &mut Sum, i| {
        acc.0 += ((i as f64) * 0.618).sin() / (1.0 + i as f64)
    })
    .unwrap()
    .0
}

#[test]
fn chunked_reduce_gives_the_same_bits_for_1_2_and_8_threads() {
    let n = 1_000_003;
    let bits: Vec<u64> = [1, 2, 8]
        .iter()
        .map(|&threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| harmonic_noise(n)).to_bits()
        })
        .collect();
    assert_eq!(bits[0], bits[1]);
    assert_eq!(bits[0], bits[2]);
}

#[test]
fn chunked_reduce_stops_when_cancelled() {
    struct Stop;
    impl pkm_traits::Progress for Stop {
        fn is_cancelled(&self) -> bool {
            true
        }
    }
    let result = chunked_reduce(10_000, &Stop, |acc: &mut Sum, _| acc.0 += 1.0);
    assert!(result.is_err());
}

/// The unit disc, split at its centre.
struct UnitDisc;

impl SlicedRegion for UnitDisc {
    fn slice(&self, y: f64) -> Option<(f64, f64)> {
        let s = 1.0 - y * y;
        (s >= 0.0).then(|| (-s.sqrt(), s.sqrt()))
    }
    fn breakpoints(&self) -> &[f64] {
        &[-1.0, 0.0, 1.0]
    }
    fn extents(&self) -> Extents {
        Extents {
            y_min: -1.0,
            y_max: 1.0,
            z_min: -1.0,
            z_max: 1.0,
        }
    }
    fn area(&self) -> f64 {
        std::f64::consts::PI
    }
}

#[test]
fn quadrature_mean_of_r_squared_over_the_disc_is_one_half() {
    let mean = mean_by_quadrature(&UnitDisc, |y, z| y * y + z * z, 24).unwrap();
    assert!((mean - 0.5).abs() < 1e-4, "{mean}");
}

#[test]
fn paper_grid_rule_uses_more_than_5000_points_and_estimates_the_area() {
    let grid = mean_by_grid(&UnitDisc, |y, z| y * y + z * z, &GridRule::default()).unwrap();
    assert!(grid.n_points > 5000);
    assert!(
        (grid.area / std::f64::consts::PI - 1.0).abs() < 2e-3,
        "{}",
        grid.area
    );
    assert!((grid.mean - 0.5).abs() < 2e-3, "{}", grid.mean);
}

#[test]
fn space_utilization_of_the_disc_in_its_box_is_pi_over_4() {
    let eta2 = space_utilization(&UnitDisc, &[[0.0, 0.0]]).unwrap();
    assert!((eta2 - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    let wider = space_utilization(&UnitDisc, &[[3.0, 0.0]]).unwrap();
    assert!((wider - std::f64::consts::PI / 8.0).abs() < 1e-15);
    assert!(space_utilization(&UnitDisc, &[[f64::NAN, 0.0]]).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn closed_form_3x3_matches_the_svd(entries in prop::array::uniform9(-3.0..3.0f64)) {
        let j = Matrix3::from_row_slice(&entries);
        let closed = inverse_condition_number_3x3(&j);
        let svd = inverse_condition_number(&j);
        prop_assert!((closed - svd).abs() < 1e-9 * (1.0 + 1.0 / svd.max(1e-300)).min(1e6), "{closed} vs {svd}");
        prop_assert!((0.0..=1.0).contains(&closed));
    }

    #[test]
    fn closed_form_3x3_is_scale_invariant(entries in prop::array::uniform9(-3.0..3.0f64), s in 0.01..100.0f64) {
        let j = Matrix3::from_row_slice(&entries);
        let a = inverse_condition_number_3x3(&j);
        let b = inverse_condition_number_3x3(&(j * s));
        prop_assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
}

/// A matrix $U\,\mathrm{diag}(\sigma)\,V^\top$ of known singular values from two rotations.
fn with_singular_values(
    sigma: [f64; 3],
    u: nalgebra::Vector3<f64>,
    v: nalgebra::Vector3<f64>,
) -> Matrix3<f64> {
    let rotation = |w: nalgebra::Vector3<f64>| nalgebra::Rotation3::new(w).into_inner();
    rotation(u) * Matrix3::from_diagonal(&sigma.into()) * rotation(v).transpose()
}

proptest! {
    /// The closed-form 1/κ (scalar and lanes) against matrices of known singular values, over
    /// the whole range 1/κ ∈ [1e-6, 1], the middle singular value anywhere from σ_max down to
    /// σ_min (two close small singular values made the old formula 41 % wrong at 1/κ ≈ 1e-4).
    /// The reference σ_min/σ_max is exact for the nominal matrix; rounding the product
    /// perturbs it by about ε·κ, 2e-10 at most here, well within the tolerance.
    #[test]
    fn closed_form_inverse_condition_matches_the_singular_values(
        log_kappa in 0.0_f64..6.0,
        mid in 0.0_f64..=1.0,
        scale in -3.0_f64..3.0,
        u in proptest::array::uniform3(-3.0_f64..3.0),
        v in proptest::array::uniform3(-3.0_f64..3.0),
    ) {
        let inverse = 10f64.powf(-log_kappa);
        // σ_mid between σ_min and σ_max, log-uniform, including both ends.
        let sigma_mid = inverse.powf(mid);
        let s = 10f64.powf(scale);
        let j = with_singular_values([s, s * sigma_mid, s * inverse], u.into(), v.into());
        let closed = inverse_condition_number_3x3(&j);
        let relative = (closed - inverse).abs() / inverse;
        prop_assert!(relative < 1e-7, "1/κ = {inverse:e}, σ_mid = {sigma_mid:e}: {closed:e} ({relative:e})");
        let mut lanes = [[0.0; pkm_workspace_indices::LANES]; 9];
        for (k, entry) in lanes.iter_mut().enumerate() {
            entry[0] = j[(k / 3, k % 3)];
        }
        let lane = pkm_workspace_indices::inverse_condition_number_3x3_lanes(&lanes)[0];
        let relative = (lane - inverse).abs() / inverse;
        prop_assert!(relative < 1e-7, "lanes: 1/κ = {inverse:e}: {lane:e} ({relative:e})");
    }
}
