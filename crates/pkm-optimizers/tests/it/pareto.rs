//! The Pareto front and its weight intervals against brute force: every pair of designs for
//! dominance, and a fine sweep of weights for the designs each weighting selects.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_optimizers::{Sense, pareto_front};
use proptest::prelude::*;

/// Larger is better: the value itself when maximised, its negation when minimised.
fn goodness(v: f64, sense: Sense) -> f64 {
    match sense {
        Sense::Maximise => v,
        Sense::Minimise => -v,
    }
}

/// Whether `a` dominates `b` (at least as good in every objective, better in one).
fn dominates(a: &[f64], b: &[f64], senses: &[Sense]) -> bool {
    let g = |v: &[f64], k: usize| goodness(v[k], senses[k]);
    (0..senses.len()).all(|k| g(a, k) >= g(b, k)) && (0..senses.len()).any(|k| g(a, k) > g(b, k))
}

/// The front by comparing every pair.
fn brute_force_front(values: &[Vec<f64>], senses: &[Sense]) -> Vec<usize> {
    (0..values.len())
        .filter(|&i| !values.iter().any(|v| dominates(v, &values[i], senses)))
        .collect()
}

/// Designs on a coarse lattice, so that ties and duplicates occur.
fn designs(k: usize) -> impl Strategy<Value = Vec<Vec<f64>>> {
    prop::collection::vec(
        prop::collection::vec((-8i32..8).prop_map(|v| f64::from(v) / 4.0), k),
        1..40,
    )
}

fn senses(k: usize) -> impl Strategy<Value = Vec<Sense>> {
    prop::collection::vec(
        prop::sample::select(vec![Sense::Minimise, Sense::Maximise]),
        k,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn the_front_is_the_set_no_design_dominates(
        (values, senses) in (2usize..5).prop_flat_map(|k| (designs(k), senses(k)))
    ) {
        let front = pareto_front(&values, &senses).unwrap();
        prop_assert_eq!(&front.members, &brute_force_front(&values, &senses));
        prop_assert_eq!(front.weight_intervals.is_some(), senses.len() == 2);
    }

    /// For two objectives, a weight w selects a member (it maximises w·γ₁ + (1 − w)·γ₂ over
    /// every design) exactly when w lies in the member's interval, up to rounding at the ends.
    #[test]
    fn weight_intervals_are_the_weights_that_select_each_design(
        values in designs(2),
        senses in senses(2),
    ) {
        let front = pareto_front(&values, &senses).unwrap();
        let intervals = front.weight_intervals.clone().unwrap();
        let utility = |v: &[f64], w: f64| {
            w * goodness(v[0], senses[0]) + (1.0 - w) * goodness(v[1], senses[1])
        };
        for step in 0..=200 {
            let w = f64::from(step) / 200.0;
            let best = values.iter().map(|v| utility(v, w)).fold(f64::NEG_INFINITY, f64::max);
            for (&i, interval) in front.members.iter().zip(&intervals) {
                let selects = utility(&values[i], w) >= best - 1e-12;
                let inside = interval.is_some_and(|(lo, hi)| lo - 1e-9 <= w && w <= hi + 1e-9);
                let strictly = interval.is_some_and(|(lo, hi)| lo + 1e-9 < w && w < hi - 1e-9);
                prop_assert!(!selects || inside, "w {w}: design {i} selected outside {interval:?}");
                prop_assert!(!strictly || selects, "w {w}: design {i} not selected inside {interval:?}");
            }
            // Some member is selected by every weight.
            prop_assert!(front.members.iter().any(|&i| utility(&values[i], w) >= best - 1e-12));
        }
    }
}

#[test]
fn dominated_points_go_and_ties_stay() {
    let v = [
        [1.0, 0.0],
        [0.0, 1.0],
        [0.5, 0.5],
        [0.4, 0.4],
        [0.5, 0.5],
        [1.0, -1.0],
    ];
    let front = pareto_front(&v, &[Sense::Maximise; 2]).unwrap();
    assert_eq!(front.members, [0, 1, 2, 4]);
    // Minimising both turns the picture over: (0.4, 0.4) and (1, −1) are the front then.
    let front = pareto_front(&v, &[Sense::Minimise; 2]).unwrap();
    assert_eq!(front.members, [1, 3, 5]);
}

#[test]
fn weight_intervals_of_a_convex_front_tile_the_unit_interval() {
    // (1, 0), (0.6, 0.6), (0, 1): the middle point wins for w in [0.4, 0.6].
    let front = pareto_front(&[[1.0, 0.0], [0.6, 0.6], [0.0, 1.0]], &[Sense::Maximise; 2]).unwrap();
    let w = front.weight_intervals.unwrap();
    let close = |got: Option<(f64, f64)>, lo: f64, hi: f64| {
        got.is_some_and(|(a, b)| (a - lo).abs() < 1e-12 && (b - hi).abs() < 1e-12)
    };
    assert!(
        close(w[0], 0.6, 1.0) && close(w[1], 0.4, 0.6) && close(w[2], 0.0, 0.4),
        "{w:?}"
    );
}

#[test]
fn hostile_input_is_refused() {
    assert!(pareto_front(&[[1.0, 2.0]], &[Sense::Maximise]).is_err());
    assert!(pareto_front(&[vec![1.0, 2.0], vec![1.0]], &[Sense::Maximise; 2]).is_err());
    for bad in [f64::NAN, f64::INFINITY] {
        assert!(
            pareto_front(&[[1.0, bad]], &[Sense::Maximise; 2]).is_err(),
            "{bad}"
        );
    }
    let empty: [[f64; 2]; 0] = [];
    let front = pareto_front(&empty, &[Sense::Maximise; 2]).unwrap();
    assert!(front.members.is_empty());
}
