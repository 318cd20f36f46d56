//! The Tsai 3-DOF translational platform (Stamper, Tsai & Walsh 1997, Fig. 1): three identical
//! legs, each a revolute lower arm $A_iB_i$ of length $a$ and a parallelogram $C_iD_i$ of length
//! $b$, with offsets $d + e$ along the arm direction and platform minus base radius $c - r$.
//!
//! Conventions (`docs/conventions.md#stamper-conventions`, spec `stamper.md` §1): leg $i$ sits
//! at angle $\phi_i$ about $Z$ with $\phi_1 = 0$; $\theta_{1i}$ (actuated) and $\theta_{2i}$
//! are measured from $u_i$ towards $w_i = Z$, $\theta_{3i}$ from $v_i$ to $C_iD_i$.

mod batch;
mod jacobian;
mod leg;
mod volume;

pub use leg::{Elbow, LegAngles, LegBranch};

use pkm_traits::DesignError;
use serde::{Deserialize, Serialize};

/// The design $(a, b, d + e, c - r, \phi_2, \phi_3)$ of the Tsai platform, $\phi_1 = 0$: lengths
/// in metres (or any one length unit), angles in radians. Stamper's maximum-GCI design is
/// [`crate::presets::stamper_max_gci`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TsaiDesign {
    /// Lower arm length $a = |A_iB_i|$ (m); positive.
    pub a: f64,
    /// Parallelogram length $b = |C_iD_i|$ (m); positive.
    pub b: f64,
    /// Offset sum $d + e$ along the arm direction (m); at least 0.
    pub d_plus_e: f64,
    /// Platform minus base radius $c - r$ (m); finite.
    pub c_minus_r: f64,
    /// Azimuth $\phi_2$ of leg 2 about $Z$ (rad); finite.
    pub phi2: f64,
    /// Azimuth $\phi_3$ of leg 3 about $Z$ (rad); finite.
    pub phi3: f64,
}

impl TsaiDesign {
    /// The design with the leg azimuths $\phi_2, \phi_3$ in degrees, as the paper prints them.
    pub fn from_deg(
        a: f64,
        b: f64,
        d_plus_e: f64,
        c_minus_r: f64,
        phi2_deg: f64,
        phi3_deg: f64,
    ) -> Self {
        Self {
            a,
            b,
            d_plus_e,
            c_minus_r,
            phi2: phi2_deg.to_radians(),
            phi3: phi3_deg.to_radians(),
        }
    }
}

/// A validated Tsai platform.
///
/// # Example
/// ```
/// use pkm_mechanisms::{Tsai3Dof, TsaiDesign, presets};
/// let design = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
/// assert!((design.reach() - 1.0).abs() < 1e-12);
/// let negative_arm = TsaiDesign { a: -0.1, ..presets::stamper_max_gci() };
/// assert!(Tsai3Dof::new(negative_arm).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tsai3Dof {
    a: f64,
    b: f64,
    s: f64,
    h: f64,
    phi: [f64; 3],
    /// $(\cos\phi_i, \sin\phi_i)$, cached for the hot loop.
    trig: [(f64, f64); 3],
}

impl Tsai3Dof {
    /// Builds the platform of `design`.
    ///
    /// # Errors
    /// [`DesignError`] when $a \le 0$, $b \le 0$, $d + e < 0$ or any value is not finite, or when
    /// the cube of the reach $(a + b + d + e)^3$ (with $|c - r|$ added), $a^2$ or $b^2$ is not a
    /// normal number: a design so large or so small that its volume or its kinematics overflow
    /// or underflow.
    pub fn new(design: TsaiDesign) -> Result<Self, DesignError> {
        let a = DesignError::require_positive("a", design.a)?;
        let b = DesignError::require_positive("b", design.b)?;
        let s = DesignError::require_finite("d+e", design.d_plus_e)?;
        if s < 0.0 {
            return Err(DesignError {
                parameter: "d+e",
                value: s,
                requirement: "must be >= 0",
            });
        }
        let h = DesignError::require_finite("c-r", design.c_minus_r)?;
        let phi = [
            0.0,
            DesignError::require_finite("phi_2", design.phi2)?,
            DesignError::require_finite("phi_3", design.phi3)?,
        ];
        let trig = phi.map(|p| (p.cos(), p.sin()));
        // The column volume and the hemisphere estimates scale with the cube of the reach,
        // and the kinematics square every length.
        let size = a + b + s + h.abs();
        DesignError::require_derived_normal("(a + b + d + e + |c - r|)^3", size * size * size)?;
        DesignError::require_derived_normal("(a + b + d + e)^3", (a + b + s).powi(3))?;
        DesignError::require_derived_normal("a^2", a * a)?;
        DesignError::require_derived_normal("b^2", b * b)?;
        Ok(Self {
            a,
            b,
            s,
            h,
            phi,
            trig,
        })
    }

    /// The design the platform was built from.
    pub fn design(&self) -> TsaiDesign {
        TsaiDesign {
            a: self.a,
            b: self.b,
            d_plus_e: self.s,
            c_minus_r: self.h,
            phi2: self.phi[1],
            phi3: self.phi[2],
        }
    }

    /// Lower arm length $a = |A_iB_i|$.
    pub fn a(&self) -> f64 {
        self.a
    }
    /// Parallelogram length $b = |C_iD_i|$.
    pub fn b(&self) -> f64 {
        self.b
    }
    /// Offset sum $d + e$.
    pub fn d_plus_e(&self) -> f64 {
        self.s
    }
    /// Platform minus base radius $c - r$.
    pub fn c_minus_r(&self) -> f64 {
        self.h
    }
    /// Leg angles $(\phi_1, \phi_2, \phi_3)$ in radians, $\phi_1 = 0$.
    pub fn phi(&self) -> [f64; 3] {
        self.phi
    }
    /// $R = a + b + d + e$, the radius of the hemisphere of eq. 3.
    pub fn reach(&self) -> f64 {
        self.a + self.b + self.s
    }
}
