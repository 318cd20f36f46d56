//! pkm: optimal design and dynamic modelling of parallel kinematic machines.
//!
//! This facade re-exports the workspace crates and holds [`papers`], the registry of experiments
//! that reproduce the published results pkm is built on (`cargo xtask reproduce`).
//!
//! | module | crate | what it does |
//! |---|---|---|
//! | [`traits`] | `pkm-traits` | shared vocabulary: kinematics, objectives, dynamics, progress, errors |
//! | [`screw_theory`] | `pkm-screw-theory` | Plücker lines, twists, wrenches, reciprocal product |
//! | [`mechanisms`] | `pkm-mechanisms` | Delta/NUWAR, Linear Delta, Tsai 3-DOF, Stewart–Gough, 3-UPU |
//! | [`workspace_indices`] | `pkm-workspace-indices` | workspace volume, condition indices, space utilisation |
//! | [`optimizers`] | `pkm-optimizers` | grid search, Gauss–Newton multistart, constrained optimisation |
//! | [`design_problems`] | `pkm-design-problems` | the papers' design problems as objectives and constraints (Stamper §5) |
//! | [`integrators`] | `pkm-integrators` | RK4, Dormand–Prince 5(4), symplectic methods |
//! | [`dynamics_hamilton`] | `pkm-dynamics-hamilton` | Hamilton's equations in extended space |
//! | [`draw`] | `pkm-draw` | SVG drawings of a mechanism's skeleton, with axes and workspaces; charts (heat maps, lines, scatter) |

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

pub use pkm_design_problems as design_problems;
pub use pkm_draw as draw;
pub use pkm_dynamics_hamilton as dynamics_hamilton;
pub use pkm_integrators as integrators;
pub use pkm_mechanisms as mechanisms;
pub use pkm_optimizers as optimizers;
pub use pkm_screw_theory as screw_theory;
pub use pkm_traits as traits;
pub use pkm_workspace_indices as workspace_indices;

pub mod papers;
