//! The optimize study through the library function: the example study against the same
//! multistart written directly on the library, every setting refused at its key path before
//! any start runs, and a finite optimality check (or a typed error) for any `check_step`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_mechanisms::{Tsai3Dof, TsaiDesign};
use pkm_optimizers::{
    AugmentedLagrangianSettings, ConstrainedResult, Sense, augmented_lagrangian,
    uniform_start_points,
};
use pkm_study::{OptimizeStudy, StudyError, from_toml_str, optimize};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Progress, Silent};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

fn example() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/studies/tsai_volume_optimize.toml");
    std::fs::read_to_string(path).unwrap()
}

fn close(a: f64, b: f64, relative: f64) -> bool {
    (a - b).abs() <= relative * a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

/// Stamper's problem written directly: W of (a, b, d+e, c−r) with legs at 120°/240°,
/// a + b + d + e ≤ 1.
struct TsaiVolume([Bounds; 4]);

impl Objective for TsaiVolume {
    fn dimension(&self) -> usize {
        4
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, x: &[f64]) -> Result<f64, ObjectiveError> {
        let d = Tsai3Dof::new(TsaiDesign::from_deg(x[0], x[1], x[2], x[3], 120.0, 240.0))?;
        Ok(d.column_volume(128)?)
    }
}

impl Constraints for TsaiVolume {
    fn n_constraints(&self) -> usize {
        1
    }
    fn inequalities(&self, x: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        g[0] = x[0] + x[1] + x[2] - 1.0;
        Ok(())
    }
}

#[test]
fn tsai_volume_optimisation_matches_the_library_run() {
    let study: OptimizeStudy = from_toml_str(&example()).unwrap();
    let outcome = optimize(&study, &Silent).unwrap();
    let r = &outcome.result;
    let b = |lo, hi| Bounds::new(lo, hi).unwrap();
    let problem = TsaiVolume([b(0.02, 1.0), b(0.02, 1.0), b(0.0, 0.5), b(0.0, 0.3)]);
    let settings = AugmentedLagrangianSettings {
        fd_step: 1e-4,
        tolerance: 1e-8,
        feasibility: 1e-6,
        max_outer: 15,
        max_inner: 100,
        scale: None,
    };
    let starts = uniform_start_points(problem.bounds(), 4, 2024).unwrap();
    let mut best: Option<ConstrainedResult> = None;
    for s in &starts {
        if let Ok(o) = augmented_lagrangian(&problem, Sense::Maximise, s, &settings, &Silent)
            && best.as_ref().is_none_or(|b| o.value > b.value)
        {
            best = Some(o);
        }
    }
    let best = best.unwrap();
    assert_eq!(r.variables, ["a", "b", "d_plus_e", "c_minus_r"]);
    assert!(
        close(r.maximum, best.value, 1e-12),
        "{} vs {}",
        r.maximum,
        best.value
    );
    for (name, v) in r.variables.iter().zip(&best.design) {
        assert!(
            close(r.design[name], *v, 1e-12),
            "{name}: {} vs {v}",
            r.design[name]
        );
    }
    // Independent of the optimiser: the reported maximum is the volume of the reported design,
    // which satisfies the constraint, and the legs stayed where the study holds them.
    let d = &r.design;
    let design = Tsai3Dof::new(TsaiDesign::from_deg(
        d["a"],
        d["b"],
        d["d_plus_e"],
        d["c_minus_r"],
        120.0,
        240.0,
    ))
    .unwrap();
    assert!(close(design.column_volume(128).unwrap(), r.maximum, 1e-12));
    assert!(d["a"] + d["b"] + d["d_plus_e"] <= 1.0 + 1e-6);
    assert!((d["phi2_deg"] - 120.0).abs() < 1e-12 && (d["phi3_deg"] - 240.0).abs() < 1e-12);
    // W grows with the size (as R³), so the reach constraint is active with a positive
    // multiplier, from the solver and from the least-squares fit of the check alike.
    let optimality = r.optimality.as_ref().unwrap();
    assert_eq!(optimality.active_constraints, [0]);
    assert!(r.constraints[0].multiplier.unwrap() > 0.0);
    assert!(optimality.least_squares_multipliers[0] > 0.0);
    // Second order: a maximum, not a saddle (issue 20: with the solver scaling and a fixed first
    // penalty the example stopped at W 1.000777 with a reduced-Hessian eigenvalue of -12.9; now
    // 5.6 and 38.9).
    assert!(!optimality.reduced_hessian_eigenvalues.is_empty());
    assert!(
        optimality
            .reduced_hessian_eigenvalues
            .iter()
            .all(|&e| e > 0.0),
        "{:?}",
        optimality.reduced_hessian_eigenvalues
    );
    // The starts table has one row per start, the best one's value being the maximum.
    let pkm_study::Artifact::Table { name, table } = &outcome.artifacts[0] else {
        panic!("the starts table comes first");
    };
    assert_eq!(name, "starts.csv");
    assert_eq!(table.rows.len(), 4);
    assert_eq!(
        table.column("volume").unwrap()[r.best_start],
        Some(r.maximum)
    );
}

/// Counts every progress event: a study refused before computing reports none.
#[derive(Default)]
struct Events(AtomicUsize);

impl Progress for Events {
    fn phase(&self, _: &str) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }
    fn start(&self, _: &str, _: u64) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }
}

/// A cheap variant of the example: 16 columns, one start, short solver runs.
fn cheap(edit: &[(&str, &str)]) -> String {
    let mut text = example()
        .replace("columns = 128", "columns = 16")
        .replace("count = 4", "count = 1")
        .replace("max_outer = 15", "max_outer = 4")
        .replace("max_inner = 100", "max_inner = 20");
    for (from, to) in edit {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    text
}

/// The key path of the error of the study `text`, checking that nothing was computed.
fn refused_at(text: &str) -> String {
    let study: OptimizeStudy = from_toml_str(text).unwrap();
    let events = Events::default();
    let e = optimize(&study, &events).expect_err("the study is invalid");
    assert!(matches!(e, StudyError::Invalid { .. }), "{e}");
    assert_eq!(
        events.0.load(Ordering::Relaxed),
        0,
        "computed before refusing: {e}"
    );
    e.path().unwrap().to_string()
}

#[test]
fn every_setting_is_refused_at_its_key_before_the_first_start() {
    let cases: [(&str, &str, &str); 10] = [
        (
            "fd_step = 1e-4",
            "fd_step = -1.0",
            "optimize.solver.fd_step",
        ),
        (
            "tolerance = 1e-8",
            "tolerance = 0.0",
            "optimize.solver.tolerance",
        ),
        (
            "max_outer = 4",
            "max_outer = 0",
            "optimize.solver.max_outer",
        ),
        ("count = 1", "count = 0", "optimize.starts.count"),
        ("count = 1", "count = 1000000000", "optimize.starts.count"),
        (
            "check_step = 1e-2",
            "check_step = 0.7",
            "optimize.check_step",
        ),
        ("columns = 16", "columns = 0", "optimize.columns"),
        ("a = [0.02, 1.0]", "a = [1.0, 0.02]", "optimize.variables.a"),
        (
            "c_minus_r = [0.0, 0.3]",
            "c = [0.0, 0.3]",
            "optimize.variables.c",
        ),
        (
            "d_plus_e = 1.0 }",
            "e = 1.0 }",
            "optimize.constraints[0].coefficients.e",
        ),
    ];
    for (from, to, path) in cases {
        assert_eq!(refused_at(&cheap(&[(from, to)])), path, "{to}");
    }
    let gci = cheap(&[("objective = \"volume\"", "objective = \"gci\"\npoints = 0")]);
    assert_eq!(refused_at(&gci), "optimize.points");
    let text = cheap(&[]);
    let section = &text[text.find("[optimize]").unwrap()..];
    let delta = format!(
        "[mechanism.rotary_delta]\nbase_radius = 0.15\nplate_offset = 0.04\narm = 0.2\n\
         forearm = 0.45\nalpha_deg = 35.0\nbeta_deg = 60.0\nmotor_plane_z = 0.0\n\
         azimuth_motor_1_deg = 0.0\n\n{section}"
    );
    assert_eq!(refused_at(&delta), "mechanism");
}

#[test]
fn any_check_step_gives_a_typed_error_at_its_key_or_a_finite_check() {
    let hostile = [
        "1e300", "1e-300", "5e-324", "0.5", "0.9", "0.0", "-1e-2", "inf", "nan", "-inf",
    ];
    for step in hostile {
        let text = cheap(&[("check_step = 1e-2", &format!("check_step = {step}"))]);
        assert_eq!(
            refused_at(&text),
            "optimize.check_step",
            "check_step = {step}"
        );
    }
    for step in ["0.49", "1e-2", "1e-6"] {
        let text = cheap(&[("check_step = 1e-2", &format!("check_step = {step}"))]);
        let study: OptimizeStudy = from_toml_str(&text).unwrap();
        match optimize(&study, &Silent) {
            Ok(outcome) => {
                let c = outcome.result.optimality.as_ref().unwrap();
                let numbers = c
                    .lagrangian_gradient
                    .iter()
                    .chain(&c.least_squares_multipliers)
                    .chain(&c.hessian_eigenvalues)
                    .chain(&c.reduced_hessian_eigenvalues)
                    .chain([&c.projected_gradient_max, &c.stationarity_residual]);
                for v in numbers {
                    assert!(v.is_finite(), "check_step = {step}: {c:?}");
                }
            }
            Err(e) => assert_eq!(
                e.path().map(ToString::to_string).as_deref(),
                Some("optimize.check_step"),
                "check_step = {step}: {e}"
            ),
        }
    }
}

#[test]
fn a_run_stopped_on_an_infeasible_outer_iterate_returns_its_last_feasible_one() {
    // Two variables, a coarse quadrature and six outer iterations (the Python suite's study):
    // both starts end their last outer iteration outside a + b <= 1 (by 2.5e-3 and 4.4e-5),
    // and both had been within the feasibility tolerance before.
    let text = "[mechanism.tsai]\na = 0.4\nb = 0.6\nd_plus_e = 0.0\nc_minus_r = 0.0\n\
        phi2_deg = 120.0\nphi3_deg = 240.0\n\n[optimize]\nobjective = \"volume\"\ncolumns = 24\n\
        check_step = 1e-2\nconstraints = [{ name = \"reach\", coefficients = { a = 1.0, b = 1.0 }, \
        at_most = 1.0 }]\n[optimize.variables]\na = [0.02, 1.0]\nb = [0.02, 1.0]\n\
        [optimize.starts]\ncount = 2\nseed = 2024\n[optimize.solver]\nfd_step = 1e-4\n\
        tolerance = 1e-6\nfeasibility = 1e-6\nmax_outer = 6\nmax_inner = 40\n";
    let study: OptimizeStudy = from_toml_str(text).unwrap();
    let r = optimize(&study, &Silent).unwrap().result;
    assert_eq!(r.starts.failed, 0, "{:?}", r.starts);
    assert_eq!(r.starts.at_iteration_limit, 2, "{:?}", r.starts);
    let reach = r.design["a"] + r.design["b"] - 1.0;
    assert!(reach <= 1e-6, "a + b - 1 = {reach:e}");
    assert!(r.maximum.is_finite() && r.maximum > 0.9, "{}", r.maximum);
}

fn robot_file_example() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/studies/symmetric_three_rpr_optimize.toml");
    std::fs::read_to_string(path).unwrap()
}

/// The robot-file example with fewer points and one start, edited.
fn cheap_robot_file(edit: &[(&str, &str)]) -> String {
    let mut text = robot_file_example()
        .replace("points = 8192", "points = 1024")
        .replace("starts = { count = 3", "starts = { count = 1");
    for (from, to) in edit {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    text
}

#[test]
fn a_robot_file_optimisation_refuses_every_setting_at_its_key_before_the_first_start() {
    let task_space = "[task_space]\nkind = \"constant_orientation\"";
    let objective = "objective = \"volume\"";
    let starts = "starts = { count = 1, seed = 5 }";
    let cases: [(&str, &str, &str); 12] = [
        (
            task_space,
            "[not_used]\nkind = \"constant_orientation\"",
            "",
        ),
        ("[sampling]\nseed = 11\npoints = 1024\n", "", "sampling"),
        ("d = [0.15, 0.6]", "r = [0.15, 0.6]", "optimize.variables.r"),
        ("d = [0.15, 0.6]", "d = [0.6, 0.15]", "optimize.variables.d"),
        (
            objective,
            "objective = \"singularity_free_volume\"",
            "task_space.singularity_free",
        ),
        (objective, "objective = \"weighted\"", "optimize.weights"),
        (
            objective,
            "objective = \"weighted\"\nweights = { gci = -1.0 }",
            "optimize.weights.gci",
        ),
        (
            objective,
            "objective = \"volume\"\nweights = { volume = 1.0 }",
            "optimize.weights",
        ),
        (
            starts,
            "starts = { count = 1, seed = 5 }\nsearch = { min_step = 0.5 }",
            "optimize.search.min_step",
        ),
        (
            starts,
            "starts = { count = 1, seed = 5 }\ncheck_step = 1e-2",
            "optimize.check_step",
        ),
        (
            starts,
            "starts = { count = 1, seed = 5 }\nsolver = { tolerance = 1e-6 }",
            "optimize.solver",
        ),
        (
            starts,
            "starts = { count = 1, seed = 5 }\nconstraints = [{ name = \"c\", \
             coefficients = { q = 1.0 }, at_most = 1.0 }]",
            "optimize.constraints[0].coefficients.q",
        ),
    ];
    for (from, to, path) in cases {
        let text = cheap_robot_file(&[(from, to)]);
        if path.is_empty() {
            // Without [task_space] the study does not parse ([not_used] is unknown) or names
            // the section: either way no computation.
            let parsed: Result<OptimizeStudy, _> = from_toml_str(&text);
            assert!(parsed.is_err(), "{to}");
            let no_section = cheap_robot_file(&[(task_space, "[unused]")]).replace(
                "[unused]\nbox = { x = [-1.0, 1.0], y = [-1.0, 1.0] }\nfixed = { rz_deg = \
                 -14.32394487827058 }\n",
                "",
            );
            assert_eq!(refused_at(&no_section), "task_space");
            continue;
        }
        assert_eq!(refused_at(&text), path, "{to}");
    }
    let bad_box = cheap_robot_file(&[("x = [-1.0, 1.0]", "x = [1.0, -1.0]")]);
    assert!(refused_at(&bad_box).starts_with("task_space"));
}

#[test]
fn a_tsai_study_refuses_the_settings_of_a_robot_file() {
    let sampling = cheap(&[("[optimize]", "[sampling]\npoints = 64\n\n[optimize]")]);
    assert_eq!(refused_at(&sampling), "sampling");
    let weighted = cheap(&[("objective = \"volume\"", "objective = \"weighted\"")]);
    assert_eq!(refused_at(&weighted), "optimize.objective");
    let search = cheap(&[(
        "objective = \"volume\"",
        "objective = \"volume\"\nsearch = { min_step = 1e-2 }",
    )]);
    assert_eq!(refused_at(&search), "optimize.search");
}

#[test]
fn a_weighted_robot_file_objective_is_the_sum_of_its_weighted_indices() {
    let text = cheap_robot_file(&[
        (
            "objective = \"volume\"",
            "objective = \"weighted\"\nweights = { volume = 1.0, gci = 20.0, \
             singularity_free_volume = 0.5 }\nsearch = { min_step = 0.05 }",
        ),
        (
            "fixed = { rz_deg = -14.32394487827058 }",
            "fixed = { rz_deg = -14.32394487827058 }\nsingularity_free = { min_direct_margin = \
             0.01, cells = 16, from = { x = 0.5, y = 0.0 } }",
        ),
    ]);
    let study: OptimizeStudy = from_toml_str(&text).unwrap();
    let outcome = optimize(&study, &Silent).unwrap();
    let r = &outcome.result;
    let i = &r.search.as_ref().unwrap().indices;
    let sum = i["volume"] + 20.0 * i["gci"] + 0.5 * i["singularity_free_volume"];
    assert!(close(r.maximum, sum, 1e-12), "{} against {sum}", r.maximum);
    assert!(i["singularity_free_volume"] > 0.0 && i["singularity_free_volume"] <= 2.0 * 2.0);
    assert!(r.optimality.is_none() && r.constraints.is_empty());
    // The same bits on a second run (the starts run in parallel, each search in order).
    let again = optimize(&study, &Silent).unwrap();
    assert_eq!(again.result, outcome.result);
}
