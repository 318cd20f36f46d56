//! The papers' designs by name (`pkm.Mechanism("nuwar")`), taken from
//! [`pkm_mechanisms::presets`] and written as the study layer's `[mechanism.<kind>]` table (as
//! `pkm.presets()` shows them), so a preset and the same dict build the same mechanism.

use crate::errors;
use pkm_mechanisms::Placement;
use pkm_mechanisms::presets as library;
use pkm_study::schema::mechanism::MechanismSpec;
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

/// The design of preset `name`, or `None`: the library's design as its study table
/// (`From`/`TryFrom` of the kind's table).
pub(crate) fn spec(name: &str) -> Option<MechanismSpec> {
    Some(match name {
        "nuwar" => MechanismSpec::RotaryDelta(library::nuwar(Placement::canonical()).into()),
        "delta" => MechanismSpec::RotaryDelta(library::miller_delta(Placement::canonical()).into()),
        "tsai" => MechanismSpec::Tsai(library::stamper_max_gci().into()),
        "three_upu" => MechanismSpec::ThreeUpu(library::park_3upu().try_into().ok()?),
        "stewart_gough" => MechanismSpec::StewartGough(library::wolf_shoham_stewart_s4_1().into()),
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
