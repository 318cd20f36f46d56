//! Named trajectories of the literature, built from the general [`Trajectory`].

use super::{MotionLaw, Path, Segment, Trajectory};
use crate::DynamicsError;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Miller's elliptical pick-and-place cycle (Miller 2004, §3.5): the half ellipse through
/// $(0, -0.2, -0.9)$, $(0, 0, -0.5)$ and $(0, 0.2, -0.9)$ m (centre $(0, 0, -0.9)$, semi-axes
/// 0.2 m in $y$ and 0.4 m in $z$), run there and back with the 3-4-5 polynomial law on the
/// eccentric angle, each way in half of `cycle_time` (s).
///
/// # Errors
/// [`DynamicsError::Invalid`] for a cycle time that is not finite and positive.
///
/// # Example
/// ```
/// use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;
/// let cycle = miller_pick_and_place(0.5)?;
/// assert!((cycle.duration() - 0.5).abs() < 1e-15);
/// assert!((cycle.sample(0.125).p.z + 0.5).abs() < 1e-12); // the top of the ellipse
/// assert!((cycle.sample(0.0).p - cycle.sample(0.5).p).norm() < 1e-12);
/// assert!(miller_pick_and_place(-1.0).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn miller_pick_and_place(cycle_time: f64) -> Result<Trajectory, DynamicsError> {
    let path = Path::Ellipse {
        centre: Vector3::new(0.0, 0.0, -0.9),
        axis_1: Vector3::new(0.0, -0.2, 0.0),
        axis_2: Vector3::new(0.0, 0.0, 0.4),
        start_angle: 0.0,
        sweep: PI,
    };
    let go = Segment {
        path,
        law: MotionLaw::Polynomial345,
        duration: cycle_time / 2.0,
        reverse: false,
    };
    Trajectory::new(vec![
        go,
        Segment {
            reverse: true,
            ..go
        },
    ])
}
