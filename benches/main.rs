//! The criterion benches of pkm (one target, one module per area). Numbers go to
//! `docs/performance.md`.

use criterion::{criterion_group, criterion_main};

mod dynamics;
mod indices;
mod integrators;

criterion_group!(
    benches,
    indices::condition_number,
    dynamics::inverse_dynamics,
    dynamics::forward_cycle,
    integrators::harmonic_oscillator
);
criterion_main!(benches);
