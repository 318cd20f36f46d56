//! The sections that studies share: the `[mechanism.<kind>]` table ([`mechanism`], the
//! registry; [`kinds`], one file per kind of the papers; [`robot_file`], any robot file),
//! `[constraints]` ([`constraints`]), `[sampling]` ([`sampling`]) and the checked quantities with
//! units that they are made of ([`units`]).

pub mod constraints;
pub mod grid;
pub mod index;
pub mod kinds;
pub mod mechanism;
pub mod robot_file;
mod robot_file_mechanism;
pub mod sampling;
pub mod units;
