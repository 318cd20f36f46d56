//! `docs/adding-a-mechanism.md`, followed step by step: a mechanism that pkm does not know (a
//! Cartesian 3-PPP gantry), declared in this test alone, runs every study that applies to it
//! (workspace, sweep, Pareto, a split sweep and its merge) and is refused by the others
//! (optimize, task) with the reason. Its workspace has a closed form (the stroke box
//! $[0, s]^3$: $W = s^3$, κ = 1 everywhere so $\eta = W$ and GCI = 1), so the studies' numbers
//! are checked against it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{SMatrix, Vector3};
use pkm_mechanisms::{LinkKind, PointKind, Skeleton, SkeletonPoint};
use pkm_study::schema::mechanism::{BuildError, WorkspaceVisitor};
use pkm_study::schema::units::PositiveMetres;
use pkm_study::{
    Actuation, Artifact, GridKind, GridRun, Merged, OptimizeStudy, ParetoStudy, Shard,
    StudyMechanism, SweepStudy, TaskMechanism, TaskStudy, WorkspaceStudy, from_toml_str, merge,
    optimize, pareto, sweep, task, workspace,
};
use pkm_traits::{
    ClosedChain, ConstrainedWorkspace, DesignError, InverseKinematics, Joints, KinematicsError,
    Silent, Task, WorkspaceConstraint,
};
use pkm_workspace_indices::Region;
use serde::{Deserialize, Serialize};

// Step 1: the mechanism in the library's terms. Closure Φ = x − q, so J_x = I, J_q = −I and
// J = −J_q⁻¹ J_x = I: every point is isotropic.

/// Three orthogonal prismatic axes carrying the platform.
#[derive(Debug, Clone, Copy)]
struct Gantry;

impl ClosedChain<3, 3> for Gantry {
    fn closure(&self, x: &Task<3>, q: &Joints<3>) -> Joints<3> {
        x - q
    }
    fn jacobian_x(&self, _: &Task<3>, _: &Joints<3>) -> SMatrix<f64, 3, 3> {
        SMatrix::identity()
    }
    fn jacobian_q(&self, _: &Task<3>, _: &Joints<3>) -> SMatrix<f64, 3, 3> {
        -SMatrix::<f64, 3, 3>::identity()
    }
}

impl InverseKinematics<3, 3> for Gantry {
    type WorkingMode = ();
    fn inverse_kinematics(&self, x: &Task<3>, (): ()) -> Result<Joints<3>, KinematicsError> {
        match x.iter().find(|v| !v.is_finite()) {
            None => Ok(*x),
            Some(&value) => Err(KinematicsError::NonFinite { what: "x", value }),
        }
    }
}

impl ConstrainedWorkspace<3, 3> for Gantry {
    fn name(&self) -> &'static str {
        "Gantry"
    }
}

// Step 2: its study table (plain serde) and what a study needs to know about it.

/// `[mechanism.gantry]`: the stroke of each axis, from 0.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct GantrySpec {
    stroke: PositiveMetres,
}

impl StudyMechanism for GantrySpec {
    pkm_study::design_variables! {
        "stroke" Length => |s| s.stroke.0,
    }

    /// The gantry is its stroke: the joint range that every axis holds.
    type Built = WorkspaceConstraint;

    fn kind(&self) -> &'static str {
        "gantry"
    }

    fn build(&self) -> Result<WorkspaceConstraint, BuildError> {
        WorkspaceConstraint::joint_range(0.0, self.stroke.0).map_err(|_| {
            BuildError::Design(
                DesignError {
                    parameter: "stroke",
                    value: self.stroke.0,
                    requirement: "must be > 0",
                }
                .into(),
            )
        })
    }

    fn actuation(&self) -> Actuation {
        Actuation::Prismatic
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        stroke: &WorkspaceConstraint,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        let mut all = vec![*stroke];
        all.extend_from_slice(constraints);
        let workspace = pkm_workspace_indices::Workspace::new(&Gantry, &[()], &all)
            .map_err(|e| BuildError::Constraint(e.to_string()))?;
        Ok(visitor.visit(&workspace))
    }

    fn reach_region(&self, _: &WorkspaceConstraint) -> Option<Region> {
        let s = self.stroke.0;
        Some(Region::Box {
            lower: Vector3::zeros(),
            upper: Vector3::new(s, s, s),
        })
    }

    fn skeleton_at(&self, _: &WorkspaceConstraint, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let point = |label: &str, kind, position| SkeletonPoint {
            label: label.into(),
            kind,
            position,
        };
        Ok(Skeleton {
            points: vec![
                point("O", PointKind::Base, Vector3::zeros()),
                point("p", PointKind::Centre, *p),
            ],
            links: vec![pkm_mechanisms::Link {
                from: 0,
                to: 1,
                kind: LinkKind::Actuated,
            }],
        })
    }
}

// Step 3: the registry of this crate's study files, one line per mechanism.
pkm_study::mechanisms! {
    /// The mechanisms of this test's studies.
    pub enum TestMechanisms {
        /// The gantry.
        Gantry(GantrySpec),
    }
}

// A registry without a wrench system takes part in task studies with one line (refused).
impl TaskMechanism for TestMechanisms {}

const STUDY: &str = r#"
[mechanism.gantry]
stroke = 0.5

[sampling]
points = 8192
replicates = 4

[[workspace.slices]]
plane = "xy"
at = 0.25
cells = 8
"#;

#[test]
fn a_mechanism_declared_here_runs_the_workspace_study() {
    let study: WorkspaceStudy<TestMechanisms> = from_toml_str(STUDY).unwrap();
    let outcome = workspace(&study, &Silent).unwrap();
    let r = &outcome.result;
    assert_eq!(r.mechanism, "gantry");
    // The sampled domain is the reach region (the stroke box) and every point is inside it.
    assert!((r.domain_volume - 0.125).abs() < 1e-15);
    assert_eq!(r.estimate.n_inside, r.estimate.n_points);
    assert!((r.estimate.volume - 0.125).abs() < 1e-12);
    // κ = 1 everywhere: η = W and GCI = 1.
    assert!((r.estimate.gci.unwrap() - 1.0).abs() < 1e-12);
    assert!((r.slices[0].inside_fraction - 1.0).abs() < 1e-15);
    assert!(
        outcome
            .artifacts
            .iter()
            .any(|a| matches!(a, Artifact::Robot { .. }))
    );
}

#[test]
fn its_design_variables_and_unknown_keys_are_checked() {
    let mut m = TestMechanisms::Gantry(GantrySpec {
        stroke: PositiveMetres(1.0),
    });
    assert_eq!(m.variables()[0].name, "stroke");
    m.set("stroke", 2.0).unwrap();
    assert!(m.get("stroke").is_some_and(|v| (v - 2.0).abs() < 1e-15));
    let e = m.set("reach", 1.0).unwrap_err();
    assert!(e.contains("expected one of stroke"), "{e}");
    let bad = STUDY.replace("stroke = 0.5", "stroke = 0.5\nreach = 1");
    let e = from_toml_str::<WorkspaceStudy<TestMechanisms>>(&bad).unwrap_err();
    assert_eq!(e.path().unwrap().to_string(), "mechanism.gantry.reach");
    let rotary = STUDY.replace(
        "[mechanism.gantry]",
        "[constraints]\njoint_range_deg = [0, 1]\n[mechanism.gantry]",
    );
    let study: WorkspaceStudy<TestMechanisms> = from_toml_str(&rotary).unwrap();
    let e = workspace(&study, &Silent).unwrap_err();
    assert!(
        e.to_string().starts_with("constraints: joint_range_deg"),
        "{e}"
    );
}

/// A grid over the stroke s = 0.25, 0.5, 0.75, 1 on the unit box's 8 × 8 × 8 cell centres
/// ((i + 1/2)/8): s·8 centres lie in [0, s] per axis, so the grid estimate of W is exactly s³.
const GRID: &str = r#"
[mechanism.gantry]
stroke = 0.5

[sampling]
sampler = "grid"
per_axis = 8
region = { box = { lower = [0.0, 0.0, 0.0], upper = [1.0, 1.0, 1.0] } }

[[variables]]
name = "stroke"
from = 0.25
to = 1.0
steps = 4

[sweep]
objective = { volume = 1.0 }
report = ["gci"]

[pareto]
objectives = ["volume", "eta"]
weights = [[0.5, 0.5]]
"#;

const STROKES: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

#[test]
fn a_mechanism_declared_here_runs_a_sweep_its_shards_and_their_merge() {
    let study: SweepStudy<TestMechanisms> = from_toml_str(GRID).unwrap();
    let whole = match sweep(&study, Shard::WHOLE, &Silent).unwrap().result {
        GridRun::Complete(r) => r,
        GridRun::Part(_) => panic!("the whole grid"),
    };
    assert_eq!(whole.mechanism, "gantry");
    assert_eq!((whole.nodes, whole.infeasible), (4, 0));
    // Maximising W = s³: the top node, s = 1, W = 1, GCI = 1.
    let (node, best) = &whole.grid_optimum;
    assert_eq!(*node, 3);
    assert!((best.design["stroke"] - 1.0).abs() < 1e-15);
    assert!((best.indices["volume"] - 1.0).abs() < 1e-12);
    assert!((best.indices["gci"] - 1.0).abs() < 1e-12);
    assert_eq!(whole.optimum, *best);
    // Every node of the landscape: W = s³ (exactly on the cell centres), GCI = 1.
    let outcome = sweep(&study, Shard::WHOLE, &Silent).unwrap();
    let landscape = outcome
        .artifacts
        .iter()
        .find_map(|a| match a {
            Artifact::Table { table, .. } if table.header.iter().any(|h| h == "volume") => {
                Some(table)
            }
            _ => None,
        })
        .unwrap();
    let column = |key: &str| landscape.header.iter().position(|h| h == key).unwrap();
    let (volume, gci) = (column("volume"), column("gci"));
    for (row, s) in landscape.rows.iter().zip(STROKES) {
        let number = |k: usize| match &row[k] {
            pkm_study::Cell::Number(v) => *v,
            other => panic!("{other:?}"),
        };
        assert!((number(volume) - s * s * s).abs() < 1e-12, "s = {s}");
        assert!((number(gci) - 1.0).abs() < 1e-12, "s = {s}");
    }
    // Two shards, merged (in any order), are the whole run.
    let parts: Vec<_> = [2, 1]
        .into_iter()
        .map(|index| {
            match sweep(&study, Shard { index, count: 2 }, &Silent)
                .unwrap()
                .result
            {
                GridRun::Part(p) => p,
                GridRun::Complete(_) => panic!("a part"),
            }
        })
        .collect();
    assert_eq!(parts[0].outcomes.len() + parts[1].outcomes.len(), 4);
    match merge(&study, GridKind::Sweep, parts, &Silent)
        .unwrap()
        .result
    {
        Merged::Sweep(merged) => assert_eq!(merged, whole),
        Merged::Pareto(_) => panic!("a sweep"),
    }
}

#[test]
fn a_mechanism_declared_here_runs_a_pareto_study() {
    let study: ParetoStudy<TestMechanisms> = from_toml_str(GRID).unwrap();
    let result = match pareto(&study, Shard::WHOLE, &Silent).unwrap().result {
        GridRun::Complete(r) => r,
        GridRun::Part(_) => panic!("the whole grid"),
    };
    // W = η = s³ both grow with s: the top node dominates every other, the front is that node
    // alone, and every weighting selects it.
    assert_eq!(result.front.len(), 1, "{:?}", result.front);
    let top = &result.front[0];
    assert_eq!((top.node, top.design["stroke"]), (3, 1.0));
    assert!((top.values[0] - 1.0).abs() < 1e-12 && (top.values[1] - 1.0).abs() < 1e-12);
    assert_eq!(top.weight_range, Some((0.0, 1.0)));
    assert_eq!(result.weighted_optima[0].node, 3);
}

#[test]
fn optimize_and_task_refuse_a_mechanism_without_a_smooth_objective_or_a_wrench_system() {
    let optimize_study = r#"
[mechanism.gantry]
stroke = 0.5
[optimize]
objective = "volume"
variables = { stroke = [0.1, 1.0] }
starts = { count = 2, seed = 1 }
"#;
    let study: OptimizeStudy<TestMechanisms> = from_toml_str(optimize_study).unwrap();
    let e = optimize(&study, &Silent).unwrap_err();
    assert_eq!(e.path().unwrap().to_string(), "mechanism");
    assert!(
        e.to_string().contains(
            "gantry has no objective that is smooth in the design: its Monte Carlo workspace \
             volume is piecewise constant in the design variables; use a sweep or pareto study"
        ),
        "{e}"
    );
    let task_study = r#"
[mechanism.gantry]
stroke = 0.5
[task]
goal = "maximise"
pose = { position = [0.1, 0.1, 0.1] }
variables = { x = [0.0, 0.5] }
twists = [{ axis = [0.0, 0.0, 1.0], point = [0.0, 0.0, 0.0], pitch = 0.0, weight = 1.0 }]
starts = { count = 2, seed = 1 }
"#;
    let study: TaskStudy<TestMechanisms> = from_toml_str(task_study).unwrap();
    let e = task(&study, &Silent).unwrap_err();
    assert_eq!(e.path().unwrap().to_string(), "mechanism");
    assert!(
        e.to_string()
            .contains("gantry has no wrench system for a task study"),
        "{e}"
    );
}
