//! The SVG itself, with plotters (no `ttf` feature: text is written as SVG `<text>`, so no
//! system font library is needed).

use crate::csv::link_kind;
use crate::{DrawError, DrawOptions, PathKind, Scene, View};
use nalgebra::Vector3;
use pkm_mechanisms::{LinkKind, PointKind};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::ops::Range;

const FONT: &str = "sans-serif";
const TITLE: u32 = 20;
const VIEW_NAME: u32 = 16;
const TICK: u32 = 12;
const LABEL: u32 = 11;

/// Margins of a view's chart, pixels: around, above (for the view's name), and the tick-label
/// areas below and to the left.
const MARGIN: u32 = 10;
const MARGIN_TOP: u32 = 30;
const X_LABELS: u32 = 35;
const Y_LABELS: u32 = 60;

pub(crate) const LINK_COLOURS: [(LinkKind, RGBColor, u32); 4] = [
    (LinkKind::Base, RGBColor(90, 90, 90), 4),
    (LinkKind::Actuated, RGBColor(200, 40, 40), 3),
    (LinkKind::Passive, RGBColor(40, 90, 200), 2),
    (LinkKind::Platform, RGBColor(20, 140, 60), 3),
];

const TRAJECTORY_COLOUR: RGBColor = RGBColor(140, 40, 170);
const BOUNDARY_COLOUR: RGBColor = RGBColor(0, 150, 160);

fn point_style(kind: PointKind) -> (RGBColor, u32) {
    match kind {
        PointKind::Base => (RGBColor(90, 90, 90), 2),
        PointKind::Actuator => (RGBColor(200, 40, 40), 5),
        PointKind::BaseJoint => (RGBColor(90, 90, 90), 4),
        PointKind::Passive => (RGBColor(40, 90, 200), 4),
        PointKind::Platform => (RGBColor(20, 140, 60), 4),
        PointKind::Centre => (BLACK, 5),
    }
}

fn backend<E: std::fmt::Display>(error: E) -> DrawError {
    DrawError::Backend(error.to_string())
}

pub(crate) fn svg(scene: &Scene, options: &DrawOptions) -> Result<String, DrawError> {
    let segments = axis_segments(scene);
    let mut buffer = String::new();
    {
        let root = SVGBackend::with_string(&mut buffer, options.size).into_drawing_area();
        root.fill(&WHITE).map_err(backend)?;
        let area = if options.title.is_empty() {
            root.clone()
        } else {
            root.titled(&options.title, (FONT, TITLE))
                .map_err(backend)?
        };
        let grid = match options.views.len() {
            1 => (1, 1),
            2 => (1, 2),
            _ => (2, 2),
        };
        let panels = area.split_evenly(grid);
        let last = options.views.len() - 1;
        for (k, (view, panel)) in options.views.iter().zip(&panels).enumerate() {
            draw_view(panel, *view, scene, &segments, options, k == last)?;
        }
        root.present().map_err(backend)?;
    }
    Ok(buffer)
}

/// Each axis as a segment: of its own length about its point, or centred on its point nearest
/// the skeleton's centroid and as long as 2.4 times the skeleton's radius about the centroid (1
/// when the skeleton is a point).
fn axis_segments(scene: &Scene) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    let points = &scene.skeleton.points;
    let n = points.len().max(1) as f64;
    let centroid = points
        .iter()
        .fold(Vector3::zeros(), |s, p| s + p.position / n);
    let radius = points
        .iter()
        .map(|p| (p.position - centroid).norm())
        .fold(0.0, f64::max);
    let across = if radius > 0.0 { 1.2 * radius } else { 1.0 };
    scene
        .axes
        .iter()
        .map(|axis| {
            let d = axis.direction / axis.direction.norm();
            let (centre, half) = match axis.length {
                Some(length) => (axis.point, 0.5 * length),
                None => (axis.point + d * (centroid - axis.point).dot(&d), across),
            };
            (centre - d * half, centre + d * half)
        })
        .collect()
}

/// Colours of the axes, by the order in which their labels first appear.
const AXIS_COLOURS: [RGBColor; 6] = [
    RGBColor(230, 130, 0),
    RGBColor(200, 0, 140),
    RGBColor(120, 80, 20),
    RGBColor(0, 170, 200),
    RGBColor(120, 140, 0),
    RGBColor(90, 60, 200),
];

/// For each axis, its colour index and whether it is the first with its label (and so gets the
/// legend entry).
fn axis_colours(scene: &Scene) -> Vec<(usize, bool)> {
    let mut labels: Vec<&str> = Vec::new();
    scene
        .axes
        .iter()
        .map(|axis| match labels.iter().position(|l| *l == axis.label) {
            Some(k) => (k, false),
            None => {
                labels.push(&axis.label);
                (labels.len() - 1, true)
            }
        })
        .collect()
}

/// Equal-scale ranges holding every `(u, v)` on a plot of `pixels`, padded by 8 %.
fn ranges(points: &[(f64, f64)], pixels: (u32, u32)) -> (Range<f64>, Range<f64>) {
    let fold = |f: fn(&(f64, f64)) -> f64| {
        points
            .iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            })
    };
    let ((u0, u1), (v0, v1)) = (fold(|p| p.0), fold(|p| p.1));
    let (w, h) = (f64::from(pixels.0.max(1)), f64::from(pixels.1.max(1)));
    let span = ((u1 - u0) / w).max((v1 - v0) / h) * 1.08;
    let per_pixel = if span > 0.0 { span } else { 1.0 / w };
    let (cu, cv) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
    (
        cu - 0.5 * per_pixel * w..cu + 0.5 * per_pixel * w,
        cv - 0.5 * per_pixel * h..cv + 0.5 * per_pixel * h,
    )
}

fn draw_view(
    panel: &DrawingArea<SVGBackend<'_>, Shift>,
    view: View,
    scene: &Scene,
    segments: &[(Vector3<f64>, Vector3<f64>)],
    options: &DrawOptions,
    legend: bool,
) -> Result<(), DrawError> {
    let project = |p: &Vector3<f64>| view.project(p);
    let mut all: Vec<(f64, f64)> = scene
        .skeleton
        .points
        .iter()
        .map(|p| project(&p.position))
        .collect();
    all.extend(segments.iter().flat_map(|(a, b)| [project(a), project(b)]));
    all.extend(
        scene
            .paths
            .iter()
            .flat_map(|p| p.points.iter().map(project)),
    );
    let (width, height) = panel.dim_in_pixel();
    let plot = (
        width.saturating_sub(2 * MARGIN + Y_LABELS),
        height.saturating_sub(MARGIN + MARGIN_TOP + X_LABELS),
    );
    let (u, v) = ranges(&all, plot);
    panel
        .draw_text(view.name(), &(FONT, VIEW_NAME).into_font().into(), (8, 6))
        .map_err(backend)?;
    let mut chart = ChartBuilder::on(panel)
        .margin(MARGIN)
        .margin_top(MARGIN_TOP)
        .x_label_area_size(X_LABELS)
        .y_label_area_size(Y_LABELS)
        .build_cartesian_2d(u, v)
        .map_err(backend)?;
    let (h, v) = view.axis_names();
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(5)
        .y_labels(5)
        .label_style((FONT, TICK))
        .x_desc(format!("{h} ({})", options.unit))
        .y_desc(format!("{v} ({})", options.unit))
        .axis_desc_style((FONT, TICK))
        .draw()
        .map_err(backend)?;

    for path in &scene.paths {
        let points = path.points.iter().map(project);
        let drawn = match path.kind {
            PathKind::Trajectory | PathKind::Boundary => {
                let (colour, width) = match path.kind {
                    PathKind::Trajectory => (TRAJECTORY_COLOUR, 2),
                    _ => (BOUNDARY_COLOUR, 1),
                };
                let style = colour.stroke_width(width);
                chart
                    .draw_series(LineSeries::new(points, style))
                    .map_err(backend)?
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], style))
            }
            PathKind::WorkspacePoints => chart
                .draw_series(points.map(|p| Circle::new(p, 1, BOUNDARY_COLOUR.filled())))
                .map_err(backend)?
                .legend(|(x, y)| Circle::new((x + 8, y), 2, BOUNDARY_COLOUR.filled())),
        };
        drawn.label(path.label.as_str());
    }

    let points = &scene.skeleton.points;
    for (kind, colour, width) in LINK_COLOURS {
        let style = colour.stroke_width(width);
        let links: Vec<_> = scene.skeleton.links_of(kind).collect();
        if links.is_empty() {
            continue;
        }
        chart
            .draw_series(links.into_iter().map(|l| {
                PathElement::new(
                    [
                        project(&points[l.from].position),
                        project(&points[l.to].position),
                    ],
                    style,
                )
            }))
            .map_err(backend)?
            .label(format!("{} link", link_kind(kind)))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], style));
    }

    for ((axis, (a, b)), (colour, first)) in
        scene.axes.iter().zip(segments).zip(axis_colours(scene))
    {
        let style = AXIS_COLOURS[colour % AXIS_COLOURS.len()].stroke_width(2);
        let drawn = chart
            .draw_series(std::iter::once(PathElement::new(
                [project(a), project(b)],
                style,
            )))
            .map_err(backend)?;
        if first {
            drawn
                .label(axis.label.as_str())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], style));
        }
    }

    for p in points {
        let (colour, radius) = point_style(p.kind);
        let at = project(&p.position);
        if p.kind == PointKind::Centre {
            chart
                .draw_series(std::iter::once(Cross::new(
                    at,
                    radius,
                    colour.stroke_width(2),
                )))
                .map_err(backend)?;
        } else {
            chart
                .draw_series(std::iter::once(Circle::new(at, radius, colour.filled())))
                .map_err(backend)?;
        }
        if options.labels && view == View::ThreeD {
            let text = Text::new(p.label.clone(), (5, -14), (FONT, LABEL).into_font());
            chart
                .draw_series(std::iter::once(EmptyElement::at(at) + text))
                .map_err(backend)?;
        }
    }

    if legend {
        let position = emptiest_corner(&all, chart.x_range(), chart.y_range());
        chart
            .configure_series_labels()
            .label_font((FONT, TICK))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(position)
            .draw()
            .map_err(backend)?;
    }
    Ok(())
}

/// The corner of the plot with the fewest of `points` in its outer 40 % × 40 %, for the legend
/// (upper right first on ties).
fn emptiest_corner(points: &[(f64, f64)], u: Range<f64>, v: Range<f64>) -> SeriesLabelPosition {
    let (du, dv) = (0.4 * (u.end - u.start), 0.4 * (v.end - v.start));
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let count = |right: bool, upper: bool| {
        points
            .iter()
            .filter(|(x, y)| {
                let horizontal = if right {
                    *x >= u.end - du
                } else {
                    *x <= u.start + du
                };
                let vertical = if upper {
                    *y >= v.end - dv
                } else {
                    *y <= v.start + dv
                };
                horizontal && vertical
            })
            .count()
    };
    let mut best = (SeriesLabelPosition::UpperRight, usize::MAX);
    for (position, right, upper) in corners {
        let n = count(right, upper);
        if n < best.1 {
            best = (position, n);
        }
    }
    best.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_have_one_scale_and_hold_every_point() {
        let points = [(0.0, 0.0), (2.0, 1.0)];
        let (u, v) = ranges(&points, (400, 100));
        let (su, sv) = ((u.end - u.start) / 400.0, (v.end - v.start) / 100.0);
        assert!((su - sv).abs() < 1e-15);
        for (x, y) in points {
            assert!(u.contains(&x) && v.contains(&y));
        }
        let corner = emptiest_corner(&[(1.9, 0.9), (1.8, 0.1)], u.clone(), v.clone());
        assert!(matches!(corner, SeriesLabelPosition::UpperLeft));
        let (u, v) = ranges(&[(3.0, 3.0)], (100, 100));
        assert!(u.end > u.start && v.end > v.start && u.contains(&3.0));
    }
}
