//! The geometric part of OpenSim's `Model::scale`: every component's `scale()` (frames, joint
//! translation functions, markers, path points, wrap objects, attached geometry, coupler
//! constraints), planned as document edits. Masses, inertias and muscle lengths follow in
//! `inertia.rs` and `path_lengths.rs`.

use super::edits::{numbers_edit, scaled_function_edit, scaled_number_edit, scaled_vec3_edit, Edit};
use super::error::ScaleError;
use super::scale_set::ScaleSet;
use crate::io::osim::OsimDocument;
use crate::io::xml::ElementId;
use crate::mechanics::{body_fixed_xyz, Vec3};
use crate::model::{opensim_path, ComponentReader, FrameIndex, ModelSpec, GROUND};

/// Joint classes whose own `scale()` changes properties osim-tune does not scale yet.
const UNSUPPORTED_JOINTS: [&str; 1] = ["ConstantCurvatureJoint"];

/// Plans the geometric scaling edits of a 4.x model `document` for `scale_set`.
pub fn geometry_edits(document: &OsimDocument, scale_set: &ScaleSet) -> Result<Vec<Edit>, ScaleError> {
    let scaler = GeometryScaler { document, frames: ModelSpec::frame_index(document)?, scale_set };
    let mut edits = Vec::new();
    for id in document.xml.ids() {
        scaler.component(ComponentReader::new(document, id), &mut edits)?;
    }
    Ok(edits)
}

struct GeometryScaler<'a> {
    document: &'a OsimDocument,
    frames: FrameIndex,
    scale_set: &'a ScaleSet,
}

impl GeometryScaler<'_> {
    fn component(&self, c: ComponentReader, edits: &mut Vec<Edit>) -> Result<(), ScaleError> {
        let mut push = |edit: Option<Edit>| edits.extend(edit);
        match c.class() {
            "Body" => {
                if let Some(factors) = self.scale_set.factors(&c.name()) {
                    push(scaled_vec3_edit(c, "mass_center", factors)?);
                }
            }
            "PhysicalOffsetFrame" => {
                if let Some(factors) = self.socket_factors(c, "socket_parent")? {
                    push(scaled_vec3_edit(c, "translation", factors)?);
                }
            }
            "Marker" | "PathPoint" | "ConditionalPathPoint" | "Station" => {
                if let Some(factors) = self.socket_factors(c, "socket_parent_frame")? {
                    push(scaled_vec3_edit(c, "location", factors)?);
                }
            }
            "MovingPathPoint" => self.moving_path_point(c, edits)?,
            "CustomJoint" => self.spatial_transform(c, edits)?,
            "EllipsoidJoint" | "ScapulothoracicJoint" => self.ellipsoid_joint(c, edits)?,
            "WrapCylinder" | "WrapSphere" | "WrapEllipsoid" | "WrapTorus" => self.wrap_object(c, edits)?,
            "CoordinateCouplerConstraint" => self.coupler(c, edits)?,
            "attached_geometry" => self.attached_geometry(c, edits)?,
            class if UNSUPPORTED_JOINTS.contains(&class) => return Err(self.unsupported(c, "scaling this joint class is not supported")),
            _ => {}
        }
        Ok(())
    }

    /// Factors of the base body of the frame a socket property names.
    fn socket_factors(&self, c: ComponentReader, socket: &str) -> Result<Option<[f64; 3]>, ScaleError> {
        let chain = self.frames.resolve(c, &c.text(socket)?, socket)?;
        Ok(self.scale_set.factors(&chain.body))
    }

    /// Factors of the base body of frame element `frame` (ground, a body or an offset frame).
    fn frame_factors(&self, frame: ComponentReader) -> Result<Option<[f64; 3]>, ScaleError> {
        match frame.class() {
            "Ground" => Ok(self.scale_set.factors(GROUND)),
            "Body" => Ok(self.scale_set.factors(&frame.name())),
            _ => {
                let chain = self.frames.resolve(frame, &opensim_path(self.document, frame.element), "frame")?;
                Ok(self.scale_set.factors(&chain.body))
            }
        }
    }

    /// The nearest enclosing frame element (wrap objects and geometry belong to one).
    fn owning_frame<'a>(&self, c: ComponentReader<'a>) -> Option<ComponentReader<'a>> {
        let xml = &self.document.xml;
        std::iter::successors(xml.parent(c.element), |&e| xml.parent(e))
            .find(|&e| matches!(xml.tag(e), "Body" | "Ground" | "PhysicalOffsetFrame"))
            .map(|e| c.at(e))
    }

    /// Each function of a `MovingPathPoint` whose coordinate socket is set.
    fn moving_path_point(&self, c: ComponentReader, edits: &mut Vec<Edit>) -> Result<(), ScaleError> {
        let Some(factors) = self.socket_factors(c, "socket_parent_frame")? else { return Ok(()) };
        for (axis, factor) in ["x", "y", "z"].into_iter().zip(factors) {
            let has_coordinate = c.optional_text(&format!("socket_{axis}_coordinate")).is_some_and(|s| !s.is_empty());
            if let Some(function) = c.object_property(&format!("{axis}_location")).filter(|_| has_coordinate) {
                edits.extend(scaled_function_edit(self.document, function.element, factor)?);
            }
        }
        Ok(())
    }

    /// `SpatialTransform::scale`: translation functions times |axis|·factors, except a
    /// `LinearFunction` with coefficients 1, 0 (the transform axis is a degree of freedom).
    fn spatial_transform(&self, joint: ComponentReader, edits: &mut Vec<Edit>) -> Result<(), ScaleError> {
        let Some(factors) = self.socket_factors(joint, "socket_parent_frame")? else { return Ok(()) };
        let Some(transform) = joint.child("SpatialTransform") else { return Ok(()) };
        for name in ["translation1", "translation2", "translation3"] {
            let Some(axis) = self.named_child(transform, name) else { continue };
            let axis = joint.at(axis);
            let Some(function) = self.transform_function(axis) else { continue };
            if is_identity_linear(joint.at(function))? {
                continue;
            }
            let direction = axis.vec3("axis")?;
            let factor = direction.iter().zip(factors).map(|(d, f)| d.abs() * f).sum();
            edits.extend(scaled_function_edit(self.document, function, factor)?);
        }
        Ok(())
    }

    /// `EllipsoidJoint::extendScale`: the radii times the parent frame's factors;
    /// `ScapulothoracicJoint::extendScale`: the thoracic radii too and then, when the child frame
    /// scales, the winging axis origin times its x and y factors.
    fn ellipsoid_joint(&self, joint: ComponentReader, edits: &mut Vec<Edit>) -> Result<(), ScaleError> {
        let Some(parent) = self.socket_factors(joint, "socket_parent_frame")? else { return Ok(()) };
        if joint.class() == "EllipsoidJoint" {
            edits.extend(scaled_vec3_edit(joint, "radii_x_y_z", parent)?);
            return Ok(());
        }
        edits.extend(scaled_vec3_edit(joint, "thoracic_ellipsoid_radii_x_y_z", parent)?);
        let Some(child) = self.socket_factors(joint, "socket_child_frame")? else { return Ok(()) };
        if joint.child("scapula_winging_axis_origin").is_some() {
            let origin = joint.numbers("scapula_winging_axis_origin", Some(2))?;
            edits.extend(numbers_edit(joint, "scapula_winging_axis_origin", &[origin[0] * child[0], origin[1] * child[1]])?);
        }
        Ok(())
    }

    fn named_child(&self, parent: ElementId, name: &str) -> Option<ElementId> {
        self.document.xml.children(parent).iter().copied().find(|&c| self.document.xml.name(c) == Some(name))
    }

    /// The function element of a `TransformAxis` (its one child that is not `coordinates`/`axis`).
    fn transform_function(&self, axis: ComponentReader) -> Option<ElementId> {
        let xml = &self.document.xml;
        xml.children(axis.element).iter().copied().find(|&c| !matches!(xml.tag(c), "coordinates" | "axis"))
    }

    /// `WrapObject::scale` and the class's own: translation, then the shape's dimensions. An
    /// absent `translation` or `xyz_body_rotation` (OpenSim 4.6 omits them at their default,
    /// zero) stays as it is.
    fn wrap_object(&self, c: ComponentReader, edits: &mut Vec<Edit>) -> Result<(), ScaleError> {
        let Some(frame) = self.owning_frame(c) else { return Ok(()) };
        let Some(factors) = self.frame_factors(frame)? else { return Ok(()) };
        if c.child("translation").is_some() {
            edits.extend(scaled_vec3_edit(c, "translation", factors)?);
        }
        let rotation = body_fixed_xyz(if c.child("xyz_body_rotation").is_some() { c.vec3("xyz_body_rotation")? } else { [0.0; 3] });
        let scaled_axis = |k: usize| rotation.column(k).component_mul(&Vec3::from(factors)).norm();
        match c.class() {
            "WrapCylinder" => {
                edits.extend(scaled_number_edit(c, "radius", (scaled_axis(0) + scaled_axis(1)) * 0.5)?);
                edits.extend(scaled_number_edit(c, "length", scaled_axis(2))?);
            }
            "WrapSphere" => edits.extend(scaled_number_edit(c, "radius", factors.iter().sum::<f64>() / 3.)?),
            "WrapEllipsoid" => {
                let old = c.vec3("dimensions")?;
                edits.extend(super::edits::numbers_edit(c, "dimensions", &[0, 1, 2].map(|k| old[k] * scaled_axis(k)))?);
            }
            _ => {
                let average = (scaled_axis(0) + scaled_axis(1)) * 0.5;
                edits.extend(scaled_number_edit(c, "inner_radius", average)?);
                edits.extend(scaled_number_edit(c, "outer_radius", average)?);
            }
        }
        Ok(())
    }

    /// `CoordinateCouplerConstraint::scale`: a translational dependent coordinate's
    /// `scale_factor` times the (uniform) factor of its joint's parent body.
    fn coupler(&self, c: ComponentReader, edits: &mut Vec<Edit>) -> Result<(), ScaleError> {
        let dependent = c.text("dependent_coordinate_name")?;
        let xml = &self.document.xml;
        let coordinate = xml.ids().find(|&e| xml.tag(e) == "Coordinate" && xml.name(e) == Some(dependent.as_str()));
        let Some(coordinate) = coordinate else { return Err(c.unknown("dependent coordinate", &dependent).into()) };
        let joint = std::iter::successors(xml.parent(coordinate), |&e| xml.parent(e)).find(|&e| xml.child(e, "socket_parent_frame").is_some());
        let Some(joint) = joint.map(|j| c.at(j)) else { return Ok(()) };
        if !is_translational(joint, c.at(coordinate), &self.frames)? {
            return Ok(());
        }
        let Some(factors) = self.socket_factors(joint, "socket_parent_frame")? else { return Ok(()) };
        if factors[0] != factors[1] || factors[0] != factors[2] {
            return Err(self.unsupported(c, "non-uniform scaling of a coupler constraint (OpenSim refuses it too)"));
        }
        edits.extend(scaled_number_edit(c, "scale_factor", factors[0])?);
        Ok(())
    }

    /// `Frame::scaleAttachedGeometry`: each geometry's `scale_factors` times the frame's factors.
    fn attached_geometry(&self, list: ComponentReader, edits: &mut Vec<Edit>) -> Result<(), ScaleError> {
        let Some(frame) = self.document.xml.parent(list.element).map(|f| list.at(f)) else { return Ok(()) };
        let Some(factors) = self.frame_factors(frame)? else { return Ok(()) };
        for &geometry in self.document.xml.children(list.element) {
            let geometry = list.at(geometry);
            if geometry.child("scale_factors").is_some() {
                edits.extend(scaled_vec3_edit(geometry, "scale_factors", factors)?);
            }
        }
        Ok(())
    }

    fn unsupported(&self, c: ComponentReader, problem: &str) -> ScaleError {
        ScaleError::Unsupported { file: self.document.xml.file().into(), line: c.line(), component: c.path(), problem: problem.into() }
    }
}

/// Whether `function` is a `LinearFunction` with coefficients exactly 1 and 0.
fn is_identity_linear(function: ComponentReader) -> Result<bool, ScaleError> {
    Ok(function.class() == "LinearFunction" && function.numbers("coefficients", Some(2))? == [1.0, 0.0])
}

/// Whether `coordinate` of `joint` is translational (OpenSim's motion-type rule, as the model
/// view applies it).
fn is_translational(joint: ComponentReader, coordinate: ComponentReader, frames: &FrameIndex) -> Result<bool, ScaleError> {
    let spec = crate::model::JointSpec::read_v4(joint, frames)?;
    let name = coordinate.name();
    Ok(spec.coordinates.iter().any(|c| c.name == name && c.motion_type == crate::model::MotionType::Translational))
}
