//! The chart layer: hostile input is a typed error (never a panic), the same chart gives the
//! same bytes, and the SVG and CSV hold the chart's content.
#![allow(clippy::unwrap_used)]

use pkm_draw::chart::{
    CLOUD, Chart, ChartError, Colour, Heatmap, LegendPosition, MAX_ITEMS, Marker, Plot, Quantity,
    Series, SeriesStyle, render_svg,
};

/// A 3 × 2 map with two undefined cells, and two markers.
fn map() -> Chart {
    Chart::heatmap(
        "GCI landscape",
        Quantity::new("a", "m"),
        Quantity::new("b", "m"),
        Heatmap {
            colour_axis: Quantity::new("GCI", ""),
            x: vec![0.0, 1.0, 2.0],
            y: vec![0.0, 0.5],
            values: vec![Some(0.1), None, Some(0.3), Some(0.4), Some(0.5), None],
        },
    )
    .with_markers([
        Marker::new("optimum", 2.0, 0.5),
        Marker::new("paper", 0.2, 0.1),
    ])
}

/// Torques by two methods: solid lines, dashed lines sharing their colours, and points.
fn lines() -> Chart {
    Chart::series(
        "motor torques",
        Quantity::new("t", "s"),
        Quantity::new("torque", "N m"),
        vec![
            Series::line(
                "Hamilton, motor 1",
                vec![(0.0, 1.0), (0.5, 2.0), (1.0, 1.5)],
            )
            .with_colour(Colour::Palette(0)),
            Series::styled(
                "Lagrange, motor 1",
                SeriesStyle::Dashed,
                vec![(0.0, 1.1), (0.5, 2.1), (1.0, 1.4)],
            )
            .with_colour(Colour::Palette(0)),
            Series::points("paper", vec![(0.25, 1.2), (0.75, 1.9)]),
            Series::styled("", SeriesStyle::LineAndPoints, vec![(0.1, 0.9), (0.9, 1.0)])
                .with_colour(Colour::Rgb([0, 0, 255])),
        ],
    )
    .with_legend(LegendPosition::LowerLeft)
}

fn count(svg: &str, pattern: &str) -> usize {
    svg.matches(pattern).count()
}

#[test]
fn the_same_chart_gives_the_same_bytes() {
    for chart in [map(), lines()] {
        let first = render_svg(&chart).unwrap();
        assert_eq!(render_svg(&chart.clone()).unwrap(), first);
        assert!(first.starts_with("<svg") && first.trim_end().ends_with("</svg>"));
    }
}

#[test]
fn a_heat_map_has_its_texts_and_one_rectangle_per_defined_cell() {
    let svg = render_svg(&map()).unwrap();
    for text in ["GCI landscape", "a (m)", "b (m)", "GCI", "optimum", "paper"] {
        assert!(
            svg.contains(&format!("\n{text}\n")),
            "the heat map lacks {text}"
        );
    }
    // The same map with every cell undefined: what remains is the frame and the colour bar.
    let mut empty = map();
    let Plot::Heatmap(m) = &mut empty.plot else {
        unreachable!()
    };
    m.values = vec![None; 6];
    let frame = count(&render_svg(&empty).unwrap(), "<rect");
    assert_eq!(
        count(&svg, "<rect") - frame,
        4,
        "one rectangle per defined cell"
    );
    // The colour bar's 64 steps and a white background.
    assert!(frame >= 65, "{frame}");
    // Markers are rings (no fill).
    assert_eq!(count(&svg, "<circle"), 2);
}

#[test]
fn a_line_chart_has_its_texts_lines_points_and_legend() {
    let chart = lines();
    let svg = render_svg(&chart).unwrap();
    for text in [
        "motor torques",
        "t (s)",
        "torque (N m)",
        "Hamilton, motor 1",
        "Lagrange, motor 1",
        "paper",
    ] {
        assert!(
            svg.contains(&format!("\n{text}\n")),
            "the line chart lacks {text}"
        );
    }
    // Two dots of "paper" and its legend dot, two dots of the unlabelled line-and-points.
    assert_eq!(count(&svg, "<circle"), 5);
    // The dashed series is drawn as dashes: more than one path element.
    assert!(
        count(&svg, "<polyline") + count(&svg, "<path") >= 4,
        "{svg}"
    );
    // Lagrange is dashed in Hamilton's colour (palette colour 0); the last series is blue.
    let red = "stroke=\"#E6194B\" stroke-width=";
    assert_eq!(
        count(&svg, &format!("{red}\"2\"")),
        2,
        "Hamilton's line and legend"
    );
    assert!(
        count(&svg, &format!("{red}\"1\"")) > 10,
        "Lagrange's dashes"
    );
    assert_eq!(count(&svg, "fill=\"#0000FF\""), 2);
}

#[test]
fn a_cloud_of_points_is_drawn_with_smaller_dots() {
    let dots = |n: u32| {
        let points = (0..n).map(|k| (f64::from(k), f64::from(k % 7))).collect();
        let chart = Chart::series("cloud", "x", "y", vec![Series::points("", points)]);
        let svg = render_svg(&chart).unwrap();
        (count(&svg, "<circle"), count(&svg, "r=\"2\""))
    };
    assert_eq!(dots(CLOUD as u32), (CLOUD, 0));
    assert_eq!(dots(CLOUD as u32 + 1), (CLOUD + 1, CLOUD + 1));
}

#[test]
fn the_data_behind_a_chart_is_its_csv() {
    assert_eq!(
        map().to_csv(),
        "x,y,z,marker\n0,0,0.1,\n1,0,,\n2,0,0.3,\n0,0.5,0.4,\n1,0.5,0.5,\n2,0.5,,\n\
         2,0.5,,optimum\n0.2,0.1,,paper\n"
    );
    let mut plain = map();
    plain.markers.clear();
    assert!(plain.to_csv().starts_with("x,y,z\n0,0,0.1\n1,0,\n"));
    let line = Chart::series(
        "t",
        "t",
        "τ",
        vec![Series::line(
            "tau_1, Hamilton",
            vec![(0.0, 1.5), (0.001, -2.0)],
        )],
    );
    assert_eq!(
        line.to_csv(),
        "series,x,y\n\"tau_1, Hamilton\",0,1.5\n\"tau_1, Hamilton\",0.001,-2\n"
    );
    assert_eq!(
        line.with_markers([Marker::new("best", 0.0, 1.5)]).to_csv(),
        "series,x,y,marker\n\"tau_1, Hamilton\",0,1.5,\n\"tau_1, Hamilton\",0.001,-2,\n,0,1.5,best\n"
    );
}

#[test]
fn a_chart_survives_a_json_round_trip() {
    for chart in [map(), lines()] {
        let json = serde_json::to_string(&chart).unwrap();
        assert_eq!(serde_json::from_str::<Chart>(&json).unwrap(), chart);
    }
    assert!(
        serde_json::to_string(&lines())
            .unwrap()
            .contains("\"style\":\"line_and_points\"")
    );
}

const HOSTILE: [f64; 6] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    1.0001e300,
    -2e300,
    f64::MAX,
];

#[test]
fn non_finite_and_huge_numbers_are_typed_errors_naming_where() {
    for v in HOSTILE {
        let mut chart = map();
        let Plot::Heatmap(m) = &mut chart.plot else {
            unreachable!()
        };
        m.values[3] = Some(v);
        assert!(matches!(
            render_svg(&chart),
            Err(ChartError::BadValue {
                what: "heat-map cell",
                index: 3,
                ..
            })
        ));
        let mut chart = map();
        let Plot::Heatmap(m) = &mut chart.plot else {
            unreachable!()
        };
        m.y[1] = v;
        assert!(matches!(
            render_svg(&chart),
            Err(ChartError::BadValue {
                what: "y centre",
                index: 1,
                ..
            })
        ));
        let mut chart = lines();
        let Plot::Series(s) = &mut chart.plot else {
            unreachable!()
        };
        s[2].points[1].1 = v;
        assert!(matches!(
            render_svg(&chart),
            Err(ChartError::BadPoint {
                series: 2,
                point: 1,
                ..
            })
        ));
        let chart = lines().with_markers([Marker::new("ok", 0.0, 0.0), Marker::new("m", v, 0.0)]);
        let error = render_svg(&chart).unwrap_err();
        assert!(matches!(
            error,
            ChartError::BadValue {
                what: "marker",
                index: 1,
                ..
            }
        ));
        assert!(error.to_string().contains("marker 1"), "{error}");
    }
}

#[test]
fn malformed_grids_and_texts_are_typed_errors() {
    let with_map = |edit: &dyn Fn(&mut Heatmap)| {
        let mut chart = map();
        let Plot::Heatmap(m) = &mut chart.plot else {
            unreachable!()
        };
        edit(m);
        render_svg(&chart)
    };
    assert!(matches!(
        with_map(&|m| m.x.clear()),
        Err(ChartError::EmptyGrid { axis: "x" })
    ));
    assert!(matches!(
        with_map(&|m| m.x[2] = 1.0),
        Err(ChartError::NotIncreasing {
            axis: "x",
            index: 2
        })
    ));
    assert!(matches!(
        with_map(&|m| m.y = vec![1.0, 0.0]),
        Err(ChartError::NotIncreasing {
            axis: "y",
            index: 1
        })
    ));
    assert!(matches!(
        with_map(&|m| m.values.pop().map(drop).unwrap_or(())),
        Err(ChartError::Shape {
            values: 5,
            nx: 3,
            ny: 2
        })
    ));
    // Too many cells is refused before anything of that size is made.
    let side: u32 = 5000;
    assert!(side as usize * side as usize > MAX_ITEMS);
    let error = with_map(&|m| {
        m.x = (0..side).map(f64::from).collect();
        m.y = m.x.clone();
    })
    .unwrap_err();
    assert!(matches!(error, ChartError::InvalidInput(_)), "{error}");
    let mut chart = lines();
    chart.title = "two\nlines".into();
    assert!(matches!(
        render_svg(&chart),
        Err(ChartError::BadText { what: "title", .. })
    ));
    let mut chart = map();
    chart.y_axis.unit = "m\u{0}".into();
    assert!(matches!(
        render_svg(&chart),
        Err(ChartError::BadText { .. })
    ));
}

#[test]
fn degenerate_but_finite_charts_are_drawn() {
    let lone = |x: f64, y: f64, z: Option<f64>| {
        Chart::heatmap(
            "lone",
            "x",
            "y",
            Heatmap {
                colour_axis: "z".into(),
                x: vec![x],
                y: vec![y],
                values: vec![z],
            },
        )
    };
    let series =
        |points: Vec<(f64, f64)>| Chart::series("s", "x", "y", vec![Series::line("a", points)]);
    let charts = [
        // No defined cell: a blank map, colour bar over [0, 1].
        lone(0.0, 0.0, None),
        lone(1e300, -1e300, Some(1e300)),
        lone(-0.0, 5e-324, Some(-1e300)),
        // Nothing to plot: empty axes.
        Chart::series("empty", "x", "y", Vec::new()),
        series(Vec::new()),
        series(vec![(1.0, 1.0)]),
        series(vec![(1e300, -1e300), (-1e300, 1e300)]),
        // Two points one unit in the last place apart, far from zero.
        series(vec![(3.6e16, 1.0), (3.6e16 + 8.0, 1.0 + f64::EPSILON)]),
        series(vec![(5e-324, 0.0), (1e-323, -5e-324)]),
    ];
    for chart in charts {
        let svg = render_svg(&chart).unwrap_or_else(|e| panic!("{}: {e}", chart.title));
        assert!(svg.contains(&format!("\n{}\n", chart.title)));
    }
}

#[test]
fn texts_are_escaped() {
    let mut chart = lines();
    chart.title = "a < b & c".into();
    let svg = render_svg(&chart).unwrap();
    assert!(svg.contains("a &lt; b &amp; c"), "{svg}");
}
