//! The criterion benches of pkm (one target, one module per area). Numbers go to
//! `docs/performance.md`.

use criterion::{criterion_group, criterion_main};

mod indices;
mod stamper;

criterion_group!(benches, indices::condition_number, stamper::gci_kernel);
criterion_main!(benches);
