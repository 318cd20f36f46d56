//! `pkm dynamics FILE`: the study layer's [`pkm_study::dynamics`] on a study file: motor
//! torques by Hamilton and Lagrange along a trajectory, and the forward retrace.
//!
//! A `trajectory.csv` file is read here, relative to the study file, and handed to the study
//! layer as `trajectory.positions` (the study layer reads no files); an error about a row is
//! placed at the `csv` key and names the CSV file and line.

use super::{Context, Report, Run};
use crate::CliError;
use pkm_study::dynamics::DynamicsStudy;
use pkm_study::schema::units::Real;
use pkm_study::{Key, KeyPath, StudyError};
use pkm_traits::Progress;
use std::path::{Path, PathBuf};

/// Arguments of `pkm dynamics`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let base = self.file.parent().unwrap_or(Path::new(""));
        super::run_library_study(
            "dynamics",
            &self.file,
            context,
            |study: &DynamicsStudy, progress: &dyn Progress| run(base, study, progress),
        )
    }
}

/// A CSV trajectory read from a file: its rows and the file line of each.
struct CsvRows {
    path: PathBuf,
    rows: Vec<[Real; 4]>,
    lines: Vec<usize>,
}

/// Runs `study`, first reading its CSV trajectory (relative to `base`) into its positions.
fn run(
    base: &Path,
    study: &DynamicsStudy,
    progress: &dyn Progress,
) -> Result<pkm_study::Outcome<pkm_study::DynamicsResult>, StudyError> {
    let Some(name) = &study.trajectory.csv else {
        return pkm_study::dynamics(study, progress);
    };
    let csv = read_csv(&base.join(name))?;
    let mut resolved = study.clone();
    resolved.trajectory.csv = None;
    resolved.trajectory.positions = Some(csv.rows.clone());
    pkm_study::dynamics(&resolved, progress).map_err(|e| at_csv_line(&csv, e))
}

/// The study layer's error about `trajectory.positions[k]` as an error at the `csv` key
/// naming the file and its line.
fn at_csv_line(csv: &CsvRows, error: StudyError) -> StudyError {
    let Some(keys) = error.path().map(KeyPath::keys) else {
        return error;
    };
    let field = |k: usize, name: &str| matches!(keys.get(k), Some(Key::Field(f)) if f == name);
    if !(field(0, "trajectory") && field(1, "positions")) {
        return error;
    }
    let file = csv.path.display();
    let message = match keys.get(2) {
        Some(Key::Index(k)) => {
            let line = csv.lines.get(*k).copied().unwrap_or(0);
            format!("{file}: line {line}: {}", error.message())
        }
        _ => format!("{file}: {}", error.message()),
    };
    StudyError::invalid("trajectory.csv", message)
}

/// Reads `t, x, y, z` rows (s, m) after a header line, blank lines skipped.
///
/// # Errors
/// [`StudyError::Invalid`] at `trajectory.csv` naming the file (and the line) for a file that
/// cannot be read or a row that is not four finite numbers.
fn read_csv(path: &Path) -> Result<CsvRows, StudyError> {
    let at = |message: String| {
        StudyError::invalid("trajectory.csv", format!("{}: {message}", path.display()))
    };
    let text = std::fs::read_to_string(path).map_err(|e| at(e.to_string()))?;
    let (mut rows, mut lines) = (Vec::new(), Vec::new());
    for (k, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| at(format!("line {}: {e}: expected t (s), x, y, z (m)", k + 1)))?;
        let &[t, x, y, z] = values.as_slice() else {
            let count = values.len();
            return Err(at(format!(
                "line {}: {count} values; expected 4: t (s), x, y, z (m)",
                k + 1
            )));
        };
        if !values.iter().all(|v| v.is_finite()) {
            return Err(at(format!("line {}: expected finite numbers", k + 1)));
        }
        rows.push([t, x, y, z].map(Real));
        lines.push(k + 1);
    }
    Ok(CsvRows {
        path: path.to_path_buf(),
        rows,
        lines,
    })
}
