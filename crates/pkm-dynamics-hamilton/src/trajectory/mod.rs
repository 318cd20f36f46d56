//! Task-space trajectories: motion programs ([`MotionLaw`]: parabolic, cycloidal, 3-4-5)
//! composed with path shapes ([`Path`]: straight line, ellipse, sheared ellipse, clothoid), with
//! analytic velocity and acceleration (Miller 2004 §3.5).
//!
//! On a segment of duration $T$ with path parameter $u = s(t/T)$:
//! $\dot p = p'(u)\,s'/T$, $\ddot p = p''(u)\,(s'/T)^2 + p'(u)\,s''/T^2$.

mod motion_law;
mod path;

pub use motion_law::MotionLaw;
pub use path::Path;

use crate::DynamicsError;
use nalgebra::Vector3;
use std::f64::consts::PI;

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

impl Segment {
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

/// How "time to traverse the ellipse … and back to the start point → 0.5 s" is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CycleReading {
    /// The round trip takes the cycle time; each leg half of it (canonical).
    RoundTrip,
    /// Each leg (go, back) takes the cycle time.
    EachLeg,
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
    /// [`DynamicsError::InvalidSetting`] for no segment, a non-positive duration or a path that
    /// fails [`Path::validate`].
    pub fn new(segments: Vec<Segment>) -> Result<Self, DynamicsError> {
        if segments.is_empty() {
            return Err(DynamicsError::InvalidSetting {
                setting: "segments",
                value: 0.0,
                requirement: "at least one segment",
            });
        }
        if let Some(s) = segments
            .iter()
            .find(|s| !(s.duration > 0.0 && s.duration.is_finite()))
        {
            return Err(DynamicsError::InvalidSetting {
                setting: "duration",
                value: s.duration,
                requirement: "must be finite and > 0",
            });
        }
        for s in &segments {
            s.path.validate()?;
        }
        Ok(Self { segments })
    }

    /// Miller's elliptical pick-and-place cycle (§3.5): the half ellipse through
    /// $(0, -0.2, -0.9)$, $(0, 0, -0.5)$, $(0, 0.2, -0.9)$ (centre $(0, 0, -0.9)$, semi-axes
    /// 0.2 in $y$ and 0.4 in $z$), 3-4-5 on the eccentric angle, there and back.
    ///
    /// # Errors
    /// [`DynamicsError::InvalidSetting`] for a non-positive cycle time.
    ///
    /// # Example
    /// ```
    /// use pkm_dynamics_hamilton::trajectory::{CycleReading, Trajectory};
    /// let t = Trajectory::pick_and_place(0.5, CycleReading::RoundTrip).unwrap();
    /// assert!((t.duration() - 0.5).abs() < 1e-15);
    /// assert!((t.sample(0.25).p.z + 0.9).abs() < 1e-12);
    /// ```
    pub fn pick_and_place(cycle_time: f64, reading: CycleReading) -> Result<Self, DynamicsError> {
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
        Self::new(vec![
            go,
            Segment {
                reverse: true,
                ..go
            },
        ])
    }

    /// Total duration.
    pub fn duration(&self) -> f64 {
        self.segments.iter().map(|s| s.duration).sum()
    }

    /// The plate motion at time `t` (clamped to the trajectory).
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
