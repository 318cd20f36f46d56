//! Seeded, deterministic multistart: start points in a box and a parallel run over them.

use crate::OptimizeError;
use pkm_traits::Bounds;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Most start points of one multistart: the starts are allocated up front.
pub const MAX_STARTS: usize = 1 << 20;

/// `n_starts` points drawn uniformly in the box `bounds`; start `k` is a pure function of
/// `(seed, k)`, so adding starts never changes the earlier ones.
///
/// # Errors
/// [`OptimizeError::InvalidSetting`] for more than [`MAX_STARTS`] starts (refused before
/// allocating).
///
/// # Example
/// ```
/// use pkm_optimizers::uniform_start_points;
/// use pkm_traits::Bounds;
/// let b = [Bounds::new(0.0, 1.0).unwrap(), Bounds::new(-2.0, 2.0).unwrap()];
/// let starts = uniform_start_points(&b, 8, 42).unwrap();
/// assert_eq!(starts.len(), 8);
/// assert!(starts.iter().all(|p| b[0].contains(p[0]) && b[1].contains(p[1])));
/// assert_eq!(starts[..4], uniform_start_points(&b, 4, 42).unwrap()[..]);
/// assert!(uniform_start_points(&b, usize::MAX, 42).is_err());
/// ```
pub fn uniform_start_points(
    bounds: &[Bounds],
    n_starts: usize,
    seed: u64,
) -> Result<Vec<Vec<f64>>, OptimizeError> {
    if n_starts > MAX_STARTS {
        return Err(OptimizeError::InvalidSetting {
            setting: "n_starts",
            value: n_starts as f64,
            requirement: "at most MAX_STARTS start points",
        });
    }
    Ok((0..n_starts)
        .map(|k| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(k as u64);
            bounds
                .iter()
                .map(|b| b.lower() + b.width() * rng.random::<f64>())
                .collect()
        })
        .collect())
}

/// Runs `local` from every start in parallel and returns the outcomes in start order, so the
/// caller's choice of the best is independent of the thread count.
pub fn run_multistart<R, F>(starts: &[Vec<f64>], local: F) -> Vec<R>
where
    R: Send,
    F: Fn(&[f64]) -> R + Sync,
{
    starts.par_iter().map(|start| local(start)).collect()
}
