//! Paden–Kahan subproblems 1 and 2 (Murray, Li & Sastry 1994, §3.3.2) for rotations about
//! axes through one point: the angles that turn one vector onto another.
//!
//! Subproblem 2: with unit axes $\omega_1, \omega_2$ (not parallel), the angles with
//! $e^{[\omega_1]\alpha} e^{[\omega_2]\beta} u = v$ go through the point
//! $z = e^{[\omega_2]\beta} u = e^{-[\omega_1]\alpha} v$,
//! $$z = \lambda\omega_1 + \mu\omega_2 \pm \gamma\,\omega_1\times\omega_2,\quad
//! \lambda = \frac{(\omega_1\cdot\omega_2)(\omega_2\cdot u) - \omega_1\cdot v}{(\omega_1\cdot\omega_2)^2 - 1},\
//! \mu = \frac{(\omega_1\cdot\omega_2)(\omega_1\cdot v) - \omega_2\cdot u}{(\omega_1\cdot\omega_2)^2 - 1},\
//! \gamma^2 = \frac{\lvert u\rvert^2 - \lambda^2 - \mu^2 - 2\lambda\mu\,\omega_1\cdot\omega_2}{\lvert\omega_1\times\omega_2\rvert^2},$$
//! and each angle is subproblem 1. Of the two roots, the one nearer home
//! ($\lvert\alpha\rvert + \lvert\beta\rvert$ least, wrapped) is the branch a numerical solve
//! from home follows.

use crate::leg_ik::wrap_angle;
use nalgebra::Vector3;

/// Subproblem 1: the angle about unit axis `w` that turns `from` onto `to` (0 when `from` is
/// on the axis).
pub(crate) fn turn(w: &Vector3<f64>, from: &Vector3<f64>, to: &Vector3<f64>) -> f64 {
    let x = from - w * w.dot(from);
    let y = to - w * w.dot(to);
    w.dot(&x.cross(&y)).atan2(x.dot(&y))
}

/// Subproblem 2: the root $(\alpha, \beta)$ nearer home with
/// $e^{[\omega_1]\alpha} e^{[\omega_2]\beta} u = v$, or `None` when $v$ is out of the reach of
/// the two axes ($\gamma^2 < 0$ beyond rounding) or they are parallel.
pub(crate) fn two_axes(
    w1: &Vector3<f64>,
    w2: &Vector3<f64>,
    u: &Vector3<f64>,
    v: &Vector3<f64>,
) -> Option<(f64, f64)> {
    let c = w1.dot(w2);
    let n = w1.cross(w2);
    let den = c * c - 1.0;
    if !(n.norm_squared() > 1e-12) {
        return None;
    }
    let lambda = (c * w2.dot(u) - w1.dot(v)) / den;
    let mu = (c * w1.dot(v) - w2.dot(u)) / den;
    let scale = u.norm_squared().max(1e-300);
    let gamma2 =
        (u.norm_squared() - lambda * lambda - mu * mu - 2.0 * lambda * mu * c) / n.norm_squared();
    if !(gamma2 >= -1e-12 * scale) {
        return None;
    }
    let gamma = gamma2.max(0.0).sqrt();
    let root = |g: f64| {
        let z = w1 * lambda + w2 * mu + n * g;
        (turn(w1, &z, v), turn(w2, u, &z))
    };
    [root(gamma), root(-gamma)].into_iter().min_by(|x, y| {
        let size = |(a, b): &(f64, f64)| wrap_angle(*a).abs() + wrap_angle(*b).abs();
        size(x).total_cmp(&size(y))
    })
}

/// A unit vector perpendicular to unit `w`.
pub(crate) fn perpendicular(w: &Vector3<f64>) -> Vector3<f64> {
    let e = if w.x.abs() < 0.6 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    w.cross(&e).normalize()
}
