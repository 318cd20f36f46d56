use criterion::Criterion;
use pkm::papers::miller2004::linear_delta::evaluation::{
    eta1, eta1_by_grid, eta2, inverse_condition, linear_delta,
};
use pkm::workspace_indices::mean_by_quadrature;
use pkm_traits::ObjectiveError;
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
    // The scalar path the batched η1 replaced (one Jacobian and one trigonometric 1/κ per node),
    // same design, rule and region: the before/after of docs/performance.md.
    let scalar_eta1 = |n| -> Result<f64, ObjectiveError> {
        let delta = linear_delta(black_box(&DESIGN))?;
        mean_by_quadrature(
            &delta.cross_section(),
            |y, z| inverse_condition(&delta, y, z),
            n,
        )
        .map_err(|e| ObjectiveError::infeasible(e.to_string()))
    };
    group.bench_function("eta1_quadrature_24_scalar", |b| b.iter(|| scalar_eta1(24)));
    group.bench_function("eta1_quadrature_16_scalar", |b| b.iter(|| scalar_eta1(16)));
    group.bench_function("eta1_paper_grid", |b| {
        b.iter(|| eta1_by_grid(black_box(&DESIGN)))
    });
    group.bench_function("eta2", |b| b.iter(|| eta2(black_box(&DESIGN))));
    // One full design evaluation, η = η1 + η2 (w1 = w2 = 1), by each η1 rule of the search:
    // the designs-per-second figure of docs/performance.md.
    for (name, n) in [("eta_quadrature_16", 16), ("eta_quadrature_24", 24)] {
        group.bench_function(name, |b| {
            b.iter(|| -> Result<f64, ObjectiveError> {
                let design = black_box(&DESIGN);
                Ok(eta1(design, n)? + eta2(design)?)
            })
        });
    }
    group.bench_function("eta_paper_grid", |b| {
        b.iter(|| -> Result<f64, ObjectiveError> {
            let design = black_box(&DESIGN);
            Ok(eta1_by_grid(design)?.mean + eta2(design)?)
        })
    });
    group.finish();
}
