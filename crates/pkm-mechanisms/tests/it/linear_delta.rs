//! Property tests of pkm-mechanisms: conformance of the Linear Delta (closure, Jacobians vs
//! central differences, IK → FK round trip) and its exact cross-section (area vs a fine slice
//! sum, corners and extents).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::Vector3;
use pkm_mechanisms::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
use pkm_traits::{SlicedRegion, Task, testkit};
use proptest::prelude::*;

fn delta(l1: f64, ya: f64, zr: f64, l2: f64) -> LinearDelta {
    let ratios = LinearDeltaRatios {
        l1_over_yr: l1,
        ya_over_yr: ya,
        zr_over_yr: zr,
        l2_over_l1: l2,
    };
    LinearDelta::new(LinearDeltaDesign { ratios, yr: 0.5 }).unwrap()
}

/// Poses on a 7 × 7 grid over the cross-section's extents, at several x.
fn poses(d: &LinearDelta) -> Vec<Task<3>> {
    let e = d.cross_section().extents();
    let mut poses = Vec::new();
    for i in 1..8 {
        for k in 1..8 {
            let y = e.y_min + (e.y_max - e.y_min) * i as f64 / 8.0;
            let z = e.z_min + (e.z_max - e.z_min) * k as f64 / 8.0;
            if d.cross_section().contains(y, z) {
                poses.push(Vector3::new(0.1 * (i + k) as f64, y, z));
            }
        }
    }
    poses
}

/// $\int (\text{hi} - \text{lo})\,dy$ by the midpoint rule on `n` slices.
fn slice_sum(region: &impl SlicedRegion, n: usize) -> f64 {
    let e = region.extents();
    let h = (e.y_max - e.y_min) / n as f64;
    (0..n)
        .filter_map(|i| region.slice(e.y_min + (i as f64 + 0.5) * h))
        .map(|(lo, hi)| (hi - lo) * h)
        .sum()
}

#[test]
fn linear_delta_passes_the_conformance_kit() {
    testkit::check_traits::<LinearDelta>();
    for d in [
        delta(2.0, 0.0, 0.0, 0.63),
        delta(1.6, 0.3, -0.4, 0.9),
        delta(1.5, 0.1, 0.3, 1.2),
    ] {
        let poses = poses(&d);
        let mode = LinearDeltaMode::PAPER;
        testkit::check_closure(&d, mode, &poses, 1e-12).unwrap();
        testkit::check_jacobians_against_central_differences(&d, mode, &poses, 1e-6, 1e-7).unwrap();
        testkit::check_ik_fk_round_trip(&d, mode, &poses, 1e-3, 1e-9).unwrap();
        testkit::check_velocity_jacobian_at(&d, mode, &poses, 1e-12).unwrap();
    }
}

#[test]
fn velocity_jacobian_is_minus_jq_inverse_jx() {
    use pkm_traits::{ClosedChain, InverseKinematics};
    let d = delta(1.6, 0.3, -0.4, 0.9);
    for x in poses(&d) {
        let q = d.inverse_kinematics(&x, LinearDeltaMode::PAPER).unwrap();
        let j = d.jacobian(&x, &q).unwrap();
        let j_yz = d.velocity_jacobian_at(&x, LinearDeltaMode::PAPER).unwrap();
        assert!((j - j_yz).amax() < 1e-12);
    }
}

#[test]
fn inverse_kinematics_rejects_poses_outside_the_cross_section() {
    use pkm_traits::{InverseKinematics, KinematicsError};
    let mode = LinearDeltaMode::PAPER;
    let unreachable = |d: &LinearDelta, y: f64, z: f64| {
        matches!(
            d.inverse_kinematics(&Vector3::new(0.3, y, z), mode),
            Err(KinematicsError::Unreachable { discriminant, .. }) if discriminant < 0.0
        )
    };
    // Inside all three discs, but above the plane z = 0 that the end effector cannot pass.
    let d = delta(2.0, 0.0, 0.0, 0.63);
    assert!(unreachable(&d, 0.0, 0.1));
    assert!(unreachable(&d, 0.2, 1e-9));
    assert!(
        d.inverse_kinematics(&Vector3::new(0.3, 0.0, 0.0), mode)
            .is_ok()
    );
    assert!(
        d.inverse_kinematics(&Vector3::new(0.3, 0.0, -0.5), mode)
            .is_ok()
    );
    // ZR < 0: inside the discs and below z = 0, but above the line A1-A3 (the centre rail at
    // A3 = (0.15, -0.2) blocks the outer arms).
    let d = delta(1.6, 0.3, -0.4, 0.9);
    assert!(unreachable(&d, 0.0, -0.1));
    assert!(
        d.inverse_kinematics(&Vector3::new(0.3, 0.15, -0.4), mode)
            .is_ok()
    );
}

#[test]
fn inverse_kinematics_succeeds_exactly_on_the_cross_section() {
    use pkm_traits::InverseKinematics;
    let mut inside = 0;
    for d in [
        delta(2.0, 0.0, 0.0, 0.63),
        delta(1.6, 0.3, -0.4, 0.9),
        delta(1.5, 0.1, 0.3, 1.2),
        delta(1.48, 0.0, -0.73, 0.01),
        delta(2.0, -0.4, -0.9, 0.7),
    ] {
        let region = d.cross_section();
        let e = region.extents();
        let (dy, dz) = (e.y_max - e.y_min, e.z_max - e.z_min);
        for i in 0..=60 {
            for k in 0..=60 {
                // A box 20 % larger than the extents on every side, off the extents' lattice.
                let y = e.y_min - 0.2 * dy + 1.4 * dy * (i as f64 + 0.37) / 61.0;
                let z = e.z_min - 0.2 * dz + 1.4 * dz * (k as f64 + 0.61) / 61.0;
                let ik = d.inverse_kinematics(&Vector3::new(0.0, y, z), LinearDeltaMode::PAPER);
                assert_eq!(ik.is_ok(), region.contains(y, z), "({y}, {z}) in {d:?}");
                inside += usize::from(ik.is_ok());
            }
        }
    }
    assert!(inside > 1000, "vacuous: only {inside} poses inside");
}

#[test]
fn bad_designs_are_typed_errors() {
    let ratios = |l1: f64, ya: f64, l2: f64| LinearDeltaRatios {
        l1_over_yr: l1,
        ya_over_yr: ya,
        zr_over_yr: 0.0,
        l2_over_l1: l2,
    };
    for (r, name) in [
        (ratios(0.9, 0.0, 1.0), "L1/YR"),
        (ratios(f64::NAN, 0.0, 1.0), "L1/YR"),
        (ratios(2.0, 1.0, 1.0), "YA/YR"),
        (ratios(2.0, 0.0, 0.0), "L2/L1"),
        (ratios(2.0, 0.0, f64::INFINITY), "L2/L1"),
    ] {
        let design = LinearDeltaDesign { ratios: r, yr: 1.0 };
        assert_eq!(LinearDelta::new(design).unwrap_err().parameter, name);
    }
    let flat = LinearDeltaDesign {
        ratios: ratios(2.0, 0.0, 1.0),
        yr: 0.0,
    };
    assert!(LinearDelta::new(flat).is_err());
}

#[test]
fn centre_rail_above_its_reach_empties_the_workspace() {
    let region = delta(2.0, 0.0, 0.5, 0.2).cross_section();
    assert!(region.is_empty());
    assert!(region.area() == 0.0);
}

#[test]
fn half_lens_area_is_the_closed_form() {
    // ZR = 0 and a centre disc that contains the lens: W is half the lens of two discs of
    // radius L at distance 2 YR, area L² acos(d/L) − d √(L² − d²) with d = YR.
    let (yr, l1) = (0.5, 2.0);
    let region = delta(l1, 0.0, 0.0, 1.8).cross_section();
    let (l, d) = (l1 * yr, yr);
    let exact = l * l * (d / l).acos() - d * (l * l - d * d).sqrt();
    assert!(
        (region.area() - exact).abs() < 1e-14,
        "{} vs {exact}",
        region.area()
    );
    assert_eq!(region.corners().len(), 3);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn area_matches_a_fine_slice_sum(
        l1 in 1.05..2.7f64, ya in -0.7..0.7f64, zr in -1.0..0.5f64, l2 in 0.05..1.8f64,
    ) {
        let region = delta(l1, ya, zr, l2).cross_section();
        prop_assume!(!region.is_empty());
        let area = region.area();
        let sum = slice_sum(&region, 200_000);
        let scale = region.extents().area();
        prop_assert!((area - sum).abs() < 1e-6 * scale, "{area} vs {sum}");
    }

    #[test]
    fn corners_lie_in_the_region_and_extents_bound_it(
        l1 in 1.05..2.7f64, ya in -0.7..0.7f64, zr in -1.0..0.5f64, l2 in 0.05..1.8f64,
    ) {
        let region = delta(l1, ya, zr, l2).cross_section();
        prop_assume!(!region.is_empty());
        let e = region.extents();
        let tol = 1e-9;
        for c in region.corners() {
            prop_assert!(c[0] >= e.y_min - tol && c[0] <= e.y_max + tol);
            prop_assert!(c[1] >= e.z_min - tol && c[1] <= e.z_max + tol);
        }
        let n = 400;
        let (mut lo_min, mut hi_max) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..=n {
            let y = e.y_min + (e.y_max - e.y_min) * i as f64 / n as f64;
            if let Some((lo, hi)) = region.slice(y) {
                lo_min = lo_min.min(lo);
                hi_max = hi_max.max(hi);
            }
        }
        prop_assert!(lo_min >= e.z_min - tol && hi_max <= e.z_max + tol);
        // Sampling misses at most (largest slope) × (half a sample spacing) near a corner.
        let slack = 0.02 * (e.y_max - e.y_min + e.z_max - e.z_min);
        prop_assert!(lo_min - e.z_min < slack && e.z_max - hi_max < slack);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The closed form behind `velocity_jacobian_at` equals the trait default (IK, then
    /// $-J_q^{-1}J_x$) to 1e-12 relative (largest entry) on random designs, modes and poses,
    /// and fails exactly where the default fails.
    #[test]
    fn closed_form_velocity_jacobian_equals_the_trait_default(
        design in (1.0..2.8f64, -0.9..0.9f64, -1.2..0.6f64, 0.2..2.0f64),
        leans in prop::array::uniform3(any::<bool>()),
        x in -1.0..1.0f64, u in -0.1..1.1f64, v in -0.1..1.1f64,
    ) {
        use pkm_traits::{ClosedChain, InverseKinematics};
        let d = delta(design.0, design.1, design.2, design.3);
        let mode = LinearDeltaMode { leans_positive: leans };
        // Over the cross-section's extents, widened by a tenth on every side.
        let e = d.cross_section().extents();
        let p = Vector3::new(x, e.y_min + u * (e.y_max - e.y_min), e.z_min + v * (e.z_max - e.z_min));
        let fast = d.velocity_jacobian_at(&p, mode);
        let reference = d.inverse_kinematics(&p, mode).and_then(|q| d.jacobian(&p, &q));
        prop_assert_eq!(fast.is_ok(), reference.is_ok());
        prop_assume!(fast.is_ok());
        if let (Ok(fast), Ok(reference)) = (fast, reference) {
            let error = (fast - reference).amax() / reference.amax();
            prop_assert!(error <= 1e-12, "{p}: relative error {error:e}");
        }
    }
}
