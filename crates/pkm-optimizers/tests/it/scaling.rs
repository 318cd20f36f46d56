//! Issue 20 ("solver quality"): problems of known optimum whose variables differ by 10⁶ in
//! scale (one near 10⁻³, one near 10³), solved from seeded uniform starts in the box.
//! Each solver, with its default scaling by the bounds, reaches the known optimum at the stated
//! tolerance and says why it stopped; with a scale of ones (the unscaled iteration, bit for bit)
//! the same runs fail, which the `*_without_scaling_*` tests pin down.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_optimizers::{
    AugmentedLagrangianSettings, CharacteristicScale, ConstrainedResult, LmSettings, LocalOptimum,
    Sense, Termination, augmented_lagrangian, levenberg_marquardt, uniform_start_points,
};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Residuals, Silent};

/// Starts per problem.
const STARTS: usize = 12;
/// Seed of the starts.
const SEED: u64 = 20;

fn bounds(pairs: [(f64, f64); 2]) -> [Bounds; 2] {
    pairs.map(|(l, u)| Bounds::new(l, u).unwrap())
}

fn ones() -> Option<CharacteristicScale> {
    Some(CharacteristicScale::new(&[1.0, 1.0]).unwrap())
}

fn relative_error(x: &[f64], expected: &[f64]) -> f64 {
    x.iter()
        .zip(expected)
        .map(|(a, b)| ((a - b) / b).abs())
        .fold(0.0, f64::max)
}

/// Rosenbrock in $u = x / 10^{-3}$, $v = y / 10^3$: residuals $(1 - u, 10 (v - u^2))$,
/// optimum $(x, y) = (10^{-3}, 10^3)$ with $f = 0$.
struct ScaledRosenbrock([Bounds; 2]);

impl Objective for ScaledRosenbrock {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0; 2];
        self.residuals(p, &mut r)?;
        Ok(r[0] * r[0] + r[1] * r[1])
    }
}

impl Residuals for ScaledRosenbrock {
    fn n_residuals(&self) -> usize {
        2
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        let (u, v) = (p[0] / 1e-3, p[1] / 1e3);
        r[0] = 1.0 - u;
        r[1] = 10.0 * (v - u * u);
        Ok(())
    }
}

/// The saturation curve $y(t) = p_2 (1 - e^{-p_1 t})$ fitted to its own exact values $y_i$ at
/// $t = 0, 150, \dots, 3000$ s, residuals relative to the data's plateau $10^3$
/// ($r_i = (y(t_i) - y_i) / 10^3$): optimum $p = (10^{-3}\,\mathrm{s}^{-1}, 10^3)$ with $f = 0$.
struct SaturationFit([Bounds; 2]);

const TRUE_FIT: [f64; 2] = [1e-3, 1e3];

fn saturation(p: &[f64], t: f64) -> f64 {
    p[1] * (1.0 - (-p[0] * t).exp())
}

impl Objective for SaturationFit {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0; 21];
        self.residuals(p, &mut r)?;
        Ok(r.iter().map(|x| x * x).sum())
    }
}

impl Residuals for SaturationFit {
    fn n_residuals(&self) -> usize {
        21
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        for (i, ri) in r.iter_mut().enumerate() {
            let t = 150.0 * i as f64;
            *ri = (saturation(p, t) - saturation(&TRUE_FIT, t)) / 1e3;
        }
        Ok(())
    }
}

/// A coupled quadratic with one active bound: residuals $(u - 2 + v/2,\ v - 2/5)$ with
/// $u = x / 10^{-3} \in [-1, 1]$ and $v = (y - 500) / 10^3$. The minimum over the box has $u$
/// on its upper bound ($\partial_u f = 2 r_1 < 0$ there): with $u = 1$,
/// $f = (v/2 - 1)^2 + (v - 2/5)^2$, $\partial_v f = \tfrac52 v - \tfrac95 = 0$ gives
/// $v = 18/25$, so $(x, y) = (10^{-3}, 1220)$ and $f = (16/25)^2 + (8/25)^2 = 64/125$.
struct ActiveBoundQuadratic([Bounds; 2]);

const QUADRATIC_OPTIMUM: [f64; 2] = [1e-3, 1220.0];

impl Objective for ActiveBoundQuadratic {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0; 2];
        self.residuals(p, &mut r)?;
        Ok(r[0] * r[0] + r[1] * r[1])
    }
}

impl Residuals for ActiveBoundQuadratic {
    fn n_residuals(&self) -> usize {
        2
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        let (u, v) = (p[0] / 1e-3, (p[1] - 500.0) / 1e3);
        r[0] = u - 2.0 + 0.5 * v;
        r[1] = v - 0.4;
        Ok(())
    }
}

impl Constraints for ActiveBoundQuadratic {
    fn n_constraints(&self) -> usize {
        0
    }
    fn inequalities(&self, _: &[f64], _: &mut [f64]) -> Result<(), ObjectiveError> {
        Ok(())
    }
}

/// $\min u^2 + v^2$ subject to $u v \ge 1$ ($g = 1 - u v \le 0$, active), $u = x / 10^{-3}$,
/// $v = y / 10^3$: optimum $(x, y) = (10^{-3}, 10^3)$, $f = 2$, multiplier $\mu = 2$
/// (from $\nabla f + \mu \nabla g = (2u - \mu v, 2v - \mu u) = 0$ at $u = v = 1$).
struct HyperbolaProblem([Bounds; 2]);

impl Objective for HyperbolaProblem {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let (u, v) = (p[0] / 1e-3, p[1] / 1e3);
        Ok(u * u + v * v)
    }
}

impl Constraints for HyperbolaProblem {
    fn n_constraints(&self) -> usize {
        1
    }
    fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        g[0] = 1.0 - (p[0] / 1e-3) * (p[1] / 1e3);
        Ok(())
    }
}

fn rosenbrock() -> ScaledRosenbrock {
    ScaledRosenbrock(bounds([(-1.5e-3, 2e-3), (-1e3, 3e3)]))
}

fn fit() -> SaturationFit {
    SaturationFit(bounds([(1e-4, 1e-2), (1e2, 1e4)]))
}

fn quadratic() -> ActiveBoundQuadratic {
    ActiveBoundQuadratic(bounds([(-1e-3, 1e-3), (0.0, 3e3)]))
}

fn hyperbola() -> HyperbolaProblem {
    HyperbolaProblem(bounds([(1e-4, 3e-3), (1e2, 3e3)]))
}

fn lm_runs<P: Residuals>(problem: &P, settings: &LmSettings) -> Vec<LocalOptimum> {
    uniform_start_points(problem.bounds(), STARTS, SEED)
        .unwrap()
        .iter()
        .map(|s| levenberg_marquardt(problem, Sense::Minimise, s, settings, &Silent).unwrap())
        .collect()
}

fn al_runs<P: Constraints>(
    problem: &P,
    settings: &AugmentedLagrangianSettings,
) -> Vec<Result<ConstrainedResult, pkm_optimizers::OptimizeError>> {
    uniform_start_points(problem.bounds(), STARTS, SEED)
        .unwrap()
        .iter()
        .map(|s| augmented_lagrangian(problem, Sense::Minimise, s, settings, &Silent))
        .collect()
}

const PROJECTED_GRADIENT: Termination = Termination::Converged {
    criterion: "projected gradient",
};

/// Whether an LM run found `optimum` to `tolerance` (relative, per variable) and said it
/// converged.
fn lm_found(run: &LocalOptimum, optimum: &[f64], tolerance: f64) -> bool {
    run.termination.converged() && relative_error(&run.design, optimum) < tolerance
}

#[test]
fn levenberg_marquardt_solves_the_scaled_rosenbrock_from_every_start() {
    // A scaled gradient of 1e-6 in a valley whose Hessian has eigenvalues 0.4 and 1e3 in
    // (u, v): the design to about 1e-6.
    for run in lm_runs(&rosenbrock(), &LmSettings::default()) {
        assert!(lm_found(&run, &[1e-3, 1e3], 1e-5), "{run:?}");
        assert_eq!(run.termination, PROJECTED_GRADIENT, "{run:?}");
    }
}

#[test]
fn levenberg_marquardt_fits_parameters_1e_minus_3_and_1e3_and_stops_on_the_projected_gradient() {
    // Stopped at a scaled gradient of 1e-6 (f about 1e-15): the parameters to 1e-6.
    for run in lm_runs(&fit(), &LmSettings::default()) {
        assert!(lm_found(&run, &TRUE_FIT, 1e-6), "{run:?}");
        assert_eq!(run.termination, PROJECTED_GRADIENT, "{run:?}");
    }
}

#[test]
fn levenberg_marquardt_holds_the_active_bound_of_the_quadratic() {
    for run in lm_runs(&quadratic(), &LmSettings::default()) {
        assert!(lm_found(&run, &QUADRATIC_OPTIMUM, 1e-8), "{run:?}");
        assert!((run.value - 0.512).abs() < 1e-12, "{run:?}");
        assert_eq!(run.termination, PROJECTED_GRADIENT, "{run:?}");
    }
}

#[test]
fn levenberg_marquardt_without_scaling_misses_the_optima() {
    let unscaled = LmSettings {
        scale: ones(),
        ..LmSettings::default()
    };
    let missed = |runs: Vec<LocalOptimum>, optimum: &[f64], tolerance: f64| {
        runs.iter()
            .filter(|r| r.termination != PROJECTED_GRADIENT || !lm_found(r, optimum, tolerance))
            .count()
    };
    let rosenbrock = missed(lm_runs(&rosenbrock(), &unscaled), &[1e-3, 1e3], 1e-5);
    let fit = missed(lm_runs(&fit(), &unscaled), &TRUE_FIT, 1e-6);
    let quadratic = missed(lm_runs(&quadratic(), &unscaled), &QUADRATIC_OPTIMUM, 1e-8);
    eprintln!("unscaled LM: missed {rosenbrock}, {fit}, {quadratic} of {STARTS} starts");
    assert!(
        rosenbrock + fit + quadratic >= STARTS,
        "{rosenbrock} {fit} {quadratic}"
    );
}

#[test]
fn augmented_lagrangian_finds_the_active_nonlinear_constraint() {
    for run in al_runs(&hyperbola(), &AugmentedLagrangianSettings::default()) {
        let run = run.unwrap();
        assert!(relative_error(&run.design, &[1e-3, 1e3]) < 1e-4, "{run:?}");
        assert!((run.multipliers[0] - 2.0).abs() < 1e-3, "{run:?}");
        assert_eq!(
            run.termination,
            Termination::Converged {
                criterion: "feasible with settled multipliers"
            }
        );
    }
}

#[test]
fn spectral_projected_gradient_holds_the_active_bound_of_the_quadratic() {
    for run in al_runs(&quadratic(), &AugmentedLagrangianSettings::default()) {
        let run = run.unwrap();
        assert!(
            relative_error(&run.design, &QUADRATIC_OPTIMUM) < 1e-6,
            "{run:?}"
        );
        assert!(run.termination.converged(), "{run:?}");
    }
}

#[test]
fn augmented_lagrangian_without_scaling_misses_the_optima() {
    let unscaled = AugmentedLagrangianSettings {
        scale: ones(),
        ..AugmentedLagrangianSettings::default()
    };
    let missed = |runs: Vec<Result<ConstrainedResult, _>>, optimum: &[f64], tolerance: f64| {
        runs.iter()
            .filter(|r| {
                !r.as_ref()
                    .is_ok_and(|r| relative_error(&r.design, optimum) < tolerance)
            })
            .count()
    };
    let hyperbola = missed(al_runs(&hyperbola(), &unscaled), &[1e-3, 1e3], 1e-4);
    let quadratic = missed(al_runs(&quadratic(), &unscaled), &QUADRATIC_OPTIMUM, 1e-6);
    eprintln!("unscaled AL: missed {hyperbola}, {quadratic} of {STARTS} starts");
    assert!(hyperbola + quadratic >= STARTS, "{hyperbola} {quadratic}");
}

#[test]
fn a_scale_of_the_wrong_length_is_refused() {
    let three = Some(CharacteristicScale::new(&[1.0, 1.0, 1.0]).unwrap());
    let lm = LmSettings {
        scale: three.clone(),
        ..LmSettings::default()
    };
    let e = levenberg_marquardt(&fit(), Sense::Minimise, &[1e-3, 1e3], &lm, &Silent).unwrap_err();
    assert!(e.to_string().contains("scale.len() = 3"), "{e}");
    let al = AugmentedLagrangianSettings {
        scale: three,
        ..AugmentedLagrangianSettings::default()
    };
    let e = augmented_lagrangian(&hyperbola(), Sense::Minimise, &[1e-3, 1e3], &al, &Silent)
        .unwrap_err();
    assert!(e.to_string().contains("scale.len() = 3"), "{e}");
}

#[test]
fn a_user_scale_is_as_good_as_the_bounds() {
    let lm = LmSettings {
        scale: Some(CharacteristicScale::new(&[1e-3, 1e3]).unwrap()),
        ..LmSettings::default()
    };
    // The gradient test is now in units of these scales (10 times smaller than the box
    // widths for p_1, so the stop is looser): the parameters to 1e-5.
    for run in lm_runs(&fit(), &lm) {
        assert!(lm_found(&run, &TRUE_FIT, 1e-5), "{run:?}");
        assert_eq!(run.termination, PROJECTED_GRADIENT, "{run:?}");
    }
}

/// A reach $r \in [0, 2.5]$ under the limit $r \le 1$ and an angle $\theta \in [0°, 360°]$:
/// maximise $f = r^3 (1 + 0.1 \cos 3\theta)$, local maxima at $r = 1$, $\theta = 0°, 120°,
/// 240°, 360°$, each with the multiplier $\mu = \partial f / \partial r = 3 \cdot 1.1$. Like
/// Stamper's volume ($\propto R^3$) across its reach limit, $f$ grows faster than any quadratic
/// penalty beyond the constraint.
struct CubicReach([Bounds; 2]);

impl Objective for CubicReach {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        Ok(p[0].powi(3) * (1.0 + 0.1 * (3.0 * p[1].to_radians()).cos()))
    }
}

impl Constraints for CubicReach {
    fn n_constraints(&self) -> usize {
        1
    }
    fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        g[0] = p[0] - 1.0;
        Ok(())
    }
}

#[test]
fn augmented_lagrangian_keeps_the_basin_of_its_start_beyond_a_cubic_reach_limit() {
    // A fixed first penalty (10) sent the first subproblem to r = 2.5, where the scaled steps
    // carried θ into another basin (θ = 100° ended at 0°; issue 20: Stamper's antiparallel legs
    // lost). A penalty that kept growing once feasible (Stamper's settings) let the multiplier
    // drift from 3.3 (3.26 after 20 outer iterations from θ = 100°).
    let problem = CubicReach(bounds([(0.0, 2.5), (0.0, 360.0)]));
    let precise = AugmentedLagrangianSettings {
        fd_step: 1e-6,
        ..AugmentedLagrangianSettings::default()
    };
    // Stamper's settings (src/papers/stamper1997/optima.rs, full mode).
    let stamper = AugmentedLagrangianSettings {
        fd_step: 1e-3,
        tolerance: 1e-6,
        feasibility: 1e-4,
        max_outer: 20,
        max_inner: 200,
        scale: None,
    };
    let starts = [
        (100.0, 120.0),
        (140.0, 120.0),
        (215.0, 240.0),
        (265.0, 240.0),
    ];
    for (settings, (start, basin)) in [precise, stamper]
        .into_iter()
        .flat_map(|s| starts.map(|st| (s.clone(), st)))
    {
        let r = augmented_lagrangian(&problem, Sense::Maximise, &[1.0, start], &settings, &Silent)
            .unwrap();
        assert!(
            (r.design[0] - 1.0).abs() < 1e-4 && (r.design[1] - basin).abs() < 0.1,
            "from θ = {start}: {r:?}"
        );
        assert!(
            (r.multipliers[0] - 3.3).abs() < 1e-2,
            "from θ = {start}: {r:?}"
        );
    }
}

/// Forty residuals $r_j = x_j / c_j - 1$ with $c_j$ alternating between $10^{-3}$ and $10^3$,
/// in a box $[c_j / 2, 2 c_j]$: optimum $x = c$ with $f = 0$.
struct ManyScales(Vec<Bounds>, Vec<f64>);

impl ManyScales {
    fn new(n: usize) -> Self {
        let c: Vec<f64> = (0..n)
            .map(|j| if j % 2 == 0 { 1e-3 } else { 1e3 })
            .collect();
        let b = c.iter().map(|c| Bounds::new(c / 2.0, 2.0 * c).unwrap());
        Self(b.collect(), c)
    }
}

impl Objective for ManyScales {
    fn dimension(&self) -> usize {
        self.1.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = vec![0.0; self.1.len()];
        self.residuals(p, &mut r)?;
        Ok(r.iter().map(|v| v * v).sum())
    }
}

impl Residuals for ManyScales {
    fn n_residuals(&self) -> usize {
        self.1.len()
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        for ((r, x), c) in r.iter_mut().zip(p).zip(&self.1) {
            *r = x / c - 1.0;
        }
        Ok(())
    }
}

#[test]
fn a_user_scale_holds_any_number_of_variables() {
    // 40 variables, past the 32 of the scale's former inline storage.
    let problem = ManyScales::new(40);
    let settings = LmSettings {
        scale: Some(CharacteristicScale::new(&problem.1).unwrap()),
        ..LmSettings::default()
    };
    let start: Vec<f64> = problem.1.iter().map(|c| 1.7 * c).collect();
    let r = levenberg_marquardt(&problem, Sense::Minimise, &start, &settings, &Silent).unwrap();
    // The projected-gradient stop: in units of the scale, ∂f/∂z_j = 2 r_j ≤ 1e-6, so each
    // relative error is at most 5e-7.
    assert!(relative_error(&r.design, &problem.1) <= 5e-7, "{r:?}");
    assert!(r.termination.converged(), "{:?}", r.termination);
}
