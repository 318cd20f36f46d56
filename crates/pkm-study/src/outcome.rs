//! What a study returns: its result (serde, the `result` of the `pkm` command's
//! `results.json`), the tables and figures a front end may keep beside it, and a short human
//! summary. Nothing here is written anywhere: writing is the caller's.

use pkm_draw::Scene;
use pkm_draw::chart::Chart;
use std::fmt::{self, Write as _};

/// A study's result with its artifacts and summary.
#[derive(Debug, Clone)]
pub struct Outcome<R> {
    /// The typed result.
    pub result: R,
    /// Tables and figures, in the order a front end should keep them (file names included:
    /// results refer to them by these names).
    pub artifacts: Vec<Artifact>,
    /// Lines of a human summary (numbers in short form, see [`short`]).
    pub summary: Vec<String>,
}

impl<R> Outcome<R> {
    /// An outcome with `result` and nothing else yet.
    pub fn new(result: R) -> Self {
        Self {
            result,
            artifacts: Vec::new(),
            summary: Vec::new(),
        }
    }

    /// Adds a summary line.
    pub fn line(&mut self, line: impl Into<String>) {
        self.summary.push(line.into());
    }

    /// Adds the drawing of the robot, or, when it could not be built, a warning line saying
    /// why (a drawing never fails a study).
    pub fn robot(&mut self, caption: impl Into<String>, scene: Result<Scene, String>) {
        match scene {
            Ok(scene) => self.artifacts.push(Artifact::Robot {
                caption: caption.into(),
                scene: Box::new(scene),
            }),
            Err(reason) => self.line(format!("warning: no drawing of the robot: {reason}")),
        }
    }
}

/// A table or figure of a study.
#[derive(Debug, Clone)]
pub enum Artifact {
    /// A table (kept as a CSV file `name`).
    Table {
        /// File name, e.g. `slice-1-xy.csv`.
        name: String,
        /// The data.
        table: Table,
    },
    /// A chart (kept as an SVG file `name`, rendered by a front end with `pkm_draw::chart::render_svg`).
    Chart {
        /// File name, e.g. `slice-1-xy.svg`.
        name: String,
        /// The chart.
        chart: Box<Chart>,
    },
    /// The robot the study studied (kept as [`ROBOT_SVG`](crate::scene::ROBOT_SVG) and
    /// [`ROBOT_CSV`](crate::scene::ROBOT_CSV)).
    Robot {
        /// Caption of the drawing.
        caption: String,
        /// The scene.
        scene: Box<Scene>,
    },
}

/// One cell of a [`Table`]. The kind is the column's type for a front end that keeps types
/// (Python: float64, int64 and bool arrays, lists of strings); the CSV text is the same for a
/// count as a number and for a flag as 0 or 1.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// A number (written as its shortest round-trip decimal).
    Number(f64),
    /// A count or an index (a grid node, a start).
    Integer(u64),
    /// Yes or no (written 1 or 0): membership.
    Flag(bool),
    /// No value (written empty).
    Missing,
    /// Text, written as CSV needs it (quoted when it holds a comma, a quote or a line break,
    /// its quotes doubled); an empty text in a column of text is a row without one.
    Text(String),
}

impl From<f64> for Cell {
    fn from(v: f64) -> Self {
        Self::Number(v)
    }
}

impl From<Option<f64>> for Cell {
    fn from(v: Option<f64>) -> Self {
        v.map_or(Self::Missing, Self::Number)
    }
}

impl From<bool> for Cell {
    fn from(v: bool) -> Self {
        Self::Flag(v)
    }
}

impl From<usize> for Cell {
    fn from(v: usize) -> Self {
        Self::Integer(v as u64)
    }
}

impl From<String> for Cell {
    fn from(v: String) -> Self {
        Self::Text(v)
    }
}

impl fmt::Display for Cell {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Number(v) => write!(f, "{v}"),
            Self::Integer(n) => write!(f, "{n}"),
            Self::Flag(b) => f.write_str(if *b { "1" } else { "0" }),
            Self::Missing => Ok(()),
            Self::Text(t) if t.contains([',', '"', '\n', '\r']) => {
                write!(f, "\"{}\"", t.replace('"', "\"\""))
            }
            Self::Text(t) => f.write_str(t),
        }
    }
}

/// Rows of named columns.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// Column names.
    pub header: Vec<String>,
    /// Rows, each as long as the header.
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// An empty table with these columns.
    pub fn new(header: impl IntoIterator<Item = impl Into<String>>) -> Self {
        Self {
            header: header.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// The table as CSV: the header line, then one line per row.
    pub fn to_csv(&self) -> String {
        let mut text = self.header.join(",");
        text.push('\n');
        for row in &self.rows {
            let cells: Vec<String> = row.iter().map(Cell::to_string).collect();
            let _ = writeln!(text, "{}", cells.join(","));
        }
        text
    }

    /// Column `name` as numbers (`None` for a missing or text cell), or `None` when there is no
    /// such column.
    pub fn column(&self, name: &str) -> Option<Vec<Option<f64>>> {
        let k = self.header.iter().position(|h| h == name)?;
        Some(
            self.rows
                .iter()
                .map(|row| match row.get(k) {
                    Some(Cell::Number(v)) => Some(*v),
                    Some(Cell::Integer(n)) => Some(*n as f64),
                    Some(Cell::Flag(b)) => Some(f64::from(u8::from(*b))),
                    _ => None,
                })
                .collect(),
        )
    }
}

/// A number for a summary line: at most 6 decimals with trailing zeros dropped, and exponent
/// form (`1e300`, `2.5e-9`) outside [1e-4, 1e9) so a huge or tiny value stays short (files keep
/// every digit).
pub fn short(v: f64) -> String {
    let magnitude = v.abs();
    if v != 0.0 && v.is_finite() && !(1e-4..1e9).contains(&magnitude) {
        let text = format!("{v:.6e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let text = format!("{v:.6}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_are_written_as_csv_needs_them() {
        let cells = [
            Cell::Number(0.5),
            Cell::Integer(7),
            Cell::Flag(true),
            Cell::Flag(false),
            Cell::Missing,
            Cell::Text("plain".into()),
            Cell::Text("a, b".into()),
            Cell::Text("say \"no\"".into()),
        ];
        let written: Vec<String> = cells.iter().map(ToString::to_string).collect();
        assert_eq!(
            written,
            [
                "0.5",
                "7",
                "1",
                "0",
                "",
                "plain",
                "\"a, b\"",
                "\"say \"\"no\"\"\""
            ]
        );
    }

    #[test]
    fn short_numbers_stay_short() {
        assert_eq!(short(1e300), "1e300");
        assert_eq!(short(-2.5e-9), "-2.5e-9");
        assert_eq!(short(0.125), "0.125");
        assert_eq!(short(3.0), "3");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(123_456.123_456_789), "123456.123457");
        assert_eq!(short(f64::NAN), "NaN");
    }

    #[test]
    fn tables_write_csv_cells_as_the_command_did() {
        let mut t = Table::new(["x", "inside", "v"]);
        t.rows.push(vec![0.1.into(), true.into(), None.into()]);
        t.rows
            .push(vec![2.0.into(), false.into(), Some(0.5).into()]);
        assert_eq!(t.to_csv(), "x,inside,v\n0.1,1,\n2,0,0.5\n");
        assert_eq!(t.column("v"), Some(vec![None, Some(0.5)]));
        assert_eq!(t.column("w"), None);
    }
}
