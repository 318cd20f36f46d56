//! The per-row kernels of `pkm.Mechanism`, as [`WorkspaceVisitor`]s of the study layer's built
//! workspace (so the constraints and working modes are the studies'), mapped over the rows on
//! rayon threads. Each row is independent, so the output is the same for any thread count.
//! 1/κ and membership go through the library's lane kernels eight rows at a time
//! (`Workspace::inverse_condition_lanes`, `Workspace::contains_lanes`): membership as the point
//! test exactly, 1/κ equal to it to rounding and to the values the workspace studies integrate.

use nalgebra::Vector3;
use numpy::ndarray::ArrayView2;
use pkm_study::registry::{Built, ForwardVisitor};
use pkm_study::schema::mechanism::{MechanismSpec, WorkspaceVisitor};
use pkm_traits::{ConstrainedWorkspace, ForwardKinematics, NewtonSettings};
use pkm_workspace_indices::{Dim, LANES, TranslationalCondition, Workspace};
use pyo3::prelude::*;
use rayon::prelude::*;

/// Rows per rayon task: large enough that scheduling costs little next to the kinematics.
const ROWS_PER_TASK: usize = 512;

/// What a [`Kernel`] computes at each row.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Op {
    /// The joints of the first mode that assembles within the constraints.
    Inverse,
    /// $J = -J_q^{-1} J_x$ at that assembly, row-major NQ × 3.
    Jacobian,
    /// $1/\kappa$ as the workspace study evaluates it.
    InverseCondition,
    /// Membership only.
    Contains,
}

/// `op` at every row of `points`.
pub(crate) struct Kernel<'a> {
    pub(crate) points: ArrayView2<'a, f64>,
    pub(crate) op: Op,
}

impl WorkspaceVisitor for Kernel<'_> {
    type Output = (Vec<f64>, Vec<bool>);

    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Self::Output
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
        let m = workspace.mechanism();
        let n = self.points.nrows();
        match self.op {
            Op::Inverse => map_rows(n, NQ, |i, out| {
                let q = workspace.assembly(&row(&self.points, i))?;
                out.copy_from_slice(q.as_slice());
                Some(())
            }),
            Op::Jacobian => map_rows(n, NQ * 3, |i, out| {
                let x = row(&self.points, i);
                let j = m.jacobian(&x, &workspace.assembly(&x)?).ok()?;
                for (k, v) in out.iter_mut().enumerate() {
                    *v = j[(k / 3, k % 3)];
                }
                Some(())
            }),
            Op::InverseCondition => map_groups(&self.points, |group| {
                workspace.inverse_condition_lanes(group)
            }),
            Op::Contains => {
                let inside = |group: &_| workspace.contains_lanes(group).map(|b| b.then_some(0.0));
                (Vec::new(), map_groups(&self.points, inside).1)
            }
        }
    }
}

/// The number of actuated joints of a built workspace.
pub(crate) struct JointCount;

impl WorkspaceVisitor for JointCount {
    type Output = usize;
    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        _: &Workspace<'_, M, NQ>,
    ) -> usize
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
        NQ
    }
}

/// Row `i` of an N × 3 array.
fn row(points: &ArrayView2<'_, f64>, i: usize) -> Vector3<f64> {
    Vector3::new(points[(i, 0)], points[(i, 1)], points[(i, 2)])
}

/// `f(i, out)` for every row `i < n` in parallel, writing `width` (≥ 1) values to `out`: NaN
/// and `false` where `f` returns `None`.
pub(crate) fn map_rows<F>(n: usize, width: usize, f: F) -> (Vec<f64>, Vec<bool>)
where
    F: Fn(usize, &mut [f64]) -> Option<()> + Sync,
{
    let mut values = vec![f64::NAN; n * width];
    let mut mask = vec![false; n];
    let visit = |(i, (out, inside)): (usize, (&mut [f64], &mut bool))| {
        *inside = f(i, out).is_some();
        if !*inside {
            out.fill(f64::NAN);
        }
    };
    values
        .par_chunks_mut(width)
        .zip(mask.par_iter_mut())
        .with_min_len(ROWS_PER_TASK)
        .enumerate()
        .for_each(visit);
    (values, mask)
}

/// `f` on the rows in groups of [`LANES`] (the library's lane kernels; the last group padded
/// with its last row), in parallel: one value per row, NaN and `false` where `f` gives `None`.
fn map_groups<F>(points: &ArrayView2<'_, f64>, f: F) -> (Vec<f64>, Vec<bool>)
where
    F: Fn(&[Vector3<f64>; LANES]) -> [Option<f64>; LANES] + Sync,
{
    let n = points.nrows();
    let mut values = vec![f64::NAN; n];
    let mut mask = vec![false; n];
    values
        .par_chunks_mut(LANES)
        .zip(mask.par_chunks_mut(LANES))
        .with_min_len(ROWS_PER_TASK / LANES)
        .enumerate()
        .for_each(|(g, (out, inside))| {
            let first = g * LANES;
            let group = std::array::from_fn(|l| row(points, (first + l).min(n - 1)));
            for ((value, inside), v) in out.iter_mut().zip(inside).zip(f(&group)) {
                (*value, *inside) = (v.unwrap_or(f64::NAN), v.is_some());
            }
        });
    (values, mask)
}

/// Forward kinematics row by row (Newton from `guess`, the library's settings), through the
/// study layer's forward-kinematics visitor (every kind that has it, robot files included).
///
/// # Errors
/// A message for a mechanism without forward kinematics in the platform position, or an
/// invalid design.
pub(crate) fn forward(
    built: &Built<MechanismSpec>,
    q: ArrayView2<'_, f64>,
    guess: ArrayView2<'_, f64>,
) -> Result<(Vec<f64>, Vec<bool>), String> {
    built
        .with_forward_kinematics(ForwardRows { q, guess })
        .map_err(|e| e.to_string())
}

/// The rows of `q` solved from the rows of `guess`.
struct ForwardRows<'a> {
    q: ArrayView2<'a, f64>,
    guess: ArrayView2<'a, f64>,
}

impl ForwardVisitor for ForwardRows<'_> {
    type Output = (Vec<f64>, Vec<bool>);

    fn visit<M: ForwardKinematics<3> + Sync>(self, m: &M) -> Self::Output {
        let (q, guess) = (self.q, self.guess);
        let settings = NewtonSettings::default();
        map_rows(q.nrows(), 3, |i, out| {
            let x = m
                .forward_kinematics(&row(&q, i), &row(&guess, i), &settings)
                .ok()?;
            out.copy_from_slice(x.as_slice());
            Some(())
        })
    }
}

/// `pkm.InvalidInput` naming the first non-finite entry of `values`.
pub(crate) fn require_finite(
    py: Python<'_>,
    values: &ArrayView2<'_, f64>,
    name: &str,
) -> PyResult<()> {
    match values.indexed_iter().find(|(_, v)| !v.is_finite()) {
        None => Ok(()),
        Some(((row, column), v)) => Err(crate::errors::invalid(
            py,
            format!("{name}[{row}, {column}] = {v}: every coordinate must be finite"),
        )),
    }
}
