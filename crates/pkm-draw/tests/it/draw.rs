//! The SVG of a scene: produced, one element per link in every view, deterministic; hostile
//! input is a typed error.
#![allow(clippy::unwrap_used)]

use nalgebra::{Isometry3, Vector3};
use pkm_draw::{
    Axis, DrawError, DrawOptions, Link, LinkKind, PathKind, PointKind, Scene, Skeleton,
    SkeletonPoint, View, render_skeleton_svg, render_svg,
};
use pkm_mechanisms::{
    ElbowMode, LegBranch, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios,
    Placement, RotaryDelta, StewartDesign, StewartGough, ThreeUpu, Tsai3Dof, TsaiDesign,
    platform_pose, presets,
};
use pkm_screw_theory::Twist;

fn skeletons() -> Vec<(&'static str, Skeleton)> {
    let delta = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
    let nuwar = RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap();
    let p = Vector3::new(0.0, -0.2, -0.9);
    let linear = LinearDelta::new(LinearDeltaDesign {
        ratios: LinearDeltaRatios::from_slice(&[2.0, 0.0, 0.0, 0.63]),
        yr: 1.0,
    })
    .unwrap();
    let tsai = Tsai3Dof::new(TsaiDesign::from_deg(0.44, 0.56, 0.1, 0.0, 120.0, 240.0)).unwrap();
    let sg = StewartGough::new(StewartDesign::from_deg(12.0, 8.0, 30.0, 8.0)).unwrap();
    let pose = platform_pose(Vector3::new(1.0, 0.0, 30.0), Vector3::x(), 0.2).unwrap();
    let upu = ThreeUpu::new(presets::park_3upu()).unwrap();
    let up = Isometry3::translation(0.0, 0.0, 40.0);
    vec![
        (
            "delta",
            Skeleton::rotary_delta(&delta, &p, ElbowMode::Out).unwrap(),
        ),
        (
            "nuwar",
            Skeleton::rotary_delta(&nuwar, &p, ElbowMode::Out).unwrap(),
        ),
        (
            "linear delta",
            Skeleton::linear_delta(
                &linear,
                &Vector3::new(0.0, 0.0, -1.0),
                LinearDeltaMode::PAPER,
            )
            .unwrap(),
        ),
        (
            "tsai",
            Skeleton::tsai(
                &tsai,
                &Vector3::new(0.0, 0.0, 0.5),
                LegBranch::PRINCIPAL_OUT,
            )
            .unwrap(),
        ),
        ("stewart", Skeleton::stewart_gough(&sg, &pose).unwrap()),
        ("3-upu", Skeleton::three_upu(&upu, &up).unwrap()),
    ]
}

/// The stroke colours of the four link kinds, as plotters writes them.
const LINK_STROKES: [&str; 4] = [
    "stroke=\"#5A5A5A\"",
    "stroke=\"#C82828\"",
    "stroke=\"#285AC8\"",
    "stroke=\"#148C3C\"",
];

fn link_elements(svg: &str) -> usize {
    svg.lines()
        .filter(|l| l.contains("<polyline") && LINK_STROKES.iter().any(|s| l.contains(s)))
        .count()
}

#[test]
fn every_mechanism_is_drawn_with_one_element_per_link_in_every_view() {
    for (name, skeleton) in skeletons() {
        for views in [vec![View::Front], View::ALL.to_vec()] {
            let options = DrawOptions {
                views: views.clone(),
                labels: false,
                ..DrawOptions::titled(name)
            };
            let svg = render_skeleton_svg(&skeleton, &options).unwrap();
            assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
            assert!(svg.contains(name));
            // Every link in every view, and one legend entry per kind of link present.
            let kinds = [
                LinkKind::Base,
                LinkKind::Actuated,
                LinkKind::Passive,
                LinkKind::Platform,
            ]
            .into_iter()
            .filter(|k| skeleton.links_of(*k).next().is_some())
            .count();
            assert_eq!(
                link_elements(&svg),
                views.len() * skeleton.links.len() + kinds,
                "{name}: {views:?}"
            );
            // One marker per point in every view: circles, and a cross (two lines) for p.
            let centres = skeleton
                .points
                .iter()
                .filter(|p| p.kind == PointKind::Centre)
                .count();
            let circles = svg.matches("<circle").count();
            assert_eq!(
                circles,
                views.len() * (skeleton.points.len() - centres),
                "{name}"
            );
        }
    }
}

#[test]
fn the_svg_is_deterministic_and_shows_the_extras() {
    let (_, skeleton) = skeletons().remove(1);
    let chi = Twist::new(Vector3::new(0.0, 1.0, 1.0), Vector3::new(0.1, 0.0, 0.0));
    let path: Vec<_> = (0..10)
        .map(|k| Vector3::new(0.0, 0.04 * f64::from(k) - 0.2, -0.9))
        .collect();
    let scene = Scene::new(skeleton)
        .with_axis(Axis::of_twist("task twist", &chi, Vector3::zeros()).unwrap())
        .with_path("trajectory", PathKind::Trajectory, path.clone())
        .with_path("boundary", PathKind::Boundary, path.clone())
        .with_path("points", PathKind::WorkspacePoints, path);
    let options = DrawOptions::titled("NUWAR with extras");
    let first = render_svg(&scene, &options).unwrap();
    assert_eq!(first, render_svg(&scene, &options).unwrap());
    for text in [
        "task twist",
        "trajectory",
        "boundary",
        "points",
        "front (x-z)",
        "3-D",
        "A1",
    ] {
        assert!(first.contains(text), "{text}");
    }
    // The axis: one orange line per view (and one in the legend); joint axes of one label share
    // a colour and a legend entry.
    assert_eq!(first.matches("stroke=\"#E68200\"").count(), 5);
    let joint = |point: Vector3<f64>| Axis {
        label: "joint axis".into(),
        point,
        direction: Vector3::x(),
        length: Some(0.05),
    };
    let joints = scene
        .clone()
        .with_axis(joint(Vector3::zeros()))
        .with_axis(joint(Vector3::new(0.0, 0.0, -0.5)));
    let svg = render_svg(&joints, &options).unwrap();
    assert_eq!(svg.matches("stroke=\"#C8008C\"").count(), 2 * 4 + 1);
    let mut bad = joints;
    bad.axes[1].length = Some(f64::NAN);
    assert!(matches!(
        render_svg(&bad, &options),
        Err(DrawError::InvalidOption { .. })
    ));
    let csv = scene.to_csv();
    let rows: Vec<&str> = csv.lines().collect();
    let n = &scene.skeleton;
    assert_eq!(rows.len(), 1 + n.points.len() + 2 * n.links.len() + 2 + 30);
    assert!(
        rows.iter()
            .any(|r| r.starts_with("axis,0,task twist,point,"))
    );
}

#[test]
fn the_axis_of_a_twist_is_its_screw_axis() {
    // A rotation about the line through (1, 2, 0) along z: v = s0 × ω.
    let s0 = Vector3::new(1.0, 2.0, 0.0);
    let w = Vector3::new(0.0, 0.0, 2.0);
    let axis = Axis::of_twist("z", &Twist::new(w, s0.cross(&w)), Vector3::zeros()).unwrap();
    assert!((axis.point - s0).norm() < 1e-15);
    assert!(axis.direction.cross(&w).norm() < 1e-15);
    let through = Vector3::new(0.0, 0.0, 5.0);
    let slide = Twist::translation(&Vector3::x(), 1.0).unwrap();
    let axis = Axis::of_twist("x", &slide, through).unwrap();
    assert_eq!(axis.point, through);
    let zero = Twist::new(Vector3::zeros(), Vector3::zeros());
    assert_eq!(
        Axis::of_twist("0", &zero, through),
        Err(DrawError::ZeroDirection { index: 0 })
    );
}

fn point(x: f64) -> SkeletonPoint {
    SkeletonPoint {
        label: "q".into(),
        kind: PointKind::Passive,
        position: Vector3::new(x, 0.0, 0.0),
    }
}

#[test]
fn hostile_input_is_a_typed_error() {
    let options = DrawOptions::default();
    assert_eq!(
        render_skeleton_svg(&Skeleton::default(), &options),
        Err(DrawError::Empty)
    );
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e300, -1e13] {
        let skeleton = Skeleton {
            points: vec![point(0.0), point(bad)],
            links: vec![],
        };
        assert!(matches!(
            render_skeleton_svg(&skeleton, &options),
            Err(DrawError::BadCoordinate { index: 1, .. })
        ));
    }
    let dangling = Skeleton {
        points: vec![point(0.0)],
        links: vec![Link {
            from: 0,
            to: 7,
            kind: LinkKind::Passive,
        }],
    };
    assert!(matches!(
        render_skeleton_svg(&dangling, &options),
        Err(DrawError::NoSuchPoint { point: 7, .. })
    ));
    let one = Skeleton {
        points: vec![point(0.0)],
        links: vec![],
    };
    let scene = Scene::new(one.clone()).with_axis(Axis {
        label: "none".into(),
        point: Vector3::zeros(),
        direction: Vector3::zeros(),
        length: None,
    });
    assert!(matches!(
        render_svg(&scene, &options),
        Err(DrawError::ZeroDirection { index: 0 })
    ));
    let scene = Scene::new(one.clone()).with_path(
        "nan",
        PathKind::Trajectory,
        vec![Vector3::new(0.0, f64::NAN, 0.0)],
    );
    assert!(matches!(
        render_svg(&scene, &options),
        Err(DrawError::BadCoordinate { .. })
    ));
    for bad in [
        DrawOptions {
            size: (0, 500),
            ..DrawOptions::default()
        },
        DrawOptions {
            size: (500, u32::MAX),
            ..DrawOptions::default()
        },
        DrawOptions {
            views: vec![],
            ..DrawOptions::default()
        },
        DrawOptions {
            views: vec![View::Top; 5],
            ..DrawOptions::default()
        },
    ] {
        assert!(matches!(
            render_skeleton_svg(&one, &bad),
            Err(DrawError::InvalidOption { .. })
        ));
    }
    // A single point and coincident points still draw (degenerate extents are padded).
    assert!(render_skeleton_svg(&one, &options).is_ok());
    let huge = Scene::new(one).with_path(
        "many",
        PathKind::WorkspacePoints,
        vec![Vector3::zeros(); pkm_draw::MAX_POINTS],
    );
    assert!(matches!(
        render_svg(&huge, &options),
        Err(DrawError::TooManyPoints { .. })
    ));
}
