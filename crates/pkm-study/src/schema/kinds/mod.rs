//! The five mechanisms of the papers as study mechanisms, one file each: the
//! `[mechanism.<kind>]` table with its defaults, the library robot it builds, and its
//! `impl StudyMechanism` (design variables, actuation, workspace, reach region, drawing).
//! Lengths are metres, angles in keys ending in `_deg` degrees (converted to radians here),
//! ratios dimensionless. A new robot is a robot file (`docs/robots.md`); a new kind here is
//! one file and one line of the registry ([`super::mechanism::MechanismSpec`]).

pub mod linear_delta;
pub mod rotary_delta;
pub mod stewart_gough;
pub mod three_upu;
pub mod tsai;

use crate::registry::BuildError;
use crate::schema::units::{Degrees, Metres};

fn zero_deg() -> Degrees {
    Degrees(0.0)
}
fn zero_m() -> Metres {
    Metres(0.0)
}

fn design_error(e: pkm_traits::DesignError) -> BuildError {
    BuildError::Design(e.into())
}
