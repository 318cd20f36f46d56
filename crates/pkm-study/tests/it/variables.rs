//! One declaration of each kind's design variables: the `design_variables!` list of its table.
//! The library's design problems name their vectors in their own order (they are library API,
//! below the study layer); the study layer hands them the table's values by those names, so
//! the names must be the table's, in the table's order.

use pkm::mechanisms::presets;
use pkm_design_problems::tsai::TSAI_VARIABLES;
use pkm_study::StudyMechanism;
use pkm_study::schema::mechanism::{StewartSpec, ThreeUpuSpec, TsaiSpec};
use pkm_study::task::{STEWART_VARIABLES, UPU_VARIABLES};

fn names<M: StudyMechanism>(spec: &M) -> Vec<String> {
    spec.variables()
        .iter()
        .map(|v| v.name.to_string())
        .collect()
}

#[test]
fn the_problems_variable_names_are_the_tables_declaration() {
    let tsai = names(&TsaiSpec::from(presets::stamper_max_gci()));
    assert_eq!(tsai, TSAI_VARIABLES);
    let upu = names(&ThreeUpuSpec::try_from(presets::park_3upu()).unwrap());
    assert_eq!(upu, UPU_VARIABLES[..8]);
    assert_eq!(
        UPU_VARIABLES[8..],
        ["x", "y", "z", "rx_deg", "ry_deg", "rz_deg"]
    );
    let stewart = names(&StewartSpec::from(presets::wolf_shoham_stewart_s4_1()));
    assert_eq!(stewart, STEWART_VARIABLES[..4]);
    assert_eq!(STEWART_VARIABLES[4..], ["x", "y", "z"]);
}
