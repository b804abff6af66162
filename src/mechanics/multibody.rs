//! The multibody tree compiled from a `ModelSpec`: ground, bodies and the joints between them in
//! parent-before-child order, the generalized coordinates (OpenSim's `CoordinateSet` order) and
//! markers fixed in bodies.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::body_link::BodyLink;
use super::coupling::Coupler;
use super::error::MechanicsError;
use super::function::Function;
use super::mobilizer::{Mobilizer, TransformAxis};
use super::mobilizer_surface::{Ellipsoid, Scapulothoracic};
use super::spatial::{Mat3, Transform, Vec3};
use crate::model::{BodySpec, CoordinateSpec, FrameChain, JointSpec, JointSurface, ModelSpec, GROUND};

/// Index of ground in [`Multibody::bodies`].
pub const GROUND_INDEX: usize = 0;

/// A body of the tree; ground is body 0 and has no joint.
#[derive(Debug, Clone)]
pub struct Body {
    pub name: String,
    /// Index of the joint that carries the body (into [`Multibody::joints`]).
    pub joint: Option<usize>,
    /// kg (0 for ground).
    pub mass: f64,
    /// m, in the body frame.
    pub mass_center: Vec3,
    /// kg·m² about the mass center, in the body frame.
    pub inertia: Mat3,
}

impl Body {
    fn new(spec: &BodySpec) -> Body {
        let [xx, yy, zz, xy, xz, yz] = spec.inertia;
        let inertia = Mat3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
        Body { name: spec.name.clone(), joint: None, mass: spec.mass, mass_center: Vec3::from(spec.mass_center), inertia }
    }
}

/// A joint compiled for evaluation: X_GB(child) = X_GB(parent) · X_PF · X_FM(q) · X_MB.
#[derive(Debug, Clone)]
pub struct Joint {
    pub name: String,
    pub parent: usize,
    pub child: usize,
    /// X_PF: the parent frame in the parent body.
    pub parent_frame: Transform,
    /// X_MB: the child body in the child frame.
    pub child_body: Transform,
    /// The child frame's name (e.g. `femur_r_offset`).
    pub child_frame: String,
    pub mobilizer: Mobilizer,
    /// Indices into [`Multibody::coordinates`], in the joint's coordinate order.
    pub coordinates: Vec<usize>,
}

/// A marker fixed in a body.
#[derive(Debug, Clone)]
pub struct Marker {
    pub name: String,
    pub body: usize,
    /// m, in the body frame.
    pub location: Vec3,
}

/// The compiled tree.
#[derive(Debug, Clone)]
pub struct Multibody {
    pub file: PathBuf,
    pub bodies: Vec<Body>,
    /// Parents before children.
    pub joints: Vec<Joint>,
    pub coordinates: Vec<CoordinateSpec>,
    pub markers: Vec<Marker>,
    /// Enforced `CoordinateCouplerConstraint`s.
    pub couplers: Vec<Coupler>,
    /// The other enforced constraints between bodies (point, distance, point-on-line, weld): held
    /// by inverse kinematics and assembly; dynamics refuses them.
    pub links: Vec<BodyLink>,
    /// The enforced constraints of classes not read (neither couplers nor links), `name
    /// (class)`: nothing here holds them (inverse kinematics and dynamics refuse them).
    pub unheld_constraints: Vec<String>,
    /// The model's gravity, m/s² in ground.
    pub gravity: Vec3,
    /// `moved_by[body][joint]`: whether the joint's coordinates move the body.
    moved_by: Vec<Vec<bool>>,
    /// The joint of each coordinate.
    coordinate_joints: Vec<usize>,
}

impl Multibody {
    pub fn new(spec: &ModelSpec) -> Result<Multibody, MechanicsError> {
        let file = spec.file.clone();
        let ground = BodySpec { name: GROUND.to_string(), mass: 0.0, mass_center: [0.0; 3], inertia: [0.0; 6] };
        let mut bodies: Vec<Body> = std::iter::once(&ground).chain(&spec.bodies).map(Body::new).collect();
        let names: Vec<String> = bodies.iter().map(|b| b.name.clone()).collect();
        let body_index: HashMap<&str, usize> = names.iter().enumerate().map(|(i, name)| (name.as_str(), i)).collect();
        let coordinates: Vec<CoordinateSpec> = spec.coordinates().cloned().collect();
        let order = tree_order(spec, &body_index)?;
        let mut joints = Vec::with_capacity(order.len());
        let mut first_coordinate = 0;
        let mut coordinate_offsets = Vec::with_capacity(spec.joints.len());
        for joint in &spec.joints {
            coordinate_offsets.push(first_coordinate);
            first_coordinate += joint.coordinates.len();
        }
        for &j in &order {
            let joint = &spec.joints[j];
            let compiler = JointCompiler { file: &file, joint, body_index: &body_index };
            let compiled = compiler.compile((coordinate_offsets[j]..coordinate_offsets[j] + joint.coordinates.len()).collect())?;
            bodies[compiled.child].joint = Some(joints.len());
            joints.push(compiled);
        }
        let mut coordinate_joints = vec![0; coordinates.len()];
        for (j, joint) in joints.iter().enumerate() {
            for &c in &joint.coordinates {
                coordinate_joints[c] = j;
            }
        }
        let couplers = Coupler::compile_all(spec, &coordinates, &file)?;
        let unheld_constraints = spec.constraints.iter().filter(|c| c.enforced && c.coupler.is_none() && c.link.is_none()).map(|c| format!("{} ({})", c.name, c.class)).collect();
        let mut multibody =
            Multibody { file, bodies, joints, coordinates, markers: Vec::new(), couplers, links: Vec::new(), unheld_constraints, gravity: Vec3::from(spec.gravity), moved_by: Vec::new(), coordinate_joints };
        multibody.moved_by = (0..multibody.bodies.len()).map(|b| multibody.ancestor_joints(b)).collect();
        for marker in &spec.markers {
            let (body, frame) = multibody.attach(&marker.frame, &marker.name)?;
            multibody.markers.push(Marker { name: marker.name.clone(), body, location: frame.apply(&Vec3::from(marker.location)) });
        }
        for constraint in spec.constraints.iter().filter(|c| c.enforced) {
            if let Some(link) = &constraint.link {
                let link = BodyLink::new(&multibody, constraint, link)?;
                multibody.links.push(link);
            }
        }
        Ok(multibody)
    }

    /// The body a frame chain hangs on and X_B,frame.
    pub fn attach(&self, frame: &FrameChain, component: &str) -> Result<(usize, Transform), MechanicsError> {
        let body = self.body_index(&frame.body).ok_or_else(|| MechanicsError::Invalid {
            file: self.file.clone(),
            component: component.to_string(),
            problem: format!("body {:?} does not exist in the model", frame.body),
        })?;
        Ok((body, chain_transform(frame)))
    }

    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.coordinates.iter().position(|c| c.name == name)
    }

    /// The default pose (rad or m per coordinate): default values, each coupler's dependent
    /// coordinate following its independent one, as OpenSim's `initSystem` assembles a model
    /// whose only constraints are couplers (its assembler holds them exactly and keeps every
    /// other coordinate at its default). A dependent's own `default_value` is not used: OpenSim
    /// overrides it too (BothLegs22's `tp_r3` by 0.31 m, leg6dof9musc's patella by 2e-8 rad).
    /// Other constraints need a solve: `solvers::ik::assemble`.
    pub fn default_pose(&self) -> Vec<f64> {
        let mut q: Vec<f64> = self.coordinates.iter().map(|c| c.default_value).collect();
        self.follow_couplers(&mut q, &[]);
        q
    }

    /// Sets the dependent coordinate of every coupler from its independent one, unless the
    /// dependent is one of `given`. A dependent that is another coupler's independent one is
    /// set first (passes until nothing moves, at most one per coupler).
    pub fn follow_couplers(&self, q: &mut [f64], given: &[usize]) {
        for _ in 0..self.couplers.len() {
            let mut moved = false;
            for coupler in self.couplers.iter().filter(|c| !given.contains(&c.dependent)) {
                let value = coupler.dependent_value(q);
                moved |= value != q[coupler.dependent];
                q[coupler.dependent] = value;
            }
            if !moved {
                break;
            }
        }
    }

    /// Sets the speed of every coupler's dependent coordinate from its independent one's at
    /// coordinates `q` (u_d = f′(q_i) u_i; chains as [`Multibody::follow_couplers`]).
    pub fn follow_coupler_speeds(&self, q: &[f64], u: &mut [f64]) {
        for _ in 0..self.couplers.len() {
            let mut moved = false;
            for coupler in &self.couplers {
                let speed = coupler.slope(q) * u[coupler.independent];
                moved |= speed != u[coupler.dependent];
                u[coupler.dependent] = speed;
            }
            if !moved {
                break;
            }
        }
    }

    /// Every coordinate's rate q̇ at `q` moving at speeds `u` (q̇ = u but for the angles of
    /// Ball, Free and ellipsoid joints, see [`Mobilizer::coordinate_rates`]).
    pub fn coordinate_rates(&self, q: &[f64], u: &[f64]) -> Vec<f64> {
        let mut rates = u.to_vec();
        for joint in self.joints.iter().filter(|j| j.mobilizer.angular_velocity_speeds() > 0) {
            let own = |values: &[f64]| joint.coordinates.iter().map(|&c| values[c]).collect::<Vec<f64>>();
            for (&c, rate) in joint.coordinates.iter().zip(joint.mobilizer.coordinate_rates(&own(q), &own(u))) {
                rates[c] = rate;
            }
        }
        rates
    }

    /// Whether a coupler makes `coordinate` its dependent one.
    pub fn is_dependent(&self, coordinate: usize) -> bool {
        self.couplers.iter().any(|k| k.dependent == coordinate)
    }

    /// The joint (index into [`Multibody::joints`]) a coordinate belongs to.
    pub fn coordinate_joint(&self, coordinate: usize) -> usize {
        self.coordinate_joints[coordinate]
    }

    /// Whether the coordinates of `joint` move `body`.
    pub fn is_moved_by(&self, body: usize, joint: usize) -> bool {
        self.moved_by[body][joint]
    }

    /// Joints from ground to `body`, as a mask over [`Multibody::joints`].
    fn ancestor_joints(&self, body: usize) -> Vec<bool> {
        let mut mask = vec![false; self.joints.len()];
        let mut current = body;
        while let Some(j) = self.bodies[current].joint {
            mask[j] = true;
            current = self.joints[j].parent;
        }
        mask
    }

    /// Joints on the tree path joining all of `bodies` (below their deepest common ancestor).
    pub fn joints_spanned(&self, bodies: &[usize]) -> Vec<usize> {
        let masks: Vec<&Vec<bool>> = bodies.iter().map(|&b| &self.moved_by[b]).collect();
        (0..self.joints.len()).filter(|&j| masks.iter().any(|m| m[j]) && !masks.iter().all(|m| m[j])).collect()
    }

    /// Joints that move at least one of `bodies`.
    pub fn joints_moving(&self, bodies: &[usize]) -> Vec<usize> {
        (0..self.joints.len()).filter(|&j| bodies.iter().any(|&b| self.moved_by[b][j])).collect()
    }
}

/// X_B,frame for a chain of offsets starting at the body.
fn chain_transform(frame: &FrameChain) -> Transform {
    frame.offsets.iter().fold(Transform::IDENTITY, |x, offset| x.compose(&Transform::from_offset(offset)))
}

/// The mobilizer of a joint that glides on `surface` (`EllipsoidJoint`, `ScapulothoracicJoint`).
fn surface_mobilizer(surface: &JointSurface) -> Mobilizer {
    match *surface {
        JointSurface::Ellipsoid { radii } => Mobilizer::Ellipsoid(Ellipsoid { radii: Vec3::from(radii) }),
        JointSurface::Scapulothoracic { radii, winging_origin, winging_direction } => {
            Mobilizer::Scapulothoracic(Box::new(Scapulothoracic::new(radii, winging_origin, winging_direction)))
        }
    }
}

/// Joint indices of `spec.joints` ordered so each joint's parent body is already placed.
fn tree_order(spec: &ModelSpec, body_index: &HashMap<&str, usize>) -> Result<Vec<usize>, MechanicsError> {
    let invalid = |component: &str, problem: String| MechanicsError::Invalid { file: spec.file.clone(), component: component.to_string(), problem };
    let mut carried_by: Vec<Option<usize>> = vec![None; body_index.len()];
    for (j, joint) in spec.joints.iter().enumerate() {
        for body in [&joint.parent.body, &joint.child.body] {
            if !body_index.contains_key(body.as_str()) {
                return Err(invalid(&joint.name, format!("body {body:?} does not exist in the model")));
            }
        }
        let child = body_index[joint.child.body.as_str()];
        if child == GROUND_INDEX {
            return Err(MechanicsError::Unsupported { file: spec.file.clone(), component: joint.name.clone(), what: "a joint whose child is ground (reversed joint)".into() });
        }
        if let Some(other) = carried_by[child] {
            return Err(MechanicsError::Unsupported {
                file: spec.file.clone(),
                component: joint.name.clone(),
                what: format!("a closed kinematic loop (body {:?} is also the child of {})", joint.child.body, spec.joints[other].name),
            });
        }
        carried_by[child] = Some(j);
    }
    let mut placed = vec![false; body_index.len()];
    placed[GROUND_INDEX] = true;
    let mut order = Vec::with_capacity(spec.joints.len());
    while order.len() < spec.joints.len() {
        let before = order.len();
        for (j, joint) in spec.joints.iter().enumerate() {
            let (parent, child) = (body_index[joint.parent.body.as_str()], body_index[joint.child.body.as_str()]);
            if placed[parent] && !placed[child] {
                placed[child] = true;
                order.push(j);
            }
        }
        if order.len() == before {
            let stuck = spec.joints.iter().find(|joint| !placed[body_index[joint.child.body.as_str()]]).map_or("model", |joint| joint.name.as_str());
            return Err(invalid(stuck, "is not connected to ground through joints".into()));
        }
    }
    if let Some(body) = spec.bodies.iter().find(|b| carried_by[body_index[b.name.as_str()]].is_none()) {
        return Err(invalid(&body.name, "no joint connects this body to the model".into()));
    }
    Ok(order)
}

/// Compiles one `JointSpec`.
struct JointCompiler<'a> {
    file: &'a Path,
    joint: &'a JointSpec,
    body_index: &'a HashMap<&'a str, usize>,
}

impl JointCompiler<'_> {
    fn compile(&self, coordinates: Vec<usize>) -> Result<Joint, MechanicsError> {
        let joint = self.joint;
        let mobilizer = self.mobilizer()?;
        if let Some(expected) = mobilizer.coordinate_count().filter(|&n| n != coordinates.len()) {
            return Err(self.invalid(format!("a {} has {expected} coordinates, found {}", joint.class, coordinates.len())));
        }
        Ok(Joint {
            name: joint.name.clone(),
            parent: self.body_index[joint.parent.body.as_str()],
            child: self.body_index[joint.child.body.as_str()],
            parent_frame: chain_transform(&joint.parent),
            child_body: chain_transform(&joint.child).inverse(),
            child_frame: joint.child.name.clone(),
            mobilizer,
            coordinates,
        })
    }

    fn mobilizer(&self) -> Result<Mobilizer, MechanicsError> {
        if let Some(surface) = &self.joint.surface {
            return Ok(surface_mobilizer(surface));
        }
        Ok(match self.joint.class.as_str() {
            "WeldJoint" => Mobilizer::Weld,
            "PinJoint" => Mobilizer::Pin,
            "SliderJoint" => Mobilizer::Slider,
            "UniversalJoint" => Mobilizer::Universal,
            "BallJoint" => Mobilizer::Ball,
            "GimbalJoint" => Mobilizer::Gimbal,
            "FreeJoint" => Mobilizer::Free,
            "PlanarJoint" => Mobilizer::Planar,
            "CustomJoint" => Mobilizer::Custom(Box::new(self.spatial_transform()?)),
            other => {
                return Err(MechanicsError::Unsupported { file: self.file.into(), component: self.joint.name.clone(), what: format!("joint class {other}") })
            }
        })
    }

    /// OpenSim's `SpatialTransform`: an axis without a function is the identity of its one
    /// coordinate, or zero without coordinates; axes are normalised; collinear axes are an error.
    fn spatial_transform(&self) -> Result<[TransformAxis; 6], MechanicsError> {
        let mut axes = Vec::with_capacity(6);
        for spec in &self.joint.spatial_transform {
            let coordinate = match spec.coordinates.as_slice() {
                [] => None,
                [name] => Some(self.joint.coordinates.iter().position(|c| &c.name == name).ok_or_else(|| {
                    self.invalid(format!("{} names coordinate {name:?}, which is not one of the joint's coordinates", spec.name))
                })?),
                _ => {
                    return Err(MechanicsError::Unsupported {
                        file: self.file.into(),
                        component: self.joint.name.clone(),
                        what: format!("{}: a function of several coordinates", spec.name),
                    })
                }
            };
            let function = match (&spec.function, coordinate) {
                (Some(function), _) => Function::new(function),
                (None, Some(_)) => Function::new(&crate::model::FunctionSpec::LinearFunction { slope: 1.0, intercept: 0.0 }),
                (None, None) => Function::new(&crate::model::FunctionSpec::Constant { value: 0.0 }),
            };
            let axis = Vec3::from(spec.axis);
            if axis.norm() == 0.0 {
                return Err(self.invalid(format!("{} has a zero axis", spec.name)));
            }
            axes.push(TransformAxis { axis: axis.normalize(), coordinate, function });
        }
        let axes: [TransformAxis; 6] = axes.try_into().map_err(|_| self.invalid("a SpatialTransform needs 6 axes".into()))?;
        for group in [&axes[..3], &axes[3..]] {
            for (a, b) in [(0, 1), (0, 2), (1, 2)] {
                if group[a].axis.cross(&group[b].axis).norm() < 1e-5 {
                    return Err(self.invalid("has collinear axes (OpenSim rejects them too)".into()));
                }
            }
        }
        Ok(axes)
    }

    fn invalid(&self, problem: String) -> MechanicsError {
        MechanicsError::Invalid { file: self.file.into(), component: self.joint.name.clone(), problem }
    }
}
