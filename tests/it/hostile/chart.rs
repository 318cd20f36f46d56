//! `pkm-draw`'s chart layer: heat maps and series with hostile numbers.

use super::{config, hostile_f64, judge};
use pkm_draw::chart::{Chart, Heatmap, Marker, Series, SeriesStyle, render_svg};
use proptest::collection::vec;
use proptest::option;
use proptest::prelude::*;

/// Within the drawable range: finite and at most 1e300 in magnitude.
fn drawable(v: f64) -> bool {
    v.abs() <= 1e300
}

/// Sorted centres (so that finite ones often increase strictly), and values that fit the grid
/// or do not.
fn heatmap() -> impl Strategy<Value = Heatmap> {
    (
        vec(hostile_f64(), 0..4),
        vec(hostile_f64(), 0..4),
        any::<bool>(),
    )
        .prop_flat_map(|(mut x, mut y, fits)| {
            x.sort_by(f64::total_cmp);
            y.sort_by(f64::total_cmp);
            let n = x.len() * y.len() + usize::from(!fits);
            (Just(x), Just(y), vec(option::of(hostile_f64()), n..=n))
        })
        .prop_map(|(x, y, values)| Heatmap {
            colour_axis: "z".into(),
            x,
            y,
            values,
        })
}

fn markers() -> impl Strategy<Value = Vec<Marker>> {
    vec(
        (hostile_f64(), hostile_f64()).prop_map(|(x, y)| Marker::new("m", x, y)),
        0..3,
    )
}

fn series() -> impl Strategy<Value = Vec<Series>> {
    let style = prop::sample::select(vec![
        SeriesStyle::Line,
        SeriesStyle::Dashed,
        SeriesStyle::Points,
        SeriesStyle::LineAndPoints,
    ]);
    vec(
        (style, vec((hostile_f64(), hostile_f64()), 0..5))
            .prop_map(|(style, points)| Series::styled("s", style, points)),
        0..3,
    )
}

fn well_formed(svg: &str) -> bool {
    svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>")
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn heat_maps_are_drawn_only_from_drawable_grids(map in heatmap(), markers in markers()) {
        let increasing = |c: &[f64]| !c.is_empty() && c.windows(2).all(|w| w[1] > w[0]);
        let valid = increasing(&map.x)
            && increasing(&map.y)
            && map.values.len() == map.x.len() * map.y.len()
            && map.x.iter().chain(&map.y).copied().all(drawable)
            && map.values.iter().flatten().copied().all(drawable)
            && markers.iter().all(|m| drawable(m.x) && drawable(m.y));
        let chart = Chart::heatmap("map", "x", "y", map).with_markers(markers);
        judge("chart::render_svg (heat map)", || render_svg(&chart), |svg| valid && well_formed(svg))?;
        // And every drawable grid is drawn.
        prop_assert_eq!(render_svg(&chart).is_ok(), valid);
    }

    #[test]
    fn series_are_drawn_only_from_drawable_points(series in series(), markers in markers()) {
        let valid = series.iter().flat_map(|s| &s.points).all(|p| drawable(p.0) && drawable(p.1))
            && markers.iter().all(|m| drawable(m.x) && drawable(m.y));
        let chart = Chart::series("series", "x", "y", series).with_markers(markers);
        judge("chart::render_svg (series)", || render_svg(&chart), |svg| valid && well_formed(svg))?;
        prop_assert_eq!(render_svg(&chart).is_ok(), valid);
    }
}
