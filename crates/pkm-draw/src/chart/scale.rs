//! Axis ranges and heat-map cell edges. Inputs are validated (finite, at most `MAX_VALUE` in
//! magnitude), so every range here is finite.

use std::ops::Range;

/// The range of `values`, padded by 5 % of its width on each side; around a single value,
/// ±max(0.5, 5 % of its magnitude); `0..1` without values.
pub(crate) fn padded(values: impl Iterator<Item = f64>) -> Range<f64> {
    let Some((lo, hi)) = extent(values) else {
        return 0.0..1.0;
    };
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5_f64.max(0.05 * lo.abs())
    };
    lo - pad..hi + pad
}

/// The smallest and largest of `values`, `None` without values.
pub(crate) fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |r, v| {
        Some(r.map_or((v, v), |(lo, hi): (f64, f64)| (lo.min(v), hi.max(v))))
    })
}

/// Cell edges around increasing `centres`: midpoints inside, mirrored half-steps at the ends
/// (±0.5 around a lone centre).
pub(crate) fn edges(centres: &[f64]) -> Vec<f64> {
    let half = |a: f64, b: f64| 0.5 * (b - a);
    let first_half = match centres {
        [a, b, ..] => half(*a, *b),
        _ => 0.5,
    };
    let last_half = match centres {
        [.., a, b] => half(*a, *b),
        _ => 0.5,
    };
    let mut edges: Vec<f64> = centres
        .first()
        .map(|c| c - first_half)
        .into_iter()
        .collect();
    edges.extend(centres.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    edges.extend(centres.last().map(|c| c + last_half));
    edges
}

/// From the first to the last edge, or the padded range of the edges when they coincide (a lone
/// centre so large that ±0.5 does not move it).
pub(crate) fn span(edges: &[f64]) -> Range<f64> {
    match (edges.first(), edges.last()) {
        (Some(&lo), Some(&hi)) if hi > lo => lo..hi,
        _ => padded(edges.iter().copied()),
    }
}

/// Position of `z` in `[lo, hi]` as a fraction in [0, 1]; the middle when the range is a point.
pub(crate) fn fraction(z: f64, lo: f64, hi: f64) -> f64 {
    if hi > lo {
        ((z - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.5
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_edges_surround_the_centres() {
        assert_eq!(edges(&[0.0, 1.0, 3.0]), [-0.5, 0.5, 2.0, 4.0]);
        assert_eq!(edges(&[2.0]), [1.5, 2.5]);
        assert!(edges(&[]).is_empty());
        assert_eq!(span(&edges(&[0.0, 1.0, 3.0])), -0.5..4.0);
    }

    #[test]
    fn ranges_are_padded_and_degenerate_ones_widened() {
        assert_eq!(padded([0.0, 10.0].into_iter()), -0.5..10.5);
        assert_eq!(padded([2.0].into_iter()), 1.5..2.5);
        assert_eq!(padded([100.0].into_iter()), 95.0..105.0);
        assert_eq!(padded(std::iter::empty()), 0.0..1.0);
        let lone = span(&edges(&[1e300]));
        assert!(lone.start < 1e300 && lone.end > 1e300 && lone.end.is_finite());
    }

    #[test]
    fn fractions_are_clamped_and_a_point_range_maps_to_the_middle() {
        let fractions = [
            fraction(0.25, 0.0, 1.0),
            fraction(-3.0, 0.0, 1.0),
            fraction(7.0, 0.0, 1.0),
            fraction(7.0, 2.0, 2.0),
        ];
        assert_eq!(
            fractions.map(f64::to_bits),
            [0.25, 0.0, 1.0, 0.5].map(f64::to_bits)
        );
    }
}
