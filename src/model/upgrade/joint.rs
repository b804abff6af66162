//! Joints: out of their child body into the `JointSet` (`Model`, < 30501), the parent and child
//! locations and orientations as offset frames `<parent>_offset` and `<child>_offset` (`Joint`,
//! < 30505), the `CoordinateSet` as the `coordinates` list (< 30507), `reverse` as swapped
//! frames (< 30514); and the offset frames of two-frame links (`TwoFrameLinker`, < 30505).

use crate::io::xml::TreeElement;
use crate::model::error::ModelError;

use super::values::stream;
use super::Upgrade;

impl Upgrade<'_> {
    /// The joint `joint` that held `child` in its 3.x `<Joint>`, in OpenSim 4's form.
    pub(super) fn joint(&self, mut joint: TreeElement, child: &str) -> Result<TreeElement, ModelError> {
        if joint.name().is_none_or(str::is_empty) {
            let name = joint.tag.to_lowercase();
            joint.set_attribute("name", &name);
        }
        let parent = joint.take("parent_body").map(|p| p.text.trim().to_string()).unwrap_or_else(|| "ground".into());
        let (translation, orientation) = self.take_offset(&mut joint, "location_in_parent", "orientation_in_parent")?;
        let parent_offset = offset_frame(&parent, translation, orientation);
        let (translation, orientation) = self.take_offset(&mut joint, "location", "orientation")?;
        let child_offset = offset_frame(child, translation, orientation);
        let reverse = joint.take("reverse").is_some_and(|r| r.text.trim() == "true");
        let (parent_socket, child_socket) = (format!("{parent}_offset"), format!("{child}_offset"));
        let (parent_socket, child_socket) = if reverse { (child_socket, parent_socket) } else { (parent_socket, child_socket) };
        let mut coordinates = TreeElement::new("coordinates");
        if let Some(mut set) = joint.take("CoordinateSet") {
            set.take("objects").into_iter().flat_map(|mut objects| objects.take_all()).for_each(|c| coordinates.push(c));
        }
        let mut frames = TreeElement::new("frames");
        frames.push(parent_offset);
        frames.push(child_offset);
        let mut converted = TreeElement { tag: joint.tag.clone(), attributes: joint.attributes.clone(), line: joint.line, ..TreeElement::new("") };
        converted.push(TreeElement::leaf("socket_parent_frame", &parent_socket));
        converted.push(TreeElement::leaf("socket_child_frame", &child_socket));
        if !coordinates.children.is_empty() {
            converted.push(coordinates);
        }
        converted.push(frames);
        converted.children.extend(joint.children);
        Ok(converted)
    }

    /// The component's `location` and `orientation` properties (given names; 0 when absent),
    /// removed from it.
    fn take_offset(&self, component: &mut TreeElement, location: &str, orientation: &str) -> Result<([f64; 3], [f64; 3]), ModelError> {
        let translation = self.values.numbers(component, location, [0.0; 3])?;
        let rotation = self.values.numbers(component, orientation, [0.0; 3])?;
        component.take(location);
        component.take(orientation);
        Ok((translation, rotation))
    }

    /// `TwoFrameLinker::updateFromXMLNode` (< 30505; `WeldConstraint`, bushing forces): each of
    /// `body_1`, `body_2` becomes socket `frame1`, `frame2` — the body itself, or a new offset
    /// frame `<body>_offset` when its location or orientation is not zero.
    pub(super) fn two_frame_links(&self, link: &mut TreeElement) -> Result<(), ModelError> {
        let mut frames = TreeElement::new("frames");
        let mut sockets = Vec::new();
        for (index, socket) in [(1, "socket_frame1"), (2, "socket_frame2")] {
            let body = link.take(&format!("body_{index}")).map(|b| b.text.trim().to_string()).unwrap_or_default();
            let (translation, rotation) = self.take_offset(link, &format!("location_body_{index}"), &format!("orientation_body_{index}"))?;
            if translation.iter().chain(&rotation).any(|&v| v != 0.0) {
                frames.push(offset_frame(&body, translation, rotation));
                sockets.push(TreeElement::leaf(socket, &format!("{body}_offset")));
            } else {
                sockets.push(TreeElement::leaf(socket, &Self::body_path(&body)));
            }
        }
        sockets.into_iter().for_each(|s| link.push(s));
        if !frames.children.is_empty() {
            link.push(frames);
        }
        Ok(())
    }
}

/// `XMLDocument::addPhysicalOffsetFrame30505_30517`: the offset frame `<body>_offset` on `body`
/// (its socket written as OpenSim writes it once the model is built: the body's absolute path).
fn offset_frame(body: &str, translation: [f64; 3], orientation: [f64; 3]) -> TreeElement {
    let parent = Upgrade::body_path(body);
    let mut frame = TreeElement::named("PhysicalOffsetFrame", &format!("{body}_offset"));
    frame.push(TreeElement::leaf("socket_parent", &parent));
    frame.push(TreeElement::leaf("translation", &stream(&translation)));
    frame.push(TreeElement::leaf("orientation", &stream(&orientation)));
    frame
}
