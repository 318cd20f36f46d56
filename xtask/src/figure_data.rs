//! The data behind every figure, as CSV beside its SVG: the points of a line plot, the cells
//! of a heatmap (and its markers), the points of a robot drawing.

use pkm::papers::{Figure, FigureKind, Heatmap};
use std::fmt::Write as _;

/// One CSV field: quoted when it holds a comma, a quote or a line break.
pub(crate) fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// The CSV of `figure`:
/// - a line plot: `series,x,y`, one row per point of every series;
/// - a heatmap: `x,y,z`, one row per cell, `z` empty where the field is undefined;
/// - an annotated heatmap: `x,y,z,marker`, the cells (no marker) and then the markers (no `z`);
/// - a robot drawing: `element,index,label,kind,x,y,z` of `pkm_draw::Scene::to_csv`.
pub(crate) fn csv(figure: &Figure) -> String {
    match &figure.kind {
        FigureKind::Lines(plot) => {
            let mut out = String::from("series,x,y\n");
            for series in &plot.series {
                let label = field(&series.label);
                for (x, y) in &series.points {
                    // Writing to a String cannot fail.
                    let _ = writeln!(out, "{label},{x},{y}");
                }
            }
            out
        }
        FigureKind::Heatmap(map) => cells(map, "x,y,z\n", ""),
        FigureKind::AnnotatedHeatmap { map, markers } => {
            let mut out = cells(map, "x,y,z,marker\n", ",");
            for m in markers {
                let _ = writeln!(out, "{},{},,{}", m.x, m.y, field(&m.label));
            }
            out
        }
        FigureKind::Robot(drawing) => drawing.scene.to_csv(),
    }
}

/// Header, then `x,y,z` of every cell of `map` followed by `suffix`.
fn cells(map: &Heatmap, header: &str, suffix: &str) -> String {
    let mut out = header.to_owned();
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

#[cfg(test)]
mod tests {
    use super::*;
    use pkm::papers::{LinePlot, LineSeries, Marker, SeriesStyle};

    fn map() -> Heatmap {
        Heatmap {
            x_label: "a".into(),
            y_label: "b".into(),
            z_label: "z".into(),
            x: vec![0.0, 1.0],
            y: vec![5.0],
            values: vec![Some(0.5), None],
        }
    }

    fn figure(kind: FigureKind) -> Figure {
        Figure {
            name: "f".into(),
            title: "t".into(),
            kind,
        }
    }

    #[test]
    fn every_kind_of_figure_has_its_data_as_csv() {
        let lines = figure(FigureKind::Lines(LinePlot {
            x_label: "t".into(),
            y_label: "τ".into(),
            series: vec![LineSeries {
                label: "tau_1, Hamilton".into(),
                style: SeriesStyle::Line,
                points: vec![(0.0, 1.5), (0.001, -2.0)],
            }],
        }));
        assert_eq!(
            csv(&lines),
            "series,x,y\n\"tau_1, Hamilton\",0,1.5\n\"tau_1, Hamilton\",0.001,-2\n"
        );
        assert_eq!(
            csv(&figure(FigureKind::Heatmap(map()))),
            "x,y,z\n0,5,0.5\n1,5,\n"
        );
        let annotated = figure(FigureKind::AnnotatedHeatmap {
            map: map(),
            markers: vec![Marker {
                label: "optimum".into(),
                x: 0.25,
                y: 5.0,
            }],
        });
        assert_eq!(
            csv(&annotated),
            "x,y,z,marker\n0,5,0.5,\n1,5,,\n0.25,5,,optimum\n"
        );
    }
}
