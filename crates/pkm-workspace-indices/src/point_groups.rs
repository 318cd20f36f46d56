//! Points in groups of [`LANES`] with their coordinates in lanes (structure of arrays), the
//! input of the lane membership kernels: transposed once, then read by every design of a sweep.

use crate::LANES;
use nalgebra::Vector3;
use pkm_traits::Lanes;

/// `points` as whole groups of [`LANES`] (coordinate `c` of point `l` of a group is
/// `group[c].0[l]`) and the remainder as points.
#[derive(Debug, Clone)]
pub(crate) struct PointGroups {
    pub(crate) groups: Vec<[Lanes<LANES>; 3]>,
    pub(crate) rest: Vec<Vector3<f64>>,
}

impl PointGroups {
    /// `points` in their order.
    pub(crate) fn new(points: &[Vector3<f64>]) -> Self {
        let chunks = points.chunks_exact(LANES);
        let rest = chunks.remainder().to_vec();
        let groups = chunks
            .map(|group| {
                let lane = |c: usize| Lanes::from_fn(|l| group[l][c]);
                [lane(0), lane(1), lane(2)]
            })
            .collect();
        Self { groups, rest }
    }

    /// The same points reordered along the Morton (Z-order) curve of their bounding box, so
    /// that the points of a group lie close together and a kernel that stops once a whole
    /// group fails a test (the rotary Delta's legs) stops often. Only for what does not depend
    /// on the order (counts); the order is deterministic (ties by index), non-finite points
    /// last.
    pub(crate) fn in_morton_order(points: &[Vector3<f64>]) -> Self {
        let finite = |p: &&Vector3<f64>| p.iter().all(|v| v.is_finite());
        let (mut lo, mut hi) = (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        );
        for p in points.iter().filter(finite) {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let key = |p: &Vector3<f64>| -> u64 {
            if !p.iter().all(|v| v.is_finite()) {
                return u64::MAX;
            }
            let cell = |c: usize| {
                let span = hi[c] - lo[c];
                let t = if span > 0.0 {
                    (p[c] - lo[c]) / span
                } else {
                    0.0
                };
                // In [0, 2^21): 21 bits per axis, 63 in all.
                (t * MORTON_CELLS).clamp(0.0, MORTON_CELLS - 1.0) as u64
            };
            spread(cell(0)) | (spread(cell(1)) << 1) | (spread(cell(2)) << 2)
        };
        let mut order: Vec<(u64, usize)> = points
            .iter()
            .enumerate()
            .map(|(k, p)| (key(p), k))
            .collect();
        order.sort_unstable();
        let sorted: Vec<Vector3<f64>> = order.iter().map(|&(_, k)| points[k]).collect();
        Self::new(&sorted)
    }
}

/// Cells per axis of the Morton key.
const MORTON_CELLS: f64 = (1u64 << 21) as f64;

/// The 21 low bits of `v` spread to every third bit (bit `i` to bit `3i`).
fn spread(v: u64) -> u64 {
    let mut x = v & 0x1f_ffff;
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_puts_bit_i_at_bit_3i() {
        for i in 0..21 {
            assert_eq!(spread(1 << i), 1 << (3 * i));
        }
        assert_eq!(spread(0x1f_ffff).count_ones(), 21);
    }

    #[test]
    fn morton_order_keeps_every_point_once() {
        let mut points: Vec<Vector3<f64>> = (0..37)
            .map(|k| Vector3::new(f64::from(k).sin(), f64::from(k).cos(), 0.1 * f64::from(k)))
            .collect();
        points.push(Vector3::new(f64::NAN, 0.0, 0.0));
        let g = PointGroups::in_morton_order(&points);
        let mut back: Vec<Vector3<f64>> = g.rest.clone();
        for group in &g.groups {
            back.extend(
                (0..LANES).map(|l| Vector3::new(group[0].0[l], group[1].0[l], group[2].0[l])),
            );
        }
        assert_eq!(back.len(), points.len());
        assert!(
            g.rest.last().is_some_and(|p| p.x.is_nan()),
            "non-finite points last"
        );
        let key = |p: &Vector3<f64>| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
        let (mut a, mut b): (Vec<_>, Vec<_>) = (
            points.iter().map(key).collect(),
            back.iter().map(key).collect(),
        );
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
    }
}
