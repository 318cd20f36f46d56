//! SVG figures with plotters: line plots with a legend, heatmaps with a colour bar, and robot
//! drawings through `pkm-draw`.
//!
//! plotters is built without its `ttf` feature: text sizes are estimated and text is written as
//! SVG `<text>`, so rendering needs no system font library.

use pkm::draw::{DrawOptions, render_svg};
use pkm::papers::{Figure, FigureKind, Heatmap, LinePlot, Marker, RobotDrawing, SeriesStyle};
use pkm_cli::plot::{edges, fraction, range, span};
use plotters::prelude::*;
use std::path::Path;

const SIZE: (u32, u32) = (900, 600);
const FONT: &str = "sans-serif";
/// Font sizes (plotters writes them to the SVG scaled by 1/1.24) of title, axis labels and ticks.
const TITLE: u32 = 28;
const LABEL: u32 = 18;
const TICK: u32 = 15;

/// Renders `figure` as an SVG file at `path`.
///
/// # Errors
/// When the file cannot be written.
pub(crate) fn render(figure: &Figure, path: &Path) -> anyhow::Result<()> {
    if let FigureKind::Robot(drawing) = &figure.kind {
        return robot(&figure.title, drawing, path);
    }
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let area = root.titled(&figure.title, (FONT, TITLE))?;
    match &figure.kind {
        FigureKind::Lines(plot) => lines(&area, plot)?,
        FigureKind::Heatmap(map) => heatmap(&area, map, &[])?,
        FigureKind::AnnotatedHeatmap { map, markers } => heatmap(&area, map, markers)?,
        FigureKind::Robot(_) => {}
    }
    root.present()?;
    Ok(())
}

/// A robot drawing through `pkm-draw`: front, side, top and 3-D views on one sheet.
fn robot(title: &str, drawing: &RobotDrawing, path: &Path) -> anyhow::Result<()> {
    let options = DrawOptions {
        unit: drawing.unit.clone(),
        ..DrawOptions::titled(title)
    };
    std::fs::write(path, render_svg(&drawing.scene, &options)?)?;
    Ok(())
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

fn lines(area: &Area<'_>, plot: &LinePlot) -> anyhow::Result<()> {
    let points = || plot.series.iter().flat_map(|s| s.points.iter().copied());
    let mut chart = ChartBuilder::on(area)
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(range(points().map(|p| p.0)), range(points().map(|p| p.1)))?;
    chart
        .configure_mesh()
        .label_style((FONT, TICK))
        .axis_desc_style((FONT, LABEL))
        .x_desc(&plot.x_label)
        .y_desc(&plot.y_label)
        .draw()?;
    for (i, series) in plot.series.iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        let finite = series
            .points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite());
        let drawn = match series.style {
            SeriesStyle::Line => chart
                .draw_series(LineSeries::new(finite, colour.stroke_width(2)))?
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
                }),
            SeriesStyle::Points => chart
                .draw_series(finite.map(|p| Circle::new(p, 3, colour.filled())))?
                .legend(move |(x, y)| Circle::new((x + 10, y), 3, colour.filled())),
        };
        drawn.label(&series.label);
    }
    chart
        .configure_series_labels()
        .label_font((FONT, TICK))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

fn colour(t: f64) -> RGBColor {
    ViridisRGB.get_color(t)
}

fn heatmap(area: &Area<'_>, map: &Heatmap, markers: &[Marker]) -> anyhow::Result<()> {
    let (plot_area, bar_area) = area.split_horizontally(SIZE.0 - 130);
    let (xe, ye) = (edges(&map.x), edges(&map.y));
    let mut chart = ChartBuilder::on(&plot_area)
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(span(&xe), span(&ye))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .label_style((FONT, TICK))
        .axis_desc_style((FONT, LABEL))
        .x_desc(&map.x_label)
        .y_desc(&map.y_label)
        .draw()?;
    let finite = || {
        map.values
            .iter()
            .flatten()
            .copied()
            .filter(|z| z.is_finite())
    };
    let z = finite().fold(None, |r: Option<(f64, f64)>, v| {
        Some(r.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))))
    });
    let (lo, hi) = z.unwrap_or((0.0, 1.0));
    let nx = map.x.len();
    let cells = map.values.iter().enumerate().filter_map(|(k, v)| {
        let v = v.filter(|v| v.is_finite())?;
        let (ix, iy) = (k % nx.max(1), k / nx.max(1));
        let corners = [
            (*xe.get(ix)?, *ye.get(iy)?),
            (*xe.get(ix + 1)?, *ye.get(iy + 1)?),
        ];
        Some(Rectangle::new(
            corners,
            colour(fraction(v, lo, hi)).filled(),
        ))
    });
    chart.draw_series(cells)?;
    for m in markers {
        let point = (m.x, m.y);
        chart.draw_series(std::iter::once(Circle::new(point, 6, RED.stroke_width(2))))?;
        chart.draw_series(std::iter::once(Text::new(
            m.label.clone(),
            point,
            (FONT, LABEL).into_font().color(&RED),
        )))?;
    }
    colour_bar(&bar_area, &map.z_label, lo, hi)
}

fn colour_bar(area: &Area<'_>, label: &str, lo: f64, hi: f64) -> anyhow::Result<()> {
    let span = if hi > lo { lo..hi } else { lo - 0.5..hi + 0.5 };
    let mut bar = ChartBuilder::on(area)
        .margin_top(20)
        .margin_bottom(70)
        .margin_right(10)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, span.clone())?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .label_style((FONT, TICK))
        .axis_desc_style((FONT, LABEL))
        .y_desc(label)
        .draw()?;
    const STEPS: u32 = 64;
    let step = (span.end - span.start) / f64::from(STEPS);
    bar.draw_series((0..STEPS).map(|k| {
        let z0 = span.start + step * f64::from(k);
        let colour = colour(fraction(z0 + 0.5 * step, lo, hi));
        Rectangle::new([(0.0, z0), (1.0, z0 + step)], colour.filled())
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_edges_surround_the_centres() {
        assert_eq!(edges(&[0.0, 1.0, 3.0]), [-0.5, 0.5, 2.0, 4.0]);
        assert_eq!(edges(&[2.0]), [1.5, 2.5]);
        assert!(edges(&[]).is_empty());
    }

    #[test]
    fn ranges_skip_non_finite_values_and_pad_degenerate_ones() {
        assert_eq!(range([0.0, f64::NAN, 10.0].into_iter()), -0.5..10.5);
        assert_eq!(range([2.0].into_iter()), 1.5..2.5);
        assert_eq!(range(std::iter::empty()), 0.0..1.0);
    }
}
