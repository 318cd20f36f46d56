//! Study files: TOML read with serde, unknown keys rejected, every error placed at its line.
//!
//! Each command owns the shape of its study (a struct of the sections it reads, built from the
//! shared sections of this module), so a new command adds its own sections without touching the
//! others. The mapping from a study's `[mechanism.*]` table to a library mechanism lives in one
//! module, [`mechanism`].

pub mod mechanism;
pub mod sampling;
pub mod units;

use crate::CliError;
use serde::de::DeserializeOwned;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// A study file as read: its path, its text (echoed in `results.json`) and its contents.
#[derive(Debug, Clone)]
pub struct StudyFile<T> {
    /// Where it was read from.
    pub path: PathBuf,
    /// The text of the file.
    pub text: String,
    /// The parsed study.
    pub study: T,
}

/// Reads and parses the study file at `path`.
///
/// # Errors
/// [`CliError::Io`] when it cannot be read, [`CliError::Study`] (file, line, column and what was
/// expected) when it is not a valid study of this shape.
pub fn load<T: DeserializeOwned>(path: &Path) -> Result<StudyFile<T>, CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| CliError::io(path, e))?;
    parse(path, text)
}

/// Parses `text` as the study file `path`.
///
/// # Errors
/// [`CliError::Study`] when it is not a valid study of this shape.
pub fn parse<T: DeserializeOwned>(path: &Path, text: String) -> Result<StudyFile<T>, CliError> {
    match toml::from_str::<T>(&text) {
        Ok(study) => Ok(StudyFile {
            path: path.to_path_buf(),
            text,
            study,
        }),
        Err(e) => Err(error_at(
            path,
            &text,
            e.span().unwrap_or(0..0),
            e.message().trim_end(),
        )),
    }
}

impl<T> StudyFile<T> {
    /// An error about the text at `span` of this file.
    pub fn error_at(&self, span: Range<usize>, message: impl Into<String>) -> CliError {
        error_at(&self.path, &self.text, span, &message.into())
    }
}

/// [`CliError::Study`] at the line and column of byte `span.start` of `text`.
pub fn error_at(path: &Path, text: &str, span: Range<usize>, message: &str) -> CliError {
    let start = span.start.min(text.len());
    let before = text.get(..start).unwrap_or("");
    let line = before.matches('\n').count() + 1;
    let column = before
        .rfind('\n')
        .map_or(before.chars().count(), |k| before[k + 1..].chars().count())
        + 1;
    let source_line = text.lines().nth(line - 1).unwrap_or("").trim_end();
    CliError::Study {
        file: path.display().to_string(),
        line,
        column,
        message: format!("{message}\n    | {source_line}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_lines_and_columns_from_one() {
        let text = "a = 1\nbb = 2\n";
        let CliError::Study { line, column, .. } = error_at(Path::new("s.toml"), text, 9..10, "x")
        else {
            unreachable!("error_at builds a study error")
        };
        assert_eq!((line, column), (2, 4));
    }
}
