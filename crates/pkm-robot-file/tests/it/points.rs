//! The joint points of the legs (`RobotModel::leg_points`) and the reach bound
//! (`RobotModel::leg_reach_ball`, `RobotModel::reach_box`), checked against the file's geometry:
//! the platform anchors are the platform pose applied to the file's platform points, every rigid
//! link keeps its home length, an actuated rail's segment is the actuator coordinate, and no
//! solved pose lies outside the bound.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::{all_files, robot, robot_text};
use nalgebra::{Point3, Vector3};
use pkm_robot_file::{Joint, LegPointKind, RobotModel};

/// Agreement of positions and lengths (m).
const EXACT: f64 = 1e-12;

/// The file's platform point of every leg: its last joint point (R point or S centre), or,
/// when P joints follow it, the foot of the home platform origin on the last P axis through it.
fn platform_points(model: &RobotModel) -> Vec<Vector3<f64>> {
    let origin = Vector3::new(model.home()[0], model.home()[1], model.home()[2]);
    model
        .legs()
        .iter()
        .map(|leg| {
            let last = leg
                .joints
                .iter()
                .rposition(|j| !matches!(j, Joint::Prismatic { .. }))
                .unwrap();
            let point = match leg.joints[last] {
                Joint::Revolute { point, .. } => point,
                Joint::Spherical { center } => center,
                Joint::Prismatic { .. } => unreachable!(),
            };
            match leg.joints.last() {
                Some(Joint::Prismatic { axis }) => point + axis * (origin - point).dot(axis),
                _ => point,
            }
        })
        .collect()
}

/// Task coordinates near home: each coordinate moved by `step` (m or rad) in turn.
fn poses_near_home(model: &RobotModel, step: f64) -> Vec<Vec<f64>> {
    let home = model.home_task();
    let mut poses = vec![home.clone()];
    for k in 0..home.len() {
        for sign in [-1.0, 1.0] {
            let mut x = home.clone();
            x[k] += sign * step;
            poses.push(x);
        }
    }
    poses
}

#[test]
fn leg_points_are_the_assembled_chain() {
    let (mut checked, mut worst_anchor, mut worst_length) = (0, 0.0_f64, 0.0_f64);
    for file in all_files() {
        let model = robot(&file);
        let anchors = platform_points(&model);
        for x in poses_near_home(&model, 0.02) {
            let Ok(c) = model.inverse_kinematics_configuration(&x, model.home_mode()) else {
                continue;
            };
            let to_platform = model.platform_pose_of(&c) * model.home_platform_pose().inverse();
            for (i, anchor) in anchors.iter().enumerate() {
                let leg = model.leg_points(i, &c).unwrap();
                let last = leg.points.last().unwrap();
                assert_eq!(last.kind, LegPointKind::Platform, "{file} leg {i}");
                let expected = (to_platform * Point3::from(*anchor)).coords;
                let error = (last.position - expected).norm();
                assert!(
                    error < EXACT,
                    "{file} leg {i} at {x:?}: anchor off by {error:e}"
                );
                worst_anchor = worst_anchor.max(error);
                assert_eq!(leg.segments.len() + 1, leg.points.len());
                for s in leg.segments.iter().filter(|s| s.prismatic.is_empty()) {
                    let length = (leg.points[s.to].position - leg.points[s.from].position).norm();
                    let error = (length - s.home_length).abs();
                    assert!(error < EXACT, "{file} leg {i} segment {s:?}: {length}");
                    worst_length = worst_length.max(error);
                }
            }
            checked += 1;
        }
    }
    println!(
        "{checked} poses; anchors within {worst_anchor:.1e} m, rigid links within \
         {worst_length:.1e} m"
    );
    assert!(checked >= 60, "vacuous: {checked} poses");
}

#[test]
fn an_actuated_rail_is_drawn_from_its_origin_to_the_carriage() {
    let model = robot("linear_delta.toml");
    let x = [0.02, -0.01, -0.21];
    let c = model
        .inverse_kinematics_configuration(&x, model.home_mode())
        .unwrap();
    let q = model.actuators_of(&c);
    for i in 0..3 {
        let leg = model.leg_points(i, &c).unwrap();
        assert_eq!(leg.points[0].kind, LegPointKind::RailOrigin);
        assert_eq!(leg.points[1].kind, LegPointKind::Actuator);
        let rail = &leg.segments[0];
        assert!(rail.actuated && rail.prismatic == [0]);
        let travel = (leg.points[1].position - leg.points[0].position).norm();
        assert!(
            (travel - q[i].abs()).abs() < EXACT,
            "leg {i}: {travel} vs {}",
            q[i]
        );
        // The rail origin is the actuator's zero: on the rail axis (x) at the file's y, z.
        assert!(leg.points[0].position.x.abs() < EXACT);
    }
}

/// The Linear Delta with its carriages limited to `[-0.6, 0.6]` m (the file has no limits, so
/// its reach is unbounded along the rails).
fn limited_linear_delta() -> RobotModel {
    let text = robot_text("linear_delta.toml")
        .replace("actuated = true,", "actuated = true, limits = [-0.6, 0.6],");
    RobotModel::from_toml(&text).unwrap()
}

/// Every pose of a 40³ grid about the bound's centre, half again as wide as the box on each
/// axis, that some
/// working mode reaches lies in every leg's ball and in the box; returns the number of reached
/// poses.
fn reached_poses_lie_in_the_bound(model: &RobotModel) -> usize {
    let [lower, upper] = model.reach_box().unwrap();
    assert!(lower.iter().chain(upper.iter()).all(|v| v.is_finite()));
    let centre = (lower + upper) / 2.0;
    let half = 0.75 * (upper - lower);
    let n = 40;
    let mut reached = 0;
    for k in 0..n * n * n {
        let t = |a: usize, i: usize| half[a] * (2.0 * (i as f64 + 0.5) / n as f64 - 1.0);
        let p = centre + Vector3::new(t(0, k % n), t(1, k / n % n), t(2, k / (n * n)));
        let inside = model
            .working_modes()
            .into_iter()
            .any(|m| model.inverse_kinematics(p.as_slice(), m).is_ok());
        if !inside {
            continue;
        }
        reached += 1;
        for i in 0..model.legs().len() {
            let (c, r) = model.leg_reach_ball(i).unwrap();
            assert!((p - c).norm() <= r, "{p} outside leg {i}'s ball");
        }
        assert!(
            p.iter()
                .zip(lower.iter().zip(&upper))
                .all(|(v, (l, u))| l <= v && v <= u),
            "{p} outside the box"
        );
    }
    reached
}

#[test]
fn no_reachable_pose_lies_outside_the_reach_bound() {
    let tsai = robot("tsai.toml");
    let reached = reached_poses_lie_in_the_bound(&tsai);
    println!("Tsai: {reached} reached poses in the bound");
    assert!(reached > 500, "vacuous: {reached}");
    let delta = limited_linear_delta();
    let reached = reached_poses_lie_in_the_bound(&delta);
    println!("Linear Delta: {reached} reached poses in the bound");
    assert!(reached > 100, "vacuous: {reached}");
}

#[test]
fn a_prismatic_joint_without_limits_leaves_the_reach_unbounded() {
    let delta = robot("linear_delta.toml");
    assert!((0..3).all(|i| delta.leg_reach_ball(i).is_none()));
    assert!(delta.reach_box().is_none());
    // Tsai: every joint is revolute, so each leg's ball is the chain's length from its motor
    // axis point, arm a + rod b plus the platform offset.
    let tsai = robot("tsai.toml");
    let (centre, radius) = tsai.leg_reach_ball(0).unwrap();
    assert!((centre - Vector3::new(0.1, 0.0, 0.0)).norm() < EXACT);
    assert!((radius - (0.44 + 0.56 + 0.1)).abs() < 1e-9, "{radius}");
}

#[test]
fn passive_bends_are_zero_at_home_and_the_legs_turn_in_a_stewart_platform() {
    for file in all_files() {
        let model = robot(&file);
        let c = model
            .inverse_kinematics_configuration(&model.home_task(), model.home_mode())
            .unwrap();
        let bends = model.passive_bends(&c).unwrap();
        assert!(bends.iter().all(|b| b.abs() < 1e-6), "{file}: {bends:?}");
    }
    // 6-UPS: the bend of leg i is the larger of the leg's turn from its home direction seen
    // from the base (U) and seen from the platform (S), computed here from the pose alone.
    let model = robot("stewart_gough.toml");
    let mut x = model.home_task();
    for (k, step) in [0.01, -0.02, 0.015, 0.05, -0.04, 0.03].iter().enumerate() {
        x[k] += step;
    }
    let c = model
        .inverse_kinematics_configuration(&x, model.home_mode())
        .unwrap();
    let bends = model.passive_bends(&c).unwrap();
    let turn = model.platform_pose_of(&c) * model.home_platform_pose().inverse();
    let anchors = platform_points(&model);
    let angle = |a: Vector3<f64>, b: Vector3<f64>| a.angle(&b);
    let mut largest = 0.0_f64;
    for (i, leg) in model.legs().iter().enumerate() {
        let Joint::Revolute { point: base, .. } = leg.joints[0] else {
            panic!("a U joint first")
        };
        let home = anchors[i] - base;
        let now = (turn * Point3::from(anchors[i])).coords - base;
        let at_base = angle(now, home);
        let at_platform = angle(turn.rotation.inverse() * now, home);
        let expected = at_base.max(at_platform);
        assert!(
            (bends[i] - expected).abs() < 1e-12,
            "leg {i}: {} vs {expected}",
            bends[i]
        );
        largest = largest.max(expected);
    }
    assert!(largest > 0.01, "vacuous: {largest}");
}
