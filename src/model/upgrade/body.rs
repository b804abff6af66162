//! Bodies: `Body::updateFromXMLNode` (< 30500: the six `inertia_xx…` into one `inertia`) and
//! `PhysicalFrame::updateFromXMLNode` (< 30502: the `VisibleObject`'s display geometry into
//! `attached_geometry` meshes, on an offset frame where it was transformed).

use nalgebra::Vector3;

use crate::io::xml::TreeElement;
use crate::model::error::ModelError;
use crate::model::orientation::{body_fixed_xyz, body_fixed_xyz_angles};

use super::values::stream;
use super::Upgrade;

/// Inertia components of a 3.x body in OpenSim 4's `inertia` order, and their defaults.
const INERTIA: [(&str, f64); 6] = [("inertia_xx", 1.0), ("inertia_yy", 1.0), ("inertia_zz", 1.0), ("inertia_xy", 0.0), ("inertia_xz", 0.0), ("inertia_yz", 0.0)];

impl Upgrade<'_> {
    /// The 3.x `ground` body as OpenSim 4's `<Ground>`: its geometry and wrap objects.
    pub(super) fn ground(&self, mut body: TreeElement) -> Result<TreeElement, ModelError> {
        let mut ground = TreeElement::named("Ground", "ground");
        ground.line = body.line;
        if let Some(visible) = body.take("VisibleObject") {
            ground.push(visible);
        }
        if let Some(wraps) = body.take("WrapObjectSet") {
            ground.push(wraps);
        }
        self.display_geometry(&mut ground)?;
        Ok(ground)
    }

    pub(super) fn body(&self, mut body: TreeElement) -> Result<TreeElement, ModelError> {
        let mut inertia = [0.0; 6];
        for (value, (property, default)) in inertia.iter_mut().zip(INERTIA) {
            *value = self.values.numbers(&body, property, [default])?[0];
            body.take(property);
        }
        body.push(TreeElement::leaf("inertia", &stream(&inertia)));
        self.display_geometry(&mut body)?;
        Ok(body)
    }

    /// The frame's `VisibleObject` as `attached_geometry`: a `Mesh` `<frame>_geom_<n>` per
    /// display geometry, its scale factors times the object's, its color, opacity and
    /// visibility in an `Appearance`; a geometry whose transform (or the object's) is not the
    /// identity hangs on a new offset frame `<frame>_geom_frame_<n>` in the frame's `components`.
    fn display_geometry(&self, frame: &mut TreeElement) -> Result<(), ModelError> {
        let Some(visible) = frame.take("VisibleObject") else { return Ok(()) };
        let name = frame.name().unwrap_or_default().to_string();
        let outer_scale = self.values.numbers(&visible, "scale_factors", [1.0; 3])?;
        let outer = self.values.numbers(&visible, "transform", [0.0; 6])?;
        let mut attached = TreeElement::new("attached_geometry");
        if self.version < 20101 {
            let files = visible.child_text("geometry_files").unwrap_or_default();
            for (index, file) in files.split_whitespace().enumerate() {
                attached.push(mesh(&format!("{name}_geom_{index}"), file, &outer_scale, None));
            }
            frame.push(attached);
            return Ok(());
        }
        let Some(objects) = visible.child("GeometrySet").and_then(|set| set.child("objects")) else { return Ok(()) };
        let mut offset_frames = Vec::new();
        for (index, display) in objects.elements().filter(|e| e.tag == "DisplayGeometry").enumerate() {
            let number = index + 1;
            let inner = self.values.numbers(display, "transform", [0.0; 6])?;
            let local_scale = self.values.numbers(display, "scale_factors", [1.0; 3])?;
            let scale: Vec<f64> = local_scale.iter().zip(outer_scale).map(|(l, o)| l * o).collect();
            let file = display.child_text("geometry_file").unwrap_or_default();
            let geometry = mesh(&format!("{name}_geom_{number}"), file, &scale, Some(display));
            if norm(&inner) < f64::EPSILON && norm(&outer) < f64::EPSILON {
                attached.push(geometry);
            } else {
                offset_frames.push(geometry_frame(&format!("{name}_geom_frame_{number}"), &outer, &inner, geometry));
            }
        }
        frame.push(attached);
        if !offset_frames.is_empty() {
            if frame.child("components").is_none() {
                frame.push(TreeElement::new("components"));
            }
            let components = frame.child_mut("components").expect("just added");
            offset_frames.into_iter().for_each(|f| components.push(f));
        }
        Ok(())
    }
}

/// A `Mesh` on its owner frame (`socket_frame` `..`), with the display geometry's appearance.
fn mesh(name: &str, file: &str, scale: &[f64], display: Option<&TreeElement>) -> TreeElement {
    let mut mesh = TreeElement::named("Mesh", name);
    mesh.push(TreeElement::leaf("socket_frame", ".."));
    mesh.push(TreeElement::leaf("scale_factors", &stream(scale)));
    let mut appearance = TreeElement::new("Appearance");
    for property in ["color", "opacity"] {
        if let Some(value) = display.and_then(|d| d.child_text(property)) {
            appearance.push(TreeElement::leaf(property, value));
        }
    }
    if display.and_then(|d| d.child_text("display_preference")) == Some("0") {
        appearance.push(TreeElement::leaf("visible", "false"));
    }
    if display.is_some() {
        mesh.push(appearance);
    }
    mesh.push(TreeElement::leaf("mesh_file", file));
    mesh
}

/// The offset frame carrying a transformed geometry: the object's transform composed with the
/// geometry's (each 3 body-fixed X-Y-Z angles then 3 translations).
fn geometry_frame(name: &str, outer: &[f64; 6], inner: &[f64; 6], geometry: TreeElement) -> TreeElement {
    let rotation = |t: &[f64; 6]| body_fixed_xyz([t[0], t[1], t[2]]);
    let (outer_rotation, inner_rotation) = (rotation(outer), rotation(inner));
    let translation = outer_rotation * Vector3::new(inner[3], inner[4], inner[5]) + Vector3::new(outer[3], outer[4], outer[5]);
    let orientation = body_fixed_xyz_angles(&(outer_rotation * inner_rotation));
    let mut frame = TreeElement::named("PhysicalOffsetFrame", name);
    frame.push(TreeElement::leaf("socket_parent", ".."));
    frame.push(TreeElement::leaf("translation", &stream(translation.as_slice())));
    frame.push(TreeElement::leaf("orientation", &stream(&orientation)));
    let mut attached = TreeElement::new("attached_geometry");
    attached.push(geometry);
    frame.push(attached);
    frame
}

fn norm(values: &[f64]) -> f64 {
    values.iter().map(|v| v * v).sum::<f64>().sqrt()
}
