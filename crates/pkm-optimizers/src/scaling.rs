//! The variable scaling of the local solvers ([`crate::levenberg_marquardt`],
//! [`crate::augmented_lagrangian`] and its spectral projected gradient).
//!
//! Each solver works in the scaled variables
//! $$ z_j = x_j / s_j, \qquad j = 1, \dots, n, $$
//! where the characteristic scale $s_j > 0$ is, by default, the width of variable $j$'s box side,
//! $s_j = u_j - l_j$, or a user-given [`CharacteristicScale`] (the settings' `scale`).
//! A variable whose box side has zero width (a fixed variable) gets $s_j = 1$: it never moves,
//! so its scale only has to be finite and positive.
//! ([`pkm_traits::Bounds`] are always finite, so there is no unbounded variable to fall back for.)
//!
//! In scaled variables the gradient is $\nabla_z f = S \nabla_x f$ and a Jacobian
//! $A_z = A S$, with $S = \mathrm{diag}(s)$, so a variable in degrees spanning 345 and one in
//! metres spanning 0.3 weigh by how much the objective changes across their boxes, not per unit.
//! The stopping tests (the projected gradient $\lVert S\, \nabla_x f \rVert_\infty$ over the
//! free variables and the projected step $\lVert S^{-1} d \rVert_\infty$) are therefore stated in
//! scaled units, and every result is reported in the user's variables $x = S z$.
//! The solvers never form $z$: they apply $S$ to gradients and Jacobian columns and $S$ to the
//! steps, so a scale of ones reproduces the unscaled iteration bit for bit (the "no scaling"
//! baseline of the tests).

use crate::OptimizeError;
use pkm_traits::{Bounds, InvalidInput};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;
use std::sync::Arc;

/// A user-given characteristic scale $s_j$ per variable (finite and $> 0$, any number of
/// variables; cloned by reference count), in the user's units: e.g. `[1e-3, 1e3]` for a parameter
/// expected near $10^{-3}$ and one near $10^3$. In a study file it is a list,
/// `scale = [1e-3, 1e3]`.
#[derive(Clone, PartialEq)]
pub struct CharacteristicScale(Arc<[f64]>);

impl CharacteristicScale {
    /// The scale `values`.
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] for no value or a value that is not finite and $> 0$ (named
    /// `scale`).
    ///
    /// # Example
    /// ```
    /// use pkm_optimizers::CharacteristicScale;
    /// assert_eq!(CharacteristicScale::new(&[1e-3, 1e3]).unwrap().values(), &[1e-3, 1e3]);
    /// assert!(CharacteristicScale::new(&[1.0, 0.0]).is_err());
    /// assert!(CharacteristicScale::new(&[]).is_err());
    /// ```
    pub fn new(values: &[f64]) -> Result<Self, OptimizeError> {
        if values.is_empty() {
            return Err(InvalidInput::new("scale.len()", 0.0, "must be at least 1").into());
        }
        let checked = values
            .iter()
            .map(|&v| InvalidInput::require_positive("scale", v))
            .collect::<Result<Vec<f64>, _>>()?;
        Ok(Self(checked.into()))
    }

    /// The scales, one per variable.
    pub fn values(&self) -> &[f64] {
        &self.0
    }
}

impl fmt::Debug for CharacteristicScale {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.values()).finish()
    }
}

impl Serialize for CharacteristicScale {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.values().serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for CharacteristicScale {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let values = Vec::<f64>::deserialize(deserializer)?;
        Self::new(&values).map_err(serde::de::Error::custom)
    }
}

/// The scales $s_j$ the solvers use on `bounds`: the user's `given` scale, else each box side's
/// width (1 for a side of zero width).
///
/// # Errors
/// [`OptimizeError::Invalid`] when `given` does not have one value per variable.
///
/// # Example
/// ```
/// use pkm_optimizers::{CharacteristicScale, variable_scales};
/// use pkm_traits::Bounds;
/// let b = [Bounds::new(0.0, 0.3).unwrap(), Bounds::new(5.0, 350.0).unwrap(), Bounds::new(2.0, 2.0).unwrap()];
/// assert_eq!(variable_scales(&b, None).unwrap(), vec![0.3, 345.0, 1.0]);
/// let given = CharacteristicScale::new(&[1.0, 2.0]).unwrap();
/// assert!(variable_scales(&b, Some(&given)).is_err());
/// ```
pub fn variable_scales(
    bounds: &[Bounds],
    given: Option<&CharacteristicScale>,
) -> Result<Vec<f64>, OptimizeError> {
    match given {
        Some(scale) if scale.values().len() != bounds.len() => Err(InvalidInput::new(
            "scale.len()",
            scale.values().len() as f64,
            "must equal the problem dimension",
        )
        .into()),
        Some(scale) => Ok(scale.values().to_vec()),
        None => Ok(bounds
            .iter()
            .map(|b| if b.width() > 0.0 { b.width() } else { 1.0 })
            .collect()),
    }
}
