//! The Hamilton and acceleration forms as [`VectorField`]s of dimension 13.

use crate::ExtendedModel;
use nalgebra::{SMatrix, SVector, Vector3, Vector6};
use pkm_traits::{RhsError, VectorField};

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

/// Solves $\begin{pmatrix} M & \Phi_q^\top \\ \Phi_q & 0\end{pmatrix} (a, b) = (r_1, r_2)$.
fn saddle(
    m: &ExtendedModel,
    t: f64,
    q: &Vector6<f64>,
    r1: &Vector6<f64>,
    r2: &Vector3<f64>,
) -> Result<(Vector6<f64>, Vector3<f64>), RhsError> {
    let phi_q = m.constraint_jacobian(q);
    let mut a = SMatrix::<f64, 9, 9>::zeros();
    a.fixed_view_mut::<6, 6>(0, 0).copy_from(&m.mass_matrix(q));
    a.fixed_view_mut::<6, 3>(0, 6).copy_from(&phi_q.transpose());
    a.fixed_view_mut::<3, 6>(6, 0).copy_from(&phi_q);
    let rhs = SVector::<f64, 9>::from_iterator(r1.iter().chain(r2.iter()).copied());
    let x = a.lu().solve(&rhs).ok_or_else(|| RhsError {
        t,
        reason: "[M Phi_q^T; Phi_q 0] is singular".to_owned(),
    })?;
    Ok((x.fixed_rows::<6>(0).into(), x.fixed_rows::<3>(6).into()))
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

/// Eqs. 16–19 with velocity-level Baumgarte gain $\kappa$ (1/s; 0 = unstabilised).
#[derive(Debug, Clone)]
pub struct HamiltonForm<'a, F> {
    /// The model.
    pub model: &'a ExtendedModel,
    /// Motor torques $\tau(t)$.
    pub torque: F,
    /// Baumgarte gain $\kappa$.
    pub kappa: f64,
}

impl<F: Fn(f64) -> Vector3<f64>> HamiltonForm<'_, F> {
    fn solve(&self, t: f64, z: &State) -> Result<(Vector6<f64>, Vector3<f64>), RhsError> {
        let q = self.positions(z);
        let p: Vector6<f64> = z.fixed_rows::<6>(6).into();
        let (qd, minus_sigma) = saddle(
            self.model,
            t,
            &q,
            &p,
            &(-self.model.constraints(&q) * self.kappa),
        )?;
        Ok((qd, -minus_sigma))
    }
}

impl<F: Fn(f64) -> Vector3<f64>> VectorField<13> for HamiltonForm<'_, F> {
    fn rhs(&self, t: f64, z: &State, dz: &mut State) -> Result<(), RhsError> {
        let q = self.positions(z);
        let (qd, sigma) = self.solve(t, z)?;
        let tau = (self.torque)(t);
        let pd = self.model.lagrangian_gradient(&q, &qd) + joint_force(&tau)
            - self.model.constraint_jacobian_rate(&q, &qd).transpose() * sigma;
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
        Ok(self.solve(t, z)?.0)
    }
}

/// The acceleration form with Baumgarte gain $\omega$ (1/s; 0 = unstabilised).
#[derive(Debug, Clone)]
pub struct AccelerationForm<'a, F> {
    /// The model.
    pub model: &'a ExtendedModel,
    /// Motor torques $\tau(t)$.
    pub torque: F,
    /// Baumgarte gain $\omega$.
    pub omega: f64,
}

impl<F: Fn(f64) -> Vector3<f64>> VectorField<13> for AccelerationForm<'_, F> {
    fn rhs(&self, t: f64, z: &State, dz: &mut State) -> Result<(), RhsError> {
        let m = self.model;
        let q = self.positions(z);
        let qd: Vector6<f64> = z.fixed_rows::<6>(6).into();
        let tau = (self.torque)(t);
        let r1 = m.lagrangian_gradient(&q, &qd) + joint_force(&tau)
            - m.mass_matrix_rate_times_velocity(&q, &qd);
        let w = self.omega;
        let r2 = -m.gamma(&q, &qd)
            - m.constraint_jacobian(&q) * qd * (2.0 * w)
            - m.constraints(&q) * (w * w);
        let (qdd, _) = saddle(m, t, &q, &r1, &r2)?;
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
