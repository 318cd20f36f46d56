//! Joint layouts of the semi-regular Stewart–Gough platform (Fig. 3 is missing from the paper;
//! the default reproduces §4.2's "all lines parallel" statement, see `docs/conventions.md`).

use nalgebra::Vector3;

/// Which platform joint each base joint is connected to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pairing {
    /// Leg $k$ joins $b_k$ to $r_k$: pairs on both platforms centred on the same azimuths.
    #[default]
    SamePattern,
    /// Classical zig-zag: platform pairs centred $60°$ off the base pairs, each base joint
    /// joined to the nearest platform joint of the neighbouring pair.
    ZigZag,
}

/// How $x_3$, $x_4$ are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AngleMode {
    /// The angle between the two joints of a pair.
    #[default]
    Separation,
    /// Half that angle.
    Half,
}

/// A joint layout: pairing, angle reading and the azimuth of the first pair.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointLayout {
    /// Base-to-platform pairing.
    pub pairing: Pairing,
    /// Reading of $x_3$, $x_4$.
    pub angle_mode: AngleMode,
    /// Azimuth of the first base pair's centre, degrees (0: on the world $+x$ axis).
    pub offset_deg: f64,
}

impl JointLayout {
    /// Base joints $b_k$ and platform joints $r_k$ (platform frame) for design $x$.
    pub(crate) fn joints(
        &self,
        x1: f64,
        x2: f64,
        x3: f64,
        x4: f64,
    ) -> ([Vector3<f64>; 6], [Vector3<f64>; 6]) {
        let half = match self.angle_mode {
            AngleMode::Separation => 0.5,
            AngleMode::Half => 1.0,
        };
        let at = |radius: f64, degrees: f64| {
            let t = degrees.to_radians();
            Vector3::new(radius * t.cos(), radius * t.sin(), 0.0)
        };
        let centre = |k: usize| self.offset_deg + 120.0 * (k / 2) as f64;
        let side = |k: usize| if k.is_multiple_of(2) { -1.0 } else { 1.0 };
        let base = std::array::from_fn(|k| at(x1, centre(k) + side(k) * half * x3));
        let platform = std::array::from_fn(|k| {
            let t = match self.pairing {
                Pairing::SamePattern => side(k) * half * x4,
                Pairing::ZigZag => side(k) * (60.0 - half * x4),
            };
            at(x2, centre(k) + t)
        });
        (base, platform)
    }
}
