//! Monte Carlo estimates are bit-identical for 1, 2 and 8 rayon threads.

use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
use pkm_traits::Silent;
use pkm_workspace_indices::{Sampler, Workspace};

fn stamper_estimate_bits() -> [u64; 4] {
    let design = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    let points = Sampler::MonteCarlo { seed: 7 }
        .unit_hemisphere_points(50_000)
        .unwrap();
    let e = Workspace::new(&design, &[[Elbow::Out; 3]], &[])
        .unwrap()
        .hemisphere_estimate(&points, design.reach(), &Silent)
        .unwrap();
    [e.volume, e.volume_se, e.eta, e.eta_se].map(f64::to_bits)
}

#[test]
fn stamper_volume_and_gci_are_bit_identical_for_1_2_8_threads() {
    let runs: Vec<[u64; 4]> = [1, 2, 8]
        .into_iter()
        .map(|k| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(k)
                .build()
                .unwrap()
                .install(stamper_estimate_bits)
        })
        .collect();
    assert!(runs[0][2] != 0, "vacuous: zero η");
    assert_eq!(runs[0], runs[1]);
    assert_eq!(runs[0], runs[2]);
}
