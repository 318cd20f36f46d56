//! The general workspace-volume estimator against closed-form volumes, its symmetry reduction,
//! its thread-count independence and its answers to bad input.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use nalgebra::Vector3;
use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
use pkm_traits::{ConstraintError, Silent, WorkspaceConstraint};
use pkm_workspace_indices::{
    Domain, ErrorModel, IndexError, MAX_POINTS, PointSet, Region, Sampler, Workspace,
    hemisphere_estimate, ratio_standard_error, sweep_volumes, workspace_volume,
    workspace_volume_and_eta,
};
use proptest::prelude::*;
use std::f64::consts::PI;

/// The estimate lies within 4 standard errors (plus a floor for an exact hit) of `exact`.
fn assert_within(volume: f64, se: f64, exact: f64) -> Result<(), TestCaseError> {
    prop_assert!(se > 0.0, "standard error {se}");
    prop_assert!(
        (volume - exact).abs() <= 4.0 * se + 1e-12,
        "{volume} vs {exact} (se {se})"
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// A ball, a cylinder, a spherical cap, a torus and the lens of two balls, each inside a region that
    /// holds it, by Monte Carlo (i.i.d. errors) and by replicated Sobol points.
    #[test]
    fn closed_form_volumes_within_four_standard_errors(
        seed in 1u64..1_000_000,
        radius in 0.2f64..2.0,
        frac in 0.1f64..0.9,
        sobol in any::<bool>(),
    ) {
        let (sampler, replicates) = if sobol {
            (Sampler::Sobol { seed }, 8)
        } else {
            (Sampler::MonteCarlo { seed }, 1)
        };
        let box_region = Region::Box {
            lower: Vector3::from_element(-radius),
            upper: Vector3::from_element(radius),
        };
        let points = PointSet::new(Domain::new(box_region).unwrap(), sampler, 1 << 13, replicates).unwrap();
        // Ball.
        let ball = workspace_volume(&points, &Silent, |p| p.norm() <= radius).unwrap();
        assert_within(ball.volume, ball.volume_se, 4.0 / 3.0 * PI * radius.powi(3))?;
        // Vertical cylinder of radius frac·R and height R.
        let rc = frac * radius;
        let cyl_set = workspace_volume(&points, &Silent, |p| p.xy().norm() <= rc && p.z.abs() <= 0.5 * radius).unwrap();
        assert_within(cyl_set.volume, cyl_set.volume_se, PI * rc * rc * radius)?;
        // Spherical cap of height h = frac·R above z = R − h.
        let h = frac * radius;
        let cap = workspace_volume(&points, &Silent, |p| p.norm() <= radius && p.z >= radius - h).unwrap();
        assert_within(cap.volume, cap.volume_se, PI * h * h * (3.0 * radius - h) / 3.0)?;
        // Lens of two balls of radius R with centres d = frac·R apart.
        let d = frac * radius;
        let c = Vector3::new(d, 0.0, 0.0);
        let lens = workspace_volume(&points, &Silent, |p| p.norm() <= radius && (p - c).norm() <= radius).unwrap();
        let lens_exact = PI * (4.0 * radius + d) * (2.0 * radius - d).powi(2) / 12.0;
        assert_within(lens.volume, lens.volume_se, lens_exact)?;
        // Torus of tube radius a = frac·R/2 about the circle of radius R − a, in a cylinder.
        let a = 0.5 * frac * radius;
        let big = radius - a;
        let cyl = PointSet::new(Domain::new(Region::axial_cylinder(radius, -a, a)).unwrap(), sampler, 1 << 13, replicates).unwrap();
        let torus = workspace_volume(&cyl, &Silent, |p| (p.xy().norm() - big).hypot(p.z) <= a).unwrap();
        assert_within(torus.volume, torus.volume_se, 2.0 * PI * PI * big * a * a)?;
    }

    /// For a 3-fold symmetric robot, one 120° sector × 3 estimates the full region's volume.
    #[test]
    fn one_sector_times_three_is_the_whole_region(
        alpha_deg in 0.0f64..90.0, beta_deg in 0.0f64..90.0, seed in 1u64..1000,
    ) {
        let m = RotaryDelta::new(presets::miller_prototype(alpha_deg.to_radians(), beta_deg.to_radians(), Placement { motor_plane_z: 0.0, azimuth_motor_1: 0.3 },
        )).unwrap();
        let (radius, depth) = m.reach_cylinder();
        let ws = Workspace::new(&m, &[ElbowMode::Out], &[WorkspaceConstraint::below(0.0).unwrap()]).unwrap();
        let full = Domain::new(Region::axial_cylinder(radius, -depth, 0.0)).unwrap();
        let sector = full.with_sector(3, 1.0).unwrap();
        let sobol = Sampler::Sobol { seed };
        let v_full = ws.volume(&PointSet::new(full, sobol, 1 << 13, 8).unwrap(), &Silent).unwrap();
        let v_sector = ws.volume(&PointSet::new(sector, sobol, 1 << 13, 8).unwrap(), &Silent).unwrap();
        let se = v_full.volume_se.hypot(v_sector.volume_se);
        prop_assert!((v_full.volume - v_sector.volume).abs() <= 4.0 * se + 1e-9,
            "{} vs {} (se {se})", v_full.volume, v_sector.volume);
    }

    /// The orthogonality identity e_i·e_j = sin²α − ½cos²α holds for every α and β.
    #[test]
    fn motor_axis_products_follow_the_closed_form(alpha in -1.6f64..1.6, beta in -3.2f64..3.2) {
        let m = RotaryDelta::new(presets::miller_prototype(alpha, beta, Placement { motor_plane_z: 0.0, azimuth_motor_1: 0.7 })).unwrap();
        let l = m.legs();
        let expected = alpha.sin().powi(2) - 0.5 * alpha.cos().powi(2);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            prop_assert!((l[i].e.dot(&l[j].e) - expected).abs() < 1e-14);
        }
    }
}

#[test]
fn grid_sampler_gives_exact_volume_of_a_box_aligned_set() {
    let domain = Domain::new(Region::Box {
        lower: Vector3::zeros(),
        upper: Vector3::from_element(1.0),
    })
    .unwrap();
    let points = PointSet::new(domain, Sampler::Grid { per_axis: 10 }, 1000, 1).unwrap();
    let e = workspace_volume(&points, &Silent, |p| p.x < 0.5).unwrap();
    assert!((e.volume - 0.5).abs() < 1e-15);
    assert_eq!(e.error_model, ErrorModel::Iid);
}

#[test]
fn eta_of_a_constant_index_is_the_volume_and_gci_is_the_index() {
    let domain = Domain::new(Region::Ball {
        center: Vector3::new(1.0, 2.0, 3.0),
        radius: 2.0,
    })
    .unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 5 }, 4096, 4).unwrap();
    let centre = Vector3::new(1.0, 2.0, 3.0);
    let e = workspace_volume_and_eta(&points, &Silent, |p| {
        ((p - centre).norm() <= 1.0).then_some(0.25)
    })
    .unwrap();
    assert!((e.eta.unwrap() - 0.25 * e.volume).abs() < 1e-12);
    assert!((e.gci().unwrap() - 0.25).abs() < 1e-12);
    assert!((e.volume - 4.0 * PI / 3.0).abs() < 4.0 * e.volume_se + 1e-3);
}

#[test]
fn the_hemisphere_estimator_is_the_general_one_on_a_hemisphere() {
    // Stamper's estimator (unit points scaled by R) and the general one on the same points.
    let sampler = Sampler::MonteCarlo { seed: 11 };
    let unit = sampler.unit_hemisphere_points(20_000).unwrap();
    let radius = 1.7;
    let domain = Domain::new(Region::Hemisphere {
        center: Vector3::zeros(),
        radius,
    })
    .unwrap();
    let points = PointSet::new(domain, sampler, 20_000, 1).unwrap();
    let f = |p: &Vector3<f64>| (p.norm() < 1.0).then(|| 1.0 - p.z);
    let old = hemisphere_estimate(&unit, radius, &Silent, f).unwrap();
    let new = workspace_volume_and_eta(&points, &Silent, f).unwrap();
    assert_eq!(old.volume.to_bits(), new.volume.to_bits());
    assert_eq!(old.volume_se.to_bits(), new.volume_se.to_bits());
    assert_eq!(old.eta.to_bits(), new.eta.unwrap().to_bits());
    assert_eq!(old.gci(), new.gci());
}

fn sweep_bits(threads: usize) -> Vec<u64> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let place = Placement {
            motor_plane_z: 0.0,
            azimuth_motor_1: 0.0,
        };
        let designs: Vec<RotaryDelta> = (0..6)
            .map(|k| {
                RotaryDelta::new(presets::miller_prototype(
                    0.1 * f64::from(k),
                    0.2 * f64::from(k),
                    place,
                ))
                .unwrap()
            })
            .collect();
        let below = [WorkspaceConstraint::below(0.0).unwrap()];
        let ws: Vec<_> = designs
            .iter()
            .map(|d| Workspace::new(d, &[ElbowMode::Out, ElbowMode::In], &below).unwrap())
            .collect();
        let (radius, depth) = designs[0].reach_cylinder();
        let domain = Domain::new(Region::axial_cylinder(radius, -depth, 0.0))
            .unwrap()
            .with_sector(3, 0.0)
            .unwrap();
        let points = PointSet::new(domain, Sampler::Sobol { seed: 3 }, 5000, 3).unwrap();
        let v = sweep_volumes(&ws, &points, &Silent, |w, x| w.contains(x)).unwrap();
        let e = ws[2].volume_and_eta(&points, &Silent).unwrap();
        let mut bits: Vec<u64> = v
            .iter()
            .flat_map(|e| [e.volume.to_bits(), e.volume_se.to_bits()])
            .collect();
        bits.push(e.eta.unwrap().to_bits());
        bits.push(ratio_standard_error(&v[1], &v[0]).unwrap().to_bits());
        bits
    })
}

#[test]
fn sweeps_are_bit_identical_for_one_two_and_eight_threads() {
    let one = sweep_bits(1);
    assert_eq!(one, sweep_bits(2));
    assert_eq!(one, sweep_bits(8));
}

#[test]
fn bad_regions_and_counts_are_typed_errors() {
    let nan = f64::NAN;
    for region in [
        Region::axial_cylinder(nan, 0.0, 1.0),
        Region::axial_cylinder(-1.0, 0.0, 1.0),
        Region::axial_cylinder(1.0, 1.0, 0.0),
        Region::axial_cylinder(1.0, 0.0, 0.0),
        Region::axial_cylinder(1e300, -1e300, 1e300),
        Region::Box {
            lower: Vector3::zeros(),
            upper: Vector3::new(1.0, -1.0, 1.0),
        },
        Region::Box {
            lower: Vector3::from_element(f64::NEG_INFINITY),
            upper: Vector3::zeros(),
        },
        Region::Ball {
            center: Vector3::zeros(),
            radius: 0.0,
        },
        Region::Hemisphere {
            center: Vector3::new(nan, 0.0, 0.0),
            radius: 1.0,
        },
    ] {
        assert!(
            matches!(Domain::new(region), Err(IndexError::Invalid(_))),
            "{region:?}"
        );
    }
    let cube = Domain::new(Region::Box {
        lower: Vector3::zeros(),
        upper: Vector3::from_element(1.0),
    })
    .unwrap();
    assert!(cube.with_sector(3, 0.0).is_err());
    let ball = Domain::new(Region::Ball {
        center: Vector3::zeros(),
        radius: 1.0,
    })
    .unwrap();
    assert!(ball.with_sector(0, 0.0).is_err());
    assert!(ball.with_sector(3, nan).is_err());
    let s = Sampler::Sobol { seed: 1 };
    assert!(matches!(
        PointSet::new(ball, s, 0, 1),
        Err(IndexError::EmptySample { .. })
    ));
    assert!(matches!(
        PointSet::new(ball, s, 10, 0),
        Err(IndexError::EmptySample { .. })
    ));
    assert!(matches!(
        PointSet::new(ball, s, u64::MAX, 2),
        Err(IndexError::TooLarge { .. })
    ));
    assert!(matches!(
        PointSet::new(ball, s, MAX_POINTS + 1, 1),
        Err(IndexError::TooLarge { .. })
    ));
    assert!(matches!(
        PointSet::new(ball, s, 10, 1000),
        Err(IndexError::TooLarge { .. })
    ));
    assert!(PointSet::new(ball, Sampler::Grid { per_axis: 4 }, 63, 1).is_err());
    assert!(PointSet::new(ball, Sampler::Grid { per_axis: 4 }, 64, 2).is_err());
    let designs: [f64; 0] = [];
    let points = PointSet::new(ball, s, 16, 1).unwrap();
    assert!(sweep_volumes(&designs, &points, &Silent, |_, _| true).is_err());
}

#[test]
fn bad_constraints_are_typed_errors() {
    let nan = f64::NAN;
    assert!(WorkspaceConstraint::half_space(Vector3::zeros(), 0.0).is_err());
    assert!(WorkspaceConstraint::half_space(Vector3::new(nan, 0.0, 1.0), 0.0).is_err());
    assert!(WorkspaceConstraint::below(f64::INFINITY).is_err());
    assert!(WorkspaceConstraint::joint_range(1.0, -1.0).is_err());
    assert!(WorkspaceConstraint::joint_range(nan, 1.0).is_err());
    assert!(WorkspaceConstraint::passive_cone(0.0).is_err());
    assert!(WorkspaceConstraint::passive_cone(4.0).is_err());
    assert!(WorkspaceConstraint::leg_clearance(-1.0).is_err());
    // Huge normals are scaled, not overflowed.
    let h = WorkspaceConstraint::half_space(Vector3::new(0.0, 0.0, 1e300), 1e300).unwrap();
    assert!(h.holds_at_position(&Vector3::new(0.0, 0.0, 0.5)));
    assert!(!h.holds_at_position(&Vector3::new(0.0, 0.0, 1.5)));
    // A joint that does not exist, and no modes.
    let m = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
    let c = WorkspaceConstraint::joint_range_of(3, 0.0, 1.0).unwrap();
    assert!(matches!(
        Workspace::new(&m, &[ElbowMode::Out], &[c]),
        Err(IndexError::Constraint(ConstraintError::NoSuchJoint { .. }))
    ));
    assert!(Workspace::new(&m, &[], &[]).is_err());
}

#[test]
fn joint_limits_only_shrink_the_workspace() {
    let m = RotaryDelta::new(presets::nuwar(Placement {
        motor_plane_z: 0.0,
        azimuth_motor_1: 0.0,
    }))
    .unwrap();
    let (radius, depth) = m.reach_cylinder();
    let domain = Domain::new(Region::axial_cylinder(radius, -depth, 0.0))
        .unwrap()
        .with_sector(3, 0.0)
        .unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 8 }, 8192, 2).unwrap();
    let below = WorkspaceConstraint::below(0.0).unwrap();
    let volume = |limits: &[WorkspaceConstraint]| {
        let ws = Workspace::new(&m, &[ElbowMode::Out], limits).unwrap();
        ws.volume(&points, &Silent).unwrap().n_inside
    };
    let free = volume(&[below]);
    let cone = volume(&[below, WorkspaceConstraint::passive_cone(0.5).unwrap()]);
    let arms = volume(&[below, WorkspaceConstraint::joint_range(-0.5, 1.5).unwrap()]);
    let apart = volume(&[below, WorkspaceConstraint::leg_clearance(0.05).unwrap()]);
    assert!(free > 0);
    for limited in [cone, arms, apart] {
        assert!(limited < free, "{limited} vs {free}");
        assert!(limited > 0);
    }
}

#[test]
fn the_tsai_workspace_through_the_traits_matches_the_stamper_kernel() {
    use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
    use pkm_traits::{InverseKinematics, KinematicsError};
    use pkm_workspace_indices::inverse_condition_number_3x3;
    let tsai = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    let radius = tsai.reach();
    let sampler = Sampler::MonteCarlo { seed: 4 };
    let unit = sampler.unit_hemisphere_points(20_000).unwrap();
    // The closure the Stamper studies were written with before the generic entry point.
    let stamper = hemisphere_estimate(&unit, radius, &Silent, |p| {
        tsai.velocity_jacobian_at(p, [Elbow::Out; 3]).map_or_else(
            |e| matches!(e, KinematicsError::Singular { .. }).then_some(0.0),
            |j| Some(inverse_condition_number_3x3(&j)),
        )
    })
    .unwrap();
    let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[]).unwrap();
    let one_by_one = hemisphere_estimate(&unit, radius, &Silent, |p| ws.inverse_condition(p));
    assert_eq!(
        one_by_one.unwrap(),
        stamper,
        "the generic entry point asked point by point is the Stamper kernel, bit for bit"
    );
    // On the lane kernels: the same points inside, η to rounding.
    let generic = ws.hemisphere_estimate(&unit, radius, &Silent).unwrap();
    assert_eq!(
        (generic.n_inside, generic.volume),
        (stamper.n_inside, stamper.volume)
    );
    assert!(
        (generic.eta / stamper.eta - 1.0).abs() < 1e-12,
        "{generic:?} vs {stamper:?}"
    );
    let domain = Domain::new(Region::Hemisphere {
        center: Vector3::zeros(),
        radius,
    })
    .unwrap();
    let points = PointSet::new(domain, sampler, 20_000, 1).unwrap();
    let e = ws.volume_and_eta(&points, &Silent).unwrap();
    // The same points mapped by the general domain (bit-identical to the scaled unit points),
    // so the same estimate to rounding of the point coordinates.
    assert!(
        (e.n_inside as f64 - stamper.n_inside as f64).abs() <= 0.002 * stamper.n_inside as f64,
        "{} vs {}",
        e.n_inside,
        stamper.n_inside
    );
    assert!((e.eta.unwrap() - stamper.eta).abs() <= 0.01 * stamper.eta);
}

#[test]
fn a_constraint_the_mechanism_cannot_evaluate_is_a_typed_error() {
    use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
    use pkm_traits::ConstraintKind;
    let tsai = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    for c in [
        WorkspaceConstraint::passive_cone(0.5).unwrap(),
        WorkspaceConstraint::leg_clearance(0.01).unwrap(),
    ] {
        let err = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[c]).unwrap_err();
        assert!(
            matches!(
                err,
                IndexError::Constraint(ConstraintError::Unsupported {
                    mechanism: "Tsai3Dof",
                    kind: ConstraintKind::PassiveCone | ConstraintKind::LegClearance
                })
            ),
            "{err}"
        );
    }
    let range = WorkspaceConstraint::joint_range(-1.0, 1.0).unwrap();
    assert!(Workspace::new(&tsai, &[[Elbow::Out; 3]], &[range]).is_ok());
}
