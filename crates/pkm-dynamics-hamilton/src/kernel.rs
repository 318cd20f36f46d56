//! The per-sample kernels of inverse and forward dynamics, written once over any scalar with the
//! four arithmetic operations ([`Arithmetic`]): `f64` for computing, and an operation counter in
//! the tests (`kernel::count`), so the operation counts reported in `docs/performance.md` are
//! those of the code that runs.
//!
//! Everything is expressed through the per-leg quantities of one configuration ([`Leg`]):
//! $d_i = \cos\theta_i u_i - \sin\theta_i w_i$, $d_i' = -\sin\theta_i u_i - \cos\theta_i w_i$,
//! $v_i = C_i - B_i = p + c_i - A_i - L_a d_i$ and $\Phi_{\theta,ii} = -2L_a\, v_i\cdot d_i'$
//! (`miller-dynamics.md` §1). In these terms $M$ is $m_t I_3$, $J I_3$ and the columns
//! $k\,d_i'$; $\Phi_x$ has the rows $2v_i^\top$; $\Phi_\theta$ is diagonal. No 6×6 or 9×9 matrix
//! is ever formed.

use nalgebra::{
    ClosedAddAssign, ClosedDivAssign, ClosedMulAssign, ClosedSubAssign, Vector3, Vector6,
};
use std::ops::Neg;

#[cfg(test)]
pub(crate) mod count;

/// A scalar with the arithmetic of the kernels.
pub(crate) trait Arithmetic:
    nalgebra::Scalar
    + Copy
    + ClosedAddAssign
    + ClosedSubAssign
    + ClosedMulAssign
    + ClosedDivAssign
    + Neg<Output = Self>
    + From<f64>
{
}

impl Arithmetic for f64 {}

/// $a\cdot b$ (3 multiplications, 2 additions).
pub(crate) fn dot<T: Arithmetic>(a: &Vector3<T>, b: &Vector3<T>) -> T {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// $a\times b$ (6 multiplications, 3 subtractions).
pub(crate) fn cross<T: Arithmetic>(a: &Vector3<T>, b: &Vector3<T>) -> Vector3<T> {
    Vector3::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

fn task<T: Arithmetic>(q: &Vector6<T>) -> Vector3<T> {
    Vector3::new(q[0], q[1], q[2])
}

/// The constants of the model that the kernels read (geometry of the legs and the five inertia
/// coefficients).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Constants {
    /// $u_i$, $w_i$ and $c_i - A_i$ of each leg.
    pub legs: [[Vector3<f64>; 3]; 3],
    /// $L_a$.
    pub arm: f64,
    /// $L_b^2$.
    pub forearm_squared: f64,
    /// $m_t$.
    pub m_t: f64,
    /// $J$.
    pub j: f64,
    /// $k$.
    pub k: f64,
    /// $g\,m_g$.
    pub g_m_g: f64,
    /// $g\,c_g$.
    pub g_c_g: f64,
}

fn c<T: Arithmetic>(v: f64) -> T {
    T::from(v)
}

fn cv<T: Arithmetic>(v: &Vector3<f64>) -> Vector3<T> {
    Vector3::new(c(v.x), c(v.y), c(v.z))
}

/// The quantities of one leg at one configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Leg<T: Arithmetic> {
    /// Arm direction $d_i$.
    pub d: Vector3<T>,
    /// Its derivative $d_i'$.
    pub d1: Vector3<T>,
    /// Forearm vector $v_i = C_i - B_i$.
    pub v: Vector3<T>,
    /// $\Phi_{\theta,ii} = -2L_a\, v_i\cdot d_i'$.
    pub phi_theta: T,
}

/// The three legs at the task position `p` with the joint angles given by
/// `(sin θ_i, cos θ_i)` (the only transcendental functions of a sample, evaluated by the caller).
pub(crate) fn legs<T: Arithmetic>(k: &Constants, p: &Vector3<T>, trig: [(T, T); 3]) -> [Leg<T>; 3] {
    let minus_two_arm: T = c(-2.0 * k.arm);
    std::array::from_fn(|i| {
        let [u, w, offset] = &k.legs[i];
        let (u, w) = (cv::<T>(u), cv::<T>(w));
        let (s, co) = trig[i];
        let d = u * co - w * s;
        let d1 = u * (-s) - w * co;
        let v = (p + cv::<T>(offset)) - d * c::<T>(k.arm);
        let phi_theta = dot(&v, &d1) * minus_two_arm;
        Leg {
            d,
            d1,
            v,
            phi_theta,
        }
    })
}

/// $p = M\dot q$: $p_x = m_t\dot x + \sum_i (k\dot\theta_i) d_i'$,
/// $p_{\theta_i} = k\, d_i'\cdot\dot x + J\dot\theta_i$ (eq. 15).
pub(crate) fn momentum<T: Arithmetic>(
    k: &Constants,
    legs: &[Leg<T>; 3],
    qd: &Vector6<T>,
) -> Vector6<T> {
    mass_times(k, legs, qd)
}

fn mass_times<T: Arithmetic>(k: &Constants, legs: &[Leg<T>; 3], a: &Vector6<T>) -> Vector6<T> {
    let x = task(a);
    let (kk, j) = (c::<T>(k.k), c::<T>(k.j));
    let mut out_x = x * c::<T>(k.m_t);
    let mut out_theta = [c::<T>(0.0); 3];
    for (i, leg) in legs.iter().enumerate() {
        out_x += leg.d1 * (kk * a[3 + i]);
        out_theta[i] = kk * dot(&leg.d1, &x) + j * a[3 + i];
    }
    Vector6::new(
        out_x.x,
        out_x.y,
        out_x.z,
        out_theta[0],
        out_theta[1],
        out_theta[2],
    )
}

/// The multipliers of $\Phi_x^\top\lambda = b$ by Cramer's rule on the columns $2v_i$:
/// $\lambda_i = b\cdot(v_j\times v_k) / (2\det V)$, $\det V = v_1\cdot(v_2\times v_3)$, with
/// $(i, j, k)$ cyclic. Returns $(\lambda, \det V)$; $\det V = 0$ is a direct-kinematic
/// singularity.
pub(crate) fn multipliers<T: Arithmetic>(legs: &[Leg<T>; 3], b: &Vector3<T>) -> (Vector3<T>, T) {
    let [v1, v2, v3] = [legs[0].v, legs[1].v, legs[2].v];
    let (c1, c2, c3) = (cross(&v2, &v3), cross(&v3, &v1), cross(&v1, &v2));
    let det = dot(&v1, &c1);
    let half_over_det = c::<T>(0.5) / det;
    let lambda = Vector3::new(dot(b, &c1), dot(b, &c2), dot(b, &c3)) * half_over_det;
    (lambda, det)
}

/// Steps 2 and 3 of Hamilton's inverse dynamics (§3.3) for the momentum rate $\dot p$:
/// $\Phi_x^\top\lambda = L_{q,x} - \dot p_x$, $\tau_i = \dot p_{\theta_i} - L_{q,\theta_i} +
/// \Phi_{\theta,ii}\lambda_i$ with $L_{q,x} = (0, 0, -g m_g)$ and
/// $L_{q,\theta_i} = -k\dot\theta_i\,(d_i\cdot\dot x) - g c_g (d_i')_z$.
/// Returns $(\tau, \det V)$.
pub(crate) fn hamilton_torques<T: Arithmetic>(
    k: &Constants,
    legs: &[Leg<T>; 3],
    qd: &Vector6<T>,
    p_rate: &Vector6<T>,
) -> (Vector3<T>, T) {
    let x = task(qd);
    let b = Vector3::new(-p_rate[0], -p_rate[1], -(c::<T>(k.g_m_g) + p_rate[2]));
    let (lambda, det) = multipliers(legs, &b);
    let (kk, g_c_g) = (c::<T>(k.k), c::<T>(k.g_c_g));
    let tau = Vector3::from_fn(|i, _| {
        let leg = &legs[i];
        let l_theta = -(kk * qd[3 + i] * dot(&leg.d, &x)) - g_c_g * leg.d1.z;
        p_rate[3 + i] - l_theta + leg.phi_theta * lambda[i]
    });
    (tau, det)
}

/// Lagrange's inverse dynamics from $\ddot q$: $r = M\ddot q + \dot M\dot q - L_q$,
/// $\Phi_x^\top\lambda = -r_x$, $\tau = r_\theta + \Phi_\theta\lambda$. The velocity terms of the
/// joint rows cancel ($(\dot M\dot q)_{\theta_i} = -k\dot\theta_i\,(d_i\cdot\dot x)$ is also the
/// first term of $L_{q,\theta_i}$), so $r_{\theta_i} = (M\ddot q)_{\theta_i} + g c_g (d_i')_z$ and
/// $r_x = (M\ddot q)_x - k\sum_i\dot\theta_i^2 d_i + (0, 0, g m_g)$. Returns $(\tau, \det V)$.
pub(crate) fn lagrange_torques<T: Arithmetic>(
    k: &Constants,
    legs: &[Leg<T>; 3],
    qd: &Vector6<T>,
    qdd: &Vector6<T>,
) -> (Vector3<T>, T) {
    let m_qdd = mass_times(k, legs, qdd);
    let kk = c::<T>(k.k);
    let mut r_x = task(&m_qdd);
    for (i, leg) in legs.iter().enumerate() {
        r_x -= leg.d * (kk * qd[3 + i] * qd[3 + i]);
    }
    let b = Vector3::new(-r_x.x, -r_x.y, -(r_x.z + c::<T>(k.g_m_g)));
    let (lambda, det) = multipliers(legs, &b);
    let g_c_g = c::<T>(k.g_c_g);
    let tau = Vector3::from_fn(|i, _| {
        let leg = &legs[i];
        m_qdd[3 + i] + g_c_g * leg.d1.z + leg.phi_theta * lambda[i]
    });
    (tau, det)
}

/// $\dot v_i = \dot x - L_a\dot\theta_i\, d_i'$.
fn forearm_rate<T: Arithmetic>(
    k: &Constants,
    leg: &Leg<T>,
    x_rate: &Vector3<T>,
    theta_rate: T,
) -> Vector3<T> {
    x_rate - leg.d1 * (c::<T>(k.arm) * theta_rate)
}

/// $\gamma_i = (\dot\Phi_q\dot q)_i = 2|\dot v_i|^2 + 2L_a\dot\theta_i^2\,(v_i\cdot d_i)$.
fn gamma<T: Arithmetic>(k: &Constants, legs: &[Leg<T>; 3], qd: &Vector6<T>) -> Vector3<T> {
    let x = task(qd);
    let two_arm = c::<T>(2.0 * k.arm);
    Vector3::from_fn(|i, _| {
        let leg = &legs[i];
        let vd = forearm_rate(k, leg, &x, qd[3 + i]);
        let two = c::<T>(2.0);
        two * dot(&vd, &vd) + two_arm * (qd[3 + i] * qd[3 + i]) * dot(&leg.v, &leg.d)
    })
}

/// The acceleration-level inverse kinematics $\ddot\theta_i = -(\Phi_x\ddot x + \gamma)_i /
/// \Phi_{\theta,ii}$, $(\Phi_x\ddot x)_i = 2v_i\cdot\ddot x$.
pub(crate) fn joint_accelerations<T: Arithmetic>(
    k: &Constants,
    legs: &[Leg<T>; 3],
    qd: &Vector6<T>,
    a: &Vector3<T>,
) -> Vector6<T> {
    let g = gamma(k, legs, qd);
    let two = c::<T>(2.0);
    let thdd = Vector3::from_fn(|i, _| -(two * dot(&legs[i].v, a) + g[i]) / legs[i].phi_theta);
    Vector6::new(a.x, a.y, a.z, thdd.x, thdd.y, thdd.z)
}

/// $\Phi_i = |v_i|^2 - L_b^2$.
pub(crate) fn constraints<T: Arithmetic>(k: &Constants, legs: &[Leg<T>; 3]) -> Vector3<T> {
    Vector3::from_fn(|i, _| dot(&legs[i].v, &legs[i].v) - c::<T>(k.forearm_squared))
}

/// $\Phi_q\dot q$: $2v_i\cdot\dot x + \Phi_{\theta,ii}\dot\theta_i$.
pub(crate) fn constraint_rate<T: Arithmetic>(legs: &[Leg<T>; 3], qd: &Vector6<T>) -> Vector3<T> {
    let x = task(qd);
    Vector3::from_fn(|i, _| c::<T>(2.0) * dot(&legs[i].v, &x) + legs[i].phi_theta * qd[3 + i])
}

/// The momentum rate of eq. 17 without the motor torques, $L_q - \dot\Phi_q^\top\sigma$:
/// task rows $(0, 0, -g m_g) - 2\sum_i \sigma_i\dot v_i$, joint rows
/// $L_{q,\theta_i} + 2L_a(\dot v_i\cdot d_i' - \dot\theta_i\, v_i\cdot d_i)\,\sigma_i$.
pub(crate) fn momentum_rate<T: Arithmetic>(
    k: &Constants,
    legs: &[Leg<T>; 3],
    qd: &Vector6<T>,
    sigma: &Vector3<T>,
) -> Vector6<T> {
    let x = task(qd);
    let (kk, g_c_g, two_arm) = (c::<T>(k.k), c::<T>(k.g_c_g), c::<T>(2.0 * k.arm));
    let mut rate_x = Vector3::new(c::<T>(0.0), c::<T>(0.0), -c::<T>(k.g_m_g));
    let mut rate_theta = [c::<T>(0.0); 3];
    for (i, leg) in legs.iter().enumerate() {
        let th = qd[3 + i];
        let vd = forearm_rate(k, leg, &x, th);
        rate_x -= vd * (c::<T>(2.0) * sigma[i]);
        let l_theta = -(kk * th * dot(&leg.d, &x)) - g_c_g * leg.d1.z;
        rate_theta[i] =
            l_theta + two_arm * (dot(&vd, &leg.d1) - th * dot(&leg.v, &leg.d)) * sigma[i];
    }
    Vector6::new(
        rate_x.x,
        rate_x.y,
        rate_x.z,
        rate_theta[0],
        rate_theta[1],
        rate_theta[2],
    )
}

/// The right-hand side of the acceleration form without the motor torques:
/// $r_1 = L_q - \dot M\dot q$ (task rows $k\sum_i\dot\theta_i^2 d_i - (0, 0, g m_g)$, joint
/// rows $-g c_g (d_i')_z$: the velocity terms cancel) and
/// $r_2 = -\gamma - 2\omega\Phi_q\dot q - \omega^2\Phi$.
pub(crate) fn acceleration_rhs<T: Arithmetic>(
    k: &Constants,
    legs: &[Leg<T>; 3],
    qd: &Vector6<T>,
    omega: T,
) -> (Vector6<T>, Vector3<T>) {
    let kk = c::<T>(k.k);
    let mut r_x = Vector3::new(c::<T>(0.0), c::<T>(0.0), -c::<T>(k.g_m_g));
    for (i, leg) in legs.iter().enumerate() {
        r_x += leg.d * (kk * qd[3 + i] * qd[3 + i]);
    }
    let g_c_g = c::<T>(k.g_c_g);
    let r1 = Vector6::new(
        r_x.x,
        r_x.y,
        r_x.z,
        -(g_c_g * legs[0].d1.z),
        -(g_c_g * legs[1].d1.z),
        -(g_c_g * legs[2].d1.z),
    );
    let two_omega = c::<T>(2.0) * omega;
    let (g, rate, phi) = (
        gamma(k, legs, qd),
        constraint_rate(legs, qd),
        constraints(k, legs),
    );
    let omega_squared = omega * omega;
    let r2 = Vector3::from_fn(|i, _| -g[i] - two_omega * rate[i] - omega_squared * phi[i]);
    (r1, r2)
}
