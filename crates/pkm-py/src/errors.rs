//! One exception hierarchy for every error of the library: `pkm.Error` and its subclasses
//! `InvalidInput`, `Infeasible`, `NotConverged` and `Cancelled`. Study errors carry the key
//! path of the offending setting as `.key_path` (`None` when the error is not about one).

use pkm_study::StudyError;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

pyo3::create_exception!(
    pkm,
    Error,
    PyException,
    "Every error of pkm. `.key_path` names the study setting it is about (or None)."
);
pyo3::create_exception!(
    pkm,
    InvalidInput,
    Error,
    "An argument, a design or a study setting that violates its requirement."
);
pyo3::create_exception!(
    pkm,
    Infeasible,
    Error,
    "No feasible design or pose: the computation ran but found nothing to return."
);
pyo3::create_exception!(
    pkm,
    NotConverged,
    Error,
    "An iterative solver stopped before its tolerance."
);
pyo3::create_exception!(
    pkm,
    Cancelled,
    Error,
    "The computation was cancelled (KeyboardInterrupt is raised as itself)."
);

/// Adds the exception types to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("Error", py.get_type::<Error>())?;
    m.add("InvalidInput", py.get_type::<InvalidInput>())?;
    m.add("Infeasible", py.get_type::<Infeasible>())?;
    m.add("NotConverged", py.get_type::<NotConverged>())?;
    m.add("Cancelled", py.get_type::<Cancelled>())?;
    Ok(())
}

/// Which exception type an error raises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Other,
    Invalid,
    Infeasible,
    NotConverged,
    Cancelled,
}

/// The exception of `kind` with `message`, and `.key_path` set to `key_path`.
pub(crate) fn raise(
    py: Python<'_>,
    kind: Kind,
    message: String,
    key_path: Option<String>,
) -> PyErr {
    let err = match kind {
        Kind::Other => Error::new_err(message),
        Kind::Invalid => InvalidInput::new_err(message),
        Kind::Infeasible => Infeasible::new_err(message),
        Kind::NotConverged => NotConverged::new_err(message),
        Kind::Cancelled => Cancelled::new_err(message),
    };
    // Setting an attribute on a fresh exception instance cannot fail in practice; if it did,
    // the exception would still carry its message.
    let _ = err.value(py).setattr("key_path", key_path);
    err
}

/// `pkm.InvalidInput` with `message` and no key path.
pub(crate) fn invalid(py: Python<'_>, message: impl Into<String>) -> PyErr {
    raise(py, Kind::Invalid, message.into(), None)
}

/// The exception of a study error, with its key path.
pub(crate) fn study_error(py: Python<'_>, e: &StudyError) -> PyErr {
    raise(
        py,
        kind_of(e),
        e.to_string(),
        e.path().map(ToString::to_string),
    )
}

/// The exception class of a study error.
fn kind_of(e: &StudyError) -> Kind {
    match e {
        StudyError::Schema { .. }
        | StudyError::Invalid { .. }
        | StudyError::Index(_)
        | StudyError::Merge(_) => Kind::Invalid,
        StudyError::NoFeasibleDesign { .. } => Kind::Infeasible,
        StudyError::Integration(_) => Kind::NotConverged,
        StudyError::Optimize(o) => optimize_kind(o),
        StudyError::Cancelled => Kind::Cancelled,
        _ => Kind::Other,
    }
}

/// The Python exception for a study that could not be loaded: the study error's class, its
/// message prefixed with the file, line and column when the loader placed it.
pub(crate) fn load_error(py: Python<'_>, e: &pkm_study::load::LoadError) -> PyErr {
    let path = e.error.path().map(ToString::to_string);
    raise(py, kind_of(&e.error), e.to_string(), path)
}

fn optimize_kind(e: &pkm_optimizers::OptimizeError) -> Kind {
    use pkm_optimizers::OptimizeError as O;
    match e {
        O::Invalid(_) => Kind::Invalid,
        O::NoFeasibleDesign { .. } => Kind::Infeasible,
        O::Cancelled => Kind::Cancelled,
        _ => Kind::Other,
    }
}
