//! The study layer's sweep against the paper experiment it reproduces: Table 2 row 4 of
//! Miller 2004 from a study file alone gives the same optimum as the `pkm::papers` experiment
//! (quick rules in both).

use pkm::papers::miller2004::linear_delta::table2;
use pkm::papers::{Context, Mode};
use pkm_study::{GridRun, GridStudy, Shard, from_toml_str, sweep};
use pkm_traits::Silent;
use pkm_workspace_indices::SectionIndexCache;

/// Relative agreement of two evaluations of the same formula with the same inputs.
const SAME: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= SAME * a.abs().max(b.abs()) + 1e-300
}

#[test]
fn linear_delta_row4_study_gives_the_experiments_optimum() {
    let text = include_str!("../../../pkm-cli/tests/studies/linear_delta_row4_quick.toml");
    let study: GridStudy = from_toml_str(text).unwrap();
    let GridRun::Complete(result) = sweep(&study, Shard::WHOLE, &Silent).unwrap().result else {
        panic!("a whole grid gives the complete result");
    };
    let context = Context {
        mode: Mode::Quick,
        progress: &Silent,
    };
    let (_, experiment) = table2::row4(&context, &SectionIndexCache::new()).unwrap();
    let optimum = &result.optimum;
    let names = ["l1_over_yr", "ya_over_yr", "zr_over_yr", "l2_over_l1"];
    for (name, expected) in names.iter().zip(experiment.design) {
        let got = optimum.design[*name];
        assert!(
            close(got, expected),
            "{name}: study {got}, experiment {expected}"
        );
    }
    assert!(close(optimum.indices["eta1"], experiment.indices[0]));
    assert!(close(optimum.indices["eta2"], experiment.indices[1]));
    assert!(close(optimum.utility, experiment.indices[2]));
}
