//! The task-based design problem of Wolf & Shoham §3–4 for the Stewart–Gough platform:
//! $F = \sum_i (L_i \wedge \chi)^2$ (eq. 14) as a least-squares objective over any subset of the
//! design $(x_1..x_4)$ ([`StewartDesignVariable`]), the position $p$ and the orientation.
//!
//! The orientation is the rotation vector $w = \alpha n$ with $|w| \le \alpha_{max}$ (the paper's
//! $-30° \le \alpha \le 30°$ with unit $n$). To keep the optimiser's box, $w$ is the smooth
//! cube-to-ball map of $u \in [-1, 1]^3$,
//! $w_x = \alpha_{max} u_x \sqrt{1 - u_y^2/2 - u_z^2/2 + u_y^2 u_z^2/3}$ (and cyclically), whose
//! cube faces map onto the sphere $|w| = \alpha_{max}$.

use crate::stewart_gough::{StewartDesign, StewartGough, pose_from_task, so3_left_jacobian};
use nalgebra::{Isometry3, Matrix3, Rotation3, Vector3};
use pkm_screw_theory::Twist;
use pkm_traits::{
    Bounds, DesignError, KinematicsError, Objective, ObjectiveError, Residuals, Task,
};
use std::borrow::Cow;

/// Finite-difference step of the design columns of [`Residuals::residual_jacobian`], relative to
/// each interval width: `pkm_optimizers::LmSettings::default().fd_step`.
const DESIGN_FD_STEP: f64 = 1e-6;

/// A design parameter of a [`StewartDesign`] that a [`StewartTaskProblem`] can free, named with
/// the unit of its optimisation variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StewartDesignVariable {
    /// [`StewartDesign::base_radius`] $x_1$ (length).
    BaseRadius,
    /// [`StewartDesign::platform_radius`] $x_2$ (length).
    PlatformRadius,
    /// [`StewartDesign::base_separation`] $x_3$ (rad).
    BaseSeparation,
    /// [`StewartDesign::platform_separation`] $x_4$ (rad).
    PlatformSeparation,
    /// [`StewartDesign::base_separation`] $x_3$ with the variable in degrees, as the paper's
    /// bounds are printed.
    BaseSeparationDeg,
    /// [`StewartDesign::platform_separation`] $x_4$ with the variable in degrees.
    PlatformSeparationDeg,
}

impl StewartDesignVariable {
    /// Sets this parameter of `design` to the variable's `value`.
    fn set(self, design: &mut StewartDesign, value: f64) {
        match self {
            Self::BaseRadius => design.base_radius = value,
            Self::PlatformRadius => design.platform_radius = value,
            Self::BaseSeparation => design.base_separation = value,
            Self::PlatformSeparation => design.platform_separation = value,
            Self::BaseSeparationDeg => design.base_separation = value.to_radians(),
            Self::PlatformSeparationDeg => design.platform_separation = value.to_radians(),
        }
    }
}

/// One free variable of a [`StewartTaskProblem`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Slot {
    Design(StewartDesignVariable),
    Position(usize),
    Rotation(usize),
}

/// $F$ of eq. 14 for a Stewart–Gough platform, with chosen variables free (see the module docs).
///
/// # Example
/// ```
/// use pkm_mechanisms::{StewartDesign, StewartDesignVariable, StewartTaskProblem};
/// use pkm_screw_theory::Twist;
/// use pkm_traits::{Bounds, Objective};
/// use nalgebra::Vector3;
/// let chi = Twist::new(Vector3::z(), Vector3::zeros());
/// let problem = StewartTaskProblem::new(StewartDesign::from_deg(3.5, 3.5, 15.0, 10.0),
///     Vector3::new(0.0, 0.0, 40.0), Vector3::zeros(), chi).unwrap()
///     .free_design(StewartDesignVariable::PlatformSeparationDeg, Bounds::new(0.0, 30.0).unwrap());
/// // x4 = x3 puts every leg in a vertical plane through the axis: F = 0.
/// assert!(problem.value(&[15.0]).unwrap() < 1e-20);
/// ```
#[derive(Debug, Clone)]
pub struct StewartTaskProblem {
    /// The mechanism of the fixed design, built once; rebuilt per evaluation only when a design
    /// variable is free.
    mechanism: StewartGough,
    position: Vector3<f64>,
    rotation: Vector3<f64>,
    max_angle: f64,
    twist: Twist,
    slots: Vec<Slot>,
    bounds: Vec<Bounds>,
    design_free: bool,
}

/// The legs at one evaluation (see [`StewartTaskProblem::legs`]).
#[derive(Default)]
struct Legs {
    arm: [Vector3<f64>; 6],
    a: [Vector3<f64>; 6],
    s: [Vector3<f64>; 6],
    /// $1 / \ell_i$.
    inv_length: [f64; 6],
}

/// The variables of one evaluation: design, position, cube coordinates $u$ and rotation vector.
struct Variables {
    design: StewartDesign,
    position: Vector3<f64>,
    cube: Vector3<f64>,
    rotation: Vector3<f64>,
}

impl StewartTaskProblem {
    /// The problem with everything fixed: `design`, position `p`, rotation vector `w`
    /// (radians), task twist `twist`.
    ///
    /// # Errors
    /// [`DesignError`] for an invalid design, a non-finite pose, or a twist that is not finite
    /// or has zero norm.
    pub fn new(
        design: StewartDesign,
        p: Vector3<f64>,
        w: Vector3<f64>,
        twist: Twist,
    ) -> Result<Self, DesignError> {
        let mechanism = StewartGough::new(design)?;
        for v in p.iter().chain(w.iter()) {
            DesignError::require_finite("pose", *v)?;
        }
        DesignError::require_positive("|chi|", twist.as_vector().norm())?;
        Ok(Self {
            mechanism,
            position: p,
            rotation: w,
            max_angle: 0.0,
            twist,
            slots: Vec::new(),
            bounds: Vec::new(),
            design_free: false,
        })
    }

    /// Frees the design parameter `variable` within `bounds` (in the variable's unit).
    #[must_use]
    pub fn free_design(self, variable: StewartDesignVariable, bounds: Bounds) -> Self {
        self.free(Slot::Design(variable), bounds)
    }

    /// Frees position coordinate $p_k$ (`k` in 0..3) within `bounds`.
    ///
    /// # Errors
    /// [`DesignError`] for `k` out of range.
    pub fn free_position(self, k: usize, bounds: Bounds) -> Result<Self, DesignError> {
        if k >= 3 {
            return Err(DesignError {
                parameter: "variable index",
                value: k as f64,
                requirement: "must be < 3 for p",
            });
        }
        Ok(self.free(Slot::Position(k), bounds))
    }

    /// Frees the orientation within $|\alpha| \le$ `max_angle` (radians): three variables
    /// $u \in [-1, 1]^3$.
    ///
    /// # Errors
    /// [`DesignError`] for a `max_angle` that is not finite and positive.
    pub fn free_rotation(mut self, max_angle: f64) -> Result<Self, DesignError> {
        self.max_angle = DesignError::require_positive("max_angle", max_angle)?;
        let unit = Bounds::SYMMETRIC_UNIT;
        for k in 0..3 {
            self.slots.push(Slot::Rotation(k));
            self.bounds.push(unit);
        }
        Ok(self)
    }

    fn free(mut self, slot: Slot, bounds: Bounds) -> Self {
        self.design_free |= matches!(slot, Slot::Design(_));
        self.slots.push(slot);
        self.bounds.push(bounds);
        self
    }

    /// The mechanism and pose at a design vector.
    ///
    /// # Errors
    /// [`ObjectiveError::Dimension`] or [`ObjectiveError::Infeasible`] (invalid design).
    pub fn evaluate(&self, v: &[f64]) -> Result<(StewartGough, Isometry3<f64>), ObjectiveError> {
        let vars = self.variables(v)?;
        let mechanism = self.mechanism_at(&vars)?;
        let pose = pose_of(&vars)?;
        Ok((mechanism.into_owned(), pose))
    }

    /// Splits a design vector into its variables (the fixed ones from the problem).
    fn variables(&self, v: &[f64]) -> Result<Variables, ObjectiveError> {
        self.check_dimension(v)?;
        let (mut x, mut p, mut u) = (self.mechanism.design(), self.position, Vector3::zeros());
        for (slot, value) in self.slots.iter().zip(v) {
            match *slot {
                Slot::Design(variable) => variable.set(&mut x, *value),
                Slot::Position(k) => p[k] = *value,
                Slot::Rotation(k) => u[k] = *value,
            }
        }
        let w = if self.max_angle > 0.0 {
            cube_to_ball(&u) * self.max_angle
        } else {
            self.rotation
        };
        Ok(Variables {
            design: x,
            position: p,
            cube: u,
            rotation: w,
        })
    }

    /// The mechanism of `vars`: the one built at construction unless a design variable is free.
    fn mechanism_at(&self, vars: &Variables) -> Result<Cow<'_, StewartGough>, ObjectiveError> {
        if self.design_free {
            Ok(Cow::Owned(StewartGough::new(vars.design)?))
        } else {
            Ok(Cow::Borrowed(&self.mechanism))
        }
    }

    /// The legs at `vars`: $R = \exp([w]_\times)$, arms $R r_i$, platform joints
    /// $a_i = p + R r_i$, lengths $\ell_i = |a_i - b_i|$ and unit directions $s_i$; the same
    /// quantities as [`StewartGough::wrench_rows`] at [`StewartTaskProblem::evaluate`]'s pose
    /// (to rounding), computed directly from the rotation matrix.
    fn legs(
        mechanism: &StewartGough,
        vars: &Variables,
        legs: &mut Legs,
    ) -> Result<(), ObjectiveError> {
        if let Some(value) = vars
            .position
            .iter()
            .chain(vars.rotation.iter())
            .copied()
            .find(|v| !v.is_finite())
        {
            return Err(KinematicsError::NonFinite { what: "x", value }.into());
        }
        let rotation = Rotation3::new(vars.rotation);
        let joints = mechanism
            .base_joints()
            .iter()
            .zip(mechanism.platform_joints());
        for (i, (b, r)) in joints.enumerate() {
            let arm = rotation * r;
            let a = vars.position + arm;
            let d = a - b;
            let length = d.norm();
            if !(length.is_finite() && length > 1e-12) {
                return Err(KinematicsError::Singular {
                    matrix: "leg direction",
                    sigma_min: length,
                }
                .into());
            }
            legs.arm[i] = arm;
            legs.a[i] = a;
            let inv_length = 1.0 / length;
            legs.s[i] = d * inv_length;
            legs.inv_length[i] = inv_length;
        }
        Ok(())
    }

    /// The leg rates $L_i \wedge \chi = s_i \cdot (\bar x + x \times a_i)$ of `legs`.
    fn rates(&self, legs: &Legs, r: &mut [f64]) {
        let (omega, linear) = (self.twist.angular(), self.twist.linear());
        for (r, (s, a)) in r.iter_mut().zip(legs.s.iter().zip(&legs.a)) {
            *r = s.dot(&(linear + omega.cross(a)));
        }
    }

    /// Central differences of the residuals in variable `j` (a design variable), step
    /// [`DESIGN_FD_STEP`] of its interval width clamped into the box (one-sided on a bound), as
    /// the optimiser's own finite differences; written into column `j` of the row-major
    /// `jacobian`.
    fn design_column(
        &self,
        v: &[f64],
        j: usize,
        jacobian: &mut [f64],
    ) -> Result<(), ObjectiveError> {
        let n = v.len();
        let (hi, lo) = self.bounds[j].difference_points(v[j], DESIGN_FD_STEP);
        let mut q = v.to_vec();
        let (mut rp, mut rm) = ([0.0; 6], [0.0; 6]);
        q[j] = hi;
        self.residuals(&q, &mut rp)?;
        q[j] = lo;
        self.residuals(&q, &mut rm)?;
        for i in 0..6 {
            jacobian[i * n + j] = if hi > lo {
                (rp[i] - rm[i]) / (hi - lo)
            } else {
                0.0
            };
        }
        Ok(())
    }
}

/// The pose ${}^wR_p$ of the variables.
fn pose_of(vars: &Variables) -> Result<Isometry3<f64>, ObjectiveError> {
    let (p, w) = (vars.position, vars.rotation);
    pose_from_task(&Task::<6>::new(p.x, p.y, p.z, w.x, w.y, w.z)).map_err(ObjectiveError::from)
}

/// The smooth map of the cube $[-1, 1]^3$ onto the unit ball (faces onto the sphere).
fn cube_to_ball(u: &Vector3<f64>) -> Vector3<f64> {
    let s = u.map(|c| c * c);
    Vector3::new(
        u.x * (1.0 - s.y / 2.0 - s.z / 2.0 + s.y * s.z / 3.0).sqrt(),
        u.y * (1.0 - s.z / 2.0 - s.x / 2.0 + s.z * s.x / 3.0).sqrt(),
        u.z * (1.0 - s.x / 2.0 - s.y / 2.0 + s.x * s.y / 3.0).sqrt(),
    )
}

/// The Jacobian $\partial\,\mathrm{ball}(u) / \partial u$ of [`cube_to_ball`]: with
/// $g_x = 1 - u_y^2/2 - u_z^2/2 + u_y^2 u_z^2/3$ (and cyclically),
/// $\partial w_x/\partial u_x = \sqrt{g_x}$,
/// $\partial w_x/\partial u_y = u_x u_y (2 u_z^2/3 - 1) / (2\sqrt{g_x})$,
/// $\partial w_x/\partial u_z = u_x u_z (2 u_y^2/3 - 1) / (2\sqrt{g_x})$; $g \ge 1/3$ on the cube.
fn cube_to_ball_jacobian(u: &Vector3<f64>) -> Matrix3<f64> {
    let s = u.map(|c| c * c);
    let mut jac = Matrix3::zeros();
    for (i, j, k) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
        let root = (1.0 - s[j] / 2.0 - s[k] / 2.0 + s[j] * s[k] / 3.0).sqrt();
        jac[(i, i)] = root;
        jac[(i, j)] = u[i] * u[j] * (2.0 * s[k] / 3.0 - 1.0) / (2.0 * root);
        jac[(i, k)] = u[i] * u[k] * (2.0 * s[j] / 3.0 - 1.0) / (2.0 * root);
    }
    jac
}

impl Objective for StewartTaskProblem {
    fn dimension(&self) -> usize {
        self.slots.len()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    /// $F$ (to be maximised or minimised by the caller's choice).
    fn value(&self, v: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0; 6];
        self.residuals(v, &mut r)?;
        Ok(r.iter().map(|x| x * x).sum())
    }
}

impl Residuals for StewartTaskProblem {
    fn n_residuals(&self) -> usize {
        6
    }

    /// The leg rates $L_i \wedge \chi = s_i \cdot (\bar x + x \times a_i)$ (as
    /// [`StewartGough::leg_rates`] at [`StewartTaskProblem::evaluate`]'s mechanism and pose, to
    /// rounding).
    fn residuals(&self, v: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        if r.len() != 6 {
            return Err(ObjectiveError::Dimension {
                expected: 6,
                got: r.len(),
            });
        }
        let vars = self.variables(v)?;
        let mechanism = self.mechanism_at(&vars)?;
        let mut legs = Legs::default();
        Self::legs(&mechanism, &vars, &mut legs)?;
        self.rates(&legs, r);
        Ok(())
    }

    /// The leg rates and their Jacobian, analytic in the position and rotation variables:
    /// $r_i = s_i \cdot v_i$ with $v_i = \bar x + x \times a_i$ has
    /// $\nabla_{a} r_i = (v_i - s_i (s_i \cdot v_i)) / \ell_i + s_i \times x$ ($\ell_i$ the leg
    /// length), $\partial a_i / \partial p = I$,
    /// $\partial a_i / \partial w = -[R r_i]_\times J_l(w)$ (left Jacobian of SO(3)) and
    /// $\partial w / \partial u = \alpha_{max} \partial\,\mathrm{ball}(u)/\partial u$. Design
    /// columns are central differences of the residuals (step $10^{-6}$ of the interval width,
    /// one-sided on a bound). The residuals are those of [`Residuals::residuals`], bit for bit.
    fn residual_jacobian(
        &self,
        v: &[f64],
        r: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, ObjectiveError> {
        let n = self.dimension();
        for (expected, got) in [(6, r.len()), (6 * n, jacobian.len())] {
            if expected != got {
                return Err(ObjectiveError::Dimension { expected, got });
            }
        }
        let vars = self.variables(v)?;
        let mechanism = self.mechanism_at(&vars)?;
        let mut legs = Legs::default();
        Self::legs(&mechanism, &vars, &mut legs)?;
        self.rates(&legs, r);
        let (omega, linear) = (self.twist.angular(), self.twist.linear());
        // ∂a_i/∂u = -[R r_i]× · du, with du = J_l(w) ∂w/∂u.
        let du = if self.max_angle > 0.0 {
            so3_left_jacobian(&vars.rotation) * cube_to_ball_jacobian(&vars.cube) * self.max_angle
        } else {
            Matrix3::zeros()
        };
        for i in 0..6 {
            let (s, a) = (legs.s[i], legs.a[i]);
            let rate = linear + omega.cross(&a);
            let grad_a = (rate - s * s.dot(&rate)) * legs.inv_length[i] + s.cross(&omega);
            // grad_aᵀ (-[arm]×) = (arm × grad_a)ᵀ.
            let grad_u = du.tr_mul(&legs.arm[i].cross(&grad_a));
            for (j, slot) in self.slots.iter().enumerate() {
                jacobian[i * n + j] = match *slot {
                    Slot::Position(k) => grad_a[k],
                    Slot::Rotation(k) => grad_u[k],
                    Slot::Design(_) => 0.0,
                };
            }
        }
        for (j, slot) in self.slots.iter().enumerate() {
            if matches!(slot, Slot::Design(_)) {
                self.design_column(v, j, jacobian)?;
            }
        }
        Ok(true)
    }
}
