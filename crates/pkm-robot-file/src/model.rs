//! The validated robot: legs expanded into elementary joints, symmetry applied, the name and
//! the mobility checked, every leg classified for its inverse kinematics.

use crate::chain::{Joint, LegActuator, LegChain};
use crate::error::RobotFileError;
use crate::file::{JointSpec, JointType, LegSpec, MAX_LEGS, RobotFile};
use crate::leg_ik::LegClass;
use crate::mass::MassProperties;
use crate::passive::PassiveLayout;
use crate::pointing::PointingLeg;
use crate::pose::{CoordinateRole, OrientationKind, PoseCoordinates, platform_pose};
use nalgebra::{Isometry3, Rotation3, Unit, Vector3};

/// Most joint letters per leg.
pub const MAX_JOINTS_PER_LEG: usize = 16;
/// Largest coordinate accepted in a file (m): beyond it the products of the kinematics lose
/// every digit.
const MAX_COORDINATE: f64 = 1e6;

/// Smallest `characteristic_length` (m): with coordinates of at most `MAX_COORDINATE` (1e6 m), the
/// homogenised moments $m/L$ stay below $10^{12}$ times the forces, finite and far from
/// overflow (a subnormal $L$ once put infinities into the margins' SVD).
pub const MIN_CHARACTERISTIC_LENGTH: f64 = 1e-6;

/// A working mode: bit $i$ is the branch of leg $i$ (0 or 1) for the legs with two
/// closed-form branches; legs with one branch or a numerical solution ignore their bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct WorkingMode(pub u64);

impl WorkingMode {
    /// The branch of leg `leg`.
    pub fn branch(self, leg: usize) -> u8 {
        u8::from(leg < 64 && (self.0 >> leg) & 1 == 1)
    }

    /// The mode with leg `leg` on `branch` (0 or 1).
    #[must_use]
    pub fn with_branch(self, leg: usize, branch: u8) -> Self {
        if leg >= 64 {
            return self;
        }
        let bit = 1u64 << leg;
        Self(if branch == 1 {
            self.0 | bit
        } else {
            self.0 & !bit
        })
    }
}

/// A parallel robot read from a robot file: one rigid base, one rigid platform, legs of
/// elementary joints given as screw axes at the home pose.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotModel {
    pub(crate) name: String,
    pub(crate) orientation: OrientationKind,
    pub(crate) roles: [CoordinateRole; 6],
    pub(crate) task: Vec<usize>,
    pub(crate) home: PoseCoordinates,
    pub(crate) home_pose: Isometry3<f64>,
    pub(crate) legs: Vec<LegChain>,
    /// The number of actuated legs, the first ones.
    pub(crate) actuated: usize,
    /// Actuator `i` as (leg, place among the leg's actuators): the legs in order, each leg's
    /// actuated joints in joint order (actuator `i` is leg `i`'s when every actuated leg has
    /// one).
    pub(crate) actuators: Vec<(usize, usize)>,
    /// The legs with constraint wrenches at home (fewer than six freedoms): the ones whose
    /// closure determines the dependent coordinates.
    pub(crate) constraining: Vec<usize>,
    /// The passive pointing leg that gives the dependent orientation from the position in
    /// closed form, when it is the one constraining leg (the Tricept's).
    pub(crate) pointing: Option<PointingLeg>,
    pub(crate) classes: Vec<LegClass>,
    /// Per leg, the closed form of its passive joints when it has one ([`PassiveLayout`]).
    pub(crate) passive: Vec<Option<PassiveLayout>>,
    pub(crate) characteristic_length: f64,
    /// Size of the robot (m): the largest distance of a joint point from the home platform
    /// origin, at least the characteristic length; scales the step limits.
    pub(crate) size: f64,
    pub(crate) home_mode: WorkingMode,
    pub(crate) twist_system: Vec<[f64; 6]>,
    /// Gravity and the platform's mass properties (the legs carry their bodies).
    pub(crate) mass: MassProperties,
    /// Which load this model comes from, for the memo of its dependent coordinates.
    pub(crate) identity: Identity,
}

/// The identity of a loaded model: every load gets a fresh one and its clones share it (they
/// are the same model), so that a per-thread memo keyed by it and the task coordinates returns
/// exactly what the model computes ([`RobotModel::full_pose`]). Not part of the model's value:
/// models compare equal whatever their identities.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Identity(pub(crate) u64);

impl Identity {
    pub(crate) fn fresh() -> Self {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        Self(NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed))
    }
}

impl PartialEq for Identity {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl RobotModel {
    /// Reads, validates and checks a robot file.
    ///
    /// # Errors
    /// [`RobotFileError::Parse`] with line and column for text that does not match the schema;
    /// [`RobotFileError::Invalid`] for a value that violates its requirement;
    /// [`RobotFileError::NameMismatch`]; [`RobotFileError::Mobility`] when the platform twist
    /// system at home does not have the declared dimension.
    pub fn from_toml(text: &str) -> Result<Self, RobotFileError> {
        Self::from_file(&RobotFile::from_toml(text)?)
    }

    /// Validates and checks a parsed robot file (see [`RobotModel::from_toml`]).
    ///
    /// # Errors
    /// As [`RobotModel::from_toml`], without the parse errors.
    pub fn from_file(file: &RobotFile) -> Result<Self, RobotFileError> {
        let roles = coordinate_roles(file)?;
        let home = home_coordinates(file)?;
        let home_pose = platform_pose(file.orientation, &home);
        let legs = expand_legs(file)?;
        let actuated = actuated_legs(&legs)?;
        crate::name::check_name(&file.name, &legs)?;
        let size = robot_size(&legs, &home_pose);
        let characteristic_length = match file.characteristic_length {
            Some(l) if (MIN_CHARACTERISTIC_LENGTH..=MAX_COORDINATE).contains(&l) => l,
            Some(l) => {
                return Err(RobotFileError::invalid(
                    "characteristic_length",
                    l,
                    "must be finite, at least 1e-6 m and at most 1e6 m",
                ));
            }
            None => default_characteristic_length(&legs, &home_pose),
        };
        let task: Vec<usize> = (0..6)
            .filter(|&k| roles[k] == CoordinateRole::Task)
            .collect();
        let actuators: Vec<(usize, usize)> = legs
            .iter()
            .enumerate()
            .flat_map(|(i, leg)| (0..leg.actuators.len()).map(move |k| (i, k)))
            .collect();
        if task.len() > actuators.len() {
            return Err(RobotFileError::invalid(
                "task",
                &file.task,
                format!(
                    "{} task coordinates for {} actuators: at least one actuator per task \
                     coordinate",
                    task.len(),
                    actuators.len(),
                ),
            ));
        }
        let twist_system = crate::mobility::check_mobility(&legs, file.orientation, &home, &roles)?;
        let size = size.max(characteristic_length);
        let classes = legs
            .iter()
            .map(|leg| LegClass::classify(leg, &home_pose, size))
            .collect::<Vec<_>>();
        let passive = legs
            .iter()
            .zip(&classes)
            .map(|(leg, class)| PassiveLayout::new(leg, class, &home_pose, size))
            .collect();
        let constraining: Vec<usize> = (0..legs.len())
            .filter(|&i| crate::mobility::constrains(&legs[i]))
            .collect();
        let orientation_follows_position = roles[..3].iter().all(|r| *r == CoordinateRole::Task)
            && roles[3..].iter().all(|r| *r == CoordinateRole::Dependent);
        let pointing = match constraining.as_slice() {
            [i] if orientation_follows_position => {
                PointingLeg::detect(*i, &legs[*i], &home_pose.translation.vector, size)
            }
            _ => None,
        };
        let mass = mass_properties(file, &home_pose)?;
        let mut model = Self {
            name: file.name.clone(),
            orientation: file.orientation,
            roles,
            task,
            home,
            home_pose,
            legs,
            actuated,
            actuators,
            constraining,
            pointing,
            classes,
            passive,
            characteristic_length,
            size,
            home_mode: WorkingMode::default(),
            twist_system,
            mass,
            identity: Identity::fresh(),
        };
        model.home_mode = model.mode_of_home();
        Ok(model)
    }

    /// The branch of every closed-form leg that reproduces the home configuration.
    fn mode_of_home(&self) -> WorkingMode {
        let mut mode = WorkingMode::default();
        for (i, class) in self.classes.iter().enumerate() {
            if class
                .solve(&self.home_pose, 1)
                .is_ok_and(|m| m.abs() < 1e-9 * self.size)
                && !class
                    .solve(&self.home_pose, 0)
                    .is_ok_and(|m| m.abs() < 1e-9 * self.size)
            {
                mode = mode.with_branch(i, 1);
            }
        }
        mode
    }

    /// The architecture name, as written in the file.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Number of task coordinates.
    pub fn dof(&self) -> usize {
        self.task.len()
    }

    /// Number of actuators: the actuated joints of the actuated legs (the first legs; passive
    /// legs follow); at least [`RobotModel::dof`], more for a redundantly actuated robot.
    pub fn actuator_count(&self) -> usize {
        self.actuators.len()
    }

    /// Actuator `i`: its leg and its joint, home value and range.
    ///
    /// # Panics
    /// Never for `i < actuator_count()`; callers index within it.
    pub(crate) fn actuator(&self, i: usize) -> (usize, &LegActuator) {
        let (leg, k) = self.actuators[i];
        (leg, &self.legs[leg].actuators[k])
    }

    /// The name of each actuator in order: the key path of its joint (`legs[1].joints[0]`).
    pub fn actuator_names(&self) -> Vec<&str> {
        self.actuators
            .iter()
            .map(|&(leg, k)| self.legs[leg].actuators[k].name.as_str())
            .collect()
    }

    /// Whether every actuated leg carries one actuator, so that actuator `i` is leg `i`'s.
    pub(crate) fn one_actuator_per_leg(&self) -> bool {
        self.actuators.len() == self.actuated
    }

    /// The legs, expanded into elementary joints: the actuated ones (the first legs; their
    /// actuators numbered in order, see [`RobotModel::actuator_names`]), then the passive
    /// ones.
    pub fn legs(&self) -> &[LegChain] {
        &self.legs
    }

    /// The orientation coordinates of the pose.
    pub fn orientation(&self) -> OrientationKind {
        self.orientation
    }

    /// The role of each of the six pose coordinates.
    pub fn coordinate_roles(&self) -> [CoordinateRole; 6] {
        self.roles
    }

    /// Names of the task coordinates, in order.
    pub fn task_names(&self) -> Vec<&'static str> {
        let names = self.orientation.coordinate_names();
        self.task.iter().map(|&k| names[k]).collect()
    }

    /// The six pose coordinates at home.
    pub fn home(&self) -> PoseCoordinates {
        self.home
    }

    /// The task coordinates at home.
    pub fn home_task(&self) -> Vec<f64> {
        self.task.iter().map(|&k| self.home[k]).collect()
    }

    /// The actuator coordinates at home (the offsets).
    pub fn home_actuators(&self) -> Vec<f64> {
        (0..self.actuator_count())
            .map(|i| self.actuator(i).1.offset)
            .collect()
    }

    /// The working mode of the home configuration.
    pub fn home_mode(&self) -> WorkingMode {
        self.home_mode
    }

    /// The characteristic length (m) of the singularity margins.
    pub fn characteristic_length(&self) -> f64 {
        self.characteristic_length
    }

    /// Number of closed-form branches of each actuated leg (1 or 2; 1 for a numerical leg).
    pub fn branch_counts(&self) -> Vec<usize> {
        self.classes[..self.actuated]
            .iter()
            .map(LegClass::branch_count)
            .collect()
    }

    /// Every working mode: all combinations of the legs' branches.
    pub fn working_modes(&self) -> Vec<WorkingMode> {
        let mut modes = vec![WorkingMode::default()];
        for (i, class) in self.classes.iter().enumerate() {
            if class.branch_count() == 2 {
                modes = modes
                    .into_iter()
                    .flat_map(|m| [m, m.with_branch(i, 1)])
                    .collect();
            }
        }
        modes
    }

    /// The label of `mode`: one character per actuated leg, `+` for branch 1 and `-` for
    /// branch 0 (a leg with one branch is `-` unless its bit is set).
    pub fn mode_label(&self, mode: WorkingMode) -> String {
        (0..self.actuated)
            .map(|i| if mode.branch(i) == 1 { '+' } else { '-' })
            .collect()
    }

    /// The working mode of `label`: `home` ([`RobotModel::home_mode`]) or one character per
    /// actuated leg, `+` (branch 1) or `-` (branch 0), as [`RobotModel::mode_label`] writes
    /// it; a leg with one branch ignores its character.
    ///
    /// # Errors
    /// [`RobotFileError::Invalid`] at `key` for another label.
    pub fn working_mode(&self, key: &str, label: &str) -> Result<WorkingMode, RobotFileError> {
        if label == "home" {
            return Ok(self.home_mode);
        }
        let legs = self.actuated;
        let valid = label.chars().count() == legs && label.chars().all(|c| c == '+' || c == '-');
        if !valid {
            return Err(RobotFileError::invalid(
                key,
                label,
                format!(
                    "a working mode is \"home\" or one `+` or `-` per actuated leg ({legs} legs; the \
                     home mode is \"{}\")",
                    self.mode_label(self.home_mode)
                ),
            ));
        }
        let mode = label
            .chars()
            .enumerate()
            .fold(WorkingMode::default(), |m, (i, c)| {
                m.with_branch(i, u8::from(c == '+'))
            });
        Ok(mode)
    }

    /// Gravity and the platform's mass properties, as the file gives them (the legs' bodies
    /// are in [`RobotModel::legs`]).
    pub fn mass_properties(&self) -> &MassProperties {
        &self.mass
    }

    /// An orthonormal basis `[ω; v_O]` of the platform twist system at home.
    pub fn home_twist_system(&self) -> &[[f64; 6]] {
        &self.twist_system
    }

    /// Name of each leg's inverse-kinematic solution (`distance`, `revolute arm`,
    /// `prismatic arm`, `numerical`; `passive (numerical)` for a leg without an actuator, whose
    /// joints are solved by damped Newton; `passive (pointing)` for a passive U + P leg that
    /// gives the dependent orientation from the position in closed form, as the Tricept's).
    pub fn leg_solvers(&self) -> Vec<&'static str> {
        self.classes
            .iter()
            .zip(&self.legs)
            .enumerate()
            .map(|(i, (class, leg))| match leg.actuators.len() {
                0 if self.pointing.is_some_and(|p| p.leg == i) => "passive (pointing)",
                0 => "passive (numerical)",
                _ => class.label(),
            })
            .collect()
    }
}

fn coordinate_roles(file: &RobotFile) -> Result<[CoordinateRole; 6], RobotFileError> {
    let names = file.orientation.coordinate_names();
    let mut roles = [CoordinateRole::Constant; 6];
    let lists = [
        ("task", &file.task, CoordinateRole::Task),
        ("dependent", &file.dependent, CoordinateRole::Dependent),
        ("idle", &file.idle, CoordinateRole::Idle),
    ];
    for (key, list, role) in lists {
        for (k, name) in list.iter().enumerate() {
            let Some(index) = names.iter().position(|n| n == name) else {
                return Err(RobotFileError::invalid(
                    format!("{key}[{k}]"),
                    name,
                    format!(
                        "must be one of {names:?} (orientation {:?})",
                        file.orientation
                    ),
                ));
            };
            if roles[index] != CoordinateRole::Constant {
                return Err(RobotFileError::invalid(
                    format!("{key}[{k}]"),
                    name,
                    "each pose coordinate may be listed once",
                ));
            }
            roles[index] = role;
        }
    }
    if file.task.is_empty() {
        return Err(RobotFileError::invalid(
            "task",
            &file.task,
            "must name at least one coordinate",
        ));
    }
    Ok(roles)
}

fn home_coordinates(file: &RobotFile) -> Result<PoseCoordinates, RobotFileError> {
    let p = file.home.position;
    let o = file.home.orientation;
    finite_vector("home.position", &p, MAX_COORDINATE)?;
    finite_vector("home.orientation", &o, std::f64::consts::PI)?;
    Ok([p[0], p[1], p[2], o[0], o[1], o[2]])
}

fn finite_vector(key: &str, v: &[f64; 3], max: f64) -> Result<Vector3<f64>, RobotFileError> {
    if v.iter().all(|x| x.is_finite() && x.abs() <= max) {
        Ok(Vector3::from(*v))
    } else {
        Err(RobotFileError::invalid(
            key,
            v,
            format!("must be finite, each entry within ±{max}"),
        ))
    }
}

fn unit_vector(key: &str, v: &[f64; 3]) -> Result<Vector3<f64>, RobotFileError> {
    let v = finite_vector(key, v, MAX_COORDINATE)?;
    let norm = v.norm();
    if norm > 1e-9 {
        Ok(v / norm)
    } else {
        Err(RobotFileError::invalid(
            key,
            v.as_slice(),
            "must have a length above 1e-9",
        ))
    }
}

/// Gravity and the platform body of the file, validated.
fn mass_properties(
    file: &RobotFile,
    home: &Isometry3<f64>,
) -> Result<MassProperties, RobotFileError> {
    let gravity = match file.gravity {
        Some(g) => Some(finite_vector("gravity", &g, 1e3)?),
        None => None,
    };
    let platform = match &file.platform {
        Some(spec) => Some(crate::mass::body(
            "platform",
            spec,
            0,
            home.translation.vector,
        )?),
        None => None,
    };
    Ok(MassProperties { gravity, platform })
}

/// The legs of the file, with the symmetry applied.
fn expand_legs(file: &RobotFile) -> Result<Vec<LegChain>, RobotFileError> {
    if file.legs.is_empty() {
        return Err(RobotFileError::invalid("legs", "[]", "at least one leg"));
    }
    let template = file
        .legs
        .iter()
        .enumerate()
        .map(|(i, leg)| leg_chain(i, leg))
        .collect::<Result<Vec<_>, _>>()?;
    let Some(sym) = file.symmetry else {
        return check_count(template);
    };
    if !(1..=MAX_LEGS).contains(&sym.count) || sym.count * template.len() > MAX_LEGS {
        return Err(RobotFileError::invalid(
            "symmetry.count",
            sym.count,
            format!("must be at least 1, with at most {MAX_LEGS} legs in all"),
        ));
    }
    let axis = unit_vector("symmetry.axis", &sym.axis)?;
    let point = finite_vector("symmetry.point", &sym.point, MAX_COORDINATE)?;
    let mut legs = Vec::with_capacity(sym.count * template.len());
    for k in 0..sym.count {
        let angle = std::f64::consts::TAU * k as f64 / sym.count as f64;
        let r = Rotation3::from_axis_angle(&Unit::new_unchecked(axis), angle);
        legs.extend(template.iter().map(|leg| rotated_leg(leg, &r, &point)));
    }
    // A copy's actuators are named by the expanded leg they drive.
    for (n, leg) in legs.iter_mut().enumerate() {
        for actuator in &mut leg.actuators {
            if let Some((_, joint)) = actuator.name.split_once('.') {
                actuator.name = format!("legs[{n}].{joint}");
            }
        }
    }
    check_count(legs)
}

fn check_count(legs: Vec<LegChain>) -> Result<Vec<LegChain>, RobotFileError> {
    if legs.len() > MAX_LEGS {
        return Err(RobotFileError::invalid(
            "legs",
            legs.len(),
            format!("at most {MAX_LEGS} legs"),
        ));
    }
    Ok(legs)
}

fn rotated_leg(leg: &LegChain, r: &Rotation3<f64>, c: &Vector3<f64>) -> LegChain {
    let turn = |p: &Vector3<f64>| r * (p - c) + c;
    let joints = leg
        .joints
        .iter()
        .map(|j| match j {
            Joint::Revolute { axis, point } => Joint::Revolute {
                axis: r * axis,
                point: turn(point),
            },
            Joint::Prismatic { axis } => Joint::Prismatic { axis: r * axis },
            Joint::Spherical { center } => Joint::Spherical {
                center: turn(center),
            },
        })
        .collect();
    LegChain {
        joints,
        bodies: leg.bodies.iter().map(|b| b.rotated(r, c)).collect(),
        ..leg.clone()
    }
}

/// One leg of the file as elementary joints.
fn leg_chain(i: usize, leg: &LegSpec) -> Result<LegChain, RobotFileError> {
    let key = format!("legs[{i}].joints");
    if leg.joints.is_empty() || leg.joints.len() > MAX_JOINTS_PER_LEG {
        return Err(RobotFileError::invalid(
            &key,
            leg.joints.len(),
            format!("a leg has 1 to {MAX_JOINTS_PER_LEG} joints"),
        ));
    }
    let mut joints = Vec::new();
    let mut letters = String::new();
    let mut actuated = Vec::new();
    let mut ends = Vec::with_capacity(leg.joints.len());
    for (k, spec) in leg.joints.iter().enumerate() {
        let key = format!("{key}[{k}]");
        if spec.actuated {
            actuated.push((joints.len(), spec, key.clone()));
        }
        letters.push(letter(spec.kind));
        joints.extend(elementary_joints(&key, spec)?);
        ends.push(joints.len());
    }
    let bodies = crate::mass::leg_bodies(i, leg, &ends)?;
    let actuators = actuated
        .into_iter()
        .map(|(joint, spec, key)| {
            if !matches!(spec.kind, JointType::R | JointType::P) {
                return Err(RobotFileError::invalid(
                    format!("{key}.type"),
                    spec.kind,
                    "only an R or a P joint can be actuated",
                ));
            }
            Ok(LegActuator {
                joint,
                offset: spec.offset,
                limits: spec.limits,
                reflected_inertia: crate::mass::reflected_inertia(&key, spec)?,
                name: key,
            })
        })
        .collect::<Result<_, _>>()?;
    Ok(LegChain {
        joints,
        actuators,
        letters,
        bodies,
    })
}

fn letter(kind: JointType) -> char {
    match kind {
        JointType::R => 'R',
        JointType::P => 'P',
        JointType::U => 'U',
        JointType::S => 'S',
        JointType::C => 'C',
    }
}

/// The elementary joints of one joint of the file (U = two R, C = R + P on one axis).
fn elementary_joints(key: &str, spec: &JointSpec) -> Result<Vec<Joint>, RobotFileError> {
    check_scalars(key, spec)?;
    let needs = |field: &str, present: bool, wanted: bool| {
        if present == wanted {
            Ok(())
        } else if wanted {
            Err(RobotFileError::invalid(
                format!("{key}.{field}"),
                "missing",
                format!("required by a {:?} joint", spec.kind),
            ))
        } else {
            Err(RobotFileError::invalid(
                format!("{key}.{field}"),
                "given",
                format!("not used by a {:?} joint", spec.kind),
            ))
        }
    };
    let (axis, axes, point) = (
        spec.axis.is_some(),
        spec.axes.is_some(),
        spec.point.is_some(),
    );
    let wanted = match spec.kind {
        JointType::R | JointType::C => (true, false, true),
        JointType::P => (true, false, false),
        JointType::U => (false, true, true),
        JointType::S => (false, false, true),
    };
    needs("axis", axis, wanted.0)?;
    needs("axes", axes, wanted.1)?;
    needs("point", point, wanted.2)?;
    let point = match spec.point {
        Some(p) => finite_vector(&format!("{key}.point"), &p, MAX_COORDINATE)?,
        None => Vector3::zeros(),
    };
    let axis = match spec.axis {
        Some(a) => unit_vector(&format!("{key}.axis"), &a)?,
        None => Vector3::z(),
    };
    Ok(match spec.kind {
        JointType::R => vec![Joint::Revolute { axis, point }],
        JointType::P => vec![Joint::Prismatic { axis }],
        JointType::C => vec![Joint::Revolute { axis, point }, Joint::Prismatic { axis }],
        JointType::S => vec![Joint::Spherical { center: point }],
        JointType::U => {
            let [a, b] = spec.axes.unwrap_or_default();
            let a = unit_vector(&format!("{key}.axes[0]"), &a)?;
            let b = unit_vector(&format!("{key}.axes[1]"), &b)?;
            if a.cross(&b).norm() < 1e-6 {
                return Err(RobotFileError::invalid(
                    format!("{key}.axes"),
                    spec.axes,
                    "the two axes of a U joint must not be parallel",
                ));
            }
            vec![
                Joint::Revolute { axis: a, point },
                Joint::Revolute { axis: b, point },
            ]
        }
    })
}

fn check_scalars(key: &str, spec: &JointSpec) -> Result<(), RobotFileError> {
    if !(spec.offset.is_finite() && spec.offset.abs() <= MAX_COORDINATE) {
        return Err(RobotFileError::invalid(
            format!("{key}.offset"),
            spec.offset,
            "must be finite, within ±1e6",
        ));
    }
    if let Some([lo, hi]) = spec.limits {
        let bounded = |v: f64| v.is_finite() && v.abs() <= MAX_COORDINATE;
        if !(bounded(lo) && bounded(hi) && lo <= spec.offset && spec.offset <= hi) {
            return Err(RobotFileError::invalid(
                format!("{key}.limits"),
                [lo, hi],
                "must be finite, within ±1e6 (m or rad), with min <= offset <= max",
            ));
        }
        if !spec.actuated {
            return Err(RobotFileError::invalid(
                format!("{key}.limits"),
                [lo, hi],
                "limits are read for the actuated joint only",
            ));
        }
    }
    if !spec.actuated {
        for (field, given) in [
            ("rotor_inertia", spec.rotor_inertia),
            ("gear_ratio", spec.gear_ratio),
        ] {
            if let Some(v) = given {
                return Err(RobotFileError::invalid(
                    format!("{key}.{field}"),
                    v,
                    "a rotor belongs to an actuated joint",
                ));
            }
        }
    }
    Ok(())
}

/// The points of a leg's joints (R points, S centres).
/// The number of actuated legs, which must come first: a passive leg (no actuated joint)
/// after every actuated one, so that the legs' order numbers the actuators.
///
/// # Errors
/// The first actuated leg that follows a passive one, or a robot without an actuated leg.
fn actuated_legs(legs: &[LegChain]) -> Result<usize, RobotFileError> {
    let actuated = legs.iter().take_while(|l| !l.actuators.is_empty()).count();
    if let Some(late) = legs[actuated..]
        .iter()
        .position(|l| !l.actuators.is_empty())
    {
        return Err(RobotFileError::invalid(
            format!("legs[{}]", actuated + late),
            "actuated",
            format!(
                "follows the passive leg legs[{actuated}]: list every passive leg (no actuated \
                 joint) after the actuated ones, whose order numbers the actuators"
            ),
        ));
    }
    if actuated == 0 {
        return Err(RobotFileError::invalid(
            "legs",
            legs.len(),
            "no leg has an actuated joint",
        ));
    }
    Ok(actuated)
}

fn joint_points(leg: &LegChain) -> impl Iterator<Item = Vector3<f64>> + '_ {
    leg.joints.iter().filter_map(|j| match j {
        Joint::Revolute { point, .. } => Some(*point),
        Joint::Spherical { center } => Some(*center),
        Joint::Prismatic { .. } => None,
    })
}

fn robot_size(legs: &[LegChain], home: &Isometry3<f64>) -> f64 {
    let origin = home.translation.vector;
    legs.iter()
        .flat_map(joint_points)
        .map(|p| (p - origin).norm())
        .fold(0.0, f64::max)
        .max(1e-3)
}

/// Mean distance from the platform origin of each leg's last joint point (1 m if it is below
/// [`MIN_CHARACTERISTIC_LENGTH`]).
fn default_characteristic_length(legs: &[LegChain], home: &Isometry3<f64>) -> f64 {
    let origin = home.translation.vector;
    let distances: Vec<f64> = legs
        .iter()
        .filter_map(|l| joint_points(l).last())
        .map(|p| (p - origin).norm())
        .collect();
    let mean = distances.iter().sum::<f64>() / distances.len().max(1) as f64;
    if mean >= MIN_CHARACTERISTIC_LENGTH {
        mean
    } else {
        1.0
    }
}
