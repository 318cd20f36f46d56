//! The trajectory of a dynamics study from Python: an N × 4 array of `t, x, y, z` rows (s, m)
//! or a CSV file of such rows after a header line, handed to the study layer as
//! `trajectory.positions` (it reads no files). A CSV file is read as the `pkm` command reads
//! it (`pkm-cli`'s `dynamics.rs`: the same parse, the same checks, errors at the `csv` key
//! naming the file and line), so both give the same bits.

use crate::{errors, points};
use pkm_study::dynamics::{DynamicsStudy, MAX_SAMPLES};
use pkm_study::schema::units::Real;
use pkm_study::{Key, KeyPath, StudyError};
use pyo3::prelude::*;
use pyo3::types::PyString;
use std::path::{Path, PathBuf};

/// Sampled positions and, for a CSV file, where each row came from.
pub(crate) struct Rows {
    rows: Vec<[Real; 4]>,
    /// The file and the line of each row, for a CSV file.
    origin: Option<(PathBuf, Vec<usize>)>,
}

/// Largest CSV file read (bytes): [`MAX_SAMPLES`] rows of four numbers as the `pkm` command
/// writes them fit well within it; a larger file is refused before it is read.
const MAX_CSV_BYTES: u64 = (MAX_SAMPLES as u64) * 128;

/// The `trajectory` argument of `pkm.dynamics`: a path (`str` or `os.PathLike`) of a CSV file
/// relative to the working directory, or an N × 4 array.
///
/// # Errors
/// `pkm.InvalidInput` at `trajectory` for a value that is neither, more than [`MAX_SAMPLES`]
/// rows (before anything is copied), or a CSV file that cannot be read.
pub(crate) fn from_argument(value: &Bound<'_, PyAny>) -> PyResult<Rows> {
    let py = value.py();
    let is_path = value.cast::<PyString>().is_ok() || value.hasattr("__fspath__")?;
    if is_path {
        let path: PathBuf = py
            .import("os")?
            .call_method1("fspath", (value,))?
            .extract()?;
        return read_csv(&path).map_err(|e| errors::study_error(py, &e));
    }
    let array = points::rows(value, "trajectory", 4)?;
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
        .map(|r| [r[0], r[1], r[2], r[3]].map(Real))
        .collect();
    Ok(Rows { rows, origin: None })
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
        .map(|name| read_csv(&base.join(name)))
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
    let Some(rows) = rows else {
        return pkm_study::dynamics(study, progress);
    };
    let mut resolved = study.clone();
    resolved.trajectory.csv = None;
    resolved.trajectory.positions = Some(rows.rows.clone());
    pkm_study::dynamics(&resolved, progress).map_err(|e| at_csv_line(rows, e))
}

/// The study layer's error about `trajectory.positions[k]` as an error at the `csv` key naming
/// the file and its line (for rows from a CSV file).
fn at_csv_line(rows: &Rows, error: StudyError) -> StudyError {
    let (Some((path, lines)), Some(keys)) = (&rows.origin, error.path().map(KeyPath::keys)) else {
        return error;
    };
    let field = |k: usize, name: &str| matches!(keys.get(k), Some(Key::Field(f)) if f == name);
    if !(field(0, "trajectory") && field(1, "positions")) {
        return error;
    }
    let file = path.display();
    let message = match keys.get(2) {
        Some(Key::Index(k)) => {
            let line = lines.get(*k).copied().unwrap_or(0);
            format!("{file}: line {line}: {}", error.message())
        }
        _ => format!("{file}: {}", error.message()),
    };
    StudyError::invalid("trajectory.csv", message)
}

/// Reads `t, x, y, z` rows (s, m) after a header line, blank lines skipped.
///
/// # Errors
/// [`StudyError::Invalid`] at `trajectory.csv` naming the file (and the line) for a file that
/// cannot be read, is too large, or has a row that is not four finite numbers.
fn read_csv(path: &Path) -> Result<Rows, StudyError> {
    let at = |message: String| {
        StudyError::invalid("trajectory.csv", format!("{}: {message}", path.display()))
    };
    let size = std::fs::metadata(path)
        .map_err(|e| at(e.to_string()))?
        .len();
    if size > MAX_CSV_BYTES {
        return Err(at(format!(
            "{size} bytes; at most {MAX_CSV_BYTES} (up to {MAX_SAMPLES} samples)"
        )));
    }
    let text = std::fs::read_to_string(path).map_err(|e| at(e.to_string()))?;
    let (mut rows, mut lines) = (Vec::new(), Vec::new());
    for (k, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| at(format!("line {}: {e}: expected t (s), x, y, z (m)", k + 1)))?;
        let &[t, x, y, z] = values.as_slice() else {
            let count = values.len();
            return Err(at(format!(
                "line {}: {count} values; expected 4: t (s), x, y, z (m)",
                k + 1
            )));
        };
        if !values.iter().all(|v| v.is_finite()) {
            return Err(at(format!("line {}: expected finite numbers", k + 1)));
        }
        rows.push([t, x, y, z].map(Real));
        lines.push(k + 1);
    }
    Ok(Rows {
        rows,
        origin: Some((path.to_path_buf(), lines)),
    })
}
