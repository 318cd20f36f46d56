//! A figure of the papers as SVG (charts through `pkm_draw::chart`, robots through `pkm-draw`)
//! and the data behind it as CSV.

use pkm::draw::{DrawOptions, chart, render_svg};
use pkm::papers::{Figure, FigureKind};

/// The SVG of `figure`.
///
/// # Errors
/// The chart layer's or the drawing's typed error for data that cannot be drawn.
pub(crate) fn svg(figure: &Figure) -> anyhow::Result<String> {
    Ok(match &figure.kind {
        FigureKind::Chart(c) => chart::render_svg(c)?,
        FigureKind::Robot(drawing) => {
            let options = DrawOptions {
                unit: drawing.unit.clone(),
                ..DrawOptions::titled(&drawing.title)
            };
            render_svg(&drawing.scene, &options)?
        }
    })
}

/// The CSV of `figure`: a chart's `Chart::to_csv` (a line plot as `series,x,y`; a heat map as
/// `x,y,z`, `z` empty where undefined; with markers a last column `marker`, the cells and then
/// the markers), a robot drawing's `Scene::to_csv` (`element,index,label,kind,x,y,z`).
pub(crate) fn csv(figure: &Figure) -> String {
    match &figure.kind {
        FigureKind::Chart(c) => c.to_csv(),
        FigureKind::Robot(drawing) => drawing.scene.to_csv(),
    }
}

/// One CSV field: quoted when it holds a comma, a quote or a line break.
pub(crate) fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pkm::draw::chart::{Chart, Heatmap, Marker, Series};

    fn map() -> Heatmap {
        Heatmap {
            colour_axis: "z".into(),
            x: vec![0.0, 1.0],
            y: vec![5.0],
            values: vec![Some(0.5), None],
        }
    }

    #[test]
    fn every_kind_of_figure_has_its_data_as_csv() {
        let series = vec![Series::line(
            "tau_1, Hamilton",
            vec![(0.0, 1.5), (0.001, -2.0)],
        )];
        let lines = Figure::chart("f", Chart::series("t", "t", "τ", series));
        assert_eq!(
            csv(&lines),
            "series,x,y\n\"tau_1, Hamilton\",0,1.5\n\"tau_1, Hamilton\",0.001,-2\n"
        );
        let plain = Figure::chart("f", Chart::heatmap("t", "a", "b", map()));
        assert_eq!(csv(&plain), "x,y,z\n0,5,0.5\n1,5,\n");
        let marked =
            Chart::heatmap("t", "a", "b", map()).with_markers([Marker::new("optimum", 0.25, 5.0)]);
        assert_eq!(
            csv(&Figure::chart("f", marked)),
            "x,y,z,marker\n0,5,0.5,\n1,5,,\n0.25,5,,optimum\n"
        );
    }

    #[test]
    fn data_that_cannot_be_drawn_is_an_error() {
        let mut bad = map();
        bad.values[0] = Some(f64::NAN);
        let figure = Figure::chart("f", Chart::heatmap("t", "a", "b", bad));
        let error = svg(&figure).unwrap_err();
        assert!(error.to_string().contains("heat-map cell 0"), "{error}");
    }
}
