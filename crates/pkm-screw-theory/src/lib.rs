//! Screw theory for parallel robots (Wolf & Shoham, §2–3): Plücker lines, twists and wrenches,
//! the reciprocal product, and the task-based objective $F(\chi) = \sum_i (L_i \wedge \chi)^2$.
//!
//! Implemented by the workspace-foundation issue; see `docs/ARCHITECTURE.md`.
#![warn(missing_docs)]
