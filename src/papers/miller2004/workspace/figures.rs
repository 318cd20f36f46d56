//! Figures of §2.1: the map of $V(\alpha, \beta)/V_{Delta}$ per reading with the Delta, NUWAR
//! and the arg-max marked, and cross-sections of the Delta's and NUWAR's workspaces.

use super::readings::SweepResult;
use super::{ALPHA_PRINTED_DEG, BETA_NUWAR_DEG, design};
use crate::papers::{Context, ExperimentError, Figure, Table};
use nalgebra::Vector3;
use pkm_draw::chart::{Chart, Heatmap, Marker, Quantity};
use pkm_draw::{Axis, Scene};
use pkm_mechanisms::{ElbowMode, RotaryDelta, Skeleton};
use pkm_traits::{ConstrainedWorkspace, WorkspaceConstraint};
use pkm_workspace_indices::Workspace;

/// One annotated map per reading.
pub(super) fn maps(results: &[SweepResult]) -> Vec<Figure> {
    results
        .iter()
        .map(|r| {
            let map = Heatmap {
                colour_axis: "V / V_Delta".into(),
                x: r.beta_deg.clone(),
                y: r.alpha_deg.clone(),
                values: r.ratios.iter().map(|(v, _)| Some(*v)).collect(),
            };
            let markers = [
                Marker::new("Delta", 0.0, 0.0),
                Marker::new("NUWAR", BETA_NUWAR_DEG, ALPHA_PRINTED_DEG),
                Marker::new(format!("max {:.4}", r.max_ratio), r.beta_opt, r.alpha_opt),
            ];
            let title = format!("§2.1 workspace volume / Delta's: {}", r.reading.name);
            let (beta, alpha) = (Quantity::new("β", "deg"), Quantity::new("α", "deg"));
            Figure::chart(
                format!("map_{}", r.reading.name),
                Chart::heatmap(title, beta, alpha, map).with_markers(markers),
            )
        })
        .collect()
}

/// Fig. 2 (a) for each compared reading: the layout of the computed optimum $(\alpha, \beta)$
/// (elbows out, motor axes $e_i$ 0.15 m long) with the plate on the centreline at the first
/// reachable height of 0.40, 0.45, …, 0.70 m below the motor plane.
pub(super) fn optimum_layouts(results: &[SweepResult]) -> Result<Vec<Figure>, ExperimentError> {
    let mut figures = Vec::new();
    for r in results.iter().filter(|r| r.reading.compared) {
        let robot = design(r.alpha_opt, r.beta_opt)?;
        let skeleton = (8..=14).find_map(|k| {
            let p = Vector3::new(0.0, 0.0, robot.motor_plane_z() - 0.05 * f64::from(k));
            Skeleton::rotary_delta(&robot, &p, ElbowMode::Out).ok()
        });
        let Some(skeleton) = skeleton else { continue };
        let scene = robot
            .legs()
            .iter()
            .fold(Scene::new(skeleton), |scene, leg| {
                scene.with_axis(Axis {
                    label: "motor axes e_i".to_owned(),
                    point: leg.motor,
                    direction: leg.e,
                    length: Some(0.15),
                })
            });
        figures.push(Figure::robot(
            format!("layout_optimum_{}", r.reading.name),
            format!(
                "Fig. 2 (a): layout of pkm's optimum α = {:.1}°, β = {:.1}° ({} reading)",
                r.alpha_opt, r.beta_opt, r.reading.name
            ),
            scene,
            "m",
        ));
    }
    Ok(figures)
}

/// Cells per axis of a cross-section.
fn cells(ctx: &Context<'_>) -> usize {
    ctx.mode.pick(41, 161)
}

/// The Delta's and NUWAR's workspaces on the vertical plane $y = 0$ through the centreline and
/// on the horizontal plane 0.6 m below the motors: 2 where the plate is below the motor plane
/// and every leg reaches, 1 where every leg reaches above it, empty elsewhere.
pub(super) fn cross_sections(
    ctx: &Context<'_>,
) -> Result<(Vec<Figure>, Vec<Table>), ExperimentError> {
    let (mut figures, mut tables) = (Vec::new(), Vec::new());
    for (name, robot) in [
        ("delta", design(0.0, 0.0)?),
        ("nuwar", design(ALPHA_PRINTED_DEG, BETA_NUWAR_DEG)?),
    ] {
        let (radius, depth) = robot.reach_cylinder();
        let n = cells(ctx);
        let axis = |lo: f64, hi: f64| -> Vec<f64> {
            (0..n)
                .map(|k| lo + (hi - lo) * (k as f64 + 0.5) / n as f64)
                .collect()
        };
        let (xs, zs) = (axis(-radius, radius), axis(-depth, depth));
        let vertical = classify(&robot, &xs, &zs, |x, z| Vector3::new(x, 0.0, z))?;
        let horizontal = classify(&robot, &xs, &xs, |x, y| Vector3::new(x, y, -0.6))?;
        for (plane, (a, b), values, labels) in [
            ("xz", (&xs, &zs), vertical, ("x", "z − z0")),
            ("xy", (&xs, &xs), horizontal, ("x", "y")),
        ] {
            tables.push(section_table(
                &format!("section_{plane}_{name}"),
                a,
                b,
                &values,
            ));
            let title = format!(
                "{} workspace, {} (2: below the motors, 1: above)",
                name.to_uppercase(),
                if plane == "xz" {
                    "plane y = 0"
                } else {
                    "plane z − z0 = −0.6 m"
                }
            );
            let map = Heatmap {
                colour_axis: "region".into(),
                x: a.clone(),
                y: b.clone(),
                values,
            };
            let (u, v) = (Quantity::new(labels.0, "m"), Quantity::new(labels.1, "m"));
            figures.push(Figure::chart(
                format!("section_{plane}_{name}"),
                Chart::heatmap(title, u, v, map),
            ));
        }
    }
    Ok((figures, tables))
}

fn classify(
    robot: &RotaryDelta,
    a: &[f64],
    b: &[f64],
    at: impl Fn(f64, f64) -> Vector3<f64>,
) -> Result<Vec<Option<f64>>, ExperimentError> {
    let below = Workspace::new(
        robot,
        &[ElbowMode::Out, ElbowMode::In],
        &[WorkspaceConstraint::below(robot.motor_plane_z())?],
    )?;
    Ok(b.iter()
        .flat_map(|v| a.iter().map(move |u| (*u, *v)))
        .map(|(u, v)| {
            let p = at(u, v);
            if below.contains(&p) {
                Some(2.0)
            } else if robot.reachable(&p, ElbowMode::Out) {
                Some(1.0)
            } else {
                None
            }
        })
        .collect())
}

fn section_table(name: &str, a: &[f64], b: &[f64], values: &[Option<f64>]) -> Table {
    Table {
        name: name.to_owned(),
        columns: ["u_m", "v_m", "region"].map(String::from).to_vec(),
        rows: b
            .iter()
            .flat_map(|v| a.iter().map(move |u| (*u, *v)))
            .zip(values)
            .map(|((u, v), z)| vec![u, v, z.unwrap_or(0.0)])
            .collect(),
    }
}
