//! Workspace volume, condition integral η = ∫ 1/κ dW and global condition index GCI = η/W of
//! the Tsai platform (Stamper, Tsai & Walsh 1997) through the generic entry point
//! (`Workspace`: mechanism → velocity Jacobian → 1/κ → estimator), local indices at one pose,
//! then the Stamper experiments with paper vs pkm values.
//! Run: `cargo run --release --example tsai_workspace [full]`.
#![allow(clippy::print_stdout)]

use nalgebra::Vector3;
use pkm::papers::{self, Context, Mode};
use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
use pkm_traits::Silent;
use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, Workspace, local_indices};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let design = Tsai3Dof::new(presets::stamper_max_gci())?;
    // The workspace of the elbow-out branch, without further constraints.
    let workspace = Workspace::new(&design, &[[Elbow::Out; 3]], &[])?;
    let hemisphere = Region::Hemisphere {
        center: Vector3::zeros(),
        radius: design.reach(),
    };
    let points = PointSet::new(
        Domain::new(hemisphere)?,
        Sampler::Sobol { seed: 1 },
        1 << 15,
        8,
    )?;
    let e = workspace.volume_and_eta(&points, &Silent)?;
    println!(
        "W = {:.4} ± {:.4}, η = {:.4} ± {:.4}, GCI = η/W = {:.4}",
        e.volume,
        e.volume_se,
        e.eta.unwrap_or(0.0),
        e.eta_se.unwrap_or(0.0),
        e.gci().unwrap_or(0.0)
    );
    let centre = Vector3::new(0.0, 0.0, 0.5);
    let local = local_indices(&design, &centre, [Elbow::Out; 3])?;
    println!(
        "at {centre:?}: 1/κ = {:.4}, σ_min = {:.4}, σ_max = {:.4}, manipulability = {:.4}",
        local.inverse_condition, local.sigma_min, local.sigma_max, local.manipulability
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
