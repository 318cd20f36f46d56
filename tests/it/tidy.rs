//! Tidy checks on the repository itself: documentation stays true to the registry.

use pkm::papers;
use std::path::Path;

fn read_doc(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("docs")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_experiment_id_is_listed_in_reproduce_md() {
    let doc = read_doc("reproduce.md");
    for experiment in papers::all() {
        assert!(
            doc.contains(experiment.id),
            "docs/reproduce.md does not list {}",
            experiment.id
        );
    }
}

#[test]
fn experiment_ids_are_unique() {
    let mut ids: Vec<_> = papers::all().iter().map(|e| e.id).collect();
    let n = ids.len();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), n, "duplicate experiment ids");
}
