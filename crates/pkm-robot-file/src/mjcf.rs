//! A robot file with its masses exported as MuJoCo's MJCF (issue 31), for MuJoCo users.
//!
//! The same tree as the URDF export ([`crate::export`]): every leg a chain of nested bodies
//! from the world, one per elementary joint (`hinge`, `slide`, a spherical joint as one `ball`
//! joint), each body's frame parallel to the world's at home at its joint's point, every joint
//! value zero at home; the `platform` body is a child of leg 0's last body. The other legs
//! close on the platform by equality constraints taken at the home configuration (MuJoCo's
//! `qpos0`): a leg that ends in a spherical joint drops it and `connect`s its last body to the
//! platform at the ball's centre (a 3-D point constraint, which is what the ball allows); any
//! other leg `weld`s its last body to the platform (6-D). Each body of the file (link, point
//! mass, platform) is a jointless child body of the body that carries it, with its
//! `inertial` at its centre of mass; MuJoCo needs a mass on every moving body, so the compiler
//! bounds masses and inertias from below (`boundmass="1e-9"`, `boundinertia="1e-12"`, far
//! below any body of a robot). Actuated joints get a `motor` of gear 1 and their range.

use crate::chain::Joint;
use crate::export::{triple, xml};
use crate::mass::Body;
use crate::model::RobotModel;
use nalgebra::Vector3;
use std::fmt::Write;

/// One body of a leg's chain being written.
struct Link {
    name: String,
    /// Its frame origin (world, at home).
    origin: Vector3<f64>,
    /// Its joint's element.
    joint: String,
    /// Jointless children: the file's bodies it carries (and the platform, for leg 0's end).
    children: Vec<String>,
}

impl RobotModel {
    /// The robot as MJCF (module documentation). A robot without mass properties exports the
    /// compiler's bound masses only; without `gravity`, gravity off.
    pub fn to_mjcf(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "<!-- {} exported by pkm: {} legs -->",
            xml(&self.name),
            self.legs.len()
        );
        let _ = writeln!(out, "<mujoco model=\"{}\">", xml(&self.name));
        let _ = writeln!(
            out,
            "  <compiler angle=\"radian\" boundmass=\"1e-9\" boundinertia=\"1e-12\"/>"
        );
        let gravity = self.mass.gravity.unwrap_or_else(Vector3::zeros);
        let _ = writeln!(out, "  <option gravity=\"{}\"/>", triple(&gravity));
        let _ = writeln!(out, "  <worldbody>");
        let home = self.home_pose.translation.vector;
        let (mut equality, mut motors) = (String::new(), String::new());
        let mut riding: Vec<Body> = self.mass.platform.into_iter().collect();
        for leg in &self.legs {
            riding.extend(leg.bodies.iter().filter(|b| b.after >= leg.joints.len()));
        }
        for (i, leg) in self.legs.iter().enumerate() {
            let connects = i > 0 && leg.joints.len() > 1;
            let ball_end = matches!(leg.joints.last(), Some(Joint::Spherical { .. }));
            let kept = if connects && ball_end {
                leg.joints.len() - 1
            } else {
                leg.joints.len()
            };
            let mut links: Vec<Link> = Vec::with_capacity(kept);
            let mut origin = Vector3::zeros();
            for (j, joint) in leg.joints[..kept].iter().enumerate() {
                let suffix = if leg.is_actuated(j) { "_mot" } else { "" };
                let name = format!("leg{i}_joint{j}{suffix}");
                let range = leg.actuator_at(j).and_then(|a| {
                    a.limits.map(|[lo, hi]| {
                        format!(
                            " limited=\"true\" range=\"{:e} {:e}\"",
                            lo - a.offset,
                            hi - a.offset
                        )
                    })
                });
                let (element, at) = match *joint {
                    Joint::Revolute { axis, point } => (
                        format!(
                            "<joint name=\"{name}\" type=\"hinge\" axis=\"{}\"{}/>",
                            triple(&axis),
                            range.unwrap_or_default()
                        ),
                        point,
                    ),
                    Joint::Prismatic { axis } => (
                        format!(
                            "<joint name=\"{name}\" type=\"slide\" axis=\"{}\"{}/>",
                            triple(&axis),
                            range.unwrap_or_default()
                        ),
                        origin,
                    ),
                    Joint::Spherical { center } => {
                        (format!("<joint name=\"{name}\" type=\"ball\"/>"), center)
                    }
                };
                if suffix == "_mot" {
                    let _ = writeln!(
                        motors,
                        "    <motor name=\"{name}\" joint=\"{name}\" gear=\"1\"/>"
                    );
                }
                origin = at;
                let last = j + 1 == kept;
                links.push(Link {
                    name: if last {
                        format!("leg{i}_end")
                    } else {
                        format!("leg{i}_link{j}")
                    },
                    origin,
                    joint: element,
                    children: Vec::new(),
                });
            }
            for (k, body) in leg.bodies.iter().enumerate() {
                if body.after >= leg.joints.len() {
                    continue;
                }
                let name = format!("leg{i}_body{k}");
                match body.after.checked_sub(1).and_then(|a| links.get_mut(a)) {
                    Some(link) => link.children.push(inertial_body(&name, &link.origin, body)),
                    // Fixed to the world (or moved by a dropped ball only: never, the ball is
                    // the last joint and its bodies ride on the platform).
                    None => {
                        let _ = write!(out, "{}", inertial_body(&name, &Vector3::zeros(), body));
                    }
                }
            }
            let Some(end) = links.last_mut() else {
                continue;
            };
            if i == 0 {
                let mut platform = format!(
                    "<body name=\"platform\" pos=\"{}\">",
                    triple(&(home - end.origin))
                );
                for (k, body) in riding.iter().enumerate() {
                    platform.push_str(&inertial_body(&format!("platform_body{k}"), &home, body));
                }
                platform.push_str("</body>");
                end.children.push(platform);
            } else if connects && ball_end {
                let Some(Joint::Spherical { center }) = leg.joints.last() else {
                    continue;
                };
                let _ = writeln!(
                    equality,
                    "    <connect name=\"leg{i}_closure\" body1=\"leg{i}_end\" body2=\"platform\" anchor=\"{}\"/>",
                    triple(&(center - end.origin))
                );
            } else {
                let _ = writeln!(
                    equality,
                    "    <weld name=\"leg{i}_closure\" body1=\"leg{i}_end\" body2=\"platform\"/>"
                );
            }
            out.push_str(&nest(&links));
        }
        let _ = writeln!(out, "  </worldbody>");
        for (tag, inner) in [("equality", &equality), ("actuator", &motors)] {
            if !inner.is_empty() {
                let _ = write!(out, "  <{tag}>\n{inner}  </{tag}>\n");
            }
        }
        let _ = writeln!(out, "</mujoco>");
        out
    }
}

/// The chain as nested bodies, each at its origin relative to its parent's.
fn nest(links: &[Link]) -> String {
    let mut inner = String::new();
    for (k, link) in links.iter().enumerate().rev() {
        let parent = k
            .checked_sub(1)
            .map_or(Vector3::zeros(), |p| links[p].origin);
        inner = format!(
            "<body name=\"{}\" pos=\"{}\">{}{}{inner}</body>",
            link.name,
            triple(&(link.origin - parent)),
            link.joint,
            link.children.concat()
        );
    }
    if inner.is_empty() {
        inner
    } else {
        format!("    {inner}\n")
    }
}

/// A jointless body at its carrier's frame origin `carrier` (world, at home) with the file
/// body's inertial at its centre of mass.
fn inertial_body(name: &str, carrier: &Vector3<f64>, body: &Body) -> String {
    let i = &body.inertia;
    format!(
        "<body name=\"{name}\"><inertial pos=\"{}\" mass=\"{:e}\" fullinertia=\"{:e} {:e} {:e} {:e} {:e} {:e}\"/></body>",
        triple(&(body.center - carrier)),
        body.mass,
        i[(0, 0)],
        i[(1, 1)],
        i[(2, 2)],
        i[(0, 1)],
        i[(0, 2)],
        i[(1, 2)]
    )
}

#[cfg(test)]
mod tests {
    use crate::chain::JointValue;
    use crate::export::tests::{EXPORT_FILES, total_mass, vector};
    use crate::model::RobotModel;
    use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
    use std::collections::HashMap;

    /// Every body's world frame for the joint values `values` (hinge and slide by name, ball
    /// joints by rotation; missing: 0), reading the MJCF back with an XML parser and composing
    /// parent ∘ pos ∘ joint motion down the nested bodies.
    fn frames(mjcf: &str, values: &HashMap<String, JointValue>) -> HashMap<String, Isometry3<f64>> {
        let doc = roxmltree::Document::parse(mjcf).unwrap();
        let mut placed = HashMap::new();
        for body in doc.descendants().filter(|n| n.has_tag_name("body")) {
            let parent = body
                .parent_element()
                .filter(|p| p.has_tag_name("body"))
                .map_or(Isometry3::identity(), |p| {
                    placed[p.attribute("name").unwrap()]
                });
            let pos = body.attribute("pos").map_or(Vector3::zeros(), vector);
            let mut frame = parent * Isometry3::translation(pos.x, pos.y, pos.z);
            for joint in body.children().filter(|c| c.has_tag_name("joint")) {
                let value = values.get(joint.attribute("name").unwrap());
                let axis = joint.attribute("axis").map_or(Vector3::z(), vector);
                let motion = match (joint.attribute("type").unwrap(), value) {
                    ("hinge", Some(JointValue::Scalar(t))) => Isometry3::from_parts(
                        Translation3::identity(),
                        UnitQuaternion::from_axis_angle(&Unit::new_normalize(axis), *t),
                    ),
                    ("slide", Some(JointValue::Scalar(s))) => {
                        Isometry3::translation(axis.x * s, axis.y * s, axis.z * s)
                    }
                    ("ball", Some(JointValue::Ball(r))) => {
                        Isometry3::from_parts(Translation3::identity(), (*r).into())
                    }
                    _ => Isometry3::identity(),
                };
                frame *= motion;
            }
            placed.insert(body.attribute("name").unwrap().to_string(), frame);
        }
        placed
    }

    fn values(
        model: &RobotModel,
        config: &crate::closure::Configuration,
    ) -> HashMap<String, JointValue> {
        let mut out = HashMap::new();
        for (i, leg) in model.legs.iter().enumerate() {
            for (j, value) in config.joints[i].iter().enumerate() {
                let suffix = if leg.is_actuated(j) { "_mot" } else { "" };
                out.insert(format!("leg{i}_joint{j}{suffix}"), *value);
            }
        }
        out
    }

    /// The exported model closes its loops at home and at 5 poses near it (every `weld`: the
    /// leg's last body keeps its home pose relative to the platform, to 1e-9; every
    /// `connect`: its anchor on the leg and on the platform coincide), carries the platform to
    /// the model's pose, has one motor per actuator, and its masses sum to the file's, on six
    /// files (distance, arm and numerical legs, ball ends, a passive leg, two actuators in a
    /// leg).
    #[test]
    fn the_exported_mjcf_closes_its_loops_and_keeps_the_masses() {
        for text in EXPORT_FILES {
            let model = RobotModel::from_toml(text).unwrap();
            let mjcf = model.to_mjcf();
            let doc = roxmltree::Document::parse(&mjcf).unwrap();
            let element =
                |tag: &'static str| doc.descendants().filter(move |n| n.has_tag_name(tag));
            assert_eq!(
                element("weld").count() + element("connect").count(),
                model.legs.len() - 1,
                "{}",
                model.name
            );
            assert_eq!(element("motor").count(), model.actuator_count());
            let home_pose = |name: &str| -> Isometry3<f64> { frames(&mjcf, &HashMap::new())[name] };
            for k in 0..6 {
                let mut x = model.home_task();
                for (c, v) in x.iter_mut().enumerate() {
                    *v += 0.004 * f64::from(k) * (1.0 + c as f64).sin();
                }
                let config = model
                    .inverse_kinematics_configuration(&x, model.home_mode())
                    .unwrap();
                let frames = frames(&mjcf, &values(&model, &config));
                let platform = frames["platform"];
                for weld in element("weld") {
                    let end = weld.attribute("body1").unwrap();
                    let relative = home_pose("platform").inverse() * home_pose(end);
                    let expected = platform * relative;
                    let gap = (frames[end].translation.vector - expected.translation.vector).norm()
                        + (frames[end].rotation.to_rotation_matrix().into_inner()
                            - expected.rotation.to_rotation_matrix().into_inner())
                        .amax();
                    assert!(
                        gap < 1e-9,
                        "{}: {end} open by {gap:e} at pose {k}",
                        model.name
                    );
                }
                for connect in element("connect") {
                    let end = connect.attribute("body1").unwrap();
                    let anchor = Point3::from(vector(connect.attribute("anchor").unwrap()));
                    let on_platform = home_pose("platform").inverse() * (home_pose(end) * anchor);
                    let gap = (frames[end] * anchor - platform * on_platform).norm();
                    assert!(
                        gap < 1e-9,
                        "{}: {end} open by {gap:e} at pose {k}",
                        model.name
                    );
                }
                let pose = crate::pose::platform_pose(model.orientation, &config.pose);
                let expected = pose * model.home_pose.inverse() * home_pose("platform");
                let gap = (platform.translation.vector - expected.translation.vector).norm();
                assert!(
                    gap < 1e-9,
                    "{}: platform off by {gap:e} at pose {k}",
                    model.name
                );
            }
            let mjcf_mass: f64 = element("inertial")
                .map(|n| n.attribute("mass").unwrap().parse::<f64>().unwrap())
                .sum();
            let file_mass = total_mass(&model);
            assert!(
                (mjcf_mass - file_mass).abs() < 1e-12 * file_mass,
                "{}",
                model.name
            );
        }
    }
}
