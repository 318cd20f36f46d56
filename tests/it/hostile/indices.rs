//! `pkm-workspace-indices` outside `volume.rs`, `sampler.rs` and `sobol.rs`: condition numbers,
//! local indices at a pose, quadrature, cross-section means, slices, the generic workspace entry
//! points and space utilisation.

use super::{config, hostile_count, hostile_f64, hostile_vec3, judge, judge_err, judge_value};
use nalgebra::{Matrix3, Matrix6, Vector3};
use pkm_mechanisms::{
    Elbow, ElbowMode, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios,
    Placement, RotaryDelta, ThreeUpu, ThreeUpuDesign, Tsai3Dof, TsaiDesign, UJointAxes, presets,
};
use pkm_traits::{Extents, JacobianLanes, Silent, SlicedRegion, WorkspaceConstraint};
use pkm_workspace_indices::{
    BoundingBox, Domain, Eta1Rule, GaussLegendre, GridRule, LANES, LocalIndices, Plane, PointSet,
    Region, Sampler, SectionIndex, SectionIndexCache, SectionIndices, Slice, Workspace,
    condition_number, inverse_condition_at, inverse_condition_number, inverse_condition_number_3x3,
    inverse_condition_of_reachable_lanes, local_indices, mean_by_grid, mean_by_quadrature,
    space_utilization, sweep_workspace_volumes,
};
use proptest::prelude::*;

/// The unit square $[0, 1]^2$.
struct Square;

impl SlicedRegion for Square {
    fn slice(&self, y: f64) -> Option<(f64, f64)> {
        (0.0..=1.0).contains(&y).then_some((0.0, 1.0))
    }
    fn breakpoints(&self) -> &[f64] {
        &[0.0, 1.0]
    }
    fn extents(&self) -> Extents {
        Extents {
            y_min: 0.0,
            y_max: 1.0,
            z_min: 0.0,
            z_max: 1.0,
        }
    }
    fn area(&self) -> f64 {
        1.0
    }
}

fn ratio(v: &f64) -> bool {
    (0.0..=1.0).contains(v)
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn inverse_condition_numbers_are_ratios(entries in prop::collection::vec(hostile_f64(), 36)) {
        let j6 = Matrix6::from_column_slice(&entries);
        let j3 = Matrix3::from_column_slice(&entries[..9]);
        judge_value("inverse_condition_number (6x6)", || inverse_condition_number(&j6), ratio)?;
        judge_value("inverse_condition_number (3x3)", || inverse_condition_number(&j3), ratio)?;
        judge_value("inverse_condition_number_3x3", || inverse_condition_number_3x3(&j3), ratio)?;
        judge_value("condition_number", || condition_number(&j3), |k| *k >= 1.0)?;
    }

    /// 1/κ is scale-invariant: the closed form agrees with the SVD for matrices scaled by
    /// 1e±200, where the products $J^\top J$ of the closed form would overflow or underflow.
    #[test]
    fn inverse_condition_number_is_scale_invariant(entries in prop::collection::vec(-1.0..1.0f64, 9), exponent in prop::sample::select(vec![-200, -100, 0, 100, 200])) {
        let j = Matrix3::from_column_slice(&entries);
        let reference = inverse_condition_number(&j);
        let scaled = j * 10f64.powi(exponent);
        judge_value("inverse_condition_number_3x3 (scaled)", || inverse_condition_number_3x3(&scaled), |v| {
            ratio(v) && (v - reference).abs() <= 1e-8
        })?;
        judge_value("inverse_condition_number (scaled)", || inverse_condition_number(&scaled), |v| {
            ratio(v) && (v - reference).abs() <= 1e-8
        })?;
    }

    #[test]
    fn area_means_end_typed_or_finite(
        n in hostile_count(), min_points in hostile_count(), target in hostile_count(), shrink in hostile_f64(),
    ) {
        let n = n.min(64);
        judge("mean_by_quadrature", || mean_by_quadrature(&Square, |y, z| y + z, n), |m| (m - 1.0).abs() < 1e-9)?;
        let rule = GridRule { min_points: min_points.min(2000), target_points: target.min(3000), shrink };
        judge("mean_by_grid", || mean_by_grid(&Square, |y, z| y + z, &rule), |m| m.mean.is_finite() && m.n_points > 0)?;
    }

    #[test]
    fn slices_and_space_utilisation(
        z in hostile_f64(), half_width in hostile_f64(), n in 0..20usize, points in prop::collection::vec((hostile_f64(), hostile_f64()), 0..3),
    ) {
        let square = BoundingBox { lower: Vector3::repeat(-half_width), upper: Vector3::repeat(half_width) };
        for plane in [Plane::Xy, Plane::Xz, Plane::Yz] {
            judge("Slice::on_plane", || Slice::on_plane(plane, z, &square, n, |p| Some(p.x + p.y)), |s| {
                s.values.len() == n * n && s.u.iter().chain(&s.v).all(|x| x.is_finite())
            })?;
        }
        let points: Vec<[f64; 2]> = points.into_iter().map(|(a, b)| [a, b]).collect();
        judge("space_utilization", || space_utilization(&Square, &points), |u| *u > 0.0 && *u <= 1.0)?;
    }
}

proptest! {
    #![proptest_config(config())]

    /// The cross-section indices of hostile Linear Delta designs (those the constructor
    /// accepts) with hostile quadrature orders, directly and through the exact cache.
    #[test]
    fn section_indices_end_typed_or_finite(
        ratios in (hostile_f64(), hostile_f64(), hostile_f64(), hostile_f64()),
        yr in hostile_f64(),
        n in hostile_count(),
    ) {
        let design = [ratios.0, ratios.1, ratios.2, ratios.3];
        let build = || LinearDelta::new(LinearDeltaDesign { ratios: LinearDeltaRatios::from_slice(&design), yr });
        let cache = SectionIndexCache::new();
        let wanted = [SectionIndex::Eta1(Eta1Rule::Quadrature(n)), SectionIndex::Eta2, SectionIndex::Area];
        for (index, value) in wanted.iter().zip(cache.values(&design, &wanted, LinearDeltaMode::PAPER, build)) {
            let check = |v: &f64| if *index == SectionIndex::Area { v.is_finite() && *v >= 0.0 } else { ratio(v) };
            judge("SectionIndexCache::values", || value, check)?;
        }
        if let Ok(delta) = build() {
            let indices = SectionIndices::new(&delta, LinearDeltaMode::PAPER);
            judge("SectionIndices::eta1", || indices.eta1(Eta1Rule::Quadrature(n)), ratio)?;
            judge("SectionIndices::eta2", || indices.eta2(), ratio)?;
            judge_value("SectionIndices::area", || indices.area(), |a| a.is_finite() && *a >= 0.0)?;
        }
    }
}

/// What every `local_indices` answer must satisfy: finite, ordered, 1/κ a ratio, and
/// $\sigma_{\min}^N \le w \le \sigma_{\max}^N$.
fn local_indices_hold(l: &LocalIndices) -> bool {
    let finite = [
        l.inverse_condition,
        l.sigma_min,
        l.sigma_max,
        l.manipulability,
    ]
    .iter()
    .all(|v| v.is_finite());
    finite
        && ratio(&l.inverse_condition)
        && 0.0 <= l.sigma_min
        && l.sigma_min <= l.sigma_max
        && l.manipulability <= l.sigma_max.powi(3) * (1.0 + 1e-12)
}

fn tsai() -> Tsai3Dof {
    Tsai3Dof::new(presets::stamper_max_gci()).unwrap()
}

proptest! {
    #![proptest_config(config())]

    /// Local indices and the generic workspace entry points of three mechanisms at hostile
    /// poses and settings (NaN, ±∞, 1e±300; singular poses of the Tsai platform: `|p_v| = b`).
    #[test]
    fn local_indices_and_workspace_entry_points(
        x in hostile_vec3(), scale in hostile_f64(), z in hostile_f64(), n in 0..12usize,
        radius in hostile_f64(), design in (hostile_f64(), hostile_f64()),
    ) {
        let tsai = tsai();
        let singular = Vector3::new(0.1, tsai.b(), 0.3);
        for p in [x, x * scale, singular] {
            judge("inverse_condition_at (Tsai3Dof)", || inverse_condition_at(&tsai, &p, [Elbow::Out; 3]), ratio)?;
            judge("inverse_condition_at (Tsai3Dof, elbows mixed)", || inverse_condition_at(&tsai, &p, [Elbow::Out, Elbow::In, Elbow::Out]), ratio)?;
            judge("local_indices (Tsai3Dof)", || local_indices(&tsai, &p, [Elbow::Out; 3]), local_indices_hold)?;
        }
        let ratios = LinearDeltaRatios { l1_over_yr: 2.0, ya_over_yr: 0.0, zr_over_yr: 0.0, l2_over_l1: 0.63 };
        let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 }).unwrap();
        judge("inverse_condition_at (LinearDelta)", || inverse_condition_at(&delta, &x, LinearDeltaMode::PAPER), ratio)?;
        judge("local_indices (LinearDelta)", || local_indices(&delta, &x, LinearDeltaMode::PAPER), local_indices_hold)?;
        if let Ok(upu) = ThreeUpu::new(ThreeUpuDesign { upper: [UJointAxes::park(0.3); 3], ..presets::park_3upu() }) {
            judge("inverse_condition_at (ThreeUpu)", || inverse_condition_at(&upu, &(x * scale), ()), ratio)?;
            judge("local_indices (ThreeUpu)", || local_indices(&upu, &(x * scale), ()), local_indices_hold)?;
        }
        // A design with hostile lengths, when valid, and hostile slice and hemisphere settings.
        if let Ok(d) = Tsai3Dof::new(TsaiDesign::from_deg(design.0, design.1, 0.0, 0.0, 120.0, 240.0)) {
            judge("local_indices (hostile Tsai3Dof)", || local_indices(&d, &x, [Elbow::Out; 3]), local_indices_hold)?;
        }
        let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[]).unwrap();
        let reach = BoundingBox { lower: Vector3::repeat(-radius), upper: Vector3::repeat(radius) };
        judge("Workspace::inverse_condition_slice", || ws.inverse_condition_slice(Plane::Xz, z, &reach, n), |s| {
            s.values.len() == n * n && s.values.iter().flatten().all(ratio)
        })?;
        let unit = [Vector3::new(0.1, 0.2, 0.3), Vector3::new(0.0, 0.0, 0.5), x];
        judge("Workspace::hemisphere_estimate", || ws.hemisphere_estimate(&unit, radius, &Silent), |e| {
            e.volume.is_finite() && e.eta.is_finite() && e.eta <= e.volume && e.gci().is_none_or(|g| ratio(&g))
        })?;
    }
}

proptest! {
    #![proptest_config(config())]

    /// The lane entry points at hostile points and Jacobians: 1/κ of every lane a ratio or
    /// `None`, the lane count the point test's count, and a sweep over no design refused.
    #[test]
    fn lane_entry_points(
        coordinates in prop::collection::vec(hostile_f64(), 3 * LANES),
        entries in prop::collection::vec(hostile_f64(), 9 * LANES),
        reachable in prop::collection::vec(any::<bool>(), LANES),
        scale in hostile_f64(),
    ) {
        let points: [Vector3<f64>; LANES] = std::array::from_fn(|l| {
            Vector3::new(coordinates[3 * l], coordinates[3 * l + 1], coordinates[3 * l + 2])
        });
        let lanes_hold = |values: &[Option<f64>; LANES]| values.iter().flatten().all(ratio);
        let j = JacobianLanes {
            jacobian: std::array::from_fn(|k| std::array::from_fn(|l| entries[LANES * k + l])),
            reachable: std::array::from_fn(|l| reachable[l]),
        };
        judge_value("inverse_condition_of_reachable_lanes", || inverse_condition_of_reachable_lanes(&j), |v| {
            lanes_hold(v) && v.iter().zip(&j.reachable).all(|(v, r)| v.is_some() == *r)
        })?;
        let tsai = tsai();
        let nuwar = RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap();
        let below = WorkspaceConstraint::below(0.0).unwrap();
        let cone = WorkspaceConstraint::passive_cone(0.6).unwrap();
        let scaled = points.map(|p| p * scale);
        for p in [&points, &scaled] {
            let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[]).unwrap();
            judge_value("Workspace::inverse_condition_lanes (Tsai3Dof)", || ws.inverse_condition_lanes(p), lanes_hold)?;
            let count = p.iter().filter(|x| ws.contains(x)).count() as u64;
            judge_value("Workspace::count_inside (Tsai3Dof)", || ws.count_inside(p), |n| *n == count)?;
            for constraints in [vec![below], vec![below, cone]] {
                let ws = Workspace::new(&nuwar, &[ElbowMode::Out, ElbowMode::In], &constraints).unwrap();
                judge_value("Workspace::inverse_condition_lanes (RotaryDelta)", || ws.inverse_condition_lanes(p), lanes_hold)?;
                let count = p.iter().filter(|x| ws.contains(x)).count() as u64;
                judge_value("Workspace::count_inside (RotaryDelta)", || ws.count_inside(p), |n| *n == count)?;
            }
        }
        let none: [Workspace<'_, Tsai3Dof>; 0] = [];
        let domain = Domain::new(Region::Ball { center: Vector3::zeros(), radius: 1.0 }).unwrap();
        let set = PointSet::new(domain, Sampler::Sobol { seed: 1 }, 64, 2).unwrap();
        judge_err("sweep_workspace_volumes (no design)", || sweep_workspace_volumes(&none, &set, &Silent))?;
    }
}

/// A Jacobian with entries near 1e300 (arm length 1e-300): its σ and product overflow, a typed
/// error; and a tiny one (lengths 1e300): 1/κ is scale-invariant and the product underflows to
/// a finite 0 or more.
#[test]
fn local_indices_of_extreme_scales_are_typed_or_finite() {
    for a in [1e-300, 1e-150, 1e150, 1e300] {
        let Ok(d) = Tsai3Dof::new(TsaiDesign::from_deg(a, a * 1.3, 0.0, 0.0, 120.0, 240.0)) else {
            continue;
        };
        let p = Vector3::new(0.0, 0.0, 1.5 * a);
        super::expect(judge(
            "local_indices (extreme scale)",
            || local_indices(&d, &p, [Elbow::Out; 3]),
            local_indices_hold,
        ));
        super::expect(judge(
            "inverse_condition_at (extreme scale)",
            || inverse_condition_at(&d, &p, [Elbow::Out; 3]),
            ratio,
        ));
    }
}

#[test]
fn huge_counts_are_refused_before_allocating() {
    for n in [usize::MAX, 1 << 40, 1 << 33] {
        super::expect(judge_err("mean_by_quadrature (huge)", || {
            mean_by_quadrature(&Square, |y, z| y + z, n)
        }));
        let unit = BoundingBox {
            lower: Vector3::repeat(-1.0),
            upper: Vector3::repeat(1.0),
        };
        super::expect(judge_err("Slice::on_plane (huge)", || {
            Slice::on_plane(Plane::Xy, 0.5, &unit, n, |_| Some(1.0))
        }));
        let rule = GridRule {
            min_points: n,
            target_points: n,
            shrink: 0.95,
        };
        super::expect(judge_err("mean_by_grid (huge)", || {
            mean_by_grid(&Square, |y, z| y + z, &rule)
        }));
        super::expect(judge_err("GaussLegendre::new (huge)", || {
            GaussLegendre::new(n)
        }));
        let tsai = tsai();
        let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[]).unwrap();
        super::expect(judge_err(
            "Workspace::inverse_condition_slice (huge)",
            || ws.inverse_condition_slice(Plane::Xy, 0.5, &unit, n),
        ));
    }
}

proptest! {
    #![proptest_config(config())]

    /// Gauss–Legendre on any interval keeps its documented contract: finite nodes and weights
    /// for finite ends (±f64::MAX included: b − a overflowed there), NaN in gives NaN out.
    #[test]
    fn gauss_legendre_nodes_keep_their_contract(a in hostile_f64(), b in hostile_f64(), n in 1..9usize) {
        let rule = GaussLegendre::new(n).unwrap();
        let mut visited = Vec::new();
        rule.for_each_on(a, b, |x, w| visited.push((x, w)));
        prop_assert_eq!(visited.len(), n);
        let finite = visited.iter().all(|(x, w)| x.is_finite() && w.is_finite());
        if a.is_finite() && b.is_finite() {
            prop_assert!(finite, "[{a}, {b}]: {visited:?}");
        }
        if a.is_nan() || b.is_nan() {
            prop_assert!(visited.iter().all(|(x, _)| x.is_nan()), "{visited:?}");
        }
    }
}
