//! The rotary Delta family of Miller 2004 (§2.1, §3.5): three motors 120° apart, each with an
//! arm of length $L_a$ and a parallelogram forearm of length $L_b$, the motor axes inclined by
//! $\alpha$ to the horizontal and turned by $\beta$ about the vertical. The Delta is
//! $\alpha = \beta = 0$; NUWAR is $\alpha = 35.26°$, $\beta = 60°$.
//!
//! Geometry (`../shared/spec/miller-dynamics.md` §1). For motor $i = 0, 1, 2$ at azimuth
//! $\varphi_i = \varphi_1 + i \cdot 120°$ the motor frame is
//! $F_i = R_z(\varphi_i) R_z(\beta) R_x(\alpha)$ with columns $u_i$ (arm direction at
//! $\theta = 0$, horizontal), $e_i$ (motor axis) and $w_i$. The motor point is
//! $A_i = (R\cos\varphi_i, R\sin\varphi_i, z_0)$, the elbow
//! $B_i = A_i + L_a d_i(\theta_i)$ with $d_i(\theta) = \cos\theta\, u_i - \sin\theta\, w_i$
//! ($\theta > 0$ swings the arm down), the plate joint-pair mid-point $C_i = p + c_i$,
//! $c_i = r(\cos\varphi_i, \sin\varphi_i, 0)$, and the loop closure is
//! $\Phi_i = |C_i - B_i|^2 - L_b^2$.

mod batch;
mod kinematics;
mod workspace;

pub use kinematics::ElbowMode;
pub use workspace::FOREARM_CLEARANCE_SPAN;

use nalgebra::{Rotation3, Vector3};
use pkm_traits::DesignError;
use serde::{Deserialize, Serialize};

/// Where the robot sits in the task frame: the open choices of the paper (its Figures 2 and 7 are
/// missing), see `docs/conventions.md` "Miller 2004 §3: dynamics".
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// Height $z_0$ of the motor plane in the task frame (m).
    pub motor_plane_z: f64,
    /// Azimuth $\varphi_1$ of motor 1 about the vertical (rad).
    pub azimuth_motor_1: f64,
}

impl Placement {
    /// The canonical placement of the spec: $z_0 = -0.2928$ m (least-squares fit of the printed
    /// start angles), $\varphi_1 = 300°$.
    pub fn canonical() -> Self {
        Self {
            motor_plane_z: -0.2928,
            azimuth_motor_1: 300f64.to_radians(),
        }
    }
}

/// One leg's fixed geometry in the task frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leg {
    /// Arm direction at $\theta = 0$ (horizontal).
    pub u: Vector3<f64>,
    /// Motor axis; $\theta$ is a right-hand rotation about it.
    pub e: Vector3<f64>,
    /// $w = u \times e$ completes the motor frame.
    pub w: Vector3<f64>,
    /// Motor point $A_i$.
    pub motor: Vector3<f64>,
    /// Plate offset $c_i$ of the joint-pair mid-point.
    pub plate_offset: Vector3<f64>,
}

impl Leg {
    /// Arm direction $d(\theta) = \cos\theta\, u - \sin\theta\, w$.
    pub fn arm_direction(&self, theta: f64) -> Vector3<f64> {
        self.u * theta.cos() - self.w * theta.sin()
    }

    /// $d'(\theta) = -\sin\theta\, u - \cos\theta\, w$ (and $d'' = -d$).
    pub fn arm_direction_derivative(&self, theta: f64) -> Vector3<f64> {
        -self.u * theta.sin() - self.w * theta.cos()
    }
}

/// The design of a rotary Delta / NUWAR: lengths in metres, angles in radians. The paper's
/// designs are in [`crate::presets`] ([`crate::presets::miller_delta`],
/// [`crate::presets::nuwar`], [`crate::presets::miller_prototype`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotaryDeltaDesign {
    /// Radial distance $R$ of the motor points from the centreline (m); positive.
    pub base_radius: f64,
    /// Radial plate offset $r$ of the joint-pair mid-points (m); finite.
    pub plate_offset: f64,
    /// Arm length $L_a$ (m); positive.
    pub arm: f64,
    /// Forearm (parallelogram) length $L_b$ (m); positive.
    pub forearm: f64,
    /// Motor-axis inclination $\alpha$ to the horizontal (rad); finite.
    pub alpha: f64,
    /// Motor turn $\beta$ about the vertical (rad); finite.
    pub beta: f64,
    /// Where the robot sits in the task frame.
    pub placement: Placement,
}

/// A validated rotary Delta / NUWAR design.
///
/// # Example
/// ```
/// use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
/// use pkm_traits::InverseKinematics;
/// use nalgebra::Vector3;
/// let nuwar = RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap();
/// let theta = nuwar.inverse_kinematics(&Vector3::new(0.0, -0.2, -0.9), ElbowMode::Out).unwrap();
/// assert!((theta[0].to_degrees() - 72.2).abs() < 0.1);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RotaryDelta {
    design: RotaryDeltaDesign,
    legs: [Leg; 3],
}

impl RotaryDelta {
    /// Builds the mechanism of `design`.
    ///
    /// # Errors
    /// [`DesignError`] for a non-positive length or a non-finite offset, angle or placement, or
    /// for lengths whose derived quantities overflow: the squares of the kinematics
    /// ($4L_a^2$, $L_a^2 + L_b^2$) and the volume of [`RotaryDelta::reach_cylinder`].
    pub fn new(design: RotaryDeltaDesign) -> Result<Self, DesignError> {
        let base_radius = DesignError::require_positive("R", design.base_radius)?;
        let r = DesignError::require_finite("r", design.plate_offset)?;
        DesignError::require_positive("La", design.arm)?;
        DesignError::require_positive("Lb", design.forearm)?;
        let alpha = DesignError::require_finite("alpha", design.alpha)?;
        let beta = DesignError::require_finite("beta", design.beta)?;
        let z0 = DesignError::require_finite("z0", design.placement.motor_plane_z)?;
        let phi1 = DesignError::require_finite("phi1", design.placement.azimuth_motor_1)?;
        let legs = [0.0, 1.0, 2.0].map(|i: f64| {
            let phi = phi1 + i * 120f64.to_radians();
            let frame = Rotation3::from_axis_angle(&Vector3::z_axis(), phi + beta)
                * Rotation3::from_axis_angle(&Vector3::x_axis(), alpha);
            let radial = Vector3::new(phi.cos(), phi.sin(), 0.0);
            Leg {
                u: frame * Vector3::x(),
                e: frame * Vector3::y(),
                w: frame * Vector3::z(),
                motor: radial * base_radius + Vector3::new(0.0, 0.0, z0),
                plate_offset: radial * r,
            }
        });
        let (arm, forearm) = (design.arm, design.forearm);
        DesignError::require_derived_finite("4 La^2", 4.0 * arm * arm)?;
        DesignError::require_derived_finite("La^2 + Lb^2", arm * arm + forearm * forearm)?;
        let mechanism = Self { design, legs };
        let (radius, half_height) = mechanism.reach_cylinder();
        DesignError::require_derived_finite(
            "reach cylinder volume",
            std::f64::consts::PI * radius * radius * 2.0 * half_height,
        )?;
        Ok(mechanism)
    }

    /// The design the mechanism was built from (the plate offsets as designed, radial even after
    /// [`RotaryDelta::with_turned_plate_offsets`]).
    pub fn design(&self) -> RotaryDeltaDesign {
        self.design
    }

    /// Base radius $R$ (radial distance of the motor points from the centreline).
    pub fn base_radius(&self) -> f64 {
        self.design.base_radius
    }

    /// Radial plate offset $r$ of the joint-pair mid-points.
    pub fn plate_offset(&self) -> f64 {
        self.design.plate_offset
    }

    /// A vertical cylinder about the centreline that holds every reachable plate position, as
    /// (radius, half-height about the motor plane): $|C_i - A_i| \le L_a + L_b$ gives
    /// $\rho \le \max_i |(c_i - A_i)_{xy}| + L_a + L_b$ (that is $|R - r| + L_a + L_b$ for radial
    /// plate offsets) and $|z - z_0| \le L_a + L_b$, whatever $\alpha, \beta$.
    pub fn reach_cylinder(&self) -> (f64, f64) {
        let reach = self.design.arm + self.design.forearm;
        let offset = self
            .legs
            .iter()
            .map(|l| (l.plate_offset - l.motor).xy().norm())
            .fold(0.0, f64::max);
        (offset + reach, reach)
    }

    /// Height $z_0$ of the motor plane.
    pub fn motor_plane_z(&self) -> f64 {
        self.legs[0].motor.z
    }

    /// The same design with each plate joint-pair mid-point turned with its motor by $\beta$
    /// about the vertical, $c_i = r(\cos(\varphi_i + \beta), \sin(\varphi_i + \beta), 0)$: the
    /// plate built to match turned motors (a reading of Miller 2004 §2.1; the default keeps
    /// $c_i$ radial).
    #[must_use]
    pub fn with_turned_plate_offsets(mut self) -> Self {
        let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), self.design.beta);
        for leg in &mut self.legs {
            leg.plate_offset = turn * leg.plate_offset;
        }
        self
    }

    /// Arm length $L_a$.
    pub fn arm(&self) -> f64 {
        self.design.arm
    }

    /// Forearm length $L_b$.
    pub fn forearm(&self) -> f64 {
        self.design.forearm
    }

    /// Motor inclination $\alpha$ and turn $\beta$ (rad).
    pub fn angles(&self) -> (f64, f64) {
        (self.design.alpha, self.design.beta)
    }

    /// The three legs.
    pub fn legs(&self) -> &[Leg; 3] {
        &self.legs
    }

    /// Elbow $B_i = A_i + L_a d_i(\theta_i)$.
    pub fn elbow(&self, leg: usize, theta: f64) -> Vector3<f64> {
        let l = &self.legs[leg % 3];
        l.motor + l.arm_direction(theta) * self.design.arm
    }

    /// Forearm vector $v_i = C_i - B_i$ at plate position `p`.
    pub fn forearm_vector(&self, leg: usize, p: &Vector3<f64>, theta: f64) -> Vector3<f64> {
        p + self.legs[leg % 3].plate_offset - self.elbow(leg, theta)
    }
}
