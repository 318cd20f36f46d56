//! Every registered experiment, run in quick mode: no comparison may fail.

use pkm::papers::{self, Context, Mode, Verdict};
use pkm_traits::Silent;

/// Runs the experiments whose id starts with `prefix` in quick mode and checks every verdict.
#[track_caller]
fn run_quick(prefix: &str) {
    let experiments: Vec<_> = papers::all()
        .into_iter()
        .filter(|e| e.matches(prefix))
        .collect();
    assert!(
        !experiments.is_empty(),
        "vacuous: no experiment registered under {prefix}"
    );
    let context = Context {
        mode: Mode::Quick,
        progress: &Silent,
    };
    for experiment in experiments {
        let outcome = (experiment.run)(&context)
            .unwrap_or_else(|e| panic!("{} failed to run: {e}", experiment.id));
        assert!(
            !outcome.comparisons.is_empty(),
            "{} reported nothing",
            experiment.id
        );
        for row in &outcome.comparisons {
            assert!(
                row.value.is_finite(),
                "{} {} is not finite",
                row.id,
                row.quantity
            );
            assert_ne!(
                row.verdict,
                Verdict::Fail,
                "{} {}: pkm {} vs paper {:?} (tolerance {:?}) {}",
                row.id,
                row.quantity,
                row.value,
                row.paper_value,
                row.tolerance,
                row.note
            );
        }
    }
}

#[test]
fn stamper1997_reproduces_in_quick_mode() {
    run_quick("stamper1997")
}
