//! The starts of a multistart study as artifacts: `starts.csv` (each start and where it ended)
//! and `starts.svg` (the values reached, best first, the best labelled with its start). Shared
//! by the `optimize` and `task` studies, with the bounds of their variables.

use crate::outcome::{Artifact, Cell, Table};
use crate::{KeyPath, StudyError};
use pkm_draw::chart::{Chart, Colour, LegendPosition, Marker, Series, SeriesStyle};
use pkm_optimizers::{MultistartRun, OptimizeError};
use pkm_traits::Bounds;
use std::fmt::Display;

/// The bounds `[lo, hi]` a study gives the variable `name` at `path`.
///
/// # Errors
/// [`StudyError::Invalid`] at `path` unless `lo <= hi`, both finite.
pub(crate) fn variable_bounds(
    path: KeyPath,
    name: &str,
    lo: f64,
    hi: f64,
) -> Result<Bounds, StudyError> {
    Bounds::new(lo, hi).map_err(|e| {
        let m = format!("{name} = [{lo}, {hi}]: expected [lower, upper] with lower <= upper");
        StudyError::invalid(path, format!("{m} ({e})"))
    })
}

/// Where one start ended: the design, then the numbers of its row (the value, then any
/// further column), and the termination.
pub(crate) struct Reached<'a, T: Display> {
    pub design: &'a [f64],
    pub numbers: Vec<f64>,
    pub termination: T,
}

/// `starts.csv` and `starts.svg`: `names` the design variables, `quantities` the columns after
/// the design (the first is the value the chart ranks), `rows` each start's row from
/// [`start_row`], `values` the values reached, `best_start` the start the study chose.
pub(crate) fn starts_artifacts(
    names: &[&str],
    quantities: &[&str],
    rows: Vec<Vec<Cell>>,
    chart: Chart,
) -> [Artifact; 2] {
    let mut header: Vec<String> = vec!["start".into()];
    header.extend(names.iter().map(|n| format!("start_{n}")));
    header.extend(names.iter().map(|n| (*n).to_owned()));
    header.extend(quantities.iter().map(|q| (*q).to_owned()));
    header.push("termination".into());
    let mut table = Table::new(header);
    table.rows = rows;
    [
        Artifact::Table {
            name: "starts.csv".into(),
            table,
        },
        Artifact::Chart {
            name: "starts.svg".into(),
            chart: Box::new(chart),
        },
    ]
}

/// Every start's row of `run` ([`start_row`]): `reached` says where a successful start ended,
/// a failed one has `missing` empty cells.
pub(crate) fn start_rows<'a, R, T: Display>(
    run: &'a MultistartRun<R>,
    missing: usize,
    reached: impl Fn(&'a R) -> Reached<'a, T>,
) -> Vec<Vec<Cell>> {
    run.starts
        .iter()
        .zip(&run.outcomes)
        .enumerate()
        .map(|(k, (start, o))| start_row(k, start, o.as_ref().map(&reached), missing))
        .collect()
}

/// Start `k`'s row: the start, then the design reached, its numbers and termination, or
/// `missing` empty cells and the reason it failed.
fn start_row<T: Display>(
    k: usize,
    start: &[f64],
    outcome: Result<Reached<'_, T>, &OptimizeError>,
    missing: usize,
) -> Vec<Cell> {
    let mut row = vec![Cell::from(k)];
    row.extend(start.iter().map(|v| Cell::Number(*v)));
    match outcome {
        Ok(r) => {
            row.extend(r.design.iter().map(|v| Cell::Number(*v)));
            row.extend(r.numbers.into_iter().map(Cell::Number));
            row.push(Cell::Text(r.termination.to_string()));
        }
        Err(e) => {
            row.extend(std::iter::repeat_n(Cell::Missing, missing));
            row.push(Cell::Text(e.to_string()));
        }
    }
    row
}

/// The values reached, best first (largest first when `maximise`; ties in start order), ranked
/// from 1, the best labelled with `best_start`.
pub(crate) fn ranked_chart(
    title: String,
    quantity: &str,
    mut reached: Vec<f64>,
    maximise: bool,
    best_start: usize,
) -> Chart {
    reached.sort_by(|a, b| {
        if maximise {
            b.total_cmp(a)
        } else {
            a.total_cmp(b)
        }
    });
    let ranked: Vec<(f64, f64)> = reached
        .iter()
        .enumerate()
        .map(|(rank, v)| (rank as f64 + 1.0, *v))
        .collect();
    let marker = ranked
        .first()
        .map(|&(x, y)| Marker::new(format!("start {best_start}"), x, y));
    let series = vec![
        Series::points("designs", ranked).with_colour(Colour::Rgb([170, 170, 170])),
        Series::styled("non-dominated", SeriesStyle::LineAndPoints, Vec::new())
            .with_colour(Colour::Rgb([0, 0, 255])),
    ];
    Chart::series(title, "rank", quantity, series)
        .with_markers(marker)
        .with_legend(LegendPosition::LowerLeft)
}
