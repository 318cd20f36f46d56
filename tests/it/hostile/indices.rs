//! `pkm-workspace-indices` outside `volume.rs`, `sampler.rs` and `sobol.rs`: condition numbers,
//! quadrature, cross-section means, slices and space utilisation.

use super::{config, hostile_count, hostile_f64, judge, judge_err, judge_value};
use nalgebra::{Matrix3, Matrix6};
use pkm_traits::{Extents, SlicedRegion};
use pkm_workspace_indices::{
    GaussLegendre, GridRule, Slice, condition_number, inverse_condition_number,
    inverse_condition_number_3x3, mean_by_grid, mean_by_quadrature, space_utilization,
};
use proptest::prelude::*;

/// The unit square $[0, 1]^2$.
struct Square;

impl SlicedRegion for Square {
    fn slice(&self, y: f64) -> Option<(f64, f64)> {
        (0.0..=1.0).contains(&y).then_some((0.0, 1.0))
    }
    fn breakpoints(&self) -> &[f64] {
        &[0.0, 1.0]
    }
    fn extents(&self) -> Extents {
        Extents {
            y_min: 0.0,
            y_max: 1.0,
            z_min: 0.0,
            z_max: 1.0,
        }
    }
    fn area(&self) -> f64 {
        1.0
    }
}

fn ratio(v: &f64) -> bool {
    (0.0..=1.0).contains(v)
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn inverse_condition_numbers_are_ratios(entries in prop::collection::vec(hostile_f64(), 36)) {
        let j6 = Matrix6::from_column_slice(&entries);
        let j3 = Matrix3::from_column_slice(&entries[..9]);
        judge_value("inverse_condition_number (6x6)", || inverse_condition_number(&j6), ratio)?;
        judge_value("inverse_condition_number (3x3)", || inverse_condition_number(&j3), ratio)?;
        judge_value("inverse_condition_number_3x3", || inverse_condition_number_3x3(&j3), ratio)?;
        judge_value("condition_number", || condition_number(&j3), |k| *k >= 1.0)?;
    }

    /// 1/κ is scale-invariant: the closed form agrees with the SVD for matrices scaled by
    /// 1e±200, where the products $J^\top J$ of the closed form would overflow or underflow.
    #[test]
    fn inverse_condition_number_is_scale_invariant(entries in prop::collection::vec(-1.0..1.0f64, 9), exponent in prop::sample::select(vec![-200, -100, 0, 100, 200])) {
        let j = Matrix3::from_column_slice(&entries);
        let reference = inverse_condition_number(&j);
        let scaled = j * 10f64.powi(exponent);
        judge_value("inverse_condition_number_3x3 (scaled)", || inverse_condition_number_3x3(&scaled), |v| {
            ratio(v) && (v - reference).abs() <= 1e-8
        })?;
        judge_value("inverse_condition_number (scaled)", || inverse_condition_number(&scaled), |v| {
            ratio(v) && (v - reference).abs() <= 1e-8
        })?;
    }

    #[test]
    fn area_means_end_typed_or_finite(
        n in hostile_count(), min_points in hostile_count(), target in hostile_count(), shrink in hostile_f64(),
    ) {
        let n = n.min(64);
        judge("mean_by_quadrature", || mean_by_quadrature(&Square, |y, z| y + z, n), |m| (m - 1.0).abs() < 1e-9)?;
        let rule = GridRule { min_points: min_points.min(2000), target_points: target.min(3000), shrink };
        judge("mean_by_grid", || mean_by_grid(&Square, |y, z| y + z, &rule), |m| m.mean.is_finite() && m.n_points > 0)?;
    }

    #[test]
    fn slices_and_space_utilisation(
        z in hostile_f64(), half_width in hostile_f64(), n in 0..20usize, points in prop::collection::vec((hostile_f64(), hostile_f64()), 0..3),
    ) {
        judge("Slice::square", || Slice::square(z, half_width, n, |x, y, _| Some(x + y)), |s| {
            s.values.len() == n * n && s.x.iter().all(|x| x.is_finite())
        })?;
        let points: Vec<[f64; 2]> = points.into_iter().map(|(a, b)| [a, b]).collect();
        judge("space_utilization", || space_utilization(&Square, &points), |u| *u > 0.0 && *u <= 1.0)?;
    }
}

#[test]
fn huge_counts_are_refused_before_allocating() {
    for n in [usize::MAX, 1 << 40, 1 << 33] {
        super::expect(judge_err("mean_by_quadrature (huge)", || {
            mean_by_quadrature(&Square, |y, z| y + z, n)
        }));
        super::expect(judge_err("Slice::square (huge)", || {
            Slice::square(0.5, 1.0, n, |_, _, _| Some(1.0))
        }));
        let rule = GridRule {
            min_points: n,
            target_points: n,
            shrink: 0.95,
        };
        super::expect(judge_err("mean_by_grid (huge)", || {
            mean_by_grid(&Square, |y, z| y + z, &rule)
        }));
        super::expect(judge_err("GaussLegendre::new (huge)", || {
            GaussLegendre::new(n)
        }));
    }
}
