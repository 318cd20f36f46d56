//! The one chart renderer: plotters' SVG backend into a string (no `ttf` feature: text is
//! written as SVG `<text>`, so no system font library is needed).

use super::scale::{edges, extent, fraction, padded, span};
use super::{
    CLOUD, Chart, ChartError, Colour, Heatmap, LegendPosition, Marker, Plot, Series, SeriesStyle,
};
use plotters::chart::SeriesAnno;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::ops::Range;

/// Width and height of every chart, pixels.
const SIZE: (u32, u32) = (900, 600);
/// Width of the colour bar beside a heat map, pixels.
const BAR_WIDTH: u32 = 130;
const FONT: &str = "sans-serif";
/// Font sizes (plotters writes them to the SVG scaled by 1/1.24) of title, axis labels and
/// ticks.
const TITLE: u32 = 26;
const LABEL: u32 = 18;
const TICK: u32 = 15;
/// Steps of the colour bar.
const BAR_STEPS: u32 = 64;
const MARKER_COLOUR: RGBColor = RED;

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
type Plane<'a> = ChartContext<'a, SVGBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn backend<E: std::fmt::Display>(error: E) -> ChartError {
    ChartError::Backend(error.to_string())
}

/// Renders `chart` as an SVG document of 900 × 600 pixels: the title above; a heat map as one
/// rectangle per defined cell with a colour bar on the right, or the series over a mesh with a
/// legend; then the markers, each a red ring with its label below it (labels of points in the
/// right half end at their point, and successive labels are stacked so they do not overlap).
///
/// The axes span the heat map's cells, or the points of the series and the markers padded by
/// 5 % (a unit range when there are none).
///
/// # Errors
/// [`Chart::validate`]'s [`ChartError`]s; [`ChartError::Backend`] if plotters fails.
pub fn render_svg(chart: &Chart) -> Result<String, ChartError> {
    chart.validate()?;
    let mut buffer = String::new();
    {
        let root = SVGBackend::with_string(&mut buffer, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(backend)?;
        let area = root.titled(&chart.title, (FONT, TITLE)).map_err(backend)?;
        match &chart.plot {
            Plot::Heatmap(map) => heatmap(&area, chart, map)?,
            Plot::Series(series) => lines(&area, chart, series)?,
        }
        root.present().map_err(backend)?;
    }
    Ok(buffer)
}

/// The cartesian plane of `area` over `x` × `y`, with the chart's axis labels.
fn plane<'a>(
    area: &Area<'a>,
    chart: &Chart,
    x: Range<f64>,
    y: Range<f64>,
    mesh: bool,
) -> Result<Plane<'a>, ChartError> {
    let mut plane = ChartBuilder::on(area)
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x, y)
        .map_err(backend)?;
    let mut style = plane.configure_mesh();
    if !mesh {
        style.disable_mesh();
    }
    style
        .label_style((FONT, TICK))
        .axis_desc_style((FONT, LABEL))
        .x_desc(chart.x_axis.to_string())
        .y_desc(chart.y_axis.to_string())
        .draw()
        .map_err(backend)?;
    Ok(plane)
}

fn heatmap(area: &Area<'_>, chart: &Chart, map: &Heatmap) -> Result<(), ChartError> {
    let (plot_area, bar_area) = area.split_horizontally(SIZE.0 - BAR_WIDTH);
    let (xe, ye) = (edges(&map.x), edges(&map.y));
    let mut plane = plane(&plot_area, chart, span(&xe), span(&ye), false)?;
    let (lo, hi) = extent(map.values.iter().flatten().copied()).unwrap_or((0.0, 1.0));
    let nx = map.x.len();
    // Validated: `values.len() == nx * ny`, so every edge index exists.
    let cells = map.values.iter().enumerate().filter_map(|(k, v)| {
        let (ix, iy) = (k % nx, k / nx);
        let corners = [
            (*xe.get(ix)?, *ye.get(iy)?),
            (*xe.get(ix + 1)?, *ye.get(iy + 1)?),
        ];
        Some(Rectangle::new(
            corners,
            ViridisRGB.get_color(fraction((*v)?, lo, hi)).filled(),
        ))
    });
    plane.draw_series(cells).map_err(backend)?;
    markers(&mut plane, &chart.markers, span(&xe))?;
    colour_bar(&bar_area, &map.colour_axis.to_string(), lo, hi)
}

fn colour_bar(area: &Area<'_>, label: &str, lo: f64, hi: f64) -> Result<(), ChartError> {
    let span = if hi > lo {
        lo..hi
    } else {
        padded([lo].into_iter())
    };
    let mut bar = ChartBuilder::on(area)
        .margin_top(20)
        .margin_bottom(70)
        .margin_right(10)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, span.clone())
        .map_err(backend)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .label_style((FONT, TICK))
        .axis_desc_style((FONT, LABEL))
        .y_desc(label)
        .draw()
        .map_err(backend)?;
    let step = (span.end - span.start) / f64::from(BAR_STEPS);
    bar.draw_series((0..BAR_STEPS).map(|k| {
        let z0 = span.start + step * f64::from(k);
        let colour = ViridisRGB.get_color(fraction(z0 + 0.5 * step, lo, hi));
        Rectangle::new([(0.0, z0), (1.0, z0 + step)], colour.filled())
    }))
    .map_err(backend)?;
    Ok(())
}

fn lines(area: &Area<'_>, chart: &Chart, series: &[Series]) -> Result<(), ChartError> {
    let points = || {
        series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .chain(chart.markers.iter().map(|m| (m.x, m.y)))
    };
    let x = padded(points().map(|p| p.0));
    let y = padded(points().map(|p| p.1));
    let mut plane = plane(area, chart, x.clone(), y, true)?;
    for (index, s) in series.iter().enumerate() {
        draw_series(&mut plane, s, colour(s.colour, index))?;
    }
    markers(&mut plane, &chart.markers, x)?;
    if series.iter().any(|s| !s.label.is_empty()) {
        plane
            .configure_series_labels()
            .position(position(chart.legend))
            .label_font((FONT, TICK))
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(backend)?;
    }
    Ok(())
}

fn colour(colour: Colour, index: usize) -> RGBAColor {
    match colour {
        Colour::Auto => Palette99::pick(index).to_rgba(),
        Colour::Palette(k) => Palette99::pick(k).to_rgba(),
        Colour::Rgb([r, g, b]) => RGBColor(r, g, b).to_rgba(),
    }
}

fn draw_series(plane: &mut Plane<'_>, s: &Series, colour: RGBAColor) -> Result<(), ChartError> {
    let points = s.points.iter().copied();
    let (line, thin, dot) = (
        colour.stroke_width(2),
        colour.stroke_width(1),
        colour.filled(),
    );
    match s.style {
        SeriesStyle::Line | SeriesStyle::LineAndPoints => {
            let drawn = plane
                .draw_series(LineSeries::new(points.clone(), line))
                .map_err(backend)?;
            if let Some(entry) = legend_entry(drawn, &s.label) {
                entry.legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], line));
            }
            if s.style == SeriesStyle::LineAndPoints {
                plane
                    .draw_series(points.map(|p| Circle::new(p, 4, dot)))
                    .map_err(backend)?;
            }
        }
        SeriesStyle::Dashed => {
            let drawn = plane
                .draw_series(DashedLineSeries::new(points, 6, 4, thin))
                .map_err(backend)?;
            if let Some(entry) = legend_entry(drawn, &s.label) {
                entry.legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], thin));
            }
        }
        SeriesStyle::Points => {
            let radius = if s.points.len() > CLOUD { 2 } else { 3 };
            let drawn = plane
                .draw_series(points.map(|p| Circle::new(p, radius, dot)))
                .map_err(backend)?;
            if let Some(entry) = legend_entry(drawn, &s.label) {
                entry.legend(move |(x, y)| Circle::new((x + 10, y), 3, dot));
            }
        }
    }
    Ok(())
}

/// The series' legend entry, labelled `label`; none for an empty label.
fn legend_entry<'a, 'b>(
    drawn: &'b mut SeriesAnno<'a, SVGBackend<'a>>,
    label: &str,
) -> Option<&'b mut SeriesAnno<'a, SVGBackend<'a>>> {
    (!label.is_empty()).then(|| drawn.label(label))
}

/// Each marker as a red ring at its point with its label below; labels of points right of the
/// middle of `x` end at their point, and the k-th label is moved down by k lines so that labels
/// of nearby points do not overlap.
fn markers(plane: &mut Plane<'_>, markers: &[Marker], x: Range<f64>) -> Result<(), ChartError> {
    let middle = 0.5 * (x.start + x.end);
    for (k, m) in markers.iter().enumerate() {
        let width = 8 * i32::try_from(m.label.chars().count()).unwrap_or(1000);
        let dx = if m.x > middle { -width - 10 } else { 10 };
        let dy = 8 + 18 * i32::try_from(k).unwrap_or(0);
        let element = EmptyElement::at((m.x, m.y))
            + Circle::new((0, 0), 7, MARKER_COLOUR.stroke_width(2))
            + Text::new(
                m.label.clone(),
                (dx, dy),
                (FONT, LABEL).into_font().color(&MARKER_COLOUR),
            );
        plane
            .draw_series(std::iter::once(element))
            .map_err(backend)?;
    }
    Ok(())
}

fn position(legend: LegendPosition) -> SeriesLabelPosition {
    match legend {
        LegendPosition::UpperLeft => SeriesLabelPosition::UpperLeft,
        LegendPosition::UpperRight => SeriesLabelPosition::UpperRight,
        LegendPosition::MiddleRight => SeriesLabelPosition::MiddleRight,
        LegendPosition::LowerLeft => SeriesLabelPosition::LowerLeft,
        LegendPosition::LowerRight => SeriesLabelPosition::LowerRight,
    }
}
