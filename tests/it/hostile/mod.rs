//! Hostile inputs at every public entry point (issue 11, "Reliability, measured").
//!
//! Every case must end in `Err(typed error)` or in an `Ok` whose value is finite and passes the
//! entry point's own check (a grid node inside its axis, a ratio in `[0, 1]`, ...): never a panic,
//! a hang, an allocation abort or a silent NaN. Strategies mix NaN, ±∞, ±0, negative numbers,
//! 1e-300, 1e300, inverted ranges and zero or huge counts with ordinary values.
//!
//! `catch_unwind` only classifies a panic so that it can be counted: the case still fails. With
//! `HOSTILE_TALLY=<file>` every verdict is appended to that file as `entry<TAB>outcome`, which is
//! how the before/after counts of `docs/ARCHITECTURE.md` were made. Hangs are prevented by bounded
//! iteration settings in the cases, and allocation aborts by asserting a typed error for huge
//! counts.

mod chart;
mod dynamics;
mod edges;
mod indices;
mod integrators;
mod mechanisms;
mod optimizers;
mod screw;
mod traits;

use proptest::prelude::*;
use std::fmt::Debug;
use std::io::Write;
use std::panic::{AssertUnwindSafe, catch_unwind};

/// Cases per property: modest, so the suite stays within a few seconds of CI.
pub(crate) fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 48,
        max_shrink_iters: 64,
        ..ProptestConfig::default()
    }
}

/// The special values of the audit, weighted against ordinary ones.
pub(crate) fn hostile_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => prop::sample::select(vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            -1.0,
            1e-300,
            -1e-300,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
        ]),
        2 => -3.0..3.0f64,
    ]
}

/// Finite but extreme values (for infallible functions whose domain is the finite numbers).
pub(crate) fn extreme_finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        2 => prop::sample::select(vec![0.0, -0.0, -1.0, 1e-300, -1e-300, 1e300, -1e300, 1e-12]),
        2 => -3.0..3.0f64,
    ]
}

/// Counts: zero, one, small, huge and `usize::MAX`.
pub(crate) fn hostile_count() -> impl Strategy<Value = usize> {
    prop_oneof![
        2 => prop::sample::select(vec![0, 1, 2, usize::MAX, usize::MAX / 2, 1 << 40, 1 << 33]),
        2 => 0..12usize,
    ]
}

pub(crate) fn hostile_vec3() -> impl Strategy<Value = nalgebra::Vector3<f64>> {
    (hostile_f64(), hostile_f64(), hostile_f64())
        .prop_map(|(x, y, z)| nalgebra::Vector3::new(x, y, z))
}

pub(crate) fn all_finite<'a>(values: impl IntoIterator<Item = &'a f64>) -> bool {
    values.into_iter().all(|v| v.is_finite())
}

fn tally(entry: &str, outcome: &str) {
    if let Some(path) = std::env::var_os("HOSTILE_TALLY")
        && let Ok(mut file) = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
    {
        let _ = writeln!(file, "{entry}\t{outcome}");
    }
}

/// Runs one case of `entry` and judges it: `Err` passes (it is typed by the signature), `Ok`
/// passes when `checked` holds, a panic or an unchecked `Ok` fails the case.
pub(crate) fn judge<T: Debug, E: Debug>(
    entry: &'static str,
    run: impl FnOnce() -> Result<T, E>,
    checked: impl FnOnce(&T) -> bool,
) -> Result<(), TestCaseError> {
    let outcome = catch_unwind(AssertUnwindSafe(run));
    let verdict = match &outcome {
        Err(_) => Some("panic"),
        Ok(Ok(value)) if !checked(value) => Some("unchecked"),
        Ok(_) => None,
    };
    tally(entry, verdict.unwrap_or("pass"));
    match (verdict, outcome) {
        (None, _) => Ok(()),
        (Some(kind), Ok(result)) => Err(TestCaseError::fail(format!("{entry}: {kind} {result:?}"))),
        (Some(kind), Err(_)) => Err(TestCaseError::fail(format!("{entry}: {kind}"))),
    }
}

/// [`judge`] for an infallible entry point.
pub(crate) fn judge_value<T: Debug>(
    entry: &'static str,
    run: impl FnOnce() -> T,
    checked: impl FnOnce(&T) -> bool,
) -> Result<(), TestCaseError> {
    judge(entry, || Ok::<T, std::convert::Infallible>(run()), checked)
}

/// [`judge`] that must end in a typed error (huge counts, steps that cannot advance).
pub(crate) fn judge_err<T: Debug, E: Debug>(
    entry: &'static str,
    run: impl FnOnce() -> Result<T, E>,
) -> Result<(), TestCaseError> {
    judge(entry, run, |_| false)
}

/// Unwraps a verdict outside proptest.
#[track_caller]
pub(crate) fn expect(verdict: Result<(), TestCaseError>) {
    if let Err(e) = verdict {
        panic!("{e}");
    }
}
