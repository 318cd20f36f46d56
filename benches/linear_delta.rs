use criterion::Criterion;
use pkm::papers::miller2004::linear_delta::evaluation::{eta1, eta1_by_grid, eta2};
use std::hint::black_box;

/// The row-4 optimum of Table 2.
const DESIGN: [f64; 4] = [2.0, 0.0, 0.0, 0.63];

pub(crate) fn eta_of_one_design(c: &mut Criterion) {
    let mut group = c.benchmark_group("miller2004/linear_delta");
    group.sample_size(10);
    group.bench_function("eta1_quadrature_24", |b| {
        b.iter(|| eta1(black_box(&DESIGN), 24))
    });
    group.bench_function("eta1_quadrature_16", |b| {
        b.iter(|| eta1(black_box(&DESIGN), 16))
    });
    group.bench_function("eta1_paper_grid", |b| {
        b.iter(|| eta1_by_grid(black_box(&DESIGN)))
    });
    group.bench_function("eta2", |b| b.iter(|| eta2(black_box(&DESIGN))));
    group.finish();
}
