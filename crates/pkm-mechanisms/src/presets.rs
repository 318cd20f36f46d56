//! The designs of the papers pkm reproduces, named by machine, each with its source. Every
//! function returns a plain design struct; build the mechanism with its `new`, for example
//! `RotaryDelta::new(presets::nuwar(Placement::canonical()))`, and change a field with struct
//! update syntax to study a neighbour of the paper's design.

use crate::{Placement, RotaryDeltaDesign, StewartDesign, ThreeUpuDesign, TsaiDesign, UJointAxes};

/// Miller 2004 §3.5 prototype with motor inclination `alpha` and turn `beta` (rad): base radius
/// $R = 0.194$ m, plate offset $r = 0.03$ m, arm $L_a = 0.26$ m, forearm $L_b = 0.48$ m. The
/// design family of the §2.1 workspace study.
pub fn miller_prototype(alpha: f64, beta: f64, placement: Placement) -> RotaryDeltaDesign {
    RotaryDeltaDesign {
        base_radius: 0.194,
        plate_offset: 0.03,
        arm: 0.26,
        forearm: 0.48,
        alpha,
        beta,
        placement,
    }
}

/// Miller 2004's Delta: the §3.5 prototype with $\alpha = \beta = 0$.
pub fn miller_delta(placement: Placement) -> RotaryDeltaDesign {
    miller_prototype(0.0, 0.0, placement)
}

/// Miller 2004's NUWAR: the §3.5 prototype with $\alpha = 35.26°$, $\beta = 60°$.
pub fn nuwar(placement: Placement) -> RotaryDeltaDesign {
    miller_prototype(35.26f64.to_radians(), 60f64.to_radians(), placement)
}

/// Stamper, Tsai & Walsh 1997 §5: the maximum-GCI Tsai design, $a = 0.44$, $b = 0.56$,
/// $d + e = c - r = 0$, $\phi_2 = 120°$, $\phi_3 = 240°$ (reach $a + b + d + e = 1$).
pub fn stamper_max_gci() -> TsaiDesign {
    TsaiDesign::from_deg(0.44, 0.56, 0.0, 0.0, 120.0, 240.0)
}

/// Wolf & Shoham 2006 §4.1 (and the start of §4.3): $x = (12\ \mathrm{cm}, 8\ \mathrm{cm},
/// 30°, 8°)$ in the default layout.
pub fn wolf_shoham_stewart_s4_1() -> StewartDesign {
    StewartDesign::from_deg(12.0, 8.0, 30.0, 8.0)
}

/// Wolf & Shoham 2006 §4.2: the printed optimum $x = (3.5\ \mathrm{cm}, 3.5\ \mathrm{cm}, 15°,
/// 15°)$ in the default layout.
pub fn wolf_shoham_stewart_s4_2() -> StewartDesign {
    StewartDesign::from_deg(3.5, 3.5, 15.0, 15.0)
}

/// Azimuths of the joints of Park's 3-UPU (Wolf & Shoham §4.4), degrees.
pub const PARK_AZIMUTHS_DEG: [f64; 3] = [-90.0, 30.0, 150.0];

/// Park's 3-UPU as Wolf & Shoham §4.4 use it: joints at [`PARK_AZIMUTHS_DEG`], base radius 20
/// and platform radius 10 (Park's dimensions are not in the paper: spec §1.6), and the upper
/// U-joint axes [`UJointAxes::park`] (tangent and outward radial).
pub fn park_3upu() -> ThreeUpuDesign {
    let azimuths = PARK_AZIMUTHS_DEG.map(f64::to_radians);
    ThreeUpuDesign {
        base_radius: 20.0,
        platform_radius: 10.0,
        azimuths,
        upper: azimuths.map(UJointAxes::park),
    }
}
