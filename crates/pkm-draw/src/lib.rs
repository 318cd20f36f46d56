//! Drawings of parallel mechanisms: a [`Skeleton`] (from `pkm-mechanisms`) at a pose, seen in
//! orthographic front, side and top views and in a 3-D (axonometric) projection, on one SVG, with
//! optional screw or twist axes, trajectories and workspace boundaries ([`Scene`]); and the one
//! chart layer of pkm ([`chart`]: heat maps, line and scatter plots).
//!
//! [`render_svg`] is the entry point of drawings, [`chart::render_svg`] that of charts;
//! [`Scene::to_csv`] and [`chart::Chart::to_csv`] write the data behind them.
//! Every input is checked first: a non-finite or huge coordinate, a link to a missing point, an
//! empty skeleton or an unusable option is a [`DrawError`], never a panic.

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(all(doctest, feature = "render"))]
#[doc = include_str!("../README.md")]
mod readme {}

pub mod chart;
mod csv;
#[cfg(feature = "render")]
mod render;
mod view;

pub use pkm_mechanisms::{Link, LinkKind, PointKind, Skeleton, SkeletonPoint};
pub use view::View;

use nalgebra::Vector3;
use pkm_screw_theory::Twist;
use serde::Serialize;
use thiserror::Error;

/// The largest coordinate magnitude accepted: far beyond any robot in any unit, and small
/// enough that projections and extents cannot overflow.
pub const MAX_COORDINATE: f64 = 1e12;

/// The largest number of points (skeleton points plus every path point) a scene may hold.
pub const MAX_POINTS: usize = 1_000_000;

/// A line drawn through the scene: a screw or twist axis, a joint axis, a task direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Axis {
    /// Legend entry.
    pub label: String,
    /// A point of the line.
    pub point: Vector3<f64>,
    /// Its direction (any non-zero length).
    pub direction: Vector3<f64>,
    /// The drawn length, centred on `point` (a joint axis); `None` draws the line across the
    /// scene, centred on its point nearest the skeleton's centroid (a screw axis).
    pub length: Option<f64>,
}

/// `(ω, v)` divided by their largest component when $|\omega|^2$ underflows (subnormal), so
/// that a tiny but representable rotation is not mistaken for a translation; unchanged (same
/// bits) otherwise.
fn scaled_if_tiny(w: Vector3<f64>, v: Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let w2 = w.norm_squared();
    if w.amax() == 0.0 || w2.is_normal() {
        return (w, v);
    }
    let scale = w.amax().max(v.amax());
    (w / scale, v / scale)
}

impl Axis {
    /// The axis of `twist` $[\omega; v]$: for $\omega \ne 0$ the line along $\omega$ through
    /// $s_0 = \omega \times v / |\omega|^2$ (its point nearest the origin, Wolf & Shoham eq. 3);
    /// for a pure translation ($\omega = 0$) the line along $v$ through `through`. A tiny
    /// rotation stays a rotation: where $|\omega|^2$ underflows, the twist is first scaled by its
    /// largest component ($s_0$ and the direction do not depend on the scale); only an $\omega$
    /// below about $10^{-154}$ of the twist's size, whose axis would lie that far away, is drawn
    /// as the translation it approximates.
    ///
    /// # Errors
    /// [`DrawError::ZeroDirection`] for the zero twist, [`DrawError::BadCoordinate`] for a
    /// non-finite twist or point.
    pub fn of_twist(
        label: impl Into<String>,
        twist: &Twist,
        through: Vector3<f64>,
    ) -> Result<Self, DrawError> {
        let (w, v) = (twist.angular(), twist.linear());
        check_vector("twist", 0, &w)?;
        check_vector("twist", 0, &v)?;
        check_vector("axis point", 0, &through)?;
        let (w, v) = scaled_if_tiny(w, v);
        let w2 = w.norm_squared();
        let (point, direction) = if w2 > 0.0 {
            (w.cross(&v) / w2, w)
        } else if v.norm_squared() > 0.0 {
            (through, v)
        } else {
            return Err(DrawError::ZeroDirection { index: 0 });
        };
        Ok(Self {
            label: label.into(),
            point,
            direction,
            length: None,
        })
    }
}

/// What a polyline of the scene stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum PathKind {
    /// A trajectory of the platform, drawn as a line.
    Trajectory,
    /// The boundary of a workspace (a cross-section outline), drawn as a line.
    Boundary,
    /// Points of a workspace (a point set), drawn as dots.
    WorkspacePoints,
}

/// A polyline or point set drawn in every view.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Path {
    /// Legend entry.
    pub label: String,
    /// What it stands for (and so how it is drawn).
    pub kind: PathKind,
    /// The points, in order.
    pub points: Vec<Vector3<f64>>,
}

/// Everything a drawing shows: the robot and the extra elements.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Scene {
    /// The robot.
    pub skeleton: Skeleton,
    /// Lines through the scene (screw and twist axes).
    pub axes: Vec<Axis>,
    /// Trajectories and workspace boundaries.
    pub paths: Vec<Path>,
}

impl Scene {
    /// The robot alone.
    pub fn new(skeleton: Skeleton) -> Self {
        Self {
            skeleton,
            ..Self::default()
        }
    }

    /// The scene with `axis` added.
    #[must_use]
    pub fn with_axis(mut self, axis: Axis) -> Self {
        self.axes.push(axis);
        self
    }

    /// The scene with the path `points` of `kind` added.
    #[must_use]
    pub fn with_path(
        mut self,
        label: impl Into<String>,
        kind: PathKind,
        points: Vec<Vector3<f64>>,
    ) -> Self {
        self.paths.push(Path {
            label: label.into(),
            kind,
            points,
        });
        self
    }

    /// Checks what [`render_svg`] needs: at least one skeleton point, every coordinate finite
    /// and at most [`MAX_COORDINATE`] in magnitude, links between existing points, axes with a
    /// non-zero direction, at most [`MAX_POINTS`] points in all.
    ///
    /// # Errors
    /// The first problem found, as a [`DrawError`].
    pub fn validate(&self) -> Result<(), DrawError> {
        let points = &self.skeleton.points;
        if points.is_empty() {
            return Err(DrawError::Empty);
        }
        let total = self
            .paths
            .iter()
            .fold(points.len(), |n, p| n.saturating_add(p.points.len()));
        if total > MAX_POINTS {
            return Err(DrawError::TooManyPoints { points: total });
        }
        for (i, p) in points.iter().enumerate() {
            check_vector("skeleton point", i, &p.position)?;
        }
        for (k, link) in self.skeleton.links.iter().enumerate() {
            for point in [link.from, link.to] {
                if point >= points.len() {
                    return Err(DrawError::NoSuchPoint {
                        link: k,
                        point,
                        points: points.len(),
                    });
                }
            }
        }
        for (i, axis) in self.axes.iter().enumerate() {
            check_vector("axis point", i, &axis.point)?;
            check_vector("axis direction", i, &axis.direction)?;
            if axis.direction.amax() == 0.0 {
                return Err(DrawError::ZeroDirection { index: i });
            }
            if let Some(length) = axis.length
                && !(length > 0.0 && length <= MAX_COORDINATE)
            {
                return Err(DrawError::InvalidOption {
                    name: "axis length",
                    value: length,
                    requirement: "must be positive and at most 1e12",
                });
            }
        }
        for (i, path) in self.paths.iter().enumerate() {
            for p in &path.points {
                check_vector("path point", i, p)?;
            }
        }
        Ok(())
    }

    /// The data behind the drawing as CSV, one row per point, header
    /// `element,index,label,kind,x,y,z`: the skeleton's points (`point`), each link as its two
    /// ends (`link`, the link's index), each axis as its point and that point plus its unit
    /// direction (`axis`), and the paths' points (`path`, the path's index).
    pub fn to_csv(&self) -> String {
        csv::scene(self)
    }
}

/// How [`render_svg`] draws.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawOptions {
    /// Caption at the top of the picture; none when empty.
    pub title: String,
    /// The views, laid out left to right and top to bottom (one, two in a row, or a 2 × 2 grid
    /// for three or four).
    pub views: Vec<View>,
    /// Width and height in pixels, each in `[200, 8000]`.
    pub size: (u32, u32),
    /// Length unit of the coordinates, written on the axes (`"m"`, `"cm"`).
    pub unit: String,
    /// Whether the points' labels are written in the 3-D view.
    pub labels: bool,
}

impl Default for DrawOptions {
    /// Front, side, top and 3-D views on 1000 × 1000 pixels, unit `m`, labels on.
    fn default() -> Self {
        Self {
            title: String::new(),
            views: View::ALL.to_vec(),
            size: (1000, 1000),
            unit: "m".to_owned(),
            labels: true,
        }
    }
}

impl DrawOptions {
    /// The default options with caption `title`.
    pub fn titled(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            ..Self::default()
        }
    }

    /// Checks what [`render_svg`] needs: each side of the image in [200, 8000] pixels, one to
    /// four views.
    ///
    /// # Errors
    /// [`DrawError::InvalidOption`] naming the option.
    pub fn validate(&self) -> Result<(), DrawError> {
        for (name, side) in [("width", self.size.0), ("height", self.size.1)] {
            if !(200..=8000).contains(&side) {
                return Err(DrawError::InvalidOption {
                    name,
                    value: f64::from(side),
                    requirement: "must lie in [200, 8000] pixels",
                });
            }
        }
        if self.views.is_empty() || self.views.len() > 4 {
            return Err(DrawError::InvalidOption {
                name: "views",
                value: self.views.len() as f64,
                requirement: "must name one to four views",
            });
        }
        Ok(())
    }
}

/// Why a drawing could not be made.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DrawError {
    /// The skeleton has no point.
    #[error("nothing to draw: the skeleton has no points")]
    Empty,
    /// A coordinate is NaN, infinite, or larger than [`MAX_COORDINATE`] in magnitude.
    #[error(
        "{what} {index} has the coordinate {value}: it must be finite and at most 1e12 in magnitude"
    )]
    BadCoordinate {
        /// Which element (`"skeleton point"`, `"axis direction"`, `"path point"`).
        what: &'static str,
        /// Its index (of the point, axis or path).
        index: usize,
        /// The offending coordinate.
        value: f64,
    },
    /// A link names a point the skeleton does not have.
    #[error("link {link} joins point {point}, but the skeleton has {points} points")]
    NoSuchPoint {
        /// Index of the link.
        link: usize,
        /// The missing point's index.
        point: usize,
        /// How many points there are.
        points: usize,
    },
    /// An axis (or the twist it comes from) has no direction.
    #[error("axis {index} has a zero direction")]
    ZeroDirection {
        /// Index of the axis.
        index: usize,
    },
    /// More than [`MAX_POINTS`] points.
    #[error("{points} points to draw, more than {MAX_POINTS}")]
    TooManyPoints {
        /// How many were given.
        points: usize,
    },
    /// An option that cannot be drawn with.
    #[error("option {name} = {value} {requirement}")]
    InvalidOption {
        /// Which option.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// The SVG backend failed (it writes to memory, so this is not expected).
    #[error("the SVG backend failed: {0}")]
    Backend(String),
}

fn check_vector(what: &'static str, index: usize, v: &Vector3<f64>) -> Result<(), DrawError> {
    match v.iter().copied().find(|c| !(c.abs() <= MAX_COORDINATE)) {
        Some(value) => Err(DrawError::BadCoordinate { what, index, value }),
        None => Ok(()),
    }
}

/// Renders `scene` as an SVG document: for every view of `options`, the links as lines coloured
/// by [`LinkKind`], the points as markers by [`PointKind`], the axes (one colour and one legend
/// entry per distinct label), trajectories and boundaries, at one scale in both directions of a
/// view (feature `render`).
///
/// # Errors
/// [`Scene::validate`]'s and the options' [`DrawError`]s; [`DrawError::Backend`] if plotters
/// fails.
#[cfg(feature = "render")]
pub fn render_svg(scene: &Scene, options: &DrawOptions) -> Result<String, DrawError> {
    scene.validate()?;
    options.validate()?;
    render::svg(scene, options)
}

/// [`render_svg`] of the robot alone (feature `render`).
///
/// # Errors
/// As [`render_svg`].
#[cfg(feature = "render")]
pub fn render_skeleton_svg(
    skeleton: &Skeleton,
    options: &DrawOptions,
) -> Result<String, DrawError> {
    render_svg(&Scene::new(skeleton.clone()), options)
}
