//! Path shapes $p(u)$, $u \in [0, 1]$, with analytic first and second derivatives.

use nalgebra::Vector3;

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
    /// sheared ellipse.
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
}

impl Path {
    /// $(p, p', p'')$ at $u$.
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
        }
    }
}
