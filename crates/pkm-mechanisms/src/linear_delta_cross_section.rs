//! The Linear Delta's $y$–$z$ workspace cross-section $W$ as an exact convex region
//! (Miller 2004, §2.2.2): the intersection of the three arm discs, the half-plane $z \le 0$ and,
//! when $Z_R < 0$, the wedge below the centre rail bounded by the lines $A_1A_3$ and $A_2A_3$
//! (the centre rail blocks the outer arms; `docs/conventions.md#linear-delta-geometry`).
//!
//! Every slice $\{z : (y, z) \in W\}$ is an interval whose bounds are disc arcs or lines; between
//! the abscissae of all pairwise intersections and of the disc extremes the bounding curves do not
//! change, so the area is a sum of closed-form integrals of arcs and lines.

use crate::linear_delta::{Line, LinearDelta, LinearDeltaMode, half_planes};
use pkm_traits::{CrossSectionWorkspace, Extents, JacobianLanes, SlicedRegion};

/// A disc $|p - c| \le r$.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Disc {
    cy: f64,
    cz: f64,
    r: f64,
}

/// Relative tolerance of the corner and extent tests (round-off of the intersections).
const TOLERANCE: f64 = 1e-9;

/// The workspace cross-section of a [`LinearDelta`]; empty when the constraints do not meet.
#[derive(Debug, Clone, PartialEq)]
pub struct CrossSection {
    discs: [Disc; 3],
    lines: Vec<Line>,
    breakpoints: Vec<f64>,
    corners: Vec<[f64; 2]>,
    extents: Option<Extents>,
    area: f64,
}

impl LinearDelta {
    /// The $y$–$z$ workspace cross-section (three discs, $z \le 0$, and the centre-rail wedge
    /// when $Z_R < 0$).
    pub fn cross_section(&self) -> CrossSection {
        CrossSection::new(self)
    }
}

impl CrossSection {
    pub(crate) fn new(delta: &LinearDelta) -> Self {
        let rails = delta.rails();
        let lengths = delta.arm_lengths();
        let discs = [0, 1, 2].map(|i| Disc {
            cy: rails[i][0],
            cz: rails[i][1],
            r: lengths[i],
        });
        let lines = half_planes(&rails).into_iter().flatten().collect();
        let mut region = Self {
            discs,
            lines,
            breakpoints: Vec::new(),
            corners: Vec::new(),
            extents: None,
            area: 0.0,
        };
        region.measure();
        region
    }

    /// Whether the cross-section is empty (zero area).
    pub fn is_empty(&self) -> bool {
        self.extents.is_none()
    }

    /// The corners of $W$: pairwise intersections of its bounding curves that lie in $W$.
    pub fn corners(&self) -> &[[f64; 2]] {
        &self.corners
    }

    /// The extents of $W$, `None` when it is empty.
    pub fn workspace_extents(&self) -> Option<Extents> {
        self.extents
    }

    fn scale(&self) -> f64 {
        self.discs.iter().map(|d| d.r).fold(1.0, f64::max)
    }

    /// The slice bounds with disc radicands allowed `tol` below zero.
    fn slice_with(&self, y: f64, tol: f64) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for d in &self.discs {
            let radicand = d.r * d.r - (y - d.cy).powi(2);
            if !(radicand >= -tol * d.r * d.r) {
                return None;
            }
            let s = radicand.max(0.0).sqrt();
            lo = lo.max(d.cz - s);
            hi = hi.min(d.cz + s);
        }
        for l in &self.lines {
            hi = hi.min(l.a * y + l.b);
        }
        (hi >= lo - tol * self.scale()).then_some((lo, hi.max(lo)))
    }

    /// Pairwise intersections of the bounding circles and lines.
    fn intersections(&self) -> Vec<[f64; 2]> {
        let mut points = Vec::new();
        for (i, d) in self.discs.iter().enumerate() {
            for e in &self.discs[i + 1..] {
                points.extend(circle_circle(d, e));
            }
            for l in &self.lines {
                points.extend(circle_line(d, l));
            }
        }
        for (i, l) in self.lines.iter().enumerate() {
            for m in &self.lines[i + 1..] {
                if (l.a - m.a).abs() > 0.0 {
                    let y = (m.b - l.b) / (l.a - m.a);
                    points.push([y, l.a * y + l.b]);
                }
            }
        }
        points
    }

    fn measure(&mut self) {
        let intersections = self.intersections();
        let mut candidates = intersections.clone();
        for d in &self.discs {
            candidates.extend([[d.cy - d.r, d.cz], [d.cy + d.r, d.cz]]);
        }
        let tol = TOLERANCE * self.scale();
        let inside = |p: &[f64; 2]| {
            self.slice_with(p[0], TOLERANCE)
                .is_some_and(|(lo, hi)| p[1] >= lo - tol && p[1] <= hi + tol)
        };
        let mut ys: Vec<f64> = candidates
            .iter()
            .map(|p| p[0])
            .filter(|y| self.slice_with(*y, TOLERANCE).is_some())
            .collect();
        ys.sort_by(f64::total_cmp);
        let (Some(&y_min), Some(&y_max)) = (ys.first(), ys.last()) else {
            return;
        };
        if !(y_max - y_min > tol) {
            return;
        }
        let mut breakpoints = vec![y_min];
        for &y in &ys[1..] {
            if y - breakpoints[breakpoints.len() - 1] > tol {
                breakpoints.push(y);
            }
        }
        if let Some(last) = breakpoints.last_mut() {
            *last = y_max;
        }
        let mut corners: Vec<[f64; 2]> = Vec::new();
        for p in intersections.iter().filter(|p| inside(p)) {
            let close = |c: &[f64; 2]| (c[0] - p[0]).hypot(c[1] - p[1]) <= tol;
            if !corners.iter().any(close) {
                corners.push(*p);
            }
        }
        self.corners = corners;
        let mut extents = Extents {
            y_min,
            y_max,
            z_min: f64::INFINITY,
            z_max: f64::NEG_INFINITY,
        };
        for &y in breakpoints.iter().chain(self.discs.iter().map(|d| &d.cy)) {
            if let Some((lo, hi)) = self.slice_with(y, TOLERANCE) {
                extents = extents.including(y, lo).including(y, hi);
            }
        }
        self.area = breakpoints
            .windows(2)
            .map(|w| self.piece_area(w[0], w[1]))
            .sum();
        self.breakpoints = breakpoints;
        self.extents = (self.area > 0.0).then_some(extents);
    }

    /// $\int_a^b (\text{hi} - \text{lo})\,dy$ in closed form, with the bounding curves found at
    /// the midpoint.
    fn piece_area(&self, a: f64, b: f64) -> f64 {
        let m = 0.5 * (a + b);
        let Some((lo, hi)) = self.slice_with(m, 0.0) else {
            return 0.0;
        };
        if !(hi > lo) {
            return 0.0;
        }
        let mut upper = f64::INFINITY;
        let mut upper_integral = 0.0;
        for d in &self.discs {
            let top = d.cz + (d.r * d.r - (m - d.cy).powi(2)).max(0.0).sqrt();
            if top < upper {
                upper = top;
                upper_integral = d.cz * (b - a) + arc_integral(d, a, b);
            }
        }
        for l in &self.lines {
            let top = l.a * m + l.b;
            if top < upper {
                upper = top;
                upper_integral = 0.5 * l.a * (b * b - a * a) + l.b * (b - a);
            }
        }
        let mut lower = f64::NEG_INFINITY;
        let mut lower_integral = 0.0;
        for d in &self.discs {
            let bottom = d.cz - (d.r * d.r - (m - d.cy).powi(2)).max(0.0).sqrt();
            if bottom > lower {
                lower = bottom;
                lower_integral = d.cz * (b - a) - arc_integral(d, a, b);
            }
        }
        upper_integral - lower_integral
    }
}

/// $\int_a^b \sqrt{r^2 - (y - c_y)^2}\,dy$.
fn arc_integral(d: &Disc, a: f64, b: f64) -> f64 {
    let f = |y: f64| {
        let t = (y - d.cy).clamp(-d.r, d.r);
        0.5 * (t * (d.r * d.r - t * t).max(0.0).sqrt() + d.r * d.r * (t / d.r).asin())
    };
    f(b) - f(a)
}

fn circle_circle(d: &Disc, e: &Disc) -> Vec<[f64; 2]> {
    let (dy, dz) = (e.cy - d.cy, e.cz - d.cz);
    let dist = dy.hypot(dz);
    if !(dist > 0.0) || dist > d.r + e.r || dist < (d.r - e.r).abs() {
        return Vec::new();
    }
    let along = (d.r * d.r - e.r * e.r + dist * dist) / (2.0 * dist);
    let across = (d.r * d.r - along * along).max(0.0).sqrt();
    let (uy, uz) = (dy / dist, dz / dist);
    let (my, mz) = (d.cy + along * uy, d.cz + along * uz);
    vec![
        [my - across * uz, mz + across * uy],
        [my + across * uz, mz - across * uy],
    ]
}

fn circle_line(d: &Disc, l: &Line) -> Vec<[f64; 2]> {
    // (1 + a²) y² + 2 (a (b − cz) − cy) y + cy² + (b − cz)² − r² = 0
    let k = l.b - d.cz;
    let qa = 1.0 + l.a * l.a;
    let qb = 2.0 * (l.a * k - d.cy);
    let qc = d.cy * d.cy + k * k - d.r * d.r;
    let disc = qb * qb - 4.0 * qa * qc;
    if !(disc >= 0.0) {
        return Vec::new();
    }
    let s = disc.sqrt();
    [(-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa)]
        .into_iter()
        .map(|y| [y, l.a * y + l.b])
        .collect()
}

impl SlicedRegion for CrossSection {
    fn slice(&self, y: f64) -> Option<(f64, f64)> {
        self.extents?;
        self.slice_with(y, 0.0).filter(|(lo, hi)| hi >= lo)
    }

    fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    fn extents(&self) -> Extents {
        self.extents.unwrap_or(Extents {
            y_min: 0.0,
            y_max: 0.0,
            z_min: 0.0,
            z_max: 0.0,
        })
    }

    fn area(&self) -> f64 {
        self.area
    }
}

/// The cross-section indices' view of the Linear Delta: $W$, the rails and the batch Jacobian
/// ([`LinearDelta::velocity_jacobian_lanes`], the scalar closed form bit for bit).
impl CrossSectionWorkspace for LinearDelta {
    type CrossSection = CrossSection;

    fn cross_section(&self) -> CrossSection {
        LinearDelta::cross_section(self)
    }

    fn actuator_points(&self) -> Vec<[f64; 2]> {
        self.rails().to_vec()
    }

    #[inline(always)]
    fn cross_section_jacobian_lanes<const N: usize>(
        &self,
        y: f64,
        z: &[f64; N],
        mode: LinearDeltaMode,
    ) -> JacobianLanes<N> {
        self.velocity_jacobian_lanes(y, z, mode)
    }
}
