//! Property tests of pkm-workspace-indices: the closed-form 3×3 inverse condition number against
//! the SVD, and the cross-section means against closed forms.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::Matrix3;
use pkm_traits::{Extents, SlicedRegion};
use pkm_workspace_indices::{
    GridRule, inverse_condition_number, inverse_condition_number_3x3, mean_by_grid,
    mean_by_quadrature, space_utilization,
};
use proptest::prelude::*;

/// The unit disc, split at its centre.
struct UnitDisc;

impl SlicedRegion for UnitDisc {
    fn slice(&self, y: f64) -> Option<(f64, f64)> {
        let s = 1.0 - y * y;
        (s >= 0.0).then(|| (-s.sqrt(), s.sqrt()))
    }
    fn breakpoints(&self) -> &[f64] {
        &[-1.0, 0.0, 1.0]
    }
    fn extents(&self) -> Extents {
        Extents {
            y_min: -1.0,
            y_max: 1.0,
            z_min: -1.0,
            z_max: 1.0,
        }
    }
    fn area(&self) -> f64 {
        std::f64::consts::PI
    }
}

#[test]
fn quadrature_mean_of_r_squared_over_the_disc_is_one_half() {
    let mean = mean_by_quadrature(&UnitDisc, |y, z| y * y + z * z, 24).unwrap();
    assert!((mean - 0.5).abs() < 1e-4, "{mean}");
}

#[test]
fn paper_grid_rule_uses_more_than_5000_points_and_estimates_the_area() {
    let grid = mean_by_grid(&UnitDisc, |y, z| y * y + z * z, &GridRule::default()).unwrap();
    assert!(grid.n_points > 5000);
    assert!(
        (grid.area / std::f64::consts::PI - 1.0).abs() < 2e-3,
        "{}",
        grid.area
    );
    assert!((grid.mean - 0.5).abs() < 2e-3, "{}", grid.mean);
}

#[test]
fn space_utilization_of_the_disc_in_its_box_is_pi_over_4() {
    let eta2 = space_utilization(&UnitDisc, &[[0.0, 0.0]]).unwrap();
    assert!((eta2 - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    let wider = space_utilization(&UnitDisc, &[[3.0, 0.0]]).unwrap();
    assert!((wider - std::f64::consts::PI / 8.0).abs() < 1e-15);
    assert!(space_utilization(&UnitDisc, &[[f64::NAN, 0.0]]).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn closed_form_3x3_matches_the_svd(entries in prop::array::uniform9(-3.0..3.0f64)) {
        let j = Matrix3::from_row_slice(&entries);
        let closed = inverse_condition_number_3x3(&j);
        let svd = inverse_condition_number(&j);
        prop_assert!((closed - svd).abs() < 1e-9 * (1.0 + 1.0 / svd.max(1e-300)).min(1e6), "{closed} vs {svd}");
        prop_assert!((0.0..=1.0).contains(&closed));
    }

    #[test]
    fn closed_form_3x3_is_scale_invariant(entries in prop::array::uniform9(-3.0..3.0f64), s in 0.01..100.0f64) {
        let j = Matrix3::from_row_slice(&entries);
        let a = inverse_condition_number_3x3(&j);
        let b = inverse_condition_number_3x3(&(j * s));
        prop_assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
}
