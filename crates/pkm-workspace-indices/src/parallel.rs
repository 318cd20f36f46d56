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

/// Reduces `visit(acc, i)` over `i in 0..n` deterministically and in parallel, for any `n`
/// (the partial results are held in batches of bounded size, never all at once).
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
    chunked_reduce_ranges(n, progress, |acc, range| {
        for i in range {
            visit(acc, i);
        }
    })
}

/// [`chunked_reduce`] with `visit(acc, range)` called once per chunk, on the chunk's index
/// range (at most [`CHUNK_SIZE`] long): for a visitor that works on several indices at once
/// (a lane kernel) and then accumulates them in index order, with the bits of
/// [`chunked_reduce`].
///
/// # Errors
/// [`Cancelled`] when `progress` asks to stop.
pub fn chunked_reduce_ranges<A, F>(
    n: u64,
    progress: &dyn Progress,
    visit: F,
) -> Result<A, Cancelled>
where
    A: Accumulator,
    F: Fn(&mut A, std::ops::Range<u64>) + Sync,
{
    let n_chunks = n.div_ceil(CHUNK_SIZE);
    let mut total = A::default();
    // Batches of chunks, so that the partial results held at once stay bounded whatever `n`;
    // the merge order (chunk after chunk) and therefore the bits are those of one batch.
    let mut first = 0;
    while first < n_chunks {
        let last = first.saturating_add(CHUNKS_PER_BATCH).min(n_chunks);
        let partials: Vec<Result<A, Cancelled>> = (first..last)
            .into_par_iter()
            .map(|chunk| {
                progress.check()?;
                let mut acc = A::default();
                let start = chunk * CHUNK_SIZE;
                let end = start.saturating_add(CHUNK_SIZE).min(n);
                visit(&mut acc, start..end);
                progress.advance(end - start);
                Ok(acc)
            })
            .collect();
        for partial in partials {
            total.merge(partial?);
        }
        first = last;
    }
    Ok(total)
}

/// Chunks reduced in parallel before their partial results are merged: 2¹⁴ chunks (6.7·10⁷
/// indices) per batch, so a reduction over any `n` holds at most this many partial results
/// (25 MB for the 1.5 kB sums of the volume estimator).
const CHUNKS_PER_BATCH: u64 = 1 << 14;
