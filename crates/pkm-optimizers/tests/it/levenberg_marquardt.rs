//! Bounded Levenberg–Marquardt: optima on bounds, KKT report, thread-count invariance.
#![allow(clippy::unwrap_used)]

use pkm_optimizers::{
    ActiveBound, LmSettings, Multistart, Sense, Termination, levenberg_marquardt,
    multistart_levenberg_marquardt,
};
use pkm_traits::{Bounds, Objective, ObjectiveError, Residuals, Silent};

/// $r = (p_0 - 1,\; 2 (p_1 + 0.5),\; p_0 p_1)$ on $[-2, 3] \times [-1, 1]$.
struct Quadratic([Bounds; 2]);

impl Objective for Quadratic {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0; 3];
        self.residuals(p, &mut r)?;
        Ok(r.iter().map(|x| x * x).sum())
    }
}

impl Residuals for Quadratic {
    fn n_residuals(&self) -> usize {
        3
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        r.copy_from_slice(&[p[0] - 1.0, 2.0 * (p[1] + 0.5), p[0] * p[1]]);
        Ok(())
    }
}

fn problem() -> Quadratic {
    Quadratic([
        Bounds::new(-2.0, 3.0).unwrap(),
        Bounds::new(-1.0, 1.0).unwrap(),
    ])
}

fn best(sense: Sense, seed: u64) -> pkm_optimizers::LocalOptimum {
    let starts = Multistart::new(16, seed);
    multistart_levenberg_marquardt(&problem(), sense, &starts, &LmSettings::default(), &Silent)
        .unwrap()
        .best
}

#[test]
fn maximum_sits_on_a_corner_with_every_bound_active() {
    // Corners: (3, 1): 4 + 9 + 9 = 22; (-2, 1): 9 + 9 + 4 = 22; (3, -1): 4 + 1 + 9 = 14.
    let max = best(Sense::Maximise, 1);
    assert!((max.value - 22.0).abs() < 1e-9, "{}", max.value);
    assert!(max.active.iter().all(|a| *a != ActiveBound::Free));
    assert!(max.reduced_hessian_eigenvalues.is_empty());
}

#[test]
fn interior_minimum_has_zero_gradient_and_positive_hessian() {
    let min = best(Sense::Minimise, 1);
    assert!(min.free_gradient_norm() < 1e-6, "{:?}", min.gradient);
    assert!(!min.reduced_hessian_eigenvalues.is_empty());
    assert!(min.reduced_hessian_eigenvalues.iter().all(|e| *e > 0.0));
}

#[test]
fn result_is_identical_for_1_and_2_threads() {
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| best(Sense::Maximise, 9))
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.value.to_bits(), b.value.to_bits());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.design), bits(&b.design));
}

/// Rosenbrock's residuals $r = (10 (p_1 - p_0^2),\; 1 - p_0)$ on $[-2, 2]^2$, with the analytic
/// Jacobian optional; counts residual evaluations.
struct Rosenbrock {
    bounds: [Bounds; 2],
    analytic: bool,
    evaluations: std::sync::atomic::AtomicUsize,
}

impl Rosenbrock {
    fn new(analytic: bool) -> Self {
        let b = Bounds::new(-2.0, 2.0).unwrap();
        Self {
            bounds: [b, b],
            analytic,
            evaluations: std::sync::atomic::AtomicUsize::new(0),
        }
    }
}

impl Objective for Rosenbrock {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0; 2];
        self.residuals(p, &mut r)?;
        Ok(r.iter().map(|x| x * x).sum())
    }
}

impl Residuals for Rosenbrock {
    fn n_residuals(&self) -> usize {
        2
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        self.evaluations
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        r.copy_from_slice(&[10.0 * (p[1] - p[0] * p[0]), 1.0 - p[0]]);
        Ok(())
    }
    fn residual_jacobian(
        &self,
        p: &[f64],
        r: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, ObjectiveError> {
        if !self.analytic {
            return Ok(false);
        }
        self.residuals(p, r)?;
        jacobian.copy_from_slice(&[-20.0 * p[0], 10.0, -1.0, 0.0]);
        Ok(true)
    }
}

#[test]
fn analytic_jacobian_reaches_the_same_optimum_as_finite_differences() {
    let run = |analytic, sense| {
        let problem = Rosenbrock::new(analytic);
        let starts =
            Multistart::new(8, 3).with_extra_starts(vec![vec![-1.2, 1.0], vec![1.5, -1.5]]);
        let optimum = multistart_levenberg_marquardt(
            &problem,
            sense,
            &starts,
            &LmSettings::default(),
            &Silent,
        )
        .unwrap()
        .best;
        (optimum, problem.evaluations.into_inner())
    };
    let ((fd_min, fd_calls), (an_min, an_calls)) =
        (run(false, Sense::Minimise), run(true, Sense::Minimise));
    assert!(
        fd_min.value < 1e-12 && an_min.value < 1e-12,
        "{fd_min:?} {an_min:?}"
    );
    for (a, b) in an_min.design.iter().zip(&fd_min.design) {
        assert!((a - 1.0).abs() < 1e-6 && (b - 1.0).abs() < 1e-6, "{a} {b}");
    }
    assert!(an_min.free_gradient_norm() < 1e-6, "{:?}", an_min.gradient);
    assert!(an_calls < fd_calls, "{an_calls} vs {fd_calls}");
    // Maximum on the corner (-2, -2): r = (-60, 3), f = 3609.
    let ((fd_max, _), (an_max, _)) = (run(false, Sense::Maximise), run(true, Sense::Maximise));
    assert!((fd_max.value - 3609.0).abs() < 1e-9, "{}", fd_max.value);
    assert_eq!(an_max.value.to_bits(), fd_max.value.to_bits());
    assert_eq!(an_max.design, fd_max.design);
    assert_eq!(an_max.active, fd_max.active);
}

#[test]
fn a_variable_fixed_by_equal_bounds_stays_put_and_reports_finite_numbers() {
    let fixed = Quadratic([
        Bounds::new(-2.0, 3.0).unwrap(),
        Bounds::new(0.25, 0.25).unwrap(),
    ]);
    let starts = Multistart::new(8, 3);
    let settings = LmSettings::default();
    let min = multistart_levenberg_marquardt(&fixed, Sense::Minimise, &starts, &settings, &Silent)
        .unwrap()
        .best;
    // r = (p0 - 1, 1.5, 0.25 p0): minimum of (p0 - 1)² + p0²/16 at p0 = 16/17.
    assert!(
        (min.design[0] - 16.0 / 17.0).abs() < 1e-6,
        "{:?}",
        min.design
    );
    assert!((min.design[1] - 0.25).abs() < 1e-15);
    assert!(
        min.gradient.iter().all(|g| g.is_finite()),
        "{:?}",
        min.gradient
    );
    assert!(
        min.reduced_hessian_eigenvalues
            .iter()
            .all(|e| e.is_finite())
    );
}

#[test]
fn termination_tells_convergence_from_the_iteration_limit() {
    let problem = Rosenbrock::new(true);
    let start = [-1.2, 1.0];
    let converged = levenberg_marquardt(
        &problem,
        Sense::Minimise,
        &start,
        &LmSettings::default(),
        &Silent,
    )
    .unwrap();
    assert!(converged.termination.converged(), "{converged:?}");
    assert!(converged.iterations < LmSettings::default().max_iterations);
    let one = LmSettings {
        max_iterations: 1,
        ..LmSettings::default()
    };
    let cut = levenberg_marquardt(&problem, Sense::Minimise, &start, &one, &Silent).unwrap();
    assert_eq!(cut.termination, Termination::MaxIterations, "{cut:?}");
    assert_eq!(cut.iterations, 1);
    assert_eq!(cut.termination.to_string(), "iteration limit reached");
    assert!(
        cut.value > 1e-6,
        "one step from (-1.2, 1) is far from the minimum"
    );
    // A maximum on a corner is a KKT point with every variable held on its bound.
    let corner = levenberg_marquardt(
        &problem,
        Sense::Maximise,
        &[-2.0, -2.0],
        &LmSettings::default(),
        &Silent,
    )
    .unwrap();
    assert_eq!(
        corner.termination,
        Termination::Converged {
            criterion: "every variable held on a bound"
        },
        "{corner:?}"
    );
}

/// $r(p) = 1 + p + 2|p - s|$ on $[-1, 1]$ with $s = 0.3$: the central-difference slope at $s$
/// is 1, so the gradient asks to decrease $p$, yet every move raises $r > 0$ (the kink's slopes
/// are $-1$ and $3$), so no step ever improves $f = r^2$.
struct Kink([Bounds; 1]);

const KINK: f64 = 0.3;

impl Objective for Kink {
    fn dimension(&self) -> usize {
        1
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0];
        self.residuals(p, &mut r)?;
        Ok(r[0] * r[0])
    }
}

impl Residuals for Kink {
    fn n_residuals(&self) -> usize {
        1
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        r[0] = 1.0 + p[0] + 2.0 * (p[0] - KINK).abs();
        Ok(())
    }
}

#[test]
fn an_objective_that_never_improves_reports_a_stall() {
    let problem = Kink([Bounds::new(-1.0, 1.0).unwrap()]);
    let stalled = levenberg_marquardt(
        &problem,
        Sense::Minimise,
        &[KINK],
        &LmSettings::default(),
        &Silent,
    )
    .unwrap();
    assert_eq!(stalled.termination, Termination::Stalled, "{stalled:?}");
    assert_eq!(stalled.iterations, 1);
    assert!(stalled.free_gradient_norm() > 1.0, "{stalled:?}");
    assert!((stalled.design[0] - KINK).abs() < 1e-15);
    assert_eq!(
        stalled.termination.to_string(),
        "stalled (no improving step)"
    );
}

proptest::proptest! {
    /// The reported reason agrees with the counts and the KKT report: the iteration limit is
    /// reported exactly when every allowed iteration ran without a convergence test being met,
    /// and a projected-gradient stop leaves a free gradient below the tolerance.
    #[test]
    fn termination_agrees_with_iterations_and_gradient(
        x in -2.0..2.0f64, y in -2.0..2.0f64, max_iterations in 1..40usize, analytic in proptest::bool::ANY,
        at_minimum in proptest::bool::ANY,
    ) {
        let problem = Rosenbrock::new(analytic);
        let settings = LmSettings { max_iterations, ..LmSettings::default() };
        // From the minimiser (1, 1), where r = 0, the projected-gradient test stops the first
        // iteration; elsewhere the projected gradient or the relative change in f stops it.
        let start = if at_minimum { [1.0, 1.0] } else { [x, y] };
        let o = levenberg_marquardt(&problem, Sense::Minimise, &start, &settings, &Silent).unwrap();
        proptest::prop_assert!(o.iterations <= max_iterations, "{o:?}");
        if o.termination == Termination::MaxIterations {
            proptest::prop_assert_eq!(o.iterations, max_iterations);
        } else {
            proptest::prop_assert!(o.iterations >= 1, "{o:?}");
        }
        if at_minimum {
            proptest::prop_assert_eq!(o.termination, Termination::Converged { criterion: "projected gradient" });
            proptest::prop_assert_eq!(o.iterations, 1);
        }
        if o.termination == (Termination::Converged { criterion: "projected gradient" }) {
            // Both widths are 4, the default scales; the test scales each gradient entry by it.
            let scaled = 4.0 * o.free_gradient_norm();
            proptest::prop_assert!(scaled <= settings.gradient_tolerance * (1.0 + o.value), "{o:?}");
        }
    }
}
