//! The lane kernels of the rotary Delta and the Tsai 3-DOF followed by the lane $1/\kappa$,
//! pinned bit for bit: a hash of every output (Jacobian entries and reachability of every lane,
//! $1/\kappa$ of the reachable ones) and the sums of the estimate over seeded points, hostile
//! points (NaN, ±inf, huge) and points within one ulp of the workspace boundary, on every
//! vector path this processor runs. The pinned values were computed by these kernels on the
//! baseline before the lane-row copies were removed and the run-time dispatch was added
//! (commit d9f1450), and re-pinned on 2026-12-04 when 1/κ below `SVD_BELOW` (1e-2) began to
//! come from the SVD, where the closed form loses digits (the η sums moved in the 12th digit,
//! the counts not at all); a change of any output bit on any path fails here.
#![allow(clippy::unwrap_used, clippy::float_cmp)]

use nalgebra::Vector3;
use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, Tsai3Dof, presets};
use pkm_traits::JacobianLanes;
use pkm_workspace_indices::{
    LANES, LaneKernel, Sampler, VectorPath, evaluate_on, inverse_condition_number_3x3_lanes,
};

fn delta() -> RotaryDelta {
    RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap()
}

fn tsai() -> Tsai3Dof {
    Tsai3Dof::new(presets::stamper_max_gci()).unwrap()
}

/// Non-finite and huge coordinates in every position, mixed with ordinary ones.
pub(crate) fn hostile() -> Vec<Vector3<f64>> {
    let specials = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MAX,
        -f64::MAX,
        1e300,
        -1e160,
        1e154,
        f64::MIN_POSITIVE,
        -0.0,
        0.0,
        0.1,
        -0.7,
    ];
    let mut out = Vec::new();
    for (i, &a) in specials.iter().enumerate() {
        for &b in &specials[i % 4..] {
            out.push(Vector3::new(a, b, -0.6));
            out.push(Vector3::new(0.05, a, b));
            out.push(Vector3::new(b, 0.02, a));
        }
    }
    out
}

/// Pairs of adjacent points (one ulp apart in the scale along a ray) on either side of the
/// boundary where `reachable` changes, found by bisection from `inside` outwards.
fn boundary_pairs(
    reachable: impl Fn(&Vector3<f64>) -> bool,
    inside: Vector3<f64>,
) -> Vec<Vector3<f64>> {
    let mut out = Vec::new();
    for k in 0..24 {
        let angle = k as f64 * std::f64::consts::TAU / 24.0;
        let direction = Vector3::new(angle.cos(), angle.sin(), 0.3 * (k % 5) as f64 - 0.6);
        let (mut lo, mut hi) = (0.0_f64, 10.0_f64);
        if !reachable(&inside) || reachable(&(inside + direction * hi)) {
            continue;
        }
        while f64::from_bits(lo.to_bits() + 1) < hi {
            let mid = 0.5 * (lo + hi);
            if reachable(&(inside + direction * mid)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        out.push(inside + direction * lo);
        out.push(inside + direction * hi);
    }
    out
}

/// The Delta's test points: seeded in the box of the Delta bench, hostile, on the boundary.
fn delta_points() -> Vec<Vector3<f64>> {
    let d = delta();
    let (lo, hi) = (Vector3::new(-0.4, -0.4, -1.2), Vector3::new(0.4, 0.4, -0.2));
    let sampler = Sampler::MonteCarlo { seed: 20261202 };
    let mut points: Vec<_> = (0..4096).map(|i| sampler.in_box(i, &lo, &hi)).collect();
    points.extend(hostile());
    let reachable = |p: &Vector3<f64>| d.jacobian_lanes(&[*p], ElbowMode::Out).reachable[0];
    let boundary = boundary_pairs(reachable, Vector3::new(0.0, 0.0, -0.7));
    assert_eq!(boundary.len(), 48);
    points.extend(boundary);
    points
}

/// The Tsai's test points: seeded in its reach hemisphere, hostile, on the boundary.
fn tsai_points() -> Vec<Vector3<f64>> {
    let t = tsai();
    let sampler = Sampler::MonteCarlo { seed: 20261202 };
    let unit = sampler.unit_hemisphere_points(4096).unwrap();
    let mut points: Vec<_> = unit.iter().map(|p| p * t.reach()).collect();
    points.extend(hostile());
    let reachable = |p: &Vector3<f64>| t.velocity_jacobian_elbow_out_lanes(&[*p]).reachable[0];
    let boundary = boundary_pairs(reachable, Vector3::new(0.05, -0.05, 0.5 * t.reach()));
    assert_eq!(boundary.len(), 48);
    points.extend(boundary);
    points
}

/// `points` in groups of [`LANES`] (the last padded with its last point).
fn groups(points: &[Vector3<f64>]) -> Vec<[Vector3<f64>; LANES]> {
    points
        .chunks(LANES)
        .map(|c| std::array::from_fn(|l| c[l.min(c.len() - 1)]))
        .collect()
}

/// FNV-1a over 64-bit words.
#[derive(Debug)]
struct Fingerprint(u64);

impl Fingerprint {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    fn add(&mut self, word: u64) {
        for byte in word.to_le_bytes() {
            self.0 = (self.0 ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
    }
}

/// The Jacobian and $1/\kappa$ of every lane.
type Outputs = (JacobianLanes<LANES>, [f64; LANES]);

/// The rotary Delta's design-index kernel, elbow out.
struct DeltaIndex(RotaryDelta);

impl LaneKernel for DeltaIndex {
    type Output = Outputs;
    #[inline(always)]
    fn evaluate(&self, p: &[Vector3<f64>; LANES]) -> Outputs {
        let j = self.0.jacobian_lanes(p, ElbowMode::Out);
        let r = inverse_condition_number_3x3_lanes(&j.jacobian);
        (j, r)
    }
}

/// The Tsai 3-DOF's design-index kernel, elbow out.
struct TsaiIndex(Tsai3Dof);

impl LaneKernel for TsaiIndex {
    type Output = Outputs;
    #[inline(always)]
    fn evaluate(&self, p: &[Vector3<f64>; LANES]) -> Outputs {
        let j = self.0.velocity_jacobian_elbow_out_lanes(p);
        let r = inverse_condition_number_3x3_lanes(&j.jacobian);
        (j, r)
    }
}

/// Hash of the reachable lanes' Jacobians and $1/\kappa$ and of every lane's reachability,
/// with the count, sum and sum of squares of $1/\kappa$ over the reachable points, summed in
/// point order.
fn pin(
    points: &[Vector3<f64>],
    kernel: &impl LaneKernel<Output = Outputs>,
    path: VectorPath,
) -> (u64, u64, u64, u64) {
    let mut hash = Fingerprint::new();
    let (mut inside, mut sum, mut sum2) = (0_u64, 0.0_f64, 0.0_f64);
    for (g, group) in groups(points).iter().enumerate() {
        let (j, r) = evaluate_on(path, kernel, group);
        for l in 0..LANES.min(points.len() - g * LANES) {
            hash.add(u64::from(j.reachable[l]));
            if j.reachable[l] {
                for entry in &j.jacobian {
                    hash.add(entry[l].to_bits());
                }
                hash.add(r[l].to_bits());
                inside += 1;
                sum += r[l];
                sum2 += r[l] * r[l];
            }
        }
    }
    (hash.0, inside, sum.to_bits(), sum2.to_bits())
}

/// Every output bit of every lane (unreachable ones included) on `path`, with every NaN as
/// one value: which NaN an operation on two NaNs returns is left open by IEEE-754, and the
/// compiler may swap the operands of an addition or a multiplication (SSE2 and AVX then
/// return NaNs of different sign in a lane that is not reachable).
fn all_bits(
    points: &[Vector3<f64>],
    kernel: &impl LaneKernel<Output = Outputs>,
    path: VectorPath,
) -> Vec<u64> {
    let mut bits = Vec::new();
    for group in groups(points) {
        let (j, r) = evaluate_on(path, kernel, &group);
        for l in 0..LANES {
            bits.push(u64::from(j.reachable[l]));
            bits.extend(j.jacobian.iter().map(|e| canonical_bits(e[l])));
            bits.push(canonical_bits(r[l]));
        }
    }
    bits
}

/// The bits of `x`, one pattern for every NaN.
fn canonical_bits(x: f64) -> u64 {
    if x.is_nan() { f64::NAN } else { x }.to_bits()
}

#[test]
fn every_vector_path_gives_the_same_bits_in_every_lane() {
    let (delta, tsai) = (DeltaIndex(delta()), TsaiIndex(tsai()));
    let (delta_points, tsai_points) = (delta_points(), tsai_points());
    let delta_baseline = all_bits(&delta_points, &delta, VectorPath::Baseline);
    let tsai_baseline = all_bits(&tsai_points, &tsai, VectorPath::Baseline);
    for path in VectorPath::available() {
        assert!(
            all_bits(&delta_points, &delta, path) == delta_baseline,
            "Delta on {path:?}"
        );
        assert!(
            all_bits(&tsai_points, &tsai, path) == tsai_baseline,
            "Tsai on {path:?}"
        );
    }
}

#[test]
fn delta_kernel_outputs_are_pinned_bit_for_bit() {
    let (kernel, points) = (DeltaIndex(delta()), delta_points());
    for path in VectorPath::available() {
        let got = pin(&points, &kernel, path);
        assert_eq!(
            got,
            (
                0x00ca_4c5f_e3e3_b251,
                1776,
                0x4082_ec0f_bec7_8ad3,
                0x4071_f0d8_7745_e8c3
            ),
            "{path:?}: {got:#x?}"
        );
    }
}

#[test]
fn tsai_kernel_outputs_are_pinned_bit_for_bit() {
    let (kernel, points) = (TsaiIndex(tsai()), tsai_points());
    for path in VectorPath::available() {
        let got = pin(&points, &kernel, path);
        assert_eq!(
            got,
            (
                0x6116_3e92_45f0_ffac,
                1590,
                0x4080_d2ec_0f96_30d7,
                0x4070_7770_8dd4_839c
            ),
            "{path:?}: {got:#x?}"
        );
    }
}
