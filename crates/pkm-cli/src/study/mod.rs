//! Study files: TOML read with serde, unknown keys rejected, every error placed at its line.
//!
//! Each command owns the shape of its study (a struct of the sections it reads, built from the
//! shared sections of this module), so a new command adds its own sections without touching the
//! others. The mapping from a study's `[mechanism.*]` table to a library mechanism lives in one
//! module, [`mechanism`].

pub use pkm_study::schema::{mechanism, sampling, units};

mod robot_file;
pub use robot_file::{StudySource, load_study, load_study_source, study_from_echo};

use crate::CliError;
use pkm_study::{Key, KeyPath, StudyError};
use std::ops::Range;
use std::path::Path;
use toml::de::{DeTable, DeValue};

/// The command's error for a study layer's error about the file `path` with contents `text`:
/// placed at the offending key's line and column when the error names a key.
pub fn study_error(path: &Path, text: &str, error: StudyError) -> CliError {
    let span = match &error {
        StudyError::Schema {
            span: Some(span), ..
        } => Some(span.clone()),
        e => e.path().map(|key| locate(text, key)),
    };
    match (span, error.path()) {
        (Some(span), Some(key)) if !key.is_root() => {
            error_at(path, text, span, &format!("{key}: {}", error.message()))
        }
        (Some(span), _) => error_at(path, text, span, &error.message()),
        (None, _) => CliError::from(error),
    }
}

/// The byte range of the value at `key` in the TOML `text`; the deepest table or array on the
/// way when the key is absent (a default), the start of the file when the text does not parse.
pub fn locate(text: &str, key: &KeyPath) -> Range<usize> {
    let Ok(root) = DeTable::parse(text) else {
        return 0..0;
    };
    let mut span = root.span();
    let mut table: Option<&DeTable<'_>> = Some(root.get_ref());
    let mut array: Option<&toml::de::DeArray<'_>> = None;
    for step in key.keys() {
        let next = match (step, table, array) {
            (Key::Field(name), Some(t), _) => t
                .iter()
                .find(|(k, _)| k.get_ref().as_ref() == name.as_str())
                .map(|(_, v)| v),
            (Key::Index(i), _, Some(a)) => a.get(*i),
            _ => None,
        };
        let Some(value) = next else { break };
        span = value.span();
        (table, array) = match value.get_ref() {
            DeValue::Table(t) => (Some(t), None),
            DeValue::Array(a) => (None, Some(a)),
            _ => (None, None),
        };
    }
    span
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
    fn keys_are_located_at_their_values() {
        let text =
            "[sweep]\nobjective = 1\n[[sweep.refine]]\nstep = 1\n[[sweep.refine]]\nstep = 2\n";
        let span = locate(text, &KeyPath::parse("sweep.refine[1].step"));
        assert_eq!(&text[span], "2");
        let absent = locate(text, &KeyPath::parse("sweep.refine[1].steps"));
        // An absent key is placed at the header of the table that would hold it.
        assert_eq!(absent.start, text.rfind("[[sweep.refine]]").unwrap_or(0));
    }

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
