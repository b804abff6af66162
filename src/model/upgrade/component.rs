//! Each component's own conversion, by class: body and coordinate names into socket paths
//! (markers, path points, constraints, springs, prescribed forces, contact geometry),
//! `isDisabled` into `appliesForce`/`isEnforced`/`enabled`, display properties into an
//! `Appearance` (paths, wrap objects, contact geometry), 2.x muscle paths, controls left at a
//! muscle's defaults, a coordinate's `motion_type` dropped, a `TransformAxis`'s function written
//! as the named object OpenSim 4 writes (`<LinearFunction name="function">`), `NaturalCubicSpline`
//! written as the `SimmSpline` OpenSim reads it as, and display objects (`VisibleObject`) that
//! have no place in OpenSim 4 dropped. Other properties OpenSim 4 no longer has (a 2.x Thelen
//! muscle's `damping`, a coordinate's `initial_value`) are kept as written; OpenSim 4 ignores them.

use crate::io::xml::TreeElement;
use crate::model::error::ModelError;
use crate::model::force::{is_muscle_class, DROPPED_MUSCLE_CONTROLS};
use crate::model::spec::is_force_class;

use super::Upgrade;

/// Body-name properties and the sockets OpenSim 4 makes of them, by class.
const BODY_SOCKETS: [(&str, &[(&str, &str)]); 10] = [
    ("Marker", &[("body", "socket_parent_frame")]),
    ("PathPoint", &[("body", "socket_parent_frame")]),
    ("ConditionalPathPoint", &[("body", "socket_parent_frame")]),
    ("MovingPathPoint", &[("body", "socket_parent_frame")]),
    ("PointConstraint", &[("body_1", "socket_body_1"), ("body_2", "socket_body_2")]),
    ("ConstantDistanceConstraint", &[("body_1", "socket_body_1"), ("body_2", "socket_body_2")]),
    ("PointOnLineConstraint", &[("line_body", "socket_line_body"), ("follower_body", "socket_follower_body")]),
    ("RollingOnSurfaceConstraint", &[("rolling_body", "socket_rolling_body"), ("surface_body", "socket_surface_body")]),
    ("PointToPointSpring", &[("body1", "socket_body1"), ("body2", "socket_body2")]),
    ("PrescribedForce", &[("body", "socket_frame")]),
];

/// Classes whose two bodies with locations and orientations become two frames.
const TWO_FRAME_LINKERS: [&str; 4] = ["WeldConstraint", "BushingForce", "FunctionBasedBushingForce", "ExpressionBasedBushingForce"];

impl Upgrade<'_> {
    /// `element`'s own conversion (its children are converted by the caller).
    pub(super) fn component(&self, element: &mut TreeElement) -> Result<(), ModelError> {
        let class = element.tag.clone();
        if let Some((_, sockets)) = BODY_SOCKETS.iter().find(|(c, _)| *c == class) {
            for (property, socket) in *sockets {
                if let Some(body) = element.take(property) {
                    element.push(TreeElement::leaf(socket, &Self::body_path(body.text.trim())));
                }
            }
        }
        if class == "NaturalCubicSpline" {
            element.tag = "SimmSpline".into();
        }
        match class.as_str() {
            "ConditionalPathPoint" => self.coordinate_sockets(element, &[("coordinate", "socket_coordinate")]),
            "MovingPathPoint" => self.moving_path_point(element),
            "GeometryPath" => geometry_path(element),
            "Coordinate" => drop(element.take("motion_type")),
            "TransformAxis" => named_transform_function(element),
            c if TWO_FRAME_LINKERS.contains(&c) => self.two_frame_links(element)?,
            c if c.starts_with("Wrap") && !c.ends_with("Set") => wrap_object(element),
            c if c.starts_with("Contact") && !c.ends_with("Set") => contact_geometry(element),
            _ => {}
        }
        element.take("VisibleObject");
        if is_muscle_class(&class) {
            self.muscle(element);
        }
        let enabled = if class.ends_with("Constraint") {
            Some("isEnforced")
        } else if class.ends_with("Controller") || class.ends_with("Probe") {
            Some("enabled")
        } else if is_force_class(&class) {
            Some("appliesForce")
        } else {
            None
        };
        if let Some(property) = enabled {
            negated_is_disabled(element, property);
        }
        Ok(())
    }

    /// Coordinate-name properties into sockets with the coordinate's path.
    fn coordinate_sockets(&self, element: &mut TreeElement, sockets: &[(&str, &str)]) {
        for (property, socket) in sockets {
            let Some(coordinate) = element.take(property) else { continue };
            let name = coordinate.text.trim();
            if !name.is_empty() {
                element.push(TreeElement::leaf(socket, &self.coordinate_path(name)));
            }
        }
    }

    /// `MovingPathPoint` (< 30000: `XAttachment` … as `x_location` …; < 30505: coordinates as
    /// sockets; its 3.x `location`, which its functions override, is no property in OpenSim 4).
    fn moving_path_point(&self, element: &mut TreeElement) {
        element.take("location");
        if self.version < 30000 {
            for (old, new) in [("XAttachment", "x_location"), ("YAttachment", "y_location"), ("ZAttachment", "z_location")] {
                if let Some(attachment) = element.child_mut(old) {
                    attachment.tag = new.into();
                }
            }
        }
        self.coordinate_sockets(element, &[("x_coordinate", "socket_x_coordinate"), ("y_coordinate", "socket_y_coordinate"), ("z_coordinate", "socket_z_coordinate")]);
    }

    /// `Muscle::updateFromXMLNode`: a 2.x (≤ 20301) muscle's `MusclePointSet` and
    /// `MuscleWrapSet` into a `GeometryPath`, `pennation_angle` renamed; (< 30513) a
    /// `min_control` of 0 and a `max_control` of 1 dropped so the muscle's own defaults hold;
    /// (< 30516) the path's default color.
    fn muscle(&self, muscle: &mut TreeElement) {
        if self.version <= 20301 {
            if muscle.child("GeometryPath").is_none() {
                let mut path = TreeElement::new("GeometryPath");
                ["MusclePointSet", "MuscleWrapSet"].iter().filter_map(|set| muscle.take(set)).for_each(|set| path.push(set));
                muscle.push(path);
            }
            if let Some(path) = muscle.child_mut("GeometryPath") {
                for (old, new) in [("MusclePointSet", "PathPointSet"), ("MuscleWrapSet", "PathWrapSet")] {
                    if let Some(set) = path.child_mut(old) {
                        set.tag = new.into();
                    }
                }
            }
            if let Some(pennation) = muscle.child_mut("pennation_angle") {
                pennation.tag = "pennation_angle_at_optimal".into();
            }
        }
        for (property, default) in DROPPED_MUSCLE_CONTROLS {
            if muscle.child_text(property).and_then(|t| t.parse::<f64>().ok()) == Some(default) {
                muscle.take(property);
            }
        }
        if let Some(path) = muscle.child_mut("GeometryPath") {
            if path.child("default_color").is_none() && path.child("Appearance").is_none() {
                path.push(TreeElement::leaf("default_color", ".8 .1 .1"));
            }
        }
    }
}

/// `isDisabled` renamed to `property` with the opposite value.
fn negated_is_disabled(element: &mut TreeElement, property: &str) {
    if let Some(flag) = element.child_mut("isDisabled") {
        let disabled = flag.text.trim().eq_ignore_ascii_case("true");
        flag.tag = property.into();
        flag.text = (!disabled).to_string();
    }
}

/// `GeometryPath::updateFromXMLNode` (< 30516): an `Appearance` with the path's
/// `default_color` and, for a hidden `VisibleObject`, `visible` false.
fn geometry_path(path: &mut TreeElement) {
    if path.child("Appearance").is_some() {
        return;
    }
    let mut appearance = TreeElement::new("Appearance");
    if let Some(visible) = path.take("VisibleObject") {
        if visible.child_text("display_preference") == Some("0") {
            appearance.push(TreeElement::leaf("visible", "false"));
        }
    }
    if let Some(color) = path.take("default_color") {
        appearance.push(TreeElement::leaf("color", color.text.trim()));
    }
    path.push(appearance);
}

/// `WrapObject::updateFromXMLNode` (< 30515): `color`, `display_preference` and the
/// `VisibleObject` into an `Appearance` (cyan, half opaque, as OpenSim's wrap objects are), added
/// only when they said something.
fn wrap_object(wrap: &mut TreeElement) {
    let (mut color, mut representation, mut visible, mut modified) = ("0 1 1".to_string(), "3".to_string(), None, false);
    if let Some(c) = wrap.take("color") {
        color = c.text.trim().to_string();
        modified = true;
    }
    let preference = |element: &TreeElement| element.text.trim().parse::<i32>().ok();
    match wrap.take("display_preference").as_ref().and_then(preference) {
        Some(0) => (visible, modified) = (Some("false"), true),
        Some(p) if p < 4 => (representation, modified) = (p.to_string(), true),
        _ => {}
    }
    match wrap.take("VisibleObject").as_ref().and_then(|object| object.child("display_preference")).and_then(preference) {
        Some(0) => (visible, modified) = (Some("false"), true),
        Some(p) if p < 4 && representation == "3" => (representation, modified) = (p.to_string(), true),
        _ => {}
    }
    if !modified {
        return;
    }
    let mut appearance = TreeElement::new("Appearance");
    appearance.push(TreeElement::leaf("color", &color));
    appearance.push(TreeElement::leaf("opacity", "0.5"));
    let mut surface = TreeElement::new("SurfaceProperties");
    surface.push(TreeElement::leaf("representation", &representation));
    appearance.push(surface);
    if let Some(v) = visible {
        appearance.push(TreeElement::leaf("visible", v));
    }
    wrap.push(appearance);
}

/// `ContactGeometry::updateFromXMLNode`: `body_name` as socket `frame` (< 30505); `color` and
/// `display_preference` into an `Appearance` (< 30507).
fn contact_geometry(geometry: &mut TreeElement) {
    if let Some(body) = geometry.take("body_name") {
        geometry.push(TreeElement::leaf("socket_frame", &Upgrade::body_path(body.text.trim())));
    }
    let mut appearance = TreeElement::new("Appearance");
    let color = geometry.take("color");
    appearance.push(TreeElement::leaf("color", color.as_ref().map_or("0 1 1", |c| c.text.trim())));
    let preference = geometry.take("display_preference");
    match preference.as_ref().map(|p| p.text.trim()) {
        Some("0") => appearance.push(TreeElement::leaf("visible", "false")),
        Some(p) => {
            let mut surface = TreeElement::new("SurfaceProperties");
            surface.push(TreeElement::leaf("representation", if p == "4" { "3" } else { p }));
            appearance.push(surface);
        }
        None => {}
    }
    if color.is_some() || preference.is_some() {
        geometry.push(appearance);
    }
}

/// A `TransformAxis`'s function written the 3.x way, `<function><LinearFunction>…</LinearFunction>
/// </function>`, as OpenSim 4 writes it: `<LinearFunction name="function">…` (its other function
/// properties — a coupler's, a moving path point's, a `MultiplierFunction`'s — it still writes
/// the 3.x way).
fn named_transform_function(axis: &mut TreeElement) {
    let Some(wrapper) = axis.elements_mut().find(|e| e.tag == "function" && e.name().is_none()) else { return };
    if wrapper.elements().count() == 1 {
        let mut function = wrapper.take_all().remove(0);
        function.set_attribute("name", "function");
        *wrapper = function;
    }
}
