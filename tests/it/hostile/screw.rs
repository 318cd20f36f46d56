//! `pkm-screw-theory`: lines, screw axes, twists and wrenches, line sets.

use super::{all_finite, config, hostile_f64, hostile_vec3, judge, judge_value};
use nalgebra::{Vector3, Vector6};
use pkm_screw_theory::{
    CommonNormal, PluckerLine, ScrewAxis, Twist, Wrench, line_set_rank, reciprocal_product,
    reciprocal_product_vectors, reciprocal_screw_system, rotation_from_axis_angle, task_objective,
    task_residuals,
};
use proptest::prelude::*;

fn unit(v: &Vector3<f64>) -> bool {
    all_finite(v.iter()) && (v.norm() - 1.0).abs() < 1e-12
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn lines_are_unit_and_finite(x in hostile_vec3(), y in hostile_vec3()) {
        // The direction is kept as given (not normalised); the normalised line has a unit one,
        // and the closest point to the origin is no farther than the first point.
        let line_is_checked = |l: &PluckerLine, through: &Vector3<f64>| {
            l.direction().amax() > 0.0 && all_finite(l.to_vector().iter())
                && unit(&l.normalized().direction())
                && all_finite(l.normalized().to_vector().iter())
                && l.closest_point_to_origin().norm() <= through.norm() * (1.0 + 1e-9) + 1e-300
        };
        judge("PluckerLine::from_points", || PluckerLine::from_points(&x, &y), |l| line_is_checked(l, &x))?;
        judge("PluckerLine::from_direction_and_point", || PluckerLine::from_direction_and_point(&x, &y), |l| line_is_checked(l, &y))?;
    }

    #[test]
    fn screw_axes_and_screws_are_finite(
        d in hostile_vec3(), p in hostile_vec3(), pitch in hostile_f64(), intensity in hostile_f64(),
    ) {
        judge("ScrewAxis::new", || ScrewAxis::new(&d, &p, pitch), |a| {
            unit(&a.direction()) && all_finite(a.unit_screw().iter())
        })?;
        judge("Twist::from_screw", || Twist::from_screw(&d, &p, pitch, intensity), |t| all_finite(t.as_vector().iter()))?;
        judge("Wrench::from_screw", || Wrench::from_screw(&d, &p, pitch, intensity), |w| all_finite(w.as_vector().iter()))?;
        judge("Twist::translation", || Twist::translation(&d, intensity), |t| all_finite(t.as_vector().iter()))?;
        judge("Wrench::couple", || Wrench::couple(&d, intensity), |w| all_finite(w.as_vector().iter()))?;
        judge("rotation_from_axis_angle", || rotation_from_axis_angle(&d, pitch), |r| all_finite(r.matrix().iter()))?;
        // Infinite pitch is the documented answer for a pure translation (ω = 0, v ≠ 0) only.
        let twist = Twist::new(d, p);
        judge("Twist::pitch", || twist.pitch(), |h| h.is_finite() || (d.amax() == 0.0 && p.amax() > 0.0))?;
    }

    #[test]
    fn common_normal_of_valid_axes_is_finite(
        d1 in hostile_vec3(), p1 in hostile_vec3(), d2 in hostile_vec3(), p2 in hostile_vec3(),
    ) {
        if let (Ok(a), Ok(b)) = (ScrewAxis::new(&d1, &p1, 0.1), ScrewAxis::new(&d2, &p2, -0.2)) {
            judge_value("CommonNormal::between", || CommonNormal::between(&a, &b), |n| {
                n.distance.is_finite() && n.angle.is_finite()
            })?;
        }
    }

    #[test]
    fn line_sets_have_a_rank(
        entries in prop::collection::vec(hostile_f64(), 0..36), rel_tol in hostile_f64(),
    ) {
        let rows: Vec<Vector6<f64>> = entries.chunks_exact(6).map(Vector6::from_column_slice).collect();
        judge("line_set_rank", || line_set_rank(&rows, rel_tol), |r| *r <= rows.len().min(6))?;
        judge("reciprocal_screw_system", || reciprocal_screw_system(&rows, rel_tol), |basis| {
            basis.len() <= 6 && basis.iter().all(|v| all_finite(v.iter()))
        })?;
    }

    /// The plain-value operations keep the documented contract (`pkm_screw_theory` crate
    /// docs): finite in (entries up to 1e75, which the objective squares twice) gives finite
    /// out, a NaN in gives a NaN out, and nothing panics.
    #[test]
    fn plain_value_operations_keep_their_nan_contract(
        a in prop::array::uniform6(-1e75..1e75f64), b in prop::array::uniform6(-1e75..1e75f64),
        nan_at in 0..7usize,
    ) {
        let (mut a, b) = (Vector6::from(a), Vector6::from(b));
        if nan_at < 6 {
            a[nan_at] = f64::NAN;
        }
        let finite_in = nan_at == 6;
        let (twist, wrench) = (Twist::from_vector(b), Wrench::from_vector(a));
        let rows = nalgebra::SMatrix::<f64, 1, 6>::from_row_slice(a.as_slice());
        let values = [
            reciprocal_product_vectors(&a, &b),
            reciprocal_product(&wrench, &twist),
            task_objective(&rows, &twist),
            task_residuals(&rows, &twist)[0],
        ];
        prop_assert!(values.iter().all(|v| v.is_finite() == finite_in), "{values:?}");
        let moved = Twist::from_vector(a).transformed(&nalgebra::Isometry3::translation(1.0, 2.0, 3.0));
        prop_assert_eq!(all_finite(moved.as_vector().iter()), finite_in);
    }
}
