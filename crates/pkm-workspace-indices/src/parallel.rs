//! Thread-count-independent parallel reductions.
//!
//! Floating-point addition is not associative, so `par_iter().sum()` gives different bits for
//! different thread counts. [`chunked_reduce`] splits the index range into fixed chunks of
//! [`CHUNK_SIZE`], accumulates each chunk serially (in parallel across chunks), and merges the
//! partial results serially in chunk order: the same bits for 1, 2 or 8 threads.

use pkm_traits::{Cancelled, Progress};
use rayon::prelude::*;

/// Number of consecutive indices accumulated serially by one task. Fixed, so that the
/// association order of the sums never depends on the thread count.
pub const CHUNK_SIZE: u64 = 4096;

/// A partial result of a reduction that can absorb the partial result of the next chunk.
pub trait Accumulator: Default + Send {
    /// Absorbs `later`, the result of the chunk that follows `self`'s.
    fn merge(&mut self, later: Self);
}

/// Reduces `visit(acc, i)` over `i in 0..n` deterministically and in parallel.
///
/// Reports `n` units of progress and checks for cancellation once per chunk.
///
/// # Errors
/// [`Cancelled`] when `progress` asks to stop.
///
/// # Example
/// ```
/// use pkm_traits::Silent;
/// use pkm_workspace_indices::{Accumulator, chunked_reduce};
/// #[derive(Default)]
/// struct Sum(f64);
/// impl Accumulator for Sum { fn merge(&mut self, later: Self) { self.0 += later.0 } }
/// let s = chunked_reduce(10_000, &Silent, |acc: &mut Sum, i| acc.0 += i as f64).unwrap();
/// assert_eq!(s.0 as u64, 10_000 * 9_999 / 2);
/// ```
pub fn chunked_reduce<A, F>(n: u64, progress: &dyn Progress, visit: F) -> Result<A, Cancelled>
where
    A: Accumulator,
    F: Fn(&mut A, u64) + Sync,
{
    let n_chunks = n.div_ceil(CHUNK_SIZE);
    let partials: Vec<Result<A, Cancelled>> = (0..n_chunks)
        .into_par_iter()
        .map(|chunk| {
            progress.check()?;
            let mut acc = A::default();
            let end = ((chunk + 1) * CHUNK_SIZE).min(n);
            for i in chunk * CHUNK_SIZE..end {
                visit(&mut acc, i);
            }
            progress.advance(end - chunk * CHUNK_SIZE);
            Ok(acc)
        })
        .collect();
    let mut total = A::default();
    for partial in partials {
        total.merge(partial?);
    }
    Ok(total)
}
