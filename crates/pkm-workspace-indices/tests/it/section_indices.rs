//! Cross-section indices (Miller 2004, eqs. 1–2) through the generic [`CrossSectionWorkspace`]
//! path, and the exact cache of a study.
//!
//! Regression (issue 17): the Linear Delta memo of the reproductions keyed designs rounded to
//! 1e-6 and computed at the rounded design, so a user sweep whose nodes were closer than that
//! got a neighbour's η1/η2 with no warning. The cache now keys the exact bits.

use nalgebra::{Matrix3, Vector3};
use pkm_mechanisms::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
use pkm_traits::{
    ClosedChain, CrossSectionWorkspace, DesignError, InverseKinematics, Joints, KinematicsError,
    SlicedRegion, Task,
};
use pkm_workspace_indices::{
    Eta1Rule, GridRule, IndexError, SectionIndex, SectionIndexCache, SectionIndices,
    inverse_condition_at, mean_by_grid, mean_by_quadrature, space_utilization,
};
use proptest::prelude::*;
use rayon::prelude::*;

fn delta(design: &[f64; 4]) -> Result<LinearDelta, DesignError> {
    LinearDelta::new(LinearDeltaDesign {
        ratios: LinearDeltaRatios::from_slice(design),
        yr: 1.0,
    })
}

/// The indices of `design` computed afresh, without a cache.
fn uncached(design: &[f64; 4], index: SectionIndex) -> Result<f64, IndexError> {
    let delta = delta(design)?;
    SectionIndices::new(&delta, LinearDeltaMode::PAPER).value(index)
}

const INDICES: [SectionIndex; 4] = [
    SectionIndex::Eta1(Eta1Rule::Quadrature(8)),
    SectionIndex::Eta1(Eta1Rule::Quadrature(12)),
    SectionIndex::Eta2,
    SectionIndex::Area,
];

#[test]
fn designs_1e_9_apart_each_get_their_own_values_bit_for_bit() {
    let cache = SectionIndexCache::new();
    let base = [2.0, 0.1, -0.2, 0.63];
    // Nodes 1e-9 apart in each variable, visited twice in a scrambled order from 4 threads.
    let designs: Vec<[f64; 4]> = (0..4)
        .flat_map(|k| {
            (0..3).map(move |i| {
                let mut d = base;
                d[k] += i as f64 * 1e-9;
                d
            })
        })
        .collect();
    let visits: Vec<[f64; 4]> = designs.iter().rev().chain(&designs).copied().collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .unwrap();
    let answers: Vec<Vec<Result<f64, IndexError>>> = pool.install(|| {
        visits
            .par_iter()
            .map(|d| cache.values(d, &INDICES, LinearDeltaMode::PAPER, || delta(d)))
            .collect()
    });
    for (design, answer) in visits.iter().zip(&answers) {
        for (index, value) in INDICES.iter().zip(answer) {
            let fresh = uncached(design, *index).unwrap();
            assert_eq!(
                value.as_ref().unwrap().to_bits(),
                fresh.to_bits(),
                "{design:?} {index:?}"
            );
        }
    }
    // Nine distinct designs (the base is shared by the four variables), four indices each.
    assert_eq!(cache.len(), 9 * INDICES.len());
    // Designs 1e-9 apart are different designs: their η1 differ (not vacuous).
    let eta1 = |d: &[f64; 4]| uncached(d, INDICES[0]).unwrap();
    let mut apart = base;
    apart[0] += 1e-9;
    assert_ne!(eta1(&base).to_bits(), eta1(&apart).to_bits());
}

#[test]
fn an_invalid_design_is_cached_as_its_typed_error() {
    let cache = SectionIndexCache::new();
    let invalid = [-1.0, 0.0, 0.0, 0.63];
    let values = cache.values(&invalid, &INDICES, LinearDeltaMode::PAPER, || {
        delta(&invalid)
    });
    for value in values {
        assert!(matches!(value, Err(IndexError::Design(_))), "{value:?}");
    }
    let again = cache.get(&invalid, SectionIndex::Eta2);
    assert!(matches!(again, Some(Err(IndexError::Design(_)))));
    // An empty cross-section (the centre arm cannot reach the outer arms' lens): η1 and η2
    // are errors, the area 0.
    let empty = [1.2, 0.9, 0.5, 0.01];
    let values = cache.values(&empty, &INDICES, LinearDeltaMode::PAPER, || delta(&empty));
    assert!(values[..3].iter().all(Result::is_err), "{values:?}");
    assert_eq!(values[3].as_ref().map(|a| a.to_bits()), Ok(0));
}

/// The Linear Delta through the default [`CrossSectionWorkspace`] methods only: its scalar
/// `velocity_jacobian_at` lane by lane instead of its batch kernel.
struct ScalarJacobian(LinearDelta);

impl ClosedChain<3, 3> for ScalarJacobian {
    fn closure(&self, x: &Task<3>, q: &Joints<3>) -> Joints<3> {
        self.0.closure(x, q)
    }
    fn jacobian_x(&self, x: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        self.0.jacobian_x(x, q)
    }
    fn jacobian_q(&self, x: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        self.0.jacobian_q(x, q)
    }
}

impl InverseKinematics<3, 3> for ScalarJacobian {
    type WorkingMode = LinearDeltaMode;
    fn inverse_kinematics(
        &self,
        x: &Task<3>,
        mode: LinearDeltaMode,
    ) -> Result<Joints<3>, KinematicsError> {
        self.0.inverse_kinematics(x, mode)
    }
    fn velocity_jacobian_at(
        &self,
        x: &Task<3>,
        mode: LinearDeltaMode,
    ) -> Result<Matrix3<f64>, KinematicsError> {
        self.0.velocity_jacobian_at(x, mode)
    }
}

impl CrossSectionWorkspace for ScalarJacobian {
    type CrossSection = pkm_mechanisms::CrossSection;
    fn cross_section(&self) -> Self::CrossSection {
        self.0.cross_section()
    }
    fn actuator_points(&self) -> Vec<[f64; 2]> {
        self.0.rails().to_vec()
    }
}

#[test]
fn the_batch_kernel_and_the_default_scalar_path_give_the_same_indices() {
    for design in [
        [2.0, 0.0, 0.0, 0.63],
        [1.55, 0.0, -0.75, 0.01],
        [2.4, 0.5, 0.3, 1.2],
    ] {
        let batch = delta(&design).unwrap();
        let scalar = ScalarJacobian(delta(&design).unwrap());
        let by_batch = SectionIndices::new(&batch, LinearDeltaMode::PAPER);
        let by_scalar = SectionIndices::new(&scalar, LinearDeltaMode::PAPER);
        // Inside the cross-section the kernels compute the same floating-point operations.
        for index in INDICES {
            let (b, s) = (by_batch.value(index), by_scalar.value(index));
            assert_eq!(
                b.map(f64::to_bits),
                s.map(f64::to_bits),
                "{design:?} {index:?}"
            );
        }
        // η2 is the library's space utilisation of W and the rails.
        let rails = batch.rails();
        let direct = space_utilization(&batch.cross_section(), &rails).unwrap();
        assert_eq!(by_batch.eta2().unwrap().to_bits(), direct.to_bits());
        // And 1/κ at a point of W (the middle of its middle slice) is the scalar index there.
        let section = by_batch.section();
        let y = 0.5 * (section.extents().y_min + section.extents().y_max);
        let (lo, hi) = section.slice(y).unwrap();
        let z = 0.5 * (lo + hi);
        let lanes = by_batch.inverse_condition_lanes(y, &[z; pkm_workspace_indices::LANES]);
        let j = batch
            .velocity_jacobian_at(&Vector3::new(0.0, y, z), LinearDeltaMode::PAPER)
            .unwrap();
        let scalar_index = pkm_workspace_indices::inverse_condition_number_3x3(&j);
        assert!((lanes[0] - scalar_index).abs() < 1e-12, "{design:?}");
    }
}

/// Batched and scalar η1 feed the same Jacobians to the two 1/κ routines and sum in the same
/// order, so they differ by the routines' disagreement only: 1e-12 relative for κ ≤ 100, about
/// εκ absolute beyond, averaged.
const BATCHED_ETA1_TOLERANCE: f64 = 1e-11;

/// 1/κ by the scalar routine at one point of the section (0 where J is not defined).
fn scalar_inverse_condition(delta: &LinearDelta, y: f64, z: f64) -> f64 {
    inverse_condition_at(delta, &Vector3::new(0.0, y, z), LinearDeltaMode::PAPER).unwrap_or(0.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Over the full search box of Table 2 row 1 (and beyond in L2/L1).
    #[test]
    fn batched_eta1_equals_the_scalar_path(
        l1 in 1.0..2.8f64,
        ya in -0.9..0.9f64,
        zr in -1.2..0.6f64,
        l2 in 0.01..2.0f64,
        n in prop::sample::select(vec![5usize, 8, 13, 16, 24]),
    ) {
        let delta = delta(&[l1, ya, zr, l2]).unwrap();
        let batched = SectionIndices::new(&delta, LinearDeltaMode::PAPER).eta1(Eta1Rule::Quadrature(n));
        let scalar = mean_by_quadrature(
            &delta.cross_section(),
            |y, z| scalar_inverse_condition(&delta, y, z),
            n,
        );
        match (batched, scalar) {
            (Ok(batched), Ok(scalar)) => prop_assert!(
                (batched - scalar).abs() <= BATCHED_ETA1_TOLERANCE,
                "batched {batched} vs scalar {scalar}"
            ),
            (batched, scalar) => prop_assert_eq!(batched.is_err(), scalar.is_err()),
        }
    }
}

#[test]
fn batched_paper_grid_equals_the_scalar_path() {
    for design in [
        [1.48, 0.0, 0.0, 0.57],
        [2.0, 0.3, -0.6, 0.63],
        [1.55, 0.0, -0.75, 0.01],
    ] {
        let delta = delta(&design).unwrap();
        let indices = SectionIndices::new(&delta, LinearDeltaMode::PAPER);
        let batched = indices.eta1_by_grid(&GridRule::default()).unwrap();
        let scalar = mean_by_grid(
            indices.section(),
            |y, z| scalar_inverse_condition(&delta, y, z),
            &GridRule::default(),
        )
        .unwrap();
        assert_eq!(batched.n_points, scalar.n_points);
        assert!(
            (batched.mean - scalar.mean).abs() <= BATCHED_ETA1_TOLERANCE,
            "{design:?}: batched {} vs scalar {}",
            batched.mean,
            scalar.mean
        );
        assert_eq!(
            indices.eta1(Eta1Rule::Grid).unwrap().to_bits(),
            batched.mean.to_bits()
        );
    }
}
