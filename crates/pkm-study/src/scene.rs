//! The picture of the robot a study studied: every command writes [`ROBOT_SVG`] (the robot's
//! skeleton in front, side, top and 3-D views, drawn by `pkm-draw`) and [`ROBOT_CSV`] (the
//! data behind it, [`Scene::to_csv`]) to `--out`.
//!
//! This module is the one place where a study's result becomes a [`Skeleton`] and a
//! [`Scene`]: the design at a representative pose with a cross-section of its workspace
//! (`workspace`, `sweep`, `pareto`, `optimize`), the optimal pose with the task twists' axes
//! (`task`), the robot at the start of its trajectory with the path (`dynamics`).
//!
//! A drawing never fails a study: a pose that cannot be drawn (no member point on the
//! cross-section, an inverse kinematics that fails) becomes a warning line of the report and no
//! drawing is written. Everything here is a function of the study alone (the cross-section is
//! evaluated in parallel but collected in order), so the files are the same bytes for any
//! `--threads`, and `pkm merge` writes the same drawing as a single run.

use crate::outcome::short;
use crate::registry::WorkspaceVisitor;
use crate::registry::{Built, StudyMechanism};
use nalgebra::{Isometry3, Vector3};
use pkm_draw::{Axis, PathKind, Scene};
use pkm_mechanisms::Skeleton;
use pkm_screw_theory::Twist;
use pkm_traits::{ConstrainedWorkspace, KinematicsError, WorkspaceConstraint};
use pkm_workspace_indices::{Dim, Region, TranslationalCondition, Workspace};
use rayon::prelude::*;

/// The drawing of the robot.
pub const ROBOT_SVG: &str = "robot.svg";
/// The data behind [`ROBOT_SVG`]: one row per point of the skeleton, link end, axis point and
/// path point (`element,index,label,kind,x,y,z`).
pub const ROBOT_CSV: &str = "robot.csv";

/// Cells per side of the workspace cross-section drawn with a design (48² = 2304 points at
/// most), fine enough to show its shape and light enough for every study.
pub const SECTION_CELLS: usize = 48;

/// Most points of a drawn trajectory; longer histories are thinned evenly.
pub const MAX_PATH_POINTS: usize = 2000;

/// A design drawn at a representative pose of its workspace under `constraints`, with the
/// workspace's members among the [`SECTION_CELLS`]² cell centres of a vertical cross-section
/// through the centre of `region`'s bounding box (the plane $y = y_c$; $x = x_c$ for the Linear
/// Delta, whose rails run along $x$) as a [`PathKind::WorkspacePoints`] path. The pose is the
/// member nearest the box's centre (the first of equally near ones); without a `region`, the
/// mechanism's reach region, or for the Linear Delta a box around its rails.
///
/// # Errors
/// Why there is no drawing: an invalid design, no member on the cross-section, a pose the
/// skeleton cannot be built at.
pub fn design_scene<M: StudyMechanism>(
    built: &Built<M>,
    constraints: &[WorkspaceConstraint],
    region: Option<Region>,
) -> Result<Scene, String> {
    let spec = built.spec();
    let region = match region {
        Some(region) => region,
        None => built.drawing_region()?,
    };
    let bounds = region.bounding_box();
    let (lower, upper, centre) = (bounds.lower, bounds.upper, bounds.centre());
    let (a, b, normal) = spec.drawing_plane();
    let cell = |axis: usize, k: usize| {
        lower[axis] + (k as f64 + 0.5) * (upper[axis] - lower[axis]) / SECTION_CELLS as f64
    };
    let points: Vec<Vector3<f64>> = (0..SECTION_CELLS * SECTION_CELLS)
        .map(|k| {
            let mut p = centre;
            p[a] = cell(a, k % SECTION_CELLS);
            p[b] = cell(b, k / SECTION_CELLS);
            p
        })
        .collect();
    let inside = built
        .with_workspace(constraints, Members { points: &points })
        .map_err(|e| e.to_string())?;
    let members: Vec<Vector3<f64>> = points
        .iter()
        .zip(inside)
        .filter_map(|(p, inside)| inside.then_some(*p))
        .collect();
    let pose = members
        .iter()
        .fold(None, |best: Option<(f64, Vector3<f64>)>, p| {
            let d = (p - centre).norm_squared();
            match best {
                Some((nearest, _)) if !(d < nearest) => best,
                _ => Some((d, *p)),
            }
        })
        .map(|(_, p)| p)
        .ok_or_else(|| {
            format!(
                "no point of the cross-section {} = {} m lies in the workspace",
                ["x", "y", "z"][normal],
                short(centre[normal])
            )
        })?;
    let label = format!(
        "workspace on {} = {} m",
        ["x", "y", "z"][normal],
        short(centre[normal])
    );
    Ok(Scene::new(built.skeleton_at(&pose)?).with_path(label, PathKind::WorkspacePoints, members))
}

/// The first skeleton of `tries` that could be built, or why none could (the last error).
pub(crate) fn first_drawable(
    p: &Vector3<f64>,
    tries: impl IntoIterator<Item = Result<Skeleton, KinematicsError>>,
) -> Result<Skeleton, String> {
    let mut last = None;
    for attempt in tries {
        match attempt {
            Ok(skeleton) => return Ok(skeleton),
            Err(e) => last = Some(e),
        }
    }
    let at = format!("[{}, {}, {}]", short(p.x), short(p.y), short(p.z));
    Err(last.map_or_else(
        || format!("no working mode of the study can be drawn at p = {at} m"),
        |e| format!("the skeleton at p = {at} m: {e}"),
    ))
}

/// Whether each point belongs to the workspace (in parallel, in order).
struct Members<'a> {
    points: &'a [Vector3<f64>],
}

impl WorkspaceVisitor for Members<'_> {
    type Output = Vec<bool>;

    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Vec<bool>
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
        self.points
            .par_iter()
            .map(|p| workspace.contains(p))
            .collect()
    }
}

/// A spatial robot at its optimal `pose` with the axis of every task twist (the point of the
/// axis nearest the origin, Wolf & Shoham eq. 3; a pure translation through the platform
/// centre); without task twists (a singularity search) the axis of `reciprocal`, the twist the
/// legs' wrenches resist least.
///
/// # Errors
/// The skeleton's [`KinematicsError`] (a leg of zero length), a zero twist.
pub fn task_scene(
    skeleton: Result<Skeleton, KinematicsError>,
    pose: &Isometry3<f64>,
    twists: &[(f64, Twist)],
    reciprocal: Option<Twist>,
) -> Result<Scene, String> {
    let mut scene = Scene::new(skeleton.map_err(|e| format!("the skeleton at the optimum: {e}"))?);
    let centre = pose.translation.vector;
    let labelled: Vec<(String, Twist)> = if twists.is_empty() {
        reciprocal
            .map(|t| ("least-constrained twist".to_owned(), t))
            .into_iter()
            .collect()
    } else {
        twists
            .iter()
            .enumerate()
            .map(|(k, (w, t))| (format!("task twist {} (weight {})", k + 1, short(*w)), *t))
            .collect()
    };
    for (label, twist) in labelled {
        scene = scene.with_axis(Axis::of_twist(label, &twist, centre).map_err(|e| e.to_string())?);
    }
    Ok(scene)
}

/// The rotary Delta of a dynamics study at the first commanded position (elbows out, the
/// branch of the dynamics), with the commanded positions as a [`PathKind::Trajectory`]
/// (every k-th sample and the last, at most [`MAX_PATH_POINTS`] + 1).
///
/// # Errors
/// An invalid design, an empty trajectory, an unreachable start.
pub fn trajectory_scene<M: StudyMechanism>(
    built: &Built<M>,
    commanded: &[Vector3<f64>],
) -> Result<Scene, String> {
    let start = commanded
        .first()
        .ok_or_else(|| "the trajectory has no samples".to_owned())?;
    Ok(with_trajectory(
        Scene::new(built.skeleton_at(start)?),
        commanded,
    ))
}

/// `scene` with the path `commanded` (at most [`MAX_PATH_POINTS`] of its points, evenly
/// thinned, the last one kept).
pub fn with_trajectory(scene: Scene, commanded: &[Vector3<f64>]) -> Scene {
    let Some(last) = commanded.last() else {
        return scene;
    };
    let step = commanded.len().div_ceil(MAX_PATH_POINTS).max(1);
    let mut path: Vec<Vector3<f64>> = commanded.iter().step_by(step).copied().collect();
    if !(commanded.len() - 1).is_multiple_of(step) {
        path.push(*last);
    }
    scene.with_path("trajectory", PathKind::Trajectory, path)
}

/// [`design_scene`] of `base` with the design variables `values` set, without constraints (the
/// workspace of `pkm optimize`'s objectives) in the mechanism's reach region.
///
/// # Errors
/// An unknown variable; as [`design_scene`].
pub fn optimum_scene<'a, M: StudyMechanism>(
    base: &M,
    values: impl IntoIterator<Item = (&'a str, f64)>,
) -> Result<Scene, String> {
    let mut spec = base.clone();
    for (name, value) in values {
        spec.set(name, value)?;
    }
    design_scene(&Built::new(spec).map_err(|e| e.to_string())?, &[], None)
}
