//! NUWAR on Miller's elliptical pick-and-place cycle: inverse dynamics by Hamilton's three steps
//! and by Lagrange, then forward dynamics (eqs. 16–19) fed with the Hamilton torques.
//!
//! `cargo run --example nuwar_pick_and_place`
#![allow(clippy::print_stdout)]

use pkm::dynamics_hamilton::forward::{ForwardForm, HamiltonForm, SampledTorques};
use pkm::dynamics_hamilton::inverse::{self, Accelerations, Differencing};
use pkm::dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm::integrators::{AdaptiveSettings, DormandPrince54, OutputTimes, integrate};
use pkm::mechanisms::{Placement, RotaryDelta, presets};
use pkm::papers::miller2004::dynamics::{CycleReading, pick_and_place};
use pkm::traits::Silent;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let nuwar = RotaryDelta::new(presets::nuwar(Placement::canonical()))?;
    let model = ExtendedModel::new(nuwar, &MassParameters::miller2004())?;
    let cycle = pick_and_place(0.5, CycleReading::RoundTrip)?;
    let dt = 1e-3;
    let samples = inverse::sample(&model, &cycle, dt)?;
    let hamilton = inverse::hamilton(&model, &samples, Differencing::Central)?;
    let lagrange = inverse::lagrange(&model, &samples, Accelerations::Exact)?;
    let peak = |tau: &[nalgebra::Vector3<f64>]| tau.iter().map(|t| t.amax()).fold(0.0, f64::max);
    println!(
        "max |tau|: Hamilton {:.2} N m, Lagrange {:.2} N m",
        peak(&hamilton),
        peak(&lagrange)
    );

    let torques = SampledTorques::new(dt, hamilton)?;
    let form = HamiltonForm::new(&model, |t| torques.at(t), 20.0)?;
    let z0 = form.initial_state(&samples[0].1.q, &samples[0].1.qd);
    let settings = AdaptiveSettings::default()
        .with_rtol(1e-9)?
        .with_atol(1e-12)?;
    let run = integrate(
        &form,
        &mut DormandPrince54::new(settings),
        (0.0, 0.5),
        &z0,
        &OutputTimes::Uniform(dt),
        &Silent,
    )?;
    let error = run
        .times
        .iter()
        .zip(&run.states)
        .map(|(t, z)| (z.fixed_rows::<3>(0) - cycle.sample(*t).p).norm())
        .fold(0.0, f64::max);
    let drift = run.states.iter().map(|z| form.drift(z)).fold(0.0, f64::max);
    println!(
        "forward run: max position error {error:.2e} m, max drift {drift:.2e} m, {} RHS evaluations",
        run.stats.evaluations
    );
    Ok(())
}
