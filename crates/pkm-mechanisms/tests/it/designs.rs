//! The design structs of every mechanism: hostile values give a typed [`DesignError`] naming the
//! field (and only values that break the documented requirement do), the `_deg` constructors
//! agree with radians, `design()` returns what was built, serde round-trips each struct and
//! rejects unknown fields.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{Isometry3, Vector3};
use pkm_mechanisms::{
    JointLayout, LinearDelta, LinearDeltaDesign, LinearDeltaRatios, Pairing, Placement,
    RotaryDelta, RotaryDeltaDesign, StewartDesign, StewartDesignVariable, StewartGough,
    StewartTaskProblem, ThreeUpu, ThreeUpuDesign, Tsai3Dof, TsaiDesign, UJointAxes, WrenchSystem,
    presets,
};
use pkm_screw_theory::Twist;
use pkm_traits::{Bounds, DesignError, Objective};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::f64::consts::PI;

const HOSTILE: [f64; 8] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -1.0,
    -1e300,
    1e300,
    f64::MIN_POSITIVE,
];

fn positive(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

fn finite(v: f64) -> bool {
    v.is_finite()
}

/// A positive length small enough that the rotary Delta's derived quantities (its squares and
/// reach cylinder) stay finite (issue 20).
fn length(v: f64) -> bool {
    positive(v) && v <= 1e100
}

/// A length whose powers (the Tsai platform's reach cubed and squares, the Linear Delta's
/// fourth powers) are normal numbers: neither huge nor tiny (issue 29).
fn scaled_length(v: f64) -> bool {
    length(v) && v >= 1e-100
}

/// A finite value that is not huge.
fn moderate(v: f64) -> bool {
    v.is_finite() && v.abs() <= 1e100
}

/// One field of a design: the parameter name its error carries, how to set it, and the
/// documented requirement.
type Field<D> = (&'static str, fn(&mut D, f64), fn(f64) -> bool);

/// Every hostile value in every field: `build` fails exactly where the requirement fails, with
/// a [`DesignError`] that names the field and carries the value.
fn check_fields<D: Copy, M>(
    valid: D,
    build: impl Fn(D) -> Result<M, DesignError>,
    fields: &[Field<D>],
) {
    assert!(build(valid).is_ok(), "the reference design is valid");
    for &(name, set, requirement) in fields {
        for v in HOSTILE {
            let mut design = valid;
            set(&mut design, v);
            match build(design) {
                Ok(_) => assert!(requirement(v), "{name} = {v:e} was accepted"),
                Err(e) => {
                    assert!(!requirement(v), "{name} = {v:e} was rejected: {e}");
                    // A derived quantity that overflows (or underflows) names itself, not the
                    // field.
                    if e.requirement.contains("derived") {
                        let extreme = v.abs() > 1e100 || v.abs() < 1e-100;
                        assert!(extreme, "{name} = {v:e} overflowed: {e}");
                        continue;
                    }
                    assert_eq!(e.parameter, name);
                    assert!(e.value.to_bits() == v.to_bits() || (e.value.is_nan() && v.is_nan()));
                }
            }
        }
    }
}

#[test]
fn rotary_delta_fields_are_validated() {
    let fields: [Field<RotaryDeltaDesign>; 8] = [
        ("R", |d, v| d.base_radius = v, length),
        (
            "r",
            |d, v| d.plate_offset = v,
            |v| finite(v) && v.abs() <= 1e100,
        ),
        ("La", |d, v| d.arm = v, length),
        ("Lb", |d, v| d.forearm = v, length),
        ("alpha", |d, v| d.alpha = v, finite),
        ("beta", |d, v| d.beta = v, finite),
        ("z0", |d, v| d.placement.motor_plane_z = v, finite),
        ("phi1", |d, v| d.placement.azimuth_motor_1 = v, finite),
    ];
    check_fields(
        presets::nuwar(Placement::canonical()),
        RotaryDelta::new,
        &fields,
    );
}

#[test]
fn tsai_fields_are_validated() {
    let fields: [Field<TsaiDesign>; 6] = [
        ("a", |d, v| d.a = v, scaled_length),
        ("b", |d, v| d.b = v, scaled_length),
        ("d+e", |d, v| d.d_plus_e = v, |v| moderate(v) && v >= 0.0),
        ("c-r", |d, v| d.c_minus_r = v, moderate),
        ("phi_2", |d, v| d.phi2 = v, finite),
        ("phi_3", |d, v| d.phi3 = v, finite),
    ];
    check_fields(presets::stamper_max_gci(), Tsai3Dof::new, &fields);
}

#[test]
fn linear_delta_fields_are_validated() {
    let valid = LinearDeltaDesign {
        ratios: LinearDeltaRatios {
            l1_over_yr: 2.0,
            ya_over_yr: 0.1,
            zr_over_yr: -0.2,
            l2_over_l1: 0.63,
        },
        yr: 1.0,
    };
    let fields: [Field<LinearDeltaDesign>; 5] = [
        ("YR", |d, v| d.yr = v, scaled_length),
        (
            "L1/YR",
            |d, v| d.ratios.l1_over_yr = v,
            |v| moderate(v) && v >= 1.0,
        ),
        ("YA/YR", |d, v| d.ratios.ya_over_yr = v, |v| v.abs() < 1.0),
        ("ZR/YR", |d, v| d.ratios.zr_over_yr = v, moderate),
        ("L2/L1", |d, v| d.ratios.l2_over_l1 = v, length),
    ];
    check_fields(valid, LinearDelta::new, &fields);
}

#[test]
fn stewart_fields_are_validated() {
    let separation = |v: f64| (0.0..=120f64.to_radians()).contains(&v);
    let fields: [Field<StewartDesign>; 5] = [
        ("x1", |d, v| d.base_radius = v, positive),
        ("x2", |d, v| d.platform_radius = v, positive),
        ("x3", |d, v| d.base_separation = v, separation),
        ("x4", |d, v| d.platform_separation = v, separation),
        ("offset", |d, v| d.layout.offset_deg = v, finite),
    ];
    check_fields(
        presets::wolf_shoham_stewart_s4_1(),
        StewartGough::new,
        &fields,
    );
    let at_limit = StewartDesign::from_deg(12.0, 8.0, 120.0, 0.0);
    assert!(StewartGough::new(at_limit).is_ok());
    assert!((at_limit.base_separation - 2.0 * PI / 3.0).abs() < 1e-15);
    let beyond = StewartDesign {
        platform_separation: at_limit.base_separation.next_up(),
        ..at_limit
    };
    assert_eq!(StewartGough::new(beyond).unwrap_err().parameter, "x4");
}

#[test]
fn three_upu_fields_are_validated() {
    let fields: [Field<ThreeUpuDesign>; 5] = [
        ("a", |d, v| d.base_radius = v, positive),
        ("b", |d, v| d.platform_radius = v, positive),
        ("azimuth", |d, v| d.azimuths[0] = v, finite),
        ("azimuth", |d, v| d.azimuths[1] = v, finite),
        ("azimuth", |d, v| d.azimuths[2] = v, finite),
    ];
    let park = presets::park_3upu();
    check_fields(park, ThreeUpu::new, &fields);
    for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut design = park;
        design.upper[1].u2.z = v;
        assert_eq!(ThreeUpu::new(design).unwrap_err().parameter, "|u1 x u2|");
    }
    let mut parallel = park;
    parallel.upper[2].u2 = parallel.upper[2].u1 * 1e300;
    assert_eq!(ThreeUpu::new(parallel).unwrap_err().parameter, "|u1 x u2|");
    let mut long = park;
    long.upper[0].u1 *= 1e150;
    assert!(
        ThreeUpu::new(long).is_ok(),
        "only the axes' directions matter"
    );
    // An axis whose squared norm overflows has no direction: a typed error, not a panic.
    long.upper[0].u1 *= 1e150;
    assert_eq!(ThreeUpu::new(long).unwrap_err().parameter, "|u1 x u2|");
}

#[test]
fn degree_constructors_agree_with_radians() {
    let tsai = TsaiDesign::from_deg(0.3, 0.5, 0.1, -0.05, 120.0, 240.0);
    assert!((tsai.phi2 - 2.0 * PI / 3.0).abs() < 1e-15);
    assert!((tsai.phi3 - 4.0 * PI / 3.0).abs() < 1e-15);
    assert_eq!(
        [tsai.a, tsai.b, tsai.d_plus_e, tsai.c_minus_r].map(f64::to_bits),
        [0.3, 0.5, 0.1, -0.05f64].map(f64::to_bits)
    );
    let phi = Tsai3Dof::new(tsai).unwrap().phi();
    assert!((phi[1] - 2.0 * PI / 3.0).abs() < 1e-15 && (phi[2] - 4.0 * PI / 3.0).abs() < 1e-15);

    let stewart = StewartDesign::from_deg(12.0, 8.0, 30.0, 8.0);
    assert!((stewart.base_separation - PI / 6.0).abs() < 1e-15);
    assert!((stewart.platform_separation - 8.0 * PI / 180.0).abs() < 1e-15);
    assert_eq!(stewart.layout, JointLayout::default());
    // The joints in radians: b_0 at -x3/2, r_1 at +x4/2, b_2 at 120° - x3/2 (same pattern).
    let sg = StewartGough::new(stewart).unwrap();
    let on_circle = |r: f64, t: f64| Vector3::new(r * t.cos(), r * t.sin(), 0.0);
    let expected = [
        (sg.base_joints()[0], on_circle(12.0, -PI / 12.0)),
        (sg.platform_joints()[1], on_circle(8.0, 4.0 * PI / 180.0)),
        (
            sg.base_joints()[2],
            on_circle(12.0, 2.0 * PI / 3.0 - PI / 12.0),
        ),
    ];
    for (got, want) in expected {
        assert!((got - want).amax() < 1e-14, "{got} vs {want}");
    }
    let zigzag = StewartDesign {
        layout: JointLayout {
            pairing: Pairing::ZigZag,
            offset_deg: 90.0,
            ..JointLayout::default()
        },
        ..stewart
    };
    // Zig-zag: r_0 at offset - (60° - x4/2).
    let r0 = StewartGough::new(zigzag).unwrap().platform_joints()[0];
    let want = on_circle(8.0, PI / 2.0 - (PI / 3.0 - 4.0 * PI / 180.0));
    assert!((r0 - want).amax() < 1e-14);

    let park = presets::park_3upu();
    for (got, want) in park
        .azimuths
        .iter()
        .zip([-PI / 2.0, PI / 6.0, 5.0 * PI / 6.0])
    {
        assert!((got - want).abs() < 1e-15);
    }
}

/// Freeing a separation in degrees or in radians is the same problem up to the unit of its
/// variable.
#[test]
fn stewart_design_variables_in_degrees_and_radians_agree() {
    let twist = Twist::new(Vector3::new(0.3, -0.2, 1.0), Vector3::new(1.0, 2.0, 0.5));
    let problem = |variable, bounds| {
        StewartTaskProblem::new(
            presets::wolf_shoham_stewart_s4_1(),
            Vector3::new(1.0, -2.0, 35.0),
            Vector3::new(0.05, 0.0, -0.1),
            twist,
        )
        .unwrap()
        .free_design(variable, bounds)
    };
    let deg = problem(
        StewartDesignVariable::PlatformSeparationDeg,
        Bounds::new(0.0, 30.0).unwrap(),
    );
    let rad = problem(
        StewartDesignVariable::PlatformSeparation,
        Bounds::new(0.0, 30f64.to_radians()).unwrap(),
    );
    let (f_deg, f_rad) = (
        deg.value(&[21.1]).unwrap(),
        rad.value(&[21.1f64.to_radians()]).unwrap(),
    );
    assert!((f_deg - f_rad).abs() <= 1e-12 * f_deg, "{f_deg} vs {f_rad}");
    let (mechanism, _) = deg.evaluate(&[21.1]).unwrap();
    assert!((mechanism.design().platform_separation - 21.1 * PI / 180.0).abs() < 1e-15);
    // The base separation variable moves the base joints only.
    let base = problem(
        StewartDesignVariable::BaseSeparationDeg,
        Bounds::new(0.0, 60.0).unwrap(),
    );
    let (moved, _) = base.evaluate(&[40.0]).unwrap();
    let fixed = StewartGough::new(presets::wolf_shoham_stewart_s4_1()).unwrap();
    assert_eq!(moved.platform_joints(), fixed.platform_joints());
    assert!((moved.design().base_separation - 40.0 * PI / 180.0).abs() < 1e-15);
}

#[test]
fn design_returns_what_was_built() {
    let rotary = presets::miller_prototype(0.4, 1.1, Placement::canonical());
    assert_eq!(RotaryDelta::new(rotary).unwrap().design(), rotary);
    let tsai = TsaiDesign::from_deg(0.3, 0.5, 0.1, -0.05, 100.0, 230.0);
    assert_eq!(Tsai3Dof::new(tsai).unwrap().design(), tsai);
    let linear = LinearDeltaDesign {
        ratios: LinearDeltaRatios::from_slice(&[2.0, 0.1, -0.2, 0.63]),
        yr: 0.7,
    };
    assert_eq!(LinearDelta::new(linear).unwrap().design(), linear);
    let stewart = presets::wolf_shoham_stewart_s4_2();
    assert_eq!(StewartGough::new(stewart).unwrap().design(), stewart);
    let upu = presets::park_3upu();
    assert_eq!(ThreeUpu::new(upu).unwrap().design(), upu);
    // Park's design reproduces the eq. 18 rows of its definition: unit couples normal to the
    // tangent and radial axes, i.e. vertical.
    let rows = ThreeUpu::new(upu)
        .unwrap()
        .wrench_rows(&Isometry3::translation(0.0, 0.0, 30.0))
        .unwrap();
    for i in 3..6 {
        assert!((rows[(i, 5)].abs() - 1.0).abs() < 1e-12);
    }
}

/// JSON round trip, bit for bit, and rejection of a misspelt field.
fn round_trip<D: Serialize + DeserializeOwned + PartialEq + std::fmt::Debug>(design: &D) {
    let json = serde_json::to_string(design).unwrap();
    let back: D = serde_json::from_str(&json).unwrap();
    assert_eq!(&back, design, "{json}");
    let mut value: serde_json::Value = serde_json::from_str(&json).unwrap();
    value
        .as_object_mut()
        .expect("a design is a JSON object")
        .insert("bogus_field".into(), 1.0.into());
    let err = serde_json::from_value::<D>(value).unwrap_err();
    assert!(err.to_string().contains("unknown field"), "{err}");
}

#[test]
fn designs_round_trip_through_json_and_reject_unknown_fields() {
    round_trip(&presets::nuwar(Placement::canonical()));
    round_trip(&Placement::canonical());
    round_trip(&presets::stamper_max_gci());
    let linear = LinearDeltaDesign {
        ratios: LinearDeltaRatios::from_slice(&[2.0, 0.1, -0.2, 0.63]),
        yr: 0.7,
    };
    round_trip(&linear);
    round_trip(&linear.ratios);
    let stewart = StewartDesign {
        layout: JointLayout {
            pairing: Pairing::ZigZag,
            offset_deg: 15.0,
            ..JointLayout::default()
        },
        ..presets::wolf_shoham_stewart_s4_1()
    };
    round_trip(&stewart);
    round_trip(&stewart.layout);
    round_trip(&presets::park_3upu());
    round_trip(&UJointAxes::park(0.3));
    // A nested unknown field is rejected too.
    let json = serde_json::to_string(&stewart)
        .unwrap()
        .replace("\"offset_deg\"", "\"offset\"");
    assert!(serde_json::from_str::<StewartDesign>(&json).is_err());
}
