//! The studies: `workspace(study, progress=None)` and the others as they exist in
//! [`pkm_study`]. Each takes the study as a dict or a TOML/JSON file path and returns the
//! outcome dict of [`crate::convert::outcome`].

use crate::{bridge, convert, errors};
use pkm_study::{Outcome, StudyError, from_json_str, from_toml_str};
use pkm_traits::Progress;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// Adds the study functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(workspace, m)?)?;
    Ok(())
}

/// The study in `study`: a mapping (the study as a dict) or a path to a `.toml` or `.json`
/// file (`str` or `os.PathLike`).
fn read<S: DeserializeOwned>(study: &Bound<'_, PyAny>) -> PyResult<S> {
    let py = study.py();
    if study.cast::<PyDict>().is_ok() || study.hasattr("keys")? {
        return convert::from_python(study);
    }
    let path: std::path::PathBuf = if study.cast::<PyString>().is_ok() {
        study.extract()?
    } else {
        let os = py.import("os")?;
        os.call_method1("fspath", (study,))
            .map_err(|_| errors::invalid(py, "study: expected a dict or a path to a TOML file"))?
            .extract()?
    };
    let text = std::fs::read_to_string(&path)
        .map_err(|e| errors::invalid(py, format!("{}: {e}", path.display())))?;
    let parsed = if path.extension().is_some_and(|e| e == "json") {
        from_json_str(&text)
    } else {
        from_toml_str(&text)
    };
    parsed.map_err(|e| errors::study_error(py, &e))
}

/// Reads `study`, runs `compute` off the main thread (Ctrl-C cancels it) and returns the
/// outcome dict.
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
    let parsed: S = read(study)?;
    let outcome = bridge::run(py, progress, |b| compute(&parsed, b))?
        .map_err(|e| errors::study_error(py, &e))?;
    Ok(convert::outcome(py, &outcome)?.into_any().unbind())
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
