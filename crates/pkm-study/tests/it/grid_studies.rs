//! The grid studies (`sweep`, `pareto`, `merge`) called directly, their numbers checked against
//! the same computation done directly through the library; shards merged bit for bit; every
//! new setting check placed at its key path.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::Vector3;
use pkm_mechanisms::{
    Elbow, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios, Tsai3Dof, TsaiDesign,
};
use pkm_study::outcome::Artifact;
use pkm_study::{
    GridKind, GridRun, GridStudy, Merged, Outcome, ParetoResult, Shard, StudyError, SweepResult,
    from_json_str, from_toml_str, merge, pareto, sweep,
};
use pkm_traits::Silent;
use pkm_workspace_indices::{
    Domain, Eta1Rule, IndexError, PointSet, Region, Sampler, SectionIndex, SectionIndices,
    Workspace,
};

/// Relative agreement of two evaluations of the same formula with the same inputs.
const SAME: f64 = 1e-12;

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-300
}

const TSAI: &str = r#"title = "Tsai platform (quick)"
[mechanism.tsai]
a = 0.44
b = 0.56
[sampling]
seed = 7
points = 2048
replicates = 2
region = { hemisphere = { center = [0.0, 0.0, 0.0], radius = 1.5 } }
[[variables]]
name = "a"
from = 0.3
to = 0.7
steps = 3
[[variables]]
name = "b"
from = 0.4
to = 0.8
steps = 3
[sweep]
objective = { gci = 1.0, volume = 0.5 }
report = ["eta"]
[[sweep.refine]]
step = 0.05
half_width = 1
"#;

const LINEAR_DELTA: &str = r#"[mechanism.linear_delta]
l1_over_yr = 2.0
ya_over_yr = 0.0
zr_over_yr = 0.0
l2_over_l1 = 0.63
[indices]
eta1_points = 8
[[variables]]
name = "l1_over_yr"
from = 1.4
to = 2.7
step = 0.1
[[variables]]
name = "zr_over_yr"
from = -0.5
to = 0.5
step = 0.25
[[variables]]
name = "l2_over_l1"
from = 0.6
to = 1.8
step = 0.2
[pareto]
objectives = ["eta1", "eta2"]
weights = [[1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]
"#;

fn study(text: &str) -> GridStudy {
    from_toml_str(text).unwrap()
}

fn complete<R>(run: Outcome<GridRun<R>>) -> (R, Outcome<()>) {
    let rest = Outcome {
        result: (),
        artifacts: run.artifacts,
        summary: run.summary,
    };
    match run.result {
        GridRun::Complete(r) => (r, rest),
        GridRun::Part(_) => panic!("a whole grid gives the complete result"),
    }
}

/// A table artifact by name.
fn table<'a>(outcome: &'a Outcome<()>, name: &str) -> &'a pkm_study::Table {
    outcome
        .artifacts
        .iter()
        .find_map(|a| match a {
            Artifact::Table { name: n, table } if n == name => Some(table),
            _ => None,
        })
        .unwrap()
}

/// A cross-section index of the Linear Delta `[L1/YR, YA/YR, ZR/YR, L2/L1]` (YR = 1),
/// straight from the library.
fn section_index(design: &[f64; 4], index: SectionIndex) -> Result<f64, IndexError> {
    let ratios = LinearDeltaRatios::from_slice(design);
    let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 })?;
    SectionIndices::new(&delta, LinearDeltaMode::PAPER).value(index)
}

#[test]
fn tsai_sweep_matches_the_library_and_refines_upwards() {
    let (result, outcome): (SweepResult, _) =
        complete(sweep(&study(TSAI), Shard::WHOLE, &Silent).unwrap());
    let domain = Domain::new(Region::Hemisphere {
        center: Vector3::zeros(),
        radius: 1.5,
    })
    .unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 7 }, 2048, 2).unwrap();
    let landscape = table(&outcome, "landscape.csv");
    let header = [
        "node",
        "a",
        "b",
        "volume",
        "eta",
        "gci",
        "utility",
        "infeasible",
    ];
    assert_eq!(landscape.header, header);
    let column = |name: &str| landscape.column(name).unwrap();
    let (a, b, volume, eta, gci) = (
        column("a"),
        column("b"),
        column("volume"),
        column("eta"),
        column("gci"),
    );
    assert_eq!(a.len(), 9);
    let mut best: Option<(usize, f64)> = None;
    for k in 0..9 {
        let (a, b) = (a[k].unwrap(), b[k].unwrap());
        let tsai = Tsai3Dof::new(TsaiDesign::from_deg(a, b, 0.0, 0.0, 120.0, 240.0)).unwrap();
        let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[]).unwrap();
        let e = ws.volume_and_eta(&points, &Silent).unwrap();
        assert!(close(volume[k].unwrap(), e.volume, SAME));
        assert!(close(eta[k].unwrap(), e.eta.unwrap(), SAME));
        assert!(close(gci[k].unwrap(), e.gci().unwrap(), SAME));
        let u = e.gci().unwrap() + 0.5 * e.volume;
        if best.is_none_or(|(_, b)| u > b) {
            best = Some((k, u));
        }
    }
    let (node, u) = best.unwrap();
    assert_eq!(result.grid_optimum.0, node);
    assert!(close(result.grid_optimum.1.utility, u, SAME));
    let refined = result.optimum.utility;
    assert!(refined >= u, "refinement never loses: {refined} < {u}");
    assert!(result.refinement_evaluations > 0);
    let names: Vec<String> = outcome
        .artifacts
        .iter()
        .map(|a| match a {
            Artifact::Table { name, .. } | Artifact::Chart { name, .. } => name.clone(),
            Artifact::Robot { .. } => "robot".into(),
        })
        .collect();
    assert_eq!(
        names,
        [
            "landscape.csv",
            "heatmap-a-b.csv",
            "heatmap-a-b.svg",
            "robot"
        ]
    );
}

#[test]
fn linear_delta_pareto_front_and_weight_ranges_match_a_brute_force() {
    let (result, outcome): (ParetoResult, _) =
        complete(pareto(&study(LINEAR_DELTA), Shard::WHOLE, &Silent).unwrap());
    let landscape = table(&outcome, "landscape.csv");
    assert_eq!(
        landscape.header[1..4],
        ["l1_over_yr", "zr_over_yr", "l2_over_l1"]
    );
    let column = |name: &str| landscape.column(name).unwrap();
    let (l1, zr, l2) = (
        column("l1_over_yr"),
        column("zr_over_yr"),
        column("l2_over_l1"),
    );
    let (eta1, eta2) = (column("eta1"), column("eta2"));
    // (node, η1, η2) of every feasible node, straight from the library.
    let mut nodes: Vec<(usize, f64, f64)> = Vec::new();
    for k in 0..l1.len() {
        let design = [l1[k].unwrap(), 0.0, zr[k].unwrap(), l2[k].unwrap()];
        let e1 = section_index(&design, SectionIndex::Eta1(Eta1Rule::Quadrature(8)));
        let (Ok(e1), Ok(e2)) = (e1, section_index(&design, SectionIndex::Eta2)) else {
            assert!(
                eta1[k].is_none(),
                "infeasible for the library, not for the study"
            );
            continue;
        };
        assert!(close(eta1[k].unwrap(), e1, SAME) && close(eta2[k].unwrap(), e2, SAME));
        nodes.push((k, e1, e2));
    }
    assert!(nodes.len() > 400);
    let dominated = |&(_, a1, a2): &(usize, f64, f64)| {
        nodes
            .iter()
            .any(|&(_, b1, b2)| b1 >= a1 && b2 >= a2 && (b1 > a1 || b2 > a2))
    };
    let expected: Vec<usize> = nodes
        .iter()
        .filter(|n| !dominated(n))
        .map(|n| n.0)
        .collect();
    let got: Vec<usize> = result.front.iter().map(|p| p.node).collect();
    assert_eq!(got, expected);
    // Whichever design maximises w·η1 + (1 − w)·η2 has a weight range that holds w.
    for k in 0..=40 {
        let w = f64::from(k) / 40.0;
        let u = |&(_, e1, e2): &(usize, f64, f64)| w * e1 + (1.0 - w) * e2;
        let best = nodes.iter().max_by(|a, b| u(a).total_cmp(&u(b))).unwrap();
        let p = result.front.iter().find(|p| p.node == best.0).unwrap();
        let (lo, hi) = p.weight_range.unwrap();
        assert!(lo <= w + 1e-9 && w <= hi + 1e-9, "w = {w}: node {}", best.0);
    }
    // The weighting (1, 1) is the front's design at w = 1/2.
    let equal = result.weighted_optima[0].node;
    let p = result.front.iter().find(|p| p.node == equal).unwrap();
    let (lo, hi) = p.weight_range.unwrap();
    assert!(lo <= 0.5 && 0.5 <= hi);
}

/// Regression (issue 17): the Linear Delta's η1/η2 were memoised per design rounded to 1e-6 and
/// computed at the rounded design, so a sweep whose nodes were closer than that reported one
/// node's values for its neighbours. Nodes 1e-9 apart now each get their own values, the
/// library's at exactly that node.
#[test]
fn a_linear_delta_sweep_with_nodes_1e_9_apart_gives_each_node_its_own_indices() {
    let text = "[mechanism.linear_delta]\n\
         l1_over_yr = 2.0\nya_over_yr = 0.0\nzr_over_yr = 0.0\nl2_over_l1 = 0.63\n\
         [indices]\neta1_points = 8\n\
         [[variables]]\nname = \"l2_over_l1\"\nfrom = 0.63\nto = 0.630000004\nsteps = 5\n\
         [sweep]\nobjective = { eta1 = 1.0, eta2 = 1.0 }\n";
    let (_, outcome) = complete(sweep(&study(text), Shard::WHOLE, &Silent).unwrap());
    let landscape = table(&outcome, "landscape.csv");
    let column = |name: &str| landscape.column(name).unwrap();
    let (l2, eta1, eta2) = (column("l2_over_l1"), column("eta1"), column("eta2"));
    assert_eq!(l2.len(), 5);
    let mut distinct = Vec::new();
    for k in 0..5 {
        let design = [2.0, 0.0, 0.0, l2[k].unwrap()];
        let library = |index| section_index(&design, index).unwrap().to_bits();
        let eta1_rule = SectionIndex::Eta1(Eta1Rule::Quadrature(8));
        assert_eq!(eta1[k].unwrap().to_bits(), library(eta1_rule), "node {k}");
        assert_eq!(
            eta2[k].unwrap().to_bits(),
            library(SectionIndex::Eta2),
            "node {k}"
        );
        distinct.push(eta1[k].unwrap().to_bits());
    }
    distinct.dedup();
    assert_eq!(distinct.len(), 5, "nodes 1e-9 apart share an η1");
}

/// The parts of a run split in `count`, each through JSON as a front end would keep it.
fn parts<R>(
    run: impl Fn(Shard) -> Result<Outcome<GridRun<R>>, StudyError>,
    count: usize,
) -> Vec<pkm_study::ShardResult> {
    (1..=count)
        .rev()
        .map(|index| match run(Shard { index, count }).unwrap().result {
            GridRun::Part(p) => {
                let json = serde_json::to_string(&p).unwrap();
                serde_json::from_str(&json).unwrap()
            }
            GridRun::Complete(_) => panic!("a part of a split grid"),
        })
        .collect()
}

#[test]
fn split_studies_merge_into_the_single_run_bit_for_bit() {
    let tsai = study(TSAI);
    let single = sweep(&tsai, Shard::WHOLE, &Silent).unwrap();
    let shards = parts(|s| sweep(&tsai, s, &Silent), 3);
    let merged = merge(&tsai, GridKind::Sweep, shards, &Silent).unwrap();
    assert!(matches!(merged.result, Merged::Sweep(_)));
    let json = |v: &dyn erased::Json| v.json();
    assert_eq!(json(&single.result), json(&merged.result));
    assert_eq!(single.summary, merged.summary);
    assert_eq!(
        format!("{:?}", single.artifacts),
        format!("{:?}", merged.artifacts)
    );

    let delta = study(LINEAR_DELTA);
    let single = pareto(&delta, Shard::WHOLE, &Silent).unwrap();
    let shards = parts(|s| pareto(&delta, s, &Silent), 2);
    let merged = merge(&delta, GridKind::Pareto, shards, &Silent).unwrap();
    assert_eq!(json(&single.result), json(&merged.result));
    assert_eq!(
        format!("{:?}", single.artifacts),
        format!("{:?}", merged.artifacts)
    );
}

/// Serialising results of different types to compare them.
mod erased {
    pub(super) trait Json {
        fn json(&self) -> String;
    }
    impl<T: serde::Serialize> Json for T {
        fn json(&self) -> String {
            serde_json::to_string(self).unwrap()
        }
    }
}

#[test]
fn merge_refuses_an_incomplete_mixed_or_foreign_set() {
    let tsai = study(TSAI);
    let mut shards = parts(|s| sweep(&tsai, s, &Silent), 3);
    let err = |parts, kind| merge(&tsai, kind, parts, &Silent).unwrap_err().to_string();
    assert!(err(Vec::new(), GridKind::Sweep).contains("no shard"));
    let two = shards[1..].to_vec();
    assert!(err(two, GridKind::Sweep).contains("expected shards 1..=3"));
    let twice = vec![shards[0].clone(), shards[0].clone(), shards[1].clone()];
    assert!(err(twice, GridKind::Sweep).contains("expected shards 1..=3"));
    let other = parts(|s| sweep(&tsai, s, &Silent), 2);
    let mixed = vec![shards[0].clone(), shards[1].clone(), other[0].clone()];
    assert!(err(mixed, GridKind::Sweep).contains("one run"));
    // The sweep's shards are not a Pareto study's (no [pareto] section).
    let e = merge(&tsai, GridKind::Pareto, shards.clone(), &Silent).unwrap_err();
    assert_eq!(e.path().map(ToString::to_string).as_deref(), Some("pareto"));
    shards[0].outcomes.pop();
    assert!(err(shards, GridKind::Sweep).contains("should hold nodes"));
}

/// A progress reporter that has already been asked to stop.
struct Stop;

impl pkm_traits::Progress for Stop {
    fn is_cancelled(&self) -> bool {
        true
    }
}

/// The key path of the error of a sweep (or Pareto study) of `text`, checked before any node
/// is evaluated (the progress reporter is already cancelled, so a computation would say so).
fn rejected_at(text: &str, kind: GridKind) -> String {
    let study: GridStudy = from_toml_str(text).unwrap();
    let cancelled = Stop;
    let e = match kind {
        GridKind::Sweep => sweep(&study, Shard::WHOLE, &cancelled).map(|_| ()),
        GridKind::Pareto => pareto(&study, Shard::WHOLE, &cancelled).map(|_| ()),
    };
    match e {
        Err(e) => e
            .path()
            .map_or_else(|| format!("no path: {e}"), ToString::to_string),
        Ok(()) => "accepted".into(),
    }
}

#[test]
fn every_setting_is_checked_before_any_computation_and_named_by_its_key() {
    let sweep_of = |extra: &str| format!("{TSAI}{extra}");
    let refine = sweep_of("[[sweep.refine]]\nstep = -0.01\nhalf_width = 2\n");
    assert_eq!(
        rejected_at(&refine, GridKind::Sweep),
        "sweep.refine[1].step"
    );
    let points = sweep_of("[[sweep.refine]]\nstep = 0.01\nhalf_width = 2\neta1_points = 0\n");
    assert_eq!(
        rejected_at(&points, GridKind::Sweep),
        "sweep.refine[1].eta1_points"
    );
    let map = sweep_of("[[sweep.heatmaps]]\nx = \"a\"\ny = \"c\"\n");
    assert_eq!(rejected_at(&map, GridKind::Sweep), "sweep.heatmaps[0].y");
    let eta1 = TSAI.replace("[sweep]\n", "[sweep]\nreport = [\"eta\", \"eta1\"]\n");
    let eta1 = eta1.replace("report = [\"eta\"]\n", "");
    assert_eq!(rejected_at(&eta1, GridKind::Sweep), "sweep.report[1]");
    let no_weight = TSAI.replace("{ gci = 1.0, volume = 0.5 }", "{ gci = 0.0 }");
    assert_eq!(rejected_at(&no_weight, GridKind::Sweep), "sweep.objective");
    let backwards = TSAI.replace("to = 0.8", "to = 0.2");
    assert!(rejected_at(&backwards, GridKind::Sweep).starts_with("variables[1]."));
    let order = LINEAR_DELTA.replace(
        "[indices]\neta1_points = 8",
        "[indices]\neta1_points = 5000",
    );
    assert_eq!(rejected_at(&order, GridKind::Pareto), "indices.eta1_points");
    let weights = LINEAR_DELTA.replace("[0.0, 1.0]]", "[0.0, 1.0, 2.0]]");
    assert_eq!(rejected_at(&weights, GridKind::Pareto), "pareto.weights[2]");
    assert_eq!(rejected_at(TSAI, GridKind::Pareto), "pareto");
    // A valid study passes every check and stops at the first node (cancelled).
    assert_eq!(rejected_at(TSAI, GridKind::Sweep), "no path: cancelled");
}

/// A reporter that is cancelled from the start and records the phases it is told of.
#[derive(Default)]
struct StoppedPhases(std::sync::Mutex<Vec<String>>);

impl pkm_traits::Progress for StoppedPhases {
    fn phase(&self, message: &str) {
        if let Ok(mut phases) = self.0.lock() {
            phases.push(message.to_owned());
        }
    }

    fn is_cancelled(&self) -> bool {
        true
    }
}

#[test]
fn a_cancelled_grid_study_stops_while_generating_its_common_points() {
    let text = format!("{TSAI}[pareto]\nobjectives = [\"volume\", \"gci\"]\n");
    for kind in [GridKind::Sweep, GridKind::Pareto] {
        let mut study: GridStudy = from_toml_str(&text).unwrap();
        if let Some(sampling) = study.sampling.as_mut() {
            // Far more points than the tests' studies use: generated only if not stopped.
            sampling.points = 4_000_000;
        }
        let progress = StoppedPhases::default();
        let run = match kind {
            GridKind::Sweep => sweep(&study, Shard::WHOLE, &progress).map(|_| ()),
            GridKind::Pareto => pareto(&study, Shard::WHOLE, &progress).map(|_| ()),
        };
        assert!(
            matches!(run, Err(StudyError::Cancelled)),
            "{kind:?}: {run:?}"
        );
        // Stopped in the points, before the grid is evaluated.
        let phases = progress.0.into_inner().unwrap();
        assert_eq!(phases, ["sampling points"], "{kind:?}");
    }
}

#[test]
fn a_grid_study_reads_from_json_and_a_bad_shard_is_an_empty_part() {
    let study: GridStudy = from_json_str(
        r#"{ "mechanism": { "linear_delta": { "l1_over_yr": 2.0, "ya_over_yr": 0.0,
               "zr_over_yr": 0.0, "l2_over_l1": 0.63 } },
             "indices": { "eta1_points": 4 },
             "variables": [ { "name": "l2_over_l1", "from": 0.6, "to": 0.7, "steps": 2 } ],
             "sweep": { "objective": { "eta2": 1.0 } } }"#,
    )
    .unwrap();
    let (result, _) = complete(sweep(&study, Shard::WHOLE, &Silent).unwrap());
    assert_eq!(result.nodes, 2);
    assert_eq!(Shard { index: 0, count: 2 }.nodes(10), 0..0);
}

/// Regression (review 4): the cross-section indices were computed in the paper's working mode
/// whatever the table's `leans_positive` said (W and η used it, η1, η2 and the area did not).
/// A sweep in another mode gives the library's values in that mode, node by node; η1 differs
/// between the modes (0.087 against the paper mode's 0.263 at the first node), η2 and the area
/// do not.
#[test]
fn cross_section_indices_are_computed_in_the_tables_working_mode() {
    let leans = [false, true, true];
    let text = "[mechanism.linear_delta]\n\
         l1_over_yr = 2.0\nya_over_yr = 0.1\nzr_over_yr = 0.2\nl2_over_l1 = 0.8\n\
         leans_positive = [false, true, true]\n\
         [indices]\neta1_points = 8\n\
         [[variables]]\nname = \"l2_over_l1\"\nfrom = 0.7\nto = 0.9\nsteps = 3\n\
         [sweep]\nobjective = { eta1 = 1.0, eta2 = 1.0, area = 1.0 }\n";
    let (_, outcome) = complete(sweep(&study(text), Shard::WHOLE, &Silent).unwrap());
    let landscape = table(&outcome, "landscape.csv");
    let column = |name: &str| landscape.column(name).unwrap();
    let l2 = column("l2_over_l1");
    let eta1 = SectionIndex::Eta1(Eta1Rule::Quadrature(8));
    let indices = [
        ("eta1", eta1),
        ("eta2", SectionIndex::Eta2),
        ("area", SectionIndex::Area),
    ];
    assert_eq!(l2.len(), 3);
    for (k, l2) in l2.iter().enumerate() {
        let design = [2.0, 0.1, 0.2, l2.unwrap()];
        let ratios = LinearDeltaRatios::from_slice(&design);
        let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 }).unwrap();
        let mode = LinearDeltaMode {
            leans_positive: leans,
        };
        let section = SectionIndices::new(&delta, mode);
        for (name, index) in indices {
            let in_mode = section.value(index).unwrap();
            assert_eq!(
                column(name)[k].unwrap().to_bits(),
                in_mode.to_bits(),
                "{name}, node {k}"
            );
        }
        let paper = section_index(&design, eta1).unwrap();
        assert!(
            (paper - section.value(eta1).unwrap()).abs() > 0.1,
            "node {k}"
        );
    }
}
