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
    /// Appends the whole groups of `points` (a multiple of [`LANES`] long, or the rest is
    /// left out).
    fn push_groups(&mut self, points: &[Vector3<f64>]) {
        self.groups.extend(points.chunks_exact(LANES).map(|group| {
            let lane = |c: usize| Lanes::from_fn(|l| group[l][c]);
            [lane(0), lane(1), lane(2)]
        }));
    }

    /// The same points reordered along the Morton (Z-order) curve of their bounding box within
    /// consecutive blocks of [`MORTON_BLOCK`] points, so that the points of a group lie close
    /// together and a kernel that stops once a whole group fails a test (the rotary Delta's
    /// legs) stops often. Only for what does not depend on the order (counts). The order is
    /// deterministic (ties by index, non-finite points last in their block), and besides the
    /// groups (as many bytes as the points) only one block is held at a time.
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
        let mut out = Self {
            groups: Vec::with_capacity(points.len() / LANES),
            rest: Vec::new(),
        };
        let mut order = Vec::with_capacity(MORTON_BLOCK.min(points.len()));
        let mut sorted = Vec::with_capacity(MORTON_BLOCK.min(points.len()));
        for block in points.chunks(MORTON_BLOCK) {
            order.clear();
            order.extend(block.iter().enumerate().map(|(k, p)| (key(p), k)));
            order.sort_unstable();
            sorted.clear();
            sorted.extend(order.iter().map(|&(_, k)| block[k]));
            out.push_groups(&sorted);
            out.rest = sorted.chunks_exact(LANES).remainder().to_vec();
        }
        out
    }
}

/// Points sorted together by [`PointGroups::in_morton_order`]: a multiple of [`LANES`], so
/// that only the last block leaves points outside the groups.
const MORTON_BLOCK: usize = 1 << 16;

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

    /// Every point once, as bit patterns, whatever the order.
    fn same_points(g: &PointGroups, points: &[Vector3<f64>]) {
        let mut back: Vec<Vector3<f64>> = g.rest.clone();
        for group in &g.groups {
            back.extend(
                (0..LANES).map(|l| Vector3::new(group[0].0[l], group[1].0[l], group[2].0[l])),
            );
        }
        let key = |p: &Vector3<f64>| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
        let (mut a, mut b): (Vec<_>, Vec<_>) = (
            points.iter().map(key).collect(),
            back.iter().map(key).collect(),
        );
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
    }

    #[test]
    fn morton_blocks_keep_every_point_once_and_leave_only_the_last_rest() {
        let n = 2 * MORTON_BLOCK + 13;
        let points: Vec<Vector3<f64>> = (0..n)
            .map(|k| {
                let k = k as f64;
                Vector3::new((0.37 * k).sin(), (0.11 * k).cos(), (k * 1e-3).fract())
            })
            .collect();
        let g = PointGroups::in_morton_order(&points);
        assert_eq!((g.groups.len(), g.rest.len()), (n / LANES, n % LANES));
        same_points(&g, &points);
    }

    #[test]
    fn morton_order_keeps_every_point_once() {
        let mut points: Vec<Vector3<f64>> = (0..37)
            .map(|k| Vector3::new(f64::from(k).sin(), f64::from(k).cos(), 0.1 * f64::from(k)))
            .collect();
        points.push(Vector3::new(f64::NAN, 0.0, 0.0));
        let g = PointGroups::in_morton_order(&points);
        assert!(
            g.rest.last().is_some_and(|p| p.x.is_nan()),
            "non-finite points last"
        );
        same_points(&g, &points);
    }
}
