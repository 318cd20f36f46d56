//! Normalised motion programs $s(\tau)$, $\tau \in [0, 1]$, $s(0) = 0$, $s(1) = 1$, with
//! $s'(0) = s'(1) = 0$ (Miller 2004 §3.5, after LePage 1999).

use std::f64::consts::PI;

/// A rest-to-rest motion program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionLaw {
    /// Parabolic "bang-bang": $s'' = \pm 4$ (acceleration jumps).
    Parabolic,
    /// Cycloidal "sine on ramp": $s = \tau - \sin(2\pi\tau)/(2\pi)$.
    Cycloidal,
    /// 3-4-5 polynomial: $s = 10\tau^3 - 15\tau^4 + 6\tau^5$.
    Polynomial345,
}

impl MotionLaw {
    /// $(s, s', s'')$ at $\tau$ (clamped to $[0, 1]$).
    pub fn eval(self, tau: f64) -> (f64, f64, f64) {
        let t = tau.clamp(0.0, 1.0);
        match self {
            Self::Parabolic if t < 0.5 => (2.0 * t * t, 4.0 * t, 4.0),
            Self::Parabolic => {
                let r = 1.0 - t;
                (1.0 - 2.0 * r * r, 4.0 * r, -4.0)
            }
            Self::Cycloidal => {
                let w = 2.0 * PI * t;
                (t - w.sin() / (2.0 * PI), 1.0 - w.cos(), 2.0 * PI * w.sin())
            }
            Self::Polynomial345 => {
                let (t2, r) = (t * t, 1.0 - t);
                (
                    t2 * t * (10.0 - 15.0 * t + 6.0 * t2),
                    30.0 * t2 * r * r,
                    60.0 * t * r * (1.0 - 2.0 * t),
                )
            }
        }
    }
}
