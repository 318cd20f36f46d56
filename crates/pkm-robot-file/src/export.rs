//! A robot file with its masses exported as URDF plus a loop-closure sidecar (issue 31), for
//! tools that take a tree and constraints (Pinocchio's closed-loop models, as Gepetto's
//! `example-parallel-robots` and `toolbox-parallel-robots` describe them).
//!
//! The tree: a massless `base` link; every leg a serial chain of its elementary joints from
//! `base` (a spherical joint as three revolute joints about z, y, x through its centre, the
//! order in which $R = R_z(\gamma) R_y(\beta) R_x(\alpha)$) ending in a link `leg<i>_end`;
//! the `platform` link is fixed to `leg0_end`, and a 6-D closure welds every other
//! `leg<i>_end` to the frame `platform_leg<i>`, fixed on the platform where that leg's end is
//! at home. Every link
//! frame is parallel to the base frame at home, at its joint's point (a prismatic joint keeps
//! its parent's point), so each joint's origin is a translation and its axis is the file's
//! axis; joint values are zero at home. Each body of the file (link, point mass, platform) is
//! a link of its own, fixed to the link that carries it, its inertial frame at its centre of
//! mass. Actuated joints are named `..._mot` (the sidecar's `name_mot`); an actuator's limits
//! become the joint's, shifted by its offset.

use crate::chain::Joint;
use crate::mass::Body;
use crate::model::RobotModel;
use nalgebra::{Matrix3, Vector3};
use std::fmt::Write;

/// A robot exported for tree-plus-constraint tools.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UrdfExport {
    /// The URDF document.
    pub urdf: String,
    /// The loop closures as YAML: `closed_loop` (pairs of frames), `type` (`6D` each),
    /// `name_mot` and `number_motor`.
    pub closures: String,
}

/// One URDF joint being written.
struct UrdfJoint<'a> {
    name: String,
    kind: &'a str,
    parent: String,
    child: String,
    origin: Vector3<f64>,
    axis: Vector3<f64>,
    limits: Option<[f64; 2]>,
}

impl RobotModel {
    /// The robot as URDF with its loop closures (module documentation). A robot without
    /// mass properties exports massless links.
    pub fn to_urdf(&self) -> UrdfExport {
        let mut out = String::new();
        let _ = writeln!(out, "<?xml version=\"1.0\"?>");
        let _ = writeln!(
            out,
            "<!-- {} exported by pkm: {} legs -->",
            xml(&self.name),
            self.legs.len()
        );
        let _ = writeln!(out, "<robot name=\"{}\">", xml(&self.name));
        let _ = writeln!(out, "  <link name=\"base\"/>");
        let home = self.home_pose.translation.vector;
        let mut closures = Vec::new();
        let mut riding: Vec<Body> = self.mass.platform.into_iter().collect();
        for (i, leg) in self.legs.iter().enumerate() {
            let mut parent = ("base".to_string(), Vector3::zeros());
            let mut carriers = Vec::with_capacity(leg.joints.len());
            for (j, joint) in leg.joints.iter().enumerate() {
                let last = j + 1 == leg.joints.len();
                let child = if last {
                    format!("leg{i}_end")
                } else {
                    format!("leg{i}_link{j}")
                };
                let suffix = if leg.is_actuated(j) { "_mot" } else { "" };
                let limits = leg
                    .actuator_at(j)
                    .and_then(|a| a.limits.map(|[lo, hi]| [lo - a.offset, hi - a.offset]));
                let name = format!("leg{i}_joint{j}{suffix}");
                let joints = match *joint {
                    Joint::Revolute { axis, point } => vec![(name, "revolute", axis, point)],
                    Joint::Prismatic { axis } => vec![(name, "prismatic", axis, parent.1)],
                    Joint::Spherical { center } => [
                        ("z", Vector3::z()),
                        ("y", Vector3::y()),
                        ("x", Vector3::x()),
                    ]
                    .into_iter()
                    .map(|(tag, axis)| (format!("{name}_{tag}"), "revolute", axis, center))
                    .collect(),
                };
                let count = joints.len();
                for (k, (name, kind, axis, at)) in joints.into_iter().enumerate() {
                    let link = if k + 1 == count {
                        child.clone()
                    } else {
                        format!("{child}_{k}")
                    };
                    let origin = at;
                    write_link(&mut out, &link);
                    write_joint(
                        &mut out,
                        &UrdfJoint {
                            name,
                            kind,
                            parent: parent.0.clone(),
                            child: link.clone(),
                            origin: origin - parent.1,
                            axis,
                            limits,
                        },
                    );
                    parent = (link, origin);
                }
                carriers.push(parent.clone());
            }
            if i == 0 {
                write_link(&mut out, "platform");
                write_fixed(&mut out, &parent.0, "platform", home - parent.1);
            } else {
                let frame = format!("platform_leg{i}");
                write_link(&mut out, &frame);
                write_fixed(&mut out, "platform", &frame, parent.1 - home);
                closures.push((parent.0.clone(), frame));
            }
            for (k, body) in leg.bodies.iter().enumerate() {
                if body.after >= leg.joints.len() {
                    riding.push(*body);
                    continue;
                }
                let carrier = match body.after {
                    0 => ("base".to_string(), Vector3::zeros()),
                    a => carriers[a - 1].clone(),
                };
                write_body(&mut out, &format!("leg{i}_body{k}"), &carrier, body);
            }
        }
        for (k, body) in riding.iter().enumerate() {
            write_body(
                &mut out,
                &format!("platform_body{k}"),
                &("platform".into(), home),
                body,
            );
        }
        let _ = writeln!(out, "</robot>");
        UrdfExport {
            urdf: out,
            closures: closure_yaml(&self.name, &closures, self.actuator_count()),
        }
    }
}

fn closure_yaml(name: &str, closures: &[(String, String)], motors: usize) -> String {
    let mut out = format!("# loop closures of {name}, exported by pkm\nclosed_loop:\n");
    for (a, b) in closures {
        let _ = writeln!(out, "  - [{a}, {b}]");
    }
    let types = vec!["6D"; closures.len()].join(", ");
    let _ = writeln!(
        out,
        "type: [{types}]\nname_mot: mot\nnumber_motor: {motors}"
    );
    out
}

fn write_link(out: &mut String, name: &str) {
    let _ = writeln!(out, "  <link name=\"{name}\"/>");
}

fn write_fixed(out: &mut String, parent: &str, child: &str, origin: Vector3<f64>) {
    let _ = writeln!(
        out,
        "  <joint name=\"{child}_fixed\" type=\"fixed\">\n    <parent link=\"{parent}\"/>\n    \
         <child link=\"{child}\"/>\n    <origin xyz=\"{}\" rpy=\"0 0 0\"/>\n  </joint>",
        triple(&origin)
    );
}

fn write_joint(out: &mut String, j: &UrdfJoint<'_>) {
    let kind = match (j.kind, j.limits) {
        ("revolute", None) => "continuous",
        (kind, _) => kind,
    };
    let _ = writeln!(
        out,
        "  <joint name=\"{}\" type=\"{kind}\">\n    <parent link=\"{}\"/>\n    <child link=\"{}\"/>\n    \
         <origin xyz=\"{}\" rpy=\"0 0 0\"/>\n    <axis xyz=\"{}\"/>",
        j.name,
        j.parent,
        j.child,
        triple(&j.origin),
        triple(&j.axis)
    );
    if kind != "continuous" {
        let [lower, upper] = j.limits.unwrap_or([-1e3, 1e3]);
        let _ = writeln!(
            out,
            "    <limit lower=\"{lower:e}\" upper=\"{upper:e}\" effort=\"1e9\" velocity=\"1e9\"/>"
        );
    }
    let _ = writeln!(out, "  </joint>");
}

/// A body as a link fixed to `carrier` (its name and frame origin), its inertial frame at the
/// centre of mass, axes parallel to the carrier's.
fn write_body(out: &mut String, name: &str, carrier: &(String, Vector3<f64>), body: &Body) {
    let i: &Matrix3<f64> = &body.inertia;
    let _ = writeln!(
        out,
        "  <link name=\"{name}\">\n    <inertial>\n      <origin xyz=\"{}\" rpy=\"0 0 0\"/>\n      \
         <mass value=\"{:e}\"/>\n      <inertia ixx=\"{:e}\" ixy=\"{:e}\" ixz=\"{:e}\" iyy=\"{:e}\" \
         iyz=\"{:e}\" izz=\"{:e}\"/>\n    </inertial>\n  </link>",
        triple(&(body.center - carrier.1)),
        body.mass,
        i[(0, 0)],
        i[(0, 1)],
        i[(0, 2)],
        i[(1, 1)],
        i[(1, 2)],
        i[(2, 2)]
    );
    write_fixed(out, &carrier.0, name, Vector3::zeros());
}

pub(crate) fn triple(v: &Vector3<f64>) -> String {
    format!("{:e} {:e} {:e}", v.x, v.y, v.z)
}

/// `text` with XML's special characters escaped.
pub(crate) fn xml(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
pub(crate) mod tests {
    use crate::chain::JointValue;
    use crate::model::RobotModel;
    use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
    use std::collections::HashMap;

    /// A URDF joint as read back.
    struct Read {
        kind: String,
        parent: String,
        child: String,
        origin: Vector3<f64>,
        axis: Vector3<f64>,
    }

    /// The six files the exports are checked on: distance, arm and numerical legs, spherical
    /// joints, a passive leg, two actuators in a leg.
    pub(crate) const EXPORT_FILES: [&str; 6] = [
        include_str!("../../../examples/robots/stewart_gough.toml"),
        include_str!("../../../examples/robots/rotary_delta.toml"),
        include_str!("../../../examples/robots/three_prs.toml"),
        include_str!("../../../examples/robots/tricept.toml"),
        include_str!("../../../examples/robots/three_ppsr.toml"),
        include_str!("../../../examples/robots/five_bar.toml"),
    ];

    /// The file's masses: every leg body and the platform (kg).
    pub(crate) fn total_mass(model: &RobotModel) -> f64 {
        model
            .legs
            .iter()
            .flat_map(|l| &l.bodies)
            .map(|b| b.mass)
            .sum::<f64>()
            + model.mass.platform.map_or(0.0, |p| p.mass)
    }

    /// Three numbers of an XML attribute (`xyz="1 2 3"`).
    pub(crate) fn vector(text: &str) -> Vector3<f64> {
        let v: Vec<f64> = text
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        Vector3::new(v[0], v[1], v[2])
    }

    /// Every link's frame for the joint values `values` (missing: 0), by reading the URDF
    /// back with an XML parser and composing parent ∘ origin ∘ motion down the tree.
    fn frames(urdf: &str, values: &HashMap<String, f64>) -> HashMap<String, Isometry3<f64>> {
        let doc = roxmltree::Document::parse(urdf).unwrap();
        let joints: Vec<(String, Read)> = doc
            .descendants()
            .filter(|n| n.has_tag_name("joint"))
            .map(|j| {
                let child = |tag: &str, attribute: &str| {
                    j.children()
                        .find(|c| c.has_tag_name(tag))
                        .and_then(|c| c.attribute(attribute))
                        .map(str::to_string)
                };
                let read = Read {
                    kind: j.attribute("type").unwrap().into(),
                    parent: child("parent", "link").unwrap(),
                    child: child("child", "link").unwrap(),
                    origin: vector(&child("origin", "xyz").unwrap()),
                    axis: child("axis", "xyz").map_or(Vector3::z(), |a| vector(&a)),
                };
                (j.attribute("name").unwrap().to_string(), read)
            })
            .collect();
        let mut placed = HashMap::from([("base".to_string(), Isometry3::identity())]);
        while placed.len() <= joints.len() {
            let before = placed.len();
            for (name, j) in &joints {
                let Some(parent) = placed.get(&j.parent).copied() else {
                    continue;
                };
                let value = values.get(name).copied().unwrap_or(0.0);
                let motion = match j.kind.as_str() {
                    "revolute" | "continuous" => Isometry3::from_parts(
                        Translation3::identity(),
                        UnitQuaternion::from_axis_angle(&Unit::new_normalize(j.axis), value),
                    ),
                    "prismatic" => {
                        Isometry3::translation(j.axis.x * value, j.axis.y * value, j.axis.z * value)
                    }
                    _ => Isometry3::identity(),
                };
                let origin = Isometry3::translation(j.origin.x, j.origin.y, j.origin.z);
                placed
                    .entry(j.child.clone())
                    .or_insert(parent * origin * motion);
            }
            assert!(placed.len() > before, "a link is not reached from base");
        }
        placed
    }

    /// The URDF joint values of a configuration of `model`.
    fn values(model: &RobotModel, config: &crate::closure::Configuration) -> HashMap<String, f64> {
        let mut out = HashMap::new();
        for (i, leg) in model.legs.iter().enumerate() {
            for (j, value) in config.joints[i].iter().enumerate() {
                let suffix = if leg.is_actuated(j) { "_mot" } else { "" };
                let name = format!("leg{i}_joint{j}{suffix}");
                match value {
                    JointValue::Scalar(v) => {
                        out.insert(name, *v);
                    }
                    JointValue::Ball(r) => {
                        let (roll, pitch, yaw) = r.euler_angles();
                        out.insert(format!("{name}_z"), yaw);
                        out.insert(format!("{name}_y"), pitch);
                        out.insert(format!("{name}_x"), roll);
                    }
                }
            }
        }
        out
    }

    /// The exported tree closes its loops (every `leg<i>_end` on its `platform_leg<i>`, 6-D,
    /// to 1e-9) and carries the platform to the model's pose, at home and at 5 poses near it,
    /// on six files (distance, arm and numerical legs, a spherical joint, a passive leg, two
    /// actuators in a leg); its masses sum to the file's.
    #[test]
    fn the_exported_tree_closes_its_loops_and_keeps_the_masses() {
        for text in EXPORT_FILES {
            let model = RobotModel::from_toml(text).unwrap();
            let export = model.to_urdf();
            let legs = model.legs.len();
            assert_eq!(export.closures.matches("  - [").count(), legs - 1);
            for k in 0..6 {
                let mut x = model.home_task();
                for (c, v) in x.iter_mut().enumerate() {
                    *v += 0.004 * f64::from(k) * (1.0 + c as f64).sin();
                }
                let config = model
                    .inverse_kinematics_configuration(&x, model.home_mode())
                    .unwrap();
                let frames = frames(&export.urdf, &values(&model, &config));
                for i in 1..legs {
                    let (end, weld) = (
                        &frames[&format!("leg{i}_end")],
                        &frames[&format!("platform_leg{i}")],
                    );
                    let gap = (end.translation.vector - weld.translation.vector).norm()
                        + end.rotation.angle_to(&weld.rotation);
                    assert!(
                        gap < 1e-9,
                        "{}: leg {i} open by {gap:e} at pose {k}",
                        model.name
                    );
                }
                let pose = crate::pose::platform_pose(model.orientation, &config.pose);
                let expected = pose
                    * model.home_pose.inverse()
                    * Isometry3::translation(
                        model.home_pose.translation.vector.x,
                        model.home_pose.translation.vector.y,
                        model.home_pose.translation.vector.z,
                    );
                let platform = frames["platform"];
                let gap = (platform.translation.vector - expected.translation.vector).norm()
                    + platform.rotation.angle_to(&expected.rotation);
                assert!(
                    gap < 1e-9,
                    "{}: platform off by {gap:e} at pose {k}",
                    model.name
                );
            }
            let doc = roxmltree::Document::parse(&export.urdf).unwrap();
            let urdf_mass: f64 = doc
                .descendants()
                .filter(|n| n.has_tag_name("mass"))
                .map(|n| n.attribute("value").unwrap().parse::<f64>().unwrap())
                .sum();
            let file_mass = total_mass(&model);
            assert!(
                (urdf_mass - file_mass).abs() < 1e-12 * file_mass,
                "{}",
                model.name
            );
        }
    }
}
