//! The closed form of a passive pointing leg: a U at a base point $A$ (two revolute joints
//! through $A$) and a prismatic joint whose line through $A$ carries the platform origin, the
//! platform fixed to the slider, as the Tricept's central UP leg. When it is the one leg that
//! constrains the platform and the orientation is dependent on the position, it gives the
//! whole pose from the position (issue 33).
//!
//! With home axes $\omega_1, \omega_2$ of the U, home slide direction $a$ and signed home
//! reach $r_0 = (p_0 - A)\cdot a$, the leg places the platform origin at
//! $p = A + (r_0 + s)\,R_U a$ with $R_U = e^{[\omega_1]\alpha} e^{[\omega_2]\beta}$, and turns the
//! platform by $R_U$: $R = R_U R_0$. So $R_U a = v = \operatorname{sign}(r_0)(p - A)/\lvert p -
//! A\rvert$, $s = \operatorname{sign}(r_0)\lvert p - A\rvert - r_0$, and $(\alpha, \beta)$ is
//! Paden–Kahan subproblem 2 (see [`crate::paden_kahan`]), the root nearer home.

use crate::chain::{Joint, LegChain};
use crate::paden_kahan::two_axes;
use nalgebra::{Rotation3, Unit, Vector3};

/// A passive U + P leg whose slider line carries the platform origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PointingLeg {
    /// Its index among the legs.
    pub leg: usize,
    base: Vector3<f64>,
    first: Unit<Vector3<f64>>,
    second: Unit<Vector3<f64>>,
    slide: Vector3<f64>,
    /// $r_0 = (p_0 - A)\cdot a$, never near zero.
    reach: f64,
}

/// The leg's joint values and the platform rotation at one position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pointing {
    /// The U's angles $(\alpha, \beta)$ (rad) and the slide $s$ (m) from home.
    pub joints: [f64; 3],
    /// $R = R_U R_0$.
    pub rotation: Rotation3<f64>,
}

/// A leg of a revolute, a revolute and a prismatic joint, without actuator: the two revolute
/// joints' axes and points, and the slide, as the file gives them at home.
pub(crate) struct UniversalSlide {
    pub first: (Vector3<f64>, Vector3<f64>),
    pub second: (Vector3<f64>, Vector3<f64>),
    pub slide: Vector3<f64>,
}

impl UniversalSlide {
    /// `leg` as a passive R + R + P chain, if it is one.
    pub(crate) fn of(leg: &LegChain) -> Option<Self> {
        let [
            Joint::Revolute {
                axis: a1,
                point: p1,
            },
            Joint::Revolute {
                axis: a2,
                point: p2,
            },
            Joint::Prismatic { axis: slide },
        ] = leg.joints.as_slice()
        else {
            return None;
        };
        leg.actuators.is_empty().then_some(Self {
            first: (*a1, *p1),
            second: (*a2, *p2),
            slide: *slide,
        })
    }
}

impl PointingLeg {
    /// Leg `index` as a pointing leg, if it is one: revolute, revolute through the same point
    /// $A$ on non-parallel axes, then prismatic, no actuator, and the home platform origin `p0`
    /// on the slider line through $A$, away from $A$ (tolerances relative to `size`).
    pub(crate) fn detect(
        index: usize,
        leg: &LegChain,
        p0: &Vector3<f64>,
        size: f64,
    ) -> Option<Self> {
        let UniversalSlide {
            first: (a1, p1),
            second: (a2, p2),
            slide,
        } = UniversalSlide::of(leg)?;
        let (a1, p1, a2, p2, slide) = (&a1, &p1, &a2, &p2, &slide);
        let tolerance = 1e-9 * size;
        let reach = (p0 - p1).dot(slide);
        let on_line = (p0 - p1 - slide * reach).norm() <= tolerance;
        let usable = (p1 - p2).norm() <= tolerance
            && a1.cross(a2).norm() > 1e-6
            && on_line
            && reach.abs() > 1e-6 * size;
        usable.then(|| Self {
            leg: index,
            base: *p1,
            first: Unit::new_normalize(*a1),
            second: Unit::new_normalize(*a2),
            slide: slide.normalize(),
            reach,
        })
    }

    /// The leg and the platform rotation with the platform origin at `p`, the home rotation
    /// `home`; `None` at the base point or where the U cannot point the slider along
    /// $p - A$ (non-orthogonal axes reach a cone of directions only).
    pub(crate) fn solve(&self, p: &Vector3<f64>, home: &Rotation3<f64>) -> Option<Pointing> {
        let along = p - self.base;
        let distance = along.norm();
        if !(distance > 1e-9 * self.reach.abs()) {
            return None;
        }
        let sign = self.reach.signum();
        let v = along * (sign / distance);
        let a = self.slide;
        let (alpha, beta) = two_axes(self.first.as_ref(), self.second.as_ref(), &a, &v)?;
        let r_u = Rotation3::from_axis_angle(&self.first, alpha)
            * Rotation3::from_axis_angle(&self.second, beta);
        if !((r_u * a - v).norm() < 1e-9) {
            return None;
        }
        Some(Pointing {
            joints: [alpha, beta, sign * distance - self.reach],
            rotation: r_u * home,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chain::LegChain;

    /// Random U axes (not orthogonal) and slide: the solved angles turn the slide onto the
    /// direction asked, the slide closes the distance, and the rotation is $R_U R_0$.
    #[test]
    fn solves_oblique_universal_joints() {
        let base = Vector3::new(0.1, -0.2, 0.05);
        let a1 = Vector3::new(1.0, 0.2, 0.1).normalize();
        let a2 = Vector3::new(-0.1, 1.0, 0.3).normalize();
        let slide = Vector3::new(0.1, -0.2, 1.0).normalize();
        let leg = LegChain {
            joints: vec![
                Joint::Revolute {
                    axis: a1,
                    point: base,
                },
                Joint::Revolute {
                    axis: a2,
                    point: base,
                },
                Joint::Prismatic { axis: slide },
            ],
            actuators: vec![],
            letters: "UP".into(),
            bodies: vec![],
        };
        let p0 = base + slide * 0.6;
        let pointing = PointingLeg::detect(0, &leg, &p0, 1.0).unwrap();
        let home = Rotation3::new(Vector3::new(0.1, 0.2, -0.3));
        for p in [
            Vector3::new(0.2, 0.1, 0.7),
            Vector3::new(-0.15, -0.3, 0.5),
            p0,
        ] {
            let s = pointing.solve(&p, &home).unwrap();
            let [alpha, beta, travel] = s.joints;
            let r_u = Rotation3::from_axis_angle(&Unit::new_normalize(a1), alpha)
                * Rotation3::from_axis_angle(&Unit::new_normalize(a2), beta);
            let reached = base + r_u * (slide * (0.6 + travel));
            assert!((reached - p).norm() < 1e-12, "{reached} vs {p}");
            assert!((s.rotation.matrix() - (r_u * home).matrix()).amax() < 1e-12);
        }
        let at_home = pointing.solve(&p0, &home).unwrap().joints;
        assert!(at_home.iter().all(|v| v.abs() < 1e-12), "{at_home:?}");
        assert!(pointing.solve(&base, &home).is_none());
    }

    /// The Tricept file: its central leg is found as the pointing leg, and the pose from its
    /// closed form equals the damped-Newton solve of the dependent coordinates (the general
    /// path, with the pointing leg withheld) to 1e-12, with the leg's joints closing it.
    #[test]
    fn agrees_with_the_numerical_solve_on_the_tricept() {
        let text = include_str!("../../../examples/robots/tricept.toml");
        let model = crate::RobotModel::from_toml(text).unwrap();
        assert_eq!(model.pointing.map(|p| p.leg), Some(3));
        let numerical = crate::RobotModel {
            pointing: None,
            identity: crate::model::Identity::fresh(),
            ..model.clone()
        };
        for k in 0..20 {
            let s = |a: f64| (f64::from(k) * a).sin();
            let x = [0.2 * s(0.7), 0.2 * s(1.9), 0.6 + 0.15 * s(2.9)];
            let (closed, newton) = (
                model.full_pose(&x).unwrap(),
                numerical.full_pose(&x).unwrap(),
            );
            let gap = (0..6)
                .map(|i| (closed[i] - newton[i]).abs())
                .fold(0.0, f64::max);
            assert!(gap < 1e-12, "{x:?}: {closed:?} vs {newton:?}");
            let config = model
                .inverse_kinematics_configuration(&x, model.home_mode())
                .unwrap();
            let back = numerical
                .inverse_kinematics_configuration(&x, model.home_mode())
                .unwrap();
            assert!((model.actuators_of(&config) - numerical.actuators_of(&back)).amax() < 1e-12);
            let margins = model.singularity_margins(&config).unwrap();
            assert!(margins.direct > 0.0, "{margins:?}");
        }
    }
}
