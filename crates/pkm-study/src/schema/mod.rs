//! The sections that studies share: the `[mechanism.<kind>]` table and `[constraints]`
//! ([`mechanism`]), `[sampling]` ([`sampling`]) and the checked quantities with units that they
//! are made of ([`units`]).

pub mod grid;
mod kinds;
pub mod mechanism;
pub mod robot_file;
pub mod sampling;
pub mod units;
