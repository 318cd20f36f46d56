//! Joint layouts of the semi-regular Stewart–Gough platform (Fig. 3 is missing from the paper;
//! the default reproduces §4.2's "all lines parallel" statement, see `docs/conventions.md`).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Which platform joint each base joint is connected to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Pairing {
    /// Leg $k$ joins $b_k$ to $r_k$: pairs on both platforms centred on the same azimuths.
    #[default]
    SamePattern,
    /// Classical zig-zag: platform pairs centred $60°$ off the base pairs, each base joint
    /// joined to the nearest platform joint of the neighbouring pair.
    ZigZag,
}

/// How $x_3$, $x_4$ are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AngleMode {
    /// The angle between the two joints of a pair.
    #[default]
    Separation,
    /// Half that angle.
    Half,
}

/// A joint layout: pairing, angle reading and the azimuth of the first pair.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointLayout {
    /// Base-to-platform pairing.
    pub pairing: Pairing,
    /// Reading of $x_3$, $x_4$.
    pub angle_mode: AngleMode,
    /// Azimuth of the first base pair's centre, degrees (0: on the world $+x$ axis).
    pub offset_deg: f64,
}

impl JointLayout {
    /// Base joints $b_k$ and platform joints $r_k$ (platform frame) on circles of
    /// `[base, platform]` radii, each pair's joints `[base, platform]` separations apart (rad).
    pub(crate) fn joints(
        &self,
        radii: [f64; 2],
        separations: [f64; 2],
    ) -> ([Vector3<f64>; 6], [Vector3<f64>; 6]) {
        let half = match self.angle_mode {
            AngleMode::Separation => 0.5,
            AngleMode::Half => 1.0,
        };
        let at = |radius: f64, t: f64| Vector3::new(radius * t.cos(), radius * t.sin(), 0.0);
        let offset = self.offset_deg.to_radians();
        let pair = 120f64.to_radians();
        let centre = |k: usize| offset + pair * (k / 2) as f64;
        let side = |k: usize| if k.is_multiple_of(2) { -1.0 } else { 1.0 };
        let base =
            std::array::from_fn(|k| at(radii[0], centre(k) + side(k) * half * separations[0]));
        let platform = std::array::from_fn(|k| {
            let t = match self.pairing {
                Pairing::SamePattern => side(k) * half * separations[1],
                Pairing::ZigZag => side(k) * (60f64.to_radians() - half * separations[1]),
            };
            at(radii[1], centre(k) + t)
        });
        (base, platform)
    }
}
