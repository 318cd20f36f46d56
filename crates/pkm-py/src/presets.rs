//! The papers' designs by name (`pkm.Mechanism("nuwar")`), taken from
//! [`pkm_mechanisms::presets`] and written as the study layer's `[mechanism.<kind>]` table (as
//! `pkm.presets()` shows them), so a preset and the same dict build the same mechanism.

use crate::errors;
use pkm_mechanisms::presets as library;
use pkm_mechanisms::{Elbow, ElbowMode, Placement, RotaryDeltaDesign, StewartDesign, TsaiDesign};
use pkm_study::schema::mechanism::{
    MechanismSpec, RotaryDeltaSpec, StewartSpec, ThreeUpuSpec, TsaiSpec,
};
use pkm_study::schema::units::{Degrees, Metres, NonNegativeMetres, PositiveMetres};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The preset names, with what each is.
const PRESETS: [(&str, &str); 5] = [
    (
        "nuwar",
        "Miller 2004 NUWAR prototype (§3.5, α = 35.26°, β = 60°)",
    ),
    ("delta", "Miller 2004 Delta prototype (§3.5, α = β = 0)"),
    ("tsai", "Stamper, Tsai & Walsh 1997 maximum-GCI design (§5)"),
    (
        "three_upu",
        "Park's 3-UPU as Wolf & Shoham 2006 §4.4 use it",
    ),
    (
        "stewart_gough",
        "Wolf & Shoham 2006 §4.1 Stewart–Gough platform at R = I",
    ),
];

/// The design of preset `name`, or `None`.
pub(crate) fn spec(name: &str) -> Option<MechanismSpec> {
    Some(match name {
        "nuwar" => rotary(library::nuwar(Placement::canonical())),
        "delta" => rotary(library::miller_delta(Placement::canonical())),
        "tsai" => tsai(library::stamper_max_gci()),
        "three_upu" => {
            let d = library::park_3upu();
            MechanismSpec::ThreeUpu(ThreeUpuSpec {
                base_radius: PositiveMetres(d.base_radius),
                platform_radius: PositiveMetres(d.platform_radius),
                azimuths_deg: library::PARK_AZIMUTHS_DEG.map(Degrees),
                beta1_deg: Degrees(0.0),
                gamma1_deg: Degrees(0.0),
                beta2_deg: Degrees(0.0),
                gamma2_deg: Degrees(0.0),
                beta3_deg: Degrees(0.0),
                gamma3_deg: Degrees(0.0),
            })
        }
        "stewart_gough" => stewart(library::wolf_shoham_stewart_s4_1()),
        _ => return None,
    })
}

/// `pkm.InvalidInput` for an unknown preset, listing the names.
pub(crate) fn unknown(py: Python<'_>, name: &str) -> PyErr {
    let names: Vec<&str> = PRESETS.iter().map(|(n, _)| *n).collect();
    errors::invalid(
        py,
        format!(
            "no preset `{name}`: expected one of {}, or a design dict",
            names.join(", ")
        ),
    )
}

fn rotary(d: RotaryDeltaDesign) -> MechanismSpec {
    MechanismSpec::RotaryDelta(RotaryDeltaSpec {
        base_radius: PositiveMetres(d.base_radius),
        plate_offset: Metres(d.plate_offset),
        arm: PositiveMetres(d.arm),
        forearm: PositiveMetres(d.forearm),
        alpha_deg: Degrees(d.alpha.to_degrees()),
        beta_deg: Degrees(d.beta.to_degrees()),
        motor_plane_z: Metres(d.placement.motor_plane_z),
        azimuth_motor_1_deg: Degrees(d.placement.azimuth_motor_1.to_degrees()),
        turned_plate_offsets: false,
        elbow: vec![ElbowMode::Out],
    })
}

fn tsai(d: TsaiDesign) -> MechanismSpec {
    MechanismSpec::Tsai(TsaiSpec {
        a: PositiveMetres(d.a),
        b: PositiveMetres(d.b),
        d_plus_e: NonNegativeMetres(d.d_plus_e),
        c_minus_r: Metres(d.c_minus_r),
        phi2_deg: Degrees(d.phi2.to_degrees()),
        phi3_deg: Degrees(d.phi3.to_degrees()),
        modes: vec![[Elbow::Out; 3]],
    })
}

fn stewart(d: StewartDesign) -> MechanismSpec {
    MechanismSpec::StewartGough(StewartSpec {
        base_radius: PositiveMetres(d.base_radius),
        platform_radius: PositiveMetres(d.platform_radius),
        base_separation_deg: Degrees(d.base_separation.to_degrees()),
        platform_separation_deg: Degrees(d.platform_separation.to_degrees()),
        pairing: d.layout.pairing,
        angle_mode: d.layout.angle_mode,
        offset_deg: Degrees(d.layout.offset_deg),
        rotation_deg: [Degrees(0.0); 3],
    })
}

/// The preset designs by name, each as its `[mechanism]` table (a dict that
/// `pkm.Mechanism` also takes) with a `"description"` beside it.
#[pyfunction]
pub(crate) fn presets(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for (name, description) in PRESETS {
        let Some(spec) = spec(name) else { continue };
        let entry = PyDict::new(py);
        entry.set_item("description", description)?;
        entry.set_item("mechanism", crate::convert::to_python(py, &spec)?)?;
        out.set_item(name, entry)?;
    }
    Ok(out)
}
