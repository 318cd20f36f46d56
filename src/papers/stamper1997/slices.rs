//! Sections $z = 0.5$ of $1/\kappa$ for the paper's two optimal designs (Figs. 5–6), and the
//! sampled workspaces of both designs.

use super::problem::design;
use crate::papers::{
    Context, ExperimentError, Figure, FigureKind, Heatmap, LinePlot, LineSeries, Outcome, Paper,
    SeriesStyle, Source,
};
use pkm_workspace_indices::{Sampler, Slice, inverse_condition_number_3x3};

/// The paper's maximum-volume design (sec. 5).
pub(super) const MAX_VOLUME_DESIGN: [f64; 6] = [0.4, 0.6, 0.0, 0.0, 5.0, 355.0];
/// The paper's maximum-GCI design (sec. 5).
pub(super) const MAX_GCI_DESIGN: [f64; 6] = [0.44, 0.56, 0.0, 0.0, 120.0, 240.0];

/// `1/κ` on $z = 0.5$ for `paper_design`, its maximum vs the paper's `paper_max`.
///
/// # Errors
/// An invalid design or grid.
pub(super) fn run_slice(
    ctx: &Context<'_>,
    id: &str,
    figure: &str,
    paper_design: [f64; 6],
    paper_max: f64,
    tolerance: f64,
) -> Result<Outcome, ExperimentError> {
    let d = design(&paper_design)?;
    let n = ctx.mode.pick(60, 240);
    let slice = Slice::square(0.5, d.reach(), n, |x, y, z| {
        d.jacobian_eq7(&nalgebra::Vector3::new(x, y, z))
            .map(|j| inverse_condition_number_3x3(&j))
    })?;
    let (max, x, y) = slice.max().unwrap_or((0.0, f64::NAN, f64::NAN));
    let source = Source::new(id, Paper::Stamper1997, figure);
    let row = source
        .check("max_inv_cond", "1", paper_max, max, tolerance)
        .erratum("stamper-slice-maxima")
        .with_note(format!("at (x, y) = ({x:.3}, {y:.3}), {n}x{n} grid"));
    let heatmap = Heatmap {
        x_label: "x / R".into(),
        y_label: "y / R".into(),
        z_label: "1/κ".into(),
        x: slice.x,
        y: slice.y,
        values: slice.values,
    };
    let mut figures = vec![Figure {
        name: "slice_z0.5".into(),
        title: format!("1/κ on z = 0.5 ({figure})"),
        kind: FigureKind::Heatmap(heatmap),
    }];
    figures.push(workspace_figure(&paper_design, ctx)?);
    Ok(Outcome {
        comparisons: vec![row],
        figures,
        ..Outcome::default()
    })
}

/// Side view $(x, z)$ of sampled points inside the workspace of `paper_design`.
fn workspace_figure(paper_design: &[f64; 6], ctx: &Context<'_>) -> Result<Figure, ExperimentError> {
    let d = design(paper_design)?;
    let points = Sampler::Sobol { seed: 5 }.unit_hemisphere_points(ctx.mode.pick(4_000, 20_000))?;
    let inside: Vec<(f64, f64)> = points
        .iter()
        .map(|p| p * d.reach())
        .filter(|p| d.contains(p))
        .map(|p| (p.x, p.z))
        .collect();
    Ok(Figure {
        name: "workspace_xz".into(),
        title: format!(
            "workspace of a = {}, b = {}, legs 0/{}/{}: sampled inside points, side view",
            paper_design[0], paper_design[1], paper_design[4], paper_design[5]
        ),
        kind: FigureKind::Lines(LinePlot {
            x_label: "x / R".into(),
            y_label: "z / R".into(),
            series: vec![LineSeries {
                label: "inside".into(),
                style: SeriesStyle::Points,
                points: inside,
            }],
        }),
    })
}
