//! The mass model of the rotary Delta family (Miller 2004 §3.5; `miller-dynamics.md` §3).
//!
//! The kinetic energy in the extended coordinates reduces to three coefficients,
//! $$ T = \tfrac12 m_t |\dot p|^2 + \sum_i \big[\tfrac12 J \dot\theta_i^2 + k\, \dot\theta_i\, d_i'(\theta_i)\cdot\dot p\big], $$
//! and the potential to two, $V = g\,[m_g z + \sum_i c_g\, d_i(\theta_i)_z]$.

use pkm_traits::DesignError;

/// How the forearm mass enters the kinetic energy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForearmModel {
    /// Slender rods whose ends move with $B_i$, $C_i$: $T = \tfrac m6(v_a^2 + v_a\cdot v_b + v_b^2)$
    /// (canonical).
    Rod,
    /// Half of each forearm lumped at the elbow, half at the plate.
    Lumped,
}

/// The masses of §3.5 and the open choices of the mass model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassParameters {
    /// Plate mass $m_p$ (kg).
    pub plate: f64,
    /// Arm inertia about the motor axis $I_A$ (kg m²).
    pub arm_inertia: f64,
    /// Arm mass $m_A$ (kg), in the potential only.
    pub arm_mass: f64,
    /// Distance of the arm's centre of mass from the motor axis $l_G$ (m; not printed).
    pub arm_centre_of_mass: f64,
    /// Elbow mass per chain $m_e$ (kg).
    pub elbow: f64,
    /// Mass of one forearm, both rods together $m_f$ (kg).
    pub forearm: f64,
    /// Gravity $g$ along $-z$ (m/s²; 0 switches it off).
    pub gravity: f64,
    /// Forearm model.
    pub forearm_model: ForearmModel,
}

impl MassParameters {
    /// The paper's values with the spec's assumptions: $l_G = L_a/2 = 0.13$ m, 0.0296 kg per
    /// forearm, rod model, $g = 9.81$.
    pub fn miller2004() -> Self {
        Self {
            plate: 0.2807,
            arm_inertia: 0.01822,
            arm_mass: 0.977,
            arm_centre_of_mass: 0.13,
            elbow: 0.0099,
            forearm: 0.0296,
            gravity: 9.81,
            forearm_model: ForearmModel::Rod,
        }
    }

    /// The coefficients $(m_t, J, k, m_g, c_g)$ for arm length $L_a$.
    ///
    /// # Errors
    /// [`DesignError`] when a mass is negative or non-finite, the plate mass or the arm length
    /// is not positive, or a coefficient overflows.
    pub fn coefficients(&self, arm: f64) -> Result<Coefficients, DesignError> {
        let arm = DesignError::require_positive("La", arm)?;
        let m_p = DesignError::require_positive("m_p", self.plate)?;
        let i_a = DesignError::require_positive("I_A", self.arm_inertia)?;
        let non_negative = |name, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(DesignError {
                    parameter: name,
                    value: v,
                    requirement: "must be finite and >= 0",
                })
            }
        };
        let m_a = non_negative("m_A", self.arm_mass)?;
        let l_g = non_negative("l_G", self.arm_centre_of_mass)?;
        let m_e = non_negative("m_e", self.elbow)?;
        let m_f = non_negative("m_f", self.forearm)?;
        let gravity = non_negative("g", self.gravity)?;
        let la2 = arm * arm;
        let (m_t, j, k) = match self.forearm_model {
            ForearmModel::Rod => (m_p + m_f, i_a + (m_e + m_f / 3.0) * la2, m_f * arm / 6.0),
            ForearmModel::Lumped => (m_p + 1.5 * m_f, i_a + (m_e + m_f / 2.0) * la2, 0.0),
        };
        let coefficients = Coefficients {
            m_t,
            j,
            k,
            m_g: m_p + 1.5 * m_f,
            c_g: m_e * arm + m_a * l_g + m_f * arm / 2.0,
            gravity,
        };
        coefficients.require_finite()?;
        Ok(coefficients)
    }
}

/// The reduced inertia coefficients of [`MassParameters::coefficients`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coefficients {
    /// Translating mass $m_t$.
    pub m_t: f64,
    /// Arm inertia with the elbow and forearm shares $J$.
    pub j: f64,
    /// Arm–plate coupling $k$.
    pub k: f64,
    /// Mass in the plate's potential $m_g$.
    pub m_g: f64,
    /// First moment of each arm about its axis $c_g$.
    pub c_g: f64,
    /// Gravity.
    pub gravity: f64,
}

impl Coefficients {
    /// Every coefficient, and the gravity terms $g m_g$, $g c_g$ of the model, must be finite.
    fn require_finite(&self) -> Result<(), DesignError> {
        let derived = [
            ("m_t", self.m_t),
            ("J", self.j),
            ("k", self.k),
            ("m_g", self.m_g),
            ("c_g", self.c_g),
            ("g m_g", self.gravity * self.m_g),
            ("g c_g", self.gravity * self.c_g),
        ];
        for (name, value) in derived {
            DesignError::require_derived_finite(name, value)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_coefficients_match_the_spec() {
        let c = MassParameters::miller2004().coefficients(0.26).unwrap();
        assert!((c.m_t - 0.3103).abs() < 1e-12);
        assert!((c.j - 0.019556227).abs() < 1e-9);
        assert!((c.k - 0.0012826667).abs() < 1e-9);
        assert!((c.m_g - 0.3251).abs() < 1e-12);
        assert!((c.c_g - 0.133432).abs() < 1e-9);
    }
}
