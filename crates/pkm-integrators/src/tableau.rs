//! Coefficients of the Dormand–Prince 5(4) pair (Dormand & Prince 1980, "A family of embedded
//! Runge–Kutta formulae", J. Comput. Appl. Math. 6(1), Table 2; Hairer, Nørsett & Wanner,
//! *Solving ODEs I*, Table II.5.2) and of its continuous extension (`dopri5`'s `d` coefficients,
//! Hairer, Nørsett & Wanner §II.6).

/// Nodes $c_i$.
pub(crate) const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];

/// Rows $a_{i,j}$, $j < i$, of the Runge–Kutta matrix (row 7 equals the weights $b$: FSAL).
pub(crate) const A2: [f64; 1] = [1.0 / 5.0];
pub(crate) const A3: [f64; 2] = [3.0 / 40.0, 9.0 / 40.0];
pub(crate) const A4: [f64; 3] = [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0];
pub(crate) const A5: [f64; 4] = [
    19372.0 / 6561.0,
    -25360.0 / 2187.0,
    64448.0 / 6561.0,
    -212.0 / 729.0,
];
pub(crate) const A6: [f64; 5] = [
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
];
/// Fifth-order weights $b_i$ (also row 7 of the matrix; $b_2 = b_7 = 0$).
pub(crate) const B: [f64; 6] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
];
/// Error weights $e_i = b_i - \hat b_i$ against the fourth-order embedded solution.
pub(crate) const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// Coefficients $d_i$ of the fourth-order continuous extension ($d_2 = 0$).
pub(crate) const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// $\sum_i w_i k_i$ over as many stages as there are weights.
pub(crate) fn combine<const M: usize, const S: usize>(
    weights: &[f64; S],
    k: &[nalgebra::SVector<f64, M>; 7],
) -> nalgebra::SVector<f64, M> {
    weights
        .iter()
        .zip(k)
        .fold(nalgebra::SVector::zeros(), |sum, (w, k)| sum + k * *w)
}
