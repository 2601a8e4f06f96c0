//! The data of a report's interactive 3-D view: obstacles, and a sequence of steps (the rests
//! of a motion), each with named polylines (centrelines) and the grippers.
//!
//! Positions are in metres in one world frame, `z` up; rotations are 3×3 matrices by rows,
//! mapping the body's frame to the world. Polyline points are kept to [`RESOLUTION`] (the page
//! stays small with a hundred rests of a wire). The viewer colours polylines by name, the same
//! name in the same colour at every step.

use serde::Serialize;

/// Polyline points are rounded to this \[m\] (10 µm), far below what a view can show.
pub const RESOLUTION: f64 = 1e-5;

/// `points` rounded to [`RESOLUTION`] (non-finite ones unchanged).
fn rounded(mut points: Vec<[f64; 3]>) -> Vec<[f64; 3]> {
    for p in &mut points {
        for x in p.iter_mut() {
            if x.is_finite() {
                // Divided by the exact integer 1/RESOLUTION, the result is the double nearest
                // to the decimal, which JSON then writes in its few digits; `+ 0.0` turns
                // `-0.0` into `0.0`.
                *x = (*x / RESOLUTION).round() / RESOLUTION.recip().round() + 0.0;
            }
        }
    }
    points
}

impl Polyline3 {
    /// A polyline `name` through `points` \[m\], rounded to [`RESOLUTION`].
    #[must_use]
    pub fn new(name: impl Into<String>, points: Vec<[f64; 3]>) -> Self {
        Self {
            name: name.into(),
            points: rounded(points),
        }
    }
}

/// A 3×3 rotation matrix by rows (body frame to world).
pub type Rotation = [[f64; 3]; 3];

/// The identity rotation.
pub const IDENTITY: Rotation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// A box obstacle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Box3 {
    /// Its name, shown in the legend.
    pub name: String,
    /// Centre \[m\], world frame.
    pub centre: [f64; 3],
    /// Half extents along the box's own axes \[m\].
    pub half_extents: [f64; 3],
    /// The box's axes in the world ([`IDENTITY`]: axis-aligned).
    pub rotation: Rotation,
}

/// A named polyline, such as a centreline.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Polyline3 {
    /// Its name, shown in the legend; the colour follows the name.
    pub name: String,
    /// Its points \[m\], world frame, rounded to [`RESOLUTION`] by [`Polyline3::new`];
    /// non-finite points are skipped by the viewer.
    pub points: Vec<[f64; 3]>,
}

/// A gripper, drawn as a small sphere, with its axes when the orientation is known.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Gripper3 {
    /// Its name (`"base"`, `"tip"`).
    pub name: String,
    /// Position \[m\], world frame.
    pub position: [f64; 3],
    /// Its frame's axes in the world, if known.
    pub rotation: Option<Rotation>,
}

/// One step of the view's slider: what is drawn at that rest.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Step3 {
    /// Shown beside the slider (`"after move 3"`).
    pub label: String,
    /// The polylines of this step.
    pub polylines: Vec<Polyline3>,
    /// The grippers at this step.
    pub grippers: Vec<Gripper3>,
}

impl Step3 {
    /// An empty step labelled `label`.
    #[must_use]
    pub fn new(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            polylines: Vec::new(),
            grippers: Vec::new(),
        }
    }

    /// Adds a polyline `name` through `points` \[m\].
    #[must_use]
    pub fn with_polyline(mut self, name: impl Into<String>, points: Vec<[f64; 3]>) -> Self {
        self.polylines.push(Polyline3::new(name, points));
        self
    }

    /// Adds a gripper at `position` \[m\], with its axes when `rotation` is given.
    #[must_use]
    pub fn with_gripper(
        mut self,
        name: impl Into<String>,
        position: [f64; 3],
        rotation: Option<Rotation>,
    ) -> Self {
        self.grippers.push(Gripper3 {
            name: name.into(),
            position,
            rotation,
        });
        self
    }
}

/// An interactive 3-D view: boxes and polylines that stay, and the steps a slider walks
/// through.
///
/// ```
/// use ftwire_report::{Scene3d, Step3, IDENTITY};
/// let view = Scene3d::new("a wire")
///     .with_box("table", [0.0, 0.0, -0.05], [0.5, 0.5, 0.05], IDENTITY)
///     .with_step(Step3::new("start").with_polyline("truth", vec![[0.0; 3], [0.1, 0.0, 0.0]]));
/// assert_eq!(view.steps.len(), 1);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scene3d {
    /// The view's heading.
    pub title: String,
    /// Obstacles, drawn at every step.
    pub boxes: Vec<Box3>,
    /// Polylines drawn at every step (a plan's start and goal).
    pub polylines: Vec<Polyline3>,
    /// The slider's steps, in order.
    pub steps: Vec<Step3>,
}

impl Scene3d {
    /// An empty view titled `title`.
    #[must_use]
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            boxes: Vec::new(),
            polylines: Vec::new(),
            steps: Vec::new(),
        }
    }

    /// Adds a box `name` at `centre` with `half_extents` \[m\] along its axes `rotation`.
    #[must_use]
    pub fn with_box(
        mut self,
        name: impl Into<String>,
        centre: [f64; 3],
        half_extents: [f64; 3],
        rotation: Rotation,
    ) -> Self {
        self.boxes.push(Box3 {
            name: name.into(),
            centre,
            half_extents,
            rotation,
        });
        self
    }

    /// Adds a polyline `name` through `points` \[m\], drawn at every step.
    #[must_use]
    pub fn with_polyline(mut self, name: impl Into<String>, points: Vec<[f64; 3]>) -> Self {
        self.polylines.push(Polyline3::new(name, points));
        self
    }

    /// Adds a step at the end of the slider.
    #[must_use]
    pub fn with_step(mut self, step: Step3) -> Self {
        self.steps.push(step);
        self
    }
}
