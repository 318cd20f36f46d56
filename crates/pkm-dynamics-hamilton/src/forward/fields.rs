//! The Hamilton and acceleration forms as [`VectorField`]s of dimension 13.

use crate::kernel::{acceleration_rhs, momentum_rate};
use crate::{Configuration, DynamicsError, ExtendedModel};
use nalgebra::{SVector, Vector3, Vector6};
use pkm_traits::{InvalidInput, RhsError, VectorField};

type State = SVector<f64, 13>;

/// What both forward forms share: the state layout and the diagnostics.
pub trait ForwardForm: VectorField<13> {
    /// The model.
    fn model(&self) -> &ExtendedModel;

    /// The initial state for positions `q` and velocities `qd` (work 0).
    fn initial_state(&self, q: &Vector6<f64>, qd: &Vector6<f64>) -> State;

    /// The velocities $\dot q$ at state `z`.
    ///
    /// # Errors
    /// [`RhsError`] when the saddle-point system is singular.
    fn velocity(&self, t: f64, z: &State) -> Result<Vector6<f64>, RhsError>;

    /// Positions $q$.
    fn positions(&self, z: &State) -> Vector6<f64> {
        z.fixed_rows::<6>(0).into()
    }

    /// Constraint drift $\max_i |\Phi_i| / (2 L_b)$ (m, a length error of the forearm).
    fn drift(&self, z: &State) -> f64 {
        let m = self.model();
        m.constraints(&self.positions(z)).amax() / (2.0 * m.mechanism().forearm())
    }

    /// Energy balance $E(t) - W(t)$; constant along exact solutions.
    ///
    /// # Errors
    /// As [`ForwardForm::velocity`].
    fn energy_minus_work(&self, t: f64, z: &State) -> Result<f64, RhsError> {
        let qd = self.velocity(t, z)?;
        Ok(self.model().energy(&self.positions(z), &qd) - z[12])
    }
}

/// Name of the saddle-point matrix in [`DynamicsError::Singular`].
pub const SADDLE_MATRIX: &str = "[M Phi_q^T; Phi_q 0]";

/// A failure of the forward form at time `t` as the integrator's error (the form's errors all
/// carry their time already; the integrator keeps `t` and the message).
fn rhs_error(t: f64, e: &DynamicsError) -> RhsError {
    RhsError {
        t,
        reason: e.to_string(),
    }
}

/// Solves $\begin{pmatrix} M & \Phi_q^\top \\ \Phi_q & 0\end{pmatrix} (a, b) = (r_1, r_2)$
/// at the configuration `at` through its 3×3 Schur complement (module `saddle`).
fn saddle(
    at: &Configuration<'_>,
    t: f64,
    r1: &Vector6<f64>,
    r2: &Vector3<f64>,
) -> Result<(Vector6<f64>, Vector3<f64>), DynamicsError> {
    let (a, b) = super::saddle::solve(at.model_constants(), at.legs(), r1, r2).ok_or(
        DynamicsError::Singular {
            matrix: SADDLE_MATRIX,
            t,
        },
    )?;
    // A state or torque whose products overflow (finite inputs near f64::MAX) gives a
    // non-finite solution of a regular system: an error, never `Ok(inf)`.
    if !(a.iter().all(|v| v.is_finite()) && b.iter().all(|v| v.is_finite())) {
        return Err(DynamicsError::NonFinite {
            what: "accelerations and multipliers of the saddle-point system",
            t,
        });
    }
    Ok((a, b))
}

fn joint_force(tau: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(0.0, 0.0, 0.0, tau.x, tau.y, tau.z)
}

fn finite(t: f64, dz: &State) -> Result<(), RhsError> {
    if dz.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(RhsError {
            t,
            reason: "non-finite derivative".to_owned(),
        })
    }
}

/// A Baumgarte gain `value` named `setting`, checked finite and $\ge 0$.
fn baumgarte_gain(setting: &'static str, value: f64) -> Result<f64, DynamicsError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(InvalidInput::new(setting, value, "a Baumgarte gain must be finite and >= 0").into())
    }
}

/// Eqs. 16–19 with velocity-level Baumgarte gain $\kappa$ (1/s; 0 = unstabilised).
#[derive(Debug, Clone)]
pub struct HamiltonForm<'a, F> {
    model: &'a ExtendedModel,
    torque: F,
    kappa: f64,
}

impl<'a, F: Fn(f64) -> Vector3<f64>> HamiltonForm<'a, F> {
    /// The Hamilton form of `model` under motor torques `torque` $= \tau(t)$ with Baumgarte
    /// gain `kappa` $= \kappa$ (1/s; 0 = unstabilised).
    ///
    /// # Errors
    /// [`DynamicsError::Invalid`] (name `"kappa"`) for a gain that is NaN, infinite or
    /// negative.
    ///
    /// ```
    /// # use pkm_dynamics_hamilton::{ExtendedModel, MassParameters, DynamicsError};
    /// # use pkm_dynamics_hamilton::forward::HamiltonForm;
    /// # use pkm_mechanisms::{Placement, RotaryDelta, presets};
    /// # use nalgebra::Vector3;
    /// let delta = RotaryDelta::new(presets::nuwar(Placement::canonical()))?;
    /// let model = ExtendedModel::new(delta, &MassParameters::miller2004())?;
    /// assert!(HamiltonForm::new(&model, |_| Vector3::zeros(), 20.0).is_ok());
    /// assert!(HamiltonForm::new(&model, |_| Vector3::zeros(), -1.0).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(model: &'a ExtendedModel, torque: F, kappa: f64) -> Result<Self, DynamicsError> {
        Ok(Self {
            model,
            torque,
            kappa: baumgarte_gain("kappa", kappa)?,
        })
    }

    /// The Baumgarte gain $\kappa$ (1/s).
    pub fn kappa(&self) -> f64 {
        self.kappa
    }

    /// The velocities $\dot q$ and multipliers $\sigma$ at state `z` (eq. 19 with Baumgarte).
    ///
    /// # Errors
    /// [`DynamicsError::Singular`] (matrix [`SADDLE_MATRIX`], time `t`) when the saddle-point
    /// matrix is singular, e.g. where $\Phi_q$ loses rank; [`DynamicsError::NonFinite`] when the
    /// solution overflows (a state or torque near `f64::MAX`). Inside an integration the same failure
    /// arrives as [`pkm_traits::IntegrationError::Rhs`] with this error's message and time.
    pub fn solve(&self, t: f64, z: &State) -> Result<(Vector6<f64>, Vector3<f64>), DynamicsError> {
        self.solve_at(&self.model.at(&self.positions(z)), t, z)
    }

    fn solve_at(
        &self,
        at: &Configuration<'_>,
        t: f64,
        z: &State,
    ) -> Result<(Vector6<f64>, Vector3<f64>), DynamicsError> {
        let p: Vector6<f64> = z.fixed_rows::<6>(6).into();
        let (qd, minus_sigma) = saddle(at, t, &p, &(-at.constraints() * self.kappa))?;
        Ok((qd, -minus_sigma))
    }
}

impl<F: Fn(f64) -> Vector3<f64>> VectorField<13> for HamiltonForm<'_, F> {
    /// $\dot q$ from eq. 19, $\dot p = L_q + Q - \dot\Phi_q^\top\sigma$ (eq. 17), all from one
    /// [`Configuration`].
    fn rhs(&self, t: f64, z: &State, dz: &mut State) -> Result<(), RhsError> {
        let at = self.model.at(&self.positions(z));
        let (qd, sigma) = self.solve_at(&at, t, z).map_err(|e| rhs_error(t, &e))?;
        let tau = (self.torque)(t);
        let pd = momentum_rate(at.model_constants(), at.legs(), &qd, &sigma) + joint_force(&tau);
        dz.fixed_rows_mut::<6>(0).copy_from(&qd);
        dz.fixed_rows_mut::<6>(6).copy_from(&pd);
        dz[12] = tau.dot(&qd.fixed_rows::<3>(3));
        finite(t, dz)
    }
}

impl<F: Fn(f64) -> Vector3<f64>> ForwardForm for HamiltonForm<'_, F> {
    fn model(&self) -> &ExtendedModel {
        self.model
    }

    /// $p = M\dot q$ ($\sigma(0) = 0$).
    fn initial_state(&self, q: &Vector6<f64>, qd: &Vector6<f64>) -> State {
        let p = self.model.mass_matrix(q) * qd;
        State::from_iterator(q.iter().chain(p.iter()).copied().chain([0.0]))
    }

    fn velocity(&self, t: f64, z: &State) -> Result<Vector6<f64>, RhsError> {
        Ok(self.solve(t, z).map_err(|e| rhs_error(t, &e))?.0)
    }
}

/// The acceleration form with Baumgarte gain $\omega$ (1/s; 0 = unstabilised).
#[derive(Debug, Clone)]
pub struct AccelerationForm<'a, F> {
    model: &'a ExtendedModel,
    torque: F,
    omega: f64,
}

impl<'a, F: Fn(f64) -> Vector3<f64>> AccelerationForm<'a, F> {
    /// The acceleration form of `model` under motor torques `torque` $= \tau(t)$ with Baumgarte
    /// gain `omega` $= \omega$ (1/s; 0 = unstabilised).
    ///
    /// # Errors
    /// [`DynamicsError::Invalid`] (name `"omega"`) for a gain that is NaN, infinite or
    /// negative.
    pub fn new(model: &'a ExtendedModel, torque: F, omega: f64) -> Result<Self, DynamicsError> {
        Ok(Self {
            model,
            torque,
            omega: baumgarte_gain("omega", omega)?,
        })
    }

    /// The Baumgarte gain $\omega$ (1/s).
    pub fn omega(&self) -> f64 {
        self.omega
    }

    /// The accelerations $\ddot q$ and multipliers $\lambda$ at state `z` under the torque
    /// `tau`.
    ///
    /// # Errors
    /// As [`HamiltonForm::solve`].
    pub fn solve(
        &self,
        t: f64,
        z: &State,
        tau: &Vector3<f64>,
    ) -> Result<(Vector6<f64>, Vector3<f64>), DynamicsError> {
        let at = self.model.at(&self.positions(z));
        let qd: Vector6<f64> = z.fixed_rows::<6>(6).into();
        let (r1, r2) = acceleration_rhs(at.model_constants(), at.legs(), &qd, self.omega);
        saddle(&at, t, &(r1 + joint_force(tau)), &r2)
    }
}

impl<F: Fn(f64) -> Vector3<f64>> VectorField<13> for AccelerationForm<'_, F> {
    fn rhs(&self, t: f64, z: &State, dz: &mut State) -> Result<(), RhsError> {
        let qd: Vector6<f64> = z.fixed_rows::<6>(6).into();
        let tau = (self.torque)(t);
        let (qdd, _) = self.solve(t, z, &tau).map_err(|e| rhs_error(t, &e))?;
        dz.fixed_rows_mut::<6>(0).copy_from(&qd);
        dz.fixed_rows_mut::<6>(6).copy_from(&qdd);
        dz[12] = tau.dot(&qd.fixed_rows::<3>(3));
        finite(t, dz)
    }
}

impl<F: Fn(f64) -> Vector3<f64>> ForwardForm for AccelerationForm<'_, F> {
    fn model(&self) -> &ExtendedModel {
        self.model
    }

    fn initial_state(&self, q: &Vector6<f64>, qd: &Vector6<f64>) -> State {
        State::from_iterator(q.iter().chain(qd.iter()).copied().chain([0.0]))
    }

    fn velocity(&self, _t: f64, z: &State) -> Result<Vector6<f64>, RhsError> {
        Ok(z.fixed_rows::<6>(6).into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MassParameters;
    use pkm_mechanisms::{Placement, RotaryDelta, presets};
    use pkm_traits::IntegrationError;

    /// The Delta (α = β = 0) with all three forearm vectors $v_i = C_i - B_i$ zero: the plate on
    /// the vertical axis with every elbow on it, $\cos\theta = (r - R)/L_a$. Then $\Phi_q = 0$ and
    /// the saddle-point matrix has rank 6.
    fn collapsed() -> (ExtendedModel, State) {
        let delta = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
        let model = ExtendedModel::new(delta, &MassParameters::miller2004()).unwrap();
        let theta = ((0.03f64 - 0.194) / 0.26).acos();
        let z = -0.2928 - 0.26 * theta.sin();
        let q = Vector6::new(0.0, 0.0, z, theta, theta, theta);
        let v = model
            .mechanism()
            .forearm_vector(0, &q.fixed_rows::<3>(0).into(), theta);
        assert!(v.norm() < 1e-15, "{v}");
        let z = State::from_iterator(q.iter().copied().chain([0.0; 7]));
        (model, z)
    }

    #[test]
    fn a_singular_saddle_matrix_is_a_typed_error() {
        let (model, z) = collapsed();
        let h = HamiltonForm::new(&model, |_| Vector3::zeros(), 0.0).unwrap();
        assert_eq!(
            h.solve(0.25, &z).unwrap_err(),
            DynamicsError::Singular {
                matrix: SADDLE_MATRIX,
                t: 0.25
            }
        );
        let a = AccelerationForm::new(&model, |_| Vector3::zeros(), 0.0).unwrap();
        assert!(matches!(
            a.solve(0.5, &z, &Vector3::zeros()),
            Err(DynamicsError::Singular { matrix: SADDLE_MATRIX, t }) if (t - 0.5).abs() < 1e-15
        ));
        // Through an integrator: the failed evaluation, with time and matrix.
        let settings = pkm_integrators::AdaptiveSettings::default();
        let err = pkm_integrators::integrate(
            &h,
            &mut pkm_integrators::DormandPrince54::new(settings),
            (0.0, 0.1),
            &z,
            &pkm_integrators::OutputTimes::Uniform(0.01),
            &pkm_traits::Silent,
        )
        .unwrap_err();
        let IntegrationError::Rhs(RhsError { t, reason }) = err else {
            panic!("expected a RHS failure, got {err:?}");
        };
        assert!(
            t.abs() < 1e-15 && reason.contains(SADDLE_MATRIX),
            "{t} {reason}"
        );
    }

    #[test]
    fn the_canonical_start_is_far_from_singular() {
        let model = ExtendedModel::new(
            RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
            &MassParameters::miller2004(),
        )
        .unwrap();
        let s = model
            .joint_motion(
                &Vector3::new(0.0, -0.2, -0.9),
                &Vector3::zeros(),
                &Vector3::zeros(),
            )
            .unwrap();
        let h = HamiltonForm::new(&model, |_| Vector3::zeros(), 0.0).unwrap();
        let (qd, _) = h.solve(0.0, &h.initial_state(&s.q, &s.qd)).unwrap();
        assert!(qd.amax() < 1e-12);
    }

    #[test]
    fn baumgarte_gains_must_be_finite_and_non_negative() {
        let model = ExtendedModel::new(
            RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
            &MassParameters::miller2004(),
        )
        .unwrap();
        let torque = |_: f64| Vector3::zeros();
        for bad in [
            f64::NAN,
            -1.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            -f64::MIN_POSITIVE,
        ] {
            let e = HamiltonForm::new(&model, torque, bad).err();
            assert!(
                matches!(e, Some(DynamicsError::Invalid(InvalidInput { name: "kappa", value, .. }))
                    if value.to_bits() == bad.to_bits()),
                "{e:?}"
            );
            let e = AccelerationForm::new(&model, torque, bad).err();
            assert!(
                matches!(e, Some(DynamicsError::Invalid(InvalidInput { name: "omega", value, .. }))
                    if value.to_bits() == bad.to_bits()),
                "{e:?}"
            );
        }
        for good in [0.0, 20.0, 1e300] {
            let h = HamiltonForm::new(&model, torque, good).unwrap();
            assert_eq!(h.kappa().to_bits(), good.to_bits());
            let a = AccelerationForm::new(&model, torque, good).unwrap();
            assert_eq!(a.omega().to_bits(), good.to_bits());
        }
    }
}
