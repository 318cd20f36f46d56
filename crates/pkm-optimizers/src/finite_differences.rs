//! The one finite-difference rule of the optimisers: every derivative that a solver of this
//! crate does not get from the problem is formed here, with steps relative to the width of each
//! variable's interval.
//!
//! The step of variable $j$ is $h_j = \epsilon\,\max(w_j, w_{\min})$, $w_j$ its interval width
//! and $w_{\min} =$ [`MIN_WIDTH`] (so a degenerate interval still gets a positive step); first
//! derivatives are central,
//! $$ \partial_j f \approx \frac{f(x^+_j) - f(x^-_j)}{x^+_j - x^-_j}, \qquad
//!    x^\pm_j = \mathrm{clamp}(x_j \pm h_j), $$
//! and therefore one-sided where a side leaves the box ([`Bounds::difference_points`]); a
//! variable fixed by equal bounds gets a zero column. Second derivatives (the reduced Hessian of
//! the Levenberg–Marquardt report) are unclamped central second differences with
//! $\epsilon =$ [`HESSIAN_RELATIVE_STEP`].
//!
//! `pkm-mechanisms`' `StewartTaskProblem` uses the same [`Bounds::difference_points`] with
//! [`RELATIVE_STEP`] for its design columns.

use pkm_traits::{Bounds, InvalidInput, ObjectiveError};

/// Default relative step $\epsilon$ of first differences ([`crate::LmSettings::fd_step`],
/// [`crate::AugmentedLagrangianSettings::fd_step`]): [`Bounds::DEFAULT_RELATIVE_STEP`].
pub const RELATIVE_STEP: f64 = Bounds::DEFAULT_RELATIVE_STEP;

/// Relative step of the central second differences, of the order of
/// $\varepsilon_{\mathrm{mach}}^{1/4} \approx 10^{-4}$, where the $O(h^2)$ truncation and the
/// $O(\varepsilon_{\mathrm{mach}}/h^2)$ rounding of a second difference balance.
pub const HESSIAN_RELATIVE_STEP: f64 = 1e-4;

/// Smallest interval width used to scale a step, so that a zero-width interval still gets a
/// positive step: [`Bounds::MIN_DIFFERENCE_WIDTH`], the floor of [`Bounds::difference_points`].
pub const MIN_WIDTH: f64 = Bounds::MIN_DIFFERENCE_WIDTH;

/// Smallest relative step $\epsilon$ accepted: one machine epsilon. Below it a step is lost in
/// the rounding of $x \pm h$ (or is a subnormal number), and a derivative column would silently
/// come out zero.
pub const MIN_RELATIVE_STEP: f64 = f64::EPSILON;

/// Checks the arguments every rule here shares: one bound per variable and a relative step
/// from [`MIN_RELATIVE_STEP`] to 1.
fn check_arguments(bounds: &[Bounds], n: usize, relative: f64) -> Result<(), ObjectiveError> {
    if bounds.len() != n {
        return Err(ObjectiveError::Dimension {
            expected: bounds.len(),
            got: n,
        });
    }
    if !((MIN_RELATIVE_STEP..=1.0).contains(&relative)) {
        return Err(InvalidInput::new(
            "relative step",
            relative,
            "must lie in [MIN_RELATIVE_STEP, 1] (f64::EPSILON to 1)",
        )
        .into());
    }
    Ok(())
}

/// The two points of a central difference of variable `k` at `x`, refused when a variable that
/// is free to move (a positive width) gets no step: `x` outside its interval or too large for
/// the step to change it.
fn difference_points(b: &Bounds, x: f64, relative: f64) -> Result<(f64, f64), ObjectiveError> {
    let (hi, lo) = b.difference_points(x, relative);
    if b.width() > 0.0 && !(hi > lo) {
        return Err(InvalidInput::new(
            "x",
            x,
            "must lie in its bounds, with a step that changes it",
        )
        .into());
    }
    Ok((hi, lo))
}

/// The step $h = \epsilon\,\max(w, w_{\min})$ of one variable (`relative` = $\epsilon$, which
/// the difference functions check; a NaN `relative` gives a NaN step, an infinite width an
/// infinite one).
///
/// # Example
/// ```
/// use pkm_optimizers::finite_differences::step;
/// use pkm_traits::Bounds;
/// let b = Bounds::new(0.0, 2.0).unwrap();
/// assert_eq!(step(&b, 1e-3), 2e-3);
/// assert_eq!(b.difference_points(1.0, 1e-3), (1.0 + step(&b, 1e-3), 1.0 - step(&b, 1e-3)));
/// ```
pub fn step(bounds: &Bounds, relative: f64) -> f64 {
    relative * bounds.width().max(MIN_WIDTH)
}

/// The central-difference gradient of `f` at `x`, given `f0 = f(x)` (a side that lands on `x`
/// itself, at a bound, reuses `f0` instead of evaluating again).
///
/// # Errors
/// [`ObjectiveError::Dimension`] unless there is one bound per variable,
/// [`ObjectiveError::InvalidInput`] for a relative step below [`MIN_RELATIVE_STEP`] or above 1
/// (or NaN), or a free variable that the step cannot move; otherwise the first error of `f`.
///
/// # Example
/// ```
/// use pkm_optimizers::finite_differences::gradient;
/// use pkm_traits::Bounds;
/// let b = [Bounds::new(-1.0, 1.0).unwrap(); 2];
/// let f = |p: &[f64]| Ok(p[0] * p[0] + 3.0 * p[1]);
/// let g = gradient(&f, &b, &[0.5, 1.0], 3.25, 1e-6).unwrap();
/// assert!((g[0] - 1.0).abs() < 1e-8 && (g[1] - 3.0).abs() < 1e-8);
/// ```
pub fn gradient<F>(
    f: &F,
    bounds: &[Bounds],
    x: &[f64],
    f0: f64,
    relative: f64,
) -> Result<Vec<f64>, ObjectiveError>
where
    F: Fn(&[f64]) -> Result<f64, ObjectiveError>,
{
    check_arguments(bounds, x.len(), relative)?;
    let mut g = vec![0.0; x.len()];
    let mut probe = x.to_vec();
    for (k, b) in bounds.iter().enumerate() {
        let (hi, lo) = difference_points(b, x[k], relative)?;
        if !(hi > lo) {
            continue;
        }
        let mut at = |v: f64| {
            probe[k] = v;
            let r = if (v - x[k]).abs() > 0.0 {
                f(&probe)
            } else {
                Ok(f0)
            };
            probe[k] = x[k];
            r
        };
        let (fp, fm) = (at(hi)?, at(lo)?);
        g[k] = (fp - fm) / (hi - lo);
    }
    Ok(g)
}

/// The central-difference Jacobian $A_{ij} = \partial r_i / \partial p_j$ of `residuals` (which
/// writes the $m$ residuals at a point into its second argument) at `p`, row-major ($m \times n$,
/// entry $(i, j)$ at `i * n + j`).
///
/// # Errors
/// As [`gradient`], with the first error of `residuals`.
///
/// # Example
/// ```
/// use pkm_optimizers::finite_differences::jacobian;
/// use pkm_traits::Bounds;
/// let b = [Bounds::new(-1.0, 1.0).unwrap(); 2];
/// let r = |p: &[f64], out: &mut [f64]| {
///     out.copy_from_slice(&[p[0] * p[1], 2.0 * p[0]]);
///     Ok(())
/// };
/// let a = jacobian(&r, &b, &[0.5, -0.25], 2, 1e-6).unwrap();
/// for (got, want) in a.iter().zip([-0.25, 0.5, 2.0, 0.0]) {
///     assert!((got - want).abs() < 1e-8);
/// }
/// ```
pub fn jacobian<R>(
    residuals: &R,
    bounds: &[Bounds],
    p: &[f64],
    m: usize,
    relative: f64,
) -> Result<Vec<f64>, ObjectiveError>
where
    R: Fn(&[f64], &mut [f64]) -> Result<(), ObjectiveError>,
{
    check_arguments(bounds, p.len(), relative)?;
    let n = p.len();
    let entries = m.checked_mul(n).ok_or_else(|| {
        ObjectiveError::from(InvalidInput::new(
            "residuals",
            m as f64,
            "m × n entries must fit in memory",
        ))
    })?;
    InvalidInput::require_within_budget("residuals", entries, size_of::<f64>())?;
    let mut a = vec![0.0; entries];
    let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
    let mut q = p.to_vec();
    for (j, b) in bounds.iter().enumerate() {
        let (hi, lo) = difference_points(b, p[j], relative)?;
        if !(hi > lo) {
            // A variable fixed by its bounds (lower = upper): its column stays zero.
            continue;
        }
        q[j] = hi;
        residuals(&q, &mut rp)?;
        q[j] = lo;
        residuals(&q, &mut rm)?;
        q[j] = p[j];
        for i in 0..m {
            a[i * n + j] = (rp[i] - rm[i]) / (hi - lo);
        }
    }
    Ok(a)
}

/// Central second differences of `f` over the variables `free` at `p`, with $f(p)$ given as
/// `f0`: $H_{kk} = (f^{+} - 2f_0 + f^{-})/h_k^2$ and
/// $H_{kl} = (f^{++} - f^{+-} - f^{-+} + f^{--})/(4h_k h_l)$, $h = $ [`step`] of each variable
/// (not clamped: the probes may leave the box by $h$). Row-major, $n_{\mathrm{free}}^2$ entries.
///
/// # Errors
/// As [`gradient`], and [`ObjectiveError::InvalidInput`] for an index of `free` that names no
/// variable or a step whose square $(2h)^2$ is not a normal number (bounds near ±1e300 or
/// ±1e-300); [`ObjectiveError::NonFinite`] for an entry that overflows; otherwise the first
/// error of `f`.
///
/// # Example
/// ```
/// use pkm_optimizers::finite_differences::{HESSIAN_RELATIVE_STEP, hessian};
/// use pkm_traits::Bounds;
/// let b = [Bounds::new(-1.0, 1.0).unwrap(); 2];
/// let f = |p: &[f64]| Ok(p[0] * p[0] * 3.0 + p[0] * p[1]);
/// let h = hessian(&f, &b, &[0.2, 0.1], &[0, 1], 0.14, HESSIAN_RELATIVE_STEP).unwrap();
/// for (got, want) in h.iter().zip([6.0, 1.0, 1.0, 0.0]) {
///     assert!((got - want).abs() < 1e-5, "{got} vs {want}");
/// }
/// ```
pub fn hessian<F>(
    f: &F,
    bounds: &[Bounds],
    p: &[f64],
    free: &[usize],
    f0: f64,
    relative: f64,
) -> Result<Vec<f64>, ObjectiveError>
where
    F: Fn(&[f64]) -> Result<f64, ObjectiveError>,
{
    check_arguments(bounds, p.len(), relative)?;
    if let Some(&j) = free.iter().find(|&&j| j >= p.len()) {
        return Err(InvalidInput::new("free", j as f64, "must name a design variable").into());
    }
    let h: Vec<f64> = free.iter().map(|&j| step(&bounds[j], relative)).collect();
    // The second differences divide by (2h)²: it must be a normal number.
    if let Some(&hk) = h.iter().find(|&&hk| !(4.0 * hk * hk).is_normal()) {
        let requirement = "(2·step)² must be a normal number: the bounds are too wide or too \
                           narrow for a second difference";
        return Err(InvalidInput::new("step", hk, requirement).into());
    }
    let f_at = |shifts: &[(usize, f64)]| {
        let mut q = p.to_vec();
        for &(k, s) in shifts {
            q[free[k]] += s * h[k];
        }
        f(&q)
    };
    let n = free.len();
    let mut hess = vec![0.0; n * n];
    for k in 0..n {
        for l in k..n {
            let v = if k == l {
                (f_at(&[(k, 1.0)])? - 2.0 * f0 + f_at(&[(k, -1.0)])?) / (h[k] * h[k])
            } else {
                (f_at(&[(k, 1.0), (l, 1.0)])?
                    - f_at(&[(k, 1.0), (l, -1.0)])?
                    - f_at(&[(k, -1.0), (l, 1.0)])?
                    + f_at(&[(k, -1.0), (l, -1.0)])?)
                    / (4.0 * h[k] * h[l])
            };
            if !v.is_finite() {
                return Err(ObjectiveError::NonFinite { value: v });
            }
            hess[k * n + l] = v;
            hess[l * n + k] = v;
        }
    }
    Ok(hess)
}
