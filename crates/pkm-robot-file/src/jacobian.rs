//! Jacobians from screws (Joshi & Tsai 2002; `spec/general-robots.md` §2a) and the three
//! singularity margins.
//!
//! At a configuration, leg $i$ has unit joint twists $\$_{i,j}$. Its **actuation wrench**
//! $w_{a,i}$ is reciprocal to all its passive twists and does work on its actuator; its
//! **constraint wrenches** $w_{c,i,k}$ are reciprocal to all its twists. For a platform twist
//! $t$: $w_{a,i} \wedge t = (w_{a,i} \wedge \$_{i,a})\,\dot q_i$ and $w_{c,i,k} \wedge t = 0$,
//! so $[J_a; J_c]\,t = [D\dot q; 0]$ with $D = \mathrm{diag}(w_{a,i} \wedge \$_{i,a})$.
//! With $t = T\dot x$ ($T$ maps the task rates to the platform twist, the dependent rates solved
//! from $J_c t = 0$), the velocity Jacobian is $J = D^{-1} J_a T$ ($\dot q = J\dot x$).

use crate::chain::stack;
use crate::closure::Configuration;
use crate::mobility::{RANK_TOLERANCE, constraint_wrenches};
use crate::model::RobotModel;
use crate::pose::{CoordinateRole, hybrid_rates};
use crate::svd::bounded_svd;
use nalgebra::{DMatrix, DVector, Matrix6, Vector3, Vector6};
use pkm_screw_theory::{reciprocal_product_vectors, reciprocal_screw_system};
use pkm_traits::KinematicsError;

/// The screw-theory Jacobians at one configuration. Wrenches are `[f; m_O]`, twists
/// `[ω; v_O]`, moments about the world origin.
#[derive(Debug, Clone, PartialEq)]
pub struct ScrewJacobians {
    /// $J_a$: one actuation wrench per leg (row), unit force (or unit couple when it has no
    /// force), `n × 6`.
    pub j_a: DMatrix<f64>,
    /// $J_c$: every leg's constraint wrenches (rows, unit norm), `k × 6`.
    pub j_c: DMatrix<f64>,
    /// $D_{ii} = w_{a,i} \wedge \$_{i,a}$: the work of the actuation wrench on the actuator's
    /// unit twist (m for a revolute actuator, 1 for a prismatic one).
    pub d: DVector<f64>,
    /// $T$: the platform twist per unit rate of each task coordinate, `6 × n`.
    pub t: DMatrix<f64>,
    /// $J = D^{-1} J_a T$, `n × n`: $\dot q = J \dot x$.
    pub j: DMatrix<f64>,
}

/// The three singularity margins at a pose, each the smallest singular value of its matrix,
/// homogenised with the characteristic length $L$ (rotations as $L\omega$, moments as
/// $m/L$, revolute actuators' $D_{ii}/L$).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingularityMargins {
    /// Inverse-kinematic (type I, serial): $\min_i |D_{ii}|$, 0 where a leg is stretched out
    /// or folded.
    pub inverse: f64,
    /// Direct (type II, parallel): $\sigma_{\min}$ of $[J_a; J_c]$ on the non-idle twists.
    pub direct: f64,
    /// Constraint: $\sigma_{6-n-\text{idle}}$ of $J_c$; `None` for a robot without constraint
    /// wrenches (six task coordinates).
    pub constraint: Option<f64>,
}

/// Unit twists of leg `i`'s joints: the actuated ones (in joint order; none for a passive
/// leg), and the passive ones.
fn leg_twists(
    model: &RobotModel,
    config: &Configuration,
    i: usize,
) -> (Vec<Vector6<f64>>, Vec<Vector6<f64>>) {
    let leg = &model.legs[i];
    let lt = leg.twists(&config.joints[i]);
    let (actuated, passive): (Vec<_>, Vec<_>) = lt
        .twists
        .into_iter()
        .partition(|(j, _)| leg.is_actuated(*j));
    let twists = |v: Vec<(usize, Vector6<f64>)>| v.into_iter().map(|(_, t)| t).collect();
    (twists(actuated), twists(passive))
}

/// The actuation wrench: in the span reciprocal to the leg's other twists (its passive ones
/// and its other actuators'), the direction that does the most work on the actuator twist
/// (constraint wrenches do none), normalised.
fn actuation_wrench(actuator: &Vector6<f64>, passive: &[Vector6<f64>]) -> Option<Vector6<f64>> {
    let basis = reciprocal_screw_system(passive, RANK_TOLERANCE).ok()?;
    let w: Vector6<f64> = basis
        .iter()
        .map(|n| n * reciprocal_product_vectors(n, actuator))
        .sum();
    normalise_wrench(&w)
}

/// The actuation wrench of a leg of six coordinates (one actuator, five passive twists) whose
/// twists are independent, from one 6 × 6 solve: with $\Delta$ the swap of a twist's halves
/// ($w \odot t = w\cdot\Delta t$), the rows $(\Delta\$_k)^\top$ of the passive twists and
/// of the actuator's, $R\,w = e_6$ gives the wrench reciprocal to every passive twist that
/// does unit work on the actuator, normalised as [`actuation_wrench`] does (its reciprocal
/// system is one-dimensional, so both give the same wrench). `None` unless the twists are
/// clearly independent (LU pivots within 1e-6 of each other; nearer a leg singularity the
/// SVD of [`actuation_wrench`] decides the rank).
fn six_twist_actuation(
    actuated: &[Vector6<f64>],
    passive: &[Vector6<f64>],
) -> Option<Vector6<f64>> {
    let ([actuator], 5) = (actuated, passive.len()) else {
        return None;
    };
    let swap = |t: &Vector6<f64>| Vector6::new(t[3], t[4], t[5], t[0], t[1], t[2]).transpose();
    let rows = Matrix6::from_fn(|r, c| {
        let t = passive.get(r).unwrap_or(actuator);
        swap(t)[c]
    });
    let lu = rows.lu();
    let pivots = lu.u().diagonal().abs();
    if !(pivots.min() > 1e-6 * pivots.max()) {
        return None;
    }
    let w = lu.solve(&Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, 1.0))?;
    normalise_wrench(&w)
}

/// Unit force, or unit couple for a pure couple; `None` for a (numerically) zero wrench.
fn normalise_wrench(w: &Vector6<f64>) -> Option<Vector6<f64>> {
    let f = w.fixed_rows::<3>(0).norm();
    let scale = if f > 1e-9 * w.norm() { f } else { w.norm() };
    (scale > 1e-300 && scale.is_finite()).then(|| w / scale)
}

impl RobotModel {
    /// The screw-theory Jacobians at a solved configuration.
    ///
    /// # Errors
    /// [`KinematicsError::Singular`] when a leg has no actuation wrench (its passive twists
    /// span all six) or the dependent rates cannot be solved from $J_c$; `"D"` when an
    /// actuator's $D_{ii}$ vanishes (an inverse-kinematic singularity).
    pub fn screw_jacobians(
        &self,
        config: &Configuration,
    ) -> Result<ScrewJacobians, KinematicsError> {
        self.check_configuration(config)?;
        let n = self.actuator_count();
        let mut j_a = DMatrix::zeros(n, 6);
        let mut d = DVector::zeros(n);
        let mut constraints = Vec::new();
        for i in self.actuated..self.legs.len() {
            // A passive leg: constraint wrenches only.
            constraints.extend(constraint_wrenches(&leg_twists(self, config, i).1));
        }
        let mut row = 0;
        for i in 0..self.actuated {
            let (actuated, passive) = leg_twists(self, config, i);
            if let ([actuator], Some(w)) = (
                actuated.as_slice(),
                six_twist_actuation(&actuated, &passive),
            ) {
                // Six independent twists: no constraint wrench.
                j_a.set_row(row, &w.transpose());
                d[row] = reciprocal_product_vectors(&w, actuator);
                row += 1;
                continue;
            }
            for (k, actuator) in actuated.iter().enumerate() {
                let mut others = passive.clone();
                others.extend(
                    actuated
                        .iter()
                        .enumerate()
                        .filter(|&(l, _)| l != k)
                        .map(|(_, t)| *t),
                );
                let w = actuation_wrench(actuator, &others).ok_or(KinematicsError::Singular {
                    matrix: "actuation wrench",
                    sigma_min: 0.0,
                })?;
                j_a.set_row(row, &w.transpose());
                d[row] = reciprocal_product_vectors(&w, actuator);
                row += 1;
            }
            let mut all = passive;
            all.extend(actuated);
            constraints.extend(constraint_wrenches(&all));
        }
        let j_c = DMatrix::from_fn(constraints.len(), 6, |r, c| constraints[r][c]);
        let t = self.task_twists(config, &j_c)?;
        let min_d = d.iter().map(|v| v.abs()).fold(f64::INFINITY, f64::min);
        if !(min_d > 1e-12 * self.size) {
            return Err(KinematicsError::Singular {
                matrix: "D",
                sigma_min: min_d,
            });
        }
        let mut j = &j_a * reciprocal_swap(&t);
        for (mut row, di) in j.row_iter_mut().zip(d.iter()) {
            row /= *di;
        }
        if !j.iter().all(|v| v.is_finite()) {
            return Err(KinematicsError::Singular {
                matrix: "J",
                sigma_min: 0.0,
            });
        }
        Ok(ScrewJacobians { j_a, j_c, d, t, j })
    }

    /// $T$: the platform twist `[ω; v_O]` per unit rate of each task coordinate, with the
    /// dependent coordinates' rates from $J_c t = 0$ (least squares on the rank of $J_c$).
    fn task_twists(
        &self,
        config: &Configuration,
        j_c: &DMatrix<f64>,
    ) -> Result<DMatrix<f64>, KinematicsError> {
        let h = hybrid_rates(self.orientation, &config.pose);
        let p = Vector3::new(config.pose[0], config.pose[1], config.pose[2]);
        let twist_of = |k: usize| {
            let w: Vector3<f64> = h.fixed_view::<3, 1>(0, k).into();
            let pd: Vector3<f64> = h.fixed_view::<3, 1>(3, k).into();
            stack(&w, &(pd - w.cross(&p)))
        };
        let task = DMatrix::from_fn(6, self.task.len(), |r, c| twist_of(self.task[c])[r]);
        let dependent: Vec<usize> = (0..6)
            .filter(|&k| self.roles[k] == CoordinateRole::Dependent)
            .collect();
        if dependent.is_empty() {
            return Ok(task);
        }
        let dep = DMatrix::from_fn(6, dependent.len(), |r, c| twist_of(dependent[c])[r]);
        // J_c Δ (T_task + T_dep R) = 0  ⇒  R = −(J_c Δ T_dep)⁺ J_c Δ T_task.
        let a = j_c * reciprocal_swap(&dep);
        let b = j_c * reciprocal_swap(&task);
        let svd = bounded_svd(a, true, true).ok_or(KinematicsError::Singular {
            matrix: "J_c T_dep",
            sigma_min: f64::NAN,
        })?;
        let smallest = svd
            .singular_values
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        if !(smallest > 1e-9 * svd.singular_values.amax()) {
            return Err(KinematicsError::Singular {
                matrix: "J_c T_dep",
                sigma_min: smallest,
            });
        }
        let rates = svd
            .solve(&(-b), 0.0)
            .map_err(|_| KinematicsError::Singular {
                matrix: "J_c T_dep",
                sigma_min: smallest,
            })?;
        Ok(task + dep * rates)
    }

    /// The three singularity margins at a configuration (see [`SingularityMargins`]).
    ///
    /// # Errors
    /// As [`RobotModel::screw_jacobians`], except that a vanishing $D_{ii}$ is a margin of 0.
    pub fn singularity_margins(
        &self,
        config: &Configuration,
    ) -> Result<SingularityMargins, KinematicsError> {
        let jac = match self.screw_jacobians(config) {
            Ok(j) => j,
            Err(KinematicsError::Singular { .. }) => {
                return Ok(SingularityMargins {
                    inverse: 0.0,
                    direct: 0.0,
                    constraint: Some(0.0),
                });
            }
            Err(e) => return Err(e),
        };
        let l = self.characteristic_length;
        let inverse = (0..self.actuator_count())
            .map(|i| {
                let (leg, actuator) = self.actuator(i);
                let revolute = matches!(
                    self.legs[leg].joints[actuator.joint],
                    crate::chain::Joint::Revolute { .. }
                );
                jac.d[i].abs() / if revolute { l } else { 1.0 }
            })
            .fold(f64::INFINITY, f64::min);
        let p = Vector3::new(config.pose[0], config.pose[1], config.pose[2]);
        let homogenise = |m: &DMatrix<f64>| homogenised_rows(m, &p, l);
        let free = self.non_idle_basis(config, l);
        let direct_matrix = stack_rows(&homogenise(&jac.j_a), &homogenise(&jac.j_c)) * &free;
        let direct = smallest_singular_value(&direct_matrix, free.ncols());
        let expected = free.ncols().saturating_sub(self.dof());
        let constraint = (expected > 0).then(|| {
            let j_c = homogenise(&jac.j_c);
            let k = expected.min(j_c.nrows());
            if k < expected {
                return 0.0;
            }
            singular_value(j_c, k)
        });
        Ok(SingularityMargins {
            inverse,
            direct,
            constraint,
        })
    }

    /// An orthonormal basis (homogenised twist coordinates $[v_p; L\omega]$) of the twists that
    /// do not move the idle coordinates, `6 × (6 − idle)`.
    fn non_idle_basis(&self, config: &Configuration, l: f64) -> DMatrix<f64> {
        let h = hybrid_rates(self.orientation, &config.pose);
        let idle: Vec<usize> = (0..6)
            .filter(|&k| self.roles[k] == CoordinateRole::Idle)
            .collect();
        // Homogenised idle twists: [ṗ_k; L ω_k] (velocity of the platform origin).
        let rows: Vec<Vector6<f64>> = idle
            .iter()
            .map(|&k| {
                let c = h.column(k);
                Vector6::new(c[3], c[4], c[5], l * c[0], l * c[1], l * c[2])
            })
            .collect();
        let mut basis = DMatrix::identity(6, 6);
        if !rows.is_empty() {
            // Zero rows pad A to 6 × 6, so that the SVD returns all six right singular vectors.
            let a = DMatrix::from_fn(6, 6, |r, c| rows.get(r).map_or(0.0, |row| row[c]));
            if let Some(v_t) = bounded_svd(a.clone(), false, true).and_then(|svd| {
                let v_t = svd.v_t?;
                Some((svd.singular_values, v_t))
            }) {
                let (singular_values, v_t) = v_t;
                let mut order: Vec<usize> = (0..6).collect();
                order.sort_by(|&i, &j| singular_values[j].total_cmp(&singular_values[i]));
                let complement: Vec<_> = order[rows.len()..]
                    .iter()
                    .map(|&k| v_t.row(k).transpose())
                    .collect();
                basis = DMatrix::from_columns(&complement);
            }
        }
        basis
    }
}

/// $\Delta T$: swaps the halves of each column, so that $J_a \Delta T$ is the reciprocal product.
fn reciprocal_swap(t: &DMatrix<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(t.nrows(), t.ncols(), |r, c| t[((r + 3) % 6, c)])
}

/// Wrench rows `[f; m_O]` as homogenised rows `[f; m_p / L]` acting on $[v_p; L\omega]$,
/// each of unit norm.
fn homogenised_rows(m: &DMatrix<f64>, p: &Vector3<f64>, l: f64) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(m.nrows(), 6);
    for (r, row) in m.row_iter().enumerate() {
        let f = Vector3::new(row[0], row[1], row[2]);
        let m_o = Vector3::new(row[3], row[4], row[5]);
        let m_p = m_o - p.cross(&f);
        let h = stack(&f, &(m_p / l));
        let norm = h.norm();
        if norm > 0.0 {
            out.set_row(r, &(h / norm).transpose());
        }
    }
    out
}

fn stack_rows(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(a.nrows() + b.nrows(), a.ncols());
    out.rows_mut(0, a.nrows()).copy_from(a);
    out.rows_mut(a.nrows(), b.nrows()).copy_from(b);
    out
}

/// The `k`-th largest singular value (the smallest of a full-rank `· × k` matrix), 0 when the
/// matrix has fewer than `k` rows or its SVD cannot be computed ([`bounded_svd`]).
fn smallest_singular_value(m: &DMatrix<f64>, k: usize) -> f64 {
    if m.nrows() < k || k == 0 {
        return 0.0;
    }
    singular_value(m.clone(), k)
}

/// The `k`-th largest singular value of `m` (`k` ≥ 1), 0 when there is none or the SVD fails.
fn singular_value(m: DMatrix<f64>, k: usize) -> f64 {
    let Some(svd) = bounded_svd(m, false, false) else {
        return 0.0;
    };
    let mut sv: Vec<f64> = svd.singular_values.iter().copied().collect();
    sv.sort_by(|a, b| b.total_cmp(a));
    k.checked_sub(1)
        .and_then(|i| sv.get(i).copied())
        .unwrap_or(0.0)
}
