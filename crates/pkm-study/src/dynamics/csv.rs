//! A trajectory as CSV text (`t, x, y, z` rows in s and m after a header line; for a robot
//! file `t` and its task coordinates), as the front ends read it from the file a study names: the study layer reads no files, so a front end reads
//! the text ([`TrajectoryCsv::MAX_BYTES`] at most) and hands it here; an error about a row is
//! placed at the `trajectory.csv` key and names the file and its line.

use super::{DynamicsResult, DynamicsStudy, MAX_SAMPLES, dynamics};
use crate::load::FileReader;
use crate::outcome::Outcome;
use crate::schema::units::Real;
use crate::{Key, KeyPath, StudyError};
use pkm_traits::Progress;
use std::path::{Path, PathBuf};

/// The rows of a trajectory CSV file and the file line of each.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryCsv {
    /// The file, as errors name it.
    pub file: PathBuf,
    /// `t, x, y, z` (s, m), or `t` and a robot file's task coordinates: finite, every row as
    /// long as the first (the study checks the width).
    pub rows: Vec<Vec<Real>>,
    /// The 1-based file line of each row.
    pub lines: Vec<usize>,
}

impl TrajectoryCsv {
    /// The largest CSV text a front end reads (bytes): [`MAX_SAMPLES`] rows of four numbers as
    /// the `pkm` command writes them fit well within it; a larger file is refused unread.
    pub const MAX_BYTES: u64 = (MAX_SAMPLES as u64) * 128;

    /// Parses `text`, the contents of `file`: a header line, then rows of finite numbers, at
    /// least two, each row as long as the first (blank lines skipped).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at `trajectory.csv`, naming the file and the line, for a row that
    /// is not such numbers, or for text longer than [`Self::MAX_BYTES`].
    pub fn parse(file: &Path, text: &str) -> Result<Self, StudyError> {
        Self::check_size(file, text.len() as u64)?;
        let at = |line: usize, message: String| csv_error(file, &format!("line {line}: {message}"));
        let (mut rows, mut lines) = (Vec::new(), Vec::new());
        for (k, line) in text.lines().enumerate().skip(1) {
            if line.trim().is_empty() {
                continue;
            }
            let values: Vec<f64> = line
                .split(',')
                .map(|v| v.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|e| at(k + 1, format!("{e}: expected t (s), x, y, z (m)")))?;
            let width = rows.first().map_or(values.len(), Vec::len);
            if values.len() != width || width < 2 {
                let count = values.len();
                return Err(at(
                    k + 1,
                    format!(
                        "{count} values; expected {}: t (s), x, y, z (m) or t and the task \
                         coordinates, as many on every row",
                        width.max(2)
                    ),
                ));
            }
            if !values.iter().all(|v| v.is_finite()) {
                return Err(at(k + 1, "expected finite numbers".into()));
            }
            rows.push(values.into_iter().map(Real).collect());
            lines.push(k + 1);
        }
        Ok(Self {
            file: file.to_path_buf(),
            rows,
            lines,
        })
    }

    /// Runs [`dynamics`] on `study` with these rows as its positions, in place of its CSV file
    /// or positions; an error about `trajectory.positions[k]` becomes an error at
    /// `trajectory.csv` naming the file and the line of row `k`.
    ///
    /// # Errors
    /// The study's errors.
    pub fn run(
        &self,
        study: &DynamicsStudy,
        progress: &dyn Progress,
    ) -> Result<Outcome<DynamicsResult>, StudyError> {
        let mut resolved = study.clone();
        resolved.trajectory.csv = None;
        resolved.trajectory.positions = Some(self.rows.clone());
        dynamics(&resolved, progress).map_err(|e| self.at_line(e))
    }

    /// Reads the CSV file `name` through `reader` (refused unread above [`Self::MAX_BYTES`]).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at `trajectory.csv` naming the file (and the line) for a file
    /// that cannot be read, is too large, or has a row that is not four finite numbers.
    pub fn read(name: &str, reader: &dyn FileReader) -> Result<Self, StudyError> {
        let shown = PathBuf::from(reader.display(name));
        let unreadable = |e: std::io::Error| csv_error(&shown, &e.to_string());
        Self::check_size(&shown, reader.size(name).map_err(unreadable)?)?;
        let text = reader.read(name).map_err(unreadable)?;
        Self::parse(&shown, &text)
    }

    /// Refuses a CSV file of `bytes` bytes larger than [`Self::MAX_BYTES`] (front ends
    /// call it with the file's size before reading it).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at `trajectory.csv` naming the file.
    pub fn check_size(file: &Path, bytes: u64) -> Result<(), StudyError> {
        if bytes > Self::MAX_BYTES {
            let max = Self::MAX_BYTES;
            return Err(csv_error(
                file,
                &format!("{bytes} bytes; at most {max} (up to {MAX_SAMPLES} samples)"),
            ));
        }
        Ok(())
    }

    fn at_line(&self, error: StudyError) -> StudyError {
        let Some(keys) = error.path().map(KeyPath::keys) else {
            return error;
        };
        let field = |k: usize, name: &str| matches!(keys.get(k), Some(Key::Field(f)) if f == name);
        if !(field(0, "trajectory") && field(1, "positions")) {
            return error;
        }
        let message = match keys.get(2) {
            Some(Key::Index(k)) => {
                let line = self.lines.get(*k).copied().unwrap_or(0);
                format!("line {line}: {}", error.message())
            }
            _ => error.message().to_owned(),
        };
        csv_error(&self.file, &message)
    }
}

/// An error at `trajectory.csv` about `file`.
fn csv_error(file: &Path, message: &str) -> StudyError {
    StudyError::invalid("trajectory.csv", format!("{}: {message}", file.display()))
}

/// Runs a dynamics study, first reading the CSV trajectory it names (`trajectory.csv`) through
/// `reader`: what every front end calls, so the CSV is read the same way everywhere.
///
/// # Errors
/// As [`TrajectoryCsv::read`] and [`dynamics`].
pub fn dynamics_reading(
    study: &DynamicsStudy,
    reader: &dyn FileReader,
    progress: &dyn Progress,
) -> Result<Outcome<DynamicsResult>, StudyError> {
    match &study.trajectory.csv {
        Some(name) => TrajectoryCsv::read(name, reader)?.run(study, progress),
        None => dynamics(study, progress),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_keep_their_file_lines_and_bad_rows_name_theirs() {
        let file = Path::new("t.csv");
        let csv = TrajectoryCsv::parse(file, "t,x,y,z\n0,1,2,3\n\n0.5, 1, 2, 3.5\n").unwrap();
        assert_eq!(csv.lines, vec![2, 4]);
        assert_eq!(
            csv.rows[1]
                .iter()
                .map(|r| r.0.to_bits())
                .collect::<Vec<_>>(),
            [0.5f64, 1.0, 2.0, 3.5].map(f64::to_bits)
        );
        for (text, wanted) in [
            ("h\n0,1,2,3\n0,1,2\n", "t.csv: line 3: 3 values"),
            ("h\n0\n", "t.csv: line 2: 1 values"),
            ("h\n0,1,2,x\n", "t.csv: line 2: invalid float"),
            ("h\n0,1,2,3\n0,1,2,inf\n", "t.csv: line 3: expected finite"),
        ] {
            let e = TrajectoryCsv::parse(file, text).unwrap_err();
            assert!(e.to_string().contains(wanted), "{e} lacks {wanted}");
            assert_eq!(
                e.path().map(ToString::to_string).as_deref(),
                Some("trajectory.csv")
            );
        }
        assert!(TrajectoryCsv::check_size(file, TrajectoryCsv::MAX_BYTES + 1).is_err());
        assert!(TrajectoryCsv::check_size(file, TrajectoryCsv::MAX_BYTES).is_ok());
    }
}
