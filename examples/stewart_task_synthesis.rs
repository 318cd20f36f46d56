//! Task-based pose synthesis for a Stewart–Gough platform (Wolf & Shoham §4.1): find the pose
//! in a box that maximises $F = \sum_i (L_i \wedge \chi)^2$ for your own task twist χ.
//!
//! Adapt `design`, `twist` and the bounds below; run with
//! `cargo run --release --example stewart_task_synthesis`.
#![allow(clippy::print_stdout)]

use nalgebra::Vector3;
use pkm_mechanisms::{StewartDesign, StewartTaskProblem};
use pkm_optimizers::{LmSettings, Multistart, Sense, multistart_levenberg_marquardt};
use pkm_screw_theory::Twist;
use pkm_traits::{Bounds, Silent};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // Base radius x1, platform radius x2 (cm), base and platform joint separations x3, x4
    // (printed in degrees; the design holds radians).
    let design = StewartDesign::from_deg(12.0, 8.0, 30.0, 8.0);
    // The task: a screw with axis direction s through s0 and pitch λ, χ = [s ; s0 × s + λ s].
    let s = Vector3::new(2.0, 2.0, 1.0).normalize();
    let s0 = Vector3::new(2.0, 3.0, 6.0);
    let twist = Twist::new(s, s0.cross(&s) + s * 1.0);
    let xy = Bounds::new(-10.0, 10.0)?;
    let problem = StewartTaskProblem::new(
        design,
        Vector3::new(0.0, 0.0, 35.0),
        Vector3::zeros(),
        twist,
    )?
    .free_position(0, xy)?
    .free_position(1, xy)?
    .free_position(2, Bounds::new(20.0, 50.0)?)?
    .free_rotation(30f64.to_radians())?;
    let best = multistart_levenberg_marquardt(
        &problem,
        Sense::Maximise,
        &Multistart::new(32, 7),
        &LmSettings::default(),
        &Silent,
    )?
    .best;
    let (_, pose) = problem.evaluate(&best.design)?;
    let w = pose.rotation.scaled_axis();
    println!("F = {:.3}", best.value);
    println!("p = {:.3?} cm", pose.translation.vector.as_slice());
    println!(
        "rotation vector α n = {:.3?} deg",
        (w * 180.0 / std::f64::consts::PI).as_slice()
    );
    println!(
        "free gradient max = {:.2e}, reduced Hessian eigenvalues = {:.3?}",
        best.free_gradient_norm(),
        best.reduced_hessian_eigenvalues
    );
    Ok(())
}
