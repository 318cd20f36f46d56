//! The wider convention search of `../shared/spec/miller-kinematics.md` §2 for NUWAR's printed
//! start angles: every discrete convention of the leg model, each with the motor-plane height
//! $z_0$ fitted by least squares.
//!
//! A convention-parameterised leg model of §1 (paper-exploration code: the library's
//! `RotaryDelta` keeps its one canonical convention). Leg $i$ of motor azimuth $\varphi_i$ has
//! the frame $F_i = R_z(\varphi_i)\, G(\alpha, \beta)$ with $G$ one of three orders (below),
//! $u_i = F_i e_x$, $w_i = F_i e_z$, the pivot $A_i = (R\cos\varphi_i, R\sin\varphi_i, z_0)$, the
//! plate point $C_i = p + c_i$, and the closed-form IK of §1: with $D = C_i - A_i$,
//! $K = (|D|^2 + L_a^2 - L_b^2)/(2L_a)$, $a = D\cdot u_i$, $b = -D\cdot w_i$,
//! $\theta_i = \operatorname{atan2}(b, a) \mp \arccos(K/\sqrt{a^2+b^2})$ (elbow out / in).
//!
//! The discrete choices: three frame orders, $\alpha = \arctan(1/\sqrt 2)$ or the printed
//! 35.26°, both signs of $\alpha$ and of $\beta = 60°$, the plate offset radial, turned with
//! $\beta$ or absent, $z$ up or down, both numbering directions with motor 1 at every 30°,
//! each leg's elbow separately, and four readings of $\theta$ (from the horizontal or the
//! vertical, either sign): $144 \cdot 2 \cdot 12 \cdot 8 \cdot 4 = 110\,592$ conventions.
//!
//! Since $z_0$ is free, only the height $h = z_0 - p_z$ of the motor plane above the plate (in
//! the robot's $z$-up frame) matters. It is scanned over every height at which a leg can reach
//! with the plate below the motors, $0 \le h \le L_a + L_b$, in 2 mm steps; every local minimum of the scan with an rms error below
//! 1° is refined by golden sections over its two neighbouring steps (after bisecting for the
//! reach limit when a neighbour is unreachable). Larger errors keep their scan value: they
//! matter for no reported count. (Measured: refining every minimum, or scanning in 1 mm
//! steps, changes neither the best fit nor any count; `docs/conventions.md`.)
//!
//! (The plate above the motors, $h < 0$, adds nothing for the horizontal readings: the
//! reflection $z \mapsto -z$ maps it to $h > 0$ with $\alpha \mapsto -\alpha$,
//! $\theta \mapsto -\theta$ and the elbows swapped.)
//!
//! Two exact symmetries pair the conventions (tested): $z$ down is $z$ up with motor 1 turned
//! by 180°, and, as the start point has $x = 0$, the mirror $x \mapsto -x$ maps each convention
//! to another (for the canonical order: $\alpha, \beta \mapsto -\alpha, -\beta$ with the
//! numbering reversed). The search keeps both, as the spec lists them, so its best fit comes
//! fourfold.

use nalgebra::{Rotation3, Vector3};
use pkm_mechanisms::ElbowMode;
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};
use std::fmt;

/// §3.5: radial distance of each motor from the centreline (m).
const BASE_RADIUS: f64 = 0.194;
/// §3.5: radial displacement of the plate's joint-pair mid-point (m).
const PLATE_OFFSET: f64 = 0.03;
/// §3.5: arm length $L_a$ (m).
const ARM: f64 = 0.26;
/// §3.5: forearm length $L_b$ (m).
const FOREARM: f64 = 0.48;
/// §2.1: NUWAR's motor turn $\beta$ (deg).
const BETA_DEG: f64 = 60.0;
/// Motor 1 at every 30°.
const AZIMUTH_STEPS: usize = 12;
/// Motors 120° apart: four azimuth steps.
const STEPS_PER_MOTOR: usize = 4;
/// Step of the $h$ scan (m).
const SCAN_STEP: f64 = 2e-3;
/// Scan minima of a larger rms error (deg) keep their scan value, unrefined.
const REFINE_BELOW_RMS_DEG: f64 = 1.0;
/// rms errors (deg) closer than this are ties.
const TIE_DEG: f64 = 1e-9;
/// Golden-section iterations: a 2 mm bracket shrinks below 1e-12 m.
const GOLDEN_ITERATIONS: usize = 60;
/// Bisections for the reach limit.
const EDGE_BISECTIONS: usize = 60;

/// Sign of a design angle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Sign {
    Plus,
    Minus,
}

impl Sign {
    const ALL: [Self; 2] = [Self::Plus, Self::Minus];

    fn apply(self, x: f64) -> f64 {
        match self {
            Self::Plus => x,
            Self::Minus => -x,
        }
    }
}

/// How the motor inclination $\alpha$ and turn $\beta$ compose into the local frame $G$.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum FrameOrder {
    /// $G = R_z(\beta) R_x(\alpha)$ (spec §1, canonical): the axis inclination is $\alpha$.
    TurnThenTilt,
    /// $G = R_x(\alpha) R_z(\beta)$: tilt about the fixed radial axis, inclination
    /// $\arcsin(\sin\alpha\cos\beta)$.
    RadialTiltOfTurned,
    /// $G = R_y(\alpha) R_z(\beta)$: tilt about the fixed tangent axis, inclination
    /// $\arcsin(\sin\alpha\sin\beta)$.
    TangentTiltOfTurned,
}

impl FrameOrder {
    const ALL: [Self; 3] = [
        Self::TurnThenTilt,
        Self::RadialTiltOfTurned,
        Self::TangentTiltOfTurned,
    ];

    fn local_frame(self, alpha: f64, beta: f64) -> Rotation3<f64> {
        let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), beta);
        match self {
            Self::TurnThenTilt => turn * Rotation3::from_axis_angle(&Vector3::x_axis(), alpha),
            Self::RadialTiltOfTurned => {
                Rotation3::from_axis_angle(&Vector3::x_axis(), alpha) * turn
            }
            Self::TangentTiltOfTurned => {
                Rotation3::from_axis_angle(&Vector3::y_axis(), alpha) * turn
            }
        }
    }
}

/// Which value of $\alpha$.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum AlphaValue {
    /// $\arctan(1/\sqrt 2) = 35.2644°$: orthogonal axes (spec §1).
    Exact,
    /// The printed 35.26°.
    Printed,
}

impl AlphaValue {
    const ALL: [Self; 2] = [Self::Exact, Self::Printed];

    fn radians(self) -> f64 {
        match self {
            Self::Exact => (1.0 / 2f64.sqrt()).atan(),
            Self::Printed => 35.26f64.to_radians(),
        }
    }
}

/// Direction of the plate offset $c_i$ (length $r$).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PlateOffset {
    /// $c_i = r(\cos\varphi_i, \sin\varphi_i, 0)$ (canonical).
    Radial,
    /// $c_i = r(\cos(\varphi_i + \beta), \sin(\varphi_i + \beta), 0)$.
    TurnedWithBeta,
    /// $c_i = 0$.
    Absent,
}

impl PlateOffset {
    const ALL: [Self; 3] = [Self::Radial, Self::TurnedWithBeta, Self::Absent];

    fn vector(self, phi: f64, beta: f64) -> Vector3<f64> {
        let along = |angle: f64| Vector3::new(angle.cos(), angle.sin(), 0.0) * PLATE_OFFSET;
        match self {
            Self::Radial => along(phi),
            Self::TurnedWithBeta => along(phi + beta),
            Self::Absent => Vector3::zeros(),
        }
    }
}

/// Direction of the task frame's $z$ axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Vertical {
    /// The task frame is the robot frame (canonical).
    Up,
    /// The task frame is the robot frame turned 180° about $x$: $(x, y, z) \mapsto (x, -y, -z)$.
    Down,
}

impl Vertical {
    const ALL: [Self; 2] = [Self::Up, Self::Down];

    /// A task-frame point in the robot's $z$-up frame.
    fn to_robot(self, p: &Vector3<f64>) -> Vector3<f64> {
        match self {
            Self::Up => *p,
            Self::Down => Vector3::new(p.x, -p.y, -p.z),
        }
    }

    /// A robot-frame height in the task frame (and back: the map is an involution).
    fn height(self, z: f64) -> f64 {
        match self {
            Self::Up => z,
            Self::Down => -z,
        }
    }
}

/// Direction in which the motors are numbered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Numbering {
    /// $\varphi_i = \varphi_1 + i \cdot 120°$ (canonical).
    CounterClockwise,
    /// $\varphi_i = \varphi_1 - i \cdot 120°$.
    Clockwise,
}

impl Numbering {
    const ALL: [Self; 2] = [Self::CounterClockwise, Self::Clockwise];

    /// Azimuth step (of 30°) of motor `leg` when motor 1 is at step `motor_1`.
    fn step(self, motor_1: usize, leg: usize) -> usize {
        let turn = STEPS_PER_MOTOR * leg;
        match self {
            Self::CounterClockwise => (motor_1 + turn) % AZIMUTH_STEPS,
            Self::Clockwise => (motor_1 + AZIMUTH_STEPS * 3 - turn) % AZIMUTH_STEPS,
        }
    }
}

/// How the printed angle is read from the model's $\theta$ (from the horizontal, positive down).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Reading {
    /// $\theta$ (canonical).
    DownFromHorizontal,
    /// $-\theta$.
    UpFromHorizontal,
    /// $90° - \theta$: from the downward vertical, positive outward.
    OutFromVertical,
    /// $\theta - 90°$.
    InFromVertical,
}

impl Reading {
    const ALL: [Self; 4] = [
        Self::DownFromHorizontal,
        Self::UpFromHorizontal,
        Self::OutFromVertical,
        Self::InFromVertical,
    ];

    fn apply(self, theta: f64) -> f64 {
        use std::f64::consts::FRAC_PI_2;
        match self {
            Self::DownFromHorizontal => theta,
            Self::UpFromHorizontal => -theta,
            Self::OutFromVertical => FRAC_PI_2 - theta,
            Self::InFromVertical => theta - FRAC_PI_2,
        }
    }
}

/// What the fit adjusts besides the discrete convention.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Unknowns {
    /// The motor-plane height $z_0$ only.
    Height,
    /// $z_0$ and a common zero $\delta$ of the three angles (one of the spec's two-unknown
    /// fits): the residuals are the errors less their mean.
    HeightAndZero,
}

impl Unknowns {
    /// The readings that differ: with a free zero, $\theta - 90°$ is $\theta$ and $90° - \theta$
    /// is $-\theta$.
    fn readings(self) -> &'static [Reading] {
        match self {
            Self::Height => &Reading::ALL,
            Self::HeightAndZero => &Reading::ALL[..2],
        }
    }

    /// The residuals left by the fit of the free zero to the angle errors `e` (rad, each in
    /// $[-\pi, \pi]$); NaN when an error is.
    fn residuals(self, e: [f64; 3]) -> [f64; 3] {
        match self {
            Self::Height => e,
            Self::HeightAndZero => {
                // Errors relative to the first, by the shorter way round, less their mean.
                let d = [0.0, wrapped_once(e[1] - e[0]), wrapped_once(e[2] - e[0])];
                let mean = (d[1] + d[2]) / 3.0;
                d.map(|x| x - mean)
            }
        }
    }

    /// Sum of the squared residuals (rad²).
    fn residual(self, e: [f64; 3]) -> f64 {
        self.residuals(e).iter().map(|r| r * r).sum()
    }
}

/// The choices shared by the three legs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Geometry {
    pub(super) order: FrameOrder,
    pub(super) alpha: AlphaValue,
    pub(super) alpha_sign: Sign,
    pub(super) beta_sign: Sign,
    pub(super) offset: PlateOffset,
    pub(super) vertical: Vertical,
}

impl Geometry {
    /// All 144 combinations, in a fixed order.
    fn all() -> Vec<Self> {
        let mut out = Vec::new();
        for order in FrameOrder::ALL {
            for alpha in AlphaValue::ALL {
                for alpha_sign in Sign::ALL {
                    for beta_sign in Sign::ALL {
                        for offset in PlateOffset::ALL {
                            for vertical in Vertical::ALL {
                                out.push(Self {
                                    order,
                                    alpha,
                                    alpha_sign,
                                    beta_sign,
                                    offset,
                                    vertical,
                                });
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// $\alpha$ and $\beta$ with their signs (rad).
    fn angles(&self) -> (f64, f64) {
        (
            self.alpha_sign.apply(self.alpha.radians()),
            self.beta_sign.apply(BETA_DEG.to_radians()),
        )
    }
}

/// One discrete convention.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Convention {
    pub(super) geometry: Geometry,
    pub(super) numbering: Numbering,
    /// Motor 1 at $30° \cdot$ `motor_1_step`.
    pub(super) motor_1_step: usize,
    pub(super) elbows: [ElbowMode; 3],
    pub(super) reading: Reading,
}

impl Convention {
    /// The spec's canonical convention (`Placement::canonical()` azimuth 300°, elbow out).
    pub(super) fn canonical(alpha: AlphaValue) -> Self {
        Self {
            geometry: Geometry {
                order: FrameOrder::TurnThenTilt,
                alpha,
                alpha_sign: Sign::Plus,
                beta_sign: Sign::Plus,
                offset: PlateOffset::Radial,
                vertical: Vertical::Up,
            },
            numbering: Numbering::CounterClockwise,
            motor_1_step: 10,
            elbows: [ElbowMode::Out; 3],
            reading: Reading::DownFromHorizontal,
        }
    }

    fn legs(&self, p_task: &Vector3<f64>) -> [LegGeometry; 3] {
        let p = self.geometry.vertical.to_robot(p_task);
        std::array::from_fn(|i| {
            let step = self.numbering.step(self.motor_1_step, i);
            LegGeometry::new(&self.geometry, step, &p)
        })
    }

    /// The model's $\theta_i$ (from the horizontal, positive down; rad) with the plate at task
    /// point `p` and the motor plane at task height `z0`; `None` when a leg cannot reach.
    pub(super) fn joint_angles(&self, p: &Vector3<f64>, z0: f64) -> Option<Vector3<f64>> {
        let h = self.geometry.vertical.height(z0) - self.geometry.vertical.to_robot(p).z;
        let legs = self.legs(p);
        let mut theta = Vector3::zeros();
        for (i, leg) in legs.iter().enumerate() {
            theta[i] = leg.theta(h, self.elbows[i])?;
        }
        Some(theta)
    }

    /// The angles as this convention prints them (deg).
    pub(super) fn printed_angles(&self, p: &Vector3<f64>, z0: f64) -> Option<Vector3<f64>> {
        self.joint_angles(p, z0)
            .map(|theta| theta.map(|t| self.reading.apply(t).to_degrees()))
    }
}

impl fmt::Display for Convention {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let g = &self.geometry;
        let sign = |s: Sign| match s {
            Sign::Plus => "+",
            Sign::Minus => "-",
        };
        let elbow = |e: ElbowMode| match e {
            ElbowMode::Out => "out",
            ElbowMode::In => "in",
        };
        write!(
            f,
            "{:?}, alpha {}{:?}, beta {}60, offset {:?}, z {:?}, {:?} from motor 1 at {} deg, \
             elbows {}/{}/{}, theta read {:?}",
            g.order,
            sign(g.alpha_sign),
            g.alpha,
            sign(g.beta_sign),
            g.offset,
            g.vertical,
            self.numbering,
            30 * self.motor_1_step,
            elbow(self.elbows[0]),
            elbow(self.elbows[1]),
            elbow(self.elbows[2]),
            self.reading,
        )
    }
}

/// One leg in the robot frame, as a function of the motor-plane height $h$ above the plate:
/// $D = C_i - A_i = (d_x, d_y, -h)$.
#[derive(Debug, Clone, Copy)]
struct LegGeometry {
    dx: f64,
    dy: f64,
    u: Vector3<f64>,
    w: Vector3<f64>,
}

impl LegGeometry {
    fn new(geometry: &Geometry, step: usize, p: &Vector3<f64>) -> Self {
        let (alpha, beta) = geometry.angles();
        let phi = (30.0 * step as f64).to_radians();
        let frame = Rotation3::from_axis_angle(&Vector3::z_axis(), phi)
            * geometry.order.local_frame(alpha, beta);
        let c = geometry.offset.vector(phi, beta);
        Self {
            dx: p.x + c.x - BASE_RADIUS * phi.cos(),
            dy: p.y + c.y - BASE_RADIUS * phi.sin(),
            u: frame * Vector3::x(),
            w: frame * Vector3::z(),
        }
    }

    /// $(\psi, \gamma) = (\operatorname{atan2}(b, a), \arccos(K/\sqrt{a^2+b^2}))$, `None` when
    /// the leg cannot reach ($|K| > \sqrt{a^2+b^2}$).
    fn arm_angles(&self, h: f64) -> Option<(f64, f64)> {
        let d = Vector3::new(self.dx, self.dy, -h);
        let k = (d.norm_squared() + ARM * ARM - FOREARM * FOREARM) / (2.0 * ARM);
        let (a, b) = (d.dot(&self.u), -d.dot(&self.w));
        let ratio = k / a.hypot(b);
        (ratio.abs() <= 1.0).then(|| (b.atan2(a), ratio.acos()))
    }

    fn theta(&self, h: f64, elbow: ElbowMode) -> Option<f64> {
        self.arm_angles(h)
            .map(|(psi, gamma)| branch(psi, gamma, elbow))
    }
}

fn branch(psi: f64, gamma: f64, elbow: ElbowMode) -> f64 {
    match elbow {
        ElbowMode::Out => psi - gamma,
        ElbowMode::In => psi + gamma,
    }
}

/// A difference of two angles of $[-\pi, \pi]$ brought into $[-\pi, \pi]$.
fn wrapped_once(x: f64) -> f64 {
    if x > PI {
        x - TAU
    } else if x < -PI {
        x + TAU
    } else {
        x
    }
}

/// An angle difference brought into $[-\pi, \pi]$ (by whole turns: the differences here lie
/// within a few turns, so this is cheaper than a division and a rounding).
fn wrapped(mut x: f64) -> f64 {
    while x > PI {
        x -= TAU;
    }
    while x < -PI {
        x += TAU;
    }
    x
}

/// The least-squares fit of one convention.
#[derive(Debug, Clone, Copy)]
pub(super) struct Fit {
    pub(super) convention: Convention,
    /// Fitted motor-plane height in the task frame (m); NaN when no height reaches the point.
    pub(super) motor_plane_z: f64,
    /// rms of the three angle errors at the fit (deg); infinite when no height reaches.
    pub(super) rms_deg: f64,
    /// Largest of the three angle errors at the fit (deg).
    pub(super) max_deg: f64,
}

/// Every convention's fit, in the fixed enumeration order.
#[derive(Debug, Clone)]
pub(super) struct Search {
    pub(super) fits: Vec<Fit>,
}

impl Search {
    /// The fit of least rms error; of fits within `TIE_DEG` of it (exact twins such as
    /// [`Vertical::Down`] and motor 1 turned by 180°), the first in enumeration order.
    pub(super) fn best(&self) -> Option<&Fit> {
        let least = self
            .fits
            .iter()
            .map(|f| f.rms_deg)
            .fold(f64::INFINITY, f64::min);
        self.fits.iter().find(|f| f.rms_deg <= least + TIE_DEG)
    }

    /// How many conventions fit with an rms error of at most `rms_deg`.
    pub(super) fn count_within(&self, rms_deg: f64) -> usize {
        self.fits.iter().filter(|f| f.rms_deg <= rms_deg).count()
    }

    /// How many conventions' fits have all three errors at most `max_deg`.
    pub(super) fn count_all_within(&self, max_deg: f64) -> usize {
        self.fits.iter().filter(|f| f.max_deg <= max_deg).count()
    }
}

/// Fits the `unknowns` for every convention to the angles `printed_deg` at task point `p`
/// (with a free zero, only the readings that differ: [`Unknowns::readings`]).
///
/// Parallel over the 144 geometries, each handled serially and collected in order, so the
/// result does not depend on the number of threads.
pub(super) fn search(printed_deg: [f64; 3], p: &Vector3<f64>, unknowns: Unknowns) -> Search {
    let printed = printed_deg.map(f64::to_radians);
    let fits = Geometry::all()
        .into_par_iter()
        .map(|geometry| search_geometry(geometry, printed, p, unknowns))
        .collect::<Vec<_>>()
        .into_iter()
        .flatten()
        .collect();
    Search { fits }
}

/// The scan heights $h_k = k \cdot$ `SCAN_STEP` up to $L_a + L_b$.
fn scan_heights() -> Vec<f64> {
    let n = ((ARM + FOREARM) / SCAN_STEP).round() as usize;
    (0..=n).map(|k| SCAN_STEP * k as f64).collect()
}

/// Errors (rad, in $[-\pi, \pi]$; NaN when unreachable) of one leg's reading over the scan,
/// for every reading, printed angle, elbow and azimuth step:
/// `table[index(reading, angle, elbow, step)][k]`.
struct ScanTable {
    len: usize,
    errors: Vec<f64>,
}

impl ScanTable {
    fn index(reading: usize, angle: usize, elbow: usize, step: usize) -> usize {
        ((reading * 3 + angle) * 2 + elbow) * AZIMUTH_STEPS + step
    }

    fn new(legs: &[LegGeometry; AZIMUTH_STEPS], heights: &[f64], printed: [f64; 3]) -> Self {
        let len = heights.len();
        let mut errors = vec![f64::NAN; Reading::ALL.len() * 3 * 2 * AZIMUTH_STEPS * len];
        for (step, leg) in legs.iter().enumerate() {
            for (k, &h) in heights.iter().enumerate() {
                let Some((psi, gamma)) = leg.arm_angles(h) else {
                    continue;
                };
                for (e, elbow) in [ElbowMode::Out, ElbowMode::In].into_iter().enumerate() {
                    let theta = branch(psi, gamma, elbow);
                    for (r, reading) in Reading::ALL.into_iter().enumerate() {
                        let read = reading.apply(theta);
                        for (a, &target) in printed.iter().enumerate() {
                            errors[Self::index(r, a, e, step) * len + k] = wrapped(read - target);
                        }
                    }
                }
            }
        }
        Self { len, errors }
    }

    fn row(&self, reading: usize, angle: usize, elbow: usize, step: usize) -> &[f64] {
        let start = Self::index(reading, angle, elbow, step) * self.len;
        &self.errors[start..start + self.len]
    }
}

/// Sum of the squared residuals (rad²) of `convention`, whose legs are `legs`, at height `h`
/// of the motor plane above the plate; infinite when a leg cannot reach.
fn residual_at(
    legs: &[LegGeometry; 3],
    convention: &Convention,
    printed: [f64; 3],
    h: f64,
    unknowns: Unknowns,
) -> f64 {
    let mut errors = [0.0; 3];
    for (i, leg) in legs.iter().enumerate() {
        let Some(theta) = leg.theta(h, convention.elbows[i]) else {
            return f64::INFINITY;
        };
        errors[i] = wrapped(convention.reading.apply(theta) - printed[i]);
    }
    unknowns.residual(errors)
}

/// The least-squares fit of $z_0$ for one `convention`, every scan minimum refined.
pub(super) fn fit_convention(
    convention: &Convention,
    printed_deg: [f64; 3],
    p: &Vector3<f64>,
) -> Fit {
    let printed = printed_deg.map(f64::to_radians);
    let legs = convention.legs(p);
    let objective = |h| residual_at(&legs, convention, printed, h, Unknowns::Height);
    let heights = scan_heights();
    let sums: Vec<f64> = heights.iter().map(|&h| objective(h)).collect();
    let (h, sum) = minimise_over_scan(&heights, &sums, objective, f64::INFINITY);
    fit(*convention, h, sum, p, printed, Unknowns::Height)
}

/// [`REFINE_BELOW_RMS_DEG`] as a sum of three squared errors (rad²).
fn refine_below() -> f64 {
    3.0 * REFINE_BELOW_RMS_DEG.to_radians().powi(2)
}

/// The 768 conventions of one geometry (384 with a free zero).
fn search_geometry(
    geometry: Geometry,
    printed: [f64; 3],
    p_task: &Vector3<f64>,
    unknowns: Unknowns,
) -> Vec<Fit> {
    let p = geometry.vertical.to_robot(p_task);
    let legs: [LegGeometry; AZIMUTH_STEPS] =
        std::array::from_fn(|step| LegGeometry::new(&geometry, step, &p));
    let heights = scan_heights();
    let table = ScanTable::new(&legs, &heights, printed);
    let mut sums = vec![0.0; heights.len()];
    let elbow_of = |bits: usize, leg: usize| {
        if bits >> leg & 1 == 0 {
            (0, ElbowMode::Out)
        } else {
            (1, ElbowMode::In)
        }
    };
    let mut fits = Vec::with_capacity(2 * AZIMUTH_STEPS * 8 * Reading::ALL.len());
    for numbering in Numbering::ALL {
        for motor_1_step in 0..AZIMUTH_STEPS {
            let steps: [usize; 3] = std::array::from_fn(|i| numbering.step(motor_1_step, i));
            for bits in 0..8 {
                let elbows = std::array::from_fn(|i| elbow_of(bits, i));
                for (r, &reading) in unknowns.readings().iter().enumerate() {
                    let rows: [&[f64]; 3] =
                        std::array::from_fn(|i| table.row(r, i, elbows[i].0, steps[i]));
                    let convention = Convention {
                        geometry,
                        numbering,
                        motor_1_step,
                        elbows: elbows.map(|e| e.1),
                        reading,
                    };
                    let three = steps.map(|step| legs[step]);
                    let objective = |h| residual_at(&three, &convention, printed, h, unknowns);
                    let (h, sum) = least_over_scan(rows, &heights, &mut sums, objective, unknowns);
                    fits.push(fit(convention, h, sum, p_task, printed, unknowns));
                }
            }
        }
    }
    fits
}

/// The least sum of squared residuals of one convention whose scan combines the three legs'
/// error `rows`: refined near the scan's minima when it is below [`REFINE_BELOW_RMS_DEG`], the scan's least
/// value otherwise. `sums` is a work buffer of the scan's length.
fn least_over_scan(
    rows: [&[f64]; 3],
    heights: &[f64],
    sums: &mut [f64],
    objective: impl Fn(f64) -> f64,
    unknowns: Unknowns,
) -> (f64, f64) {
    let scan = rows[0]
        .iter()
        .zip(rows[1])
        .zip(rows[2])
        .map(|((&a, &b), &c)| {
            let sum = unknowns.residual([a, b, c]);
            if sum.is_nan() { f64::INFINITY } else { sum }
        });
    let least = scan.clone().fold(f64::INFINITY, f64::min);
    let refine_below = refine_below();
    if least <= refine_below {
        for (s, value) in sums.iter_mut().zip(scan) {
            *s = value;
        }
        minimise_over_scan(heights, sums, objective, refine_below)
    } else {
        let k = scan.clone().position(|s| s <= least).unwrap_or(0);
        (heights[k], least)
    }
}

/// The fit record of `convention` at height `h` above the task point `p` with sum of squared
/// residuals `sum` (rad²).
fn fit(
    convention: Convention,
    h: f64,
    sum: f64,
    p: &Vector3<f64>,
    printed: [f64; 3],
    unknowns: Unknowns,
) -> Fit {
    let vertical = convention.geometry.vertical;
    let motor_plane_z = vertical.height(vertical.to_robot(p).z + h);
    let max_deg = convention
        .printed_angles(p, motor_plane_z)
        .map_or(f64::INFINITY, |read| {
            let errors = std::array::from_fn(|i| wrapped(read[i].to_radians() - printed[i]));
            unknowns
                .residuals(errors)
                .iter()
                .fold(0.0, |m, r| f64::max(m, r.abs()))
                .to_degrees()
        });
    Fit {
        convention,
        motor_plane_z: if sum.is_finite() {
            motor_plane_z
        } else {
            f64::NAN
        },
        rms_deg: (sum / 3.0).sqrt().to_degrees(),
        max_deg,
    }
}

/// The least value of `objective` near the scan's local minima: each minimum $k$ below
/// `refine_below` is refined over $[h_{k-1}, h_{k+1}]$ (cut at the reach limit). Returns `(h, objective(h))`, infinite
/// when no scan height is reachable.
fn minimise_over_scan(
    heights: &[f64],
    sums: &[f64],
    objective: impl Fn(f64) -> f64,
    refine_below: f64,
) -> (f64, f64) {
    let n = sums.len();
    let mut best = (f64::NAN, f64::INFINITY);
    for k in 0..n {
        let here = sums[k];
        let left_higher = k == 0 || here <= sums[k - 1];
        let right_higher = k + 1 == n || here < sums[k + 1];
        if !(here.is_finite() && left_higher && right_higher) {
            continue;
        }
        if !(here <= refine_below) {
            if here < best.1 {
                best = (heights[k], here);
            }
            continue;
        }
        let lo = reachable_end(heights[k.saturating_sub(1)], heights[k], &objective);
        let hi = reachable_end(heights[(k + 1).min(n - 1)], heights[k], &objective);
        let h = golden_section(lo, hi, &objective);
        for (x, f) in [(h, objective(h)), (heights[k], here)] {
            if f < best.1 {
                best = (x, f);
            }
        }
    }
    best
}

/// `end` if the objective is finite there, otherwise the reach limit between `end` and the
/// reachable `inner`, by bisection (its reachable side).
fn reachable_end(end: f64, inner: f64, objective: &impl Fn(f64) -> f64) -> f64 {
    if objective(end).is_finite() {
        return end;
    }
    let (mut bad, mut good) = (end, inner);
    for _ in 0..EDGE_BISECTIONS {
        let mid = 0.5 * (bad + good);
        if objective(mid).is_finite() {
            good = mid;
        } else {
            bad = mid;
        }
    }
    good
}

/// Golden-section search for a minimum of `objective` on `[lo, hi]`.
fn golden_section(mut lo: f64, mut hi: f64, objective: &impl Fn(f64) -> f64) -> f64 {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let mut a = hi - ratio * (hi - lo);
    let mut b = lo + ratio * (hi - lo);
    let (mut fa, mut fb) = (objective(a), objective(b));
    for _ in 0..GOLDEN_ITERATIONS {
        if fa < fb {
            hi = b;
            (b, fb) = (a, fa);
            a = hi - ratio * (hi - lo);
            fa = objective(a);
        } else {
            lo = a;
            (a, fa) = (b, fb);
            b = lo + ratio * (hi - lo);
            fb = objective(b);
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]

    use super::*;
    use pkm_mechanisms::{Placement, RotaryDelta, presets};
    use pkm_traits::InverseKinematics;

    fn start() -> Vector3<f64> {
        Vector3::new(0.0, -0.2, -0.9)
    }

    #[test]
    fn canonical_convention_equals_rotary_delta() {
        let mut checked = 0;
        for z0 in [-0.35, -0.2928, -0.25] {
            for azimuth_step in [0, 3, 10] {
                let placement = Placement {
                    motor_plane_z: z0,
                    azimuth_motor_1: (30.0 * azimuth_step as f64).to_radians(),
                };
                let nuwar = RotaryDelta::new(presets::nuwar(placement)).unwrap();
                let convention = Convention {
                    motor_1_step: azimuth_step,
                    ..Convention::canonical(AlphaValue::Printed)
                };
                for p in [start(), Vector3::new(0.1, 0.05, -0.7)] {
                    let ours = convention.joint_angles(&p, z0);
                    let Ok(library) = nuwar.inverse_kinematics(&p, ElbowMode::Out) else {
                        assert!(ours.is_none(), "reachable for us only: {p} {z0}");
                        continue;
                    };
                    let ours = ours.unwrap();
                    assert!((library - ours).amax() < 1e-12, "{library} vs {ours}");
                    checked += 1;
                }
            }
        }
        assert!(checked >= 10, "only {checked} poses reachable");
    }

    #[test]
    fn frame_orders_give_the_spec_inclinations() {
        let (alpha, beta) = (0.4, 1.0);
        let inclination = |order: FrameOrder| (order.local_frame(alpha, beta) * Vector3::y()).z;
        let expected = [
            alpha.sin(),
            alpha.sin() * beta.cos(),
            alpha.sin() * beta.sin(),
        ];
        for (order, sine) in FrameOrder::ALL.into_iter().zip(expected) {
            assert!((inclination(order) - sine).abs() < 1e-15, "{order:?}");
        }
    }

    /// $z$ down is $z$ up with the point's $y$ mirrored, i.e. motor 1 turned by 180°, at the
    /// same height of the motor plane above the plate.
    #[test]
    fn z_down_is_z_up_turned_half_a_revolution() {
        let mut checked = 0;
        for geometry in Geometry::all()
            .into_iter()
            .filter(|g| g.vertical == Vertical::Up)
        {
            let up = Convention {
                geometry,
                numbering: Numbering::Clockwise,
                motor_1_step: 2,
                elbows: [ElbowMode::Out, ElbowMode::In, ElbowMode::Out],
                reading: Reading::OutFromVertical,
            };
            let down = Convention {
                geometry: Geometry {
                    vertical: Vertical::Down,
                    ..geometry
                },
                motor_1_step: 8,
                ..up
            };
            let h = 0.62;
            let (Some(a), Some(b)) = (
                up.printed_angles(&start(), start().z + h),
                down.printed_angles(&start(), start().z - h),
            ) else {
                continue;
            };
            assert!((a - b).amax() < 1e-9, "{geometry:?}: {a} vs {b}");
            checked += 1;
        }
        assert!(checked >= 10, "only {checked} geometries reached");
    }

    /// The start point has $x = 0$: the mirror $x \mapsto -x$ (motor 1 at $180° - \varphi_1$,
    /// numbering reversed) flips $\beta$, and $\alpha$ unless the tilt is about the tangent.
    #[test]
    fn mirror_image_conventions_print_the_same_angles() {
        let flip = |s: Sign| match s {
            Sign::Plus => Sign::Minus,
            Sign::Minus => Sign::Plus,
        };
        let mut checked = 0;
        for geometry in Geometry::all() {
            let left = Convention {
                geometry,
                numbering: Numbering::CounterClockwise,
                motor_1_step: 2,
                elbows: [ElbowMode::In, ElbowMode::Out, ElbowMode::Out],
                reading: Reading::DownFromHorizontal,
            };
            let right = Convention {
                geometry: Geometry {
                    alpha_sign: match geometry.order {
                        FrameOrder::TangentTiltOfTurned => geometry.alpha_sign,
                        _ => flip(geometry.alpha_sign),
                    },
                    beta_sign: flip(geometry.beta_sign),
                    ..geometry
                },
                numbering: Numbering::Clockwise,
                motor_1_step: 4,
                ..left
            };
            // The motor plane 0.6 m above the plate, in the task frame.
            let z0 = match geometry.vertical {
                Vertical::Up => -0.3,
                Vertical::Down => -1.5,
            };
            let (Some(a), Some(b)) = (
                left.printed_angles(&start(), z0),
                right.printed_angles(&start(), z0),
            ) else {
                continue;
            };
            assert!((a - b).amax() < 1e-9, "{geometry:?}: {a} vs {b}");
            checked += 1;
        }
        assert!(checked >= 40, "only {checked} geometries reached");
    }

    #[test]
    fn a_single_fit_is_a_least_squares_minimum() {
        let printed = [70.95, 87.13, 51.65];
        let convention = Convention::canonical(AlphaValue::Exact);
        let fit = fit_convention(&convention, printed, &start());
        let rms_at = |z0: f64| {
            convention
                .printed_angles(&start(), z0)
                .map_or(f64::INFINITY, |a| {
                    ((a - Vector3::from(printed)).norm_squared() / 3.0).sqrt()
                })
        };
        assert!(
            (rms_at(fit.motor_plane_z) - fit.rms_deg).abs() < 1e-12,
            "{fit:?}"
        );
        for dz in [1e-5, -1e-5, 1e-2, -1e-2, 0.1, -0.1] {
            assert!(rms_at(fit.motor_plane_z + dz) > fit.rms_deg, "{dz}");
        }
    }

    #[test]
    fn search_is_identical_for_any_number_of_threads() {
        let printed = [70.95, 87.13, 51.65];
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| search(printed, &start(), Unknowns::Height))
        };
        let (one, three) = (run(1), run(3));
        assert_eq!(one.fits.len(), three.fits.len());
        for (a, b) in one.fits.iter().zip(&three.fits) {
            assert_eq!(a.convention, b.convention);
            assert_eq!(a.rms_deg.to_bits(), b.rms_deg.to_bits(), "{a:?}");
            assert_eq!(
                a.motor_plane_z.to_bits(),
                b.motor_plane_z.to_bits(),
                "{a:?}"
            );
        }
    }

    #[test]
    fn search_recovers_a_planted_convention() {
        let planted = Convention {
            geometry: Geometry {
                order: FrameOrder::RadialTiltOfTurned,
                alpha: AlphaValue::Exact,
                alpha_sign: Sign::Plus,
                beta_sign: Sign::Minus,
                offset: PlateOffset::TurnedWithBeta,
                vertical: Vertical::Up,
            },
            numbering: Numbering::Clockwise,
            motor_1_step: 5,
            elbows: [ElbowMode::Out, ElbowMode::In, ElbowMode::Out],
            reading: Reading::DownFromHorizontal,
        };
        let (z0, angles) = [-0.3137, -0.4137, -0.2137, -0.5137]
            .into_iter()
            .find_map(|z0| Some((z0, planted.printed_angles(&start(), z0)?)))
            .unwrap();
        let found = search(
            [angles[0], angles[1], angles[2]],
            &start(),
            Unknowns::Height,
        );
        assert_eq!(found.fits.len(), 110_592);
        let best = found.best().unwrap();
        assert!(best.rms_deg < 1e-9, "{best:?}");
        let own = found.fits.iter().find(|f| f.convention == planted).unwrap();
        assert!(own.rms_deg < 1e-9 && own.max_deg < 1e-9, "{own:?}");
        assert!((own.motor_plane_z - z0).abs() < 1e-9, "{own:?}");
        let alone = fit_convention(&planted, [angles[0], angles[1], angles[2]], &start());
        assert!(
            (alone.motor_plane_z - own.motor_plane_z).abs() < 1e-12,
            "{alone:?}"
        );
        // Exact fits: the planted convention, its z-down twin (motor 1 turned by 180°), its
        // mirror image and the mirror's twin.
        let exact: Vec<_> = found
            .fits
            .iter()
            .filter(|f| f.rms_deg <= 1e-9)
            .map(|f| f.convention.to_string())
            .collect();
        assert_eq!(exact.len(), 4, "{exact:#?}");

        // With a free zero the same convention is found under an offset of all three angles.
        let shifted = angles.map(|a| a + 7.3);
        let found = search(
            [shifted[0], shifted[1], shifted[2]],
            &start(),
            Unknowns::HeightAndZero,
        );
        assert_eq!(found.fits.len(), 110_592 / 2);
        let own = found.fits.iter().find(|f| f.convention == planted).unwrap();
        assert!(own.rms_deg < 1e-9 && own.max_deg < 1e-9, "{own:?}");
        assert!(found.best().unwrap().rms_deg < 1e-9);
    }
}
