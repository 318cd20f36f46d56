//! The first six dimensions of the Sobol sequence (Joe & Kuo 2008 direction numbers,
//! `new-joe-kuo-6.21201`), 32-bit, with an optional random digital shift, in natural order.
//! Computed directly from the bits of $i$, so point $i$ costs $O(32)$ per dimension and needs no
//! state beyond a per-thread memo of the last digital shift.
//!
//! `sobol_burley` was considered; it stops at $2^{16}$ points and returns `f32`, too few and too
//! coarse for the 200,000-point sets of Stamper et al.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::cell::Cell;

const BITS: usize = 32;

/// Dimensions of the sequence: as many as a platform pose has coordinates.
pub(crate) const SOBOL_DIMENSIONS: usize = 6;

/// Joe–Kuo's primitive polynomial of each dimension after the first, as (degree $s$,
/// coefficients $a$, initial $m_1 \dots m_s$).
const POLYNOMIALS: [(usize, u64, [u64; 4]); SOBOL_DIMENSIONS - 1] = [
    (1, 0, [1, 0, 0, 0]),
    (2, 1, [1, 3, 0, 0]),
    (3, 1, [1, 3, 1, 0]),
    (3, 2, [1, 1, 1, 0]),
    (4, 1, [1, 1, 3, 3]),
];

/// Direction numbers $v_k = m_k 2^{32-k}$ of dimension `d` (0: van der Corput, $m_k = 1$;
/// otherwise the recurrence of Bratley & Fox,
/// $m_k = 2a_1m_{k-1} \oplus 2^2a_2m_{k-2} \oplus \dots \oplus 2^s m_{k-s} \oplus m_{k-s}$).
const fn directions(d: usize) -> [u32; BITS] {
    let mut m = [1u64; BITS];
    if d > 0 {
        let (s, a, initial) = POLYNOMIALS[d - 1];
        let mut k = 0;
        while k < BITS {
            m[k] = if k < s {
                initial[k]
            } else {
                let mut value = m[k - s] ^ (m[k - s] << s);
                let mut j = 1;
                while j < s {
                    // a_j is bit s − 1 − j of a.
                    if (a >> (s - 1 - j)) & 1 == 1 {
                        value ^= m[k - j] << j;
                    }
                    j += 1;
                }
                value
            };
            k += 1;
        }
    }
    let mut v = [0u32; BITS];
    let mut k = 0;
    while k < BITS {
        v[k] = (m[k] << (BITS - 1 - k)) as u32;
        k += 1;
    }
    v
}

const DIRECTIONS: [[u32; BITS]; SOBOL_DIMENSIONS] = [
    directions(0),
    directions(1),
    directions(2),
    directions(3),
    directions(4),
    directions(5),
];

/// The digital shift of `seed` (none for 0): six words of ChaCha8 seeded with `seed`,
/// remembered per thread for the last seed asked, since a point set asks the same seed for
/// every point and seeding ChaCha costs more than the point. The first three words are those
/// of the three-dimensional sequence, so its points did not change when dimensions were added.
fn digital_shift(seed: u64) -> [u32; SOBOL_DIMENSIONS] {
    thread_local! {
        static LAST: Cell<Option<(u64, [u32; SOBOL_DIMENSIONS])>> = const { Cell::new(None) };
    }
    if seed == 0 {
        return [0; SOBOL_DIMENSIONS];
    }
    LAST.with(|last| match last.get() {
        Some((s, shift)) if s == seed => shift,
        _ => {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let shift = std::array::from_fn(|_| rng.random());
            last.set(Some((seed, shift)));
            shift
        }
    })
}

/// Coordinate `d` (< [`SOBOL_DIMENSIONS`]) of point $i$ under the digital shift `shift`.
fn coordinate(index: u32, d: usize, shift: u32) -> f64 {
    let mut x = shift;
    for (k, v) in DIRECTIONS[d].iter().enumerate() {
        if (index >> k) & 1 == 1 {
            x ^= v;
        }
    }
    f64::from(x) / 4_294_967_296.0
}

/// Point $i$ of the 3-D Sobol sequence in $[0, 1)^3$, digitally shifted by a pure function of
/// `seed` (no shift when `seed = 0`). Indices wrap modulo $2^{32}$.
pub(crate) fn sobol3(i: u64, seed: u64) -> [f64; 3] {
    let shift = digital_shift(seed);
    std::array::from_fn(|d| coordinate(i as u32, d, shift[d]))
}

/// Point $i$ of the Sobol sequence in $[0, 1)^n$, $n$ = `out.len()` $\le$
/// [`SOBOL_DIMENSIONS`], written into `out` (its first three coordinates are those of
/// [`sobol3`]). Indices wrap modulo $2^{32}$; `out` longer than [`SOBOL_DIMENSIONS`] has its
/// extra entries left alone (callers check the dimension first).
pub(crate) fn sobol_n(i: u64, seed: u64, out: &mut [f64]) {
    let shift = digital_shift(seed);
    for (d, value) in out.iter_mut().enumerate().take(SOBOL_DIMENSIONS) {
        *value = coordinate(i as u32, d, shift[d]);
    }
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
    fn six_dimensions_match_an_independent_implementation() {
        // 64 × (natural-order point i) of dimensions 3, 4 and 5 from SciPy 1.17's unscrambled
        // `scipy.stats.qmc.Sobol(d=6)` (Joe–Kuo 21201 direction numbers), its Gray-code order
        // mapped to natural order: natural point g(n) = n ^ (n >> 1) is SciPy's point n.
        let expected: [[u32; 16]; 3] = [
            [0, 32, 48, 16, 8, 40, 56, 24, 20, 52, 36, 4, 28, 60, 44, 12],
            [0, 32, 16, 48, 8, 40, 24, 56, 44, 12, 60, 28, 36, 4, 52, 20],
            [0, 32, 16, 48, 24, 56, 8, 40, 12, 44, 28, 60, 20, 52, 4, 36],
        ];
        let mut p = [0.0; SOBOL_DIMENSIONS];
        for i in 0..16u32 {
            sobol_n(u64::from(i), 0, &mut p);
            for (d, column) in expected.iter().enumerate() {
                let e = f64::from(column[i as usize]);
                assert_eq!(
                    (p[d + 3] * 64.0).to_bits(),
                    e.to_bits(),
                    "point {i}, dim {}",
                    d + 3
                );
            }
        }
        // Later points (i = 48..52) of dimension 5: 59, 27, 43, 11.
        for (i, e) in [(48, 59.0), (49, 27.0), (50, 43.0), (51, 11.0)] {
            sobol_n(i, 0, &mut p);
            assert_eq!((p[5] * 64.0).to_bits(), f64::to_bits(e));
        }
    }

    #[test]
    fn the_first_three_coordinates_are_those_of_the_3d_sequence() {
        let mut p = [0.0; SOBOL_DIMENSIONS];
        for i in [0, 1, 17, 1000, 123_456] {
            sobol_n(i, 9, &mut p);
            assert_eq!(p[..3], sobol3(i, 9));
        }
    }

    #[test]
    fn every_dimension_is_stratified_in_dyadic_blocks() {
        let mut p = [0.0; SOBOL_DIMENSIONS];
        for d in 0..SOBOL_DIMENSIONS {
            let mut seen = [false; 64];
            for i in 0..64 {
                sobol_n(i, 7, &mut p);
                seen[(p[d] * 64.0) as usize] = true;
            }
            assert!(seen.iter().all(|&s| s), "dimension {d}");
        }
    }
}
