//! The two sensitivity statements of Miller 2004, §2.2.4: with w2 = 1, w1 must exceed 3 before
//! the geometry changes considerably; with w1 = 1, raising w2 only lowers L2/L1, by at most 0.03.

use super::search::{Optimum, Rules, optimise, search_box};
use super::table2::STATED_LIMITS;
use crate::papers::{Comparison, Context, ExperimentError, Mode, Paper, Source};
use pkm_workspace_indices::SectionIndexCache;

/// (L1/YR, YA/YR, ZR/YR) agree on the 0.01 lattice.
const SAME_NODE: f64 = 0.005;
/// A "considerable change in geometry": (L1/YR, YA/YR, ZR/YR) moves by more than this.
const JUMP: f64 = 0.1;

/// Largest change of (L1/YR, YA/YR, ZR/YR) between `a` and `b`.
fn geometry_change(a: &Optimum, b: &Optimum) -> f64 {
    (0..3)
        .map(|k| (a.design[k] - b.design[k]).abs())
        .fold(0.0, f64::max)
}

fn at_weights(
    w: (f64, f64),
    cache: &SectionIndexCache,
    context: &Context<'_>,
) -> Result<Optimum, ExperimentError> {
    optimise(
        w,
        search_box(STATED_LIMITS)?,
        Rules::for_mode(context.mode),
        cache,
        context,
    )
}

/// Sweep of w1 at w2 = 1: L2/L1 at each weight, the largest geometry change for w1 ≤ 3 and the
/// weight at which the geometry jumps (bisected to 0.01 in full mode).
///
/// # Errors
/// As [`optimise`].
pub fn w1_sweep(
    context: &Context<'_>,
    cache: &SectionIndexCache,
) -> Result<Vec<Comparison>, ExperimentError> {
    let source = Source::new(
        "miller2004.linear_delta.sensitivity.w1",
        Paper::Miller2004,
        "§2.2.4, increasing w1",
    );
    let weights = context.mode.pick(
        &[1.0, 2.0, 3.0, 4.0, 5.0][..],
        &[1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 10.0],
    );
    let base = at_weights((1.0, 1.0), cache, context)?;
    let mut rows = Vec::new();
    let mut change_up_to_3: f64 = 0.0;
    // The first sweep interval (previous weight, weight) over which the geometry jumps, wherever
    // it lies: a jump at w1 <= 3 must fail the "above 3" check, not go unnoticed.
    let mut jump: Option<(f64, f64)> = None;
    let mut previous = 1.0;
    for &w1 in weights {
        let optimum = at_weights((w1, 1.0), cache, context)?;
        rows.push(source.info(&format!("L2/L1 (w1={w1})"), "", optimum.design[3]));
        let change = geometry_change(&optimum, &base);
        if w1 <= 3.0 {
            change_up_to_3 = change_up_to_3.max(change);
        }
        if jump.is_none() && change > JUMP {
            jump = Some((previous, w1));
        }
        previous = w1;
    }
    rows.push(
        source
            .check(
                "max change of (L1/YR, YA/YR, ZR/YR) for w1 <= 3",
                "",
                0.0,
                change_up_to_3,
                SAME_NODE,
            )
            .with_note("'w1 > 3 necessary before a considerable change in geometry'"),
    );
    let w1_jump = match jump {
        Some((below, above)) => Some(bisect_jump(below, above, &base, cache, context)?),
        None => None,
    };
    let above_3 = w1_jump.is_some_and(|w| w > 3.0);
    rows.push(
        source
            .check(
                "w1_jump_above_3",
                "",
                1.0,
                f64::from(u8::from(above_3)),
                0.0,
            )
            .with_note(match w1_jump {
                Some(w) => {
                    format!("1 when the geometry's first jump lies above w1 = 3; it is at w1 = {w}")
                }
                None => format!("0: no jump of the geometry found for w1 <= {previous}"),
            }),
    );
    if let Some(w1_jump) = w1_jump {
        rows.push(source.info("w1_jump", "", w1_jump).with_note(
            "weight above which (L1/YR, YA/YR, ZR/YR) moves by more than 0.1; the paper says w1 > 3",
        ));
    }
    Ok(rows)
}

/// Bisects the jump of the geometry between `below` and `above` to 0.01 (full mode only).
fn bisect_jump(
    mut below: f64,
    mut above: f64,
    base: &Optimum,
    cache: &SectionIndexCache,
    context: &Context<'_>,
) -> Result<f64, ExperimentError> {
    let resolution = context.mode.pick(f64::INFINITY, 0.01);
    while above - below > resolution {
        let mid = 0.5 * (below + above);
        if geometry_change(&at_weights((mid, 1.0), cache, context)?, base) > JUMP {
            above = mid;
        } else {
            below = mid;
        }
    }
    Ok(above)
}

/// Sweep of w2 at w1 = 1: L2/L1 at each weight, the largest change of the other variables, and
/// the largest decrease of L2/L1 (its limit w2 → ∞ is the η2-only optimum, Table 2 row 3).
///
/// # Errors
/// As [`optimise`].
pub fn w2_sweep(
    context: &Context<'_>,
    cache: &SectionIndexCache,
) -> Result<Vec<Comparison>, ExperimentError> {
    let source = Source::new(
        "miller2004.linear_delta.sensitivity.w2",
        Paper::Miller2004,
        "§2.2.4, increasing w2",
    );
    let weights = match context.mode {
        Mode::Quick => &[1.0, 2.0, 10.0][..],
        Mode::Full => &[1.0, 1.1, 1.2, 1.5, 2.0, 3.0, 5.0, 10.0, 100.0],
    };
    let base = at_weights((1.0, 1.0), cache, context)?;
    let limit = at_weights((0.0, 1.0), cache, context)?;
    let mut rows = Vec::new();
    let mut change: f64 = geometry_change(&limit, &base);
    let mut decrease: f64 = base.design[3] - limit.design[3];
    for &w2 in weights {
        let optimum = at_weights((1.0, w2), cache, context)?;
        rows.push(source.info(&format!("L2/L1 (w2={w2})"), "", optimum.design[3]));
        change = change.max(geometry_change(&optimum, &base));
        decrease = decrease.max(base.design[3] - optimum.design[3]);
    }
    rows.push(source.info("L2/L1 (w2 -> infinity)", "", limit.design[3]));
    rows.push(source.check(
        "max change of (L1/YR, YA/YR, ZR/YR)",
        "",
        0.0,
        change,
        SAME_NODE,
    ));
    rows.push(
        source
            .check("max decrease of L2/L1", "", 0.03, decrease, SAME_NODE)
            .with_note("the limit w2 -> infinity is the eta2-only optimum"),
    );
    Ok(rows)
}
