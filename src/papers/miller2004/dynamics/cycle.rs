//! The two readings of the cycle time of Miller's elliptical pick-and-place cycle (§3.5); the
//! cycle itself is the library's preset
//! ([`pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place`]).

use pkm_dynamics_hamilton::DynamicsError;
use pkm_dynamics_hamilton::trajectory::Trajectory;
use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;

/// How "time to traverse the ellipse … and back to the start point → 0.5 s" is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CycleReading {
    /// The round trip takes the cycle time; each leg half of it (canonical).
    RoundTrip,
    /// Each leg (go, back) takes the cycle time.
    EachLeg,
}

/// Miller's cycle with the paper's `cycle_time` read as `reading`.
///
/// # Errors
/// [`DynamicsError::Invalid`] for a cycle time that is not finite and positive.
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
    miller_pick_and_place(match reading {
        CycleReading::RoundTrip => cycle_time,
        // Each leg in the cycle time is a round trip in twice it (exactly: 2t/2 = t).
        CycleReading::EachLeg => 2.0 * cycle_time,
    })
}
