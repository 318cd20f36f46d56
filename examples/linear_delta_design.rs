//! Optimal Linear Delta designs for your own weights (Miller 2004, §2.2, eq. 3).
//!
//! ```text
//! cargo run --release --example linear_delta_design -- 1:1 2:1 1:3
//! ```
//! Each argument is `w1:w2`; the search runs over the limits of §2.2.3 with the quick
//! quadrature (add `--full` for the accurate one used by Table 2).
#![allow(clippy::print_stdout)]

use pkm::mechanisms::LinearDeltaMode;
use pkm::papers::miller2004::linear_delta::{
    evaluation::linear_delta,
    search::{Rules, optimise, search_box},
    table2::STATED_LIMITS,
};
use pkm::papers::{Context, Mode};
use pkm::workspace_indices::{SectionIndexCache, SectionIndices};
use pkm_traits::Silent;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = if args.iter().any(|a| a == "--full") {
        Mode::Full
    } else {
        Mode::Quick
    };
    let mut weights: Vec<(f64, f64)> = Vec::new();
    for arg in args.iter().filter(|a| !a.starts_with("--")) {
        let (w1, w2) = arg.split_once(':').ok_or("weights are written w1:w2")?;
        weights.push((w1.parse()?, w2.parse()?));
    }
    if weights.is_empty() {
        weights = vec![(1.0, 1.0), (2.0, 1.0), (1.0, 2.0)];
    }
    let context = Context {
        mode,
        progress: &Silent,
    };
    // The indices of every design searched, shared by the weightings (they do not depend on
    // the weights).
    let cache = SectionIndexCache::new();
    let bounds = search_box(STATED_LIMITS)?;
    println!("  w1    w2 | L1/YR YA/YR ZR/YR L2/L1 |   eta1   eta2    eta");
    for (w1, w2) in weights {
        let rules = Rules::for_mode(mode);
        let optimum = optimise((w1, w2), bounds, rules, &cache, &context)?;
        let [l1, ya, zr, l2] = optimum.design;
        let [eta1, eta2, eta] = optimum.indices;
        // The search skips η1 when w1 = 0; report it at the optimum all the same.
        let eta1 = if eta1.is_nan() {
            let delta = linear_delta(&optimum.design)?;
            SectionIndices::new(&delta, LinearDeltaMode::PAPER).eta1(rules.fine)?
        } else {
            eta1
        };
        println!(
            "{w1:5.2} {w2:5.2} | {l1:5.2} {ya:5.2} {zr:5.2} {l2:5.2} | {eta1:6.4} {eta2:6.4} {eta:6.4}"
        );
    }
    Ok(())
}
