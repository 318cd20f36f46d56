//! pkm for Python: the extension module `pkm._native` behind the Python package `pkm`
//! (`python/pkm`).
//!
//! Everything here translates: Python values in (dicts, TOML paths, NumPy arrays), the study
//! layer ([`pkm_study`]) and the library crates compute, Python values out (dicts, NumPy
//! arrays) and one exception hierarchy ([`errors`]). The package holds no science of its own.
//!
//! - [`mechanism`]: `pkm.Mechanism`, kinematics vectorised over N × 3 arrays (N × n in a robot
//!   file's own task coordinates, [`task_kernels`]) on rayon threads with the GIL released
//!   ([`points`] reads and checks the arrays);
//! - [`studies`]: one function per study kind, the study read as given ([`source`]), run off
//!   the main thread so that Ctrl-C cancels it ([`bridge`]), results as plain Python objects
//!   ([`convert`]); a dynamics trajectory from an array or a CSV file ([`trajectory`]).
#![allow(
    rustdoc::private_intra_doc_links,
    reason = "a Python extension with no Rust API: its crate docs are a map of its private modules"
)]

mod bridge;
mod convert;
mod errors;
mod kernels;
mod mechanism;
mod points;
mod presets;
mod source;
mod studies;
mod task_kernels;
mod trajectory;

use pyo3::prelude::*;

/// The extension module `pkm._native`; `pkm/__init__.py` re-exports it.
#[pymodule]
#[pyo3(name = "_native")]
fn pkm_native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    m.add_class::<mechanism::Mechanism>()?;
    m.add_function(wrap_pyfunction!(presets::presets, m)?)?;
    m.add("MAX_POINTS", points::MAX_POINTS)?;
    studies::register(m)?;
    Ok(())
}
