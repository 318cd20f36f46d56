//! Workspaces in any task space: a box of $n \le 6$ task coordinates (lengths and angles
//! mixed), sampled without storing its points, and three estimators over it:
//! - [`task_volume_and_eta`]: the measure $W$ of $\{u : \texttt{local}(u) \ne \text{None}\}$ and
//!   $\eta = \int f\,dW$, with the estimator of [`crate::workspace_volume_and_eta`]
//!   ($W = V_D\,n_{in}/n$, standard errors from replicates or the i.i.d. formulas);
//! - [`nested_task_volumes`]: the same for a nested family of sets $S_0 \supseteq S_1 \supseteq
//!   \dots$ in one pass (a dexterous workspace over refined orientation grids);
//! - [`connected_task_volume`]: the part of a set on a regular grid that is connected to a
//!   given point through neighbouring cells (a singularity-free workspace).
//!
//! The measure is that of the coordinates: a box over $(x, y, r_z)$ in m, m and rad has
//! measure in m²·rad. Point $i$ is a pure function of the sampler, its seed and $i$, and every
//! sum is taken in fixed chunks merged in index order ([`crate::chunked_reduce_ranges`]), so
//! the bits do not depend on the thread count; memory is bounded by a chunk, not the sample.

use crate::estimator::{Sums, summarise};
use crate::parallel::chunked_reduce_ranges;
use crate::points::MAX_POINTS;
use crate::sobol::{SOBOL_DIMENSIONS, sobol_n};
use crate::{Accumulator, IndexError, Sampler, VolumeEstimate};
use pkm_traits::{InvalidInput, Progress};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::collections::VecDeque;

/// Most task coordinates: a platform pose has six.
pub const MAX_TASK_DIMENSION: usize = SOBOL_DIMENSIONS;

/// Most cells of a [`connected_task_volume`] grid (one byte each while it is searched).
pub const MAX_GRID_CELLS: u64 = 1 << 26;

/// A box $\prod_k [l_k, u_k]$ of task coordinates, each side finite and positive, its measure
/// finite and positive.
#[derive(Debug, Clone, PartialEq)]
pub struct TaskBox {
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl TaskBox {
    /// The box `[lower, upper]`.
    ///
    /// # Errors
    /// [`IndexError::Invalid`] for sides of different lengths, no side or more than
    /// [`MAX_TASK_DIMENSION`], a bound that is not finite, a side with $u_k \le l_k$, or a
    /// measure that is zero or not finite (sides too small or too large for `f64`).
    pub fn new(lower: Vec<f64>, upper: Vec<f64>) -> Result<Self, IndexError> {
        let n = lower.len();
        if n != upper.len() || n == 0 || n > MAX_TASK_DIMENSION {
            return Err(invalid(
                "task box dimension",
                n as f64,
                "1 to 6 coordinates, as many lower as upper bounds",
            ));
        }
        for (l, u) in lower.iter().zip(&upper) {
            if !(l.is_finite() && u.is_finite()) {
                return Err(invalid(
                    "task box bound",
                    if l.is_finite() { *u } else { *l },
                    "finite",
                ));
            }
            if !(u - l > 0.0) || !(u - l).is_finite() {
                return Err(invalid(
                    "task box side",
                    u - l,
                    "upper bound above the lower bound, the side finite",
                ));
            }
        }
        let b = Self { lower, upper };
        let measure = b.measure();
        if !(measure > 0.0 && measure.is_finite()) {
            return Err(invalid("task box measure", measure, "positive and finite"));
        }
        Ok(b)
    }

    /// Number of coordinates $n$.
    pub fn dimension(&self) -> usize {
        self.lower.len()
    }

    /// Lower corner.
    pub fn lower(&self) -> &[f64] {
        &self.lower
    }

    /// Upper corner.
    pub fn upper(&self) -> &[f64] {
        &self.upper
    }

    /// Its measure $\prod_k (u_k - l_k)$.
    pub fn measure(&self) -> f64 {
        self.lower
            .iter()
            .zip(&self.upper)
            .map(|(l, u)| u - l)
            .product()
    }

    /// The point of unit-cube coordinates `unit` (in place).
    fn map(&self, unit: &mut [f64]) {
        for ((v, l), u) in unit.iter_mut().zip(&self.lower).zip(&self.upper) {
            *v = l + (u - l) * *v;
        }
    }
}

fn invalid(name: &'static str, value: f64, requirement: &'static str) -> IndexError {
    InvalidInput::new(name, value, requirement).into()
}

/// The points of a task-space estimate: `replicates` blocks of `per_replicate` points of
/// `sampler` in `region`, replicate $r$ drawn with [`Sampler::reseeded`]`(r)`. The points are
/// computed when asked, never stored.
#[derive(Debug, Clone, PartialEq)]
pub struct TaskPoints {
    region: TaskBox,
    sampler: Sampler,
    per_replicate: u64,
    replicates: u32,
}

impl TaskPoints {
    /// Random or quasi-random points: `replicates` × `per_replicate` of them. A grid sampler
    /// has one replicate of `per_axis`$^n$ cell centres whatever the counts given.
    ///
    /// # Errors
    /// [`IndexError::EmptySample`] for no point; [`IndexError::TooLarge`] for more than
    /// [`MAX_REPLICATES`](crate::MAX_REPLICATES) replicates or [`MAX_POINTS`] points; [`IndexError::Invalid`] for a
    /// Sobol sampler in more than [`MAX_TASK_DIMENSION`] coordinates.
    pub fn new(
        region: TaskBox,
        sampler: Sampler,
        per_replicate: u64,
        replicates: u32,
    ) -> Result<Self, IndexError> {
        let (per_replicate, replicates) = match sampler {
            Sampler::Grid { per_axis } => (grid_cells(per_axis, region.dimension())?, 1),
            _ => (per_replicate, replicates),
        };
        crate::points::check_counts(per_replicate, replicates)?;
        Ok(Self {
            region,
            sampler,
            per_replicate,
            replicates,
        })
    }

    /// The region.
    pub fn region(&self) -> &TaskBox {
        &self.region
    }

    /// Points per replicate.
    pub fn per_replicate(&self) -> u64 {
        self.per_replicate
    }

    /// Replicates.
    pub fn replicates(&self) -> u32 {
        self.replicates
    }

    /// All points, every replicate.
    pub fn total(&self) -> u64 {
        self.per_replicate * u64::from(self.replicates)
    }

    /// Point $k$ (point $k \bmod m$ of replicate $\lfloor k/m \rfloor$) into `out` (length
    /// $n$).
    pub fn point(&self, k: u64, out: &mut [f64]) {
        let (r, i) = (k / self.per_replicate, k % self.per_replicate);
        self.sampler.reseeded(r).unit_cube_n(i, out);
        self.region.map(out);
    }
}

/// Cells of a grid of `per_axis` cells per side in `n` coordinates, at most [`MAX_POINTS`].
fn grid_cells(per_axis: u32, n: usize) -> Result<u64, IndexError> {
    let cells = (0..n).try_fold(1u64, |c, _| c.checked_mul(per_axis.into()));
    match cells {
        Some(c) if c <= MAX_POINTS => Ok(c),
        _ => Err(IndexError::TooLarge {
            what: "grid cells",
            requested: cells.unwrap_or(u64::MAX),
            limit: MAX_POINTS,
        }),
    }
}

impl Sampler {
    /// Point $i$ in the unit cube $[0, 1)^n$, $n$ = `out.len()`: ChaCha8 stream $i$ of the seed
    /// (its first three numbers are those of [`Sampler::unit_cube`]), the Sobol sequence's
    /// first $n \le 6$ dimensions (those of [`Sampler::unit_cube`] first), or the centre of cell
    /// $i$ of a `per_axis`$^n$ grid in lexicographic order (the first coordinate slowest).
    /// A Sobol point in more than six coordinates leaves the extra ones at 0.5 (callers check
    /// the dimension: [`TaskPoints::new`]).
    pub fn unit_cube_n(&self, i: u64, out: &mut [f64]) {
        match *self {
            Self::MonteCarlo { seed } => {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                rng.set_stream(i);
                out.iter_mut().for_each(|v| *v = rng.random());
            }
            Self::Sobol { seed } => {
                out.iter_mut().for_each(|v| *v = 0.5);
                sobol_n(i, seed, out);
            }
            Self::Grid { per_axis } => {
                let n = u64::from(per_axis.max(1));
                let mut rest = i;
                for v in out.iter_mut().rev() {
                    *v = ((rest % n) as f64 + 0.5) / n as f64;
                    rest /= n;
                }
            }
        }
    }
}

/// $W$ and $\eta = \int f\,dW$ over `points`, $f$ = `local(u)` where it is `Some` (inside;
/// a non-finite $f$ counts as 0) — the estimator of [`crate::workspace_volume_and_eta`] on
/// points of any dimension.
///
/// # Errors
/// [`IndexError::Cancelled`] when `progress` asks to stop (checked once per chunk);
/// [`IndexError::NonFinite`] when $\eta$ overflows.
///
/// # Example
/// ```
/// use pkm_traits::Silent;
/// use pkm_workspace_indices::{Sampler, TaskBox, TaskPoints, task_volume_and_eta};
/// // The unit 4-ball, π²/2, in the box [-1, 1]⁴.
/// let region = TaskBox::new(vec![-1.0; 4], vec![1.0; 4])?;
/// let points = TaskPoints::new(region, Sampler::Sobol { seed: 5 }, 1 << 14, 4)?;
/// let e = task_volume_and_eta(&points, &Silent, |u| (u.iter().map(|v| v * v).sum::<f64>() <= 1.0).then_some(1.0))?;
/// let exact = std::f64::consts::PI.powi(2) / 2.0;
/// assert!((e.volume - exact).abs() < 5.0 * e.volume_se);
/// # Ok::<(), pkm_workspace_indices::IndexError>(())
/// ```
pub fn task_volume_and_eta<F>(
    points: &TaskPoints,
    progress: &dyn Progress,
    local: F,
) -> Result<VolumeEstimate, IndexError>
where
    F: Fn(&[f64]) -> Option<f64> + Sync,
{
    let nested = nested_task_volumes(points, 1, progress, |u| match local(u) {
        Some(f) => (1, Some(f)),
        None => (0, None),
    })?;
    nested
        .into_iter()
        .next()
        .ok_or(IndexError::EmptySample { n_samples: 0 })
}

/// Per-level sums of a nested estimate.
#[derive(Default)]
struct LevelSums(Vec<Sums>);

impl Accumulator for LevelSums {
    fn merge(&mut self, later: Self) {
        if self.0.is_empty() {
            self.0 = later.0;
            return;
        }
        for (a, b) in self.0.iter_mut().zip(later.0) {
            a.merge(b);
        }
    }
}

/// One estimate per level $\ell < L$ = `levels` of a nested family $S_0 \supseteq S_1
/// \supseteq \dots \supseteq S_{L-1}$: `local(u)` returns how many levels $u$ belongs to
/// ($u \in S_\ell$ for $\ell <$ that count; counts above $L$ are read as $L$) and the local
/// index $f(u)$ integrated over every level that holds $u$. The sets share their points, so
/// the differences between levels are free of sampling noise between them.
///
/// # Errors
/// [`IndexError::Invalid`] for `levels` outside 1..=16; otherwise as
/// [`task_volume_and_eta`].
pub fn nested_task_volumes<F>(
    points: &TaskPoints,
    levels: usize,
    progress: &dyn Progress,
    local: F,
) -> Result<Vec<VolumeEstimate>, IndexError>
where
    F: Fn(&[f64]) -> (usize, Option<f64>) + Sync,
{
    if !(1..=16).contains(&levels) {
        return Err(invalid("levels", levels as f64, "1 to 16 nested sets"));
    }
    let m = points.per_replicate;
    let n = points.region.dimension();
    let sums = chunked_reduce_ranges(points.total(), progress, |acc: &mut LevelSums, range| {
        if acc.0.is_empty() {
            acc.0 = (0..levels).map(|_| Sums::default()).collect();
        }
        let mut u = vec![0.0; n];
        for k in range {
            points.point(k, &mut u);
            let (count, f) = local(&u);
            let f = f.filter(|f| f.is_finite()).unwrap_or(0.0);
            let r = (k / m) as usize;
            for level in &mut acc.0[..count.min(levels)] {
                level.inside[r] += 1;
                level.f[r] += f;
                level.f2[r] += f * f;
            }
        }
    })?;
    let measure = points.region.measure();
    let empty = (0..levels).map(|_| Sums::default());
    let sums: Vec<Sums> = if sums.0.is_empty() {
        empty.collect()
    } else {
        sums.0
    };
    sums.iter()
        .map(|s| summarise(s, points.replicates as usize, m, measure))
        .collect()
}

/// The part of a set that is connected to a point, on a grid ([`connected_task_volume`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ConnectedVolume {
    /// Cells per side.
    pub per_axis: u32,
    /// Measure of one cell.
    pub cell_measure: f64,
    /// Cells whose centre is in the set.
    pub cells_inside: u64,
    /// Cells of the set connected to the start cell through faces.
    pub cells_connected: u64,
    /// `cells_inside` × `cell_measure`.
    pub volume_inside: f64,
    /// `cells_connected` × `cell_measure`.
    pub volume_connected: f64,
}

/// The measure of the cells of a `per_axis`$^n$ grid over `region` whose centres are in the set
/// (`inside(centre)`) and that are connected to the cell holding `start` through shared faces
/// (each cell's $2n$ face neighbours): a grid approximation of the connected component of
/// the set through `start`. A wall of the complement thinner than a cell can be stepped over,
/// and a neck thinner than a cell can be cut; both vanish as `per_axis` grows.
///
/// # Errors
/// [`IndexError::Invalid`] when `start` has the wrong length or lies outside the region or
/// in a cell outside the set; [`IndexError::TooLarge`] for more than [`MAX_GRID_CELLS`]
/// cells (refused before allocating); [`IndexError::Cancelled`].
pub fn connected_task_volume<F>(
    region: &TaskBox,
    per_axis: u32,
    start: &[f64],
    progress: &dyn Progress,
    inside: F,
) -> Result<ConnectedVolume, IndexError>
where
    F: Fn(&[f64]) -> bool + Sync,
{
    let n = region.dimension();
    let cells = grid_cells(per_axis, n)?;
    if cells > MAX_GRID_CELLS || per_axis == 0 {
        return Err(IndexError::TooLarge {
            what: "grid cells",
            requested: cells,
            limit: MAX_GRID_CELLS,
        });
    }
    let start_cell = cell_of(region, per_axis, start)?;
    let points = TaskPoints::new(region.clone(), Sampler::Grid { per_axis }, cells, 1)?;
    let member = grid_membership(&points, progress, &inside)?;
    if !member[start_cell as usize] {
        return Err(invalid(
            "start of the connected region",
            start_cell as f64,
            "a cell whose centre is in the set (the start pose is not)",
        ));
    }
    let connected = flood_fill(&member, per_axis, n, start_cell);
    let cells_inside = member.iter().filter(|m| **m).count() as u64;
    let cell_measure = region.measure() / cells as f64;
    Ok(ConnectedVolume {
        per_axis,
        cell_measure,
        cells_inside,
        cells_connected: connected,
        volume_inside: cells_inside as f64 * cell_measure,
        volume_connected: connected as f64 * cell_measure,
    })
}

/// The index of the grid cell that holds `u`.
fn cell_of(region: &TaskBox, per_axis: u32, u: &[f64]) -> Result<u64, IndexError> {
    if u.len() != region.dimension() {
        return Err(invalid(
            "start point coordinates",
            u.len() as f64,
            "as many as the region has",
        ));
    }
    let mut index = 0u64;
    for ((v, l), h) in u.iter().zip(&region.lower).zip(&region.upper) {
        if !(l <= v && v <= h) {
            return Err(invalid("start point", *v, "inside the sampled region"));
        }
        let c = (((v - l) / (h - l)) * f64::from(per_axis)) as u64;
        index = index * u64::from(per_axis) + c.min(u64::from(per_axis) - 1);
    }
    Ok(index)
}

/// Membership of every cell centre, in parallel chunks that each check `progress`.
fn grid_membership<F>(
    points: &TaskPoints,
    progress: &dyn Progress,
    inside: &F,
) -> Result<Vec<bool>, IndexError>
where
    F: Fn(&[f64]) -> bool + Sync,
{
    let n = points.region.dimension();
    let mut member = vec![false; points.total() as usize];
    member
        .par_chunks_mut(crate::CHUNK_SIZE as usize)
        .enumerate()
        .try_for_each(|(c, chunk)| {
            progress.check()?;
            let mut u = vec![0.0; n];
            for (j, m) in chunk.iter_mut().enumerate() {
                points.point(c as u64 * crate::CHUNK_SIZE + j as u64, &mut u);
                *m = inside(&u);
            }
            progress.advance(chunk.len() as u64);
            Ok::<(), IndexError>(())
        })?;
    Ok(member)
}

/// Cells of `member` reached from `start` through faces (breadth first).
fn flood_fill(member: &[bool], per_axis: u32, n: usize, start: u64) -> u64 {
    let side = u64::from(per_axis);
    let mut seen = vec![false; member.len()];
    let mut queue = VecDeque::from([start]);
    seen[start as usize] = true;
    let mut count = 0;
    while let Some(cell) = queue.pop_front() {
        count += 1;
        let mut stride = 1u64;
        for _ in 0..n {
            let digit = (cell / stride) % side;
            let down = (digit > 0).then(|| cell - stride);
            let up = (digit + 1 < side).then(|| cell + stride);
            for next in [down, up].into_iter().flatten() {
                if member[next as usize] && !seen[next as usize] {
                    seen[next as usize] = true;
                    queue.push_back(next);
                }
            }
            stride *= side;
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use pkm_traits::Silent;

    fn cube(n: usize) -> TaskBox {
        TaskBox::new(vec![-1.0; n], vec![1.0; n]).unwrap()
    }

    #[test]
    fn boxes_without_measure_are_refused() {
        assert!(TaskBox::new(vec![0.0], vec![0.0]).is_err());
        assert!(TaskBox::new(vec![0.0, 1.0], vec![1.0]).is_err());
        assert!(TaskBox::new(vec![f64::NAN], vec![1.0]).is_err());
        assert!(TaskBox::new(vec![-1e300; 3], vec![1e300; 3]).is_err());
        assert!(TaskBox::new(vec![0.0; 7], vec![1.0; 7]).is_err());
        assert!(TaskBox::new(vec![], vec![]).is_err());
    }

    #[test]
    fn the_bits_do_not_depend_on_the_thread_count() {
        let points = TaskPoints::new(cube(5), Sampler::MonteCarlo { seed: 3 }, 30_000, 3).unwrap();
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                task_volume_and_eta(&points, &Silent, |u| {
                    (u[0] + u[1] < 0.3).then(|| u[2].abs())
                })
                .unwrap()
            })
        };
        let (one, four) = (run(1), run(4));
        assert_eq!(one.volume.to_bits(), four.volume.to_bits());
        assert_eq!(one.eta.unwrap().to_bits(), four.eta.unwrap().to_bits());
    }

    #[test]
    fn a_half_space_of_a_six_cube_has_half_its_measure() {
        for sampler in [Sampler::Sobol { seed: 2 }, Sampler::MonteCarlo { seed: 2 }] {
            let points = TaskPoints::new(cube(6), sampler, 1 << 13, 4).unwrap();
            let e = task_volume_and_eta(&points, &Silent, |u| (u[5] - u[2] < 0.0).then_some(1.0))
                .unwrap();
            assert!(
                (e.volume - 32.0).abs() < 5.0 * e.volume_se,
                "{sampler:?}: {e:?}"
            );
            assert!(e.volume_se > 0.0 && e.volume_se < 0.5);
        }
    }

    #[test]
    fn nested_levels_count_nested_balls() {
        // Balls of radius 1, 0.8, 0.5 in 3-D: 4π/3 r³.
        let radii = [1.0, 0.8, 0.5];
        let points = TaskPoints::new(cube(3), Sampler::Sobol { seed: 4 }, 1 << 14, 4).unwrap();
        let e = nested_task_volumes(&points, 3, &Silent, |u| {
            let r = u.iter().map(|v| v * v).sum::<f64>().sqrt();
            (radii.iter().filter(|&&b| r <= b).count(), Some(1.0))
        })
        .unwrap();
        for (level, r) in radii.iter().enumerate() {
            let exact = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
            assert!(
                (e[level].volume - exact).abs() < 5.0 * e[level].volume_se,
                "level {level}"
            );
        }
    }

    #[test]
    fn two_separate_blocks_are_two_components() {
        // |u0| > 0.2 splits the square into two halves of measure 1.6 each.
        let region = cube(2);
        let c =
            connected_task_volume(&region, 50, &[0.9, 0.0], &Silent, |u| u[0].abs() > 0.2).unwrap();
        assert_eq!(c.cells_inside, 2 * c.cells_connected);
        assert!((c.volume_connected - 1.6).abs() < 1e-12, "{c:?}");
        let closed = connected_task_volume(&region, 50, &[0.9, 0.0], &Silent, |u| {
            u[0].abs() > 0.2 || u[1] > 0.5
        })
        .unwrap();
        assert_eq!(closed.cells_connected, closed.cells_inside);
        assert!(
            connected_task_volume(&region, 50, &[0.0, 0.0], &Silent, |u| u[0].abs() > 0.2).is_err()
        );
        assert!(connected_task_volume(&cube(6), 64, &[0.0; 6], &Silent, |_| true).is_err());
    }

    #[test]
    fn grid_cells_are_the_3d_grid_in_three_coordinates() {
        let mut u = [0.0; 3];
        for i in [0, 7, 100, 511] {
            Sampler::Grid { per_axis: 8 }.unit_cube_n(i, &mut u);
            assert_eq!(
                u.map(f64::to_bits),
                Sampler::Grid { per_axis: 8 }.unit_cube(i).map(f64::to_bits)
            );
            Sampler::MonteCarlo { seed: 9 }.unit_cube_n(i, &mut u);
            assert_eq!(
                u.map(f64::to_bits),
                Sampler::MonteCarlo { seed: 9 }
                    .unit_cube(i)
                    .map(f64::to_bits)
            );
        }
    }
}
