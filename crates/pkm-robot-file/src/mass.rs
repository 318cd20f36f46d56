//! Mass properties of a robot file (issue 31): the links of each leg, point masses at joint
//! points, the platform, actuator rotors and gravity, validated on load with the key path of
//! any bad value. `docs/robots.md` documents the fields with their units.

use crate::error::RobotFileError;
use crate::file::{BodySpec, JointSpec, LegSpec};
use nalgebra::{Matrix3, Rotation3, SymmetricEigen, Vector3};

/// Largest mass (kg) and inertia (kg m²) a file may give: beyond any machine, and far from
/// overflow in the products of the dynamics.
const MAX_MASS: f64 = 1e9;

/// One rigid body at the home pose, in the base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// How many of its leg's elementary joints move it (for a leg body; all of them for a
    /// body carried by the platform).
    pub after: usize,
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass at home (m).
    pub center: Vector3<f64>,
    /// Inertia tensor about the centre of mass, base axes at home (kg m²).
    pub inertia: Matrix3<f64>,
}

impl Body {
    /// The body turned by `r` about `point` (a copy of a symmetric leg).
    pub(crate) fn rotated(&self, r: &Rotation3<f64>, point: &Vector3<f64>) -> Self {
        Self {
            center: r * (self.center - point) + point,
            inertia: r.matrix() * self.inertia * r.matrix().transpose(),
            ..*self
        }
    }
}

/// The mass properties of a robot beyond its legs' bodies.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MassProperties {
    /// Gravitational acceleration (m/s², base frame), if the file gives it.
    pub gravity: Option<Vector3<f64>>,
    /// The platform, if the file gives it.
    pub platform: Option<Body>,
}

/// A validated body from `spec` at `key`, moved by `after` joints, its centre of mass
/// defaulting to `default_center`.
///
/// # Errors
/// [`RobotFileError::Invalid`] at `key.mass` for a mass that is negative, not finite or above
/// 1e9 kg; at `key.center_of_mass` for a centre beyond ±1e6 m; at `key.inertia` for a tensor
/// that is not finite, not symmetric, not positive semidefinite or whose principal moments
/// violate the triangle inequality $I_1 \le I_2 + I_3$.
pub(crate) fn body(
    key: &str,
    spec: &BodySpec,
    after: usize,
    default_center: Vector3<f64>,
) -> Result<Body, RobotFileError> {
    let mass = point_mass(&format!("{key}.mass"), spec.mass)?;
    let center = match spec.center_of_mass {
        Some(c) if c.iter().all(|v| v.is_finite() && v.abs() <= 1e6) => Vector3::from(c),
        Some(c) => {
            return Err(RobotFileError::invalid(
                format!("{key}.center_of_mass"),
                c,
                "must be finite, each entry within ±1e6 m",
            ));
        }
        None => default_center,
    };
    let inertia = match spec.inertia {
        Some(rows) => inertia_tensor(&format!("{key}.inertia"), &rows)?,
        None => Matrix3::zeros(),
    };
    Ok(Body {
        after,
        mass,
        center,
        inertia,
    })
}

/// The bodies of leg `i`: its `links` (link `m` between file joints `m` and `m + 1`, moved by
/// the `ends[m]` elementary joints through joint `m`) and the point masses at its joints
/// (carried by the body after the joint; after the last joint, by the platform).
///
/// # Errors
/// [`RobotFileError::Invalid`] at `legs[i].links` for a count other than 0 or one fewer than
/// the joints, at a link's fields as [`body`] says (and at its `center_of_mass` when a
/// neighbouring joint is a P, which has no point to default it from), at
/// `legs[i].joints[m].mass` for a bad mass or one on a P joint.
pub(crate) fn leg_bodies(
    i: usize,
    leg: &LegSpec,
    ends: &[usize],
) -> Result<Vec<Body>, RobotFileError> {
    let n = leg.joints.len();
    if !(leg.links.is_empty() || leg.links.len() + 1 == n) {
        return Err(RobotFileError::invalid(
            format!("legs[{i}].links"),
            leg.links.len(),
            format!(
                "one link between each two joints: {} for {n} joints (or none)",
                n - 1
            ),
        ));
    }
    let point = |m: usize| leg.joints[m].point.map(Vector3::from);
    let mut bodies = Vec::new();
    for (m, link) in leg.links.iter().enumerate() {
        let key = format!("legs[{i}].links[{m}]");
        let midpoint = match (point(m), point(m + 1)) {
            (Some(a), Some(b)) => (a + b) / 2.0,
            _ if link.center_of_mass.is_some() || link.mass == 0.0 => Vector3::zeros(),
            _ => {
                return Err(RobotFileError::invalid(
                    format!("{key}.center_of_mass"),
                    "missing",
                    "required when joint m or m + 1 is a P joint (it has no point to take \
                     the midpoint of)",
                ));
            }
        };
        bodies.push(body(&key, link, ends[m], midpoint)?);
    }
    for (m, joint) in leg.joints.iter().enumerate() {
        let Some(mass) = joint.mass else { continue };
        let key = format!("legs[{i}].joints[{m}].mass");
        let mass = point_mass(&key, mass)?;
        let Some(at) = point(m) else {
            return Err(RobotFileError::invalid(
                key,
                mass,
                "a point mass sits at a joint's point: a P joint has none",
            ));
        };
        bodies.push(Body {
            after: ends[m],
            mass,
            center: at,
            inertia: Matrix3::zeros(),
        });
    }
    Ok(bodies)
}

/// The rotor inertia reflected to the joint of `spec` at `key`: `rotor_inertia *
/// gear_ratio²`.
///
/// # Errors
/// [`RobotFileError::Invalid`] at `key.rotor_inertia` or `key.gear_ratio` for a bad value
/// (the ratio finite, positive and at most 1e6) or either given on a joint that is not
/// actuated.
pub(crate) fn reflected_inertia(key: &str, spec: &JointSpec) -> Result<f64, RobotFileError> {
    let rotor = match spec.rotor_inertia {
        Some(v) => point_mass(&format!("{key}.rotor_inertia"), v)?,
        None => 0.0,
    };
    let ratio = spec.gear_ratio.unwrap_or(1.0);
    if !(ratio > 0.0 && ratio <= 1e6) {
        return Err(RobotFileError::invalid(
            format!("{key}.gear_ratio"),
            ratio,
            "must be finite, positive and at most 1e6",
        ));
    }
    Ok(rotor * ratio * ratio)
}

/// A mass (kg) or a rotor inertia (kg m²) checked at `key`: finite, at least 0, at most 1e9.
pub(crate) fn point_mass(key: &str, mass: f64) -> Result<f64, RobotFileError> {
    if (0.0..=MAX_MASS).contains(&mass) {
        Ok(mass)
    } else {
        Err(RobotFileError::invalid(
            key,
            mass,
            "must be finite, at least 0 and at most 1e9",
        ))
    }
}

/// An inertia tensor checked at `key`: finite entries within 1e9, symmetric to 1e-9 of its
/// largest entry, principal moments $\ge 0$ and each at most the sum of the other two (both
/// to 1e-9 of the trace), as every rigid body's are.
fn inertia_tensor(key: &str, rows: &[[f64; 3]; 3]) -> Result<Matrix3<f64>, RobotFileError> {
    let m = Matrix3::from_fn(|r, c| rows[r][c]);
    let refuse = |why: &str| Err(RobotFileError::invalid(key, rows, why));
    if !m.iter().all(|v| v.is_finite() && v.abs() <= MAX_MASS) {
        return refuse("entries must be finite and within ±1e9 kg m²");
    }
    let scale = m.amax();
    if (m - m.transpose()).amax() > 1e-9 * scale {
        return refuse("must be symmetric");
    }
    let symmetric = (m + m.transpose()) * 0.5;
    let moments = SymmetricEigen::new(symmetric).eigenvalues;
    let tolerance = 1e-9 * moments.iter().map(|v| v.abs()).sum::<f64>();
    if moments.iter().any(|&v| v < -tolerance) {
        return refuse("must be positive semidefinite (principal moments at least 0)");
    }
    let total: f64 = moments.sum();
    if moments.iter().any(|&v| v > total - v + tolerance) {
        return refuse(
            "principal moments must obey the triangle inequality (each at most the sum of the \
             other two), as a rigid body's do",
        );
    }
    Ok(symmetric)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(inertia: [[f64; 3]; 3]) -> BodySpec {
        BodySpec {
            mass: 1.0,
            center_of_mass: None,
            inertia: Some(inertia),
        }
    }

    #[test]
    fn bad_tensors_are_refused_and_good_ones_kept() {
        let key = |r: Result<Body, RobotFileError>| match r {
            Err(RobotFileError::Invalid { requirement, .. }) => requirement,
            other => panic!("{other:?}"),
        };
        let at = |m| body("platform", &spec(m), 0, Vector3::zeros());
        assert!(key(at([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])).contains("symmetric"));
        assert!(
            key(at([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]])).contains("semidefinite")
        );
        assert!(key(at([[3.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])).contains("triangle"));
        assert!(
            key(at([[f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])).contains("finite")
        );
        // A slender rod (one moment zero, the triangle's boundary) and a rotated box.
        assert!(at([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]).is_ok());
        assert!(at([[2.0, 0.3, 0.1], [0.3, 1.5, -0.2], [0.1, -0.2, 1.0]]).is_ok());
        for bad in [-1.0, f64::NAN, f64::INFINITY, 1e300] {
            let r = body(
                "links[0]",
                &BodySpec {
                    mass: bad,
                    center_of_mass: None,
                    inertia: None,
                },
                1,
                Vector3::zeros(),
            );
            assert!(key(r).contains("at least 0"));
        }
        let far = BodySpec {
            mass: 1.0,
            center_of_mass: Some([1e300, 0.0, 0.0]),
            inertia: None,
        };
        assert!(key(body("platform", &far, 0, Vector3::zeros())).contains("±1e6"));
    }
}
