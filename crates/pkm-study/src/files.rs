//! The files a study names, as a front end reads them ([`FileReader`]: relative to the study
//! file, or from a `results.json` echo), and places in their text ([`Place`], [`locate`]): what
//! the study loader ([`crate::load`]) and the robot-file table share.

use crate::{Key, KeyPath};
use std::io;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::de::{DeTable, DeValue};

/// How a front end reads the files a study names, by the name written in the study.
pub trait FileReader {
    /// The size in bytes of the file `name`, asked before it is read (a file above its bound is
    /// refused unread).
    ///
    /// # Errors
    /// The I/O error of a file that cannot be found.
    fn size(&self, name: &str) -> io::Result<u64>;

    /// The text of the file `name`.
    ///
    /// # Errors
    /// The I/O error of a file that cannot be read or is not UTF-8.
    fn read(&self, name: &str) -> io::Result<String>;

    /// The name a person would use for `name` in a message and in `results.json` (for a
    /// directory, the path that was read).
    fn display(&self, name: &str) -> String {
        name.to_owned()
    }
}

/// Files read relative to a directory (the study file's; empty for the working directory).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Directory(pub PathBuf);

impl Directory {
    /// The directory of the study file `path`.
    pub fn of_study(path: &Path) -> Self {
        Self(path.parent().map(Path::to_path_buf).unwrap_or_default())
    }
}

impl FileReader for Directory {
    fn size(&self, name: &str) -> io::Result<u64> {
        std::fs::metadata(self.0.join(name)).map(|m| m.len())
    }

    fn read(&self, name: &str) -> io::Result<String> {
        std::fs::read_to_string(self.0.join(name))
    }

    fn display(&self, name: &str) -> String {
        self.0.join(name).display().to_string()
    }
}

/// The files a `results.json` echoes, so a study's output is read back without the files it
/// came from: every name reads as the echoed robot file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Echoed(pub Option<NamedFile>);

impl FileReader for Echoed {
    fn size(&self, name: &str) -> io::Result<u64> {
        self.read(name).map(|text| text.len() as u64)
    }

    fn read(&self, _: &str) -> io::Result<String> {
        self.0
            .as_ref()
            .map(|f| f.text.clone())
            .ok_or_else(|| io::Error::new(io::ErrorKind::NotFound, "the echo holds no robot file"))
    }

    fn display(&self, name: &str) -> String {
        self.0
            .as_ref()
            .map_or_else(|| name.to_owned(), |f| f.file.clone())
    }
}

/// A file a study named, as it was read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NamedFile {
    /// Its name for a person ([`FileReader::display`]).
    pub file: String,
    /// Its text.
    pub text: String,
}

/// Where an error is: a file, a line and a column (from 1), and the text of the line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Place {
    /// The study file's name as the front end gave it, or the robot file's.
    pub file: String,
    /// The line, from 1.
    pub line: usize,
    /// The column in characters, from 1.
    pub column: usize,
    /// The line's text, without its end.
    pub source_line: String,
}

impl Place {
    /// The place of byte `offset` of `text` in `file`.
    pub fn at(file: &str, text: &str, offset: usize) -> Self {
        let start = offset.min(text.len());
        let before = text.get(..start).unwrap_or("");
        let line = before.matches('\n').count() + 1;
        let column = before
            .rfind('\n')
            .map_or(before.chars().count(), |k| before[k + 1..].chars().count())
            + 1;
        let source_line = text
            .lines()
            .nth(line - 1)
            .unwrap_or("")
            .trim_end()
            .to_owned();
        Self {
            file: file.to_owned(),
            line,
            column,
            source_line,
        }
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
    fn places_count_lines_and_columns_from_one() {
        let place = Place::at("s.toml", "a = 1\nbb = 2\n", 9);
        assert_eq!((place.line, place.column), (2, 4));
        assert_eq!(place.source_line, "bb = 2");
        // An offset past the end is the end.
        assert_eq!(Place::at("s.toml", "a", 99).column, 2);
    }
}
