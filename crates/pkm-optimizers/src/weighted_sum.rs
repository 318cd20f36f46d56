//! Several least-squares problems over the same variables as one: the weighted sum
//! $F = \sum_k w_k F_k$, $F_k = \lVert r_k \rVert^2$, as the stacked residuals
//! $(\sqrt{w_1}\, r_1, \dots, \sqrt{w_K}\, r_K)$, whose sum of squares is $F$ (Wolf & Shoham
//! eq. 15's weighted tasks, for [`crate::levenberg_marquardt`]).

use crate::OptimizeError;
use pkm_traits::{Bounds, InvalidInput, Objective, ObjectiveError, Residuals};

/// The problem $F = \sum_k w_k F_k$ of the module docs. Its Jacobian is the stacked
/// $\sqrt{w_k}\,\partial r_k/\partial p$ when every part provides its own
/// ([`Residuals::residual_jacobian`]), else not provided (the solvers then difference the
/// stacked residuals). With one part of weight 1 it is that part, bit for bit.
///
/// # Example
/// ```
/// use pkm_optimizers::WeightedSum;
/// use pkm_traits::{Bounds, Objective, ObjectiveError, Residuals};
/// struct Offset(f64, [Bounds; 1]);
/// impl Objective for Offset {
///     fn dimension(&self) -> usize { 1 }
///     fn bounds(&self) -> &[Bounds] { &self.1 }
///     fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> { self.sum_of_squares(p) }
/// }
/// impl Residuals for Offset {
///     fn n_residuals(&self) -> usize { 1 }
///     fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
///         r[0] = p[0] - self.0;
///         Ok(())
///     }
/// }
/// let b = [Bounds::new(-1.0, 1.0)?];
/// let sum = WeightedSum::new(vec![(1.0, Offset(0.0, b)), (3.0, Offset(0.5, b))])?;
/// // F(p) = p² + 3 (p − ½)², at p = 0.25: 1/16 + 3/16.
/// assert!((sum.value(&[0.25])? - 0.25).abs() < 1e-15);
/// assert!(WeightedSum::new(vec![(-1.0, Offset(0.0, b))]).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct WeightedSum<P> {
    /// `(w_k, sqrt(w_k), problem_k)`.
    parts: Vec<(f64, f64, P)>,
}

impl<P: Residuals> WeightedSum<P> {
    /// The weighted sum of `parts` (weight $w_k$, problem).
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] for no part, a weight that is not finite and $\ge 0$, or a part
    /// whose variables (dimension and bounds) differ from the first's.
    pub fn new(parts: Vec<(f64, P)>) -> Result<Self, OptimizeError> {
        let Some((_, first)) = parts.first() else {
            return Err(InvalidInput::new("parts", 0.0, "at least one part").into());
        };
        if let Some((w, _)) = parts.iter().find(|(w, _)| !(w.is_finite() && *w >= 0.0)) {
            return Err(InvalidInput::new("weight", *w, "must be finite and >= 0").into());
        }
        let (n, bounds) = (first.dimension(), first.bounds());
        if let Some((_, p)) = parts
            .iter()
            .find(|(_, p)| p.dimension() != n || p.bounds() != bounds)
        {
            let dimension = p.dimension() as f64;
            return Err(InvalidInput::new(
                "part dimension",
                dimension,
                "every part has the variables and bounds of the first",
            )
            .into());
        }
        Ok(Self {
            parts: parts.into_iter().map(|(w, p)| (w, w.sqrt(), p)).collect(),
        })
    }

    /// The parts with their weights $w_k$, in order.
    pub fn parts(&self) -> impl Iterator<Item = (f64, &P)> {
        self.parts.iter().map(|(w, _, p)| (*w, p))
    }

    /// The first part (every part has its variables).
    fn first(&self) -> &P {
        // `new` refuses an empty list, and the parts never change.
        &self.parts[0].2
    }
}

impl<P: Residuals> Objective for WeightedSum<P> {
    fn dimension(&self) -> usize {
        self.first().dimension()
    }
    fn bounds(&self) -> &[Bounds] {
        self.first().bounds()
    }
    fn value(&self, design: &[f64]) -> Result<f64, ObjectiveError> {
        self.sum_of_squares(design)
    }
}

impl<P: Residuals> Residuals for WeightedSum<P> {
    fn n_residuals(&self) -> usize {
        self.parts.iter().map(|(_, _, p)| p.n_residuals()).sum()
    }

    fn residuals(&self, design: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        check_len(self.n_residuals(), r.len())?;
        let mut offset = 0;
        for (_, s, p) in &self.parts {
            let m = p.n_residuals();
            let part = &mut r[offset..offset + m];
            p.residuals(design, part)?;
            part.iter_mut().for_each(|x| *x *= s);
            offset += m;
        }
        Ok(())
    }

    fn residual_jacobian(
        &self,
        design: &[f64],
        r: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, ObjectiveError> {
        let (total, n) = (self.n_residuals(), self.dimension());
        check_len(total, r.len())?;
        check_len(total * n, jacobian.len())?;
        let mut offset = 0;
        for (_, s, p) in &self.parts {
            let m = p.n_residuals();
            let rows = &mut r[offset..offset + m];
            let block = &mut jacobian[offset * n..(offset + m) * n];
            if !p.residual_jacobian(design, rows, block)? {
                return Ok(false);
            }
            rows.iter_mut().for_each(|x| *x *= s);
            block.iter_mut().for_each(|x| *x *= s);
            offset += m;
        }
        Ok(true)
    }
}

fn check_len(expected: usize, got: usize) -> Result<(), ObjectiveError> {
    if expected == got {
        Ok(())
    } else {
        Err(ObjectiveError::Dimension { expected, got })
    }
}
