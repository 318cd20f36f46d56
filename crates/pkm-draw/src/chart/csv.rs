//! The data behind a chart, as CSV.

use super::{Chart, Heatmap, Plot, Series};
use crate::csv::field;
use std::fmt::Write as _;

/// [`Chart::to_csv`].
pub(super) fn chart(chart: &Chart) -> String {
    let marked = !chart.markers.is_empty();
    // With markers, every data row gets an empty last column.
    let suffix = if marked { "," } else { "" };
    let mut out = match &chart.plot {
        Plot::Heatmap(map) => cells(map, suffix),
        Plot::Series(series) => points(series, suffix),
    };
    let heatmap = matches!(chart.plot, Plot::Heatmap(_));
    for m in &chart.markers {
        let label = field(&m.label);
        // Writing to a String cannot fail.
        let _ = if heatmap {
            writeln!(out, "{},{},,{label}", m.x, m.y)
        } else {
            writeln!(out, ",{},{},{label}", m.x, m.y)
        };
    }
    out
}

/// `x,y,z[,marker]`, then `x,y,z` of every cell (x fastest), `z` empty without a value.
fn cells(map: &Heatmap, suffix: &str) -> String {
    let mut out = format!("x,y,z{}\n", if suffix.is_empty() { "" } else { ",marker" });
    let nx = map.x.len().max(1);
    for (k, value) in map.values.iter().enumerate() {
        let (Some(x), Some(y)) = (map.x.get(k % nx), map.y.get(k / nx)) else {
            continue;
        };
        let z = value.map(|z| z.to_string()).unwrap_or_default();
        let _ = writeln!(out, "{x},{y},{z}{suffix}");
    }
    out
}

/// `series,x,y[,marker]`, then one row per point of every series.
fn points(series: &[Series], suffix: &str) -> String {
    let mut out = format!(
        "series,x,y{}\n",
        if suffix.is_empty() { "" } else { ",marker" }
    );
    for s in series {
        let label = field(&s.label);
        for (x, y) in &s.points {
            let _ = writeln!(out, "{label},{x},{y}{suffix}");
        }
    }
    out
}
