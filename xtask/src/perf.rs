//! `cargo xtask perf`: the figures of `docs/performance.md`, reproduced in one window.
//!
//! Runs the criterion benches of the root package (`cargo bench --bench main`), the robot-file
//! and study benches, and the peers (`../shared/peers`: NumPy's Delta design-index kernel,
//! Pinocchio's inverse and forward dynamics of the NUWAR; `benches/peers`: Pinocchio's of the
//! Stewart–Gough exported from its robot file) back to back, then writes one table of pkm's figures and one of the
//! ratios to the peers, each row stamped with the date, the commit and the load average of the
//! window (`target/perf/perf.md`, `perf.json`; `--update-docs` splices the tables into
//! `docs/performance.md`). A shared machine's absolute times drift; the ratios measured in the
//! same window are what `docs/performance.md` quotes.

use crate::report::{git_commit, replace_between_markers};
use crate::reproduce::workspace_root;
use anyhow::{Context as _, bail};
use pkm_term::OutputDir;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::SystemTime;

/// The benches whose figures `docs/performance.md` quotes (a criterion filter).
const DEFAULT_FILTER: &str = "delta_kernel|stamper/gci_kernel|workspace/membership|indices/|miller2004_inverse_dynamics_cpu/(hamilton|lagrange)_one_sample$|miller2004_forward_cpu/(hamilton|acceleration_form)_rhs|wolf/s4_1/F_";

/// Options of `cargo xtask perf`.
#[derive(Debug, clap::Args)]
pub(crate) struct PerfArgs {
    /// Criterion filter (a regular expression over bench ids).
    #[arg(long, default_value = DEFAULT_FILTER)]
    filter: String,
    /// Criterion's measurement time per bench, in seconds.
    #[arg(long, default_value_t = 3)]
    measurement_time: u32,
    /// Criterion's warm-up time per bench, in seconds.
    #[arg(long, default_value_t = 1)]
    warm_up_time: u32,
    /// The folder of the peer scripts; the peers are skipped (and said so) when it is absent.
    #[arg(long, default_value = "../shared/peers")]
    peers: PathBuf,
    /// The Python interpreter for the peers (one with NumPy; with Pinocchio, `pip install pin`,
    /// for the dynamics peer).
    #[arg(long, default_value = "python3")]
    python: PathBuf,
    /// How many times each peer script runs (its best and median are quoted).
    #[arg(long, default_value_t = 3)]
    peer_runs: u32,
    /// Where to write `perf.md` and `perf.json` [default: target/perf in the workspace].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Skip the timed full `reproduce` run.
    #[arg(long)]
    skip_reproduce: bool,
    /// Also write the tables into `docs/performance.md` between `<!-- perf:begin -->` and
    /// `<!-- perf:end -->`.
    #[arg(long)]
    update_docs: bool,
}

/// When and where the figures were measured.
#[derive(Debug, Serialize)]
struct Window {
    start: String,
    end: String,
    commit: String,
    load_start: String,
    load_end: String,
}

/// One criterion bench: its median time and, for benches with a throughput, elements per second.
#[derive(Debug, Serialize)]
struct BenchFigure {
    id: String,
    /// Median and its 95 % confidence bounds, nanoseconds per iteration.
    median_ns: [f64; 3],
    /// Elements per iteration (points, designs), when the bench declares a throughput.
    elements: Option<u64>,
}

impl BenchFigure {
    /// Elements per second at the median.
    fn rate(&self) -> Option<f64> {
        self.elements.map(|n| n as f64 / (self.median_ns[1] * 1e-9))
    }
}

/// A peer figure: the best and the median of its runs.
#[derive(Debug, Serialize)]
struct PeerFigure {
    id: String,
    best: f64,
    median: f64,
    unit: &'static str,
}

/// A ratio of pkm to a peer in the same window.
#[derive(Debug, Serialize)]
struct Ratio {
    what: &'static str,
    pkm: String,
    peer: String,
    /// How many times faster pkm is, at the medians.
    factor: f64,
}

#[derive(Debug, Serialize)]
struct Perf {
    window: Window,
    /// Wall seconds of a full `reproduce` run by this binary (its profile), when run.
    reproduce_wall_s: Option<f64>,
    benches: Vec<BenchFigure>,
    peers: Vec<PeerFigure>,
    peers_skipped: Vec<String>,
    ratios: Vec<Ratio>,
}

/// Runs the benches and the peers and writes the tables.
///
/// # Errors
/// When `--out` cannot be created, `cargo bench` fails, or a criterion result cannot be read.
pub(crate) fn run(args: &PerfArgs) -> anyhow::Result<()> {
    let root = workspace_root();
    let mut out = OutputDir::create(&args.out.clone().unwrap_or(root.join("target/perf")))?;
    let (start, load_start) = (now(), load_average());
    let since = SystemTime::now();
    let reproduce_wall_s = if args.skip_reproduce {
        None
    } else {
        Some(time_reproduce(&out.dir().join("reproduce"))?)
    };
    run_benches(&root, args)?;
    let benches = read_criterion(&root.join("target/criterion"), since)?;
    let (peers, peers_skipped) = run_peers(&root, args);
    let window = Window {
        start,
        end: now(),
        commit: git_commit(&root),
        load_start,
        load_end: load_average(),
    };
    let ratios = ratios(&benches, &peers);
    let perf = Perf {
        window,
        reproduce_wall_s,
        benches,
        peers,
        peers_skipped,
        ratios,
    };
    let markdown = markdown(&perf);
    out.write("perf.md", markdown.as_bytes())?;
    out.write("perf.json", serde_json::to_string_pretty(&perf)?.as_bytes())?;
    println!("{markdown}");
    if args.update_docs {
        let docs = root.join("docs/performance.md");
        let text = std::fs::read_to_string(&docs).with_context(|| docs.display().to_string())?;
        let updated = replace_between_markers(&text, &markdown, BEGIN, END)?;
        std::fs::write(&docs, updated).with_context(|| docs.display().to_string())?;
    }
    Ok(())
}

const BEGIN: &str = "<!-- perf:begin -->";
const END: &str = "<!-- perf:end -->";

fn now() -> String {
    humantime::format_rfc3339_seconds(SystemTime::now()).to_string()
}

/// `/proc/loadavg`'s three averages, or `unknown` off Linux.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|| "unknown".to_owned())
}

/// Wall seconds of `reproduce` (every experiment, full sizes) run by this very binary, its
/// report written to `report`.
///
/// # Errors
/// When the binary cannot be started or the run fails.
fn time_reproduce(report: &Path) -> anyhow::Result<f64> {
    let exe = std::env::current_exe().context("cannot locate the xtask binary")?;
    let start = std::time::Instant::now();
    let status = Command::new(exe)
        .args(["reproduce", "--out"])
        .arg(report)
        .status()
        .context("cannot run reproduce")?;
    if !status.success() {
        bail!("reproduce failed ({status})");
    }
    Ok(start.elapsed().as_secs_f64())
}

/// The root package's benches under `--filter`, then the robot-file and study benches (all of
/// them).
fn run_benches(root: &Path, args: &PerfArgs) -> anyhow::Result<()> {
    let targets: [(&[&str], &str); 3] = [
        (&["--bench", "main"], &args.filter),
        (&["-p", "pkm-robot-file", "--bench", "robot_file"], ""),
        (&["-p", "pkm-study", "--bench", "study"], ""),
    ];
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    for (target, filter) in targets {
        let status = Command::new(&cargo)
            .current_dir(root)
            .arg("bench")
            .args(target)
            .arg("--")
            .args(["--warm-up-time", &args.warm_up_time.to_string()])
            .args(["--measurement-time", &args.measurement_time.to_string()])
            .args((!filter.is_empty()).then_some(filter))
            .status()
            .context("cannot run cargo bench")?;
        if !status.success() {
            bail!("cargo bench {} failed ({status})", target.join(" "));
        }
    }
    Ok(())
}

#[derive(Deserialize)]
struct BenchmarkJson {
    full_id: String,
    throughput: Option<Value>,
}

/// Every criterion result under `dir` written after `since`, sorted by id.
fn read_criterion(dir: &Path, since: SystemTime) -> anyhow::Result<Vec<BenchFigure>> {
    let mut figures = Vec::new();
    for entry in walkdir::WalkDir::new(dir)
        .into_iter()
        .filter_map(Result::ok)
    {
        let path = entry.path();
        if !path.ends_with("new/benchmark.json") || !written_after(path, since) {
            continue;
        }
        let read = |p: &Path| -> anyhow::Result<String> {
            std::fs::read_to_string(p).with_context(|| p.display().to_string())
        };
        let bench: BenchmarkJson = serde_json::from_str(&read(path)?)?;
        let estimates: Value =
            serde_json::from_str(&read(&path.with_file_name("estimates.json"))?)?;
        figures.push(BenchFigure {
            id: bench.full_id,
            median_ns: median_of(&estimates)
                .with_context(|| format!("{}: no median", path.display()))?,
            elements: bench
                .throughput
                .as_ref()
                .and_then(|t| t.get("Elements"))
                .and_then(Value::as_u64),
        });
    }
    figures.sort_by(|a, b| a.id.cmp(&b.id));
    Ok(figures)
}

fn written_after(path: &Path, since: SystemTime) -> bool {
    std::fs::metadata(path)
        .and_then(|m| m.modified())
        .is_ok_and(|t| t >= since)
}

/// `[lower, estimate, upper]` of criterion's median.
fn median_of(estimates: &Value) -> Option<[f64; 3]> {
    let median = estimates.get("median")?;
    let interval = median.get("confidence_interval")?;
    Some([
        interval.get("lower_bound")?.as_f64()?,
        median.get("point_estimate")?.as_f64()?,
        interval.get("upper_bound")?.as_f64()?,
    ])
}

/// A peer script, the JSON fields it times and the unit of each.
struct Peer {
    /// Its path in the peers folder, or in the repository for a [`PeerKind`] other than
    /// `Shared`.
    script: &'static str,
    /// Where it is and what it is given.
    kind: PeerKind,
    /// (figure id, JSON pointer to the best value, pointer to the median value, unit)
    figures: &'static [(&'static str, &'static str, &'static str, &'static str)],
}

/// Where a peer script is and what it is given.
#[derive(Clone, Copy)]
enum PeerKind {
    /// In the peers folder, without arguments.
    Shared,
    /// In the repository (`benches/`), without arguments.
    Repository,
    /// In the repository: compares pkm's Python package with the NumPy peer (it needs `pkm`
    /// importable by `--python` and is given the NumPy peer's path as `--peer PATH`).
    PythonPackage,
    /// In the repository: times a robot file of `examples/robots/` (given as
    /// `--moving --time PATH`), calling the `pkm` command, built in the release profile and
    /// named in `PKM_COMMAND`.
    RobotFile(&'static str),
}

const PEERS: [Peer; 5] = [
    Peer {
        script: "numpy_delta_gci.py",
        kind: PeerKind::Shared,
        figures: &[
            (
                "numpy_svd",
                "/timing/numpy_svd/points_per_s_max",
                "/timing/numpy_svd/points_per_s_median",
                "points/s",
            ),
            (
                "numpy_eigvalsh",
                "/timing/numpy_eigvalsh/points_per_s_max",
                "/timing/numpy_eigvalsh/points_per_s_median",
                "points/s",
            ),
        ],
    },
    Peer {
        script: "pin_bench.py",
        kind: PeerKind::Shared,
        figures: &[
            (
                "pinocchio_id_torques_cpu",
                "/timing_us/id_torques/cpu_min_us",
                "/timing_us/id_torques/cpu_median_us",
                "µs",
            ),
            (
                "pinocchio_constraintDynamics_cpu",
                "/timing_us/constraintDynamics/cpu_min_us",
                "/timing_us/constraintDynamics/cpu_median_us",
                "µs",
            ),
            (
                "pinocchio_forwardDynamics_kkt_cpu",
                "/timing_us/forwardDynamics_kkt/cpu_min_us",
                "/timing_us/forwardDynamics_kkt/cpu_median_us",
                "µs",
            ),
        ],
    },
    Peer {
        script: "benches/peers/pin_robot_file.py",
        kind: PeerKind::RobotFile("examples/robots/stewart_gough.toml"),
        figures: &[
            (
                "pinocchio_6ups_id_cpu",
                "/timing_us/inverse_dynamics/cpu_min_us",
                "/timing_us/inverse_dynamics/cpu_median_us",
                "µs",
            ),
            (
                "pinocchio_6ups_constraintDynamics_cpu",
                "/timing_us/constraintDynamics/cpu_min_us",
                "/timing_us/constraintDynamics/cpu_median_us",
                "µs",
            ),
        ],
    },
    Peer {
        script: "benches/peers/fksgp_dietmaier.py",
        kind: PeerKind::Repository,
        figures: &[
            (
                "fksgp_dietmaier_cpu",
                "/timing_us/solver66/cpu_min_us",
                "/timing_us/solver66/cpu_median_us",
                "µs",
            ),
            (
                "fksgp_dietmaier_wall",
                "/timing_us/solver66/wall_min_us",
                "/timing_us/solver66/wall_median_us",
                "µs",
            ),
        ],
    },
    Peer {
        script: "benches/python/kernels.py",
        kind: PeerKind::PythonPackage,
        figures: &[
            (
                "python_over_rust",
                "/python_over_rust",
                "/python_over_rust",
                "×",
            ),
            (
                "numpy_over_python",
                "/numpy_over_python",
                "/numpy_over_python",
                "×",
            ),
        ],
    },
];

/// Runs every peer `args.peer_runs` times; a peer that cannot run is listed with the reason.
fn run_peers(root: &Path, args: &PerfArgs) -> (Vec<PeerFigure>, Vec<String>) {
    let dir = root.join(&args.peers);
    let numpy_peer = dir.join(PEERS[0].script);
    let (mut figures, mut skipped) = (Vec::new(), Vec::new());
    for peer in &PEERS {
        let robot = match peer.kind {
            PeerKind::RobotFile(file) => Some(root.join(file)),
            _ => None,
        };
        let script = match peer.kind {
            PeerKind::Shared => dir.join(peer.script),
            _ => root.join(peer.script),
        };
        let peer_args = match (&robot, peer.kind) {
            (Some(robot), _) => vec!["--moving".as_ref(), "--time".as_ref(), robot.as_os_str()],
            (None, PeerKind::PythonPackage) => vec!["--peer".as_ref(), numpy_peer.as_os_str()],
            _ => vec![],
        };
        let pkm = match robot.as_ref().map(|_| build_pkm_command(root)).transpose() {
            Ok(pkm) => pkm,
            Err(reason) => {
                skipped.push(format!("{}: {reason}", peer.script));
                continue;
            }
        };
        let runs: Result<Vec<Value>, String> = (0..args.peer_runs.max(1))
            .map(|_| run_peer(&args.python, &script, &peer_args, pkm.as_deref()))
            .collect();
        match runs {
            Ok(runs) => figures.extend(peer.figures.iter().filter_map(|f| summarise(&runs, f))),
            Err(reason) => skipped.push(format!("{}: {reason}", peer.script)),
        }
    }
    (figures, skipped)
}

/// Builds the `pkm` command in the release profile for the peers that call it; its path.
fn build_pkm_command(root: &Path) -> Result<PathBuf, String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(&cargo)
        .current_dir(root)
        .args(["build", "--release", "-p", "pkm-cli"])
        .status()
        .map_err(|e| format!("cannot run cargo build: {e}"))?;
    if !status.success() {
        return Err(format!(
            "cargo build --release -p pkm-cli failed ({status})"
        ));
    }
    Ok(root.join("target/release/pkm"))
}

/// One run of a peer script: the JSON object on its last output line (`PKM_COMMAND` set to
/// `pkm` when given).
fn run_peer(
    python: &Path,
    script: &Path,
    args: &[&std::ffi::OsStr],
    pkm: Option<&Path>,
) -> Result<Value, String> {
    if !script.is_file() {
        return Err(format!("{} not found", script.display()));
    }
    eprintln!("peer: {} {}", python.display(), script.display());
    let mut command = Command::new(python);
    command.arg(script).args(args);
    if let Some(pkm) = pkm {
        command.env("PKM_COMMAND", pkm);
    }
    let output = command
        .output()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    match stdout.lines().last().map(serde_json::from_str::<Value>) {
        Some(Ok(value)) if output.status.success() => Ok(value),
        _ => {
            let stderr = String::from_utf8_lossy(&output.stderr);
            Err(stderr.lines().last().unwrap_or("no output").to_owned())
        }
    }
}

/// Best and median over the runs of one figure (best: the largest rate or the smallest time).
fn summarise(
    runs: &[Value],
    (id, best, median, unit): &(&'static str, &'static str, &'static str, &'static str),
) -> Option<PeerFigure> {
    let values = |pointer: &str| -> Option<Vec<f64>> {
        runs.iter().map(|r| r.pointer(pointer)?.as_f64()).collect()
    };
    let (bests, mut medians) = (values(best)?, values(median)?);
    let rate = *unit == "points/s";
    let pick = |a: f64, b: f64| if rate { a.max(b) } else { a.min(b) };
    medians.sort_by(f64::total_cmp);
    Some(PeerFigure {
        id: (*id).to_owned(),
        best: bests.iter().copied().reduce(pick)?,
        median: medians[medians.len() / 2],
        unit,
    })
}

/// What a pkm bench is compared with.
#[derive(Clone, Copy)]
enum Against {
    /// A peer figure (NumPy, Pinocchio).
    Peer(&'static str),
    /// Another pkm bench.
    Bench(&'static str),
}

/// The ratios that `docs/performance.md` quotes: (what, pkm bench, what it is compared with).
const RATIOS: [(&str, &str, Against); 15] = [
    (
        "Delta design index, 1 thread, vs NumPy SVD",
        "delta_kernel/batch/1_threads",
        Against::Peer("numpy_svd"),
    ),
    (
        "Delta design index, 1 thread, vs NumPy eigvalsh",
        "delta_kernel/batch/1_threads",
        Against::Peer("numpy_eigvalsh"),
    ),
    (
        "NUWAR inverse dynamics, one sample (CPU time)",
        "miller2004_inverse_dynamics_cpu/lagrange_one_sample",
        Against::Peer("pinocchio_id_torques_cpu"),
    ),
    (
        "NUWAR forward dynamics, one evaluation (CPU time), vs constraintDynamics",
        "miller2004_forward_cpu/acceleration_form_rhs",
        Against::Peer("pinocchio_constraintDynamics_cpu"),
    ),
    (
        "NUWAR forward dynamics, one evaluation (CPU time), vs dense KKT",
        "miller2004_forward_cpu/acceleration_form_rhs",
        Against::Peer("pinocchio_forwardDynamics_kkt_cpu"),
    ),
    (
        "Delta design index, lane kernel vs scalar kernel, 1 thread",
        "delta_kernel/batch/1_threads",
        Against::Bench("delta_kernel/scalar/1_threads"),
    ),
    (
        "§2.1 membership (NUWAR), 1 thread: the library's lane count vs point by point",
        "workspace/membership/1_threads",
        Against::Bench("workspace/membership/point_by_point_1_threads"),
    ),
    (
        "Tsai GCI estimate, 1 thread: the library's lane estimator vs point by point",
        "stamper/gci_kernel/1_threads",
        Against::Bench("stamper/gci_kernel/point_by_point_1_threads"),
    ),
    (
        "IK + J + 1/κ of the Delta: hand-written model vs the same robot from a file (goal: the file within 5 ×)",
        "robot_file/rotary_delta/ik_j_inverse_kappa/hand_written",
        Against::Bench("robot_file/rotary_delta/ik_j_inverse_kappa/general"),
    ),
    (
        "Forward kinematics from a guess, Delta: hand-written vs from its file (goal: the file within 3 ×)",
        "robot_file/forward_kinematics/rotary_delta/hand_written",
        Against::Bench("robot_file/forward_kinematics/rotary_delta/general"),
    ),
    (
        "Forward kinematics from a guess, Tsai: hand-written vs from its file (goal: the file within 3 ×)",
        "robot_file/forward_kinematics/tsai/hand_written",
        Against::Bench("robot_file/forward_kinematics/tsai/general"),
    ),
    (
        "Inverse dynamics, one sample, 6-UPS from its file vs Pinocchio's fastest Python route on the exported model (goal: pkm 10 × faster)",
        "robot_file/inverse_dynamics/stewart_gough/efforts",
        Against::Peer("pinocchio_6ups_id_cpu"),
    ),
    (
        "Inverse dynamics, one sample, Delta: hand-written vs from its file (goal: the file within 2 ×)",
        "robot_file/inverse_dynamics/rotary_delta/hand_written",
        Against::Bench("robot_file/inverse_dynamics/rotary_delta/efforts"),
    ),
    (
        "Every assembly mode of Dietmaier's design (40 real), 1 thread, vs fkSGP's elimination template in Python/NumPy (its CPU time, all threads; goal: 10 ms per core)",
        "robot_file/assembly_modes/dietmaier_40/homotopy_1_thread",
        Against::Peer("fksgp_dietmaier_cpu"),
    ),
    (
        "Every assembly mode of Dietmaier's design, 2 threads, vs fkSGP (wall time)",
        "robot_file/assembly_modes/dietmaier_40/homotopy",
        Against::Peer("fksgp_dietmaier_wall"),
    ),
];

fn ratios(benches: &[BenchFigure], peers: &[PeerFigure]) -> Vec<Ratio> {
    let bench = |id: &str| benches.iter().find(|b| b.id == id);
    RATIOS
        .iter()
        .filter_map(|&(what, bench_id, against)| {
            let ours = bench(bench_id)?;
            let (factor, other) = match against {
                Against::Peer(id) => {
                    let peer = peers.iter().find(|p| p.id == id)?;
                    let factor = match (ours.rate(), peer.unit) {
                        (Some(rate), "points/s") => rate / peer.median,
                        (None, "µs") => peer.median * 1e3 / ours.median_ns[1],
                        _ => return None,
                    };
                    (
                        factor,
                        format!("{id} {} (median)", number(peer.median, peer.unit)),
                    )
                }
                Against::Bench(id) => {
                    let theirs = bench(id)?;
                    let factor = theirs.median_ns[1] / ours.median_ns[1];
                    (factor, format!("{id} {}", figure(theirs)))
                }
            };
            Some(Ratio {
                what,
                pkm: format!("{bench_id} {}", figure(ours)),
                peer: other,
                factor,
            })
        })
        .collect()
}

/// A bench's figure: its rate when it has a throughput, else its median time.
fn figure(bench: &BenchFigure) -> String {
    match bench.rate() {
        Some(rate) => number(rate, "points/s"),
        None => number(bench.median_ns[1], "ns"),
    }
}

fn number(value: f64, unit: &str) -> String {
    match unit {
        "points/s" if value >= 1e6 => format!("{:.2} M points/s", value / 1e6),
        "points/s" => format!("{value:.0} points/s"),
        "×" => format!("{value:.3} ×"),
        _ => format!("{value:.3} {unit}"),
    }
}

fn markdown(perf: &Perf) -> String {
    let w = &perf.window;
    let mut s = format!(
        "Measured by `cargo xtask perf` from {} to {}, commit `{}`, load average {} at the start and {} at the end.\n\n",
        w.start, w.end, w.commit, w.load_start, w.load_end
    );
    if let Some(wall) = perf.reproduce_wall_s {
        s += &format!("Full `cargo xtask reproduce`: **{wall:.1} s** wall.\n\n");
    }
    s += "| bench | median time per iteration [95 % interval] | rate at the median |\n|---|---|---|\n";
    for b in &perf.benches {
        let [lo, mid, hi] = b.median_ns.map(format_time);
        let rate = b.rate().map(|r| number(r, "points/s")).unwrap_or_default();
        s += &format!("| `{}` | {mid} [{lo}, {hi}] | {rate} |\n", b.id);
    }
    s += "\n| peer | best | median |\n|---|---|---|\n";
    for p in &perf.peers {
        s += &format!(
            "| `{}` | {} | {} |\n",
            p.id,
            number(p.best, p.unit),
            number(p.median, p.unit)
        );
    }
    for reason in &perf.peers_skipped {
        s += &format!("| skipped: {reason} | | |\n");
    }
    s += "\n| ratio | pkm | compared with | pkm (first column) faster by |\n|---|---|---|---|\n";
    for r in &perf.ratios {
        s += &format!(
            "| {} | {} | {} | {:.1} × |\n",
            r.what, r.pkm, r.peer, r.factor
        );
    }
    s
}

fn format_time(ns: f64) -> String {
    match ns {
        t if t >= 1e9 => format!("{:.3} s", t * 1e-9),
        t if t >= 1e6 => format!("{:.3} ms", t * 1e-6),
        t if t >= 1e3 => format!("{:.3} µs", t * 1e-3),
        t => format!("{t:.1} ns"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_peer_figure_takes_the_fastest_run_and_the_median_of_medians() {
        let runs = [
            json!({"timing": {"numpy_svd": {"points_per_s_max": 10.0, "points_per_s_median": 8.0}}}),
            json!({"timing": {"numpy_svd": {"points_per_s_max": 12.0, "points_per_s_median": 9.0}}}),
            json!({"timing": {"numpy_svd": {"points_per_s_max": 11.0, "points_per_s_median": 5.0}}}),
        ];
        let f = summarise(&runs, &PEERS[0].figures[0]).unwrap();
        assert_eq!((f.best, f.median), (12.0, 8.0));
        let times = [
            json!({"timing_us": {"id_torques": {"cpu_min_us": 3.0, "cpu_median_us": 4.0}}}),
            json!({"timing_us": {"id_torques": {"cpu_min_us": 2.0, "cpu_median_us": 6.0}}}),
        ];
        let f = summarise(&times, &PEERS[1].figures[0]).unwrap();
        assert_eq!((f.best, f.median), (2.0, 6.0));
    }

    #[test]
    fn ratios_divide_rates_and_times_at_the_medians() {
        let benches = [
            BenchFigure {
                id: "delta_kernel/batch/1_threads".into(),
                median_ns: [0.9e9, 1e9, 1.1e9],
                elements: Some(2_000_000),
            },
            BenchFigure {
                id: "delta_kernel/scalar/1_threads".into(),
                median_ns: [3.5e9, 4e9, 4.5e9],
                elements: Some(2_000_000),
            },
            BenchFigure {
                id: "miller2004_inverse_dynamics_cpu/lagrange_one_sample".into(),
                median_ns: [60.0, 70.0, 80.0],
                elements: None,
            },
        ];
        let peers = [
            PeerFigure {
                id: "numpy_svd".into(),
                best: 5e5,
                median: 4e5,
                unit: "points/s",
            },
            PeerFigure {
                id: "pinocchio_id_torques_cpu".into(),
                best: 20.0,
                median: 21.0,
                unit: "µs",
            },
        ];
        let r = ratios(&benches, &peers);
        let factors: Vec<f64> = r.iter().map(|r| r.factor).collect();
        assert_eq!(factors.len(), 3, "{factors:?}");
        assert!((factors[0] - 5.0).abs() < 1e-12, "vs NumPy: {factors:?}");
        assert!(
            (factors[1] - 300.0).abs() < 1e-9,
            "vs Pinocchio: {factors:?}"
        );
        assert!(
            (factors[2] - 4.0).abs() < 1e-12,
            "lanes vs scalar: {factors:?}"
        );
    }

    #[test]
    fn criterion_results_are_read_with_their_throughput() {
        let dir = tempfile::tempdir().unwrap();
        let new = dir.path().join("delta_kernel/batch_1_threads/new");
        std::fs::create_dir_all(&new).unwrap();
        let since = SystemTime::now() - std::time::Duration::from_secs(1);
        std::fs::write(
            new.join("benchmark.json"),
            r#"{"full_id":"delta_kernel/batch/1_threads","throughput":{"Elements":1048576}}"#,
        )
        .unwrap();
        std::fs::write(
            new.join("estimates.json"),
            r#"{"median":{"confidence_interval":{"lower_bound":1.0,"upper_bound":3.0},"point_estimate":2.0}}"#,
        )
        .unwrap();
        let figures = read_criterion(dir.path(), since).unwrap();
        assert_eq!(figures.len(), 1);
        assert_eq!(
            figures[0].median_ns.map(f64::to_bits),
            [1.0f64, 2.0, 3.0].map(f64::to_bits)
        );
        assert_eq!(figures[0].elements, Some(1_048_576));
        let later = SystemTime::now() + std::time::Duration::from_secs(60);
        assert!(
            read_criterion(dir.path(), later).unwrap().is_empty(),
            "stale results are skipped"
        );
    }
}
