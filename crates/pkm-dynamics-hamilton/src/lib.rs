//! Hamilton's canonical equations in the extended space $s = (x, q)$ of task and joint
//! coordinates (Miller 2004, §3), with Baumgarte stabilisation, and the acceleration-based
//! Lagrange formulation in the same coordinates for comparison.
#![warn(missing_docs)]
