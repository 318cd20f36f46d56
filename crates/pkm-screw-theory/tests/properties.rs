//! Property tests of the screw-theory crate against independent relations.

use nalgebra::{Isometry3, Matrix3, SMatrix, Translation3, UnitQuaternion, Vector3, Vector6};
use pkm_screw_theory::*;
use proptest::prelude::*;

fn vec3(range: f64) -> impl Strategy<Value = Vector3<f64>> {
    [-range..range, -range..range, -range..range].prop_map(|[x, y, z]| Vector3::new(x, y, z))
}

fn direction() -> impl Strategy<Value = Vector3<f64>> {
    vec3(1.0).prop_filter("not too short", |v| v.norm() > 0.1)
}

fn vec6(range: f64) -> impl Strategy<Value = Vector6<f64>> {
    (vec3(range), vec3(range)).prop_map(|(a, b)| Vector6::new(a.x, a.y, a.z, b.x, b.y, b.z))
}

fn isometry() -> impl Strategy<Value = Isometry3<f64>> {
    (vec3(10.0), vec3(3.0)).prop_map(|(t, w)| {
        Isometry3::from_parts(Translation3::from(t), UnitQuaternion::from_scaled_axis(w))
    })
}

fn axis() -> impl Strategy<Value = ScrewAxis> {
    (direction(), vec3(10.0), -5.0..5.0).prop_filter_map("valid axis", |(d, p, pitch)| {
        ScrewAxis::new(&d, &p, pitch).ok()
    })
}

fn rows6() -> impl Strategy<Value = SMatrix<f64, 6, 6>> {
    proptest::collection::vec(-5.0..5.0_f64, 36).prop_map(|v| SMatrix::from_row_slice(&v))
}

/// The eq. 9 skew matrix exactly as printed: last row `[n2, n1, 0]`.
fn skew_as_printed(n: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -n.z, n.y, n.z, 0.0, -n.x, n.y, n.x, 0.0)
}

proptest! {
    #[test]
    fn klein_identity_holds_for_lines_from_points(x in vec3(100.0), y in vec3(100.0)) {
        prop_assume!((x - y).norm() > 1e-3);
        let line = PluckerLine::from_points(&x, &y).unwrap();
        let scale = line.direction().norm() * line.moment().norm();
        prop_assert!(line.klein_form().abs() <= 1e-12 * scale.max(1.0));
        // the line contains both points: p × d equals the moment for p = x and p = y
        let d = line.direction();
        prop_assert!((x.cross(&d) - line.moment()).norm() <= 1e-9 * (1.0 + scale));
        prop_assert!((y.cross(&d) - line.moment()).norm() <= 1e-9 * (1.0 + scale));
    }

    #[test]
    fn reciprocal_product_is_symmetric_and_invariant(
        w in vec6(10.0), t in vec6(10.0), g in isometry()
    ) {
        let (wrench, twist) = (Wrench::from_vector(w), Twist::from_vector(t));
        let p = reciprocal_product(&wrench, &twist);
        prop_assert_eq!(
            reciprocal_product_vectors(&w, &t).to_bits(),
            reciprocal_product_vectors(&t, &w).to_bits()
        );
        let moved = reciprocal_product(&wrench.transformed(&g), &twist.transformed(&g));
        prop_assert!((moved - p).abs() <= 1e-9 * (1.0 + w.norm() * t.norm() * 10.0));
    }

    #[test]
    fn transformed_twist_moves_points_consistently(t in vec6(3.0), g in isometry(), p in vec3(5.0)) {
        // the velocity of the moved point g(p) under the moved twist is R times the old velocity
        let twist = Twist::from_vector(t);
        let moved = twist.transformed(&g).velocity_at(&(g * nalgebra::Point3::from(p)).coords);
        let expected = g.rotation * twist.velocity_at(&p);
        prop_assert!((moved - expected).norm() <= 1e-9 * (1.0 + t.norm() * 20.0));
    }

    #[test]
    fn eq5_equals_eq6(twist_axis in axis(), wrench_axis in axis(), q in -3.0..3.0, rho in -3.0..3.0) {
        let eq5 = reciprocal_product(&Wrench::on_axis(&wrench_axis, rho), &Twist::on_axis(&twist_axis, q));
        let eq6 = reciprocal_product_geometric(&twist_axis, q, &wrench_axis, rho);
        let scale = (q * rho).abs() * (10.0 + twist_axis.point().norm() + wrench_axis.point().norm());
        prop_assert!((eq5 - eq6).abs() <= 1e-9 * scale.max(1e-12), "eq5 {} eq6 {}", eq5, eq6);
    }

    #[test]
    fn eq5_equals_eq6_for_parallel_axes(d in direction(), p in vec3(10.0), r in vec3(10.0),
                                        l in -2.0..2.0, lr in -2.0..2.0, flip in any::<bool>()) {
        let dr = if flip { -d } else { d };
        let (a, b) = (ScrewAxis::new(&d, &p, l).unwrap(), ScrewAxis::new(&dr, &r, lr).unwrap());
        let eq5 = reciprocal_product(&Wrench::on_axis(&b, 1.0), &Twist::on_axis(&a, 1.0));
        let eq6 = reciprocal_product_geometric(&a, 1.0, &b, 1.0);
        prop_assert!((eq5 - eq6).abs() <= 1e-9 * (10.0 + p.norm() + r.norm()));
    }

    #[test]
    fn objective_is_zero_exactly_on_the_reciprocal_system(
        rows3 in proptest::collection::vec(vec6(5.0), 3), c in vec3(2.0), extra in vec6(5.0)
    ) {
        let rows = SMatrix::<f64, 3, 6>::from_rows(&rows3.iter().map(|r| r.transpose()).collect::<Vec<_>>());
        let system = reciprocal_screw_system(&rows3, 1e-10).unwrap();
        prop_assume!(system.len() == 3);
        let chi = Twist::from_vector(system[0] * c.x + system[1] * c.y + system[2] * c.z);
        prop_assert!(task_objective(&rows, &chi) <= 1e-20 * (1.0 + rows.norm_squared()));
        // a twist with a component outside the reciprocal system does work: F > 0
        let outside = extra - system.iter().fold(Vector6::zeros(), |acc, s| acc + s * s.dot(&extra));
        prop_assume!(outside.norm() > 1e-3);
        prop_assert!(task_objective(&rows, &Twist::from_vector(outside)) > 0.0);
    }

    #[test]
    fn rank_plus_reciprocal_dimension_is_six(rows in proptest::collection::vec(vec6(5.0), 0..9)) {
        let rank = line_set_rank(&rows, 1e-10).unwrap();
        prop_assert_eq!(rank, rows.len().min(6));
        prop_assert_eq!(reciprocal_screw_system(&rows, 1e-10).unwrap().len(), 6 - rank);
    }

    #[test]
    fn gradients_match_central_differences(rows in rows6(), t in vec6(2.0)) {
        let twist = Twist::from_vector(t);
        let h = 1e-6;
        let g_rows = task_objective_gradient_rows(&rows, &twist);
        for k in 0..36 {
            let (mut plus, mut minus) = (rows, rows);
            plus[k] += h;
            minus[k] -= h;
            let fd = (task_objective(&plus, &twist) - task_objective(&minus, &twist)) / (2.0 * h);
            prop_assert!((fd - g_rows[k]).abs() <= 1e-5 * (1.0 + g_rows[k].abs()), "row entry {}: fd {} vs {}", k, fd, g_rows[k]);
        }
        let g_twist = task_objective_gradient_twist(&rows, &twist);
        for k in 0..6 {
            let (mut plus, mut minus) = (t, t);
            plus[k] += h;
            minus[k] -= h;
            let fd = (task_objective(&rows, &Twist::from_vector(plus))
                - task_objective(&rows, &Twist::from_vector(minus))) / (2.0 * h);
            prop_assert!((fd - g_twist[k]).abs() <= 1e-5 * (1.0 + g_twist[k].abs()), "twist entry {}: fd {} vs {}", k, fd, g_twist[k]);
        }
    }

    #[test]
    fn rotation_is_proper_and_matches_nalgebra(n in direction(), angle in -4.0..4.0_f64) {
        let r = rotation_from_axis_angle(&n, angle).unwrap();
        let m = r.matrix();
        prop_assert!((m.transpose() * m - Matrix3::identity()).norm() <= 1e-12);
        prop_assert!((m.determinant() - 1.0).abs() <= 1e-12);
        let reference = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(n), angle);
        prop_assert!((m - reference.matrix()).norm() <= 1e-12);
        // the matrix exponential of the correct skew matrix agrees too
        prop_assert!((m - (skew(&n.normalize()) * angle).exp()).norm() <= 1e-10);
    }

    #[test]
    fn printed_eq9_matrix_is_not_orthogonal(n in direction(), angle in 0.2..1.0_f64) {
        let n = n.normalize();
        // the typo only matters when n has x and y components
        prop_assume!(n.x.abs() > 0.2 && n.y.abs() > 0.2);
        let printed = (skew_as_printed(&n) * angle).exp();
        prop_assert!((printed.transpose() * printed - Matrix3::identity()).norm() > 1e-3);
    }
}

#[test]
fn printed_eq9_matrix_is_harmless_for_the_papers_axes() {
    for n in [Vector3::z(), Vector3::x()] {
        let printed = (skew_as_printed(&n) * 0.3).exp();
        let proper = rotation_from_axis_angle(&n, 0.3).unwrap();
        assert!((printed - proper.matrix()).norm() < 1e-12);
    }
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let p = Vector3::new(1.0, 2.0, 3.0);
    assert!(matches!(
        PluckerLine::from_points(&p, &p),
        Err(ScrewError::CoincidentPoints { .. })
    ));
    assert!(matches!(
        PluckerLine::from_direction_and_point(&Vector3::zeros(), &p),
        Err(ScrewError::ZeroDirection { .. })
    ));
    assert!(matches!(
        Twist::from_screw(&Vector3::z(), &p, f64::NAN, 1.0),
        Err(ScrewError::NonFinite { .. })
    ));
    assert!(matches!(
        Twist::from_vector(Vector6::zeros()).pitch(),
        Err(ScrewError::ZeroScrew { .. })
    ));
    assert!(matches!(
        rotation_from_axis_angle(&Vector3::zeros(), 1.0),
        Err(ScrewError::ZeroDirection { .. })
    ));
    assert!(matches!(
        line_set_rank(&[Vector6::repeat(f64::INFINITY)], 1e-9),
        Err(ScrewError::NonFinite { .. })
    ));
    assert!(matches!(
        line_set_rank(&[], 1.5),
        Err(ScrewError::InvalidTolerance { .. })
    ));
    let pitch = Twist::translation(&Vector3::z(), 2.0)
        .unwrap()
        .pitch()
        .unwrap();
    assert!(pitch.is_infinite() && pitch > 0.0, "{pitch}");
    let message = PluckerLine::from_points(&p, &p).unwrap_err().to_string();
    assert!(message.contains('0'), "{message}");
}

#[test]
fn parallel_lines_have_rank_three() {
    let rows: Vec<Vector6<f64>> = (0..6)
        .map(|k| {
            let angle = f64::from(k) * 1.1;
            PluckerLine::from_direction_and_point(
                &Vector3::z(),
                &Vector3::new(angle.cos(), angle.sin(), 0.0),
            )
            .unwrap()
            .to_vector()
        })
        .collect();
    assert_eq!(line_set_rank(&rows, 1e-9).unwrap(), 3);
    assert_eq!(reciprocal_screw_system(&rows, 1e-9).unwrap().len(), 3);
}
