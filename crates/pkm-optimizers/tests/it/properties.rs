//! Property tests of pkm-optimizers: grid searches recover a known minimum to their resolution
//! and give the same bits for 1, 2 and 8 rayon threads.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_optimizers::{
    GridAxis, GridSearch, LatticeLevel, RefinementSettings, Sense, Termination,
    lattice_refined_search, refined_grid_search,
};
use pkm_traits::{Bounds, Objective, ObjectiveError, Silent};
use proptest::prelude::*;

/// $\sum_k (p_k - c_k)^2$ on $[-1, 1]^3$.
struct Bowl {
    centre: [f64; 3],
    bounds: [Bounds; 3],
}

impl Objective for Bowl {
    fn dimension(&self) -> usize {
        3
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        Ok(p.iter()
            .zip(&self.centre)
            .map(|(x, c)| (x - c).powi(2))
            .sum())
    }
}

fn bowl(centre: [f64; 3]) -> Bowl {
    Bowl {
        centre,
        bounds: [Bounds::new(-1.0, 1.0).unwrap(); 3],
    }
}

const LEVELS: [LatticeLevel; 2] = [
    LatticeLevel {
        step: 0.05,
        half_width: 2,
    },
    LatticeLevel {
        step: 0.01,
        half_width: 3,
    },
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn lattice_refinement_recovers_the_minimum_to_the_finest_step(c in prop::array::uniform3(-0.95..0.95f64)) {
        let coarse = GridSearch::new(vec![GridAxis::with_step(-1.0, 1.0, 0.1).unwrap(); 3]).unwrap();
        let result = lattice_refined_search(&bowl(c), Sense::Minimise, &coarse, &LEVELS, &Silent).unwrap();
        for k in 0..3 {
            prop_assert!((result.best[k] - c[k]).abs() <= 0.005 + 1e-9, "{:?} vs {c:?}", result.best);
        }
    }

    #[test]
    fn halving_refinement_recovers_the_minimum_to_its_resolution(c in prop::array::uniform3(-0.95..0.95f64)) {
        let coarse = GridSearch::new(vec![GridAxis::new(-1.0, 1.0, 11).unwrap(); 3]).unwrap();
        let settings = RefinementSettings::default();
        let result = refined_grid_search(&bowl(c), Sense::Minimise, &coarse, &[1e-3; 3], &settings, &Silent).unwrap();
        for k in 0..3 {
            prop_assert!((result.best[k] - c[k]).abs() <= 1e-3, "{:?} vs {c:?}", result.best);
        }
    }
}

#[test]
fn grid_searches_give_the_same_bits_for_1_2_and_8_threads() {
    let objective = bowl([0.123, -0.456, 0.789]);
    let coarse = GridSearch::new(vec![GridAxis::with_step(-1.0, 1.0, 0.1).unwrap(); 3])
        .unwrap()
        .keeping_landscape();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            lattice_refined_search(&objective, Sense::Minimise, &coarse, &LEVELS, &Silent).unwrap()
        })
    };
    let reference = run(1);
    for threads in [2, 8] {
        let other = run(threads);
        assert_eq!(other.evaluations, reference.evaluations);
        assert_eq!(other.best_value.to_bits(), reference.best_value.to_bits());
        let bits =
            |r: &pkm_optimizers::GridResult| r.best.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&other), bits(&reference));
        assert_eq!(other.landscape, reference.landscape);
    }
}

/// $f(x) = -x$ on $[-10, 10]$: every window's best node is its upper edge.
struct Ramp([Bounds; 1]);

impl Objective for Ramp {
    fn dimension(&self) -> usize {
        1
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        Ok(-p[0])
    }
}

#[test]
fn grid_searches_say_why_they_stopped() {
    let c = [0.123, -0.456, 0.789];
    let coarse = GridSearch::new(vec![GridAxis::new(-1.0, 1.0, 11).unwrap(); 3]).unwrap();
    let plain = pkm_optimizers::grid_search(&bowl(c), Sense::Minimise, &coarse, &Silent).unwrap();
    assert_eq!(
        plain.termination,
        Termination::Converged {
            criterion: "every node evaluated"
        }
    );
    let refine = |max_levels| {
        let settings = RefinementSettings {
            max_levels,
            ..RefinementSettings::default()
        };
        refined_grid_search(
            &bowl(c),
            Sense::Minimise,
            &coarse,
            &[1e-3; 3],
            &settings,
            &Silent,
        )
        .unwrap()
    };
    // 0.2 halves to below 1e-3 in 8 levels.
    assert_eq!(
        refine(20).termination,
        Termination::Converged {
            criterion: "resolution reached"
        }
    );
    assert_eq!(refine(3).termination, Termination::MaxIterations);
    // The bowl's optimum settles inside the windows; the ramp's keeps leaving them.
    let levels = [LatticeLevel {
        step: 0.01,
        half_width: 2,
    }];
    let settled =
        lattice_refined_search(&bowl(c), Sense::Minimise, &coarse, &levels, &Silent).unwrap();
    assert_eq!(
        settled.termination,
        Termination::Converged {
            criterion: "optimum inside every window"
        }
    );
    let ramp = Ramp([Bounds::new(-10.0, 10.0).unwrap()]);
    let short = GridSearch::new(vec![GridAxis::new(-1.0, 1.0, 3).unwrap()]).unwrap();
    let moving = lattice_refined_search(&ramp, Sense::Minimise, &short, &levels, &Silent).unwrap();
    assert_eq!(moving.termination, Termination::MaxIterations);
    assert!(
        moving.best[0] > 1.0 && moving.best[0] < 10.0,
        "{:?}",
        moving.best
    );
}
