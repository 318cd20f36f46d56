//! Figure data: Fig. 6 (η, η1, η2 on two planes through the optimum) and the optimal design's
//! cross-section with its 1/κ map (the paper's missing Figs. 4–5).

use super::evaluation::{Utility, inverse_condition, linear_delta};
use super::search::{Optimum, Rules, search_box};
use super::table2::{STATED_LIMITS, VARIABLES};
use crate::papers::{ExperimentError, Figure, Mode};
use pkm_draw::chart::{Chart, Heatmap};
use pkm_traits::SlicedRegion;
use pkm_workspace_indices::SectionIndexCache;
use rayon::prelude::*;

/// Evenly spaced values from `lo` to `hi` with `step`.
fn axis(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let n = ((hi - lo) / step).round() as usize;
    (0..=n).map(|i| lo + i as f64 * step).collect()
}

/// Fig. 6: η, η1 and η2 of w1 = w2 = 1 on the planes (L1/YR, L2/L1) and (YA/YR, ZR/YR) through
/// `optimum`.
///
/// # Errors
/// [`ExperimentError::Objective`] for a bound that cannot be built.
pub fn figure6(
    optimum: &Optimum,
    mode: Mode,
    cache: &SectionIndexCache,
) -> Result<Vec<Figure>, ExperimentError> {
    let utility = Utility {
        w1: 1.0,
        w2: 1.0,
        rule: Rules::for_mode(mode).coarse,
        bounds: search_box(STATED_LIMITS)?,
        cache,
    };
    let step = mode.pick(0.1, 0.05);
    let mut figures = Vec::new();
    for (plane, (kx, ky)) in [("a", (0, 3)), ("b", (1, 2))] {
        let xs = axis(STATED_LIMITS[kx].0, STATED_LIMITS[kx].1, step);
        let ys = axis(STATED_LIMITS[ky].0, STATED_LIMITS[ky].1, step);
        let values: Vec<Option<[f64; 3]>> = (0..xs.len() * ys.len())
            .into_par_iter()
            .map(|flat| {
                let mut design = optimum.design;
                design[kx] = xs[flat % xs.len()];
                design[ky] = ys[flat / xs.len()];
                utility.indices(&design).ok()
            })
            .collect();
        for (k, name) in ["eta", "eta1", "eta2"].into_iter().enumerate() {
            let index = [2, 0, 1][k];
            let title = format!(
                "Fig. 6: {name} on the plane ({}, {}) through the optimum",
                VARIABLES[kx], VARIABLES[ky]
            );
            let map = Heatmap {
                colour_axis: name.into(),
                x: xs.clone(),
                y: ys.clone(),
                values: values.iter().map(|v| v.map(|v| v[index])).collect(),
            };
            figures.push(Figure::chart(
                format!("fig6_{name}_{plane}"),
                Chart::heatmap(title, VARIABLES[kx], VARIABLES[ky], map),
            ));
        }
    }
    Ok(figures)
}

/// The y–z cross-section of `design` with 1/κ at every cell centre inside it.
///
/// # Errors
/// [`ExperimentError::Objective`] for an invalid design.
pub fn cross_section_map(design: &[f64; 4], mode: Mode) -> Result<Figure, ExperimentError> {
    let delta = linear_delta(design)?;
    let region = delta.cross_section();
    let e = region.extents();
    let cells = mode.pick(40, 160);
    let hy = (e.y_max - e.y_min) / cells as f64;
    let ys: Vec<f64> = (0..cells)
        .map(|i| e.y_min + (i as f64 + 0.5) * hy)
        .collect();
    let nz = ((e.z_max - e.z_min) / hy).ceil().max(1.0) as usize;
    let zs: Vec<f64> = (0..nz).map(|k| e.z_min + (k as f64 + 0.5) * hy).collect();
    let values = (0..ys.len() * zs.len())
        .map(|flat| {
            let (y, z) = (ys[flat % ys.len()], zs[flat / ys.len()]);
            region
                .contains(y, z)
                .then(|| inverse_condition(&delta, y, z))
        })
        .collect();
    let title = format!(
        "Workspace cross-section and 1/kappa of the optimum ({:.2}, {:.2}, {:.2}, {:.2})",
        design[0], design[1], design[2], design[3]
    );
    let map = Heatmap {
        colour_axis: "1/kappa".into(),
        x: ys,
        y: zs,
        values,
    };
    Ok(Figure::chart(
        "cross_section_inverse_condition",
        Chart::heatmap(title, "y/YR", "z/YR", map),
    ))
}
