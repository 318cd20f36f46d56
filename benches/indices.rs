use criterion::Criterion;
use nalgebra::Matrix3;
use std::hint::black_box;

/// $1/\kappa$ of the spec's test-vector Jacobian (Stamper design (.44, .56, 0, 0, 120, 240) at
/// P = (0.1, −0.05, 0.5)): the SVD route and the closed form of the hot loops.
pub(crate) fn condition_number(c: &mut Criterion) {
    let j = Matrix3::new(1.58, -0.23, 2.09, 1.38, -1.80, 1.35, 1.48, 1.48, 1.69);
    c.bench_function("indices/inverse_condition_number_svd_3x3", |b| {
        b.iter(|| pkm::workspace_indices::inverse_condition_number(black_box(&j)))
    });
    c.bench_function("indices/inverse_condition_number_3x3_closed_form", |b| {
        b.iter(|| pkm::workspace_indices::inverse_condition_number_3x3(black_box(&j)))
    });
}
