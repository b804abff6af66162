//! `ScaleSet`: X, Y, Z scale factors per body, as OpenSim's ModelScaler builds it.

/// Scale factors of one body (OpenSim `Scale`: `segment`, `scales`).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyScaleFactors {
    pub body: String,
    /// Dimensionless X, Y, Z factors in the body frame.
    pub factors: [f64; 3],
}

/// Factors for every body of a model, starting at 1 (ground included, as OpenSim lists every
/// physical frame).
#[derive(Debug, Clone, PartialEq)]
pub struct ScaleSet {
    pub bodies: Vec<BodyScaleFactors>,
}

impl ScaleSet {
    /// Unit factors for `ground` and each body in `bodies`.
    pub fn unit<'a>(bodies: impl IntoIterator<Item = &'a str>) -> ScaleSet {
        let names = std::iter::once(crate::model::GROUND).chain(bodies);
        ScaleSet { bodies: names.map(|body| BodyScaleFactors { body: body.to_string(), factors: [1.0; 3] }).collect() }
    }

    /// The factors of `body`, `None` when the set has no entry for it.
    pub fn factors(&self, body: &str) -> Option<[f64; 3]> {
        self.bodies.iter().find(|b| b.body == body).map(|b| b.factors)
    }

    /// Sets the factor of `body` along the chosen axes (X, Y, Z); `false` when the body is not in
    /// the set (OpenSim then ignores the entry).
    pub fn set_axes(&mut self, body: &str, axes: [bool; 3], factor: f64) -> bool {
        let Some(entry) = self.bodies.iter_mut().find(|b| b.body == body) else { return false };
        for (value, _) in entry.factors.iter_mut().zip(axes).filter(|(_, on)| *on) {
            *value = factor;
        }
        true
    }

    /// Replaces all three factors of `body` (a manual scale); `false` when the body is unknown.
    pub fn set(&mut self, body: &str, factors: [f64; 3]) -> bool {
        match self.bodies.iter_mut().find(|b| b.body == body) {
            Some(entry) => {
                entry.factors = factors;
                true
            }
            None => false,
        }
    }

    /// The set as an OpenSim `ScaleSet` document (what ScaleTool's `output_scale_file` holds),
    /// with full-precision factors.
    pub fn to_document_text(&self) -> String {
        let mut text = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"40600\">\n\t<ScaleSet name=\"ScaleSet\">\n\t\t<objects>\n");
        for body in &self.bodies {
            let [x, y, z] = body.factors;
            text.push_str(&format!(
                "\t\t\t<Scale>\n\t\t\t\t<scales> {x} {y} {z}</scales>\n\t\t\t\t<segment>{}</segment>\n\t\t\t\t<apply>true</apply>\n\t\t\t</Scale>\n",
                body.body
            ));
        }
        text.push_str("\t\t</objects>\n\t\t<groups />\n\t</ScaleSet>\n</OpenSimDocument>\n");
        text
    }
}
