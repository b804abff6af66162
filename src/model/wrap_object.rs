//! Wrap objects (`WrapCylinder`, `WrapEllipsoid`, `WrapSphere`, `WrapTorus`) fixed to bodies.
//! Their geometry is read where wrapping is computed; here they are listed.

use serde::Serialize;

use super::reader::ComponentReader;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WrapObjectSpec {
    pub name: String,
    pub class: String,
    /// The body (or `ground`) the wrap object is fixed to.
    pub body: String,
}

impl WrapObjectSpec {
    pub fn read(reader: ComponentReader, body: &str) -> WrapObjectSpec {
        WrapObjectSpec { name: reader.name(), class: reader.class().to_string(), body: body.to_string() }
    }
}
