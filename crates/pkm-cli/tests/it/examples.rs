//! Every study of `examples/studies/` is a valid study of its command (its grid, indices and
//! constraints checked); the studies themselves run in `studies.rs` in their quick versions.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::example;
use pkm_cli::study;
use pkm_study::{
    AssemblyStudy, DynamicsStudy, GridStudy, OptimizeStudy, Shard, StudyError, TaskStudy,
    WorkspaceStudy,
};

/// A progress reporter that has already been asked to stop: a study that gets past its checks
/// stops at its first computation.
struct Stop;

impl pkm_traits::Progress for Stop {
    fn is_cancelled(&self) -> bool {
        true
    }
}

/// The nodes of the grid of the example study `name`, after every check of `kind`.
fn checked_grid(name: &str, kind: &str) -> usize {
    let (_, grid): (String, GridStudy) = study::load_study(&example(name)).unwrap();
    let run = match kind {
        "sweep" => pkm_study::sweep(&grid, Shard::WHOLE, &Stop).map(|_| ()),
        _ => pkm_study::pareto(&grid, Shard::WHOLE, &Stop).map(|_| ()),
    };
    assert!(matches!(run, Err(StudyError::Cancelled)), "{name}: {run:?}");
    pkm_study::grid::prepare(&grid, &[], &pkm_traits::Silent)
        .unwrap()
        .grid
        .len()
}

#[test]
fn the_example_studies_are_valid() {
    for name in [
        "nuwar_workspace.toml",
        "three_upu_workspace.toml",
        "stewart_gough_workspace.toml",
        "robot_file_workspace.toml",
        "tricept_workspace.toml",
        "three_prs_reachable.toml",
        "exechon_reachable.toml",
        "four_rrr_reachable.toml",
        "three_ppsr_constant_orientation.toml",
        "five_bar_reachable.toml",
        "stewart_gough_constant_orientation.toml",
        "stewart_gough_dexterous.toml",
        "three_rpr_constant_orientation.toml",
        "hexa_orientation.toml",
        "agile_eye_orientation.toml",
    ] {
        let _: (String, WorkspaceStudy) = study::load_study(&example(name)).unwrap();
    }
    for name in ["tsai_volume_gci.toml", "linear_delta_table2_row4.toml"] {
        assert!(checked_grid(name, "sweep") > 10, "{name}");
    }
    assert!(checked_grid("linear_delta_pareto.toml", "pareto") > 1000);
    assert_eq!(checked_grid("three_prs_sweep.toml", "sweep"), 5);
    for name in [
        "tsai_volume_optimize.toml",
        "symmetric_three_rpr_optimize.toml",
    ] {
        let _: (String, OptimizeStudy) = study::load_study(&example(name)).unwrap();
    }
    for name in [
        "stewart_task_synthesis.toml",
        "three_upu_singularity.toml",
        "three_prs_task_synthesis.toml",
    ] {
        let (_, task): (String, TaskStudy) = study::load_study(&example(name)).unwrap();
        let run = pkm_study::task(&task, &Stop);
        assert!(matches!(run, Err(StudyError::Cancelled)), "{name}: {run:?}");
    }
    for name in [
        "stewart_gough_dynamics.toml",
        "rotary_delta_file_dynamics.toml",
        "three_prs_dynamics.toml",
        "hexa_dynamics.toml",
    ] {
        let (_, study): (String, DynamicsStudy) = study::load_study(&example(name)).unwrap();
        let run = pkm_study::dynamics(&study, &Stop);
        assert!(matches!(run, Err(StudyError::Cancelled)), "{name}: {run:?}");
    }
    let (_, modes): (String, AssemblyStudy) =
        study::load_study(&example("dietmaier_assembly_modes.toml")).unwrap();
    let run = pkm_study::assembly(&modes, &Stop);
    assert!(matches!(run, Err(StudyError::Cancelled)), "{run:?}");
    let (_, dynamics): (String, DynamicsStudy) =
        study::load_study(&example("nuwar_dynamics_csv.toml")).unwrap();
    let csv = dynamics
        .trajectory
        .csv
        .expect("the example reads a CSV trajectory");
    assert!(example(&csv).is_file(), "{csv} beside the study");
    let listed: Vec<String> = std::fs::read_dir(example(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    assert_eq!(
        listed.len(),
        30,
        "a new example study needs a check here: {listed:?}"
    );
}
