//! Forward kinematics: damped Newton on the closure with the actuators held, from a given
//! assembly mode; and every assembly mode by seeded multistart with de-duplication, each
//! labelled by continuation back to the home configuration (never by a determinant's sign).

use crate::chain::JointValue;
use crate::closure::{ClosureProblem, Configuration, LegResidual, same_pose};
use crate::jacobian::SingularityMargins;
use crate::lm::{SolverSettings, levenberg_marquardt};
use crate::model::RobotModel;
use crate::polynomial::HomotopyReport;
use crate::pose::CoordinateRole;
use crate::self_motion::{SINGULAR_MARGIN, SelfMotion};
use nalgebra::{Rotation3, Vector3};
use pkm_traits::{InvalidInput, KinematicsError};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Steps of a continuation in the actuator coordinates.
const CONTINUATION_STEPS: usize = 16;
/// Most starts of an enumeration.
pub const MAX_STARTS: usize = 100_000;

/// How [`RobotModel::assembly_modes`] searches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ModeSearch {
    /// Parameter homotopy where the robot has a polynomial form
    /// ([`RobotModel::forward_kinematics_all`]), with the multistart added when its report is
    /// not complete; the multistart alone otherwise. The default.
    #[default]
    Auto,
    /// The seeded multistart alone.
    Multistart,
}

/// Settings of [`RobotModel::assembly_modes`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnumerationSettings {
    /// How to search.
    pub method: ModeSearch,
    /// Random starts of the multistart. Default 200.
    pub starts: usize,
    /// Seed of the ChaCha8 stream of starts. Default 0.
    pub seed: u64,
    /// Two solutions are one when their pose coordinates differ by less than this (m, rad).
    /// Default 1e-6: far above the 1e-12 closure tolerance, far below any real separation.
    pub distinct: f64,
    /// Label every mode by continuation back to the home actuators
    /// ([`AssemblyMode::home_label`]): a second search at home (unless `q` is home) and a
    /// continuation per mode. Default true; false leaves every label `None`.
    pub label: bool,
}

impl Default for EnumerationSettings {
    fn default() -> Self {
        Self {
            method: ModeSearch::Auto,
            starts: 200,
            seed: 0,
            distinct: 1e-6,
            label: true,
        }
    }
}

/// One assembly mode at given actuator coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct AssemblyMode {
    /// The configuration (pose and every joint).
    pub configuration: Configuration,
    /// The task coordinates.
    pub task: Vec<f64>,
    /// Continuation label: `Some(k)` when following the actuators back to home lands on the
    /// home assembly mode enumerated `k`-th at home (0 is the home configuration itself);
    /// `None` when the path meets a singularity, or when labels were not asked for
    /// ([`EnumerationSettings::label`]).
    pub home_label: Option<usize>,
    /// The singularity margins there; a mode with a zero margin is a singular solution (an
    /// actuator free at a fixed pose, as the Agile Eye's platform axis on an actuated axis,
    /// valid for a range of actuator coordinates; or a self-motion).
    pub margins: SingularityMargins,
    /// `Some` when the mode is one point of a continuum of solutions at these actuator
    /// coordinates (a self-motion), reported once for every solution found on it.
    pub self_motion: Option<SelfMotion>,
}

/// Every assembly mode found at one set of actuator coordinates, with how they were found.
#[derive(Debug, Clone, PartialEq)]
pub struct AssemblySearch {
    /// The modes.
    pub modes: Vec<AssemblyMode>,
    /// The homotopy's report when it ran: with [`HomotopyReport::complete`], the modes are
    /// every real assembly mode.
    pub homotopy: Option<HomotopyReport>,
    /// Whether the multistart ran (the robot has no polynomial form, the homotopy's report
    /// was not complete, or it was asked for).
    pub multistart: bool,
}

impl AssemblyMode {
    /// Whether the mode is singular: an inverse or direct margin below `tolerance`.
    pub fn is_singular(&self, tolerance: f64) -> bool {
        !(self.margins.inverse > tolerance && self.margins.direct > tolerance)
    }
}

impl RobotModel {
    /// Forward kinematics: the configuration with actuator coordinates `q` closest (by damped
    /// Newton) to `seed`.
    ///
    /// # Errors
    /// [`KinematicsError::InvalidInput`] / [`KinematicsError::NonFinite`] for a bad `q`;
    /// [`KinematicsError::NotConverged`] with the residual reached.
    pub fn forward_kinematics_from(
        &self,
        q: &[f64],
        seed: &Configuration,
    ) -> Result<Configuration, KinematicsError> {
        self.forward_kinematics_with(q, seed, &SolverSettings::default())
    }

    /// [`RobotModel::forward_kinematics_from`] with explicit solver settings.
    pub(crate) fn forward_kinematics_with(
        &self,
        q: &[f64],
        seed: &Configuration,
        settings: &SolverSettings,
    ) -> Result<Configuration, KinematicsError> {
        self.check_configuration(seed)?;
        let mut start = seed.clone();
        self.set_actuators(&mut start, q)?;
        let problem = ClosureProblem {
            model: self,
            legs: (0..self.legs.len()).collect(),
            free_pose: (0..6)
                .filter(|&k| {
                    matches!(
                        self.roles[k],
                        CoordinateRole::Task | CoordinateRole::Dependent
                    )
                })
                .collect(),
            fixed_actuators: true,
            residual: LegResidual::Pose,
        };
        let (mut c, _) = levenberg_marquardt(&problem, start, settings)?;
        c.pose = crate::pose::canonical(self.orientation, &c.pose);
        Ok(c)
    }

    pub(crate) fn set_actuators(
        &self,
        c: &mut Configuration,
        q: &[f64],
    ) -> Result<(), KinematicsError> {
        if q.len() != self.actuator_count() {
            return Err(InvalidInput::new(
                "q.len()",
                q.len() as f64,
                "must equal the number of actuators",
            )
            .into());
        }
        if let Some(&value) = q.iter().find(|v| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { what: "q", value });
        }
        for (i, &q_i) in q.iter().enumerate() {
            let (leg, actuator) = self.actuator(i);
            c.joints[leg][actuator.joint] = JointValue::Scalar(q_i - actuator.offset);
        }
        Ok(())
    }

    /// Forward kinematics by continuation from home: the actuators walk from home to `q` in
    /// equal steps, each solved from the last. Its result is the assembly mode "of home".
    ///
    /// # Errors
    /// As [`RobotModel::forward_kinematics_from`] at any step (a singularity on the path).
    pub fn forward_kinematics_from_home(
        &self,
        q: &[f64],
    ) -> Result<Configuration, KinematicsError> {
        self.continuation(&self.home_actuators(), q, Configuration::home(self))
    }

    fn continuation(
        &self,
        from: &[f64],
        to: &[f64],
        mut c: Configuration,
    ) -> Result<Configuration, KinematicsError> {
        if to.len() != from.len() {
            return Err(InvalidInput::new(
                "q.len()",
                to.len() as f64,
                "must equal the number of actuators",
            )
            .into());
        }
        for step in 1..=CONTINUATION_STEPS {
            let s = step as f64 / CONTINUATION_STEPS as f64;
            let q: Vec<f64> = from.iter().zip(to).map(|(a, b)| a + s * (b - a)).collect();
            c = self.forward_kinematics_from(&q, &c)?;
        }
        Ok(c)
    }

    /// Every assembly mode found at actuator coordinates `q` ([`RobotModel::assembly_search`]
    /// without the statement of how they were found).
    ///
    /// # Errors
    /// As [`RobotModel::assembly_search`].
    pub fn assembly_modes(
        &self,
        q: &[f64],
        settings: &EnumerationSettings,
    ) -> Result<Vec<AssemblyMode>, KinematicsError> {
        Ok(self.assembly_search(q, settings)?.modes)
    }

    /// Every assembly mode found at actuator coordinates `q`, de-duplicated, ordered by their
    /// distance from the home pose, each labelled by continuation back to home: by parameter
    /// homotopy where the robot has a polynomial form ([`ModeSearch::Auto`]: every mode when
    /// its report is complete), with the damped Newton from home and from `settings.starts`
    /// seeded random configurations added otherwise; with the report of the homotopy.
    ///
    /// # Errors
    /// [`KinematicsError::InvalidInput`] for a bad `q` or too many starts (at most 100 000).
    pub fn assembly_search(
        &self,
        q: &[f64],
        settings: &EnumerationSettings,
    ) -> Result<AssemblySearch, KinematicsError> {
        InvalidInput::require_count_at_most(
            "starts",
            settings.starts,
            MAX_STARTS,
            "at most 100000 starts",
        )?;
        InvalidInput::require_positive("distinct", settings.distinct)?;
        let (mut found, homotopy, multistart) = self.searched(q, settings)?;
        let home = self.home;
        let distance = |c: &Configuration| {
            c.pose
                .iter()
                .zip(&home)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        };
        found.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
        let home_modes = if !settings.label {
            Vec::new()
        } else if q == self.home_actuators().as_slice() {
            found.clone()
        } else {
            let mut at_home = self.searched(&self.home_actuators(), settings)?.0;
            at_home.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
            at_home
        };
        let margins: Vec<SingularityMargins> = found
            .iter()
            .map(|c| {
                self.singularity_margins(c).unwrap_or(SingularityMargins {
                    inverse: 0.0,
                    direct: 0.0,
                    constraint: Some(0.0),
                })
            })
            .collect();
        let singular: Vec<usize> = (0..found.len())
            .filter(|&k| !(margins[k].direct >= SINGULAR_MARGIN))
            .collect();
        let mut self_motion: Vec<Option<Option<SelfMotion>>> = vec![Some(None); found.len()];
        for group in self.self_motions(q, &found, &singular) {
            let motion = SelfMotion {
                samples: group.len(),
                extent: self.extent(&found, &group),
            };
            for &k in &group[1..] {
                self_motion[k] = None;
            }
            self_motion[group[0]] = Some(Some(motion));
        }
        let modes = found
            .into_iter()
            .zip(margins)
            .zip(self_motion)
            .filter_map(|((c, margins), motion)| {
                let self_motion = motion?;
                let home_label = (settings.label)
                    .then(|| self.continuation(q, &self.home_actuators(), c.clone()).ok())
                    .flatten()
                    .and_then(|back| {
                        home_modes
                            .iter()
                            .position(|m| same_pose(self.orientation, m, &back, settings.distinct))
                    });
                let task = self.task.iter().map(|&k| c.pose[k]).collect();
                Some(AssemblyMode {
                    configuration: c,
                    task,
                    home_label,
                    margins,
                    self_motion,
                })
            })
            .collect();
        Ok(AssemblySearch {
            modes,
            homotopy,
            multistart,
        })
    }

    /// The distinct solutions at `q` by the method of `settings`, with the homotopy's report
    /// and whether the multistart ran.
    fn searched(
        &self,
        q: &[f64],
        settings: &EnumerationSettings,
    ) -> Result<(Vec<Configuration>, Option<HomotopyReport>, bool), KinematicsError> {
        let all = match settings.method {
            ModeSearch::Auto if self.homotopy_unsupported().is_none() => {
                Some(self.forward_kinematics_all(q)?)
            }
            _ => None,
        };
        let complete = all.as_ref().is_some_and(|a| a.report.complete());
        let mut found = all
            .as_ref()
            .map_or_else(Vec::new, |a| a.configurations.clone());
        if !complete {
            for c in self.solutions(q, settings)? {
                if !found
                    .iter()
                    .any(|f| same_pose(self.orientation, f, &c, settings.distinct))
                {
                    found.push(c);
                }
            }
        }
        Ok((found, all.map(|a| a.report), !complete))
    }

    /// The distinct solutions at `q` from home and from the seeded random starts.
    fn solutions(
        &self,
        q: &[f64],
        settings: &EnumerationSettings,
    ) -> Result<Vec<Configuration>, KinematicsError> {
        let mut home = Configuration::home(self);
        self.set_actuators(&mut home, q)?;
        let mut found: Vec<Configuration> = Vec::new();
        let mut rng = ChaCha8Rng::seed_from_u64(settings.seed);
        for start in 0..=settings.starts {
            let seed = if start == 0 {
                home.clone()
            } else {
                self.random_start(&home, &mut rng)
            };
            let Ok(c) = self.forward_kinematics_from(q, &seed) else {
                continue;
            };
            if !found
                .iter()
                .any(|f| same_pose(self.orientation, f, &c, settings.distinct))
            {
                found.push(c);
            }
        }
        Ok(found)
    }

    /// A random start: free pose coordinates around home (±size, ±π) and random joint values.
    fn random_start(&self, home: &Configuration, rng: &mut ChaCha8Rng) -> Configuration {
        let mut c = home.clone();
        for k in 0..6 {
            if matches!(
                self.roles[k],
                CoordinateRole::Task | CoordinateRole::Dependent
            ) {
                let span = if k < 3 {
                    self.size
                } else {
                    std::f64::consts::PI
                };
                c.pose[k] += span * rng.random_range(-1.0..1.0);
            }
        }
        for (i, leg) in self.legs.iter().enumerate() {
            for (j, value) in c.joints[i].iter_mut().enumerate() {
                if leg.is_actuated(j) {
                    continue;
                }
                *value = match value {
                    JointValue::Scalar(_) => JointValue::Scalar(
                        rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
                    ),
                    JointValue::Ball(_) => JointValue::Ball(Rotation3::new(Vector3::new(
                        rng.random_range(-2.0..2.0),
                        rng.random_range(-2.0..2.0),
                        rng.random_range(-2.0..2.0),
                    ))),
                };
            }
        }
        c
    }
}
