//! Planar regions described by their vertical slices: the workspace cross-sections of
//! translation-invariant mechanisms (Miller 2004, §2.2: the Linear Delta's $y$–$z$ section).

/// Axis-aligned extents $[y_{\min}, y_{\max}] \times [z_{\min}, z_{\max}]$ of a planar set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extents {
    /// Smallest $y$.
    pub y_min: f64,
    /// Largest $y$.
    pub y_max: f64,
    /// Smallest $z$.
    pub z_min: f64,
    /// Largest $z$.
    pub z_max: f64,
}

impl Extents {
    /// The smallest extents that contain `self` and the point `(y, z)`.
    pub fn including(self, y: f64, z: f64) -> Self {
        Self {
            y_min: self.y_min.min(y),
            y_max: self.y_max.max(y),
            z_min: self.z_min.min(z),
            z_max: self.z_max.max(z),
        }
    }

    /// Area $(y_{\max} - y_{\min})(z_{\max} - z_{\min})$.
    pub fn area(&self) -> f64 {
        (self.y_max - self.y_min) * (self.z_max - self.z_min)
    }
}

/// A closed, bounded, non-empty region of the $(y, z)$ plane whose vertical slices are intervals
/// (a convex region, for instance), with the abscissae where the curves bounding the slices
/// change.
///
/// Between two consecutive [`SlicedRegion::breakpoints`] the lower and upper bounds of the slice
/// are smooth functions of $y$, so a quadrature on each such interval converges fast.
pub trait SlicedRegion: Sync {
    /// The slice $\{z : (y, z) \in W\} = [\text{lo}(y), \text{hi}(y)]$, or `None` when it is
    /// empty.
    fn slice(&self, y: f64) -> Option<(f64, f64)>;

    /// Sorted abscissae, from $y_{\min}$ to $y_{\max}$ inclusive, between which the slice bounds
    /// are smooth.
    fn breakpoints(&self) -> &[f64];

    /// Axis-aligned extents of the region.
    fn extents(&self) -> Extents;

    /// Exact area of the region.
    fn area(&self) -> f64;

    /// Whether `(y, z)` lies in the region (closed test, no tolerance).
    fn contains(&self, y: f64, z: f64) -> bool {
        self.slice(y).is_some_and(|(lo, hi)| lo <= z && z <= hi)
    }
}
