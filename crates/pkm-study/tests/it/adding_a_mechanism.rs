//! `docs/adding-a-mechanism.md`, followed step by step: a mechanism that pkm does not know (a
//! Cartesian 3-PPP gantry), declared in this test alone, runs through the study layer. Its
//! workspace has a closed form (the stroke box, κ = 1 everywhere), so the study's numbers are
//! checked against it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{SMatrix, Vector3};
use pkm_mechanisms::{LinkKind, PointKind, Skeleton, SkeletonPoint};
use pkm_study::schema::mechanism::{BuildError, WorkspaceVisitor};
use pkm_study::schema::units::PositiveMetres;
use pkm_study::{Actuation, Artifact, StudyMechanism, WorkspaceStudy, from_toml_str, workspace};
use pkm_traits::{
    ClosedChain, ConstrainedWorkspace, InverseKinematics, Joints, KinematicsError, Silent, Task,
    WorkspaceConstraint,
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

    fn kind(&self) -> &'static str {
        "gantry"
    }

    fn actuation(&self) -> Actuation {
        Actuation::Prismatic
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        let mut all = vec![
            WorkspaceConstraint::joint_range(0.0, self.stroke.0)
                .map_err(|e| BuildError::Design(e.to_string()))?,
        ];
        all.extend_from_slice(constraints);
        let workspace = pkm_workspace_indices::Workspace::new(&Gantry, &[()], &all)
            .map_err(|e| BuildError::Constraint(e.to_string()))?;
        Ok(visitor.visit(&workspace))
    }

    fn reach_region(&self) -> Result<Option<Region>, BuildError> {
        let s = self.stroke.0;
        Ok(Some(Region::Box {
            lower: Vector3::zeros(),
            upper: Vector3::new(s, s, s),
        }))
    }

    fn skeleton_at(&self, p: &Vector3<f64>) -> Result<Skeleton, String> {
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
