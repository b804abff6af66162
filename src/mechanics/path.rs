//! Muscle paths (`GeometryPath`): the active points, the path length and OpenSim's moment arm
//! (`Muscle::computeMomentArm`, the generalized force a unit tension produces). Wrap objects are
//! not applied yet: such paths are straight lines through their points and say so.

use super::coupling;
use super::error::MechanicsError;
use super::function::Function;
use super::kinematics::Kinematics;
use super::multibody::Multibody;
use super::spatial::{Transform, Vec3};
use crate::model::{ForceSpec, ModelSpec, MovingComponent, PathPointKind};

/// Simbody's `SignificantReal` (ε^⅞): segments shorter than this have no direction.
const SIGNIFICANT_LENGTH: f64 = 1.8189894035458565e-14;

/// `ConditionalPathPoint` range tolerance OpenSim applies (rad or m).
const CONDITIONAL_TOLERANCE: f64 = 1e-5;

/// One coordinate of a `MovingPathPoint`: location = f(q clamped to the coordinate's range).
#[derive(Debug, Clone)]
struct MovingAxis {
    coordinate: usize,
    function: Function,
    range: [f64; 2],
}

#[derive(Debug, Clone)]
enum PointKind {
    Fixed(Vec3),
    Conditional { location: Vec3, coordinate: usize, range: [f64; 2] },
    Moving(Box<[MovingAxis; 3]>),
}

#[derive(Debug, Clone)]
struct PathPoint {
    body: usize,
    /// X_B,frame of the frame the point's location is given in.
    frame: Transform,
    kind: PointKind,
}

impl PathPoint {
    /// Whether the point is on the path for coordinate values `q`.
    fn is_active(&self, q: &[f64]) -> bool {
        match &self.kind {
            PointKind::Conditional { coordinate, range, .. } => {
                (range[0] - CONDITIONAL_TOLERANCE..=range[1] + CONDITIONAL_TOLERANCE).contains(&q[*coordinate])
            }
            _ => true,
        }
    }

    /// Location in the point's frame (m).
    fn location(&self, q: &[f64]) -> Vec3 {
        match &self.kind {
            PointKind::Fixed(location) | PointKind::Conditional { location, .. } => *location,
            PointKind::Moving(axes) => Vec3::from_fn(|k, _| {
                let axis = &axes[k];
                axis.function.value(q[axis.coordinate].clamp(axis.range[0], axis.range[1]))
            }),
        }
    }
}

/// A point of the current path, placed.
#[derive(Debug, Clone, Copy)]
struct ActivePoint {
    point: usize,
    body: usize,
    /// m, in ground.
    location: Vec3,
}

/// Scratch space of one path evaluation, reused between calls.
#[derive(Debug, Clone, Default)]
pub struct PathScratch {
    active: Vec<ActivePoint>,
    /// Unit vector from each active point to the next (NaN when they coincide).
    directions: Vec<Vec3>,
}

/// A muscle's path compiled for evaluation.
#[derive(Debug, Clone)]
pub struct GeometryPath {
    pub name: String,
    points: Vec<PathPoint>,
    /// Coordinates (indices into [`Multibody::coordinates`], ascending) the path can depend on:
    /// those of the joints between the bodies its points and wrap objects are on, and those
    /// that move or switch its points.
    pub spanned: Vec<usize>,
    /// Wrap objects in the path's `PathWrapSet`, which this path does not apply.
    pub ignored_wraps: Vec<String>,
}

impl GeometryPath {
    pub fn new(multibody: &Multibody, model: &ModelSpec, force: &ForceSpec) -> Result<GeometryPath, MechanicsError> {
        let invalid = |problem: String| MechanicsError::Invalid { file: multibody.file.clone(), component: force.name.clone(), problem };
        let coordinate = |name: &str, point: &str| {
            multibody.coordinate_index(name).ok_or_else(|| invalid(format!("path point {point}: coordinate {name:?} does not exist in the model")))
        };
        if force.path_points.len() < 2 {
            return Err(invalid(format!("a path needs at least 2 points, found {}", force.path_points.len())));
        }
        let mut points = Vec::with_capacity(force.path_points.len());
        let mut bodies = Vec::new();
        let mut switches = Vec::new();
        for spec in &force.path_points {
            let (body, frame) = multibody.attach(&spec.frame, &format!("{}/{}", force.name, spec.name))?;
            let kind = match &spec.kind {
                PathPointKind::PathPoint { location } => PointKind::Fixed(Vec3::from(*location)),
                PathPointKind::ConditionalPathPoint { location, coordinate: name, range } => {
                    let coordinate = coordinate(name, &spec.name)?;
                    switches.push(coordinate);
                    PointKind::Conditional { location: Vec3::from(*location), coordinate, range: *range }
                }
                PathPointKind::MovingPathPoint { x, y, z } => {
                    let mut axis = |component: &MovingComponent| {
                        let c = coordinate(&component.coordinate, &spec.name)?;
                        switches.push(c);
                        Ok(MovingAxis { coordinate: c, function: Function::new(&component.function), range: multibody.coordinates[c].range })
                    };
                    PointKind::Moving(Box::new([axis(x)?, axis(y)?, axis(z)?]))
                }
            };
            bodies.push(body);
            points.push(PathPoint { body, frame, kind });
        }
        for wrap in &force.path_wraps {
            let object = model.wrap_objects.iter().find(|w| w.name == wrap.wrap_object).ok_or_else(|| invalid(format!("wrap object {:?} does not exist in the model", wrap.wrap_object)))?;
            bodies.push(multibody.body_index(&object.body).ok_or_else(|| invalid(format!("wrap object {:?} is on unknown body {:?}", object.name, object.body)))?);
        }
        let mut spanned: Vec<usize> = multibody.joints_spanned(&bodies).into_iter().flat_map(|j| multibody.joints[j].coordinates.iter().copied()).collect();
        spanned.extend(switches);
        let coupled: Vec<usize> = spanned.iter().flat_map(|&c| coupling::partners(&multibody.couplers, c)).collect();
        spanned.extend(coupled);
        spanned.sort_unstable();
        spanned.dedup();
        let ignored_wraps = force.path_wraps.iter().map(|w| w.wrap_object.clone()).collect();
        Ok(GeometryPath { name: force.name.clone(), points, spanned, ignored_wraps })
    }

    /// Path length (m): the sum of the straight segments between active points.
    pub fn length(&self, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch) -> f64 {
        self.place(kinematics, q, scratch);
        scratch.active.windows(2).map(|pair| (pair[1].location - pair[0].location).norm()).sum()
    }

    /// Path length (m), and in `moment_arms[k]` the moment arm about `coordinates[k]`: m for a
    /// rotational coordinate, m/m for a translational one; positive when tension drives q up.
    /// For a path without wrapping r = −∂L/∂q, except about `BallJoint`/`FreeJoint` rotations,
    /// where OpenSim's generalized speed is an angular velocity and r the torque about the
    /// parent frame's axis.
    ///
    /// Computed as OpenSim does: the unit tension acts at each active point next to a point on
    /// another body, along the segment, and its generalized force is the moment arm; a
    /// `MovingPathPoint` adds the work of its motion in its frame to the coordinate of its x
    /// location. Generalized forces on coordinates tied by couplers are summed along the
    /// constraint (`q` must satisfy the couplers).
    pub fn moment_arms(
        &self,
        multibody: &Multibody,
        kinematics: &Kinematics,
        q: &[f64],
        scratch: &mut PathScratch,
        coordinates: &[usize],
        moment_arms: &mut [f64],
    ) -> f64 {
        let length = self.length(kinematics, q, scratch);
        scratch.directions.clear();
        scratch.directions.extend(scratch.active.windows(2).map(|pair| direction(&pair[0].location, &pair[1].location)));
        for (&coordinate, moment_arm) in coordinates.iter().zip(moment_arms.iter_mut()) {
            *moment_arm = 0.0;
            coupling::for_each_coupling(&multibody.couplers, q, coordinate, |c, weight| {
                *moment_arm += weight * self.generalized_force(multibody, kinematics, q, scratch, c);
            });
        }
        length
    }

    /// The generalized force about `coordinate` of a unit tension along the placed path.
    fn generalized_force(&self, multibody: &Multibody, kinematics: &Kinematics, q: &[f64], scratch: &PathScratch, coordinate: usize) -> f64 {
        let mut force = 0.0;
        for (pair, d) in scratch.active.windows(2).zip(&scratch.directions) {
            let (from, to) = (&pair[0], &pair[1]);
            if from.body == to.body {
                continue;
            }
            force += d.dot(&kinematics.point_partial(multibody, from.body, &from.location, coordinate));
            force -= d.dot(&kinematics.point_partial(multibody, to.body, &to.location, coordinate));
            force += self.moving_work(kinematics, q, from, coordinate).dot(d);
            force -= self.moving_work(kinematics, q, to, coordinate).dot(d);
        }
        force
    }

    /// OpenSim's `getdPointdQ` in ground for a `MovingPathPoint` whose x location is driven by
    /// `coordinate` (all three slopes, at the unclamped values); zero otherwise.
    fn moving_work(&self, kinematics: &Kinematics, q: &[f64], active: &ActivePoint, coordinate: usize) -> Vec3 {
        let point = &self.points[active.point];
        match &point.kind {
            PointKind::Moving(axes) if axes[0].coordinate == coordinate => {
                let slopes = Vec3::from_fn(|k, _| axes[k].function.derivative(q[axes[k].coordinate]));
                kinematics.bodies[point.body].rotation * point.frame.rotation * slopes
            }
            _ => Vec3::zeros(),
        }
    }

    /// Fills `scratch.active` with the active points and their locations in ground.
    fn place(&self, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch) {
        scratch.active.clear();
        for (index, point) in self.points.iter().enumerate().filter(|(_, p)| p.is_active(q)) {
            let in_body = point.frame.apply(&point.location(q));
            scratch.active.push(ActivePoint { point: index, body: point.body, location: kinematics.bodies[point.body].apply(&in_body) });
        }
    }
}

/// Unit vector from `from` to `to`, NaN when the points coincide (as OpenSim).
fn direction(from: &Vec3, to: &Vec3) -> Vec3 {
    let segment = to - from;
    let norm = segment.norm();
    if norm < SIGNIFICANT_LENGTH {
        Vec3::repeat(f64::NAN)
    } else {
        segment / norm
    }
}
