//! The task-based design problem of Wolf & Shoham §3–4 for the Stewart–Gough platform:
//! $F = \sum_i (L_i \wedge \chi)^2$ (eq. 14) as a least-squares objective over any subset of the
//! design $(x_1..x_4)$, the position $p$ and the orientation.
//!
//! The orientation is the rotation vector $w = \alpha n$ with $|w| \le \alpha_{max}$ (the paper's
//! $-30° \le \alpha \le 30°$ with unit $n$). To keep the optimiser's box, $w$ is the smooth
//! cube-to-ball map of $u \in [-1, 1]^3$,
//! $w_x = \alpha_{max} u_x \sqrt{1 - u_y^2/2 - u_z^2/2 + u_y^2 u_z^2/3}$ (and cyclically), whose
//! cube faces map onto the sphere $|w| = \alpha_{max}$.

use crate::stewart_gough::{StewartGough, pose_from_task};
use crate::stewart_layout::JointLayout;
use nalgebra::{Isometry3, Vector3};
use pkm_screw_theory::Twist;
use pkm_traits::{Bounds, DesignError, Objective, ObjectiveError, Residuals, Task};

/// One free variable of a [`StewartTaskProblem`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Slot {
    Design(usize),
    Position(usize),
    Rotation(usize),
}

/// $F$ of eq. 14 for a Stewart–Gough platform, with chosen variables free (see the module docs).
///
/// # Example
/// ```
/// use pkm_mechanisms::{JointLayout, StewartTaskProblem};
/// use pkm_screw_theory::Twist;
/// use pkm_traits::{Bounds, Objective};
/// use nalgebra::Vector3;
/// let chi = Twist::new(Vector3::z(), Vector3::zeros());
/// let problem = StewartTaskProblem::new([3.5, 3.5, 15.0, 10.0], JointLayout::default(),
///     Vector3::new(0.0, 0.0, 40.0), Vector3::zeros(), chi).unwrap()
///     .free_design(3, Bounds::new(0.0, 30.0).unwrap()).unwrap();
/// // x4 = x3 puts every leg in a vertical plane through the axis: F = 0.
/// assert!(problem.value(&[15.0]).unwrap() < 1e-20);
/// ```
#[derive(Debug, Clone)]
pub struct StewartTaskProblem {
    design: [f64; 4],
    layout: JointLayout,
    position: Vector3<f64>,
    rotation: Vector3<f64>,
    max_angle: f64,
    twist: Twist,
    slots: Vec<Slot>,
    bounds: Vec<Bounds>,
}

impl StewartTaskProblem {
    /// The problem with everything fixed: design $x$, position `p`, rotation vector `w`
    /// (radians), task twist `twist`.
    ///
    /// # Errors
    /// [`DesignError`] for an invalid design, a non-finite pose, or a twist that is not finite
    /// or has zero norm.
    pub fn new(
        design: [f64; 4],
        layout: JointLayout,
        p: Vector3<f64>,
        w: Vector3<f64>,
        twist: Twist,
    ) -> Result<Self, DesignError> {
        StewartGough::with_layout(design[0], design[1], design[2], design[3], layout)?;
        for v in p.iter().chain(w.iter()) {
            DesignError::require_finite("pose", *v)?;
        }
        DesignError::require_positive("|chi|", twist.as_vector().norm())?;
        Ok(Self {
            design,
            layout,
            position: p,
            rotation: w,
            max_angle: 0.0,
            twist,
            slots: Vec::new(),
            bounds: Vec::new(),
        })
    }

    /// Frees design parameter $x_{k+1}$ (`k` in 0..4) within `bounds`.
    ///
    /// # Errors
    /// [`DesignError`] for `k` out of range.
    pub fn free_design(self, k: usize, bounds: Bounds) -> Result<Self, DesignError> {
        self.free(Slot::Design(k), k, bounds)
    }

    /// Frees position coordinate $p_k$ (`k` in 0..3) within `bounds`.
    ///
    /// # Errors
    /// [`DesignError`] for `k` out of range.
    pub fn free_position(self, k: usize, bounds: Bounds) -> Result<Self, DesignError> {
        self.free(Slot::Position(k), k + 1, bounds)
    }

    /// Frees the orientation within $|\alpha| \le$ `max_angle` (radians): three variables
    /// $u \in [-1, 1]^3$.
    ///
    /// # Errors
    /// [`DesignError`] for a `max_angle` that is not finite and positive.
    pub fn free_rotation(mut self, max_angle: f64) -> Result<Self, DesignError> {
        self.max_angle = DesignError::require_positive("max_angle", max_angle)?;
        let unit = Bounds {
            lower: -1.0,
            upper: 1.0,
        };
        for k in 0..3 {
            self.slots.push(Slot::Rotation(k));
            self.bounds.push(unit);
        }
        Ok(self)
    }

    fn free(mut self, slot: Slot, k: usize, bounds: Bounds) -> Result<Self, DesignError> {
        if k >= 4 {
            return Err(DesignError {
                parameter: "variable index",
                value: k as f64,
                requirement: "must be < 4 for x, < 3 for p",
            });
        }
        self.slots.push(slot);
        self.bounds.push(bounds);
        Ok(self)
    }

    /// The mechanism and pose at a design vector.
    ///
    /// # Errors
    /// [`ObjectiveError::Dimension`] or [`ObjectiveError::Infeasible`] (invalid design).
    pub fn evaluate(&self, v: &[f64]) -> Result<(StewartGough, Isometry3<f64>), ObjectiveError> {
        self.check_dimension(v)?;
        let (mut x, mut p, mut u) = (self.design, self.position, Vector3::zeros());
        for (slot, value) in self.slots.iter().zip(v) {
            match *slot {
                Slot::Design(k) => x[k] = *value,
                Slot::Position(k) => p[k] = *value,
                Slot::Rotation(k) => u[k] = *value,
            }
        }
        let w = if self.max_angle > 0.0 {
            cube_to_ball(&u) * self.max_angle
        } else {
            self.rotation
        };
        let mechanism = StewartGough::with_layout(x[0], x[1], x[2], x[3], self.layout)?;
        let pose = pose_from_task(&Task::<6>::new(p.x, p.y, p.z, w.x, w.y, w.z)).map_err(|e| {
            ObjectiveError::Infeasible {
                reason: e.to_string(),
            }
        })?;
        Ok((mechanism, pose))
    }
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

    /// The leg rates $L_i \wedge \chi$.
    fn residuals(&self, v: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        if r.len() != 6 {
            return Err(ObjectiveError::Dimension {
                expected: 6,
                got: r.len(),
            });
        }
        let (mechanism, pose) = self.evaluate(v)?;
        let rates =
            mechanism
                .leg_rates(&pose, &self.twist)
                .map_err(|e| ObjectiveError::Infeasible {
                    reason: e.to_string(),
                })?;
        r.copy_from_slice(rates.as_slice());
        Ok(())
    }
}
