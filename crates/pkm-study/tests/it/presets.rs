//! The papers' designs as study tables (`From`/`TryFrom` of each kind's table): the table of a
//! library design builds that design back, to rounding of the degree conversions.

use pkm_mechanisms::{Placement, UJointAxes, presets};
use pkm_study::StudyMechanism;
use pkm_study::schema::mechanism::{RotaryDeltaSpec, StewartSpec, ThreeUpuSpec, TsaiSpec};

fn close(a: &[f64], b: &[f64]) {
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= 1e-12 * (1.0 + x.abs()), "{a:?} vs {b:?}");
    }
}

#[test]
fn the_table_of_a_library_design_builds_that_design() {
    for d in [
        presets::nuwar(Placement::canonical()),
        presets::miller_delta(Placement::canonical()),
    ] {
        let built = RotaryDeltaSpec::from(d).build().unwrap().design();
        close(
            &[
                built.base_radius,
                built.plate_offset,
                built.arm,
                built.forearm,
                built.alpha,
                built.beta,
            ],
            &[
                d.base_radius,
                d.plate_offset,
                d.arm,
                d.forearm,
                d.alpha,
                d.beta,
            ],
        );
    }
    let d = presets::stamper_max_gci();
    let built = TsaiSpec::from(d).build().unwrap().design();
    close(
        &[
            built.a,
            built.b,
            built.d_plus_e,
            built.c_minus_r,
            built.phi2,
            built.phi3,
        ],
        &[d.a, d.b, d.d_plus_e, d.c_minus_r, d.phi2, d.phi3],
    );
    let d = presets::wolf_shoham_stewart_s4_1();
    let built = StewartSpec::from(d).build().unwrap().platform().design();
    close(
        &[
            built.base_radius,
            built.platform_radius,
            built.base_separation,
            built.platform_separation,
        ],
        &[
            d.base_radius,
            d.platform_radius,
            d.base_separation,
            d.platform_separation,
        ],
    );
    let d = presets::park_3upu();
    let built = ThreeUpuSpec::try_from(d).unwrap().build().unwrap().design();
    close(&built.azimuths, &d.azimuths);
    for (b, a) in built.upper.iter().zip(&d.upper) {
        assert!((b.u1 - a.u1).norm() < 1e-12 && (b.u2 - a.u2).norm() < 1e-12);
    }
}

#[test]
fn a_three_upu_with_axes_other_than_parks_has_no_table() {
    let mut d = presets::park_3upu();
    d.upper[1] = UJointAxes::park_tilted(d.azimuths[1], 0.2, 0.0);
    let refused = ThreeUpuSpec::try_from(d).unwrap_err();
    assert!(refused.contains("not Park's"), "{refused}");
}
