//! A cache of cross-section indices for the designs of one study, keyed by the exact design.
//!
//! A search or a sweep asks for the same design more than once (a refinement window overlaps
//! the grid it refines, a study weighs the same indices several ways), and $\eta_1$ costs
//! thousands of condition numbers. The cache returns what [`SectionIndices`] computed at
//! exactly the design asked for (the bit patterns of its `f64`s, so two designs 1e-9 apart,
//! or `0.0` and `-0.0`, are two entries) or nothing: never the value of a neighbouring design.
//! It is a value the caller owns for one study, not global state.

use crate::{Eta1Rule, GaussLegendre, IndexError, SectionIndex, SectionIndices};
use pkm_traits::{CrossSectionWorkspace, DesignError};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

/// A design's `f64`s by their bit patterns.
type DesignKey = Box<[u64]>;

fn key(design: &[f64]) -> DesignKey {
    design.iter().map(|v| v.to_bits()).collect()
}

/// The section indices computed so far in one study, each once per exact design (thread-safe:
/// a parallel sweep shares one).
///
/// # Example
/// ```
/// use pkm_mechanisms::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
/// use pkm_workspace_indices::{Eta1Rule, SectionIndex, SectionIndexCache};
/// let cache = SectionIndexCache::new();
/// let design = [2.0, 0.0, 0.0, 0.63];
/// let builds = std::cell::Cell::new(0);
/// let build = || {
///     builds.set(builds.get() + 1);
///     let ratios = LinearDeltaRatios::from_slice(&design);
///     LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 })
/// };
/// let wanted = [SectionIndex::Eta1(Eta1Rule::Quadrature(8)), SectionIndex::Eta2];
/// let first = cache.values(&design, &wanted, LinearDeltaMode::PAPER, build);
/// let again = cache.values(&design, &wanted, LinearDeltaMode::PAPER, build);
/// assert_eq!((first, builds.get(), cache.len()), (again, 1, 2));
/// assert!(cache.get(&[2.0, 0.0, 0.0, 0.63 + 1e-9], SectionIndex::Eta2).is_none());
/// ```
#[derive(Debug, Default)]
pub struct SectionIndexCache {
    values: Mutex<HashMap<(DesignKey, SectionIndex), Result<f64, IndexError>>>,
    /// The Gauss–Legendre rules built so far, one per order: a rule is a pure function of its
    /// order, so reusing it changes no value, and a study builds each order once instead of
    /// once per design.
    rules: Mutex<Vec<Arc<GaussLegendre>>>,
}

impl SectionIndexCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// The value of `index` computed at exactly `design`, `None` if it was not.
    pub fn get(&self, design: &[f64], index: SectionIndex) -> Option<Result<f64, IndexError>> {
        self.lock().get(&(key(design), index)).cloned()
    }

    /// The values of `indices` at `design`, in order: the cached ones, and the others computed
    /// on one [`SectionIndices`] of the mechanism that `build` returns in `mode` (called only
    /// when one is missing) and cached. `design` is the key: every number that determines the
    /// values, so `build` must construct the mechanism of exactly `design`, and a cache that
    /// serves more than one working mode includes the mode in it (the study layer appends the
    /// Linear Delta's leans as 0/1); its error is every missing index's
    /// ([`IndexError::Design`]).
    pub fn values<M: CrossSectionWorkspace>(
        &self,
        design: &[f64],
        indices: &[SectionIndex],
        mode: M::WorkingMode,
        build: impl FnOnce() -> Result<M, DesignError>,
    ) -> Vec<Result<f64, IndexError>> {
        let design = key(design);
        let cached: Vec<_> = {
            let values = self.lock();
            indices
                .iter()
                .map(|&index| values.get(&(design.clone(), index)).cloned())
                .collect()
        };
        if cached.iter().all(Option::is_some) {
            return cached.into_iter().flatten().collect();
        }
        // Computed outside the lock: threads on other designs do not wait; two threads on the
        // same design compute the same values.
        let mechanism = build();
        let section = mechanism
            .as_ref()
            .map(|mechanism| SectionIndices::new(mechanism, mode));
        let values: Vec<_> = cached
            .into_iter()
            .zip(indices)
            .map(|(cached, &index)| {
                cached.unwrap_or_else(|| match (&section, index) {
                    (Err(e), _) => Err(IndexError::Design((*e).clone())),
                    (Ok(section), SectionIndex::Eta1(Eta1Rule::Quadrature(n))) => {
                        section.eta1_by_quadrature(&*self.rule(n)?)
                    }
                    (Ok(section), index) => section.value(index),
                })
            })
            .collect();
        let mut cache = self.lock();
        for (&index, value) in indices.iter().zip(&values) {
            cache.insert((design.clone(), index), value.clone());
        }
        values
    }

    /// The number of cached values.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The table; a thread that panicked while holding it cannot have left it half-written
    /// (every critical section is a lookup or an insert), so a poisoned lock is used as is.
    fn lock(&self) -> MutexGuard<'_, HashMap<(DesignKey, SectionIndex), Result<f64, IndexError>>> {
        self.values.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The `n`-point Gauss–Legendre rule, built on first use.
    fn rule(&self, n: usize) -> Result<Arc<GaussLegendre>, IndexError> {
        let mut rules = self.rules.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(rule) = rules.iter().find(|rule| rule.len() == n) {
            return Ok(Arc::clone(rule));
        }
        let rule = Arc::new(GaussLegendre::new(n)?);
        rules.push(Arc::clone(&rule));
        Ok(rule)
    }
}
