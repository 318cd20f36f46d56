//! The forward kinematics of a robot file as a square polynomial system, for parameter
//! homotopy ([`pkm_homotopy`], issue 32): every assembly mode at given actuator coordinates,
//! with a statement of how each path ended.
//!
//! With its actuator known, every leg of a closed-form class places a platform point $c_i$
//! (platform frame) at a known distance $L_i$ from a known base point $B_i$: the base point of
//! a distance leg with $L_i$ its length, or an arm's elbow moved by its actuator with $L_i$ its
//! rod. With the platform pose $(R, t)$ each leg is the sphere condition (eq. K1)
//! $$\lvert R\,c_i + t - B_i\rvert^2 - L_i^2 = 0,$$
//! written in polynomial unknowns by the robot's free pose coordinates:
//! - **translational** (orientation constant, $R_0$): $z = t$; eq. K1 with $R_0 c_i$;
//! - **planar** (orientation about $z$ only, $r_x = r_y = 0$): $z = (t, u, v)$ with
//!   $R = R_z(u, v)$, $u^2 + v^2 = 1$;
//! - **spherical** (position constant, $t_0$): $z = e$, a quaternion, $R = \tilde R(e)/\Delta$
//!   with $\tilde R$ its homogeneous quadratic rotation and $\Delta = e\cdot e$: eq. K1 times
//!   $\Delta$, $(\lvert c\rvert^2 + \lvert d\rvert^2 - L^2)\,\Delta + 2\,(\tilde R c)\cdot d = 0$,
//!   $d = t_0 - B$; and a random linear gauge $a\cdot e = 1$ (one quaternion of each pair
//!   $\pm e$);
//! - **spatial**: Study's parameters $z = (e, g)$ on his quadric $e\cdot g = 0$, with
//!   $t = 2\operatorname{vec}(g\bar e)/\Delta$; eq. K1 times $\Delta$ is the quadric (Husty
//!   1996)
//!   $$\Delta\,(\lvert c\rvert^2 + \lvert B\rvert^2 - L^2) + 4\,g\cdot g + 4\,c\cdot
//!   \operatorname{vec}(\bar e g) - 2\,(\tilde R c)\cdot B - 4\,B\cdot\operatorname{vec}(g\bar e)
//!   = 0,$$
//!   with the random gauge $a\cdot(e, g) = 1$: for the general Stewart–Gough platform, 40
//!   solutions.
//!
//! A leg whose elbow is a single revolute joint normal to its rod (a PRS or RRS leg: the arm
//! leg's elbow point $B_i$, the joint's axis $a_i$ carried by the actuator) also keeps the
//! platform point in the plane through $B_i$ normal to $a_i$ (eq. K2)
//! $$a_i\cdot(R\,c_i + t - B_i) = 0,$$
//! times $\Delta$ in Study's form $a_i\cdot(\tilde R c_i + 2\operatorname{vec}(g\bar e)) -
//! (a_i\cdot B_i)\,\Delta = 0$, a quadric too; only the spatial form needs it (the planar and
//! spherical forms hold it already). The plane passes through the sphere's centre for every
//! parameter, so the generic member keeps the robot's structure: the 3-PRS has 16 generic
//! solutions (a plane with its own offset would give 40, with the robot on a special locus
//! where most paths end singular). With it the pose coordinates may be dependent (the 3-PRS's
//! x, y and torsion): all six are unknowns of the spatial form.
//!
//! A passive leg made of a universal joint at $O$ and a slide that carries the platform (the
//! Tricept's) keeps the platform's origin on the slide's line and the joint's angle (eq. K3,
//! [`line_leg`]): three more quadrics in Study's form.
//!
//! A constant position coordinate $k$ adds $t_k - t_{0k} = 0$ (times $\Delta$ in Study's
//! form). Every equation is quadratic in $z$ and in the parameters $(B_i, c_i, L_i^2, t_0)$,
//! so the central differences that give $F_z$ and $\partial_s F$ are exact to rounding. More
//! equations than unknowns (redundant actuation) are squared up by a random complex
//! combination of the leg equations, whose solutions include the robot's (each is checked on
//! its own closure). Robots with legs that hold the platform otherwise (a single R joint at
//! the base or the platform, as the Exechon's), other passive legs, several actuators in a leg,
//! numerical legs or other orientation patterns are not written here:
//! [`RobotModel::polynomial_form`] says why, and the multistart serves them.

use crate::chain::Joint;
use crate::closure::{Configuration, same_pose};
use crate::leg_ik::LegClass;
use crate::model::RobotModel;
use crate::pose::{CoordinateRole, OrientationKind};
use nalgebra::{DMatrix, DVector, Rotation3, UnitQuaternion, Vector3};
use pkm_homotopy::{C64, Endpoint, QuadraticFamily};
use pkm_traits::{InvalidInput, KinematicsError};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How the platform pose is written in polynomial unknowns (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum PoseForm {
    /// $z = t$, the orientation constant.
    Translational,
    /// $z = (t, u, v)$, $R = R_z(u, v)$.
    Planar,
    /// $z = e$, the position constant.
    Spherical,
    /// $z = (e, g)$, Study's parameters.
    Spatial,
}

impl PoseForm {
    fn unknowns(self) -> usize {
        match self {
            Self::Translational => 3,
            Self::Planar => 5,
            Self::Spherical => 4,
            Self::Spatial => 8,
        }
    }
}

/// A robot's family of forward-kinematics systems: its pose form, its legs and its constant
/// position coordinates. Parameters: per leg $B_i$ (3), $c_i$ (3, in the world orientation
/// for the translational form), $L_i^2$; then $t_0$ (3); then the normal $a_i$ (3) of each
/// leg with an elbow plane.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ForwardSystem {
    pub form: PoseForm,
    pub legs: usize,
    /// Position coordinates held constant.
    pub constant: Vec<usize>,
    /// Which legs have an elbow plane (eq. K2).
    pub planes: Vec<bool>,
    /// Passive line legs (eq. K3; spatial form).
    pub lines: usize,
    /// The random gauge (spherical and spatial forms) and the random squaring-up matrix of
    /// the leg equations (rows: leg equations kept; identity when square).
    gauge: Vec<C64>,
    squaring: DMatrix<C64>,
}

/// The architecture key of a cached start system.
pub(crate) type Architecture = (PoseForm, usize, Vec<usize>, Vec<bool>, usize);

/// `[x; y; z]` products of complex vectors (bilinear: no conjugation).
fn dot(a: &[C64; 3], b: &[C64; 3]) -> C64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The quaternion product $(a_0, \vec a)(b_0, \vec b)$.
fn multiply(a: &[C64; 4], b: &[C64; 4]) -> [C64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

fn conjugate(a: &[C64; 4]) -> [C64; 4] {
    [a[0], -a[1], -a[2], -a[3]]
}

/// $\tilde R(e)\,c = e\,c\,\bar e$ (vector part): the rotation times $\Delta$.
fn rotate(e: &[C64; 4], c: &[C64; 3]) -> [C64; 3] {
    let r = multiply(
        &multiply(e, &[C64::new(0.0, 0.0), c[0], c[1], c[2]]),
        &conjugate(e),
    );
    [r[1], r[2], r[3]]
}

fn vector_part(q: &[C64; 4]) -> [C64; 3] {
    [q[1], q[2], q[3]]
}

impl ForwardSystem {
    /// The family of `form` with `legs` legs and the constant positions `constant`; the gauge
    /// and squaring-up drawn from a ChaCha8 stream seeded by the architecture, so that one
    /// architecture always gives the same family.
    pub(crate) fn new(
        form: PoseForm,
        legs: usize,
        constant: Vec<usize>,
        planes: Vec<bool>,
        lines: usize,
    ) -> Option<Self> {
        let n = form.unknowns();
        let equations = legs + planes.iter().filter(|&&p| p).count() + 3 * lines;
        let fixed = match form {
            PoseForm::Translational => constant.len(),
            PoseForm::Planar => constant.len() + 1,
            PoseForm::Spherical => 1,
            PoseForm::Spatial => constant.len() + 2,
        };
        let kept = n.checked_sub(fixed).filter(|&k| k <= equations && k > 0)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed_of(form, legs, &constant, &planes, lines));
        let mut complex = || C64::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        let gauge = (0..n).map(|_| complex()).collect();
        let squaring = if kept == equations {
            DMatrix::identity(equations, equations)
        } else {
            DMatrix::from_fn(kept, equations, |_, _| complex())
        };
        Some(Self {
            form,
            legs,
            constant,
            planes,
            lines,
            gauge,
            squaring,
        })
    }

    /// Whether the leg equations are combined at random into fewer.
    pub(crate) fn squared_up(&self) -> bool {
        self.squaring.nrows() < self.squaring.ncols()
    }

    /// The number of parameters.
    pub(crate) fn parameters(&self) -> usize {
        self.lines_at() + LINE_PARAMETERS * self.lines
    }

    /// Where the passive line legs' parameters start.
    fn lines_at(&self) -> usize {
        7 * self.legs + 3 + 3 * self.planes.iter().filter(|&&p| p).count()
    }

    /// Where leg `i`'s plane normal starts among the parameters, if it has a plane.
    fn normal_at(&self, i: usize) -> Option<usize> {
        let before = self.planes[..i].iter().filter(|&&p| p).count();
        self.planes[i].then_some(7 * self.legs + 3 + 3 * before)
    }

    /// The leg equations at `z`, each leg's sphere (eq. K1) then its elbow plane (eq. K2)
    /// when it has one, times $\Delta$ where the form needs it.
    fn leg_equations(&self, z: &[C64], p: &[C64]) -> Vec<C64> {
        let mut equations = Vec::with_capacity(2 * self.legs);
        for i in 0..self.legs {
            equations.push(self.sphere(i, z, p));
            if let Some(k) = self.normal_at(i) {
                equations.push(self.plane(i, [p[k], p[k + 1], p[k + 2]], z, p));
            }
        }
        for j in 0..self.lines {
            let at = self.lines_at() + LINE_PARAMETERS * j;
            equations.extend(line_leg(z, &p[at..at + LINE_PARAMETERS]));
        }
        equations
    }

    /// Leg `i`'s elbow plane (eq. K2) $a\cdot(R\,c + t - B) = 0$ with the normal `a`, times
    /// $\Delta$ in the spherical and spatial forms (a quadric in Study's parameters).
    fn plane(&self, i: usize, a: [C64; 3], z: &[C64], p: &[C64]) -> C64 {
        let t0 = [p[7 * self.legs], p[7 * self.legs + 1], p[7 * self.legs + 2]];
        let q = &p[7 * i..7 * i + 7];
        let (b, c) = ([q[0], q[1], q[2]], [q[3], q[4], q[5]]);
        let offset = |v: [C64; 3], scale: C64| dot(&a, &v) - dot(&a, &b) * scale;
        let one = C64::new(1.0, 0.0);
        match self.form {
            PoseForm::Translational => offset([c[0] + z[0], c[1] + z[1], c[2] + z[2]], one),
            PoseForm::Planar => {
                let (u, v) = (z[3], z[4]);
                offset(
                    [
                        u * c[0] - v * c[1] + z[0],
                        v * c[0] + u * c[1] + z[1],
                        c[2] + z[2],
                    ],
                    one,
                )
            }
            PoseForm::Spherical => {
                let e = [z[0], z[1], z[2], z[3]];
                let delta = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
                let rc = rotate(&e, &c);
                offset(
                    [
                        rc[0] + t0[0] * delta,
                        rc[1] + t0[1] * delta,
                        rc[2] + t0[2] * delta,
                    ],
                    delta,
                )
            }
            PoseForm::Spatial => {
                let e = [z[0], z[1], z[2], z[3]];
                let g = [z[4], z[5], z[6], z[7]];
                let delta = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
                let (rc, ge) = (rotate(&e, &c), vector_part(&multiply(&g, &conjugate(&e))));
                offset(
                    [
                        rc[0] + ge[0] * 2.0,
                        rc[1] + ge[1] * 2.0,
                        rc[2] + ge[2] * 2.0,
                    ],
                    delta,
                )
            }
        }
    }

    /// Leg `i`'s sphere (eq. K1), times $\Delta$ where the form needs it.
    fn sphere(&self, i: usize, z: &[C64], p: &[C64]) -> C64 {
        let t0 = [p[7 * self.legs], p[7 * self.legs + 1], p[7 * self.legs + 2]];
        {
            {
                let q = &p[7 * i..7 * i + 7];
                let (b, c, l2) = ([q[0], q[1], q[2]], [q[3], q[4], q[5]], q[6]);
                match self.form {
                    PoseForm::Spatial => study_leg(z, &b, &c, l2),
                    PoseForm::Spherical => {
                        // (|c|² + |d|² − L²) Δ + 2 (R̃c)·d, d = t0 − B.
                        let e = [z[0], z[1], z[2], z[3]];
                        let delta = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
                        let d = [t0[0] - b[0], t0[1] - b[1], t0[2] - b[2]];
                        (dot(&c, &c) + dot(&d, &d) - l2) * delta + dot(&rotate(&e, &c), &d) * 2.0
                    }
                    PoseForm::Translational => {
                        let d = [c[0] + z[0] - b[0], c[1] + z[1] - b[1], c[2] + z[2] - b[2]];
                        dot(&d, &d) - l2
                    }
                    PoseForm::Planar => {
                        let (u, v) = (z[3], z[4]);
                        let d = [
                            u * c[0] - v * c[1] + z[0] - b[0],
                            v * c[0] + u * c[1] + z[1] - b[1],
                            c[2] + z[2] - b[2],
                        ];
                        dot(&d, &d) - l2
                    }
                }
            }
        }
    }

    /// $F(z; p)$: the squared-up leg equations, then the form's own.
    pub(crate) fn residual(&self, z: &[C64], p: &[C64]) -> Vec<C64> {
        let legs = DVector::from_vec(self.leg_equations(z, p));
        let mut f: Vec<C64> = (&self.squaring * legs).iter().copied().collect();
        let t0 = [p[7 * self.legs], p[7 * self.legs + 1], p[7 * self.legs + 2]];
        let one = C64::new(1.0, 0.0);
        match self.form {
            PoseForm::Translational => f.extend(self.constant.iter().map(|&k| z[k] - t0[k])),
            PoseForm::Planar => {
                f.extend(self.constant.iter().map(|&k| z[k] - t0[k]));
                f.push(z[3] * z[3] + z[4] * z[4] - one);
            }
            PoseForm::Spherical => {
                f.push(self.gauge.iter().zip(z).map(|(a, z)| a * z).sum::<C64>() - one);
            }
            PoseForm::Spatial => {
                let e = [z[0], z[1], z[2], z[3]];
                let g = [z[4], z[5], z[6], z[7]];
                let delta = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
                let t = vector_part(&multiply(&g, &conjugate(&e)));
                f.extend(self.constant.iter().map(|&k| t[k] * 2.0 - t0[k] * delta));
                f.push(e.iter().zip(&g).map(|(a, b)| a * b).sum());
                f.push(self.gauge.iter().zip(z).map(|(a, z)| a * z).sum::<C64>() - one);
            }
        }
        f
    }

    /// The real point of a solution `z`, if it has one: its coordinates when their imaginary
    /// parts are below `tolerance` of its size; for the homogeneous forms (spherical, spatial), whose
    /// complex gauge scales a real pose by a complex factor, after dividing by the largest
    /// quaternion coordinate.
    pub(crate) fn real(&self, z: &DVector<C64>, tolerance: f64) -> Option<Vec<f64>> {
        let scaled = match self.form {
            PoseForm::Spherical | PoseForm::Spatial => {
                let pivot = z
                    .rows(0, 4)
                    .iter()
                    .copied()
                    .max_by(|a, b| a.norm().total_cmp(&b.norm()))?;
                if !(pivot.norm() > 0.0) {
                    return None;
                }
                z.map(|c| c / pivot)
            }
            PoseForm::Translational | PoseForm::Planar => z.clone(),
        };
        let size = scaled.iter().map(|c| c.norm()).fold(1.0, f64::max);
        scaled
            .iter()
            .all(|c| c.im.abs() <= tolerance * size)
            .then(|| scaled.iter().map(|c| c.re).collect())
    }

    /// Whether a path of the spatial form that stalled at `s` near its end with unknowns `z`
    /// is heading for Study's exceptional generator $e = 0$ (no pose): its quaternion below
    /// $10\sqrt{1 - s}$ of the unknowns (it shrinks like $\sqrt{1 - s}$ on such a path; a pose's
    /// quaternion is of the order of the unknowns unless it is tens of metres away).
    pub(crate) fn exceptional(&self, z: &DVector<C64>, s: f64) -> bool {
        let size = |v: &[C64]| v.iter().map(|c| c.norm()).fold(0.0, f64::max);
        self.form == PoseForm::Spatial
            && s > 0.99
            && size(&z.as_slice()[..4]) < 10.0 * (1.0 - s).sqrt() * size(z.as_slice())
    }

    /// The pose $(R, t)$ of a real solution `z` (imaginary parts dropped by the caller's check).
    pub(crate) fn pose(&self, z: &[f64], p: &[f64]) -> Option<(Rotation3<f64>, Vector3<f64>)> {
        let t0 = Vector3::new(p[7 * self.legs], p[7 * self.legs + 1], p[7 * self.legs + 2]);
        let quaternion = |e: &[f64]| {
            let q = nalgebra::Quaternion::new(e[0], e[1], e[2], e[3]);
            (q.norm() > 1e-12).then(|| UnitQuaternion::from_quaternion(q))
        };
        match self.form {
            PoseForm::Translational => {
                Some((Rotation3::identity(), Vector3::new(z[0], z[1], z[2])))
            }
            PoseForm::Planar => Some((
                Rotation3::from_axis_angle(&Vector3::z_axis(), z[4].atan2(z[3])),
                Vector3::new(z[0], z[1], z[2]),
            )),
            PoseForm::Spherical => Some((quaternion(&z[..4])?.to_rotation_matrix(), t0)),
            PoseForm::Spatial => {
                let e = quaternion(&z[..4])?;
                let raw = nalgebra::Quaternion::new(z[0], z[1], z[2], z[3]);
                let g = nalgebra::Quaternion::new(z[4], z[5], z[6], z[7]);
                let t = (g * raw.conjugate()).imag() * (2.0 / raw.norm_squared());
                Some((e.to_rotation_matrix(), t))
            }
        }
    }
}

/// Eq. K1 times $\Delta$ in Study's parameters (module documentation).
fn study_leg(z: &[C64], b: &[C64; 3], c: &[C64; 3], l2: C64) -> C64 {
    let e = [z[0], z[1], z[2], z[3]];
    let g = [z[4], z[5], z[6], z[7]];
    let delta = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
    let gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2] + g[3] * g[3];
    let eg = vector_part(&multiply(&conjugate(&e), &g));
    let ge = vector_part(&multiply(&g, &conjugate(&e)));
    delta * (dot(c, c) + dot(b, b) - l2) + gg * 4.0 + dot(c, &eg) * 4.0
        - dot(&rotate(&e, c), b) * 2.0
        - dot(b, &ge) * 4.0
}

/// Parameters of a passive line leg: $O$, $a_1$, $a_2$ (platform frame), $u$, $w$ (platform
/// frame, normal to the slide), $u\cdot r_0$, $w\cdot r_0$, $k$.
const LINE_PARAMETERS: usize = 18;

/// A passive line leg (eq. K3): a universal joint at $O$ (axes $a_1$ fixed, $a_2$ carried)
/// then a passive slide, the platform on the slider: in the platform frame its origin stays on
/// the slide's line, $u\cdot(R^\top(t - O) - r_0) = w\cdot(R^\top(t - O) - r_0) = 0$, and
/// the joint keeps its angle, $a_1\cdot R a_2 = k$. With $R^\top(t - O)\Delta = 2\operatorname{vec}(\bar e g) -
/// \operatorname{vec}(\bar e O e)$ and $R a_2 \Delta = \operatorname{vec}(e a_2 \bar e)$, three
/// quadrics in Study's parameters.
fn line_leg(z: &[C64], q: &[C64]) -> [C64; 3] {
    let e = [z[0], z[1], z[2], z[3]];
    let g = [z[4], z[5], z[6], z[7]];
    let delta = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
    let v3 = |k: usize| [q[k], q[k + 1], q[k + 2]];
    let (o, a1, a2, u, w) = (v3(0), v3(3), v3(6), v3(9), v3(12));
    let (ur0, wr0, k) = (q[15], q[16], q[17]);
    let eg = vector_part(&multiply(&conjugate(&e), &g));
    let eoe = vector_part(&multiply(
        &multiply(&conjugate(&e), &[C64::new(0.0, 0.0), o[0], o[1], o[2]]),
        &e,
    ));
    let body = [
        eg[0] * 2.0 - eoe[0],
        eg[1] * 2.0 - eoe[1],
        eg[2] * 2.0 - eoe[2],
    ];
    [
        dot(&u, &body) - ur0 * delta,
        dot(&w, &body) - wr0 * delta,
        dot(&a1, &rotate(&e, &a2)) - k * delta,
    ]
}

/// Adds `c` to `configurations` unless one of them has its pose (1e-6).
fn push_new(kind: OrientationKind, configurations: &mut Vec<Configuration>, c: Configuration) {
    if !configurations.iter().any(|f| same_pose(kind, f, &c, 1e-6)) {
        configurations.push(c);
    }
}

/// A seed that depends on the architecture alone.
fn seed_of(form: PoseForm, legs: usize, constant: &[usize], planes: &[bool], lines: usize) -> u64 {
    let mut seed = 0x5eed_u64 ^ (form as u64) << 8 ^ (legs as u64) << 16;
    for &k in constant {
        seed ^= 1 << (24 + k);
    }
    for (i, _) in planes.iter().enumerate().filter(|(_, p)| **p) {
        seed ^= 1 << (32 + i % 32);
    }
    seed ^ (lines as u64) << 60
}

impl QuadraticFamily for ForwardSystem {
    fn unknowns(&self) -> usize {
        self.form.unknowns()
    }

    fn residual(&self, z: &[C64], p: &[C64], f: &mut [C64]) {
        for (slot, v) in f.iter_mut().zip(ForwardSystem::residual(self, z, p)) {
            *slot = v;
        }
    }
}

impl RobotModel {
    /// The polynomial family of this robot's forward kinematics, or why there is none.
    pub(crate) fn polynomial_form(&self) -> Result<ForwardSystem, &'static str> {
        if self.actuators.len() != self.actuated {
            return Err("a leg with several actuators");
        }
        let lines = self.legs.len() - self.actuated;
        if (self.actuated..self.legs.len()).any(|i| self.line_leg(i).is_none()) {
            return Err(
                "a passive leg other than a universal joint and a slide carrying the platform",
            );
        }
        if self.classes[..self.actuated].contains(&LegClass::Numeric) {
            return Err("a leg without a closed form (a numerical leg)");
        }
        let free = |k: usize| {
            matches!(
                self.roles[k],
                CoordinateRole::Task | CoordinateRole::Dependent
            )
        };
        let constant: Vec<usize> = (0..3).filter(|&k| !free(k)).collect();
        let turning: Vec<usize> = (3..6).filter(|&k| free(k)).collect();
        let form = match turning.as_slice() {
            [] => PoseForm::Translational,
            [5] if self.orientation == OrientationKind::RotationVector
                && self.home[3] == 0.0
                && self.home[4] == 0.0 =>
            {
                PoseForm::Planar
            }
            [3, 4, 5] if constant.len() == 3 => PoseForm::Spherical,
            [3, 4, 5] => PoseForm::Spatial,
            _ => return Err("an orientation that is neither constant, about z alone nor free"),
        };
        let constant = if form == PoseForm::Spherical {
            vec![]
        } else {
            constant
        };
        // The planar and spherical forms hold the elbow planes already (every axis normal to
        // the plane of motion, or through the centre).
        let planes = (0..self.actuated)
            .map(|i| form == PoseForm::Spatial && self.elbow_plane(i, 0.0).is_some())
            .collect();
        if lines > 0 && form != PoseForm::Spatial {
            return Err("a passive leg on a robot whose orientation is not free");
        }
        ForwardSystem::new(form, self.actuated, constant, planes, lines).ok_or(
            "fewer equations than unknowns (a leg that holds the platform beyond its sphere and \
             an elbow plane, as a single R joint at the base or the platform)",
        )
    }

    /// The real parameters of the forward kinematics at actuator coordinates `q` (motions
    /// from the offsets), or `None` for a distance leg made shorter than zero.
    pub(crate) fn polynomial_parameters(
        &self,
        system: &ForwardSystem,
        q: &[f64],
    ) -> Option<Vec<f64>> {
        let home_rotation = self.home_pose.rotation.to_rotation_matrix();
        let mut p = Vec::with_capacity(system.parameters());
        for (i, class) in self.classes.iter().enumerate().take(self.actuated) {
            let actuator = self.legs[i].sole_actuator()?;
            let motion = q[i] - actuator.offset;
            let sphere = class.sphere(motion)?;
            let (b, c, length) = (sphere.center, sphere.point, sphere.length);
            if !(length >= 0.0) {
                return None;
            }
            let c = if system.form == PoseForm::Translational {
                home_rotation * c
            } else {
                c
            };
            p.extend([b.x, b.y, b.z, c.x, c.y, c.z, length * length]);
        }
        p.extend(self.home_pose.translation.vector.iter());
        for (i, leg) in self.legs.iter().enumerate().take(self.actuated) {
            if let Some(a) = self.elbow_plane(i, q[i] - leg.sole_actuator()?.offset) {
                p.extend(a.iter());
            }
        }
        for i in self.actuated..self.legs.len() {
            p.extend(self.line_leg(i)?);
        }
        Some(p)
    }

    /// The parameters of passive leg `i` as a line leg (eq. K3), when it is one: a universal
    /// joint (two revolute axes that meet at $O$) then a passive slide, the platform on the
    /// slider (home frame: $a_2$, the slide and $r_0$ in the platform's frame at home).
    pub(crate) fn line_leg(&self, i: usize) -> Option<[f64; LINE_PARAMETERS]> {
        let crate::pointing::UniversalSlide {
            first: (a1, p1),
            second: (a2, p2),
            slide,
        } = crate::pointing::UniversalSlide::of(&self.legs[i])?;
        let (a1, p1, a2, p2, slide) = (&a1, &p1, &a2, &p2, &slide);
        // The axes meet: p1 + s a1 = p2 + t a2 in the least-squares sense, within 1e-9 size.
        let n = a1.cross(a2);
        if n.norm() < 1e-9 {
            return None;
        }
        let d = p2 - p1;
        if d.dot(&n).abs() > 1e-9 * self.size * n.norm() {
            return None;
        }
        let s = d.cross(a2).dot(&n) / n.norm_squared();
        let o = p1 + a1 * s;
        let home = self.home_pose.rotation.to_rotation_matrix();
        let to_body = |v: &Vector3<f64>| home.inverse() * v;
        let (a2b, slide_b) = (to_body(a2), to_body(slide).normalize());
        let r = to_body(&(self.home_pose.translation.vector - o));
        let r0 = r - slide_b * r.dot(&slide_b);
        let u = slide_b
            .cross(&Vector3::x())
            .try_normalize(1e-6)
            .unwrap_or_else(|| slide_b.cross(&Vector3::y()).normalize());
        let w = slide_b.cross(&u);
        let k = a1.dot(a2);
        Some([
            o.x,
            o.y,
            o.z,
            a1.x,
            a1.y,
            a1.z,
            a2b.x,
            a2b.y,
            a2b.z,
            u.x,
            u.y,
            u.z,
            w.x,
            w.y,
            w.z,
            u.dot(&r0),
            w.dot(&r0),
            k,
        ])
    }

    /// The normal of leg `i`'s elbow plane with its actuator at `motion` (base frame), when
    /// its elbow is a single revolute joint normal to the rod (a PRS or RRS leg): the rod
    /// turns in the plane through the elbow normal to the joint's axis (eq. K2), which the
    /// actuator carries (a revolute actuator turns it with the arm).
    pub(crate) fn elbow_plane(&self, i: usize, motion: f64) -> Option<Vector3<f64>> {
        let leg = &self.legs[i];
        if !matches!(
            self.classes[i],
            LegClass::RevoluteArm { .. } | LegClass::PrismaticArm { .. }
        ) {
            return None;
        }
        let (m, elbow, wrist) = crate::leg_ik::arm_split(leg, &self.home_pose, self.size)?;
        let (1, Joint::Revolute { axis, .. }) = (m, &leg.joints[1]) else {
            return None;
        };
        if (wrist - elbow).dot(axis).abs() > 1e-9 * self.size {
            return None;
        }
        Some(match leg.joints[0] {
            Joint::Revolute { axis: turn, .. } => {
                Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(turn), motion) * axis
            }
            _ => *axis,
        })
    }
}

/// What the homotopy guarantees at one set of actuator coordinates (issue 32): the paths
/// tracked from the generic solutions of the robot's architecture and how each ended.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HomotopyReport {
    /// The polynomial form (`"spatial (Study parameters)"`, `"translational"`, ...).
    pub form: String,
    /// Isolated solutions of a generic member of the family, found by monodromy: the number of
    /// paths tracked.
    pub generic_solutions: usize,
    /// Whether the monodromy stopped because five consecutive loops added no solution.
    pub monodromy_stable: bool,
    /// Finite, nonsingular, real endpoints that close the robot's own closure: its assembly
    /// modes.
    pub real: usize,
    /// Finite, nonsingular endpoints with an imaginary part: no real configuration.
    pub complex: usize,
    /// Endpoints where the system's Jacobian is singular (on the discriminant, a self-motion,
    /// Study's exceptional set $e = 0$ of no pose); the real ones that close the robot's
    /// closure are among the configurations, on a singularity.
    pub singular: usize,
    /// Paths that went to infinity.
    pub at_infinity: usize,
    /// Paths of the spatial form that end on Study's exceptional generator $e = 0$ (its
    /// quaternion below 1e-4 of the unknowns where the tracker stops): points of no pose, which
    /// a robot of special geometry (planar base and platform, say) has for every leg length.
    pub exceptional: usize,
    /// Real endpoints that the robot's own closure refused: a root of the squared-up system of
    /// a redundantly actuated robot that the extra actuator does not allow, or, in a square
    /// system, a disagreement between the polynomial form and the robot (then the report is
    /// not complete).
    pub refused: usize,
    /// Whether the leg equations were combined at random into fewer (redundant actuation), so
    /// that refused real roots are expected.
    pub squared_up: bool,
    /// Nonsingular endpoints that another path had reached already (within 1e-8): two paths
    /// met, so one of them jumped and a solution may be missing. Counted once per repeat; not
    /// in `real` or `complex`.
    pub repeated: usize,
    /// Paths the tracker could not follow: their index and the reason.
    pub failed: Vec<(usize, String)>,
}

impl HomotopyReport {
    /// Whether every path ended at its own finite, nonsingular solution (real or complex)
    /// with a stable monodromy, and every real one closed the robot (unless squared up): then
    /// the real configurations are every real assembly mode.
    /// Paths that end singular, at infinity, on Study's exceptional set, on another path's
    /// solution or failed leave room for a real mode near them (the Hexa at home loses one of
    /// 16 so: its path passes near the exceptional set, where the system is singular, and
    /// stalls).
    pub fn complete(&self) -> bool {
        self.monodromy_stable
            && self.failed.is_empty()
            && self.singular + self.at_infinity + self.exceptional + self.repeated == 0
            && (self.refused == 0 || self.squared_up)
    }
}

/// Every assembly mode at one set of actuator coordinates by homotopy, with its report.
#[derive(Debug, Clone, PartialEq)]
pub struct AllSolutions {
    /// The real configurations, closed on the robot's closure.
    pub configurations: Vec<Configuration>,
    /// How every path ended.
    pub report: HomotopyReport,
}

impl PoseForm {
    fn label(self) -> &'static str {
        match self {
            Self::Translational => "translational (position unknowns, orientation constant)",
            Self::Planar => "planar (position and the cosine and sine of the turn about z)",
            Self::Spherical => "spherical (a quaternion, the position constant)",
            Self::Spatial => "spatial (Study parameters)",
        }
    }
}

impl RobotModel {
    /// Why this robot's forward kinematics has no polynomial form here (`None` when it has
    /// one: [`RobotModel::forward_kinematics_all`] applies).
    pub fn homotopy_unsupported(&self) -> Option<&'static str> {
        self.polynomial_form().err()
    }

    /// The polynomial form [`RobotModel::forward_kinematics_all`] writes this robot in
    /// (`HomotopyReport::form`), `None` when it has none.
    pub fn homotopy_form(&self) -> Option<&'static str> {
        self.polynomial_form()
            .ok()
            .map(|system| system.form.label())
    }

    /// Every assembly mode at actuator coordinates `q` by parameter homotopy (module
    /// documentation): the generic solutions of the robot's architecture (found once by
    /// monodromy, cached) tracked to the robot's parameters; every finite, nonsingular, real
    /// endpoint turned into a configuration (the passive joints solved at its pose) and
    /// checked on the robot's own closure; the report says how every path ended.
    ///
    /// # Errors
    /// [`KinematicsError::InvalidInput`] for a robot without a polynomial form (the reason:
    /// [`RobotModel::homotopy_unsupported`]), a `q` of the wrong length or a leg made shorter
    /// than zero; [`KinematicsError::NonFinite`] for a non-finite `q`.
    pub fn forward_kinematics_all(&self, q: &[f64]) -> Result<AllSolutions, KinematicsError> {
        let system = self.polynomial_form().map_err(|reason| {
            KinematicsError::from(InvalidInput::new("robot", f64::NAN, reason))
        })?;
        let mut home = Configuration::home(self);
        self.set_actuators(&mut home, q)?;
        let p = self.polynomial_parameters(&system, q).ok_or_else(|| {
            KinematicsError::from(InvalidInput::new(
                "q",
                f64::NAN,
                "a leg made shorter than zero",
            ))
        })?;
        let start = generic_start(&system);
        let target: Vec<C64> = p.iter().map(|&v| C64::new(v, 0.0)).collect();
        let mut report = HomotopyReport {
            form: system.form.label().to_owned(),
            generic_solutions: start.monodromy.solutions.len(),
            monodromy_stable: start.monodromy.stable,
            real: 0,
            complex: 0,
            singular: 0,
            at_infinity: 0,
            exceptional: 0,
            refused: 0,
            squared_up: system.squared_up(),
            repeated: 0,
            failed: Vec::new(),
        };
        let mut reached: Vec<DVector<C64>> = Vec::new();
        let mut configurations: Vec<Configuration> = Vec::new();
        for (k, path) in self
            .track_all(&system, &start.monodromy, &target)
            .into_iter()
            .enumerate()
        {
            match path.end {
                Endpoint::Regular(z) => {
                    if pkm_homotopy::contains(&reached, &z, 1e-8) {
                        report.repeated += 1;
                        continue;
                    }
                    reached.push(z.clone());
                    let Some(re) = system.real(&z, 1e-8) else {
                        report.complex += 1;
                        continue;
                    };
                    report.real += 1;
                    match self.configuration_at(&system, &re, &p, q, &home, 1e-6) {
                        Some(c) => push_new(self.orientation, &mut configurations, c),
                        None => {
                            report.real -= 1;
                            report.refused += 1;
                        }
                    }
                }
                Endpoint::Singular(z) => {
                    report.singular += 1;
                    // A real singular endpoint is a configuration on or near a singularity: Newton
                    // converges to it slowly, so it is real to 1e-4 and refined on the robot's
                    // own closure.
                    let closed = system
                        .real(&z, 1e-4)
                        .and_then(|re| self.configuration_at(&system, &re, &p, q, &home, 1e-4));
                    if let Some(c) = closed {
                        push_new(self.orientation, &mut configurations, c);
                    }
                }
                Endpoint::Infinity { .. } => report.at_infinity += 1,
                Endpoint::Failed { s, at, .. } if system.exceptional(&at, s) => {
                    report.exceptional += 1;
                }
                Endpoint::Failed { s, reason, .. } => {
                    report.failed.push((k, format!("{reason} at s = {s:.6}")));
                }
            }
        }
        Ok(AllSolutions {
            configurations,
            report,
        })
    }

    /// Every generic solution tracked to `target`. A path that fails away from its end met a
    /// near-singularity of its segment, and two paths that end at one solution mean one of
    /// them jumped to the other's: each such path is tracked again, up to three times, through
    /// random complex parameters (seeded by its index) with steps ten times smaller; a path
    /// that ends singular or at infinity is tracked again once so (a jumped path can end
    /// there).
    fn track_all(
        &self,
        system: &ForwardSystem,
        generic: &pkm_homotopy::Monodromy,
        target: &[C64],
    ) -> Vec<pkm_homotopy::Path> {
        let settings = pkm_homotopy::TrackSettings::default();
        let careful = pkm_homotopy::TrackSettings {
            initial_step: settings.initial_step / 10.0,
            max_step: settings.max_step / 10.0,
            ..settings
        };
        let p0 = &generic.parameters;
        let mut paths = pkm_homotopy::track_many(system, &generic.solutions, p0, target, &settings);
        let scale = target.iter().map(|v| v.norm()).fold(1.0, f64::max);
        for round in 0..3u64 {
            let redo: Vec<usize> = (0..paths.len())
                .filter(|&k| match &paths[k].end {
                    Endpoint::Failed { s, .. } => *s < 1.0 - settings.endgame,
                    Endpoint::Singular(_) | Endpoint::Infinity { .. } => round == 0,
                    Endpoint::Regular(z) => paths.iter().enumerate().any(|(l, other)| {
                        l != k
                            && matches!(&other.end, Endpoint::Regular(w)
                                if pkm_homotopy::contains(std::slice::from_ref(w), z, 1e-8))
                    }),
                })
                .collect();
            if redo.is_empty() {
                break;
            }
            for k in redo {
                let mut rng = ChaCha8Rng::seed_from_u64((k as u64) << 8 | round);
                let via: Vec<C64> = p0
                    .iter()
                    .zip(target)
                    .map(|(a, b)| {
                        let shake =
                            C64::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
                        (a + b) * 0.5 + shake * scale
                    })
                    .collect();
                let z0 = &generic.solutions[k];
                paths[k] = pkm_homotopy::track_through(system, z0, p0, &via, target, &careful);
            }
        }
        paths
    }

    /// The configuration of a real solution `z`: its pose, every leg's joints solved there
    /// with its actuator at `q`, refined on the robot's closure and kept only if the refined
    /// pose is the solution's (to `tolerance`).
    fn configuration_at(
        &self,
        system: &ForwardSystem,
        z: &[f64],
        p: &[f64],
        q: &[f64],
        home: &Configuration,
        tolerance: f64,
    ) -> Option<Configuration> {
        let (rotation, position) = system.pose(z, p)?;
        let rotation = if system.form == PoseForm::Translational {
            self.home_pose.rotation.to_rotation_matrix()
        } else {
            rotation
        };
        let mut c = home.clone();
        c.pose[..3].copy_from_slice(position.as_slice());
        c.pose[3..].copy_from_slice(self.orientation.coordinates_of(&rotation).as_slice());
        for (i, (leg, &q_i)) in self.legs.iter().zip(q).enumerate() {
            let motion = q_i - leg.sole_actuator()?.offset;
            c.joints[i] = self.passive_joints(i, motion, &c).ok()?;
        }
        for i in self.actuated..self.legs.len() {
            c.joints[i] = self.numeric_leg(i, &c).ok()?;
        }
        let refined = self.forward_kinematics_from(q, &c).ok()?;
        same_pose(self.orientation, &refined, &c, tolerance).then_some(refined)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn real(v: &[f64]) -> Vec<C64> {
        v.iter().map(|&x| C64::new(x, 0.0)).collect()
    }

    /// At the home configuration of every supported example robot, the home pose written in
    /// its form's unknowns solves the system to 1e-12 (the equations and the parameters agree
    /// with the robot's geometry).
    #[test]
    fn the_home_pose_solves_the_system_of_every_supported_file() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/robots");
        let mut supported = Vec::new();
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "toml") {
                continue;
            }
            let model = RobotModel::from_toml(&std::fs::read_to_string(&path).unwrap()).unwrap();
            let Ok(system) = model.polynomial_form() else {
                continue;
            };
            let p = model
                .polynomial_parameters(&system, &model.home_actuators())
                .unwrap();
            let r = model.home_pose.rotation;
            let t = model.home_pose.translation.vector;
            let q = r.quaternion();
            let z: Vec<f64> = match system.form {
                PoseForm::Translational => t.iter().copied().collect(),
                PoseForm::Planar => vec![t.x, t.y, t.z, model.home[5].cos(), model.home[5].sin()],
                PoseForm::Spherical | PoseForm::Spatial => {
                    // The gauge a·z = 1 fixes the scale of (e, g).
                    let e = [q.w, q.i, q.j, q.k];
                    let tq = nalgebra::Quaternion::new(0.0, t.x, t.y, t.z);
                    let g = tq * nalgebra::Quaternion::new(q.w, q.i, q.j, q.k) * 0.5;
                    let mut raw = e.to_vec();
                    if system.form == PoseForm::Spatial {
                        raw.extend([g.w, g.i, g.j, g.k]);
                    }
                    raw
                }
            };
            let mut z = real(&z);
            if matches!(system.form, PoseForm::Spherical | PoseForm::Spatial) {
                let scale: C64 = system.gauge.iter().zip(&z).map(|(a, z)| a * z).sum();
                z.iter_mut().for_each(|v| *v /= scale);
            }
            let f = system.residual(&z, &real(&p));
            let worst = f.iter().map(|c| c.norm()).fold(0.0, f64::max);
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            assert!(worst < 1e-12, "{name}: {worst:e} {f:?}");
            supported.push((name, system.form));
        }
        supported.sort_by(|a, b| a.0.cmp(&b.0));
        let names: Vec<&str> = supported.iter().map(|(n, _)| n.as_str()).collect();
        for expected in [
            "stewart_gough",
            "dietmaier_40",
            "hexa",
            "rotary_delta",
            "three_rpr",
            "five_bar",
            "agile_eye",
            "tsai",
        ] {
            assert!(
                names.contains(&expected),
                "{expected} not supported: {supported:?}"
            );
        }
    }
}

impl ForwardSystem {
    /// A generic member of the family with one solution: a random complex pose `z0` on the
    /// form's own equations (planar $u^2 + v^2 = 1$, Study's quadric, the gauge), random
    /// complex points $B_i$, $c_i$, the constant positions of `z0`, and each $L_i^2$ that puts
    /// `z0` on leg $i$'s equation (which is affine in $L_i^2$). Only the legs' own equations
    /// are solved by `z0`, so the squared-up combination is too.
    fn generic_start(&self, rng: &mut ChaCha8Rng) -> (Vec<C64>, DVector<C64>) {
        let mut complex = || C64::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        let n = self.form.unknowns();
        let mut z: Vec<C64> = (0..n).map(|_| complex()).collect();
        match self.form {
            PoseForm::Planar => {
                let theta = complex();
                (z[3], z[4]) = (theta.cos(), theta.sin());
            }
            PoseForm::Spatial => {
                let eg: C64 = (0..4).map(|k| z[k] * z[4 + k]).sum();
                let ee: C64 = (0..4).map(|k| z[k] * z[k]).sum();
                for k in 0..4 {
                    let shift = z[k] * (eg / ee);
                    z[4 + k] -= shift;
                }
            }
            PoseForm::Translational | PoseForm::Spherical => {}
        }
        if matches!(self.form, PoseForm::Spherical | PoseForm::Spatial) {
            let scale: C64 = self.gauge.iter().zip(&z).map(|(a, z)| a * z).sum();
            z.iter_mut().for_each(|v| *v /= scale);
        }
        let mut p: Vec<C64> = (0..self.parameters()).map(|_| complex()).collect();
        // The constant positions of z0 (t0 is the last three parameters).
        let t = match self.form {
            PoseForm::Translational | PoseForm::Planar => [z[0], z[1], z[2]],
            PoseForm::Spherical => [p[7 * self.legs], p[7 * self.legs + 1], p[7 * self.legs + 2]],
            PoseForm::Spatial => {
                let e = [z[0], z[1], z[2], z[3]];
                let delta: C64 = e.iter().map(|v| v * v).sum();
                let g = [z[4], z[5], z[6], z[7]];
                let v = vector_part(&multiply(&g, &conjugate(&e)));
                [v[0] * 2.0 / delta, v[1] * 2.0 / delta, v[2] * 2.0 / delta]
            }
        };
        p[7 * self.legs..7 * self.legs + 3].copy_from_slice(&t);
        for i in 0..self.legs {
            p[7 * i + 6] = C64::new(0.0, 0.0);
            let at_zero = self.sphere(i, &z, &p);
            p[7 * i + 6] = C64::new(1.0, 0.0);
            let slope = at_zero - self.sphere(i, &z, &p);
            p[7 * i + 6] = at_zero / slope;
            // The plane is linear in its normal a: a·w = 0 with w_k the plane at a = e_k;
            // project the random normal off w (bilinearly), so the plane holds at z0 and
            // still passes through the leg's sphere centre B.
            if let Some(k) = self.normal_at(i) {
                let unit = |j: usize| {
                    let mut a = [C64::new(0.0, 0.0); 3];
                    a[j] = C64::new(1.0, 0.0);
                    self.plane(i, a, &z, &p)
                };
                let w = [unit(0), unit(1), unit(2)];
                let a = [p[k], p[k + 1], p[k + 2]];
                let shift = dot(&a, &w) / dot(&w, &w);
                for j in 0..3 {
                    p[k + j] = a[j] - w[j] * shift;
                }
            }
        }
        // A line leg's equations (spatial form) are affine in u·r0, w·r0 and k, each times -Δ.
        for j in 0..self.lines {
            let delta: C64 = z[..4].iter().map(|v| v * v).sum();
            let at = self.lines_at() + LINE_PARAMETERS * j;
            p[at + 15..at + 18].fill(C64::new(0.0, 0.0));
            let values = line_leg(&z, &p[at..at + LINE_PARAMETERS]);
            for (k, v) in values.iter().enumerate() {
                p[at + 15 + k] = v / delta;
            }
        }
        (p, DVector::from_vec(z))
    }
}

/// The solutions of a generic member of an architecture, found once by monodromy.
#[derive(Debug)]
pub(crate) struct GenericStart {
    pub monodromy: pkm_homotopy::Monodromy,
}

/// The start systems found so far, by architecture: what [`generic_start`] would compute,
/// computed once (the monodromy is seeded by the architecture, so the cache returns the same
/// bits as a fresh run).
static STARTS: std::sync::OnceLock<
    std::sync::Mutex<std::collections::HashMap<Architecture, std::sync::Arc<GenericStart>>>,
> = std::sync::OnceLock::new();

/// The generic start of `system`'s architecture (module documentation), from the cache.
pub(crate) fn generic_start(system: &ForwardSystem) -> std::sync::Arc<GenericStart> {
    let key: Architecture = (
        system.form,
        system.legs,
        system.constant.clone(),
        system.planes.clone(),
        system.lines,
    );
    let cache = STARTS.get_or_init(Default::default);
    if let Some(found) = cache.lock().ok().and_then(|c| c.get(&key).cloned()) {
        return found;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed_of(
        system.form,
        system.legs,
        &system.constant,
        &system.planes,
        system.lines,
    ));
    let (p0, z0) = system.generic_start(&mut rng);
    let monodromy = pkm_homotopy::monodromy(
        system,
        &p0,
        z0,
        &pkm_homotopy::MonodromySettings::default(),
        &mut rng,
    );
    let start = std::sync::Arc::new(GenericStart { monodromy });
    if let Ok(mut c) = cache.lock() {
        c.entry(key).or_insert_with(|| start.clone());
    }
    start
}
