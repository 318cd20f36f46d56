//! Task-space trajectories: motion programs ([`MotionLaw`]: parabolic, cycloidal, 3-4-5)
//! composed with path shapes ([`Path`]: straight line, ellipse, sheared ellipse, clothoid), with
//! analytic velocity and acceleration (Miller 2004 §3.5). Named trajectories of the literature
//! are in [`presets`] (Miller's pick-and-place cycle: [`presets::miller_pick_and_place`]).
//!
//! On a segment of duration $T$ with path parameter $u = s(t/T)$:
//! $\dot p = p'(u)\,s'/T$, $\ddot p = p''(u)\,(s'/T)^2 + p'(u)\,s''/T^2$.

mod motion_law;
mod path;
pub mod presets;

pub use motion_law::MotionLaw;
pub use path::{MAX_CLOTHOID_TURNS, Path};

use crate::DynamicsError;
use nalgebra::Vector3;
use pkm_traits::InvalidInput;

/// Position, velocity and acceleration of the plate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaskMotion {
    /// $p$.
    pub p: Vector3<f64>,
    /// $\dot p$.
    pub v: Vector3<f64>,
    /// $\ddot p$.
    pub a: Vector3<f64>,
}

/// One rest-to-rest move along a path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// The path.
    pub path: Path,
    /// The motion program.
    pub law: MotionLaw,
    /// Duration (s).
    pub duration: f64,
    /// Run the path from $u = 1$ back to $u = 0$.
    pub reverse: bool,
}

/// Safety factor on the largest derivatives seen at the probe points of
/// [`Segment::check_motion_is_finite`]: every motion law has $|s'| \le 2$ and $|s''| \le 2\pi$,
/// and the paths' derivatives vary by less than this factor between probes.
const MOTION_MARGIN: f64 = 64.0;

impl Segment {
    /// Checks that the motion derived from the path and the duration is finite: the path's
    /// points and derivatives at $u = 0, \tfrac18, \dots, 1$, and the bounds
    /// $|\dot p| \le 2\,\max|p'|/T$, $|\ddot p| \le (4\max|p''| + 2\pi\max|p'|)/T^2$ with
    /// a margin of [`MOTION_MARGIN`].
    fn check_motion_is_finite(&self) -> Result<(), DynamicsError> {
        let (mut p1, mut p2) = (0.0f64, 0.0f64);
        for k in 0..=8 {
            let [p, d1, d2] = self.path.eval(f64::from(k) / 8.0);
            if !p
                .iter()
                .chain(d1.iter())
                .chain(d2.iter())
                .all(|v| v.is_finite())
            {
                return Err(InvalidInput::new(
                    "path",
                    f64::INFINITY,
                    "must have finite points and derivatives",
                )
                .into());
            }
            p1 = p1.max(d1.amax());
            p2 = p2.max(d2.amax());
        }
        let t = self.duration;
        let speed = MOTION_MARGIN * 2.0 * p1 / t;
        let acceleration = MOTION_MARGIN * (4.0 * p2 + 2.0 * std::f64::consts::PI * p1) / t / t;
        if !(speed.is_finite() && acceleration.is_finite()) {
            return Err(InvalidInput::new(
                "duration",
                t,
                "too short for the path: its velocity or acceleration overflows",
            )
            .into());
        }
        Ok(())
    }

    fn sample(&self, t: f64) -> TaskMotion {
        let (s, s1, s2) = self.law.eval(t / self.duration);
        let (u, sign) = if self.reverse {
            (1.0 - s, -1.0)
        } else {
            (s, 1.0)
        };
        let [p, p1, p2] = self.path.eval(u);
        let (ud, udd) = (sign * s1 / self.duration, sign * s2 / self.duration.powi(2));
        TaskMotion {
            p,
            v: p1 * ud,
            a: p2 * ud * ud + p1 * udd,
        }
    }
}

/// A sequence of segments run one after the other.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    segments: Vec<Segment>,
}

impl Trajectory {
    /// Chains segments.
    ///
    /// # Errors
    /// [`DynamicsError::Invalid`] for no segment, a non-positive duration, a path that
    /// fails [`Path::validate`], a total duration that overflows, or a segment whose positions,
    /// velocities or accelerations would overflow (a path too large for `f64`, or too long for
    /// its duration: $|p'|/T$ or $|p''|/T^2$ beyond `f64`).
    pub fn new(segments: Vec<Segment>) -> Result<Self, DynamicsError> {
        if segments.is_empty() {
            return Err(InvalidInput::new("segments", 0.0, "at least one segment").into());
        }
        if let Some(s) = segments
            .iter()
            .find(|s| !(s.duration > 0.0 && s.duration.is_finite()))
        {
            return Err(InvalidInput::new("duration", s.duration, "must be finite and > 0").into());
        }
        for s in &segments {
            s.path.validate()?;
            s.check_motion_is_finite()?;
        }
        let total: f64 = segments.iter().map(|s| s.duration).sum();
        if !total.is_finite() {
            return Err(InvalidInput::new("duration", total, "the total must be finite").into());
        }
        Ok(Self { segments })
    }

    /// Total duration.
    pub fn duration(&self) -> f64 {
        self.segments.iter().map(|s| s.duration).sum()
    }

    /// The plate motion at time `t` (clamped to the trajectory: an infinite `t` gives the
    /// nearest end). NaN in, NaN out: a NaN `t` gives a NaN position, never a panic; every
    /// other `t` gives a finite motion (the path and the law are validated).
    pub fn sample(&self, t: f64) -> TaskMotion {
        let mut start = 0.0;
        for (n, s) in self.segments.iter().enumerate() {
            if t < start + s.duration || n + 1 == self.segments.len() {
                return s.sample((t - start).clamp(0.0, s.duration));
            }
            start += s.duration;
        }
        // `new` guarantees a segment, so the loop returns; keep a total function anyway.
        self.segments[0].sample(0.0)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Miller's cycle in `duration`: the test cycle of this crate's unit tests.
    pub(crate) fn ellipse_cycle(duration: f64) -> Trajectory {
        presets::miller_pick_and_place(duration).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn the_test_cycle_goes_there_and_back() {
        let t = ellipse_cycle(0.5);
        assert!((t.duration() - 0.5).abs() < 1e-15);
        assert!((t.sample(0.25).p.z + 0.9).abs() < 1e-12);
        assert!((t.sample(0.125).p.z + 0.5).abs() < 1e-12);
        assert!((t.sample(0.0).p - t.sample(0.5).p).norm() < 1e-12);
        // There and back: the same point at the same time from either end.
        for k in 0..=10 {
            let t1 = 0.025 * f64::from(k);
            assert!(
                (t.sample(t1).p - t.sample(0.5 - t1).p).norm() < 1e-12,
                "t = {t1}"
            );
        }
    }
}
