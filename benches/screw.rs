use criterion::Criterion;
use nalgebra::{SMatrix, Vector3, Vector6};
use pkm::screw_theory::{
    PluckerLine, Twist, Wrench, reciprocal_product, task_objective, task_objective_gradient_rows,
    task_objective_gradient_twist,
};
use std::hint::black_box;

/// Six fixed, generic leg rows and a λ = 1 twist (the §4.1 task of Wolf & Shoham).
fn rows_and_twist() -> (SMatrix<f64, 6, 6>, Twist) {
    let mut rows = SMatrix::<f64, 6, 6>::zeros();
    for k in 0..6 {
        let t = 1.05 * k as f64;
        let base = Vector3::new(12.0 * t.cos(), 12.0 * t.sin(), 0.0);
        let top = Vector3::new(
            8.0 * (t + 0.4).cos() - 10.0,
            8.0 * (t + 0.4).sin() - 10.0,
            50.0,
        );
        if let Ok(line) = PluckerLine::from_points(&base, &top) {
            rows.set_row(k, &line.normalized().to_vector().transpose());
        }
    }
    let chi = Twist::from_vector(Vector6::new(
        2.0 / 3.0,
        2.0 / 3.0,
        1.0 / 3.0,
        -7.0 / 3.0,
        4.0,
        -1.0 / 3.0,
    ));
    (rows, chi)
}

pub(crate) fn screw(c: &mut Criterion) {
    let (rows, chi) = rows_and_twist();
    let wrench = Wrench::from_vector(rows.row(0).transpose());
    c.bench_function("screw/reciprocal_product", |b| {
        b.iter(|| reciprocal_product(black_box(&wrench), black_box(&chi)))
    });
    c.bench_function("screw/task_objective_6_rows", |b| {
        b.iter(|| task_objective(black_box(&rows), black_box(&chi)))
    });
    c.bench_function("screw/task_objective_gradient_rows_6", |b| {
        b.iter(|| task_objective_gradient_rows(black_box(&rows), black_box(&chi)))
    });
    c.bench_function("screw/task_objective_gradient_twist_6", |b| {
        b.iter(|| task_objective_gradient_twist(black_box(&rows), black_box(&chi)))
    });
}
