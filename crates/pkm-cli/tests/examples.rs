//! Every study of `examples/studies/` is a valid study of its command (its grid, indices and
//! constraints checked); the studies themselves run in `studies.rs` in their quick versions.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::example;
use pkm_cli::commands::dynamics::DynamicsStudy;
use pkm_cli::commands::task::TaskStudy;
use pkm_cli::commands::{pareto, sweep};
use pkm_cli::grid::{self, GridStudy};
use pkm_cli::study;
use pkm_study::{OptimizeStudy, WorkspaceStudy};

#[test]
fn the_example_studies_are_valid() {
    for name in [
        "nuwar_workspace.toml",
        "three_upu_workspace.toml",
        "stewart_gough_workspace.toml",
    ] {
        let _: (String, WorkspaceStudy) = study::load_study(&example(name)).unwrap();
    }
    for name in ["tsai_volume_gci.toml", "linear_delta_table2_row4.toml"] {
        let file: study::StudyFile<GridStudy> = study::load(&example(name)).unwrap();
        let requested = sweep::requested_indices(&file).unwrap();
        let prepared = grid::prepare(&file, &requested).unwrap();
        assert!(prepared.grid.len() > 10, "{name}");
    }
    let file: study::StudyFile<GridStudy> =
        study::load(&example("linear_delta_pareto.toml")).unwrap();
    let prepared = grid::prepare(&file, &pareto::requested(&file).unwrap()).unwrap();
    assert!(prepared.grid.len() > 1000);
    let _: (String, OptimizeStudy) =
        study::load_study(&example("tsai_volume_optimize.toml")).unwrap();
    for name in ["stewart_task_synthesis.toml", "three_upu_singularity.toml"] {
        let _: study::StudyFile<TaskStudy> = study::load(&example(name)).unwrap();
    }
    let _: study::StudyFile<DynamicsStudy> =
        study::load(&example("nuwar_dynamics_csv.toml")).unwrap();
    let listed: Vec<String> = std::fs::read_dir(example(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    assert_eq!(
        listed.len(),
        10,
        "a new example study needs a check here: {listed:?}"
    );
}
