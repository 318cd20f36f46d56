//! `pkm.Mechanism`: one design (a preset name or a `[mechanism.<kind>]` dict) under its
//! workspace constraints, with its kinematics vectorised over N × 3 arrays of positions, or
//! N × n arrays of its own task coordinates for a robot file whose task is not the position.
//!
//! Every kernel reads the array in place, releases the GIL and maps the rows on rayon threads;
//! a row the library puts outside the workspace (no working mode assembles within the
//! constraints, or Newton does not converge) is NaN with `False` in the mask beside it.

use crate::kernels::{self, Kernel, Op};
use crate::task_kernels::TaskSpaceModel;
use crate::{convert, errors, points, presets};
use pkm_study::StudyError;
use pkm_study::StudyMechanism as _;
use pkm_study::registry::Built;
use pkm_study::schema::mechanism::{ConstraintsSpec, MechanismSpec};
use pkm_study::workspace::checked_constraints;
use pkm_traits::WorkspaceConstraint;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use serde::Deserialize;

/// A design with its workspace constraints, as a study's `[mechanism]` and `[constraints]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Design {
    mechanism: MechanismSpec,
    constraints: Option<ConstraintsSpec>,
}

/// A parallel kinematic machine: `design` is a preset name (see `pkm.presets()`) or the
/// study layer's `[mechanism]` table as a dict (`{"rotary_delta": {"arm": 0.2, ...}}`, or a
/// robot file `{"robot_file": {"file": "robots/tsai.toml"}}` read from the working directory,
/// or its keys inline);
/// `constraints` is a `[constraints]` table (`{"joint_range_deg": [-40, 90]}`).
///
/// Raises `pkm.InvalidInput` (with `.key_path`) for a design or constraint the study layer
/// refuses.
#[pyclass(frozen, module = "pkm")]
pub(crate) struct Mechanism {
    /// The design, built once.
    built: Built<MechanismSpec>,
    constraints_spec: Option<ConstraintsSpec>,
    constraints: Vec<WorkspaceConstraint>,
    joints: usize,
    /// A robot file whose task is not `["x", "y", "z"]`: its task-space kernels.
    task_space: Option<TaskSpaceModel>,
}

#[pymethods]
impl Mechanism {
    #[new]
    #[pyo3(signature = (design, constraints = None))]
    fn new(
        py: Python<'_>,
        design: &Bound<'_, PyAny>,
        constraints: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let table = PyDict::new(py);
        match design.cast::<PyString>() {
            Ok(name) => {
                let name: String = name.extract()?;
                let spec = presets::spec(&name).ok_or_else(|| presets::unknown(py, &name))?;
                table.set_item("mechanism", convert::to_python(py, &spec)?)?;
            }
            Err(_) => table.set_item("mechanism", design)?,
        }
        if let Some(c) = constraints {
            table.set_item("constraints", c)?;
        }
        let design: Design = convert::from_python(&table)?;
        Self::build(py, design)
    }

    /// The mechanism kind (`"rotary_delta"`, `"tsai"`, ...).
    #[getter]
    fn kind(&self) -> &'static str {
        self.built.spec().kind()
    }

    /// The number of actuated joints (3, or 6 for the Stewart–Gough platform; a robot file's
    /// actuators).
    #[getter]
    fn joints(&self) -> usize {
        self.joints
    }

    /// The name of each actuator of a robot file, the columns of every joint array: the key
    /// path of its joint (`"legs[0].joints[1]"`; a leg may carry several); `None` for a
    /// built-in mechanism.
    #[getter]
    fn actuators(&self) -> Option<Vec<String>> {
        let names = |model: &pkm_robot_file::RobotModel| {
            model
                .actuator_names()
                .into_iter()
                .map(String::from)
                .collect()
        };
        match (&self.task_space, self.built.spec()) {
            (Some(ts), _) => Some(names(&ts.model)),
            (None, MechanismSpec::RobotFile(robot)) => robot.model().ok().map(|m| names(&m)),
            _ => None,
        }
    }

    /// The task coordinates, the columns of every `points` array: `["x", "y", "z"]` (m), or a
    /// robot file's own (`["z", "tilt_x", "tilt_y"]`: lengths in m, angles in rad).
    #[getter]
    fn task(&self) -> Vec<&'static str> {
        match &self.task_space {
            Some(ts) => ts.model.task_names(),
            None => vec!["x", "y", "z"],
        }
    }

    /// The design variables a sweep may vary.
    #[getter]
    fn variables(&self) -> Vec<String> {
        self.built
            .spec()
            .variables()
            .iter()
            .map(|v| v.name.to_string())
            .collect()
    }

    /// The `[mechanism]` and `[constraints]` tables of this mechanism, as a dict a study takes.
    fn design<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        out.set_item("mechanism", convert::to_python(py, self.built.spec())?)?;
        if let Some(c) = &self.constraints_spec {
            out.set_item("constraints", convert::to_python(py, c)?)?;
        }
        Ok(out)
    }

    fn __repr__(&self) -> String {
        format!(
            "pkm.Mechanism({:?}, {} joints, {} constraints)",
            self.built.spec().kind(),
            self.joints,
            self.constraints.len()
        )
    }

    /// Joint coordinates at each position: `points` is N × 3 (m); returns the N × joints
    /// array (rad or m) of the first working mode that assembles within the constraints, and
    /// the boolean mask of the rows inside the workspace (the other rows are NaN).
    fn inverse_kinematics<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let (values, mask, n) = self.run(py, points, Op::Inverse)?;
        Ok((
            points::array(py, values, &[n, self.joints])?,
            points::mask(py, mask),
        ))
    }

    /// The velocity Jacobian J = -J_q⁻¹ J_x (q̇ = J ẋ) at each position: N × joints × 3 (× n
    /// for a robot file in its task space), and
    /// the mask of the rows where the point is inside the workspace and J is defined (not at
    /// an inverse-kinematic singularity); the other rows are NaN.
    fn velocity_jacobian<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let (values, mask, n) = self.run(py, points, Op::Jacobian)?;
        let shape = [n, self.joints, self.task().len()];
        Ok((points::array(py, values, &shape)?, points::mask(py, mask)))
    }

    /// The local index of the workspace studies at each position: `"inverse_condition"`
    /// (1/κ of J in [0, 1], 0 where J_q is singular; the value the workspace study
    /// integrates; for a robot file in its task space, of the homogenised J) and `"inside"`
    /// (the mask; outside rows are NaN). A robot file in its task space adds its three
    /// singularity margins, `"inverse_margin"`, `"direct_margin"` and `"constraint_margin"`
    /// (NaN without constraint wrenches).
    fn local_indices<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (values, mask, n) = self.run(py, points, Op::InverseCondition)?;
        let out = PyDict::new(py);
        out.set_item("inverse_condition", points::array(py, values, &[n])?)?;
        out.set_item("inside", points::mask(py, mask))?;
        if let Some(ts) = &self.task_space {
            let array = points::rows(points, "points", ts.dimension())?;
            let view = array.as_array();
            let (margins, _) = py
                .detach(|| ts.margins(&view))
                .map_err(|m| errors::invalid(py, m))?;
            let columns: Vec<Vec<f64>> = (0..3)
                .map(|c| margins.iter().skip(c).step_by(3).copied().collect())
                .collect();
            for (name, column) in ["inverse_margin", "direct_margin", "constraint_margin"]
                .into_iter()
                .zip(columns)
            {
                out.set_item(name, points::array(py, column, &[n])?)?;
            }
        }
        Ok(out)
    }

    /// Whether each position (N × 3, m) belongs to the workspace under the constraints.
    fn contains<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (_, mask, _) = self.run(py, points, Op::Contains)?;
        Ok(points::mask(py, mask))
    }

    /// Positions that close the loops for N × 3 `joints` (Newton from the N × 3 `guess`, which
    /// selects the assembly mode): the N × 3 positions and the mask of the rows where Newton
    /// converged (the others are NaN). For a robot file, damped Newton on the closure of every
    /// leg, its passive joints started from the inverse kinematics at `guess` on the branches
    /// nearest `joints` (`pkm_robot_file::Robot`). Not defined for the Stewart–Gough platform
    /// at a fixed orientation (6 legs, 3 coordinates).
    fn forward_kinematics<'py>(
        &self,
        py: Python<'py>,
        joints: &Bound<'py, PyAny>,
        guess: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let (legs, n) = match &self.task_space {
            Some(ts) => (ts.joints(), ts.dimension()),
            None => (3, 3),
        };
        let q = points::rows(joints, "joints", legs)?;
        let g = points::rows(guess, "guess", n)?;
        let (q, g) = (q.as_array(), g.as_array());
        if q.nrows() != g.nrows() {
            return Err(errors::invalid(
                py,
                format!("guess: {} rows for {} rows of joints", g.nrows(), q.nrows()),
            ));
        }
        kernels::require_finite(py, &q, "joints")?;
        kernels::require_finite(py, &g, "guess")?;
        let rows = q.nrows();
        let (built, task_space) = (&self.built, &self.task_space);
        let (values, mask) = py
            .detach(|| match task_space {
                Some(ts) => ts.forward(&q, &g),
                None => kernels::forward(built, q, g),
            })
            .map_err(|m| errors::invalid(py, m))?;
        Ok((
            points::array(py, values, &[rows, n])?,
            points::mask(py, mask),
        ))
    }

    /// For benches/python: seconds the `local_indices` kernel takes on a Rust-owned copy of
    /// `points` (the copy is made before the clock starts), without any Python object.
    fn _time_rust_kernel(&self, py: Python<'_>, points: &Bound<'_, PyAny>) -> PyResult<f64> {
        let owned = points::rows(points, "points", 3)?.as_array().to_owned();
        let (built, constraints) = (&self.built, &self.constraints);
        py.detach(|| {
            let start = std::time::Instant::now();
            let kernel = Kernel {
                points: owned.view(),
                op: Op::InverseCondition,
            };
            let out = built.with_workspace(constraints, kernel);
            let seconds = start.elapsed().as_secs_f64();
            out.map(|_| seconds)
        })
        .map_err(|e| errors::study_error(py, &StudyError::from(e)))
    }
}

impl Mechanism {
    fn build(py: Python<'_>, design: Design) -> PyResult<Self> {
        let mut spec = design.mechanism;
        // `{"robot_file": {"file": "robots/tsai.toml"}}`: relative to the working directory,
        // as every file name of a study given as a dict.
        if let MechanismSpec::RobotFile(robot) = &mut spec {
            robot
                .resolve_file(&pkm_study::load::Directory::default())
                .map_err(|e| errors::study_error(py, &e))?;
        }
        let refused = |e: StudyError| errors::study_error(py, &e);
        spec.check().map_err(refused)?;
        let built = Built::new(spec).map_err(|e| refused(e.into()))?;
        let constraints =
            checked_constraints(&built, design.constraints.as_ref()).map_err(refused)?;
        let task_space = Self::task_space(built.spec(), &constraints).map_err(refused)?;
        let joints = match &task_space {
            Some(ts) => ts.joints(),
            None => built
                .with_workspace(&constraints, kernels::JointCount)
                .map_err(|e| refused(e.into()))?,
        };
        Ok(Self {
            built,
            constraints_spec: design.constraints,
            constraints,
            joints,
            task_space,
        })
    }

    /// The task-space model of a robot file whose task is not the position, its constraints
    /// checked; `None` for every other design.
    fn task_space(
        spec: &MechanismSpec,
        constraints: &[WorkspaceConstraint],
    ) -> Result<Option<TaskSpaceModel>, StudyError> {
        let MechanismSpec::RobotFile(robot) = spec else {
            return Ok(None);
        };
        let model = robot.model()?;
        if model.task_names() == ["x", "y", "z"] {
            return Ok(None);
        }
        let modes = robot.working_modes(&model)?;
        pkm_robot_file::TaskWorkspace::new(&model, &modes, constraints, Default::default())
            .map_err(|e| StudyError::invalid("constraints", e.to_string()))?;
        Ok(Some(TaskSpaceModel {
            model,
            modes,
            constraints: constraints.to_vec(),
        }))
    }

    /// Runs `op` on the rows of `points` with the GIL released: the values (row-major), the
    /// mask and the number of rows.
    fn run(
        &self,
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        op: Op,
    ) -> PyResult<(Vec<f64>, Vec<bool>, usize)> {
        let columns = self
            .task_space
            .as_ref()
            .map_or(3, TaskSpaceModel::dimension);
        let array = points::rows(points, "points", columns)?;
        let view = array.as_array();
        kernels::require_finite(py, &view, "points")?;
        let n = view.nrows();
        if let Some(ts) = &self.task_space {
            let (values, mask) = py
                .detach(|| ts.run(&view, op))
                .map_err(|m| errors::invalid(py, m))?;
            return Ok((values, mask, n));
        }
        let (built, constraints) = (&self.built, &self.constraints);
        let (values, mask) = py
            .detach(|| built.with_workspace(constraints, Kernel { points: view, op }))
            .map_err(|e| errors::study_error(py, &StudyError::from(e)))?;
        Ok((values, mask, n))
    }
}
