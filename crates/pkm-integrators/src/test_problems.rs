//! Canonical test problems with closed-form solutions or invariants, shared by the tests,
//! property tests and benches (as diffsol's `test_models`).
//!
//! | problem | equation | what it checks |
//! |---|---|---|
//! | [`ExponentialDecay`] | $\dot y = -\lambda y$ | order of convergence, closed form |
//! | [`HarmonicOscillator`] | $\dot q = p,\ \dot p = -\omega^2 q$ | closed form, quadratic invariant |
//! | [`Pendulum`] | $\dot\theta = p,\ \dot p = -\omega_0^2 \sin\theta$ | non-quadratic energy over long runs |
//! | [`RotatingDecay`] | $\dot z = \begin{pmatrix} a & -b \\\\ b & a \end{pmatrix} z$ | linear systems with random coefficients |
//! | [`Blowup`] | $\dot y = y^2$ | finite-time blow-up at $t = 1/y_0$ |

use nalgebra::{SVector, Vector1, Vector2};
use pkm_traits::{DesignError, RhsError, VectorField};

/// $\dot y = -\lambda y$, solution $y(t) = y_0 e^{-\lambda t}$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExponentialDecay {
    lambda: f64,
}

impl ExponentialDecay {
    /// Decay with rate `lambda`.
    ///
    /// # Errors
    /// [`DesignError`] unless `lambda` is finite.
    pub fn new(lambda: f64) -> Result<Self, DesignError> {
        Ok(Self {
            lambda: DesignError::require_finite("lambda", lambda)?,
        })
    }

    /// The exact solution at `t` from `y0` at 0.
    pub fn exact(&self, t: f64, y0: &Vector1<f64>) -> Vector1<f64> {
        y0 * (-self.lambda * t).exp()
    }
}

impl VectorField<1> for ExponentialDecay {
    fn rhs(&self, _t: f64, z: &Vector1<f64>, dz: &mut Vector1<f64>) -> Result<(), RhsError> {
        *dz = z * -self.lambda;
        Ok(())
    }
}

/// $\dot q = p,\ \dot p = -\omega^2 q$ with state $z = (q, p)$; energy
/// $E = \tfrac12 (p^2 + \omega^2 q^2)$ (a quadratic invariant), period $2\pi/\omega$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HarmonicOscillator {
    omega: f64,
}

impl HarmonicOscillator {
    /// Oscillator with angular frequency `omega`.
    ///
    /// # Errors
    /// [`DesignError`] unless `omega` is finite and `> 0`.
    pub fn new(omega: f64) -> Result<Self, DesignError> {
        Ok(Self {
            omega: DesignError::require_positive("omega", omega)?,
        })
    }

    /// Angular frequency.
    pub fn omega(&self) -> f64 {
        self.omega
    }

    /// $z_0 = (1, 0)$.
    pub fn initial_state(&self) -> Vector2<f64> {
        Vector2::new(1.0, 0.0)
    }

    /// The exact solution at `t` from `z0` at 0.
    pub fn exact(&self, t: f64, z0: &Vector2<f64>) -> Vector2<f64> {
        let (s, c) = (self.omega * t).sin_cos();
        Vector2::new(
            z0[0] * c + z0[1] * s / self.omega,
            -z0[0] * self.omega * s + z0[1] * c,
        )
    }

    /// $E = \tfrac12 (p^2 + \omega^2 q^2)$.
    pub fn energy(&self, z: &Vector2<f64>) -> f64 {
        0.5 * (z[1] * z[1] + (self.omega * z[0]).powi(2))
    }
}

impl VectorField<2> for HarmonicOscillator {
    fn rhs(&self, _t: f64, z: &Vector2<f64>, dz: &mut Vector2<f64>) -> Result<(), RhsError> {
        *dz = Vector2::new(z[1], -self.omega * self.omega * z[0]);
        Ok(())
    }
}

/// The mathematical pendulum $\dot\theta = p,\ \dot p = -\omega_0^2 \sin\theta$, state
/// $z = (\theta, p)$, energy $E = \tfrac12 p^2 + \omega_0^2 (1 - \cos\theta)$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pendulum {
    omega0: f64,
}

impl Pendulum {
    /// Pendulum with small-angle angular frequency `omega0`.
    ///
    /// # Errors
    /// [`DesignError`] unless `omega0` is finite and `> 0`.
    pub fn new(omega0: f64) -> Result<Self, DesignError> {
        Ok(Self {
            omega0: DesignError::require_positive("omega0", omega0)?,
        })
    }

    /// $E = \tfrac12 p^2 + \omega_0^2 (1 - \cos\theta)$.
    pub fn energy(&self, z: &Vector2<f64>) -> f64 {
        0.5 * z[1] * z[1] + self.omega0 * self.omega0 * (1.0 - z[0].cos())
    }
}

impl VectorField<2> for Pendulum {
    fn rhs(&self, _t: f64, z: &Vector2<f64>, dz: &mut Vector2<f64>) -> Result<(), RhsError> {
        *dz = Vector2::new(z[1], -self.omega0 * self.omega0 * z[0].sin());
        Ok(())
    }
}

/// $\dot z = \begin{pmatrix} a & -b \\\\ b & a \end{pmatrix} z$, solution
/// $z(t) = e^{a t} R(b t)\, z_0$ with $R$ the rotation matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotatingDecay {
    a: f64,
    b: f64,
}

impl RotatingDecay {
    /// The system with growth rate `a` and angular velocity `b`.
    ///
    /// # Errors
    /// [`DesignError`] unless both are finite.
    pub fn new(a: f64, b: f64) -> Result<Self, DesignError> {
        Ok(Self {
            a: DesignError::require_finite("a", a)?,
            b: DesignError::require_finite("b", b)?,
        })
    }

    /// The exact solution at `t` from `z0` at 0.
    pub fn exact(&self, t: f64, z0: &Vector2<f64>) -> Vector2<f64> {
        let (s, c) = (self.b * t).sin_cos();
        Vector2::new(c * z0[0] - s * z0[1], s * z0[0] + c * z0[1]) * (self.a * t).exp()
    }
}

impl VectorField<2> for RotatingDecay {
    fn rhs(&self, _t: f64, z: &Vector2<f64>, dz: &mut Vector2<f64>) -> Result<(), RhsError> {
        *dz = Vector2::new(self.a * z[0] - self.b * z[1], self.b * z[0] + self.a * z[1]);
        Ok(())
    }
}

/// $\dot y = y^2$, solution $y(t) = y_0 / (1 - y_0 t)$, which blows up at $t = 1/y_0$.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Blowup;

impl Blowup {
    /// The exact solution at `t` from `y0` at 0 (before the blow-up).
    pub fn exact(&self, t: f64, y0: &Vector1<f64>) -> Vector1<f64> {
        y0 / (1.0 - y0[0] * t)
    }
}

impl VectorField<1> for Blowup {
    fn rhs(&self, _t: f64, z: &SVector<f64, 1>, dz: &mut SVector<f64, 1>) -> Result<(), RhsError> {
        *dz = z.component_mul(z);
        Ok(())
    }
}
