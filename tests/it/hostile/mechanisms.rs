//! `pkm-mechanisms`: every constructor, and IK, FK and Jacobians of every mechanism.

use super::{
    all_finite, config, hostile_count, hostile_f64, hostile_vec3, judge, judge_err, judge_value,
};
use nalgebra::{Isometry3, SVector, Vector3};
use pkm_mechanisms::{
    ConstantOrientation, Elbow, ElbowMode, JointLayout, LegBranch, LinearDelta, LinearDeltaDesign,
    LinearDeltaMode, LinearDeltaRatios, Placement, RotaryDelta, RotaryDeltaDesign, StewartDesign,
    StewartDesignVariable, StewartGough, StewartTaskProblem, ThreeUpu, ThreeUpuDesign, Tsai3Dof,
    TsaiDesign, UJointAxes, WrenchSystem, platform_pose, pose_from_task, presets,
};
use pkm_screw_theory::Twist;
use pkm_traits::{
    Bounds, ClosedChain, ForwardKinematics, InverseKinematics, NewtonSettings, Objective,
    SlicedRegion, WorkspaceConstraint,
};
use pkm_workspace_indices::Workspace;
use proptest::prelude::*;

/// IK at `x`; where it succeeds, the loop closes, the Jacobian is finite or typed, and FK from
/// `guess` (bounded iterations) returns a closing pose or a typed error.
fn kinematics<M, const N: usize>(
    name: &'static str,
    m: &M,
    x: &SVector<f64, N>,
    mode: M::WorkingMode,
    guess: &SVector<f64, N>,
) -> Result<(), TestCaseError>
where
    M: InverseKinematics<N, N> + ForwardKinematics<N>,
{
    let ik = m.inverse_kinematics(x, mode);
    judge(
        name,
        || m.inverse_kinematics(x, mode),
        |q| all_finite(q.iter()) && m.closure(x, q).amax() <= 1e-6 * (1.0 + x.amax()),
    )?;
    let q = match ik {
        Ok(q) => q,
        Err(_) => *x,
    };
    judge(
        "ClosedChain::jacobian",
        || m.jacobian(x, &q),
        |j| all_finite(j.iter()),
    )?;
    judge(
        "InverseKinematics::velocity_jacobian_at",
        || m.velocity_jacobian_at(x, mode),
        |j| all_finite(j.iter()),
    )?;
    let settings = NewtonSettings {
        tolerance: 1e-10,
        max_iterations: 30,
    };
    judge(
        "ForwardKinematics::forward_kinematics",
        || m.forward_kinematics(&q, guess, &settings),
        |x| all_finite(x.iter()) && m.closure(x, &q).amax() <= 1e-9,
    )
}

fn tsai_design() -> impl Strategy<Value = (f64, f64, f64, f64, f64, f64)> {
    (
        hostile_f64(),
        hostile_f64(),
        hostile_f64(),
        hostile_f64(),
        hostile_f64(),
        hostile_f64(),
    )
}

fn valid_tsai() -> impl Strategy<Value = Tsai3Dof> {
    (
        0.1..1.0f64,
        0.1..1.0f64,
        prop_oneof![Just(0.0), 0.0..0.3f64],
        -0.2..0.2f64,
    )
        .prop_map(|(a, b, s, h)| {
            Tsai3Dof::new(TsaiDesign::from_deg(a, b, s, h, 120.0, 240.0)).unwrap()
        })
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn tsai_constructor_and_kinematics(design in tsai_design(), p in hostile_vec3(), guess in hostile_vec3()) {
        let (a, b, d_plus_e, c_minus_r, phi2, phi3) = design;
        let design = TsaiDesign { a, b, d_plus_e, c_minus_r, phi2, phi3 };
        judge("Tsai3Dof::new", || Tsai3Dof::new(design), |d| d.reach().is_finite())?;
        judge("TsaiDesign::from_deg", || Tsai3Dof::new(TsaiDesign::from_deg(a, b, d_plus_e, c_minus_r, phi2, phi3)), |d| d.reach().is_finite())?;
        if let Ok(d) = Tsai3Dof::new(design) {
            kinematics("Tsai3Dof::inverse_kinematics", &d, &p, [Elbow::Out; 3], &guess)?;
        }
    }

    /// Singular points of valid designs: `d + e = 0` and `|p_v| = b` make the offset length
    /// `L = 0`, where θ₂ is undefined.
    #[test]
    fn tsai_legs_at_singular_points(d in valid_tsai(), x in -0.5..0.5f64, z in -0.5..0.9f64, sign in prop::bool::ANY, leg in 0..3usize) {
        let y = if sign { d.b() } else { -d.b() };
        let p = Vector3::new(x, y, z);
        for branch in LegBranch::ALL {
            judge("Tsai3Dof::leg_inverse_kinematics", || d.leg_inverse_kinematics(leg, &p, branch), |angles| {
                all_finite([angles.theta1, angles.theta2, angles.theta3].iter())
                    && (d.leg_chain_end(angles) - d.leg_target(leg, &p)).amax() <= 1e-9
            })?;
        }
        kinematics("Tsai3Dof::inverse_kinematics", &d, &p, [Elbow::Out; 3], &Vector3::new(0.0, 0.0, 0.5))?;
    }

    #[test]
    fn linear_delta_constructor_and_kinematics(
        r in (hostile_f64(), hostile_f64(), hostile_f64(), hostile_f64()), yr in hostile_f64(),
        y in hostile_f64(), z in hostile_f64(), x in hostile_vec3(), guess in hostile_vec3(),
    ) {
        let ratios = LinearDeltaRatios { l1_over_yr: r.0, ya_over_yr: r.1, zr_over_yr: r.2, l2_over_l1: r.3 };
        let design = LinearDeltaDesign { ratios, yr };
        judge("LinearDelta::new", || LinearDelta::new(design), |d| {
            all_finite(d.arm_lengths().iter()) && d.rails().iter().all(|r| all_finite(r.iter()))
        })?;
        if let Ok(d) = LinearDelta::new(design) {
            judge("LinearDelta::arm_reaches", || d.arm_reaches(y, z), |q| all_finite(q.iter()))?;
            judge("LinearDelta::velocity_jacobian_at", || d.velocity_jacobian_at(&Vector3::new(0.0, y, z), LinearDeltaMode::PAPER), |j| all_finite(j.iter()))?;
            let section = d.cross_section();
            judge_value("CrossSection::area", || section.area(), |a| a.is_finite() && *a >= 0.0)?;
            judge_value("CrossSection::slice", || section.slice(y), |s| s.is_none_or(|(lo, hi)| lo.is_finite() && hi.is_finite() && lo <= hi))?;
            kinematics("LinearDelta::inverse_kinematics", &d, &x, LinearDeltaMode::PAPER, &guess)?;
        }
    }

    #[test]
    fn linear_delta_reachable_kinematics(
        r in (1.0..2.0f64, -0.9..0.9f64, -1.0..1.0f64, 0.5..1.5f64), y in -1.0..1.0f64, z in -2.0..2.0f64,
    ) {
        let ratios = LinearDeltaRatios { l1_over_yr: r.0, ya_over_yr: r.1, zr_over_yr: r.2, l2_over_l1: r.3 };
        let d = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 }).unwrap();
        kinematics("LinearDelta::inverse_kinematics", &d, &Vector3::new(0.1, y, z), LinearDeltaMode::PAPER, &Vector3::new(0.0, y, z))?;
    }

    #[test]
    fn stewart_gough_constructor_and_kinematics(
        x in (hostile_f64(), hostile_f64(), hostile_f64(), hostile_f64()), offset in hostile_f64(),
        p in hostile_vec3(), w in hostile_vec3(), alpha in hostile_f64(),
    ) {
        let finite_joints = |s: &StewartGough| {
            s.base_joints().iter().chain(s.platform_joints()).all(|v| all_finite(v.iter()))
        };
        judge("StewartDesign::from_deg", || StewartGough::new(StewartDesign::from_deg(x.0, x.1, x.2, x.3)), finite_joints)?;
        let layout = JointLayout { offset_deg: offset, ..JointLayout::default() };
        let design = StewartDesign {
            base_radius: x.0, platform_radius: x.1, base_separation: x.2, platform_separation: x.3, layout,
        };
        judge("StewartGough::new", || StewartGough::new(design), finite_joints)?;
        judge("platform_pose", || platform_pose(p, w, alpha), |g| all_finite(g.to_homogeneous().iter()))?;
        let task = SVector::<f64, 6>::new(p.x, p.y, p.z, w.x, w.y, w.z);
        judge("pose_from_task", || pose_from_task(&task), |g| all_finite(g.to_homogeneous().iter()))?;
        let sg = StewartGough::new(StewartDesign::from_deg(1.0, 0.5, 20.0, 30.0)).unwrap();
        if let Ok(pose) = pose_from_task(&task) {
            let twist = Twist::new(Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.1, 0.0, 0.0));
            judge("StewartGough::wrench_rows", || sg.wrench_rows(&pose), |m| all_finite(m.iter()))?;
            judge("StewartGough::leg_rates", || sg.leg_rates(&pose, &twist), |m| all_finite(m.iter()))?;
            judge("StewartGough::task_objective", || sg.task_objective(&pose, &twist), |f| f.is_finite())?;
        }
        let guess = SVector::<f64, 6>::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
        kinematics("StewartGough::inverse_kinematics", &sg, &task, (), &guess)?;
    }

    #[test]
    fn stewart_constant_orientation_kinematics(w in hostile_vec3(), p in hostile_vec3()) {
        let sg = StewartGough::new(StewartDesign::from_deg(1.0, 0.5, 20.0, 30.0)).unwrap();
        let finite_view = |v: &ConstantOrientation| {
            all_finite(v.rotation().matrix().iter())
                && v.shell_centres().iter().all(|c| all_finite(c.iter()))
        };
        judge("ConstantOrientation::new", || ConstantOrientation::new(sg.clone(), w), finite_view)?;
        let view = ConstantOrientation::new(sg, Vector3::new(0.1, -0.2, 0.3)).unwrap();
        judge(
            "ConstantOrientation::inverse_kinematics",
            || view.inverse_kinematics(&p, ()),
            |q| all_finite(q.iter()) && view.closure(&p, q).amax() <= 1e-6 * (1.0 + p.amax()).powi(2),
        )?;
        judge(
            "ConstantOrientation::velocity_jacobian_at",
            || view.velocity_jacobian_at(&p, ()),
            |j| all_finite(j.iter()),
        )?;
        let lengths = WorkspaceConstraint::joint_range(0.5, 2.0).unwrap();
        let ws = Workspace::new(&view, &[()], &[lengths]).unwrap();
        let r = ws.inverse_condition(&p);
        prop_assert!(r.is_none_or(|r| (0.0..=1.0).contains(&r)), "1/κ = {r:?} at {p}");
        prop_assert_eq!(ws.contains(&p), r.is_some());
    }

    #[test]
    fn three_upu_constructor_and_wrenches(
        a in hostile_f64(), b in hostile_f64(), u1 in hostile_vec3(), u2 in hostile_vec3(),
        theta in hostile_f64(), p in hostile_vec3(), guess in hostile_vec3(),
    ) {
        let axes = UJointAxes { u1, u2 };
        let design = ThreeUpuDesign {
            base_radius: a,
            platform_radius: b,
            azimuths: [theta, 0.3, -theta],
            upper: [axes, UJointAxes::park(theta), axes],
        };
        judge("ThreeUpu::new", || ThreeUpu::new(design), |_| true)?;
        let park = ThreeUpuDesign { base_radius: a, platform_radius: b, ..presets::park_3upu() };
        if let Ok(m) = ThreeUpu::new(ThreeUpuDesign { upper: [UJointAxes::park(0.3); 3], ..park }) {
            let pose = Isometry3::translation(p.x, p.y, p.z);
            let twist = Twist::new(Vector3::new(0.0, 0.0, 1.0), Vector3::zeros());
            judge("ThreeUpu::wrench_rows", || m.wrench_rows(&pose), |r| all_finite(r.iter()))?;
            judge("ThreeUpu::task_objective", || m.task_objective(&pose, &twist), |f| f.is_finite())?;
            kinematics("ThreeUpu::inverse_kinematics", &m, &p, (), &guess)?;
        }
    }

    #[test]
    fn stewart_task_problem(
        design in (hostile_f64(), hostile_f64(), hostile_f64(), hostile_f64()), p in hostile_vec3(),
        w in hostile_vec3(), chi in hostile_vec3(), k in hostile_count(), max_angle in hostile_f64(),
        v in prop::collection::vec(hostile_f64(), 0..6),
    ) {
        let twist = Twist::new(chi, Vector3::new(0.1, 0.0, 0.0));
        let design = StewartDesign::from_deg(design.0, design.1, design.2, design.3);
        judge("StewartTaskProblem::new", || StewartTaskProblem::new(design, p, w, twist), |_| true)?;
        let base = StewartTaskProblem::new(StewartDesign::from_deg(1.0, 0.5, 20.0, 30.0), Vector3::new(0.0, 0.0, 1.0), Vector3::zeros(), twist);
        if let (Ok(problem), Ok(bounds)) = (base, Bounds::new(0.5, 2.0)) {
            judge("StewartTaskProblem::free_position", || problem.clone().free_position(k, bounds), |_| true)?;
            judge("StewartTaskProblem::free_rotation", || problem.clone().free_rotation(max_angle), |_| true)?;
            let free = problem.free_design(StewartDesignVariable::BaseRadius, bounds).free_rotation(0.5);
            if let Ok(free) = free {
                judge("StewartTaskProblem::value", || free.value(&v), |f| f.is_finite())?;
            }
        }
    }

    #[test]
    fn rotary_delta_constructor_and_kinematics(
        g in (hostile_f64(), hostile_f64(), hostile_f64(), hostile_f64()), angles in (hostile_f64(), hostile_f64()),
        z0 in hostile_f64(), x in hostile_vec3(), guess in hostile_vec3(),
    ) {
        let placement = Placement { motor_plane_z: z0, azimuth_motor_1: 0.3 };
        let design = RotaryDeltaDesign {
            base_radius: g.0, plate_offset: g.1, arm: g.2, forearm: g.3, alpha: angles.0, beta: angles.1, placement,
        };
        judge("RotaryDelta::new", || RotaryDelta::new(design), |d| d.arm().is_finite())?;
        judge("presets::miller_delta", || RotaryDelta::new(presets::miller_delta(placement)), |d| d.arm().is_finite())?;
        let d = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
        kinematics("RotaryDelta::inverse_kinematics", &d, &x, ElbowMode::Out, &guess)?;
    }
}

#[test]
fn tsai_column_volume_refuses_huge_grids() {
    let d = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    for ngrid in [0, usize::MAX, 1 << 40] {
        super::expect(judge_err("Tsai3Dof::column_volume (huge)", || {
            d.column_volume(ngrid)
        }));
    }
    super::expect(judge(
        "Tsai3Dof::column_volume",
        || d.column_volume(50),
        |v| v.is_finite() && *v > 0.0,
    ));
}

/// The rotary Delta's lane test and its inverse kinematics agree at every point, one ulp either
/// side of the workspace boundary included (171 of 1,204 points there disagreed): along 200
/// rays from an inside point, the boundary is found to the last ulp by bisection on the
/// inverse kinematics, and the lane test is asked at the 7 ulps of t around it, one lane and
/// four at a time.
#[test]
fn rotary_delta_lanes_agree_with_the_inverse_kinematics_at_the_boundary() {
    use pkm_traits::Lanes;
    for design in [
        presets::nuwar(Placement::canonical()),
        presets::miller_delta(Placement::canonical()),
    ] {
        let delta = RotaryDelta::new(design).unwrap();
        let reaches = |p: &Vector3<f64>| delta.inverse_kinematics(p, ElbowMode::Out).is_ok();
        let centre = Vector3::new(0.0, 0.0, -0.75);
        assert!(reaches(&centre), "the rays start inside");
        let (mut checked, mut disagree) = (0, Vec::new());
        for k in 0..200 {
            // Fibonacci directions on the sphere.
            let z = 1.0 - (2.0 * k as f64 + 1.0) / 200.0;
            let phi = k as f64 * std::f64::consts::PI * (3.0 - 5.0_f64.sqrt());
            let r = (1.0 - z * z).sqrt();
            let dir = Vector3::new(r * phi.cos(), r * phi.sin(), z);
            let (mut lo, mut hi) = (0.0_f64, 4.0_f64);
            if reaches(&(centre + dir * hi)) {
                continue;
            }
            while hi - lo > 0.0 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if reaches(&(centre + dir * mid)) {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            let mut t = lo;
            for _ in 0..3 {
                t = t.next_down();
            }
            let points: Vec<Vector3<f64>> = (0..7)
                .map(|_| {
                    let p = centre + dir * t;
                    t = t.next_up();
                    p
                })
                .collect();
            for chunk in points.chunks(4) {
                let lanes: [Lanes<4>; 3] = std::array::from_fn(|c| {
                    Lanes(std::array::from_fn(|l| chunk[l.min(chunk.len() - 1)][c]))
                });
                let four = delta.reachable_lanes(&lanes);
                for (l, p) in chunk.iter().enumerate() {
                    let one = delta.reachable_lanes(&[Lanes([p.x]), Lanes([p.y]), Lanes([p.z])])[0];
                    checked += 1;
                    if one != reaches(p) || four[l] != reaches(p) {
                        disagree.push(*p);
                    }
                }
            }
        }
        assert!(checked > 1000, "vacuous: {checked} points");
        assert!(
            disagree.is_empty(),
            "{} of {checked} disagree: {:?}",
            disagree.len(),
            &disagree[..disagree.len().min(3)]
        );
    }
}

proptest! {
    #![proptest_config(config())]

    /// `StewartGough::leg_lengths` keeps its documented contract: finite for a finite pose of
    /// translation below 1e150, NaN in gives NaN out, never a panic.
    #[test]
    fn stewart_leg_lengths_keep_their_contract(
        t in prop::array::uniform3(-1e150..1e150f64), r in prop::array::uniform3(-4.0..4.0f64), nan in prop::bool::ANY,
    ) {
        let platform = StewartGough::new(presets::wolf_shoham_stewart_s4_1()).unwrap();
        let mut x = Vector3::from(t);
        if nan {
            x[1] = f64::NAN;
        }
        let pose = Isometry3::new(x, Vector3::from(r));
        let lengths = platform.leg_lengths(&pose);
        if nan {
            prop_assert!(lengths.iter().all(|l| l.is_nan()), "{lengths:?}");
        } else {
            prop_assert!(all_finite(lengths.iter()), "{x:?}: {lengths:?}");
        }
    }
}
