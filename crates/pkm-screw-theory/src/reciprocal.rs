//! The reciprocal product of a wrench and a twist (Wolf & Shoham eq. 5–6).

use nalgebra::{DMatrix, Vector3, Vector6};

use crate::ray;
use crate::screw_axis::ScrewAxis;
use crate::screws::{Twist, Wrench};

/// The reciprocal product of two ray-order 6-vectors, $a \wedge b = a_{top} \cdot b_{bottom} +
/// a_{bottom} \cdot b_{top} = a^\top \Delta b$, where $\Delta$ swaps the halves. Symmetric,
/// bit for bit. Plain arithmetic: NaN in, NaN out, and products beyond `f64` give ±∞ (the
/// validated entry points above it check their results).
pub fn reciprocal_product_vectors(a: &Vector6<f64>, b: &Vector6<f64>) -> f64 {
    let ((a_top, a_bottom), (b_top, b_bottom)) = (ray::halves(a), ray::halves(b));
    a_top.dot(&b_bottom) + a_bottom.dot(&b_top)
}

/// The reciprocal product (virtual power) of a wrench $L = [j; \bar j]$ and a twist
/// $\chi = [x; \bar x]$, eq. 5 and 14: $L \wedge \chi = \bar j \cdot x + j \cdot \bar x$.
/// It vanishes when the wrench does no work on the twist (the screws are reciprocal). NaN in,
/// NaN out, as [`reciprocal_product_vectors`].
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::{reciprocal_product, Twist, Wrench};
/// // A force along z through the origin does no work on a rotation about the z axis.
/// let force = Wrench::new(Vector3::z(), Vector3::zeros());
/// assert_eq!(reciprocal_product(&force, &Twist::new(Vector3::z(), Vector3::zeros())), 0.0);
/// // A force along z does work 1 on a unit translation along z.
/// assert_eq!(reciprocal_product(&force, &Twist::new(Vector3::zeros(), Vector3::z())), 1.0);
/// ```
pub fn reciprocal_product(wrench: &Wrench, twist: &Twist) -> f64 {
    reciprocal_product_vectors(wrench.as_vector(), twist.as_vector())
}

/// The common normal from one screw axis to another: the distance $a \ge 0$ along it and the
/// angle $\alpha$ from the first direction to the second, right-handed about the normal
/// (Wolf & Shoham Fig. 1; convention of `spec/wolf-shoham.md` §1.1).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::{CommonNormal, ScrewAxis};
/// // The z axis and a line along y through (2, 0, 0): a = 2, α = −90° about +x.
/// let z = ScrewAxis::new(&Vector3::z(), &Vector3::zeros(), 0.0)?;
/// let y = ScrewAxis::new(&Vector3::y(), &Vector3::new(2.0, 0.0, 0.0), 0.0)?;
/// let normal = CommonNormal::between(&z, &y);
/// assert!((normal.distance - 2.0).abs() < 1e-12);
/// assert!((normal.angle.abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
/// # Ok::<(), pkm_screw_theory::ScrewError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommonNormal {
    /// Distance $a$ between the axes (non-negative).
    pub distance: f64,
    /// Twist angle $\alpha \in (-\pi, \pi]$.
    pub angle: f64,
}

impl CommonNormal {
    /// The common normal pointing from `from` to `to`. For parallel axes (direction cross
    /// product exactly zero) the normal is the perpendicular offset and $\alpha \in \{0, \pi\}$.
    pub fn between(from: &ScrewAxis, to: &ScrewAxis) -> Self {
        let (s, sr) = (from.direction(), to.direction());
        let offset = to.point() - from.point();
        let c = s.cross(&sr);
        let cross_norm = c.norm();
        if cross_norm > 0.0 {
            // Signed distance along s × s_r; flipping the normal flips the sign of sin α.
            let signed = offset.dot(&c) / cross_norm;
            let sin = cross_norm.copysign(signed);
            return Self {
                distance: signed.abs(),
                angle: sin.atan2(s.dot(&sr)),
            };
        }
        let perpendicular: Vector3<f64> = offset - s * offset.dot(&s);
        Self {
            distance: perpendicular.norm(),
            angle: 0.0_f64.atan2(s.dot(&sr)),
        }
    }
}

/// The geometric form of the reciprocal product, eq. 6:
/// $$\delta W = \rho\,\dot q\,\big((\lambda + \lambda_r)\cos\alpha - a \sin\alpha\big),$$
/// with $a$, $\alpha$ the [`CommonNormal`] from the twist axis to the wrench axis. Equal to
/// eq. 5 for the twist $\dot q\,\hat{\$}$ and the wrench $\rho\,\hat{\$}_r$.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::*;
/// let twist_axis = ScrewAxis::new(&Vector3::z(), &Vector3::zeros(), 0.3)?;
/// let wrench_axis = ScrewAxis::new(&Vector3::x(), &Vector3::new(0.0, 0.0, 2.0), -0.1)?;
/// let eq6 = reciprocal_product_geometric(&twist_axis, 1.5, &wrench_axis, 2.0);
/// let eq5 = reciprocal_product(&Wrench::on_axis(&wrench_axis, 2.0), &Twist::on_axis(&twist_axis, 1.5));
/// assert!((eq6 - eq5).abs() < 1e-12);
/// # Ok::<(), ScrewError>(())
/// ```
pub fn reciprocal_product_geometric(
    twist_axis: &ScrewAxis,
    twist_intensity: f64,
    wrench_axis: &ScrewAxis,
    wrench_intensity: f64,
) -> f64 {
    let CommonNormal { distance, angle } = CommonNormal::between(twist_axis, wrench_axis);
    let pitch_sum = twist_axis.pitch() + wrench_axis.pitch();
    wrench_intensity * twist_intensity * (pitch_sum * angle.cos() - distance * angle.sin())
}

/// The unit twist most nearly reciprocal to every row of a wrench matrix $W$ (six or more rows
/// of six, each a wrench in Plücker order $[j; \bar j]$), with $\sigma_{min}(W)$: the rows act
/// on the swapped twist ($r = W\,\Delta\chi$), so $\chi$ is the swapped right singular vector
/// of $\sigma_{min}$, and $|W\,\Delta\chi| = \sigma_{min}$ (0 when the rows do no work on
/// $\chi$: a singular configuration). `None` for fewer than six rows, a non-finite entry or
/// an SVD that does not converge in 1000 sweeps.
///
/// # Example
/// ```
/// use nalgebra::DMatrix;
/// use pkm_screw_theory::most_reciprocal_twist;
/// // Five unit forces along x, y, z through the origin and moments about x, y: nothing
/// // resists a rotation about z, the twist every row is reciprocal to.
/// let mut w = DMatrix::<f64>::zeros(6, 6);
/// for k in 0..5 { w[(k, k)] = 1.0; }
/// let (sigma, twist) = most_reciprocal_twist(&w).unwrap();
/// assert!(sigma < 1e-15 && (twist.as_vector()[2].abs() - 1.0).abs() < 1e-15);
/// ```
pub fn most_reciprocal_twist(rows: &DMatrix<f64>) -> Option<(f64, Twist)> {
    if rows.nrows() < 6 || rows.ncols() != 6 || !rows.iter().all(|v| v.is_finite()) {
        return None;
    }
    let svd = rows.clone().try_svd(false, true, f64::EPSILON, 1000)?;
    let v_t = svd.v_t?;
    let k = (0..6).min_by(|&i, &j| svd.singular_values[i].total_cmp(&svd.singular_values[j]))?;
    let y = v_t.row(k).transpose();
    let twist = Twist::from_vector(Vector6::new(y[3], y[4], y[5], y[0], y[1], y[2]));
    Some((svd.singular_values[k], twist))
}
