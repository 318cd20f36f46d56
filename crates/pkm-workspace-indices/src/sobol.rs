//! The first three dimensions of the Sobol sequence (Joe & Kuo 2008 direction numbers), 32-bit,
//! with an optional random digital shift, in natural order. Computed directly from the bits of $i$, so point $i$
//! costs $O(32)$ and needs no state beyond a per-thread memo of the last digital shift.
//!
//! `sobol_burley` was considered; it stops at $2^{16}$ points and returns `f32`, too few and too
//! coarse for the 200,000-point sets of Stamper et al.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::cell::Cell;

const BITS: usize = 32;

/// Direction numbers $v_k = m_k 2^{32-k}$ of dimension `d` (0: van der Corput; 1: $x + 1$,
/// $m = 1$; 2: $x^2 + x + 1$, $m = 1, 3$).
const fn directions(d: usize) -> [u32; BITS] {
    let mut m = [0u64; BITS];
    let mut k = 0;
    while k < BITS {
        m[k] = match d {
            0 => 1,
            1 => {
                if k == 0 {
                    1
                } else {
                    (2 * m[k - 1]) ^ m[k - 1]
                }
            }
            _ => {
                if k == 0 {
                    1
                } else if k == 1 {
                    3
                } else {
                    (2 * m[k - 1]) ^ (4 * m[k - 2]) ^ m[k - 2]
                }
            }
        };
        k += 1;
    }
    let mut v = [0u32; BITS];
    let mut k = 0;
    while k < BITS {
        v[k] = (m[k] << (BITS - 1 - k)) as u32;
        k += 1;
    }
    v
}

const DIRECTIONS: [[u32; BITS]; 3] = [directions(0), directions(1), directions(2)];

/// The digital shift of `seed` (none for 0): three words of ChaCha8 seeded with `seed`,
/// remembered per thread for the last seed asked, since a point set asks the same seed for
/// every point and seeding ChaCha costs more than the point.
fn digital_shift(seed: u64) -> [u32; 3] {
    thread_local! {
        static LAST: Cell<Option<(u64, [u32; 3])>> = const { Cell::new(None) };
    }
    if seed == 0 {
        return [0; 3];
    }
    LAST.with(|last| match last.get() {
        Some((s, shift)) if s == seed => shift,
        _ => {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let shift = [rng.random(), rng.random(), rng.random()];
            last.set(Some((seed, shift)));
            shift
        }
    })
}

/// Point $i$ of the 3-D Sobol sequence in $[0, 1)^3$, digitally shifted by a pure function of
/// `seed` (no shift when `seed = 0`). Indices wrap modulo $2^{32}$.
pub(crate) fn sobol3(i: u64, seed: u64) -> [f64; 3] {
    let shift = digital_shift(seed);
    let index = i as u32;
    let mut out = [0.0; 3];
    for (d, value) in out.iter_mut().enumerate() {
        let mut x = shift[d];
        for (k, v) in DIRECTIONS[d].iter().enumerate() {
            if (index >> k) & 1 == 1 {
                x ^= v;
            }
        }
        *value = f64::from(x) / 4_294_967_296.0;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_points_match_the_published_sequence() {
        // Joe–Kuo in natural (not Gray-code) order: point i XORs v_k for the set bits k of i.
        // Gray-code point 4, (.375, .375, .625), is natural point 6.
        let expected = [
            [0.0, 0.0, 0.0],
            [0.5, 0.5, 0.5],
            [0.25, 0.75, 0.75],
            [0.75, 0.25, 0.25],
            [0.125, 0.625, 0.375],
            [0.625, 0.125, 0.875],
            [0.375, 0.375, 0.625],
        ];
        for (i, e) in expected.iter().enumerate() {
            let p = sobol3(i as u64, 0);
            assert!(
                p.iter().zip(e).all(|(a, b)| (a - b).abs() < 1e-12),
                "{i}: {p:?}"
            );
        }
    }

    #[test]
    fn every_dimension_is_stratified_in_dyadic_blocks() {
        for d in 0..3 {
            let mut seen = [false; 64];
            for i in 0..64 {
                seen[(sobol3(i, 7)[d] * 64.0) as usize] = true;
            }
            assert!(seen.iter().all(|&s| s), "dimension {d}");
        }
    }
}
