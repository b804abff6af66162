//! Swapping a model's knee for a `PinJoint` about a functional axis. The joint keeps its name,
//! its coordinate (name, range, default, clamping, so motions, setups and conditional or moving
//! path points keyed on it still work) and the names of its offset frames. The parent frame is
//! put on the axis with its Z along it; the child frame is placed so that the child body's pose
//! relative to the parent body at the reference angle is unchanged.

use crate::io::osim::{format_numbers, OsimDocument, OsimError};
use crate::io::xml::{EditError, ElementId};
use crate::mechanics::{body_fixed_xyz_angles, rotation_about, Mat3, MechanicsError, Multibody, MuscleGeometry, Transform, Vec3};
use crate::model::{upgrade, ComponentReader, JointSpec, ModelError, ModelSpec, MotionType, Offset};

use super::path_change::{path_changes, PathChange};

/// A joint axis in the parent body's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointAxis {
    /// A point on the axis, m.
    pub point: Vec3,
    /// Unit direction; the joint angle turns the child about it by the right-hand rule.
    pub direction: Vec3,
}

/// The model with its knee swapped, and what the swap changed.
#[derive(Debug, Clone)]
pub struct SwappedKnee {
    pub document: OsimDocument,
    pub joint: String,
    pub coordinate: String,
    /// The coordinate value (rad) at which the child's pose is preserved.
    pub reference_angle: f64,
    /// The new parent offset frame in the parent body, and the child offset frame in the child body.
    pub parent_frame: Offset,
    pub child_frame: Offset,
    /// Largest distance (m) between a child-body point within 1 m of its origin before and after
    /// the swap, at the reference angle (rounding only, when the written model is re-read).
    pub reference_pose_error: f64,
    /// Path length and moment-arm changes of the muscles that cross the joint.
    pub paths: Vec<PathChange>,
}

/// Why the knee could not be swapped.
#[derive(Debug, thiserror::Error)]
pub enum SwapError {
    #[error(transparent)]
    Osim(#[from] OsimError),
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Mechanics(#[from] MechanicsError),
    #[error(transparent)]
    Edit(#[from] EditError),
    #[error("{}: no joint named {joint:?} in the JointSet (joints: {known})", file.display())]
    UnknownJoint { file: std::path::PathBuf, joint: String, known: String },
    #[error("{}:{line}: joint {joint:?} {problem}", file.display())]
    Unsupported { file: std::path::PathBuf, line: usize, joint: String, problem: String },
    #[error("the knee axis {problem}")]
    BadAxis { problem: String },
}

/// Replaces joint `joint` by a `PinJoint` about `axis` (in the parent body's frame), preserving
/// the child's pose at `reference_angle` (rad; `None`: the coordinate's default value). A 2.x/3.x
/// model is converted to OpenSim 4's format first, as OpenSim 4 would write it.
pub fn swap_knee(document: &OsimDocument, joint: &str, axis: &JointAxis, reference_angle: Option<f64>) -> Result<SwappedKnee, SwapError> {
    let axis = checked_axis(axis)?;
    let upgraded = upgrade(document)?;
    let document: &OsimDocument = &upgraded;
    let spec = ModelSpec::read(document)?;
    let (element, joint_spec) = hinge(document, &spec, joint)?;
    let coordinate = joint_spec.coordinates[0].clone();
    let reference_angle = reference_angle.unwrap_or(coordinate.default_value);
    let multibody = Multibody::new(&spec)?;
    let child_in_parent = child_in_parent(&multibody, joint_spec, &coordinate.name, reference_angle)?;
    let parent_frame = Transform { rotation: frame_along(&axis.direction), translation: axis.point };
    let turned = Transform { rotation: rotation_about(&Vec3::z(), reference_angle), translation: Vec3::zeros() };
    let child_frame = child_in_parent.inverse().compose(&parent_frame).compose(&turned);
    let mut swapped = document.clone();
    let (parent_offset, child_offset) = (offset_of(&parent_frame), offset_of(&child_frame));
    rewrite_joint(&mut swapped, element, &parent_offset, &child_offset)?;
    let swapped = OsimDocument::from_bytes(swapped.xml.serialize(), document.xml.file())?;
    let new_spec = ModelSpec::read(&swapped)?;
    let new_multibody = Multibody::new(&new_spec)?;
    let reference_pose_error = pose_distance(&child_in_parent, &self::child_in_parent(&new_multibody, joint_spec, &coordinate.name, reference_angle)?);
    let paths = path_changes(&MuscleGeometry::new(&spec)?, &MuscleGeometry::new(&new_spec)?, &coordinate)?;
    Ok(SwappedKnee {
        document: swapped,
        joint: joint.to_string(),
        coordinate: coordinate.name,
        reference_angle,
        parent_frame: parent_offset,
        child_frame: child_offset,
        reference_pose_error,
        paths,
    })
}

fn checked_axis(axis: &JointAxis) -> Result<JointAxis, SwapError> {
    let norm = axis.direction.norm();
    if !(norm > 1e-12 && norm.is_finite() && axis.point.iter().all(|v| v.is_finite())) {
        let problem = format!("must have a finite point and a non-zero direction (point {:?}, direction {:?})", axis.point.as_slice(), axis.direction.as_slice());
        return Err(SwapError::BadAxis { problem });
    }
    Ok(JointAxis { point: axis.point, direction: axis.direction / norm })
}

/// The joint's element and spec, checked to be a one-coordinate rotational joint
/// whose frames are offset frames it owns, each directly on a body.
fn hinge<'a>(document: &OsimDocument, spec: &'a ModelSpec, joint: &str) -> Result<(ElementId, &'a JointSpec), SwapError> {
    let file = document.xml.file().to_path_buf();
    let Some(joint_spec) = spec.joints.iter().find(|j| j.name == joint) else {
        let known = spec.joints.iter().map(|j| j.name.as_str()).collect::<Vec<_>>().join(", ");
        return Err(SwapError::UnknownJoint { file, joint: joint.into(), known });
    };
    let element = document.resolve(&format!("/jointset/{joint}"))?;
    let unsupported = |problem: String| SwapError::Unsupported { file: file.clone(), line: document.xml.line(element), joint: joint.into(), problem };
    let rotational = joint_spec.coordinates.len() == 1 && joint_spec.coordinates[0].motion_type == MotionType::Rotational;
    if !rotational {
        return Err(unsupported(format!("has {} coordinate(s); a knee swap needs a joint with one rotational coordinate", joint_spec.coordinates.len())));
    }
    let name = &joint_spec.coordinates[0].name;
    if let Some(axis) = joint_spec.spatial_transform.iter().find(|a| a.coordinates.iter().any(|c| c != name)) {
        return Err(unsupported(format!("{} depends on {:?}, not only on {name}", axis.name, axis.coordinates)));
    }
    for socket in ["socket_parent_frame", "socket_child_frame"] {
        let frame = owned_frame(document, element, socket).ok_or_else(|| unsupported(format!("<{socket}> is not a PhysicalOffsetFrame the joint owns")))?;
        let chain = if socket == "socket_parent_frame" { &joint_spec.parent } else { &joint_spec.child };
        if chain.offsets.len() != 1 {
            let problem = format!("<{socket}> frame {:?} is not attached directly to a body", document.xml.name(frame).unwrap_or_default());
            return Err(unsupported(problem));
        }
    }
    Ok((element, joint_spec))
}

/// The `PhysicalOffsetFrame` in the joint's `<frames>` that its socket `socket` names.
fn owned_frame(document: &OsimDocument, joint: ElementId, socket: &str) -> Option<ElementId> {
    let xml = &document.xml;
    let name = xml.text(xml.child(joint, socket)?)?.trim().to_string();
    let frames = xml.child(joint, "frames")?;
    xml.children(frames).iter().copied().find(|&f| xml.tag(f) == "PhysicalOffsetFrame" && xml.name(f) == Some(name.as_str()))
}

/// X_PC: the child body in the parent body with the joint's coordinate at `angle` and every other
/// coordinate at its default.
fn child_in_parent(multibody: &Multibody, joint: &JointSpec, coordinate: &str, angle: f64) -> Result<Transform, SwapError> {
    let missing = |what: &str| MechanicsError::Invalid { file: multibody.file.clone(), component: joint.name.clone(), problem: format!("{what} not in the compiled model") };
    let index = multibody.coordinate_index(coordinate).ok_or_else(|| missing("coordinate"))?;
    let parent = multibody.body_index(&joint.parent.body).ok_or_else(|| missing("parent body"))?;
    let child = multibody.body_index(&joint.child.body).ok_or_else(|| missing("child body"))?;
    let mut q = multibody.default_pose();
    q[index] = angle;
    let mut kinematics = multibody.kinematics();
    multibody.realize(&q, &mut kinematics);
    Ok(kinematics.bodies[parent].inverse().compose(&kinematics.bodies[child]))
}

/// A right-handed rotation whose Z column is `direction` and whose X column is the parent's X
/// made perpendicular to it (its Y when the axis lies along X).
fn frame_along(direction: &Vec3) -> Mat3 {
    let reference = if direction.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
    let x = (reference - direction * direction.dot(&reference)).normalize();
    let y = direction.cross(&x);
    Mat3::from_columns(&[x, y, *direction])
}

fn offset_of(transform: &Transform) -> Offset {
    Offset { translation: transform.translation.into(), orientation: body_fixed_xyz_angles(&transform.rotation) }
}

/// Renames the joint to `PinJoint`, removes its `SpatialTransform` and writes the two offsets.
fn rewrite_joint(document: &mut OsimDocument, joint: ElementId, parent: &Offset, child: &Offset) -> Result<(), SwapError> {
    let frames = [("socket_parent_frame", parent), ("socket_child_frame", child)];
    let mut values = Vec::new();
    for (socket, offset) in frames {
        let reader = ComponentReader::new(document, joint);
        let frame = owned_frame(document, joint, socket).ok_or_else(|| reader.missing(socket))?;
        let reader = reader.at(frame);
        for (property, numbers) in [("translation", offset.translation), ("orientation", offset.orientation)] {
            let element = reader.child(property).ok_or_else(|| reader.missing(property))?;
            values.push((element, format_numbers(&numbers)));
        }
    }
    let xml = &mut document.xml;
    if xml.tag(joint) != "PinJoint" {
        xml.rename_element(joint, "PinJoint")?;
    }
    if let Some(transform) = xml.child(joint, "SpatialTransform") {
        xml.remove_element(transform)?;
    }
    for (element, text) in values {
        xml.set_text(element, &text)?;
    }
    Ok(())
}

/// A bound (m) on the displacement of any point within 1 m of the child origin between two
/// child poses: ‖Δt‖ + ‖ΔR‖_F.
fn pose_distance(a: &Transform, b: &Transform) -> f64 {
    let rotation = (a.rotation - b.rotation).norm();
    (a.translation - b.translation).norm() + rotation
}
