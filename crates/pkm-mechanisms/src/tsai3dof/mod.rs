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

/// A validated design $(a, b, d + e, c - r, \phi_2, \phi_3)$ of the Tsai platform, $\phi_1 = 0$.
///
/// # Example
/// ```
/// use pkm_mechanisms::Tsai3Dof;
/// let design = Tsai3Dof::from_degrees(0.44, 0.56, 0.0, 0.0, 120.0, 240.0).unwrap();
/// assert!((design.reach() - 1.0).abs() < 1e-12);
/// assert!(Tsai3Dof::new(-0.1, 0.5, 0.0, 0.0, 1.0, 2.0).is_err());
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
    /// A design with leg angles $\phi_2, \phi_3$ in radians.
    ///
    /// # Errors
    /// [`DesignError`] when $a \le 0$, $b \le 0$, $d + e < 0$ or any value is not finite.
    pub fn new(
        a: f64,
        b: f64,
        d_plus_e: f64,
        c_minus_r: f64,
        phi2: f64,
        phi3: f64,
    ) -> Result<Self, DesignError> {
        let a = DesignError::require_positive("a", a)?;
        let b = DesignError::require_positive("b", b)?;
        let s = DesignError::require_finite("d+e", d_plus_e)?;
        if s < 0.0 {
            return Err(DesignError {
                parameter: "d+e",
                value: s,
                requirement: "must be >= 0",
            });
        }
        let h = DesignError::require_finite("c-r", c_minus_r)?;
        let phi = [
            0.0,
            DesignError::require_finite("phi_2", phi2)?,
            DesignError::require_finite("phi_3", phi3)?,
        ];
        let trig = phi.map(|p| (p.cos(), p.sin()));
        Ok(Self {
            a,
            b,
            s,
            h,
            phi,
            trig,
        })
    }

    /// As [`Tsai3Dof::new`] with $\phi_2, \phi_3$ in degrees, as the paper prints them.
    ///
    /// # Errors
    /// As [`Tsai3Dof::new`].
    pub fn from_degrees(
        a: f64,
        b: f64,
        d_plus_e: f64,
        c_minus_r: f64,
        phi2_deg: f64,
        phi3_deg: f64,
    ) -> Result<Self, DesignError> {
        Self::new(
            a,
            b,
            d_plus_e,
            c_minus_r,
            phi2_deg.to_radians(),
            phi3_deg.to_radians(),
        )
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
