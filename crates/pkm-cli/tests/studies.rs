//! The grid studies (`sweep`, `pareto`) end to end through the `pkm` binary, their numbers
//! checked against the same computation done directly through the library. The workspace
//! study's science is checked in `crates/pkm-study/tests/workspace.rs`, the Linear Delta
//! study against Miller's Table 2 experiment in the root `tests/it/linear_delta_study.rs`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{close, csv, run_study, study};
use nalgebra::Vector3;
use pkm_mechanisms::{
    Elbow, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios, Tsai3Dof, TsaiDesign,
};
use pkm_traits::Silent;
use pkm_workspace_indices::{
    Domain, Eta1Rule, IndexError, PointSet, Region, Sampler, SectionIndex, SectionIndices,
    Workspace,
};

/// Relative agreement of two evaluations of the same formula with the same inputs.
const SAME: f64 = 1e-12;

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap()
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
    let out = tempfile::tempdir().unwrap();
    let results = run_study("sweep", &study("tsai_quick.toml"), out.path(), &[]);
    let domain = Domain::new(Region::Hemisphere {
        center: Vector3::zeros(),
        radius: 1.5,
    })
    .unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 7 }, 2048, 2).unwrap();
    let (header, rows) = csv(&out.path().join("landscape.csv"));
    assert_eq!(
        header,
        [
            "node",
            "a",
            "b",
            "volume",
            "eta",
            "gci",
            "utility",
            "infeasible"
        ]
    );
    assert_eq!(rows.len(), 9);
    let mut best: Option<(usize, f64)> = None;
    for (k, row) in rows.iter().enumerate() {
        let (a, b): (f64, f64) = (row[1].parse().unwrap(), row[2].parse().unwrap());
        let tsai = Tsai3Dof::new(TsaiDesign::from_deg(a, b, 0.0, 0.0, 120.0, 240.0)).unwrap();
        let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[]).unwrap();
        let e = ws.volume_and_eta(&points, &Silent).unwrap();
        let gci = e.gci().unwrap();
        assert!(close(row[3].parse().unwrap(), e.volume, SAME));
        assert!(close(row[4].parse().unwrap(), e.eta.unwrap(), SAME));
        assert!(close(row[5].parse().unwrap(), gci, SAME));
        let u = gci + 0.5 * e.volume;
        if best.is_none_or(|(_, b)| u > b) {
            best = Some((k, u));
        }
    }
    let (node, u) = best.unwrap();
    let grid_optimum = &results["result"]["grid_optimum"];
    assert_eq!(grid_optimum[0].as_u64(), Some(node as u64));
    assert!(close(f(&grid_optimum[1]["utility"]), u, SAME));
    let refined = f(&results["result"]["optimum"]["utility"]);
    assert!(refined >= u, "refinement never loses: {refined} < {u}");
    assert!(out.path().join("heatmap-a-b.svg").exists());
}

#[test]
fn linear_delta_pareto_front_and_weight_ranges_match_a_brute_force() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "pareto",
        &study("linear_delta_pareto_quick.toml"),
        out.path(),
        &[],
    );
    let (header, rows) = csv(&out.path().join("landscape.csv"));
    assert_eq!(header[1..4], ["l1_over_yr", "zr_over_yr", "l2_over_l1"]);
    // (node, η1, η2) of every feasible node, straight from the library.
    let nodes: Vec<(usize, f64, f64)> = rows
        .iter()
        .filter_map(|row| {
            let v: Vec<f64> = row[1..4].iter().map(|c| c.parse().unwrap()).collect();
            let design = [v[0], 0.0, v[1], v[2]];
            let e1 = section_index(&design, SectionIndex::Eta1(Eta1Rule::Quadrature(8)));
            let (Ok(e1), Ok(e2)) = (e1, section_index(&design, SectionIndex::Eta2)) else {
                assert!(
                    row[4].is_empty(),
                    "infeasible for the library, not for pkm: {row:?}"
                );
                return None;
            };
            assert!(
                close(row[4].parse().unwrap(), e1, SAME)
                    && close(row[5].parse().unwrap(), e2, SAME)
            );
            Some((row[0].parse().unwrap(), e1, e2))
        })
        .collect();
    assert!(nodes.len() > 400);
    let dominated = |&(_, a1, a2): &(usize, f64, f64)| {
        nodes
            .iter()
            .any(|&(_, b1, b2)| b1 >= a1 && b2 >= a2 && (b1 > a1 || b2 > a2))
    };
    let expected: Vec<u64> = nodes
        .iter()
        .filter(|n| !dominated(n))
        .map(|n| n.0 as u64)
        .collect();
    let front = results["result"]["front"].as_array().unwrap();
    let got: Vec<u64> = front.iter().map(|p| p["node"].as_u64().unwrap()).collect();
    assert_eq!(got, expected);
    // Whichever design maximises w·η1 + (1 − w)·η2 has a weight range that holds w.
    for k in 0..=40 {
        let w = f64::from(k) / 40.0;
        let u = |&(_, e1, e2): &(usize, f64, f64)| w * e1 + (1.0 - w) * e2;
        let best = nodes.iter().max_by(|a, b| u(a).total_cmp(&u(b))).unwrap();
        let p = front
            .iter()
            .find(|p| p["node"].as_u64() == Some(best.0 as u64))
            .unwrap();
        let range = &p["weight_range"];
        assert!(
            f(&range[0]) <= w + 1e-9 && w <= f(&range[1]) + 1e-9,
            "w = {w}: node {} has range {range}",
            best.0
        );
    }
    // The weighting (1, 1) is the front's design at w = 1/2.
    let equal = &results["result"]["weighted_optima"][0];
    let node = equal["node"].as_u64().unwrap();
    let p = front
        .iter()
        .find(|p| p["node"].as_u64() == Some(node))
        .unwrap();
    assert!(f(&p["weight_range"][0]) <= 0.5 && 0.5 <= f(&p["weight_range"][1]));
    assert!(out.path().join("front.svg").exists());
}

/// Regression (issue 17): the Linear Delta's η1/η2 were memoised per design rounded to 1e-6 and
/// computed at the rounded design, so a sweep whose nodes were closer than that reported one
/// node's values for its neighbours. Nodes 1e-9 apart now each get their own values, the
/// library's at exactly that node.
#[test]
fn a_linear_delta_sweep_with_nodes_1e_9_apart_gives_each_node_its_own_indices() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("close.toml");
    std::fs::write(
        &path,
        "[mechanism.linear_delta]\n\
         l1_over_yr = 2.0\nya_over_yr = 0.0\nzr_over_yr = 0.0\nl2_over_l1 = 0.63\n\
         [indices]\neta1_points = 8\n\
         [[variables]]\nname = \"l2_over_l1\"\nfrom = 0.63\nto = 0.630000004\nsteps = 5\n\
         [sweep]\nobjective = { eta1 = 1.0, eta2 = 1.0 }\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    run_study("sweep", &path, &out, &[]);
    let (header, rows) = csv(&out.join("landscape.csv"));
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (l2, eta1, eta2) = (column("l2_over_l1"), column("eta1"), column("eta2"));
    assert_eq!(rows.len(), 5);
    let mut distinct = Vec::new();
    for row in &rows {
        let design = [2.0, 0.0, 0.0, row[l2].parse().unwrap()];
        let cell = |k: usize| row[k].parse::<f64>().unwrap().to_bits();
        let eta1_rule = SectionIndex::Eta1(Eta1Rule::Quadrature(8));
        let library = |index| section_index(&design, index).unwrap().to_bits();
        assert_eq!(cell(eta1), library(eta1_rule), "{row:?}");
        assert_eq!(cell(eta2), library(SectionIndex::Eta2), "{row:?}");
        distinct.push(cell(eta1));
    }
    distinct.dedup();
    assert_eq!(distinct.len(), 5, "nodes 1e-9 apart share an η1");
}
