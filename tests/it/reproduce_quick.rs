//! Every registered experiment, run in quick mode: no comparison may fail.

use pkm::papers::{self, Comparison, Context, Mode, Verdict};
use pkm_traits::Silent;
use std::path::Path;

/// An `erratum` row must point at a heading of `docs/conventions.md` that exists.
#[track_caller]
fn assert_erratum_is_documented(row: &Comparison, conventions: &str) {
    let anchor = row
        .note
        .split("docs/conventions.md#")
        .nth(1)
        .and_then(|rest| rest.split([';', ' ', ')']).next())
        .unwrap_or_else(|| panic!("{} {}: erratum without an anchor", row.id, row.quantity));
    assert!(
        conventions.contains(anchor),
        "{} {}: docs/conventions.md has no heading `{anchor}`",
        row.id,
        row.quantity
    );
}

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
    let conventions =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/conventions.md"))
            .expect("docs/conventions.md");
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
            if row.verdict == Verdict::Erratum {
                assert_erratum_is_documented(row, &conventions);
            }
        }
    }
}

#[test]
fn wolf2006_s4_reproduces_in_quick_mode() {
    run_quick("wolf2006.s4")
}

#[test]
fn wolf2006_s2_reproduces_in_quick_mode() {
    run_quick("wolf2006.s2")
}

#[test]
fn miller2004_linear_delta_reproduces_in_quick_mode() {
    run_quick("miller2004.linear_delta")
}

#[test]
fn miller2004_workspace_reproduces_in_quick_mode() {
    run_quick("miller2004.workspace")
}

#[test]
fn miller2004_dynamics_reproduces_in_quick_mode() {
    run_quick("miller2004.dynamics")
}

#[test]
fn miller2004_nuwar_reproduces_in_quick_mode() {
    run_quick("miller2004.nuwar")
}

#[test]
fn stamper1997_reproduces_in_quick_mode() {
    run_quick("stamper1997")
}
