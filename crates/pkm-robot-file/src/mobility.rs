//! The mobility check on load: the platform twist system at home is the intersection of the
//! legs' twist spaces, i.e. the screws reciprocal to every leg's constraint wrenches
//! (Joshi & Tsai 2002; `spec/general-robots.md` §2a).

use crate::chain::LegChain;
use crate::error::RobotFileError;
use crate::pose::{CoordinateRole, OrientationKind, PoseCoordinates, hybrid_rates};
use nalgebra::{DMatrix, Vector3, Vector6};
use pkm_screw_theory::reciprocal_screw_system;

/// Relative rank tolerance of the screw systems: well above round-off of metre-sized axes and
/// far below any real first-order motion.
pub(crate) const RANK_TOLERANCE: f64 = 1e-9;

/// The constraint wrenches of one leg: the screws reciprocal to all its joint twists.
pub(crate) fn constraint_wrenches(twists: &[Vector6<f64>]) -> Vec<Vector6<f64>> {
    reciprocal_screw_system(twists, RANK_TOLERANCE).unwrap_or_default()
}

/// The constraint wrenches of `leg` at home.
fn home_constraints(leg: &LegChain) -> Vec<Vector6<f64>> {
    let twists: Vec<_> = leg
        .twists(&leg.home_values())
        .twists
        .iter()
        .map(|t| t.1)
        .collect();
    constraint_wrenches(&twists)
}

/// In a leg with several actuators, each actuator's twist at home must be independent of the
/// leg's other joint twists: else the actuation wrench that drives it does no work on it
/// (two actuators in series along one line, say) and the leg's actuators cannot be driven
/// independently.
///
/// # Errors
/// [`RobotFileError::Invalid`] at the actuator's key path.
fn check_independent_actuators(leg: &LegChain) -> Result<(), RobotFileError> {
    if leg.actuators.len() < 2 {
        return Ok(());
    }
    let twists = leg.twists(&leg.home_values()).twists;
    let all = constraint_wrenches(&twists.iter().map(|t| t.1).collect::<Vec<_>>()).len();
    for actuator in &leg.actuators {
        let others: Vec<_> = twists
            .iter()
            .filter(|(j, _)| *j != actuator.joint)
            .map(|t| t.1)
            .collect();
        if constraint_wrenches(&others).len() == all {
            return Err(RobotFileError::invalid(
                &actuator.name,
                "actuated",
                "its twist at home is a combination of the leg's other joint twists, so the \
                 leg's actuators cannot be driven independently: actuate another joint",
            ));
        }
    }
    Ok(())
}

/// Whether `leg` has constraint wrenches at home (its joints span fewer than six twists).
pub(crate) fn constrains(leg: &LegChain) -> bool {
    !home_constraints(leg).is_empty()
}

/// Checks that the platform twist system at home has dimension `task + idle`, moves every
/// task and idle coordinate independently, and leaves the constant coordinates still.
/// Returns the twist system (orthonormal basis, `[ω; v_O]`).
///
/// # Errors
/// [`RobotFileError::Mobility`] with the twist system found.
pub(crate) fn check_mobility(
    legs: &[LegChain],
    orientation: OrientationKind,
    home: &PoseCoordinates,
    roles: &[CoordinateRole; 6],
) -> Result<Vec<[f64; 6]>, RobotFileError> {
    let mut wrenches = Vec::new();
    let mut per_leg = Vec::with_capacity(legs.len());
    for (i, leg) in legs.iter().enumerate() {
        let constraints = home_constraints(leg);
        if leg.actuators.is_empty() && constraints.is_empty() {
            return Err(RobotFileError::invalid(
                format!("legs[{i}]"),
                leg.letters.as_str(),
                "a passive leg (no actuated joint) must constrain the platform, but its joints \
                 span every twist at home: drop it, or actuate one of its joints",
            ));
        }
        check_independent_actuators(leg)?;
        per_leg.push(constraints.len());
        wrenches.extend(constraints);
    }
    let names = orientation.coordinate_names();
    let declared = |role: CoordinateRole| -> Vec<&str> {
        (0..6)
            .filter(|&k| roles[k] == role)
            .map(|k| names[k])
            .collect()
    };
    let legs_say = per_leg
        .iter()
        .enumerate()
        .map(|(i, n)| format!("legs[{i}]: {n}"))
        .collect::<Vec<_>>()
        .join(", ");
    let system = reciprocal_screw_system(&wrenches, RANK_TOLERANCE).unwrap_or_default();
    let basis: Vec<[f64; 6]> = system.iter().map(|t| (*t).into()).collect();
    let fail = |reason: String| RobotFileError::Mobility {
        reason,
        found: basis.len(),
        twist_system: basis.clone(),
    };
    let free: Vec<usize> = (0..6)
        .filter(|&k| matches!(roles[k], CoordinateRole::Task | CoordinateRole::Idle))
        .collect();
    if system.len() != free.len() {
        return Err(fail(format!(
            "the legs leave the platform {} degrees of freedom, the file declares {} task and \
             idle coordinates (`task` = {:?}, `idle` = {:?}); constraint wrenches per leg at \
             home: {legs_say} (a leg with too few joints constrains more, one with a joint too \
             many constrains less)",
            system.len(),
            free.len(),
            declared(CoordinateRole::Task),
            declared(CoordinateRole::Idle),
        )));
    }
    // Pose-coordinate rates of each basis twist: ẋ = H⁻¹ [ω; v_O + ω × p].
    let Some(h_inv) = hybrid_rates(orientation, home).try_inverse() else {
        return Err(fail(
            "the orientation coordinates are singular at home".into(),
        ));
    };
    let p = Vector3::new(home[0], home[1], home[2]);
    let rates = DMatrix::from_fn(6, system.len(), |row, col| {
        let t = &system[col];
        let w = Vector3::new(t[0], t[1], t[2]);
        let v = Vector3::new(t[3], t[4], t[5]) + w.cross(&p);
        (h_inv * Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z))[row]
    });
    let scale = rates.amax().max(1.0);
    for k in (0..6).filter(|&k| roles[k] == CoordinateRole::Constant) {
        let moved = rates.row(k).amax();
        if moved > 1e-7 * scale {
            return Err(fail(format!(
                "the legs let `{}` move (rate {moved:.3e}) but the file does not declare it: \
                 put it in `task`, `dependent` or `idle`; constraint wrenches per leg at home: \
                 {legs_say}",
                names[k]
            )));
        }
    }
    let selected = DMatrix::from_fn(free.len(), system.len(), |r, c| rates[(free[r], c)]);
    let smallest = crate::svd::bounded_svd(selected, false, false).map_or(0.0, |svd| {
        svd.singular_values
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    });
    if free.is_empty() || !(smallest > 1e-7 * scale) {
        return Err(fail(format!(
            "the task and idle coordinates ({:?}) do not parametrise the twist system (smallest \
             singular value {smallest:.3e}): the legs move the platform along other coordinates; \
             constraint wrenches per leg at home: {legs_say}",
            free.iter().map(|&k| names[k]).collect::<Vec<_>>()
        )));
    }
    Ok(basis)
}
