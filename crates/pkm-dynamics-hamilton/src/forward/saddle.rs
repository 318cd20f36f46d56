//! The saddle-point system of eq. 19 solved through its block structure.
//!
//! $$ \begin{pmatrix} M & \Phi_q^\top \\ \Phi_q & 0 \end{pmatrix}
//!    \begin{pmatrix} a \\ b \end{pmatrix} = \begin{pmatrix} r_1 \\ r_2 \end{pmatrix},\qquad
//!    M = \begin{pmatrix} m_t I & K \\ K^\top & J I \end{pmatrix},\quad
//!    \Phi_q = (\Phi_x \;\; \Phi_\theta),\quad K_{:,i} = k\,d_i',\quad
//!    \Phi_\theta = \mathrm{diag}(\phi_i). $$
//!
//! Eliminating the joint rows ($J I$ is diagonal), $a_\theta = (r_{1\theta} - K^\top a_x -
//! \Phi_\theta b)/J$, leaves
//! $$ A a_x + B^\top b = r_{1x} - K r_{1\theta}/J, \qquad B a_x - D b = r_2 - \Phi_\theta
//!    r_{1\theta}/J, $$
//! with $A = m_t I - K K^\top/J$ (the Schur complement of $J I$ in $M$, positive definite with
//! $M$), $B = \Phi_x - \Phi_\theta K^\top/J$ (row $i$: $2v_i - (\phi_i k/J) d_i'$) and
//! $D = \Phi_\theta^2/J$. Eliminating $a_x$ gives the 3×3 Schur complement
//! $$ S = B A^{-1} B^\top + D = \Phi_q M^{-1}\Phi_q^\top, \qquad
//!    S b = B A^{-1}(r_{1x} - K r_{1\theta}/J) - (r_2 - \Phi_\theta r_{1\theta}/J), $$
//! symmetric positive definite exactly when $\Phi_q$ has full rank. Both 3×3 systems are solved
//! by $LDL^\top$ factorisations. The saddle-point matrix counts as singular when a pivot of $S$
//! is at most $9\varepsilon \max(\max_i S_{ii},\, 4L_b^2/m_t)$, i.e. zero to working precision:
//! $S$ is formed with a relative error of a few $\varepsilon$, and on the constraint manifold the
//! rows $2v_i$ of $\Phi_x$ have length $2L_b$, so $4L_b^2/m_t$ is the size $S$ has away from
//! singularities (this keeps a $\Phi_q$ that is zero up to rounding singular; on the canonical
//! cycle the smallest pivot of $S$ is of order 1).

use crate::kernel::{Constants, Leg, dot};
use nalgebra::{Matrix3, Vector3, Vector6};

/// $LDL^\top$ of a symmetric 3×3 matrix (unit lower $L$, pivots $D$).
struct Ldl {
    l10: f64,
    l20: f64,
    l21: f64,
    pivots: Vector3<f64>,
}

impl Ldl {
    /// Factorises `a`; `None` when a pivot is at most `9 ε max(max_i a_ii, scale)` (or not a
    /// number).
    fn new(a: &Matrix3<f64>, scale: f64) -> Option<Self> {
        let d0 = a[(0, 0)];
        let (l10, l20) = (a[(1, 0)] / d0, a[(2, 0)] / d0);
        let d1 = a[(1, 1)] - l10 * a[(1, 0)];
        let a21 = a[(2, 1)] - l20 * a[(1, 0)];
        let l21 = a21 / d1;
        let d2 = a[(2, 2)] - l20 * a[(2, 0)] - l21 * a21;
        let threshold = 9.0 * f64::EPSILON * a[(0, 0)].max(a[(1, 1)]).max(a[(2, 2)]).max(scale);
        let pivots = Vector3::new(d0, d1, d2);
        pivots.iter().all(|d| *d > threshold).then_some(Self {
            l10,
            l20,
            l21,
            pivots,
        })
    }

    fn solve(&self, b: &Vector3<f64>) -> Vector3<f64> {
        let y1 = b.y - self.l10 * b.x;
        let y2 = b.z - self.l20 * b.x - self.l21 * y1;
        let z = Vector3::new(b.x, y1, y2).component_div(&self.pivots);
        let x2 = z.z;
        let x1 = z.y - self.l21 * x2;
        let x0 = z.x - self.l10 * x1 - self.l20 * x2;
        Vector3::new(x0, x1, x2)
    }
}

/// Solves the saddle-point system for `(a, b)`; `None` when it is singular.
pub(crate) fn solve(
    k: &Constants,
    legs: &[Leg<f64>; 3],
    r1: &Vector6<f64>,
    r2: &Vector3<f64>,
) -> Option<(Vector6<f64>, Vector3<f64>)> {
    let inv_j = 1.0 / k.j;
    let k_over_j = k.k * inv_j;
    let mut a = Matrix3::from_diagonal_element(k.m_t);
    let mut r1x = Vector3::new(r1[0], r1[1], r1[2]);
    let mut rows = [Vector3::zeros(); 3];
    let mut r2p = Vector3::zeros();
    for (i, leg) in legs.iter().enumerate() {
        a -= (leg.d1 * k_over_j * k.k) * leg.d1.transpose();
        r1x -= leg.d1 * (k_over_j * r1[3 + i]);
        rows[i] = leg.v * 2.0 - leg.d1 * (leg.phi_theta * k_over_j);
        r2p[i] = r2[i] - leg.phi_theta * r1[3 + i] * inv_j;
    }
    let a = Ldl::new(&a, 0.0)?;
    let columns = rows.map(|row| a.solve(&row));
    let y = a.solve(&r1x);
    let mut s = Matrix3::zeros();
    for i in 0..3 {
        for j in 0..=i {
            s[(i, j)] = dot(&rows[i], &columns[j]);
            s[(j, i)] = s[(i, j)];
        }
        s[(i, i)] += legs[i].phi_theta * legs[i].phi_theta * inv_j;
    }
    let rhs = Vector3::from_fn(|i, _| dot(&rows[i], &y) - r2p[i]);
    let b = Ldl::new(&s, 4.0 * k.forearm_squared / k.m_t)?.solve(&rhs);
    let a_x = y - columns[0] * b.x - columns[1] * b.y - columns[2] * b.z;
    let a_theta = Vector3::from_fn(|i, _| {
        (r1[3 + i] - k.k * dot(&legs[i].d1, &a_x) - legs[i].phi_theta * b[i]) * inv_j
    });
    let a = Vector6::new(a_x.x, a_x.y, a_x.z, a_theta.x, a_theta.y, a_theta.z);
    Some((a, b))
}
