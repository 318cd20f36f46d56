//! Screw theory for parallel robots (Wolf & Shoham, §2–3): Plücker lines, twists and wrenches,
//! the reciprocal product, and the task-based objective $F(\chi) = \sum_i (L_i \wedge \chi)^2$.
//!
//! Conventions (`docs/conventions.md`, Wolf & Shoham):
//! - every 6-vector is in **ray order** `[direction-like; moment-like]` with moments about the
//!   **world origin**: a line `[d; m]` (eq. 1), a twist `[ω; v_O]` (eq. 3, 12), a wrench
//!   `[f; m_O]` (eq. 4, 13);
//! - the reciprocal product is $a \wedge b = a^\top \Delta b$, $\Delta$ swapping the halves
//!   (eq. 5); its geometric form is eq. 6;
//! - rigid motions act on all three by the same adjoint map `[R u; R v + t × R u]`.
//!
//! Non-finite values: the checked constructors (`PluckerLine::from_points`, `ScrewAxis::new`,
//! `Twist::from_screw`, `Twist::translation`, `Wrench::couple`, ...) refuse them with a
//! [`ScrewError`]. The plain-value operations on vectors a caller built directly
//! (`Twist::new`/`from_vector`, the reciprocal products, `task_objective`, `task_residuals` and
//! their gradients, `transformed`, `velocity_at`, `skew`) follow IEEE arithmetic and never
//! panic: a NaN in gives a NaN out, and finite inputs give finite results as long as each
//! product stays below `f64::MAX` (entries up to about 1e150, or 1e75 for the objective $F$,
//! which squares the products); beyond that they give ±∞. Check with
//! `pkm_traits::checked::all_finite` where a caller's values may be extreme.

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod error;
mod line;
mod line_set;
mod objective;
mod ray;
mod reciprocal;
mod rotation;
mod screw_axis;
mod screws;

pub use error::ScrewError;
pub use line::PluckerLine;
pub use line_set::{line_set_rank, reciprocal_screw_system};
pub use objective::{
    task_objective, task_objective_gradient_rows, task_objective_gradient_twist, task_residuals,
};
pub use reciprocal::{
    CommonNormal, most_reciprocal_twist, reciprocal_product, reciprocal_product_geometric,
    reciprocal_product_vectors,
};
pub use rotation::{rotation_from_axis_angle, skew};
pub use screw_axis::ScrewAxis;
pub use screws::{Twist, Wrench};
