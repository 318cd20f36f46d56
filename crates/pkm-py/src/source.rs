//! A study as the caller gave it: a mapping (the study as a dict) or the path of a `.toml` or
//! `.json` file (`str` or `os.PathLike`), read once. It parses into any study type, gives the
//! directory that relative file names in it are read from, and turns into a plain dict (what a
//! shard of a split study carries, so that `pkm.merge` needs nothing but the parts).

use crate::{convert, errors};
use pkm_study::load::{self, Directory, Format};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

/// A study as given.
pub(crate) enum Source<'py> {
    /// A dict (or any mapping).
    Mapping(Bound<'py, PyAny>),
    /// A study file and its text.
    File { path: PathBuf, text: String },
}

impl<'py> Source<'py> {
    /// Reads `study`: a mapping as it is, a path's file text.
    ///
    /// # Errors
    /// `pkm.InvalidInput` for a value that is neither, or a file that cannot be read.
    pub(crate) fn of(study: &Bound<'py, PyAny>) -> PyResult<Self> {
        let py = study.py();
        if study.cast::<PyDict>().is_ok() || study.hasattr("keys")? {
            return Ok(Self::Mapping(study.clone()));
        }
        let path: PathBuf = if study.cast::<PyString>().is_ok() {
            study.extract()?
        } else {
            let os = py.import("os")?;
            os.call_method1("fspath", (study,))
                .map_err(|_| {
                    errors::invalid(py, "study: expected a dict or a path to a TOML file")
                })?
                .extract()?
        };
        let text = std::fs::read_to_string(&path)
            .map_err(|e| errors::invalid(py, format!("{}: {e}", path.display())))?;
        Ok(Self::File { path, text })
    }

    /// The study as the serde type `S`, read by the study layer's loader as the `pkm` command
    /// reads it ([`pkm_study::load`]): a robot file named by `[mechanism.robot_file] file` is
    /// read relative to [`Source::base`] and put in its place, and an error is placed at its
    /// line in the study file or the robot file.
    ///
    /// # Errors
    /// `pkm.InvalidInput` (or the study error's class) with the key path where it does not fit.
    pub(crate) fn parse<S: DeserializeOwned>(&self, py: Python<'py>) -> PyResult<S> {
        self.parse_at(py, self.base())
    }

    /// [`Source::parse`] with the files it names read relative to `base` (a dict made from a
    /// study file keeps that file's directory).
    ///
    /// # Errors
    /// As [`Source::parse`].
    pub(crate) fn parse_at<S: DeserializeOwned>(
        &self,
        py: Python<'py>,
        base: PathBuf,
    ) -> PyResult<S> {
        let reader = Directory(base);
        let loaded = match self {
            Self::Mapping(m) => match convert::from_python::<toml::Table>(m) {
                Ok(document) => load::load_document(document, &reader),
                // Not a TOML table (a `None` somewhere): the schema says where.
                Err(_) => return convert::from_python(m),
            },
            Self::File { path, text } => {
                let name = path.display().to_string();
                load::load(&name, text.clone(), Format::of_path(path), &reader)
                    .map(|(_, loaded)| loaded)
            }
        };
        loaded
            .map(|l| l.study)
            .map_err(|e| errors::load_error(py, &e))
    }

    /// Where relative file names in the study are read from: the study file's directory, or
    /// the working directory for a dict.
    pub(crate) fn base(&self) -> PathBuf {
        match self {
            Self::Mapping(_) => PathBuf::new(),
            Self::File { path, .. } => path.parent().map(Path::to_path_buf).unwrap_or_default(),
        }
    }

    /// The study as a new plain dict: a deep copy of the mapping, or the file's document.
    ///
    /// # Errors
    /// `pkm.InvalidInput` for a file that is not TOML (or JSON).
    pub(crate) fn to_dict(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let value = match self {
            Self::Mapping(m) => {
                let copy = py.import("copy")?.call_method1("deepcopy", (m,))?;
                py.get_type::<PyDict>().call1((copy,))?
            }
            Self::File { path, text } => {
                let unreadable = |e: &dyn std::fmt::Display| {
                    errors::invalid(py, format!("{}: {e}", path.display()))
                };
                if Format::of_path(path) == Format::Json {
                    let v: serde_json::Value =
                        serde_json::from_str(text).map_err(|e| unreadable(&e))?;
                    convert::to_python(py, &v)?
                } else {
                    let v: toml::Table = toml::from_str(text).map_err(|e| unreadable(&e))?;
                    convert::to_python(py, &v)?
                }
            }
        };
        value
            .cast_into::<PyDict>()
            .map_err(|_| errors::invalid(py, "study: expected a table of settings"))
    }
}
