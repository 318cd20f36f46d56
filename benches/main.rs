//! The criterion benches of pkm (one target, one module per area). Numbers go to
//! `docs/performance.md`.

use criterion::{criterion_group, criterion_main};

mod indices;
mod integrators;

criterion_group!(
    benches,
    indices::condition_number,
    integrators::harmonic_oscillator
);
criterion_main!(benches);
