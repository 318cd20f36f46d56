//! The studies of the `pkm` command as functions: `workspace`, `sweep`, `pareto`, `merge`,
//! `optimize`, `task`, `dynamics` and `assembly`. Each takes the study as a dict or a TOML/JSON file path
//! ([`Source`]), runs the study layer's function of the same name off the main thread
//! ([`bridge`]) and returns the outcome dict of [`convert::outcome`].
//!
//! A study kind of the study layer, `f(&Study, &dyn Progress) -> Result<Outcome<R>, _>`, is one
//! `#[pyfunction]` calling [`run`] here, a line in [`register`], and its Python wrapper and stub.
//!
//! A grid study run on a shard `(i, n)` with n > 1 returns its part: the outcome dict with
//! `result` the shard's node values, plus `kind` (`"sweep"` or `"pareto"`) and `study` (the study
//! as a plain dict), so that [`merge`] needs nothing but the parts.

use crate::source::Source;
use crate::{bridge, convert, errors, trajectory};
use pkm_study::{GridKind, GridRun, GridStudy, Outcome, Shard, ShardResult, StudyError};
use pkm_traits::Progress;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyDictMethods};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// Adds the study functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(workspace, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(pareto, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(optimize, m)?)?;
    m.add_function(wrap_pyfunction!(task, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics, m)?)?;
    m.add_function(wrap_pyfunction!(assembly, m)?)?;
    Ok(())
}

/// Runs `compute` on the parsed study off the main thread (Ctrl-C cancels it) and returns the
/// outcome dict.
fn compute_outcome<'py, S, R>(
    py: Python<'py>,
    parsed: &S,
    progress: Option<&Bound<'py, PyAny>>,
    compute: impl FnOnce(&S, &dyn Progress) -> Result<Outcome<R>, StudyError> + Send,
) -> PyResult<Bound<'py, PyDict>>
where
    S: Sync,
    R: Serialize + Send,
{
    let outcome = bridge::run(py, progress, |b| compute(parsed, b))?
        .map_err(|e| errors::study_error(py, &e))?;
    convert::outcome(py, &outcome)
}

/// Reads `study` as `S`, runs `compute` on it and returns the outcome dict.
fn run<S, R>(
    study: &Bound<'_, PyAny>,
    progress: Option<&Bound<'_, PyAny>>,
    compute: impl FnOnce(&S, &dyn Progress) -> Result<Outcome<R>, StudyError> + Send,
) -> PyResult<Py<PyAny>>
where
    S: DeserializeOwned + Sync,
    R: Serialize + Send,
{
    let py = study.py();
    let parsed: S = Source::of(study)?.parse(py)?;
    Ok(compute_outcome(py, &parsed, progress, compute)?
        .into_any()
        .unbind())
}

/// The workspace study (`pkm workspace`): volume ± standard error, η and GCI, slices of 1/κ.
/// `study` is a dict or a TOML path; `progress(task, label, done, total)` is called on the
/// main thread as the study advances. Returns {"result", "summary", "tables", "figures"}.
#[pyfunction]
#[pyo3(signature = (study, progress = None))]
fn workspace(study: &Bound<'_, PyAny>, progress: Option<&Bound<'_, PyAny>>) -> PyResult<Py<PyAny>> {
    run(
        study,
        progress,
        pkm_study::workspace::<pkm_study::MechanismSpec>,
    )
}

/// The optimisation study (`pkm optimize`): multistart constrained optimisation with the
/// first- and second-order checks at the optimum. Returns the outcome dict.
#[pyfunction]
#[pyo3(signature = (study, progress = None))]
fn optimize(study: &Bound<'_, PyAny>, progress: Option<&Bound<'_, PyAny>>) -> PyResult<Py<PyAny>> {
    run(
        study,
        progress,
        pkm_study::optimize::<pkm_study::MechanismSpec>,
    )
}

/// The sweep study (`pkm sweep`) of the whole grid, or of the shard `(i, n)` (1 ≤ i ≤ n).
/// `pkm.assembly`: [`pkm_study::assembly`] on a study dict or TOML path.
#[pyfunction]
#[pyo3(signature = (study, progress = None))]
fn assembly(study: &Bound<'_, PyAny>, progress: Option<&Bound<'_, PyAny>>) -> PyResult<Py<PyAny>> {
    run(study, progress, pkm_study::assembly)
}

/// `pkm.task`: [`pkm_study::task`] on a study dict or TOML path.
#[pyfunction]
#[pyo3(signature = (study, progress = None))]
fn task(study: &Bound<'_, PyAny>, progress: Option<&Bound<'_, PyAny>>) -> PyResult<Py<PyAny>> {
    run(study, progress, pkm_study::task::<pkm_study::MechanismSpec>)
}

#[pyfunction]
#[pyo3(signature = (study, shard = None, progress = None))]
fn sweep(
    study: &Bound<'_, PyAny>,
    shard: Option<&Bound<'_, PyAny>>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    grid_study(GridKind::Sweep, study, shard, progress, pkm_study::sweep)
}

/// The Pareto study (`pkm pareto`) of the whole grid, or of the shard `(i, n)` (1 ≤ i ≤ n).
#[pyfunction]
#[pyo3(signature = (study, shard = None, progress = None))]
fn pareto(
    study: &Bound<'_, PyAny>,
    shard: Option<&Bound<'_, PyAny>>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    grid_study(GridKind::Pareto, study, shard, progress, pkm_study::pareto)
}

/// The name of a grid study kind in a part's `kind`.
fn kind_name(kind: GridKind) -> &'static str {
    match kind {
        GridKind::Sweep => "sweep",
        GridKind::Pareto => "pareto",
    }
}

/// A grid study function of the study layer (`pkm_study::sweep`, `pkm_study::pareto`).
type GridStudyFn<R> =
    fn(&GridStudy, Shard, &dyn Progress) -> Result<Outcome<GridRun<R>>, StudyError>;

/// A grid study of kind `kind` on `shard`; a part carries its kind and study.
fn grid_study<R: Serialize + Send>(
    kind: GridKind,
    study: &Bound<'_, PyAny>,
    shard: Option<&Bound<'_, PyAny>>,
    progress: Option<&Bound<'_, PyAny>>,
    compute: GridStudyFn<R>,
) -> PyResult<Py<PyAny>> {
    let py = study.py();
    let shard = shard.map(shard_of).transpose()?.unwrap_or(Shard::WHOLE);
    let source = Source::of(study)?;
    let parsed: GridStudy = source.parse(py)?;
    let out = compute_outcome(py, &parsed, progress, |s, p| compute(s, shard, p))?;
    if shard.count > 1 {
        out.set_item("kind", kind_name(kind))?;
        out.set_item("study", source.to_dict(py)?)?;
    }
    Ok(out.into_any().unbind())
}

/// `(i, n)` as the shard I/N.
///
/// # Errors
/// `pkm.InvalidInput` unless two integers with 1 ≤ i ≤ n.
fn shard_of(value: &Bound<'_, PyAny>) -> PyResult<Shard> {
    let py = value.py();
    let refuse = || {
        let m = format!("shard: expected (i, n) with 1 <= i <= n, got {value}");
        errors::invalid(py, m)
    };
    let (index, count): (usize, usize) = value.extract().map_err(|_| refuse())?;
    let shard = Shard { index, count };
    if shard.is_valid() {
        Ok(shard)
    } else {
        Err(refuse())
    }
}

/// A part of a split grid study, read back.
struct Part {
    kind: GridKind,
    study: GridStudy,
    result: ShardResult,
}

/// Reads part `k` of `pkm.merge`'s argument.
///
/// # Errors
/// `pkm.InvalidInput` naming `parts[k]` for anything but the return value of a shard.
fn part_of(k: usize, value: &Bound<'_, PyAny>) -> PyResult<Part> {
    let py = value.py();
    let refuse = |why: String| {
        let m = format!(
            "parts[{k}]: not the return value of pkm.sweep or pkm.pareto with shard=(i, n), \
             n > 1 ({why})"
        );
        errors::invalid(py, m)
    };
    let dict = value
        .cast::<PyDict>()
        .map_err(|_| refuse(format!("a {}", value.get_type())))?;
    let item = |key: &str| {
        dict.get_item(key)?
            .ok_or_else(|| refuse(format!("no `{key}`")))
    };
    let kind = match item("kind")?.extract::<String>().as_deref() {
        Ok("sweep") => GridKind::Sweep,
        Ok("pareto") => GridKind::Pareto,
        _ => return Err(refuse("`kind` is not \"sweep\" or \"pareto\"".into())),
    };
    let study = convert::from_python(&item("study")?).map_err(|e| refuse(format!("study: {e}")))?;
    let result =
        convert::from_python(&item("result")?).map_err(|e| refuse(format!("result: {e}")))?;
    Ok(Part {
        kind,
        study,
        result,
    })
}

/// Joins the parts of a split sweep or Pareto study (the return values of
/// `sweep(study, shard=(i, n))` for i = 1…n, in any order) into the single run's outcome.
#[pyfunction]
#[pyo3(signature = (parts, progress = None))]
fn merge(parts: &Bound<'_, PyAny>, progress: Option<&Bound<'_, PyAny>>) -> PyResult<Py<PyAny>> {
    let py = parts.py();
    let parts: Vec<Part> = parts
        .try_iter()
        .map_err(|_| errors::invalid(py, "parts: expected a list of shard results"))?
        .enumerate()
        .map(|(k, p)| part_of(k, &p?))
        .collect::<PyResult<_>>()?;
    let Some(first) = parts.first() else {
        return Err(errors::study_error(
            py,
            &pkm_study::MergeError::NoShards.into(),
        ));
    };
    let (kind, study) = (first.kind, first.study.clone());
    if let Some(k) = parts
        .iter()
        .position(|p| p.kind != kind || p.study != study)
    {
        let m = format!(
            "parts[{k}]: a shard of another study or kind than parts[0]; merge only the shards \
             of one run"
        );
        return Err(errors::invalid(py, m));
    }
    let results: Vec<ShardResult> = parts.into_iter().map(|p| p.result).collect();
    let out = compute_outcome(py, &study, progress, move |s, p| {
        pkm_study::merge(s, kind, results, p)
    })?;
    Ok(out.into_any().unbind())
}

/// The dynamics study (`pkm dynamics`): motor torques by Hamilton and Lagrange along a
/// trajectory, and the forward retrace. `trajectory` (an N × 4 array of t, x, y, z rows or a
/// CSV path) replaces the study's `trajectory.csv` / `trajectory.positions`; a study's own
/// `trajectory.csv` is read relative to the study file (a dict's: the working directory).
#[pyfunction]
#[pyo3(signature = (study, trajectory = None, progress = None))]
fn dynamics(
    study: &Bound<'_, PyAny>,
    trajectory: Option<&Bound<'_, PyAny>>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let py = study.py();
    let source = Source::of(study)?;
    let parsed: pkm_study::DynamicsStudy = match trajectory {
        // The study may then leave out its [trajectory] table.
        Some(_) => {
            let dict = source.to_dict(py)?;
            if !dict.contains("trajectory")? {
                dict.set_item("trajectory", PyDict::new(py))?;
            }
            // Read as the study itself is (its robot file relative to the study file).
            Source::Mapping(dict.into_any()).parse_at(py, source.base())?
        }
        None => source.parse(py)?,
    };
    let rows = match trajectory {
        Some(t) => Some(trajectory::from_argument(t)?),
        None => trajectory::from_study(&parsed, &source.base())
            .map_err(|e| errors::study_error(py, &e))?,
    };
    let out = compute_outcome(py, &parsed, progress, |s, p| {
        trajectory::run(s, rows.as_ref(), p)
    })?;
    Ok(out.into_any().unbind())
}
