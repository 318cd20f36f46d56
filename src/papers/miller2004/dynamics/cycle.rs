//! Miller's elliptical pick-and-place cycle (§3.5) and the two readings of its cycle time,
//! built from the general [`Trajectory`] of `pkm-dynamics-hamilton`.

use nalgebra::Vector3;
use pkm_dynamics_hamilton::DynamicsError;
use pkm_dynamics_hamilton::trajectory::{MotionLaw, Path, Segment, Trajectory};
use std::f64::consts::PI;

/// How "time to traverse the ellipse … and back to the start point → 0.5 s" is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CycleReading {
    /// The round trip takes the cycle time; each leg half of it (canonical).
    RoundTrip,
    /// Each leg (go, back) takes the cycle time.
    EachLeg,
}

/// Miller's elliptical pick-and-place cycle (§3.5): the half ellipse through
/// $(0, -0.2, -0.9)$, $(0, 0, -0.5)$, $(0, 0.2, -0.9)$ (centre $(0, 0, -0.9)$, semi-axes
/// 0.2 in $y$ and 0.4 in $z$), 3-4-5 on the eccentric angle, there and back.
///
/// # Errors
/// [`DynamicsError::InvalidSetting`] for a cycle time that is not finite and positive.
///
/// # Example
/// ```
/// use pkm::papers::miller2004::dynamics::{CycleReading, pick_and_place};
/// let t = pick_and_place(0.5, CycleReading::RoundTrip).unwrap();
/// assert!((t.duration() - 0.5).abs() < 1e-15);
/// assert!((t.sample(0.25).p.z + 0.9).abs() < 1e-12);
/// let slow = pick_and_place(0.5, CycleReading::EachLeg).unwrap();
/// assert!((slow.duration() - 1.0).abs() < 1e-15);
/// assert!(pick_and_place(-1.0, CycleReading::RoundTrip).is_err());
/// ```
pub fn pick_and_place(cycle_time: f64, reading: CycleReading) -> Result<Trajectory, DynamicsError> {
    let leg = match reading {
        CycleReading::RoundTrip => cycle_time / 2.0,
        CycleReading::EachLeg => cycle_time,
    };
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
        duration: leg,
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
