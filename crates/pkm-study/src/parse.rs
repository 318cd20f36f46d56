//! Studies from text or from any serde data model. The schema is plain serde types, so a TOML
//! file, a JSON string or a Python dict (through any serde deserializer) is a study; every
//! error names the key path of the offending setting.

use crate::error::{KeyPath, StudyError};
use serde::Deserialize;
use serde::de::DeserializeOwned;
use std::fmt::Display;

/// Reads a study from TOML text; errors carry the key path and the byte span.
///
/// # Errors
/// [`StudyError::Schema`] when `text` is not TOML or not a study of this shape.
pub fn from_toml_str<T: DeserializeOwned>(text: &str) -> Result<T, StudyError> {
    let document = toml::Deserializer::parse(text).map_err(|e| StudyError::Schema {
        path: KeyPath::root(),
        message: e.message().trim_end().to_owned(),
        span: e.span(),
    })?;
    serde_path_to_error::deserialize(document).map_err(|e| {
        let path = KeyPath::from(e.path());
        let inner = e.into_inner();
        StudyError::Schema {
            path,
            message: inner.message().trim_end().to_owned(),
            span: inner.span(),
        }
    })
}

/// Reads a study from JSON text: one JSON value and nothing after it but whitespace.
///
/// # Errors
/// [`StudyError::Schema`] when `text` is not JSON, not a study of this shape, or has anything
/// after the value (`{...} garbage`).
pub fn from_json_str<T: DeserializeOwned>(text: &str) -> Result<T, StudyError> {
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let study = from_deserializer(&mut deserializer)?;
    deserializer.end().map_err(|e| StudyError::Schema {
        path: KeyPath::root(),
        message: format!("after the study: {e}"),
        span: None,
    })?;
    Ok(study)
}

/// Reads a study from any serde deserializer (a Python dict, YAML, a `serde_json::Value`, ...).
///
/// # Errors
/// [`StudyError::Schema`] with the deserializer's message at the key path where it failed.
pub fn from_deserializer<'de, T, D>(deserializer: D) -> Result<T, StudyError>
where
    T: Deserialize<'de>,
    D: serde::Deserializer<'de>,
    D::Error: Display,
{
    serde_path_to_error::deserialize(deserializer).map_err(|e| StudyError::Schema {
        path: KeyPath::from(e.path()),
        message: e.inner().to_string(),
        span: None,
    })
}
