//! Workspace volume and global condition index of the Tsai platform (Stamper, Tsai & Walsh
//! 1997), then the Stamper experiments with paper vs pkm values.
//! Run: `cargo run --release --example tsai_workspace [full]`.
#![allow(clippy::print_stdout)]

use pkm::papers::{self, Context, Mode};
use pkm_mechanisms::{Tsai3Dof, presets};
use pkm_traits::Silent;
use pkm_workspace_indices::{Sampler, hemisphere_estimate, inverse_condition_number_3x3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let design = Tsai3Dof::new(presets::stamper_max_gci())?;
    let points = Sampler::MonteCarlo { seed: 1 }.unit_hemisphere_points(200_000)?;
    let e = hemisphere_estimate(&points, design.reach(), &Silent, |p| {
        design
            .jacobian_eq7(p)
            .map(|j| inverse_condition_number_3x3(&j))
    })?;
    println!(
        "W = {:.4} ± {:.4}, GCI = {:.4} ± {:.4}",
        e.volume, e.volume_se, e.gci, e.gci_se
    );
    let mode = if std::env::args().any(|a| a == "full") {
        Mode::Full
    } else {
        Mode::Quick
    };
    let context = Context {
        mode,
        progress: &Silent,
    };
    for experiment in papers::all()
        .into_iter()
        .filter(|e| e.matches("stamper1997"))
    {
        for row in (experiment.run)(&context)?.comparisons {
            println!(
                "{} {} = {:.5} (paper {:?}, tol {:?}) {:?} {}",
                row.id,
                row.quantity,
                row.value,
                row.paper_value,
                row.tolerance,
                row.verdict,
                row.note
            );
        }
    }
    Ok(())
}
