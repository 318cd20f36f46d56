//! Table 2 row 4 of Miller 2004 from a study file alone: `pkm sweep` on
//! `crates/pkm-cli/tests/studies/linear_delta_row4_quick.toml` finds the same optimum as the
//! `pkm::papers` experiment (quick rules in both). The facade is a path-only dev-dependency: the
//! command itself does not depend on it, and the facade does not depend on the command.

use clap::Parser;
use pkm::papers::miller2004::linear_delta::table2;
use pkm::papers::{Context, Mode};
use pkm_traits::Silent;
use pkm_workspace_indices::SectionIndexCache;
use std::path::Path;

/// Relative agreement of two evaluations of the same formula with the same inputs.
const SAME: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= SAME * a.abs().max(b.abs()) + 1e-300
}

#[test]
fn linear_delta_row4_study_gives_the_experiments_optimum() {
    let study =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/studies/linear_delta_row4_quick.toml");
    let out = tempfile::tempdir().unwrap();
    let cli = pkm_cli::Cli::parse_from([
        "pkm",
        "sweep",
        study.to_str().unwrap(),
        "--out",
        out.path().to_str().unwrap(),
        "--quiet",
    ]);
    pkm_cli::run(&cli).unwrap();
    let text = std::fs::read_to_string(out.path().join("results.json")).unwrap();
    let results: serde_json::Value = serde_json::from_str(&text).unwrap();
    let context = Context {
        mode: Mode::Quick,
        progress: &Silent,
    };
    let (_, experiment) = table2::row4(&context, &SectionIndexCache::new()).unwrap();
    let optimum = &results["result"]["optimum"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    let names = ["l1_over_yr", "ya_over_yr", "zr_over_yr", "l2_over_l1"];
    for (name, expected) in names.iter().zip(experiment.design) {
        let got = f(&optimum["design"][name]);
        assert!(
            close(got, expected),
            "{name}: study {got}, experiment {expected}"
        );
    }
    assert!(close(f(&optimum["indices"]["eta1"]), experiment.indices[0]));
    assert!(close(f(&optimum["indices"]["eta2"]), experiment.indices[1]));
    assert!(close(f(&optimum["utility"]), experiment.indices[2]));
}
