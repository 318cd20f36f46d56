//! The views: orthographic projections on the coordinate planes and one axonometric 3-D view.

use nalgebra::Vector3;

/// A direction of view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// Looking along $+y$: $x$ to the right, $z$ up.
    Front,
    /// Looking along $-x$: $y$ to the right, $z$ up.
    Side,
    /// Looking down $-z$: $x$ to the right, $y$ up.
    Top,
    /// An axonometric view from azimuth −60° and elevation 25°: horizontal
    /// $u = p \cdot (-\sin a, \cos a, 0)$, vertical
    /// $v = p \cdot (-\sin e \cos a, -\sin e \sin a, \cos e)$ with $a = -60°$, $e = 25°$.
    ThreeD,
}

impl View {
    /// Front, side, top and 3-D, the order of a 2 × 2 sheet.
    pub const ALL: [Self; 4] = [Self::Front, Self::Side, Self::Top, Self::ThreeD];

    /// Name written on the view.
    pub fn name(self) -> &'static str {
        match self {
            Self::Front => "front (x-z)",
            Self::Side => "side (y-z)",
            Self::Top => "top (x-y)",
            Self::ThreeD => "3-D",
        }
    }

    /// Names of the horizontal and vertical coordinates, without unit.
    #[cfg(feature = "render")]
    pub(crate) fn axis_names(self) -> (&'static str, &'static str) {
        match self {
            Self::Front => ("x", "z"),
            Self::Side => ("y", "z"),
            Self::Top => ("x", "y"),
            Self::ThreeD => ("u", "v"),
        }
    }

    /// The screen coordinates $(u, v)$ of `p`.
    pub fn project(self, p: &Vector3<f64>) -> (f64, f64) {
        match self {
            Self::Front => (p.x, p.z),
            Self::Side => (p.y, p.z),
            Self::Top => (p.x, p.y),
            Self::ThreeD => {
                let (sa, ca) = (-60f64).to_radians().sin_cos();
                let (se, ce) = 25f64.to_radians().sin_cos();
                let right = Vector3::new(-sa, ca, 0.0);
                let up = Vector3::new(-se * ca, -se * sa, ce);
                (p.dot(&right), p.dot(&up))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_3d_view_is_an_orthonormal_projection() {
        // The screen rows are orthonormal: the squared lengths of the images of e_x, e_y, e_z
        // sum to 2 (the squared norms of the two rows), and a vertical segment stays vertical.
        let images: f64 = [Vector3::x(), Vector3::y(), Vector3::z()]
            .iter()
            .map(|e| {
                let (u, v) = View::ThreeD.project(e);
                u * u + v * v
            })
            .sum();
        assert!((images - 2.0).abs() < 1e-15);
        assert!(View::ThreeD.project(&Vector3::z()).0.abs() < 1e-15);
        let p = Vector3::new(0.3, -1.2, 2.5);
        assert_eq!(View::Front.project(&p), (0.3, 2.5));
        assert_eq!(View::Side.project(&p), (-1.2, 2.5));
        assert_eq!(View::Top.project(&p), (0.3, -1.2));
    }
}
