//! Workspace studies of robot files in their own task space (`[task_space]`): the
//! Stewart–Gough examples `stewart_gough_constant_orientation.toml` (positions at rz = 10°) and
//! `stewart_gough_dexterous.toml` (positions reaching every orientation of tilt ≤ 5°, torsion
//! ±5°, on grids of 10, 39 and 205 orientations), without their singularity-free search, on
//! $4 \times 2^{14}$ Sobol points, through the study library as `pkm workspace` runs them.
//! Throughput is sampled positions per second.

use criterion::{Criterion, Throughput};
use pkm_study::WorkspaceStudy;
use pkm_traits::Silent;

/// The example study `name` with its robot file named by an absolute path and without the
/// singularity-free search.
fn example(name: &str) -> Option<WorkspaceStudy> {
    let root = env!("CARGO_MANIFEST_DIR");
    let text = std::fs::read_to_string(format!("{root}/examples/studies/{name}")).ok()?;
    let text = text
        .replace("\"../robots/", &format!("\"{root}/examples/robots/"))
        .lines()
        .filter(|l| !l.starts_with("singularity_free"))
        .collect::<Vec<_>>()
        .join("\n");
    let mut document: toml::Table = toml::from_str(&text).ok()?;
    let read = |file: &str| std::fs::read_to_string(file);
    pkm_study::schema::robot_file::RobotFileSpec::resolve_in_document(&mut document, read).ok()?;
    pkm_study::from_deserializer(toml::Value::Table(document)).ok()
}

pub(crate) fn stewart_gough(c: &mut Criterion) {
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
