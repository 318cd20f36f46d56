//! Wolf & Shoham §4.1: F of the pose problem at the paper's pose (value and residuals), its
//! gradient as the optimiser computes it (analytic residual Jacobian) and by the optimiser's
//! finite-difference fallback, and one full-mode §4.1 multistart optimisation.

use criterion::Criterion;
use pkm::papers::wolf2006::{maximise_pose, section_4_1_problem};
use pkm::papers::{ExperimentError, Mode};
use pkm::traits::{Objective, ObjectiveError, Residuals};
use std::hint::black_box;

/// The paper's λ = 1 pose in the problem's variables $(p, u)$: $p = (-10, -10, 50)$ cm,
/// $w = -13.5° \cdot z$, i.e. $u = (0, 0, -13.5/30)$ (the cube-to-ball map is the identity on
/// the axes).
const PAPER_POSE: [f64; 6] = [-10.0, -10.0, 50.0, 0.0, 0.0, -13.5 / 30.0];

/// $\nabla F = 2 A^\top r$ with $A$ from central differences of the residuals, step
/// $10^{-6}$ of each interval width clamped into the box: the fallback rule of
/// `pkm_optimizers::levenberg_marquardt` for problems without `Residuals::residual_jacobian`
/// (its `residuals_and_jacobian`, private there; `LmSettings::default().fd_step`), one residual
/// evaluation plus two per variable. Kept as the reference the analytic gradient replaces.
fn fd_gradient<P: Residuals>(
    problem: &P,
    p: &[f64],
    gradient: &mut [f64],
) -> Result<(), ObjectiveError> {
    let rel = pkm::optimizers::LmSettings::default().fd_step;
    let (mut r, mut rp, mut rm) = ([0.0; 6], [0.0; 6], [0.0; 6]);
    problem.residuals(p, &mut r)?;
    let mut q = [0.0; 6];
    q.copy_from_slice(p);
    for (j, b) in problem.bounds().iter().enumerate() {
        let (hi, lo) = b.difference_points(p[j], rel);
        q[j] = hi;
        problem.residuals(&q, &mut rp)?;
        q[j] = lo;
        problem.residuals(&q, &mut rm)?;
        q[j] = p[j];
        gradient[j] = (0..6)
            .map(|i| 2.0 * r[i] * (rp[i] - rm[i]) / (hi - lo))
            .sum();
    }
    Ok(())
}

/// $\nabla F = 2 A^\top r$ with $A$ from `Residuals::residual_jacobian` (analytic in $(p, u)$),
/// as `levenberg_marquardt` computes it for this problem; returns $F$.
fn analytic_gradient<P: Residuals>(
    problem: &P,
    p: &[f64],
    gradient: &mut [f64],
) -> Result<f64, ObjectiveError> {
    let (mut r, mut a) = ([0.0; 6], [0.0; 36]);
    if !problem.residual_jacobian(p, &mut r, &mut a)? {
        return Err(ObjectiveError::infeasible("no analytic Jacobian"));
    }
    for (j, g) in gradient.iter_mut().enumerate() {
        *g = (0..6).map(|i| 2.0 * a[i * 6 + j] * r[i]).sum();
    }
    Ok(r.iter().map(|x| x * x).sum())
}

pub(crate) fn section_4_1(c: &mut Criterion) {
    let Ok(problem) = section_4_1_problem(1.0) else {
        return;
    };
    assert_eq!(problem.dimension(), PAPER_POSE.len());
    let mut group = c.benchmark_group("wolf/s4_1");
    group.bench_function("F_value_at_paper_pose", |b| {
        b.iter(|| problem.value(black_box(&PAPER_POSE)))
    });
    group.bench_function("F_residuals_at_paper_pose", |b| {
        let mut r = [0.0; 6];
        b.iter(|| {
            problem
                .residuals(black_box(&PAPER_POSE), &mut r)
                .map(|()| r[0])
        })
    });
    group.bench_function("F_gradient_analytic", |b| {
        let mut g = [0.0; 6];
        b.iter(|| analytic_gradient(&problem, black_box(&PAPER_POSE), &mut g).map(|f| f + g[0]))
    });
    group.bench_function("F_gradient_fd_fallback", |b| {
        let mut g = [0.0; 6];
        b.iter(|| fd_gradient(&problem, black_box(&PAPER_POSE), &mut g).map(|()| g[0]))
    });
    group.finish();

    let mut group = c.benchmark_group("wolf/s4_1_multistart");
    group.sample_size(10);
    group.bench_function("full_mode_64_starts", |b| {
        b.iter(|| -> Result<f64, ExperimentError> {
            Ok(maximise_pose(black_box(&problem), Mode::Full)?.value)
        })
    });
    group.finish();
}
