#![doc = include_str!("../README.md")]

pub mod tsai;
pub mod upu;

/// A design problem of this crate whose objective is smooth in the design, so that a
/// gradient-based optimiser (the augmented Lagrangian of `pkm-optimizers`) can solve it: what a
/// mechanism that poses one gives (the study layer's `optimize` study runs on it).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum DesignProblem {
    /// The Tsai platform's ([`tsai::TsaiProblem`], Stamper §5), at its nominal design
    /// $(a, b, d + e, c - r, \phi_2, \phi_3)$ in m and degrees ([`tsai::TSAI_VARIABLES`]):
    /// its column-quadrature volume is smooth in the design.
    Tsai {
        /// The values of the variables that are not optimised.
        nominal: [f64; 6],
    },
}
