//! The criterion benches of pkm (one target, one module per area). Numbers go to
//! `docs/performance.md`.

use criterion::{criterion_group, criterion_main};

mod indices;
mod linear_delta;

criterion_group!(
    benches,
    indices::condition_number,
    linear_delta::eta_of_one_design
);
criterion_main!(benches);
