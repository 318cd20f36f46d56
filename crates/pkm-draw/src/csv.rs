//! The data behind a drawing, as CSV.

use crate::{PathKind, Scene};
use nalgebra::Vector3;
use pkm_mechanisms::{LinkKind, PointKind};
use std::fmt::Write as _;

/// A label as one CSV field: quoted when it holds a comma, a quote or a line break.
pub(crate) fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

fn row(out: &mut String, element: &str, index: usize, label: &str, kind: &str, p: &Vector3<f64>) {
    // Writing to a String cannot fail.
    let _ = writeln!(
        out,
        "{element},{index},{},{kind},{},{},{}",
        field(label),
        p.x,
        p.y,
        p.z
    );
}

fn point_kind(kind: PointKind) -> &'static str {
    match kind {
        PointKind::Base => "base",
        PointKind::Actuator => "actuator",
        PointKind::BaseJoint => "base_joint",
        PointKind::Passive => "passive",
        PointKind::Platform => "platform",
        PointKind::Centre => "centre",
    }
}

pub(crate) fn link_kind(kind: LinkKind) -> &'static str {
    match kind {
        LinkKind::Base => "base",
        LinkKind::Actuated => "actuated",
        LinkKind::Passive => "passive",
        LinkKind::Platform => "platform",
    }
}

fn path_kind(kind: PathKind) -> &'static str {
    match kind {
        PathKind::Trajectory => "trajectory",
        PathKind::Boundary => "boundary",
        PathKind::WorkspacePoints => "workspace_points",
    }
}

pub(crate) fn scene(scene: &Scene) -> String {
    let mut out = String::from("element,index,label,kind,x,y,z\n");
    let points = &scene.skeleton.points;
    for (i, p) in points.iter().enumerate() {
        row(
            &mut out,
            "point",
            i,
            &p.label,
            point_kind(p.kind),
            &p.position,
        );
    }
    for (k, link) in scene.skeleton.links.iter().enumerate() {
        for end in [link.from, link.to] {
            if let Some(p) = points.get(end) {
                row(
                    &mut out,
                    "link",
                    k,
                    &p.label,
                    link_kind(link.kind),
                    &p.position,
                );
            }
        }
    }
    for (i, axis) in scene.axes.iter().enumerate() {
        let unit = axis.direction / axis.direction.norm();
        row(&mut out, "axis", i, &axis.label, "point", &axis.point);
        row(
            &mut out,
            "axis",
            i,
            &axis.label,
            "point_plus_unit_direction",
            &(axis.point + unit),
        );
    }
    for (i, path) in scene.paths.iter().enumerate() {
        for p in &path.points {
            row(&mut out, "path", i, &path.label, path_kind(path.kind), p);
        }
    }
    out
}
