//! The settings as study files hold them: the tables of the example studies read into the
//! library's settings, omitted keys take today's defaults, unknown keys are refused, values
//! are checked by `validate` (not by reading), and JSON round trips.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_optimizers::{
    AugmentedLagrangianSettings, CharacteristicScale, GridAxis, GridSearch, LatticeLevel,
    LmSettings, Multistart, RefinementSettings, Sense, kkt::KktSettings,
};
use serde::de::DeserializeOwned;
use std::path::Path;

/// The table at `path` (e.g. `["optimize", "solver"]`) of the example study `name`.
fn table<T: DeserializeOwned>(name: &str, path: &[&str]) -> T {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/studies")
        .join(name);
    let text = std::fs::read_to_string(file).unwrap();
    let mut value: toml::Value = toml::from_str(&text).unwrap();
    for key in path {
        value = value
            .get(*key)
            .cloned()
            .unwrap_or_else(|| panic!("{name}: no {key}"));
    }
    value.try_into().unwrap()
}

#[test]
fn the_example_studies_read_into_the_library_settings() {
    let solver: AugmentedLagrangianSettings =
        table("tsai_volume_optimize.toml", &["optimize", "solver"]);
    assert_eq!(
        solver,
        AugmentedLagrangianSettings {
            fd_step: 1e-4,
            tolerance: 1e-8,
            feasibility: 1e-6,
            max_outer: 15,
            max_inner: 100,
            scale: None,
        }
    );
    let starts: Multistart = table("tsai_volume_optimize.toml", &["optimize", "starts"]);
    assert_eq!(starts, Multistart::new(4, 2024));
    let starts: Multistart = table("stewart_task_synthesis.toml", &["task", "starts"]);
    assert_eq!(starts, Multistart::new(20, 2006));
    let starts: Multistart = table("three_upu_singularity.toml", &["task", "starts"]);
    assert_eq!(starts, Multistart::new(16, 44));
}

#[test]
fn omitted_keys_take_the_defaults() {
    let lm: LmSettings = toml::from_str("").unwrap();
    assert_eq!(lm, LmSettings::default());
    let lm: LmSettings = toml::from_str("tolerance = 1e-9").unwrap();
    assert_eq!(
        lm,
        LmSettings {
            tolerance: 1e-9,
            ..LmSettings::default()
        }
    );
    let al: AugmentedLagrangianSettings = toml::from_str("max_outer = 3").unwrap();
    assert_eq!(
        al.max_inner,
        AugmentedLagrangianSettings::default().max_inner
    );
    let refinement: RefinementSettings = toml::from_str("").unwrap();
    assert_eq!(refinement, RefinementSettings::default());
    let check: KktSettings = toml::from_str("step = 1e-3").unwrap();
    assert_eq!(
        check,
        KktSettings {
            step: 1e-3,
            ..KktSettings::default()
        }
    );
    let extra: Multistart = toml::from_str("count = 2\nseed = 1\nextra = [[0.5, 1.0]]").unwrap();
    assert_eq!(extra.total(), 3);
}

#[test]
fn unknown_keys_and_missing_counts_are_refused() {
    assert!(toml::from_str::<LmSettings>("max_iteration = 3").is_err());
    assert!(toml::from_str::<AugmentedLagrangianSettings>("fd = 1e-3").is_err());
    assert!(
        toml::from_str::<Multistart>("count = 2").is_err(),
        "the seed is required"
    );
    assert!(toml::from_str::<Multistart>("count = 2\nseed = 1\nextras = []").is_err());
    assert!(toml::from_str::<LatticeLevel>("step = 0.1").is_err());
}

#[test]
fn values_are_checked_by_validate_not_by_reading() {
    let lm: LmSettings = toml::from_str("tolerance = -1.0").unwrap();
    assert!(lm.validate().is_err());
    let starts: Multistart = toml::from_str("count = 0\nseed = 1").unwrap();
    assert!(starts.validate().is_err());
}

#[test]
fn senses_and_grids_are_snake_case_and_checked_when_read() {
    assert_eq!(
        serde_json::to_string(&Sense::Maximise).unwrap(),
        "\"maximise\""
    );
    assert_eq!(
        serde_json::from_str::<Sense>("\"minimise\"").unwrap(),
        Sense::Minimise
    );
    assert!(serde_json::from_str::<Sense>("\"Minimise\"").is_err());
    let grid = GridSearch::new(vec![GridAxis::new(0.0, 1.0, 5).unwrap(); 2])
        .unwrap()
        .keeping_landscape();
    let json = serde_json::to_string(&grid).unwrap();
    assert_eq!(serde_json::from_str::<GridSearch>(&json).unwrap(), grid);
    let read: GridSearch =
        serde_json::from_str(r#"{"axes": [{"lower": 0, "upper": 1, "n": 3}]}"#).unwrap();
    assert!(!read.keeps_landscape() && read.nodes() == 3);
    for bad in [
        r#"{"axes": []}"#,
        r#"{"axes": [{"lower": 1, "upper": 0, "n": 3}]}"#,
        r#"{"axes": [{"lower": 0, "upper": 1, "n": 0}]}"#,
        r#"{"axes": [{"lower": 0, "upper": 1, "n": 16777216}, {"lower": 0, "upper": 1, "n": 2}]}"#,
    ] {
        assert!(serde_json::from_str::<GridSearch>(bad).is_err(), "{bad}");
    }
}

#[test]
fn settings_round_trip_through_json() {
    let al = AugmentedLagrangianSettings {
        max_outer: 7,
        ..Default::default()
    };
    let json = serde_json::to_string(&al).unwrap();
    assert_eq!(
        serde_json::from_str::<AugmentedLagrangianSettings>(&json).unwrap(),
        al
    );
    let starts = Multistart::new(3, 9).with_extra_starts(vec![vec![0.25, -1.0]]);
    let json = serde_json::to_string(&starts).unwrap();
    assert_eq!(serde_json::from_str::<Multistart>(&json).unwrap(), starts);
}

#[test]
fn a_characteristic_scale_is_a_list_checked_when_read() {
    let lm: LmSettings = toml::from_str("scale = [1e-3, 1e3]").unwrap();
    assert_eq!(lm.scale.as_ref().unwrap().values(), &[1e-3, 1e3]);
    let al: AugmentedLagrangianSettings = toml::from_str("scale = [0.5]").unwrap();
    assert_eq!(al.scale, Some(CharacteristicScale::new(&[0.5]).unwrap()));
    for bad in [
        "scale = []",
        "scale = [1.0, 0.0]",
        "scale = [-1.0]",
        "scale = [nan]",
        "scale = [inf]",
    ] {
        let e = toml::from_str::<LmSettings>(bad).unwrap_err().to_string();
        assert!(e.contains("scale"), "{bad}: {e}");
    }
    // Any number of variables (the scale was once stored inline, at most 32).
    let many = format!("scale = [{}]", vec!["2.5"; 1000].join(", "));
    let al: AugmentedLagrangianSettings = toml::from_str(&many).unwrap();
    assert_eq!(al.scale.unwrap().values(), &[2.5; 1000][..]);
    // Round trip, and no key at all when there is no scale (settings echoed as before).
    let json = serde_json::to_string(&lm).unwrap();
    assert_eq!(serde_json::from_str::<LmSettings>(&json).unwrap(), lm);
    let plain = serde_json::to_string(&AugmentedLagrangianSettings::default()).unwrap();
    assert!(!plain.contains("scale"), "{plain}");
}
