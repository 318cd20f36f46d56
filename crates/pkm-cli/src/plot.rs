//! SVG figures with plotters (after `xtask/src/plot.rs`): heat maps with a colour bar and
//! scatter plots with highlighted points. Built without plotters' `ttf` feature: text is written
//! as SVG `<text>`, so rendering needs no system font library.

use plotters::prelude::*;
use std::ops::Range;
use std::path::Path;

const SIZE: (u32, u32) = (900, 600);
const FONT: &str = "sans-serif";
const TITLE: u32 = 26;
const LABEL: u32 = 18;
const TICK: u32 = 15;

/// A labelled point drawn over a figure.
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// Position.
    pub x: f64,
    /// Position.
    pub y: f64,
    /// Label.
    pub label: String,
}

/// Values on the grid `x × y` (cell centres, increasing), `values[iy * x.len() + ix]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Heatmap {
    /// Title.
    pub title: String,
    /// Axis label.
    pub x_label: String,
    /// Axis label.
    pub y_label: String,
    /// Colour-bar label.
    pub z_label: String,
    /// Cell centres along x.
    pub x: Vec<f64>,
    /// Cell centres along y.
    pub y: Vec<f64>,
    /// Values, `None` where there is none (drawn blank).
    pub values: Vec<Option<f64>>,
    /// Points marked on the map.
    pub markers: Vec<Marker>,
}

/// Points, some highlighted (drawn larger and labelled).
#[derive(Debug, Clone, PartialEq)]
pub struct Scatter {
    /// Title.
    pub title: String,
    /// Axis label.
    pub x_label: String,
    /// Axis label.
    pub y_label: String,
    /// Background points (grey).
    pub background: Vec<(f64, f64)>,
    /// Foreground points (joined by a line, in order).
    pub front: Vec<(f64, f64)>,
    /// Labelled points.
    pub markers: Vec<Marker>,
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

fn text_error<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// The finite range of `values`, padded by 5 % (a unit range around a single value).
pub fn range(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return 0.0..1.0;
    }
    let pad = if hi - lo > 0.0 {
        0.05 * (hi - lo)
    } else {
        0.5_f64.max(0.05 * lo.abs())
    };
    lo - pad..hi + pad
}

/// Cell edges around increasing `centres`: midpoints inside, mirrored half-steps at the ends.
pub fn edges(centres: &[f64]) -> Vec<f64> {
    let half = |a: f64, b: f64| 0.5 * (b - a);
    let first_half = match centres {
        [a, b, ..] => half(*a, *b),
        _ => 0.5,
    };
    let last_half = match centres {
        [.., a, b] => half(*a, *b),
        _ => 0.5,
    };
    let mut edges: Vec<f64> = centres
        .first()
        .map(|c| c - first_half)
        .into_iter()
        .collect();
    edges.extend(centres.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    edges.extend(centres.last().map(|c| c + last_half));
    edges
}

/// From the first to the last edge (a unit range when there are none).
pub fn span(edges: &[f64]) -> Range<f64> {
    match (edges.first(), edges.last()) {
        (Some(&lo), Some(&hi)) if hi > lo => lo..hi,
        _ => range(edges.iter().copied()),
    }
}

/// Position of `z` in `[lo, hi]` as a fraction; the middle when the range is a point.
pub fn fraction(z: f64, lo: f64, hi: f64) -> f64 {
    if hi > lo {
        ((z - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.5
    }
}

/// Renders `map` to an SVG file at `path`.
///
/// # Errors
/// plotters' message when the file cannot be written.
pub fn heatmap(map: &Heatmap, path: &Path) -> Result<(), String> {
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(text_error)?;
    let area = root.titled(&map.title, (FONT, TITLE)).map_err(text_error)?;
    draw_heatmap(&area, map).map_err(text_error)?;
    root.present().map_err(text_error)
}

fn draw_heatmap<'a>(area: &Area<'a>, map: &Heatmap) -> Result<(), Box<dyn std::error::Error + 'a>> {
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
    let (lo, hi) = finite()
        .fold(None, |r: Option<(f64, f64)>, v| {
            Some(r.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))))
        })
        .unwrap_or((0.0, 1.0));
    let nx = map.x.len().max(1);
    let cells = map.values.iter().enumerate().filter_map(|(k, v)| {
        let v = v.filter(|v| v.is_finite())?;
        let (ix, iy) = (k % nx, k / nx);
        let corners = [
            (*xe.get(ix)?, *ye.get(iy)?),
            (*xe.get(ix + 1)?, *ye.get(iy + 1)?),
        ];
        Some(Rectangle::new(
            corners,
            ViridisRGB.get_color(fraction(v, lo, hi)).filled(),
        ))
    });
    chart.draw_series(cells)?;
    for m in &map.markers {
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

fn colour_bar<'a>(
    area: &Area<'a>,
    label: &str,
    lo: f64,
    hi: f64,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
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
        let colour = ViridisRGB.get_color(fraction(z0 + 0.5 * step, lo, hi));
        Rectangle::new([(0.0, z0), (1.0, z0 + step)], colour.filled())
    }))?;
    Ok(())
}

/// Renders `plot` to an SVG file at `path`.
///
/// # Errors
/// plotters' message when the file cannot be written.
pub fn scatter(plot: &Scatter, path: &Path) -> Result<(), String> {
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(text_error)?;
    let area = root
        .titled(&plot.title, (FONT, TITLE))
        .map_err(text_error)?;
    draw_scatter(&area, plot).map_err(text_error)?;
    root.present().map_err(text_error)
}

fn draw_scatter<'a>(
    area: &Area<'a>,
    plot: &Scatter,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
    let all = || {
        plot.background
            .iter()
            .chain(&plot.front)
            .copied()
            .chain(plot.markers.iter().map(|m| (m.x, m.y)))
    };
    let mut chart = ChartBuilder::on(area)
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(range(all().map(|p| p.0)), range(all().map(|p| p.1)))?;
    chart
        .configure_mesh()
        .label_style((FONT, TICK))
        .axis_desc_style((FONT, LABEL))
        .x_desc(&plot.x_label)
        .y_desc(&plot.y_label)
        .draw()?;
    let grey = RGBColor(170, 170, 170);
    chart
        .draw_series(
            plot.background
                .iter()
                .map(|p| Circle::new(*p, 2, grey.filled())),
        )?
        .label("designs")
        .legend(move |(x, y)| Circle::new((x + 10, y), 2, grey.filled()));
    chart
        .draw_series(LineSeries::new(
            plot.front.iter().copied(),
            BLUE.stroke_width(2),
        ))?
        .label("non-dominated")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE.stroke_width(2)));
    chart.draw_series(plot.front.iter().map(|p| Circle::new(*p, 4, BLUE.filled())))?;
    let x_range = range(all().map(|p| p.0));
    let middle = 0.5 * (x_range.start + x_range.end);
    for (k, m) in plot.markers.iter().enumerate() {
        // Labels are stacked below their points and kept inside the plot: those in the right
        // half end at their point.
        let width = 8 * i32::try_from(m.label.chars().count()).unwrap_or(40);
        let dx = if m.x > middle { -width - 10 } else { 10 };
        let dy = 8 + 18 * i32::try_from(k).unwrap_or(0);
        let label = EmptyElement::at((m.x, m.y))
            + Circle::new((0, 0), 7, RED.stroke_width(2))
            + Text::new(
                m.label.clone(),
                (dx, dy),
                (FONT, LABEL).into_font().color(&RED),
            );
        chart.draw_series(std::iter::once(label))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .label_font((FONT, TICK))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
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
}
