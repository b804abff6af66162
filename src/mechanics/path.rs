//! Muscle paths (`GeometryPath`): the active points, the wrapping over OpenSim 4.6's wrap
//! objects (`GeometryPath::applyWrapObjects`) and the path length; what its tension applies is
//! `path_tension.rs`'s. Paths that also wrap over objects of classes OpenSim 4.6 does not have
//! (3.x's `WrapCylinderObst`, …) are straight lines through their points and say so.

use super::coupling;
use super::error::MechanicsError;
use super::function::Function;
use super::kinematics::Kinematics;
use super::multibody::Multibody;
use super::spatial::{body_fixed_xyz, Transform, Vec3};
use super::wrap_cylinder::Cylinder;
use super::wrap_ellipsoid::Ellipsoid;
use super::wrap_sphere::Sphere;
use super::wrap_surface::{Quadrant, SurfacePath, WrapMethod, WrapSurface, Wrapping};
use super::wrap_torus::Torus;
use crate::model::{ForceSpec, ModelSpec, MovingComponent, PathPointKind, WrapObjectSpec, WrapShape};

/// Simbody's `SignificantReal` (ε^⅞): segments shorter than this have no direction.
const SIGNIFICANT_LENGTH: f64 = 1.8189894035458565e-14;

/// `ConditionalPathPoint` range tolerance OpenSim applies (rad or m).
const CONDITIONAL_TOLERANCE: f64 = 1e-5;

/// One coordinate of a `MovingPathPoint`: location = f(q clamped to the coordinate's range).
#[derive(Debug, Clone)]
pub(super) struct MovingAxis {
    pub(super) coordinate: usize,
    pub(super) function: Function,
    range: [f64; 2],
}

#[derive(Debug, Clone)]
pub(super) enum PointKind {
    Fixed(Vec3),
    Conditional { location: Vec3, coordinate: usize, range: [f64; 2] },
    Moving(Box<[MovingAxis; 3]>),
}

#[derive(Debug, Clone)]
pub(super) struct PathPoint {
    pub(super) body: usize,
    /// X_B,frame of the frame the point's location is given in.
    pub(super) frame: Transform,
    pub(super) kind: PointKind,
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

/// A `PathWrap` over a `WrapCylinder`, `WrapEllipsoid`, `WrapSphere` or `WrapTorus`, compiled.
#[derive(Debug, Clone)]
struct PathWrap {
    /// Index of the wrap object in the model (two `PathWrap`s may share one).
    object: usize,
    body: usize,
    /// X_B,wrap: the wrap object's frame in its body (`xyz_body_rotation`, `translation`).
    frame: Transform,
    active: bool,
    surface: WrapSurface,
    /// First and last path point (0-based indices into `points`) the wrap may span.
    range: [usize; 2],
}

impl PathWrap {
    /// The wrap of the current path's segments `segments` (each by its first point): the first
    /// one whose straight line crosses the cylinder, else the one whose wrapping lengthens the
    /// path least (measured at the locations OpenSim sees); with the action of the last segment
    /// tried. Segments between two tangent points of one wrap object are skipped.
    fn best_segment(&self, kinematics: &Kinematics, active: &[ActivePoint], segments: std::ops::Range<usize>, seen: &mut [[Option<Vec3>; 2]], single_wrap: bool) -> (Option<SegmentWrap>, WrapAction) {
        let to_body = &kinematics.bodies[self.body];
        let into_wrap = |p: &Vec3| {
            let in_body = to_body.rotation.transpose() * (p - to_body.translation);
            self.frame.rotation.transpose() * (in_body - self.frame.translation)
        };
        let (mut best, mut action, mut least_change) = (None, WrapAction::NoWrap, f64::INFINITY);
        for segment in segments {
            let (a, b) = (active[segment], active[segment + 1]);
            if a.wrap_object().is_some() && a.wrap_object() == b.wrap_object() {
                continue;
            }
            let placed = |path: &SurfacePath| {
                let (r1, r2) = (self.frame.apply(&path.r1), self.frame.apply(&path.r2));
                SegmentWrap { end: segment + 1, r1_ground: to_body.apply(&r1), r2_ground: to_body.apply(&r2), length: path.length }
            };
            match self.surface.wrap_line(&into_wrap(&a.location), &into_wrap(&b.location), single_wrap) {
                Wrapping::Mandatory(path) => return (Some(placed(&path)), WrapAction::Mandatory),
                Wrapping::Wrapped(path) => {
                    action = WrapAction::Wrapped;
                    let candidate = placed(&path);
                    let (a_seen, b_seen) = (observed(&a, seen), observed(&b, seen));
                    let change = (a_seen - candidate.r1_ground).norm() + candidate.length + (b_seen - candidate.r2_ground).norm() - (a_seen - b_seen).norm();
                    if change < least_change {
                        best = Some(candidate);
                        least_change = change;
                    }
                }
                Wrapping::InsideRadius => action = WrapAction::InsideRadius,
                Wrapping::NoWrap => action = WrapAction::NoWrap,
            }
        }
        (best, action)
    }
}

/// Where a point of the current path comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Source {
    /// `points[k]`.
    Point(usize),
    /// A tangent point of `wraps[path_wrap]` (a `PathWrapPoint`, the first or `second`); `arc`
    /// is the surface length from the previous point, 0 for the first tangent point.
    Wrap { path_wrap: usize, object: usize, second: bool, arc: f64 },
}

/// A point of the current path, placed.
#[derive(Debug, Clone, Copy)]
pub(super) struct ActivePoint {
    pub(super) source: Source,
    pub(super) body: usize,
    /// m, in ground, where the point is now.
    pub(super) location: Vec3,
}

impl ActivePoint {
    fn wrap_object(&self) -> Option<usize> {
        match self.source {
            Source::Wrap { object, .. } => Some(object),
            Source::Point(_) => None,
        }
    }
}

/// OpenSim's `WrapObject::WrapAction` of the last segment a wrap tried.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum WrapAction {
    NoWrap,
    InsideRadius,
    Wrapped,
    Mandatory,
}

/// Scratch space of one path evaluation, reused between calls.
#[derive(Debug, Clone, Default)]
pub struct PathScratch {
    pub(super) active: Vec<ActivePoint>,
    /// Unit vector from each active point to the next (NaN when they coincide).
    pub(super) directions: Vec<Vec3>,
    /// Order in which the wraps are applied, and each one's last action.
    order: Vec<usize>,
    actions: Vec<WrapAction>,
    /// The ground location OpenSim sees for each `PathWrap`'s two tangent points (see
    /// [`observed`]).
    observed: Vec<[Option<Vec3>; 2]>,
}

/// The best wrap of one `PathWrap` so far: the segment it replaces and its tangent points in
/// ground.
#[derive(Debug, Clone, Copy)]
struct SegmentWrap {
    /// Index in the current path of the segment's second point.
    end: usize,
    r1_ground: Vec3,
    r2_ground: Vec3,
    length: f64,
}

/// A muscle's path compiled for evaluation.
#[derive(Debug, Clone)]
pub struct GeometryPath {
    pub name: String,
    pub(super) points: Vec<PathPoint>,
    /// Coordinates (indices into [`Multibody::coordinates`], ascending) the path can depend on:
    /// those of the joints between the bodies its points and wrap objects are on, and those
    /// that move or switch its points.
    pub spanned: Vec<usize>,
    /// Coordinates (ascending) the path's tension has generalized forces on as OpenSim applies
    /// it: `spanned`, and for a path over wrap objects also those of the joints that move all
    /// its bodies together — OpenSim's stale tangent points leave its forces unbalanced under
    /// such a rigid motion (e.g. Rajagopal2016's gastrocnemii get hip moment arms of 1e-4 m).
    pub loaded: Vec<usize>,
    /// Wrap objects in the path's `PathWrapSet`, which this path does not apply (all of them
    /// when osim-tune does not compute the wrapping over any one).
    pub ignored_wraps: Vec<String>,
    /// The `PathWrap`s applied, in `PathWrapSet` order.
    wraps: Vec<PathWrap>,
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
        let mut wraps = Vec::with_capacity(force.path_wraps.len());
        for wrap in &force.path_wraps {
            let index = model.wrap_objects.iter().position(|w| w.name == wrap.wrap_object).ok_or_else(|| invalid(format!("wrap object {:?} does not exist in the model", wrap.wrap_object)))?;
            let object = &model.wrap_objects[index];
            let body = multibody.body_index(&object.body).ok_or_else(|| invalid(format!("wrap object {:?} is on unknown body {:?}", object.name, object.body)))?;
            bodies.push(body);
            let quadrant = Quadrant::parse(&object.quadrant).map_err(|problem| invalid(format!("wrap object {:?}: {problem}", object.name)))?;
            let method = WrapMethod::parse(&wrap.method).map_err(|problem| invalid(format!("path wrap over {:?}: {problem}", object.name)))?;
            let Some(surface) = wrap_surface(object, quadrant, method) else { continue };
            let last = points.len() - 1;
            let bound = |value: i32, default: usize| if value < 1 { Ok(default) } else { (value as usize - 1 <= last).then_some(value as usize - 1).ok_or(()) };
            let range = match (bound(wrap.range[0], 0), bound(wrap.range[1], last)) {
                (Ok(first), Ok(end)) => [first, end],
                _ => return Err(invalid(format!("path wrap over {:?}: range {} {} goes beyond the path's {} points", object.name, wrap.range[0], wrap.range[1], points.len()))),
            };
            let frame = Transform { rotation: body_fixed_xyz(object.xyz_body_rotation), translation: Vec3::from(object.translation) };
            wraps.push(PathWrap { object: index, body, frame, active: object.active, surface, range });
        }
        let coordinates = |joints: Vec<usize>| {
            let moving: Vec<usize> = joints.into_iter().flat_map(|j| multibody.joints[j].coordinates.iter().copied()).chain(switches.iter().copied()).collect();
            coupling::tied_coordinates(multibody, &moving)
        };
        let spanned = coordinates(multibody.joints_spanned(&bodies));
        let loaded = if wraps.is_empty() { spanned.clone() } else { coordinates(multibody.joints_moving(&bodies)) };
        let ignored_wraps = if wraps.len() == force.path_wraps.len() {
            Vec::new()
        } else {
            wraps.clear();
            force.path_wraps.iter().map(|w| w.wrap_object.clone()).collect()
        };
        let loaded = if ignored_wraps.is_empty() { loaded } else { spanned.clone() };
        Ok(GeometryPath { name: force.name.clone(), points, spanned, loaded, ignored_wraps, wraps })
    }

    /// Path length (m): the straight segments between the points of the current path and the
    /// surface lengths over the wrap objects.
    pub fn length(&self, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch) -> f64 {
        self.place(kinematics, q, scratch);
        self.apply_wraps(kinematics, q, scratch);
        current_length(&scratch.active, &mut scratch.observed)
    }

    /// Places the path ([`GeometryPath::length`]) and the unit direction of each of its segments
    /// as OpenSim sees them; returns the length (m).
    pub(super) fn place_with_directions(&self, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch) -> f64 {
        let length = self.length(kinematics, q, scratch);
        scratch.directions.clear();
        let PathScratch { active, directions, observed: seen, .. } = scratch;
        directions.extend(active.windows(2).map(|pair| direction(&observed(&pair[0], seen), &observed(&pair[1], seen))));
        length
    }

    /// Fills `scratch.active` with the active points and their locations in ground.
    fn place(&self, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch) {
        scratch.active.clear();
        for (index, point) in self.points.iter().enumerate().filter(|(_, p)| p.is_active(q)) {
            let in_body = point.frame.apply(&point.location(q));
            scratch.active.push(ActivePoint { source: Source::Point(index), body: point.body, location: kinematics.bodies[point.body].apply(&in_body) });
        }
    }

    /// `GeometryPath::applyWrapObjects`: inserts each wrap's two tangent points into the current
    /// path. A path with one wrap is wrapped once; with several, up to 8 passes, each wrap
    /// re-applied on the path the others left, until the length changes by less than 0.5 mm.
    /// Each wrap takes the first segment of its range the straight line of which crosses the
    /// object, else the segment whose wrapping lengthens the path least.
    fn apply_wraps(&self, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch) {
        let count = self.wraps.len();
        if count == 0 {
            return;
        }
        scratch.order.clear();
        scratch.order.extend(0..count);
        scratch.actions.clear();
        scratch.actions.resize(count, WrapAction::NoWrap);
        scratch.observed.clear();
        scratch.observed.resize(count, [None, None]);
        let passes = if count < 2 { 1 } else { 8 };
        let mut last_length = f64::INFINITY;
        for pass in 0..passes {
            for i in 0..count {
                scratch.actions[i] = WrapAction::NoWrap;
                let w = scratch.order[i];
                remove_wrap_points(&mut scratch.active, w);
                let wrap = &self.wraps[w];
                if !wrap.active {
                    continue;
                }
                let active_in = |k: usize| self.points[k].is_active(q);
                let Some(first) = (wrap.range[0]..=wrap.range[1]).find(|&k| active_in(k)) else { return };
                let Some(last) = (wrap.range[0]..=wrap.range[1]).rev().find(|&k| active_in(k)) else { return };
                let position = |k: usize| scratch.active.iter().position(|p| p.source == Source::Point(k));
                let (Some(start), Some(end)) = (position(first), position(last)) else { return };
                let (best, action) = wrap.best_segment(kinematics, &scratch.active, start..end, &mut scratch.observed, count == 1);
                scratch.actions[i] = action;
                if let Some(best) = best {
                    let point = |location: Vec3, second: bool, arc: f64| ActivePoint { source: Source::Wrap { path_wrap: w, object: wrap.object, second, arc }, body: wrap.body, location };
                    scratch.active.insert(best.end, point(best.r1_ground, false, 0.0));
                    scratch.active.insert(best.end + 1, point(best.r2_ground, true, best.length));
                }
            }
            let length = current_length(&scratch.active, &mut scratch.observed);
            if (length - last_length).abs() < 0.0005 {
                break;
            }
            last_length = length;
            // A first wrap that missed and a second that found a point inside its object: try
            // them the other way round.
            if pass == 0 && count > 1 && scratch.actions[0] == WrapAction::NoWrap && scratch.actions[1] == WrapAction::InsideRadius {
                scratch.order.swap(0, 1);
                remove_wrap_points(&mut scratch.active, 0);
            }
        }
    }
}

/// The surface a `PathWrap` wraps over: `None` for a class OpenSim 4.6 does not have.
fn wrap_surface(object: &WrapObjectSpec, quadrant: Option<Quadrant>, method: WrapMethod) -> Option<WrapSurface> {
    match object.shape {
        WrapShape::Cylinder { radius, length } => Some(WrapSurface::Cylinder(Cylinder { radius, length, quadrant })),
        WrapShape::Ellipsoid { dimensions } => Some(WrapSurface::Ellipsoid(Ellipsoid { dimensions: Vec3::from(dimensions), quadrant, method })),
        WrapShape::Sphere { radius } => Some(WrapSurface::Sphere(Sphere { radius, quadrant })),
        WrapShape::Torus { inner_radius, outer_radius } => Some(WrapSurface::Torus(Torus { inner_radius, outer_radius, quadrant })),
        WrapShape::Other => None,
    }
}

/// Removes the two tangent points of `path_wrap` from the current path, if it has them.
fn remove_wrap_points(active: &mut Vec<ActivePoint>, path_wrap: usize) {
    if let Some(j) = active.iter().position(|p| matches!(p.source, Source::Wrap { path_wrap: w, .. } if w == path_wrap)) {
        active.drain(j..j + 2);
    }
}

/// The ground location OpenSim uses for a point of the current path (`getLocationInGround`).
/// OpenSim caches a point's ground location the first time it is asked for in a state, and moving
/// a `PathWrapPoint` (`setLocation`) does not invalidate that cache: a tangent point keeps the
/// ground location it had when first measured — by the length at the end of a wrapping pass or
/// by a length-change comparison — even when a later pass moves it. The straight segments next
/// to tangent points, and so the path length and the moment arms' directions, use these stale
/// locations; the wrapping itself and the surface lengths use the current ones.
fn observed(point: &ActivePoint, observed: &mut [[Option<Vec3>; 2]]) -> Vec3 {
    match point.source {
        Source::Point(_) => point.location,
        Source::Wrap { path_wrap, second, .. } => *observed[path_wrap][usize::from(second)].get_or_insert(point.location),
    }
}

/// `calcLengthAfterPathComputation`: straight segments between the observed locations, and the
/// surface length between the two tangent points of a wrap object.
fn current_length(active: &[ActivePoint], seen: &mut [[Option<Vec3>; 2]]) -> f64 {
    let mut length = 0.0;
    for pair in active.windows(2) {
        let (from, to) = (observed(&pair[0], seen), observed(&pair[1], seen));
        length += match (pair[0].source, pair[1].source) {
            (Source::Wrap { object: a, .. }, Source::Wrap { object: b, arc, .. }) if a == b => arc,
            _ => (to - from).norm(),
        };
    }
    length
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

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::io::osim::OsimDocument;
    use crate::mechanics::{AppliedForces, MotionState, MuscleGeometry};

    /// The loads a tension applies do the work its moment arms say: their generalized forces
    /// (inverse dynamics at rest with and without them), plus the moving points' mobility
    /// forces, are the tension times the moment arm about every coordinate. gait2392 has
    /// MovingPathPoints; arm26 wraps over cylinders and ellipsoids.
    #[test]
    fn tension_loads_have_the_moment_arms_generalized_forces() {
        for file in ["models/gait2392_thelen2003muscle.osim", "fixtures/models/arm26.osim"] {
            let spec = ModelSpec::read(&OsimDocument::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join(file)).unwrap()).unwrap();
            let geometry = MuscleGeometry::new(&spec).unwrap();
            let multibody = &geometry.multibody;
            let mut q = multibody.default_pose();
            q.iter_mut().enumerate().for_each(|(c, v)| *v += 0.3 * (c as f64 * 0.8).sin());
            let mut kinematics = multibody.kinematics();
            multibody.realize(&q, &mut kinematics);
            let n = q.len();
            let zero = vec![0.0; n];
            let state = MotionState { q: &q, u: &zero, udot: &zero };
            let at_rest = multibody.inverse_dynamics(&state, &[]);
            let all: Vec<usize> = (0..n).collect();
            let mut scratch = PathScratch::default();
            for path in &geometry.paths {
                let mut arms = vec![0.0; n];
                path.moment_arms(multibody, &kinematics, &q, &mut scratch, &all, &mut arms);
                let mut applied = AppliedForces::new(n);
                path.tension_loads(&kinematics, &q, &mut scratch, 100.0, &mut applied);
                let loaded = multibody.inverse_dynamics(&state, &applied.loads);
                for c in 0..n {
                    let applied = at_rest[c] - loaded[c] + applied.mobility[c];
                    assert!((applied - 100.0 * arms[c]).abs() < 1e-10, "{file} {} about {}: {applied} vs {}", path.name, multibody.coordinates[c].name, 100.0 * arms[c]);
                }
            }
        }
    }

    /// Two points on different bodies that coincide separate at their relative speed, whichever
    /// way they move, as OpenSim's `calcSpeedBetween` has it (OpenSim 4.6 gives 0.3 m/s for
    /// both signs on this slider, whose path runs from ground to the sliding block).
    #[test]
    fn coincident_points_separate_at_their_relative_speed() {
        let spec = ModelSpec::read(&OsimDocument::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/models/degroote_bench.osim")).unwrap()).unwrap();
        let geometry = MuscleGeometry::new(&spec).unwrap();
        let multibody = &geometry.multibody;
        let slider = multibody.coordinate_index("default_length").unwrap();
        let path = geometry.paths.iter().find(|p| p.spanned.contains(&slider)).unwrap();
        let mut q = multibody.default_pose();
        q[slider] = 0.0;
        let mut kinematics = multibody.kinematics();
        multibody.realize(&q, &mut kinematics);
        let mut scratch = PathScratch::default();
        for speed in [0.3, -0.3] {
            let mut u = vec![0.0; q.len()];
            u[slider] = speed;
            let (length, lengthening) = path.length_and_speed(multibody, &kinematics, &q, &mut scratch, &[slider], &u);
            assert_eq!(length, 0.0);
            assert!((lengthening - 0.3).abs() < 1e-15, "{lengthening}");
        }
    }
}
