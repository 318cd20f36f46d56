//! The mechanism registry: what a study needs to know about a mechanism, stated once per
//! mechanism through the [`StudyMechanism`] trait rather than a match arm per command.
//!
//! A study's `[mechanism.<kind>]` table is one of the kinds listed by [`mechanisms!`](crate::mechanisms!) (one
//! line each); every command takes any [`StudyMechanism`] (a task study a
//! [`TaskMechanism`](crate::task::TaskMechanism) too), so a new mechanism is a table type
//! (plain serde), a [`design_variables!`](crate::design_variables!) line and an `impl StudyMechanism`, then one line in a
//! [`mechanisms!`](crate::mechanisms!) list (see `docs/adding-a-mechanism.md`).

pub use crate::schema::constraints::Actuation;
use crate::schema::constraints::ConstraintsSpec;
use crate::{Infeasible, StudyError};
use nalgebra::Vector3;
use pkm_design_problems::DesignProblem;
use pkm_mechanisms::Skeleton;
use pkm_traits::{
    ConstrainedWorkspace, CrossSectionWorkspace, DesignError, ForwardKinematics,
    WorkspaceConstraint,
};
use pkm_workspace_indices::{Dim, Region, TranslationalCondition, Workspace};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::borrow::Cow;
use std::fmt::Debug;

/// The unit of a design variable in a study (the library receives SI units and radians).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Unit {
    /// Metres.
    Length,
    /// Degrees in a study (its key ends in `_deg`), radians in the library.
    Angle,
    /// Dimensionless.
    Ratio,
}

/// A design variable as a study names it: a key of the table (a static name), or a name the
/// table itself declares (a robot file's `[parameters]`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Variable {
    /// Its key in the `[mechanism.<kind>]` table (`"alpha_deg"`).
    pub name: Cow<'static, str>,
    /// Its unit in the study.
    pub unit: Unit,
}

/// A mechanism as a study sees it: its table (serde), its design variables, its actuation, and
/// the library mechanism it builds ([`StudyMechanism::build`]), whose workspace, reach region,
/// drawing and forward kinematics a study asks of one [`Built`] handle.
pub trait StudyMechanism: Debug + Clone + Send + Sync + Serialize + DeserializeOwned {
    /// The library mechanism this table builds, with what its questions need beyond the table.
    type Built: Send + Sync + 'static;

    /// The kind's key: `[mechanism.<kind>]`.
    fn kind(&self) -> &'static str;

    /// The design variables a sweep, a Pareto study or an optimisation may vary: a static
    /// list for a table with fixed keys, an owned one for a table that declares its own.
    fn variables(&self) -> Cow<'static, [Variable]>;

    /// The value of variable `name` in its study unit, `None` for an unknown name.
    fn get(&self, name: &str) -> Option<f64>;

    /// The slot of variable `name` (study unit), `None` for an unknown name.
    fn slot(&mut self, name: &str) -> Option<&mut f64>;

    /// How the actuated joints move.
    fn actuation(&self) -> Actuation;

    /// Checks the table before any computation, beyond what its serde types check (default:
    /// nothing more to check).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at the key path of the offending
    /// value.
    fn check(&self) -> Result<(), StudyError> {
        Ok(())
    }

    /// Builds the library mechanism: the one place a table becomes one. A study builds it once
    /// ([`Built::new`]) and asks it every question below.
    ///
    /// # Errors
    /// [`BuildError::Design`] for an invalid design.
    fn build(&self) -> Result<Self::Built, BuildError>;

    /// Hands the workspace of `built` (this table's [`StudyMechanism::build`]) under
    /// `constraints` to `visitor`.
    ///
    /// # Errors
    /// [`BuildError::Constraint`] for a constraint this mechanism cannot evaluate;
    /// [`BuildError::Design`] for a design without a workspace in the platform position.
    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        built: &Self::Built,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError>;

    /// A region that holds every reachable position of `built`, when the mechanism has one
    /// (default: none; studies then give `[sampling.region]`).
    fn reach_region(&self, built: &Self::Built) -> Option<Region> {
        let _ = built;
        None
    }

    /// The skeleton of `built` with the platform at `p`, in the first working mode of the study
    /// that reaches it.
    ///
    /// # Errors
    /// Why it cannot be drawn (no mode reaches `p`).
    fn skeleton_at(&self, built: &Self::Built, p: &Vector3<f64>) -> Result<Skeleton, String>;

    /// Where to look for a pose of `built` to draw when the study gives no region (default:
    /// the reach region).
    ///
    /// # Errors
    /// Why there is none.
    fn drawing_region(&self, built: &Self::Built) -> Result<Region, String> {
        self.reach_region(built)
            .ok_or_else(|| format!("{} has no region to draw a pose in", self.kind()))
    }

    /// The axes `(a, b, normal)` of the vertical cross-section drawn with a design (default:
    /// the plane $y = y_c$).
    fn drawing_plane(&self) -> (usize, usize, usize) {
        (0, 2, 1)
    }

    /// Hands the mechanism with an exact workspace cross-section (the Linear Delta's, Miller
    /// 2004 §2.2: $\eta_1$, $\eta_2$ and the area) to `visitor`, with its working mode;
    /// `None` (the default) for a mechanism without one.
    fn with_cross_section<V: CrossSectionVisitor>(&self, visitor: V) -> Option<V::Output> {
        let _ = visitor;
        None
    }

    /// The library design problem this table poses whose objective is smooth in the design
    /// (the capability of the [`optimize`](crate::optimize()) study); `None` (the default) for
    /// a mechanism without one, whose Monte Carlo workspace volume counts points and so is
    /// piecewise constant in the design.
    fn design_problem(&self) -> Option<DesignProblem> {
        None
    }

    /// Hands `built` to `visitor` as a [`ForwardKinematics`] in the platform position $x$ (the
    /// capability of `pkm.Mechanism.forward_kinematics`).
    ///
    /// # Errors
    /// [`BuildError::Unsupported`] for a mechanism without forward kinematics in $x$ (the
    /// default, with the mechanism's kind); [`BuildError::Design`] for a robot file whose task
    /// is not the position.
    fn with_forward_kinematics<V: ForwardVisitor>(
        &self,
        built: &Self::Built,
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        let _ = (built, visitor);
        Err(BuildError::Unsupported(format!(
            "{} has no forward kinematics in the platform position",
            self.kind()
        )))
    }

    /// The robot file of a `[mechanism.robot_file]` table (default: none), whose studies may
    /// run in its own task space ([`crate::task_space`]).
    fn robot_file(&self) -> Option<&crate::schema::robot_file::RobotFileSpec> {
        None
    }

    /// Sets variable `name` to `value` (study unit). The value is checked when the mechanism is
    /// built, so a sweep records an invalid node as infeasible.
    ///
    /// # Errors
    /// The list of valid names when `name` is not one of [`StudyMechanism::variables`].
    fn set(&mut self, name: &str, value: f64) -> Result<(), String> {
        let kind = self.kind();
        let variables = self.variables();
        let names = variables.iter().map(|v| &*v.name).collect::<Vec<_>>();
        let slot = self.slot(name).ok_or_else(|| {
            format!(
                "`{name}` is not a design variable of {kind}: expected one of {}",
                names.join(", ")
            )
        })?;
        *slot = value;
        Ok(())
    }

    /// The library constraints of a `[constraints]` table (SI units, radians), joint ranges in
    /// the unit of this mechanism's actuation.
    ///
    /// # Errors
    /// A message when a joint range is given in the wrong unit or the library refuses a value.
    fn constraints(&self, spec: &ConstraintsSpec) -> Result<Vec<WorkspaceConstraint>, String> {
        spec.to_library(self.kind(), self.actuation())
    }
}

/// Receives a built workspace, whatever the mechanism type (closures cannot be generic).
pub trait WorkspaceVisitor {
    /// What the visit returns.
    type Output;
    /// Works on `workspace` (`NQ` actuated joints: 3, or a Stewart–Gough platform's 6).
    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Self::Output
    where
        Dim<NQ>: TranslationalCondition<NQ>;
}

/// Receives a mechanism with an exact workspace cross-section, whatever its type
/// ([`StudyMechanism::with_cross_section`]): `key` holds every number that determines the
/// values (the design and the working mode, for a cache keyed by them), `build` constructs the
/// mechanism (called only when a value must be computed).
pub trait CrossSectionVisitor {
    /// What the visit returns.
    type Output;
    /// Works on the mechanism that `build` returns, in `mode`.
    fn visit<M: CrossSectionWorkspace>(
        self,
        key: &[f64],
        mode: M::WorkingMode,
        build: impl FnOnce() -> Result<M, DesignError>,
    ) -> Self::Output;
}

/// Receives a built mechanism with forward kinematics in the platform position, whatever its
/// type ([`StudyMechanism::with_forward_kinematics`]).
pub trait ForwardVisitor {
    /// What the visit returns.
    type Output;
    /// Works on `mechanism` (`NQ` actuated joints).
    fn visit<M: ForwardKinematics<3> + Sync>(self, mechanism: &M) -> Self::Output;
}

/// Why a mechanism cannot answer: an invalid design (recorded as infeasible in sweeps), a
/// constraint it cannot evaluate or a capability it does not have (errors of the study).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BuildError {
    /// The design is infeasible (invalid parameters, a robot file without a model).
    #[error(transparent)]
    Design(#[from] Infeasible),
    /// A constraint does not apply to this mechanism.
    #[error("{0}")]
    Constraint(String),
    /// The mechanism does not have the capability asked for (forward kinematics in the
    /// platform position).
    #[error("{0}")]
    Unsupported(String),
}

/// A study mechanism built once: its table and the library mechanism it builds, asked every
/// question of a study (workspace, reach region, drawing, forward kinematics) without building
/// it again.
///
/// ```
/// use pkm_study::registry::Built;
/// use pkm_study::schema::mechanism::TsaiSpec;
///
/// let table: TsaiSpec = pkm_study::from_toml_str("a = 0.44\nb = 0.56\n")?;
/// let tsai = Built::new(table)?;
/// assert!(tsai.reach_region().is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Built<M: StudyMechanism> {
    spec: M,
    mechanism: M::Built,
}

impl<M: StudyMechanism> Debug for Built<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Built")
            .field("spec", &self.spec)
            .finish_non_exhaustive()
    }
}

impl<M: StudyMechanism> Built<M> {
    /// Builds `spec`'s mechanism.
    ///
    /// # Errors
    /// [`BuildError::Design`] for an invalid design.
    pub fn new(spec: M) -> Result<Self, BuildError> {
        let mechanism = spec.build()?;
        Ok(Self { spec, mechanism })
    }

    /// The table it was built from.
    pub fn spec(&self) -> &M {
        &self.spec
    }

    /// [`StudyMechanism::with_workspace`].
    ///
    /// # Errors
    /// As [`StudyMechanism::with_workspace`].
    pub fn with_workspace<V: WorkspaceVisitor>(
        &self,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        self.spec
            .with_workspace(&self.mechanism, constraints, visitor)
    }

    /// [`StudyMechanism::reach_region`].
    pub fn reach_region(&self) -> Option<Region> {
        self.spec.reach_region(&self.mechanism)
    }

    /// [`StudyMechanism::drawing_region`].
    ///
    /// # Errors
    /// As [`StudyMechanism::drawing_region`].
    pub fn drawing_region(&self) -> Result<Region, String> {
        self.spec.drawing_region(&self.mechanism)
    }

    /// [`StudyMechanism::skeleton_at`].
    ///
    /// # Errors
    /// As [`StudyMechanism::skeleton_at`].
    pub fn skeleton_at(&self, p: &Vector3<f64>) -> Result<Skeleton, String> {
        self.spec.skeleton_at(&self.mechanism, p)
    }

    /// [`StudyMechanism::with_forward_kinematics`].
    ///
    /// # Errors
    /// As [`StudyMechanism::with_forward_kinematics`].
    pub fn with_forward_kinematics<V: ForwardVisitor>(
        &self,
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        self.spec.with_forward_kinematics(&self.mechanism, visitor)
    }
}

/// The built mechanism of a registry ([`mechanisms!`](crate::mechanisms!)): its kind's
/// [`StudyMechanism::Built`], whatever the kind.
pub struct AnyBuilt(Box<dyn std::any::Any + Send + Sync>);

impl Debug for AnyBuilt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AnyBuilt").finish_non_exhaustive()
    }
}

impl AnyBuilt {
    /// `built` behind the registry.
    #[doc(hidden)]
    pub fn new<T: Send + Sync + 'static>(built: T) -> Self {
        Self(Box::new(built))
    }

    /// The kind's built mechanism.
    ///
    /// # Errors
    /// [`BuildError::Unsupported`] when it was built from a table of another kind.
    #[doc(hidden)]
    pub fn get<T: 'static>(&self) -> Result<&T, BuildError> {
        self.0.downcast_ref().ok_or_else(|| {
            BuildError::Unsupported("a mechanism built from a table of another kind".to_owned())
        })
    }
}

pub(crate) fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, V: WorkspaceVisitor, const NQ: usize>(
    mechanism: &M,
    modes: &[M::WorkingMode],
    constraints: &[WorkspaceConstraint],
    visitor: V,
) -> Result<V::Output, BuildError>
where
    Dim<NQ>: TranslationalCondition<NQ>,
{
    let workspace = Workspace::new(mechanism, modes, constraints)
        .map_err(|e| BuildError::Constraint(e.to_string()))?;
    Ok(visitor.visit(&workspace))
}

/// An error of the study at `mechanism`, or at the robot file's key that refused the design.
impl From<BuildError> for StudyError {
    fn from(e: BuildError) -> Self {
        match e {
            BuildError::Design(Infeasible::RobotFile {
                path: Some(path),
                message,
            }) => Self::Invalid { path, message },
            e => Self::invalid("mechanism", e.to_string()),
        }
    }
}

/// Declares a table type's design variables: `design_variables!(Spec { "key" Unit => field
/// path, ... })` implements `variables`, `get` and `slot` of [`StudyMechanism`] inside an
/// `impl StudyMechanism for Spec` block.
#[macro_export]
macro_rules! design_variables {
    ($($name:literal $unit:ident => |$s:ident| $place:expr),* $(,)?) => {
        fn variables(&self) -> ::std::borrow::Cow<'static, [$crate::registry::Variable]> {
            ::std::borrow::Cow::Borrowed(&[$($crate::registry::Variable {
                name: ::std::borrow::Cow::Borrowed($name),
                unit: $crate::registry::Unit::$unit,
            }),*])
        }

        fn get(&self, name: &str) -> Option<f64> {
            match name {
                $($name => {
                    let $s = self;
                    Some($place)
                })*
                _ => None,
            }
        }

        fn slot(&mut self, name: &str) -> Option<&mut f64> {
            match name {
                $($name => {
                    let $s = self;
                    Some(&mut $place)
                })*
                _ => None,
            }
        }
    };
}

/// Declares a registry: an enum with one variant per mechanism table (externally tagged, the
/// tag is the kind: `[mechanism.<kind>]`) that implements [`StudyMechanism`] by delegation.
/// The calling crate depends on `serde` (its tables derive its traits too);
/// `crates/pkm-study/tests/it/adding_a_mechanism.rs` declares one.
///
/// A registry of two of the papers' tables (a table of your own implements [`StudyMechanism`]
/// as the gantry does):
///
/// ```
/// use pkm_study::StudyMechanism;
/// use pkm_study::schema::mechanism::{TsaiSpec, RotaryDeltaSpec};
///
/// pkm_study::mechanisms! {
///     /// The mechanisms of my study files.
///     pub enum MyMechanisms {
///         /// The Tsai platform.
///         Tsai(TsaiSpec),
///         /// A rotary Delta.
///         RotaryDelta(RotaryDeltaSpec),
///     }
/// }
///
/// let table: MyMechanisms = pkm_study::from_toml_str("[tsai]\na = 0.44\nb = 0.56\n")?;
/// assert_eq!(table.kind(), "tsai");
/// assert_eq!(table.get("a"), Some(0.44));
/// # Ok::<(), pkm_study::StudyError>(())
/// ```
#[macro_export]
macro_rules! mechanisms {
    ($(#[$meta:meta])* $vis:vis enum $name:ident {
        $($(#[$doc:meta])* $variant:ident($spec:ty),)*
    }) => {
        $(#[$meta])*
        #[derive(
            Debug,
            Clone,
            PartialEq,
            ::serde::Deserialize,
            ::serde::Serialize,
        )]
        #[serde(rename_all = "snake_case", deny_unknown_fields)]
        $vis enum $name {
            $($(#[$doc])* $variant($spec),)*
        }

        impl $crate::registry::StudyMechanism for $name {
            type Built = $crate::registry::AnyBuilt;

            fn kind(&self) -> &'static str {
                match self { $(Self::$variant(m) => m.kind(),)* }
            }
            fn variables(&self) -> ::std::borrow::Cow<'static, [$crate::registry::Variable]> {
                match self { $(Self::$variant(m) => m.variables(),)* }
            }
            fn get(&self, name: &str) -> Option<f64> {
                match self { $(Self::$variant(m) => m.get(name),)* }
            }
            fn slot(&mut self, name: &str) -> Option<&mut f64> {
                match self { $(Self::$variant(m) => m.slot(name),)* }
            }
            fn actuation(&self) -> $crate::registry::Actuation {
                match self { $(Self::$variant(m) => m.actuation(),)* }
            }
            fn check(&self) -> Result<(), $crate::StudyError> {
                match self { $(Self::$variant(m) => m.check(),)* }
            }
            fn build(&self) -> Result<Self::Built, $crate::registry::BuildError> {
                match self { $(Self::$variant(m) => m.build().map($crate::registry::AnyBuilt::new),)* }
            }
            fn with_workspace<V: $crate::registry::WorkspaceVisitor>(
                &self,
                built: &Self::Built,
                constraints: &[$crate::__private::pkm_traits::WorkspaceConstraint],
                visitor: V,
            ) -> Result<V::Output, $crate::registry::BuildError> {
                match self { $(Self::$variant(m) => m.with_workspace(built.get()?, constraints, visitor),)* }
            }
            fn reach_region(
                &self,
                built: &Self::Built,
            ) -> Option<$crate::__private::pkm_workspace_indices::Region> {
                match self { $(Self::$variant(m) => m.reach_region(built.get().ok()?),)* }
            }
            fn skeleton_at(
                &self,
                built: &Self::Built,
                p: &$crate::__private::nalgebra::Vector3<f64>,
            ) -> Result<$crate::__private::pkm_mechanisms::Skeleton, String> {
                match self {
                    $(Self::$variant(m) => m.skeleton_at(built.get().map_err(|e| e.to_string())?, p),)*
                }
            }
            fn drawing_region(
                &self,
                built: &Self::Built,
            ) -> Result<$crate::__private::pkm_workspace_indices::Region, String> {
                match self {
                    $(Self::$variant(m) => m.drawing_region(built.get().map_err(|e| e.to_string())?),)*
                }
            }
            fn drawing_plane(&self) -> (usize, usize, usize) {
                match self { $(Self::$variant(m) => m.drawing_plane(),)* }
            }
            fn with_cross_section<V: $crate::registry::CrossSectionVisitor>(
                &self,
                visitor: V,
            ) -> Option<V::Output> {
                match self { $(Self::$variant(m) => m.with_cross_section(visitor),)* }
            }
            fn design_problem(
                &self,
            ) -> Option<$crate::__private::pkm_design_problems::DesignProblem> {
                match self { $(Self::$variant(m) => m.design_problem(),)* }
            }
            fn robot_file(&self) -> Option<&$crate::schema::robot_file::RobotFileSpec> {
                match self { $(Self::$variant(m) => m.robot_file(),)* }
            }
            fn with_forward_kinematics<V: $crate::registry::ForwardVisitor>(
                &self,
                built: &Self::Built,
                visitor: V,
            ) -> Result<V::Output, $crate::registry::BuildError> {
                match self { $(Self::$variant(m) => m.with_forward_kinematics(built.get()?, visitor),)* }
            }
        }
    };
}
