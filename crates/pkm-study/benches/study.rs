//! Workspace studies of robot files in their own task space (`[task_space]`): the
//! Stewart–Gough examples `stewart_gough_constant_orientation.toml` (positions at rz = 10°) and
//! `stewart_gough_dexterous.toml` (positions reaching every orientation of tilt ≤ 5°, torsion
//! ±5°, on grids of 10, 39 and 205 orientations), without their singularity-free search, on
//! $4 \times 2^{14}$ Sobol points, through the study library as `pkm workspace` runs them.
//! Throughput is sampled positions per second.

#![allow(
    missing_docs,
    reason = "criterion_group! defines the undocumented `benches` function"
)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pkm_study::WorkspaceStudy;
use pkm_study::load::Format;
use pkm_traits::Silent;

/// The example study `name` without its singularity-free search, read by the study loader as
/// `pkm workspace` reads it.
fn example(name: &str) -> Option<WorkspaceStudy> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/studies")
        .join(name);
    let text = std::fs::read_to_string(&path).ok()?;
    let text = text
        .lines()
        .filter(|l| !l.starts_with("singularity_free"))
        .collect::<Vec<_>>()
        .join("\n");
    let reader = pkm_study::load::Directory::of_study(&path);
    let (_, loaded) = pkm_study::load::load(name, text, Format::Toml, &reader).ok()?;
    Some(loaded.study)
}

fn stewart_gough(c: &mut Criterion) {
    let mut group = c.benchmark_group("task_space/stewart_gough");
    group.sample_size(10);
    for kind in ["constant_orientation", "dexterous"] {
        let Some(study) = example(&format!("stewart_gough_{kind}.toml")) else {
            return;
        };
        let points = u64::from(study.sampling.replicates) * study.sampling.points;
        group.throughput(Throughput::Elements(points));
        group.bench_function(kind, |b| b.iter(|| pkm_study::workspace(&study, &Silent)));
    }
    group.finish();
}

criterion_group!(benches, stewart_gough);
criterion_main!(benches);
