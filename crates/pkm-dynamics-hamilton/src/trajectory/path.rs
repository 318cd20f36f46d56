//! Path shapes $p(u)$, $u \in [0, 1]$, with analytic first and second derivatives: the four
//! shapes of Miller 2004 §3.5 (straight line, ellipse, sheared ellipse, clothoid).
//!
//! The variants have public fields; the constructors ([`Path::line`], [`Path::ellipse`],
//! [`Path::sheared_ellipse`], [`Path::clothoid`]) and [`Path::validate`] (called by
//! [`crate::trajectory::Trajectory::new`]) reject parameters that cannot describe a path.

use crate::DynamicsError;
use nalgebra::Vector3;
use pkm_traits::InvalidInput;

/// A geometric path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Path {
    /// Straight line from `start` to `end`.
    Line {
        /// $p(0)$.
        start: Vector3<f64>,
        /// $p(1)$.
        end: Vector3<f64>,
    },
    /// $p = c + \cos\varphi\, a_1 + \sin\varphi\, a_2$, $\varphi = \varphi_0 + u\,\Delta\varphi$.
    /// Orthogonal $a_1$, $a_2$ give an ellipse with these semi-axes; non-orthogonal ones a
    /// sheared ellipse (see [`Path::sheared_ellipse`]).
    Ellipse {
        /// Centre $c$.
        centre: Vector3<f64>,
        /// $a_1$.
        axis_1: Vector3<f64>,
        /// $a_2$.
        axis_2: Vector3<f64>,
        /// $\varphi_0$ (rad).
        start_angle: f64,
        /// $\Delta\varphi$ (rad).
        sweep: f64,
    },
    /// Clothoid (Euler spiral) of arc length $L$ in the plane of `tangent` and `normal`:
    /// curvature $\kappa(s) = \kappa_0 + c\,s$ linear in the arc length $s = uL$, heading
    /// $\theta(s) = \kappa_0 s + c s^2/2$ from `tangent` towards `normal`, and
    /// $$ p(s) = p_0 + \int_0^s \big(\cos\theta(\sigma)\, e_1 + \sin\theta(\sigma)\, e_2\big)\, d\sigma $$
    /// (generalised Fresnel integrals, evaluated by composite 8-point Gauss–Legendre quadrature
    /// with panels over which the heading turns by at most 1 rad: truncation error below
    /// $10^{-20} L$, so the position is accurate to rounding).
    /// $e_1$ is `tangent` normalised, $e_2$ the part of `normal` orthogonal to it, normalised.
    /// Derivatives are analytic: $dp/ds = \cos\theta\, e_1 + \sin\theta\, e_2$,
    /// $d^2p/ds^2 = \kappa(s)\,(-\sin\theta\, e_1 + \cos\theta\, e_2)$, times $L$ and $L^2$ in $u$.
    Clothoid {
        /// $p(0)$.
        start: Vector3<f64>,
        /// Direction of $dp/ds$ at $s = 0$ (need not be unit).
        tangent: Vector3<f64>,
        /// Direction of positive curvature (need not be unit or orthogonal to `tangent`).
        normal: Vector3<f64>,
        /// $\kappa_0$, curvature at the start (1/m).
        curvature: f64,
        /// $c = d\kappa/ds$ (1/m²).
        sharpness: f64,
        /// $L > 0$ (m).
        length: f64,
    },
}

/// Nodes and weights of the 8-point Gauss–Legendre rule on $[-1, 1]$ (positive half).
const GAUSS_LEGENDRE_8: [(f64, f64); 4] = [
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
];

/// Smallest admissible sine of the angle between two spanning vectors.
const MIN_SINE: f64 = 1e-9;

fn finite_vector(setting: &'static str, v: &Vector3<f64>) -> Result<(), DynamicsError> {
    v.iter()
        .try_for_each(|x| InvalidInput::require_finite(setting, *x).map(drop))
        .map_err(Into::into)
}

/// `v` divided by its largest component where $|v|^2$ overflows (1e200) or underflows (1e-200)
/// (the same direction, with a norm in $[1, \sqrt 3]$); unchanged, to the bit, otherwise and
/// for the zero vector.
fn unit_scaled(v: &Vector3<f64>) -> Vector3<f64> {
    let largest = v.amax();
    if largest > 0.0 && !v.norm_squared().is_normal() {
        v / largest
    } else {
        *v
    }
}

/// $|a \times b| / (|a|\,|b|)$, 0 when either vector is zero.
fn sine_between(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let (a, b) = (unit_scaled(a), unit_scaled(b));
    let scale = a.norm() * b.norm();
    if scale > 0.0 {
        a.cross(&b).norm() / scale
    } else {
        0.0
    }
}

/// The orthonormal frame $(e_1, e_2)$ of a clothoid's plane.
fn plane(tangent: &Vector3<f64>, normal: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let e1 = unit_scaled(tangent).normalize();
    let normal = unit_scaled(normal);
    let e2 = (normal - e1 * e1.dot(&normal)).normalize();
    (e1, e2)
}

/// The most Gauss–Legendre panels of a clothoid's Fresnel integrals: a path whose heading may
/// turn by more radians than this, $L\max(|\kappa_0|, |\kappa_0 + cL|, \sqrt{|c|})$, is
/// refused, so the quadrature never runs with fewer panels than its accuracy needs.
pub const MAX_CLOTHOID_TURNS: f64 = 1e7;

/// The panels [`fresnel`] needs over arc length `s`: $|s|\max(|\kappa_0|, |\kappa_0 + cs|,
/// \sqrt{|c|})$.
fn clothoid_turns(kappa0: f64, c: f64, s: f64) -> f64 {
    let rate = kappa0.abs().max((kappa0 + c * s).abs());
    (s.abs() * rate).max(s.abs() * c.abs().sqrt())
}

/// $\left(\int_0^s \cos\theta,\ \int_0^s \sin\theta\right)$ with $\theta = \kappa_0\sigma + c\sigma^2/2$.
///
/// Composite 8-point Gauss–Legendre: $n$ equal panels with $n \ge |s|\max|\theta'|$ and
/// $n \ge |s|\sqrt{|c|}$, so the heading turns by at most 1 rad per panel and the quadratic part of
/// the phase changes by at most 1/2 rad; the rule's error is then of order $10^{-23}$ per unit
/// length (the $(2\cdot 8)$-th derivative of the integrand is bounded by the 16th power of the
/// phase rate).
fn fresnel(kappa0: f64, c: f64, s: f64) -> (f64, f64) {
    // At most MAX_CLOTHOID_TURNS for a validated path (|s| ≤ L, and the rate is largest at an
    // end); the clamp only keeps the cast defined.
    let n = clothoid_turns(kappa0, c, s)
        .ceil()
        .clamp(1.0, MAX_CLOTHOID_TURNS) as usize;
    let h = s / n as f64;
    let theta = |x: f64| x * (kappa0 + 0.5 * c * x);
    let (mut cx, mut sy) = (0.0, 0.0);
    for k in 0..n {
        let mid = (k as f64 + 0.5) * h;
        for &(x, w) in &GAUSS_LEGENDRE_8 {
            for sigma in [mid - 0.5 * h * x, mid + 0.5 * h * x] {
                let (sn, cs) = theta(sigma).sin_cos();
                cx += w * cs;
                sy += w * sn;
            }
        }
    }
    (cx * 0.5 * h, sy * 0.5 * h)
}

impl Path {
    /// A validated straight line.
    ///
    /// # Errors
    /// [`DynamicsError::Invalid`] for a non-finite point.
    pub fn line(start: Vector3<f64>, end: Vector3<f64>) -> Result<Self, DynamicsError> {
        let path = Self::Line { start, end };
        path.validate()?;
        Ok(path)
    }

    /// A validated ellipse arc $c + \cos\varphi\, a_1 + \sin\varphi\, a_2$.
    ///
    /// # Errors
    /// [`DynamicsError::Invalid`] for a non-finite value, a zero sweep, or axes that are
    /// zero or parallel.
    pub fn ellipse(
        centre: Vector3<f64>,
        axis_1: Vector3<f64>,
        axis_2: Vector3<f64>,
        start_angle: f64,
        sweep: f64,
    ) -> Result<Self, DynamicsError> {
        let path = Self::Ellipse {
            centre,
            axis_1,
            axis_2,
            start_angle,
            sweep,
        };
        path.validate()?;
        Ok(path)
    }

    /// The ellipse with orthogonal semi-axes $a_1$, $a_2$ sheared parallel to $a_1$ by the factor
    /// $k$: in the ellipse's frame $(\xi, \eta) \mapsto (\xi + k\eta, \eta)$, i.e. an
    /// [`Path::Ellipse`] with second axis $a_2 + k\,(|a_2|/|a_1|)\,a_1$. $k = 0$ is the ellipse.
    ///
    /// # Errors
    /// [`DynamicsError::Invalid`] for a non-finite value, a zero sweep, or semi-axes that
    /// are zero or not orthogonal (|cos| > 1e-9).
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use pkm_dynamics_hamilton::trajectory::Path;
    /// let p = Path::sheared_ellipse(Vector3::zeros(), Vector3::x() * 0.2, Vector3::z() * 0.4,
    ///     0.5, 0.0, std::f64::consts::PI).unwrap();
    /// // At φ = π/2 the top point moves by k·b = 0.2 along the first axis.
    /// let [top, _, _] = p.eval(0.5);
    /// assert!((top - Vector3::new(0.2, 0.0, 0.4)).norm() < 1e-15);
    /// ```
    pub fn sheared_ellipse(
        centre: Vector3<f64>,
        semi_axis_1: Vector3<f64>,
        semi_axis_2: Vector3<f64>,
        shear: f64,
        start_angle: f64,
        sweep: f64,
    ) -> Result<Self, DynamicsError> {
        InvalidInput::require_finite("sheared_ellipse.shear", shear)?;
        finite_vector("sheared_ellipse.semi_axis_1", &semi_axis_1)?;
        finite_vector("sheared_ellipse.semi_axis_2", &semi_axis_2)?;
        let (a, b) = (semi_axis_1.norm(), semi_axis_2.norm());
        if !(a > 0.0 && b > 0.0) {
            return Err(InvalidInput::new(
                "sheared_ellipse.semi_axis",
                a.min(b),
                "semi-axes must be non-zero",
            )
            .into());
        }
        let cosine = semi_axis_1.dot(&semi_axis_2) / (a * b);
        if cosine.abs() > MIN_SINE {
            return Err(InvalidInput::new(
                "sheared_ellipse.semi_axes_cosine",
                cosine,
                "semi-axes must be orthogonal",
            )
            .into());
        }
        Self::ellipse(
            centre,
            semi_axis_1,
            semi_axis_2 + semi_axis_1 * (shear * b / a),
            start_angle,
            sweep,
        )
    }

    /// A validated clothoid (see [`Path::Clothoid`]).
    ///
    /// # Errors
    /// [`DynamicsError::Invalid`] for a non-finite value, a length that is not positive,
    /// a zero `tangent`, a `normal` that is zero or parallel to `tangent`, or a heading that
    /// turns by more than [`MAX_CLOTHOID_TURNS`] rad over the path.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use pkm_dynamics_hamilton::trajectory::Path;
    /// // θ = π s²/2 over s ∈ [0, 1]: the end point is (C(1), S(1)), the Fresnel integrals.
    /// let p = Path::clothoid(Vector3::zeros(), Vector3::x(), Vector3::y(), 0.0,
    ///     std::f64::consts::PI, 1.0).unwrap();
    /// let [end, _, _] = p.eval(1.0);
    /// assert!((end - Vector3::new(0.779_893_400_376_822_8, 0.438_259_147_390_354_8, 0.0)).norm() < 1e-15);
    /// ```
    pub fn clothoid(
        start: Vector3<f64>,
        tangent: Vector3<f64>,
        normal: Vector3<f64>,
        curvature: f64,
        sharpness: f64,
        length: f64,
    ) -> Result<Self, DynamicsError> {
        let path = Self::Clothoid {
            start,
            tangent,
            normal,
            curvature,
            sharpness,
            length,
        };
        path.validate()?;
        Ok(path)
    }

    /// Checks that the parameters describe a path with finite derivatives.
    ///
    /// # Errors
    /// As the constructors.
    pub fn validate(&self) -> Result<(), DynamicsError> {
        match self {
            Self::Line { start, end } => {
                finite_vector("line.start", start)?;
                finite_vector("line.end", end)
            }
            Self::Ellipse {
                centre,
                axis_1,
                axis_2,
                start_angle,
                sweep,
            } => {
                finite_vector("ellipse.centre", centre)?;
                finite_vector("ellipse.axis_1", axis_1)?;
                finite_vector("ellipse.axis_2", axis_2)?;
                InvalidInput::require_finite("ellipse.start_angle", *start_angle)?;
                InvalidInput::require_finite("ellipse.sweep", *sweep)?;
                if *sweep == 0.0 {
                    return Err(
                        InvalidInput::new("ellipse.sweep", *sweep, "must be non-zero").into(),
                    );
                }
                let sine = sine_between(axis_1, axis_2);
                if sine < MIN_SINE {
                    return Err(InvalidInput::new(
                        "ellipse.axes_sine",
                        sine,
                        "axes must be non-zero and not parallel",
                    )
                    .into());
                }
                Ok(())
            }
            Self::Clothoid {
                start,
                tangent,
                normal,
                curvature,
                sharpness,
                length,
            } => {
                finite_vector("clothoid.start", start)?;
                finite_vector("clothoid.tangent", tangent)?;
                finite_vector("clothoid.normal", normal)?;
                InvalidInput::require_finite("clothoid.curvature", *curvature)?;
                InvalidInput::require_finite("clothoid.sharpness", *sharpness)?;
                if !(*length > 0.0 && length.is_finite()) {
                    return Err(InvalidInput::new(
                        "clothoid.length",
                        *length,
                        "must be finite and > 0",
                    )
                    .into());
                }
                let sine = sine_between(tangent, normal);
                if sine < MIN_SINE {
                    return Err(InvalidInput::new(
                        "clothoid.tangent_normal_sine",
                        sine,
                        "tangent and normal must be non-zero and not parallel",
                    )
                    .into());
                }
                let turns = clothoid_turns(*curvature, *sharpness, *length);
                if !(turns <= MAX_CLOTHOID_TURNS) {
                    return Err(InvalidInput::new(
                        "clothoid.turns",
                        turns,
                        "the heading may turn by at most MAX_CLOTHOID_TURNS (1e7) rad over the \
                         path: L·max(|κ0|, |κ0 + cL|, √|c|)",
                    )
                    .into());
                }
                Ok(())
            }
        }
    }

    /// $(p, p', p'')$ at $u$ (derivatives with respect to $u$). On a validated path, finite for
    /// every finite $u$ whose point stays within the float range ($u \in [0, 1]$ always);
    /// NaN in, NaN out: a NaN $u$ gives a NaN position, never a panic.
    pub fn eval(&self, u: f64) -> [Vector3<f64>; 3] {
        match *self {
            Self::Line { start, end } => [start + (end - start) * u, end - start, Vector3::zeros()],
            Self::Ellipse {
                centre,
                axis_1,
                axis_2,
                start_angle,
                sweep,
            } => {
                let (s, c) = (start_angle + sweep * u).sin_cos();
                let radial = axis_1 * c + axis_2 * s;
                [
                    centre + radial,
                    (axis_2 * c - axis_1 * s) * sweep,
                    -radial * (sweep * sweep),
                ]
            }
            Self::Clothoid {
                start,
                tangent,
                normal,
                curvature,
                sharpness,
                length,
            } => {
                let (e1, e2) = plane(&tangent, &normal);
                let s = u * length;
                let (sin, cos) = (s * (curvature + 0.5 * sharpness * s)).sin_cos();
                let kappa = curvature + sharpness * s;
                let (cx, sy) = fresnel(curvature, sharpness, s);
                [
                    start + e1 * cx + e2 * sy,
                    (e1 * cos + e2 * sin) * length,
                    (e2 * cos - e1 * sin) * (kappa * length * length),
                ]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn spiral() -> Path {
        // Heading turns from 0 through κ0 L + c L²/2 = 1.5 + 2.0 = 3.5 rad; curvature changes sign
        // nowhere but grows from 3 to 11 1/m.
        Path::clothoid(
            Vector3::new(0.1, -0.2, -0.8),
            Vector3::new(0.0, 2.0, 0.0),
            Vector3::new(0.0, 1.0, 1.0),
            3.0,
            16.0,
            0.5,
        )
        .unwrap()
    }

    /// Central differences of `p` and `p'` in `u` against the analytic `p'`, `p''`.
    fn check_derivatives(path: &Path, tol: f64) {
        let h = 1e-5;
        for k in 0..=20 {
            let u = f64::from(k) / 20.0;
            let [_, d1, d2] = path.eval(u);
            let [pp, dp, _] = path.eval(u + h);
            let [pm, dm, _] = path.eval(u - h);
            let fd1 = (pp - pm) / (2.0 * h);
            let fd2 = (dp - dm) / (2.0 * h);
            assert!(
                (fd1 - d1).norm() <= tol * d1.norm().max(1.0),
                "p' at {u}: {fd1} vs {d1}"
            );
            assert!(
                (fd2 - d2).norm() <= tol * d2.norm().max(1.0),
                "p'' at {u}: {fd2} vs {d2}"
            );
        }
    }

    #[test]
    fn analytic_derivatives_match_central_differences_for_every_shape() {
        let c = Vector3::new(0.0, 0.0, -0.9);
        let shapes = [
            Path::line(Vector3::new(0.1, 0.0, -0.7), Vector3::new(-0.1, 0.2, -0.8)).unwrap(),
            Path::ellipse(c, Vector3::y() * -0.2, Vector3::z() * 0.4, 0.0, PI).unwrap(),
            Path::sheared_ellipse(c, Vector3::y() * 0.2, Vector3::z() * 0.4, 0.3, 0.1, 2.0)
                .unwrap(),
            spiral(),
            Path::clothoid(c, Vector3::x(), -Vector3::y(), -2.0, 10.0, 0.6).unwrap(),
        ];
        for path in &shapes {
            check_derivatives(path, 1e-8);
        }
    }

    #[test]
    fn clothoid_matches_the_fresnel_integrals() {
        // θ = π s²/2: p(s) = (C(s), S(s)); reference values of C and S from mpmath
        // (`fresnelc`, `fresnels` at 30 digits), rounded to 16.
        let p = Path::clothoid(Vector3::zeros(), Vector3::x(), Vector3::y(), 0.0, PI, 3.0).unwrap();
        for (s, c, sn) in [
            (0.5, 0.492_344_225_871_446_4, 0.064_732_432_859_999_28),
            (1.0, 0.779_893_400_376_822_8, 0.438_259_147_390_354_8),
            (2.0, 0.488_253_406_075_340_8, 0.343_415_678_363_698_2),
            (3.0, 0.605_720_789_297_685_6, 0.496_312_998_967_375),
        ] {
            let [end, _, _] = p.eval(s / 3.0);
            assert!((end.x - c).abs() < 1e-14, "C({s}) = {} vs {c}", end.x);
            assert!((end.y - sn).abs() < 1e-14, "S({s}) = {} vs {sn}", end.y);
            assert!(end.z.abs() < 1e-15);
        }
    }

    #[test]
    fn clothoid_is_parameterised_by_arc_length_with_linear_curvature() {
        let path = spiral();
        let Path::Clothoid {
            curvature,
            sharpness,
            length,
            tangent,
            normal,
            ..
        } = path
        else {
            unreachable!()
        };
        let binormal = tangent.cross(&normal).normalize();
        let n = 20_000;
        let mut polyline = 0.0;
        let mut last = path.eval(0.0)[0];
        for k in 1..=n {
            let u = f64::from(k) / f64::from(n);
            let [p, d1, d2] = path.eval(u);
            polyline += (p - last).norm();
            last = p;
            // |dp/ds| = 1 and the signed curvature (p' × p'')·b / |p'|³ = κ0 + c s.
            assert!((d1.norm() / length - 1.0).abs() < 1e-14);
            let kappa = d1.cross(&d2).dot(&binormal) / d1.norm().powi(3);
            let expected = curvature + sharpness * u * length;
            assert!(
                (kappa - expected).abs() < 1e-12 * expected.abs(),
                "{kappa} vs {expected}"
            );
        }
        // A chord of length h under curvature κ is shorter than its arc by about κ²h³/24.
        let h: f64 = length / f64::from(n);
        let bound = 11.0_f64.powi(2) * h.powi(3) / 24.0 * f64::from(n);
        assert!(
            polyline <= length && length - polyline <= bound + 1e-12,
            "{polyline} vs {length}"
        );
    }

    #[test]
    fn quadrature_is_converged() {
        // Doubling the panels does not change the position: the panel rule is at rounding level.
        for (k0, c, s) in [(3.0, 16.0, 0.5), (-2.0, 40.0, 1.3), (0.0, 200.0, 1.0)] {
            let (x, y) = fresnel(k0, c, s);
            let (mut xr, mut yr) = (0.0, 0.0);
            let n = 64;
            for i in 0..n {
                let a = s * f64::from(i) / f64::from(n);
                let b = s * f64::from(i + 1) / f64::from(n);
                // The integrand from a: θ(a + σ) = θ(a) + θ'(a) σ + c σ²/2.
                let th = a * (k0 + 0.5 * c * a);
                let (dx, dy) = fresnel(k0 + c * a, c, b - a);
                let (sn, cs) = th.sin_cos();
                xr += cs * dx - sn * dy;
                yr += sn * dx + cs * dy;
            }
            assert!(
                (x - xr).abs() < 1e-13 && (y - yr).abs() < 1e-13,
                "{x} {xr} {y} {yr}"
            );
        }
    }

    #[test]
    fn bad_parameters_are_typed_errors() {
        let z = Vector3::zeros;
        let setting = |r: Result<Path, DynamicsError>| match r {
            Err(DynamicsError::Invalid(e)) => e.name,
            other => panic!("expected Invalid, got {other:?}"),
        };
        assert_eq!(
            setting(Path::line(z(), Vector3::new(f64::NAN, 0.0, 0.0))),
            "line.end"
        );
        assert_eq!(
            setting(Path::ellipse(
                z(),
                Vector3::x(),
                Vector3::x() * 2.0,
                0.0,
                1.0
            )),
            "ellipse.axes_sine"
        );
        assert_eq!(
            setting(Path::ellipse(z(), Vector3::x(), Vector3::y(), 0.0, 0.0)),
            "ellipse.sweep"
        );
        assert_eq!(
            setting(Path::sheared_ellipse(
                z(),
                Vector3::x(),
                Vector3::new(1.0, 1.0, 0.0),
                0.1,
                0.0,
                1.0
            )),
            "sheared_ellipse.semi_axes_cosine"
        );
        assert_eq!(
            setting(Path::sheared_ellipse(z(), z(), Vector3::y(), 0.1, 0.0, 1.0)),
            "sheared_ellipse.semi_axis"
        );
        for length in [0.0, -1.0, f64::INFINITY, f64::NAN] {
            assert_eq!(
                setting(Path::clothoid(
                    z(),
                    Vector3::x(),
                    Vector3::y(),
                    1.0,
                    1.0,
                    length
                )),
                "clothoid.length"
            );
        }
        assert_eq!(
            setting(Path::clothoid(
                z(),
                Vector3::x(),
                Vector3::x() * -3.0,
                1.0,
                1.0,
                1.0
            )),
            "clothoid.tangent_normal_sine"
        );
        assert_eq!(
            setting(Path::clothoid(z(), z(), Vector3::y(), 1.0, 1.0, 1.0)),
            "clothoid.tangent_normal_sine"
        );
        assert_eq!(
            setting(Path::clothoid(
                z(),
                Vector3::x(),
                Vector3::y(),
                f64::NAN,
                1.0,
                1.0
            )),
            "clothoid.curvature"
        );
    }
}
