//! Cross-formulation checks: Hamilton vs Lagrange inverse dynamics, and inverse followed by
//! forward dynamics (Miller 2004 §3).

use nalgebra::Vector3;
use pkm::dynamics_hamilton::inverse::{self, Accelerations, Differencing};
use pkm::dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm::mechanisms::{Placement, RotaryDelta, presets};
use pkm::papers::miller2004::dynamics::{CycleReading, pick_and_place};

fn max_diff(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max)
}

/// Hamilton's momenta differencing converges to the exact Lagrange torques at second order
/// (central): refining Δt by 10 shrinks the gap by about 100; with the same differencing on both
/// sides they agree far better than against exact accelerations.
#[test]
fn hamilton_converges_to_lagrange_at_second_order() {
    let trajectory = pick_and_place(0.5, CycleReading::RoundTrip).unwrap();
    for mechanism in [
        RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
        RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap(),
    ] {
        let m = ExtendedModel::new(mechanism, &MassParameters::miller2004()).unwrap();
        let gap = |dt: f64| {
            let s = inverse::sample(&m, &trajectory, dt).unwrap();
            let h = inverse::hamilton(&m, &s, Differencing::Central).unwrap();
            let exact = inverse::lagrange(&m, &s, Accelerations::Exact).unwrap();
            let same = inverse::lagrange(&m, &s, Accelerations::Differenced(Differencing::Central))
                .unwrap();
            (max_diff(&h, &exact), max_diff(&h, &same))
        };
        let (coarse, coarse_same) = gap(1e-3);
        let (fine, _) = gap(1e-4);
        let order = (coarse / fine).log10() * 2.0;
        assert!(
            (1.7..2.3).contains(&order),
            "order {order}: {coarse} → {fine}"
        );
        assert!(
            coarse_same < 0.01 && coarse_same < coarse / 10.0,
            "{coarse_same} vs {coarse}"
        );
    }
}
