//! The criterion benches of pkm (one target, one module per area). Numbers go to
//! `docs/performance.md`.

#![allow(
    missing_docs,
    reason = "criterion_group! defines the undocumented `benches` function"
)]

use criterion::{criterion_group, criterion_main};

mod delta_kernel;
mod dynamics;
mod indices;
mod integrators;
mod linear_delta;
mod screw;
mod stamper;
mod wolf;
mod workspace;

criterion_group!(
    benches,
    indices::condition_number,
    integrators::harmonic_oscillator,
    linear_delta::eta_of_one_design,
    screw::screw,
    stamper::gci_kernel,
    stamper::gci_kernel_batch,
    delta_kernel::delta_kernel,
    dynamics::inverse_dynamics,
    dynamics::forward_cycle,
    wolf::section_4_1,
    workspace::membership_kernel,
);
criterion_main!(benches);
