//! The trajectory of a dynamics study from Python: an N × 4 array of `t, x, y, z` rows (s, m;
//! N × (1 + n) rows of `t` and a robot file's n task coordinates) or a CSV file of such rows
//! after a header line, handed to the study layer as
//! `trajectory.positions` (it reads no files). A CSV file is read as the `pkm` command reads
//! it (through the study layer's `TrajectoryCsv`: the same parse, the same checks, errors at the
//! `csv` key naming the file and line), so both give the same bits.

use crate::{errors, points};
use pkm_study::StudyError;
use pkm_study::dynamics::{DynamicsStudy, MAX_SAMPLES, TrajectoryCsv};
use pkm_study::load::Directory;
use pkm_study::schema::units::Real;
use pyo3::prelude::*;
use pyo3::types::PyString;
use std::path::Path;

/// Sampled positions: from an array, or from a CSV file (which knows the line of each row).
pub(crate) enum Rows {
    /// An N × k array's rows.
    Array(Vec<Vec<Real>>),
    /// A CSV file's rows.
    Csv(TrajectoryCsv),
}

/// The `trajectory` argument of `pkm.dynamics`: a path (`str` or `os.PathLike`) of a CSV file
/// relative to the working directory, or an N × k array (k = 4 for the rotary Delta, 1 + n for
/// a robot file with n task coordinates: the study checks it).
///
/// # Errors
/// `pkm.InvalidInput` at `trajectory` for a value that is neither, more than [`MAX_SAMPLES`]
/// rows (before anything is copied), or a CSV file that cannot be read.
pub(crate) fn from_argument(value: &Bound<'_, PyAny>) -> PyResult<Rows> {
    let py = value.py();
    let is_path = value.cast::<PyString>().is_ok() || value.hasattr("__fspath__")?;
    if is_path {
        let path: String = py
            .import("os")?
            .call_method1("fspath", (value,))?
            .extract()?;
        return TrajectoryCsv::read(&path, &Directory::default())
            .map(Rows::Csv)
            .map_err(|e| errors::study_error(py, &e));
    }
    let width = points::columns_of(value, "trajectory")?
        .filter(|&k| k >= 2)
        .unwrap_or(4);
    let array = points::rows(value, "trajectory", width)?;
    let view = array.as_array();
    if view.nrows() > MAX_SAMPLES {
        let m = format!("{} rows, at most {MAX_SAMPLES}", view.nrows());
        return Err(errors::study_error(
            py,
            &StudyError::invalid("trajectory", m),
        ));
    }
    let rows = view
        .rows()
        .into_iter()
        .map(|r| r.iter().copied().map(Real).collect())
        .collect();
    Ok(Rows::Array(rows))
}

/// Reads the study's own `trajectory.csv` (relative to `base`) when it names one.
///
/// # Errors
/// As [`read_csv`].
pub(crate) fn from_study(study: &DynamicsStudy, base: &Path) -> Result<Option<Rows>, StudyError> {
    study
        .trajectory
        .csv
        .as_ref()
        .map(|name| TrajectoryCsv::read(name, &Directory(base.to_path_buf())).map(Rows::Csv))
        .transpose()
}

/// Runs the dynamics of `study` with `rows` (when given) as its positions, in place of its
/// CSV file or positions; errors about a CSV row name the file and line.
///
/// # Errors
/// The study's errors.
pub(crate) fn run(
    study: &DynamicsStudy,
    rows: Option<&Rows>,
    progress: &dyn pkm_traits::Progress,
) -> Result<pkm_study::Outcome<pkm_study::DynamicsResult>, StudyError> {
    match rows {
        None => pkm_study::dynamics(study, progress),
        Some(Rows::Csv(csv)) => csv.run(study, progress),
        Some(Rows::Array(rows)) => {
            let mut resolved = study.clone();
            resolved.trajectory.csv = None;
            resolved.trajectory.positions = Some(rows.clone());
            pkm_study::dynamics(&resolved, progress)
        }
    }
}
