//! Working-mode labels (`RobotModel::mode_label`, `RobotModel::working_mode`): one `+` or `-`
//! per actuated leg, read back to the same mode for every mode of every example file; `home` is the
//! home mode; anything else is refused at its key.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::{all_files, robot};
use pkm_robot_file::RobotFileError;

#[test]
fn every_mode_label_reads_back_to_its_mode() {
    let mut checked = 0;
    for file in all_files() {
        let model = robot(&file);
        for mode in model.working_modes() {
            let label = model.mode_label(mode);
            let actuated_legs = model
                .legs()
                .iter()
                .filter(|l| !l.actuators.is_empty())
                .count();
            assert_eq!(label.chars().count(), actuated_legs, "{file}");
            assert_eq!(
                model.working_mode("modes[0]", &label).unwrap(),
                mode,
                "{file} {label}"
            );
            checked += 1;
        }
        assert_eq!(
            model.working_mode("modes[0]", "home").unwrap(),
            model.home_mode()
        );
    }
    assert!(checked > 20, "vacuous: {checked}");
}

#[test]
fn a_bad_label_is_refused_at_its_key() {
    let model = robot("tsai.toml");
    for bad in ["", "++", "++++", "+x-", "out", "HOME"] {
        match model.working_mode("modes[3]", bad) {
            Err(RobotFileError::Invalid {
                key, requirement, ..
            }) => {
                assert_eq!(key, "modes[3]");
                assert!(requirement.contains("3 legs"), "{requirement}");
            }
            other => panic!("{bad:?}: {other:?}"),
        }
    }
}
