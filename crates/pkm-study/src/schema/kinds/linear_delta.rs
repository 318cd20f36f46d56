//! `[mechanism.linear_delta]`: the Linear Delta of Miller 2004 §2.2 (three parallel rails along
//! x, the ratios of Table 1 and the scale YR): its table, the library robot it builds, and what
//! a study asks of it.

use super::design_error;
use crate::design_variables;
use crate::registry::{
    Actuation, BuildError, CrossSectionVisitor, ForwardVisitor, StudyMechanism, WorkspaceVisitor,
    visit,
};
use crate::scene::first_drawable;
use crate::schema::units::{PositiveMetres, Real};
use nalgebra::Vector3;
use pkm_mechanisms::{
    LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios, Skeleton,
};
use pkm_traits::WorkspaceConstraint;
use pkm_workspace_indices::Region;
use serde::{Deserialize, Serialize};

/// `[mechanism.linear_delta]`: the ratios of Miller 2004, Table 1, and the scale YR.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LinearDeltaSpec {
    /// L1/YR, outer arm length over actuator separation (≥ 1).
    pub l1_over_yr: Real,
    /// YA/YR, horizontal eccentricity of the centre rail (|YA/YR| < 1).
    pub ya_over_yr: Real,
    /// ZR/YR, vertical eccentricity of the centre rail.
    pub zr_over_yr: Real,
    /// L2/L1, centre arm over outer arm length (> 0).
    pub l2_over_l1: Real,
    /// The actuator separation YR (m), the length unit of the ratios.
    #[serde(default = "one_m")]
    pub yr: PositiveMetres,
    /// Which way each arm leans along the rails (default: the paper's `[true, true, false]`).
    #[serde(default = "paper_leans")]
    pub leans_positive: [bool; 3],
}

fn one_m() -> PositiveMetres {
    PositiveMetres(1.0)
}
fn paper_leans() -> [bool; 3] {
    LinearDeltaMode::PAPER.leans_positive
}

impl StudyMechanism for LinearDeltaSpec {
    design_variables! {
        "l1_over_yr" Ratio => |s| s.l1_over_yr.0,
        "ya_over_yr" Ratio => |s| s.ya_over_yr.0,
        "zr_over_yr" Ratio => |s| s.zr_over_yr.0,
        "l2_over_l1" Ratio => |s| s.l2_over_l1.0,
        "yr" Length => |s| s.yr.0,
    }

    type Built = LinearDelta;

    fn kind(&self) -> &'static str {
        "linear_delta"
    }

    /// The Linear Delta of a `[mechanism.linear_delta]` table.
    ///
    /// # Errors
    /// [`BuildError::Design`] with the library's reason for an invalid design.
    fn build(&self) -> Result<LinearDelta, BuildError> {
        let ratios = LinearDeltaRatios {
            l1_over_yr: self.l1_over_yr.0,
            ya_over_yr: self.ya_over_yr.0,
            zr_over_yr: self.zr_over_yr.0,
            l2_over_l1: self.l2_over_l1.0,
        };
        LinearDelta::new(LinearDeltaDesign {
            ratios,
            yr: self.yr.0,
        })
        .map_err(design_error)
    }

    fn actuation(&self) -> Actuation {
        Actuation::Prismatic
    }

    fn with_forward_kinematics<V: ForwardVisitor>(
        &self,
        built: &LinearDelta,
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        Ok(visitor.visit(built))
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        built: &LinearDelta,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        let mode = LinearDeltaMode {
            leans_positive: self.leans_positive,
        };
        visit(built, &[mode], constraints, visitor)
    }

    fn skeleton_at(&self, robot: &LinearDelta, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let mode = LinearDeltaMode {
            leans_positive: self.leans_positive,
        };
        first_drawable(p, [Skeleton::linear_delta(robot, p, mode)])
    }

    /// Unbounded along its rails: the box $|x| \le L$ around the rails widened by the longest
    /// arm $L$ in $y$ and $z$.
    fn drawing_region(&self, robot: &LinearDelta) -> Result<Region, String> {
        let reach = robot.arm_lengths().into_iter().fold(0.0, f64::max);
        let rails = robot.rails();
        let (mut lower, mut upper) = (
            Vector3::new(-reach, 0.0, 0.0),
            Vector3::new(reach, 0.0, 0.0),
        );
        for axis in [1, 2] {
            let along = rails.iter().map(|r| r[axis - 1]);
            lower[axis] = along.clone().fold(f64::INFINITY, f64::min) - reach;
            upper[axis] = along.fold(f64::NEG_INFINITY, f64::max) + reach;
        }
        Ok(Region::Box { lower, upper })
    }

    /// The plane $x = x_c$ across the rails.
    fn drawing_plane(&self) -> (usize, usize, usize) {
        (1, 2, 0)
    }

    /// Its cross-section at $Y_R = 1$ (the indices are of the ratios, the design variables of
    /// Miller 2004 Table 2) in the table's working mode (`leans_positive`).
    fn with_cross_section<V: CrossSectionVisitor>(&self, visitor: V) -> Option<V::Output> {
        let ratios = [
            self.l1_over_yr.0,
            self.ya_over_yr.0,
            self.zr_over_yr.0,
            self.l2_over_l1.0,
        ];
        let leans = self.leans_positive;
        let key = [
            ratios[0],
            ratios[1],
            ratios[2],
            ratios[3],
            f64::from(u8::from(leans[0])),
            f64::from(u8::from(leans[1])),
            f64::from(u8::from(leans[2])),
        ];
        let mode = LinearDeltaMode {
            leans_positive: leans,
        };
        let build = || {
            let ratios = LinearDeltaRatios::from_slice(&ratios);
            LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 })
        };
        Some(visitor.visit(&key, mode, build))
    }
}
