//! Output files written atomically: each into a temporary file of the same directory, then
//! renamed over its name, so a reader, a crash or a Ctrl-C never sees a half-written file.

use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why an output file or directory could not be written.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum OutputError {
    /// The output path names something that is not a directory (a file, or a path below one).
    #[error("{}: not a directory", path.display())]
    NotADirectory {
        /// The path given.
        path: PathBuf,
    },
    /// A file name that is not a plain name inside the directory.
    #[error(
        "{name:?} is not a file name (it must be non-empty, without a path separator, and not . or ..)"
    )]
    BadName {
        /// The name given.
        name: String,
    },
    /// The operating system refused to create, write, rename or remove something.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The caller's writer failed (see [`OutputDir::write_with`]); nothing was put in place.
    #[error("{}: {source}", path.display())]
    Writer {
        /// The file that was being written.
        path: PathBuf,
        /// The writer's error.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The temporary sibling of `path`: `.<name>.<process id>.partial` in the same directory (a
/// rename within one directory is atomic).
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.partial", std::process::id()))
}

/// Writes `bytes` to `path` atomically: into a temporary file of the same directory, then
/// renamed over `path` (the temporary file is removed if the rename fails).
///
/// # Errors
/// [`OutputError::Io`] naming the file the operating system refused.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    let staged = temporary(path);
    std::fs::write(&staged, bytes).map_err(io(&staged))?;
    commit(&staged, path)
}

/// Renames `staged` over `path`, removing `staged` when that fails.
fn commit(staged: &Path, path: &Path) -> Result<(), OutputError> {
    std::fs::rename(staged, path).map_err(|e| {
        let _ = std::fs::remove_file(staged);
        io(path)(e)
    })
}

/// An output directory: created and checked writable before any work, its files written
/// atomically, their names recorded in the order first written.
#[derive(Debug)]
pub struct OutputDir {
    dir: PathBuf,
    files: Vec<String>,
}

impl OutputDir {
    /// Creates `dir` (and its parents) if needed and checks that files can be written in it
    /// (by writing and removing an empty probe file), so a bad output path is reported before
    /// any computation rather than after it.
    ///
    /// # Errors
    /// [`OutputError::NotADirectory`] when `dir` is a file or lies below one;
    /// [`OutputError::Io`] when it cannot be created or written.
    pub fn create(dir: &Path) -> Result<Self, OutputError> {
        let below_a_file = dir.ancestors().any(|a| a.is_file());
        if below_a_file {
            return Err(OutputError::NotADirectory {
                path: dir.to_path_buf(),
            });
        }
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        let probe = dir.join(format!(".write-check-{}", std::process::id()));
        std::fs::write(&probe, b"").map_err(io(dir))?;
        std::fs::remove_file(&probe).map_err(io(&probe))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            files: Vec::new(),
        })
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The path of the file `name` in the directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// The names written so far, each once, in the order first written.
    pub fn files(&self) -> &[String] {
        &self.files
    }

    /// Writes `bytes` to the file `name` atomically and records the name.
    ///
    /// # Errors
    /// [`OutputError::BadName`] unless `name` is a plain file name; [`OutputError::Io`].
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<PathBuf, OutputError> {
        let path = self.checked_path(name)?;
        write_atomically(&path, bytes)?;
        self.record(name);
        Ok(path)
    }

    /// Writes the file `name` with `write`, which is handed a temporary path in the directory
    /// (for writers that want a path, such as a renderer); the file is renamed into place and
    /// recorded only when `write` succeeds, and the temporary file is removed when it fails.
    ///
    /// # Errors
    /// [`OutputError::Writer`] with `write`'s error; [`OutputError::BadName`];
    /// [`OutputError::Io`].
    pub fn write_with<E>(
        &mut self,
        name: &str,
        write: impl FnOnce(&Path) -> Result<(), E>,
    ) -> Result<PathBuf, OutputError>
    where
        E: Into<Box<dyn std::error::Error + Send + Sync>>,
    {
        let path = self.checked_path(name)?;
        let staged = temporary(&path);
        if let Err(e) = write(&staged) {
            let _ = std::fs::remove_file(&staged);
            return Err(OutputError::Writer {
                path,
                source: e.into(),
            });
        }
        commit(&staged, &path)?;
        self.record(name);
        Ok(path)
    }

    fn checked_path(&self, name: &str) -> Result<PathBuf, OutputError> {
        let plain = !name.is_empty()
            && name != "."
            && name != ".."
            && !name.contains(['/', '\\'])
            && Path::new(name).file_name().is_some_and(|n| n == name);
        if plain {
            Ok(self.path(name))
        } else {
            Err(OutputError::BadName {
                name: name.to_owned(),
            })
        }
    }

    fn record(&mut self, name: &str) {
        if !self.files.iter().any(|f| f == name) {
            self.files.push(name.to_owned());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn files_are_written_whole_and_recorded_once_in_order() {
        let root = tempfile::tempdir().unwrap();
        let mut out = OutputDir::create(&root.path().join("a/b")).unwrap();
        out.write("b.csv", b"x\n1\n").unwrap();
        out.write("a.json", b"{}").unwrap();
        out.write("b.csv", b"x\n2\n").unwrap();
        assert_eq!(out.files(), ["b.csv", "a.json"]);
        assert_eq!(std::fs::read(out.path("b.csv")).unwrap(), b"x\n2\n");
        assert_eq!(
            entries(out.dir()),
            ["a.json", "b.csv"],
            "no temporary file left"
        );
    }

    #[test]
    fn a_failed_writer_leaves_neither_the_file_nor_its_temporary() {
        let root = tempfile::tempdir().unwrap();
        let mut out = OutputDir::create(root.path()).unwrap();
        out.write("f.svg", b"old").unwrap();
        let error = out
            .write_with("f.svg", |path| {
                std::fs::write(path, b"half").unwrap();
                Err("the renderer refused")
            })
            .unwrap_err();
        assert!(
            error.to_string().contains("the renderer refused"),
            "{error}"
        );
        assert_eq!(std::fs::read(out.path("f.svg")).unwrap(), b"old");
        assert_eq!(entries(out.dir()), ["f.svg"]);
        out.write_with("g.svg", |path| std::fs::write(path, b"new"))
            .unwrap();
        assert_eq!(out.files(), ["f.svg", "g.svg"]);
        assert_eq!(std::fs::read(out.path("g.svg")).unwrap(), b"new");
    }

    #[test]
    fn names_outside_the_directory_are_refused() {
        let root = tempfile::tempdir().unwrap();
        let mut out = OutputDir::create(root.path()).unwrap();
        for name in ["", ".", "..", "../x", "a/b", "a\\b", "/etc/x"] {
            assert!(
                matches!(out.write(name, b""), Err(OutputError::BadName { .. })),
                "{name}"
            );
        }
        assert!(out.files().is_empty());
    }

    #[test]
    fn a_file_is_not_an_output_directory() {
        let root = tempfile::tempdir().unwrap();
        let file = root.path().join("file");
        std::fs::write(&file, "keep").unwrap();
        for dir in [file.clone(), file.join("below")] {
            assert!(matches!(
                OutputDir::create(&dir),
                Err(OutputError::NotADirectory { .. })
            ));
        }
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep");
    }
}
