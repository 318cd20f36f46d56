//! Python values to and from the study layer's serde types, and a study's [`Outcome`] as a
//! plain dict: `result` (exactly the `result` of the `pkm` command's `results.json`),
//! `summary` (lines), `tables` (name → {column → NumPy array}) and `figures` (name → the SVG
//! text the command writes under that name; the Python layer wraps each in a `pkm.Figure`).

use crate::errors;
use pkm_study::{Artifact, Cell, Outcome, StudyError, Table, from_deserializer};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// `value` (a dict, list, number, ...) as the serde type `T`.
///
/// # Errors
/// `pkm.InvalidInput` with the key path where the value does not fit.
pub(crate) fn from_python<T: DeserializeOwned>(value: &Bound<'_, PyAny>) -> PyResult<T> {
    let mut de = pythonize::Depythonizer::from_object(value);
    from_deserializer(&mut de).map_err(|e| errors::study_error(value.py(), &e))
}

/// `value` as plain Python objects (dicts, lists, floats, str, None).
pub(crate) fn to_python<'py, T: Serialize>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, value).map_err(|e| errors::study_error(py, &schema_error(&e)))
}

fn schema_error(e: &dyn std::fmt::Display) -> StudyError {
    StudyError::invalid("(result)", e.to_string())
}

/// The outcome as a dict (see the module documentation).
pub(crate) fn outcome<'py, R: Serialize>(
    py: Python<'py>,
    outcome: &Outcome<R>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("result", to_python(py, &outcome.result)?)?;
    out.set_item("summary", PyList::new(py, &outcome.summary)?)?;
    let tables = PyDict::new(py);
    let figures = PyDict::new(py);
    for artifact in &outcome.artifacts {
        match artifact {
            Artifact::Table { name, table } => tables.set_item(name, columns(py, table)?)?,
            Artifact::Chart { name, chart } => {
                let svg = pkm_draw::chart::render_svg(chart)
                    .map_err(|e| errors::invalid(py, format!("{name}: {e}")))?;
                figures.set_item(name, svg)?;
            }
            // As in the command, a robot that cannot be drawn is left out, never an error.
            Artifact::Robot { caption, scene } => {
                let options = pkm_draw::DrawOptions::titled(caption);
                if let Ok(svg) = pkm_draw::render_svg(scene, &options) {
                    figures.set_item(pkm_study::scene::ROBOT_SVG, svg)?;
                }
            }
        }
    }
    out.set_item("tables", tables)?;
    out.set_item("figures", figures)?;
    Ok(out)
}

/// A table as {column → values}, each column with its type: a list of strings for a column of
/// text (`None` for a row without one), an int64 array for counts (grid nodes, starts), a bool
/// array for flags (membership), a float64 array otherwise (NaN for a missing cell).
fn columns<'py>(py: Python<'py>, table: &Table) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for (k, name) in table.header.iter().enumerate() {
        let cells: Vec<&Cell> = table.rows.iter().filter_map(|r| r.get(k)).collect();
        let n = cells.len();
        let all = |kind: fn(&Cell) -> bool| n > 0 && cells.iter().all(|c| kind(c));
        if cells.iter().any(|c| matches!(c, Cell::Text(_))) {
            let list = PyList::empty(py);
            for cell in cells {
                match cell {
                    Cell::Text(t) if !t.is_empty() => list.append(t)?,
                    Cell::Text(_) | Cell::Missing => list.append(py.None())?,
                    other => list.append(other.to_string())?,
                }
            }
            out.set_item(name, list)?;
        } else if all(|c| matches!(c, Cell::Integer(_))) {
            let values: Vec<i64> = cells
                .iter()
                .map(|c| match c {
                    Cell::Integer(v) => i64::try_from(*v).unwrap_or(i64::MAX),
                    _ => 0,
                })
                .collect();
            out.set_item(name, numpy::PyArray1::from_vec(py, values))?;
        } else if all(|c| matches!(c, Cell::Flag(_))) {
            let values: Vec<bool> = cells
                .iter()
                .map(|c| matches!(c, Cell::Flag(true)))
                .collect();
            out.set_item(name, numpy::PyArray1::from_vec(py, values))?;
        } else {
            let values: Vec<f64> = cells
                .iter()
                .map(|c| match c {
                    Cell::Number(v) => *v,
                    Cell::Integer(v) => *v as f64,
                    Cell::Flag(b) => f64::from(u8::from(*b)),
                    Cell::Missing | Cell::Text(_) => f64::NAN,
                })
                .collect();
            out.set_item(name, crate::points::array(py, values, &[n])?)?;
        }
    }
    Ok(out)
}
