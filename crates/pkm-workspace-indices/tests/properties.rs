//! Properties of the condition indices and of the deterministic parallel reduction.
#![allow(clippy::unwrap_used)]

use nalgebra::{Matrix3, Matrix6};
use pkm_traits::Silent;
use pkm_workspace_indices::{
    Accumulator, chunked_reduce, condition_number, inverse_condition_number,
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
