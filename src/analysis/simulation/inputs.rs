//! What a ForwardTool setup simulates, read from the files it names: the model with the
//! actuators of its force-set files, the external loads, the controllers (the model's and the
//! setup's) and the states file.

use std::path::{Path, PathBuf};

use super::{Plant, SimulationError};
use crate::analysis::analyze_tool::AnalyzeModel;
use crate::analysis::controllers::Controllers;
use crate::analysis::external_loads::ExternalLoads;
use crate::analysis::static_optimization::{force_generators, Generator};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::model::{read_force_set, ActuatorSpec, ModelSpec};
use crate::setup::{read_document, AnalyzeSetup};

/// The model a ForwardTool setup moves, and its inputs.
pub struct ForwardModel {
    pub spec: ModelSpec,
    pub geometry: MuscleGeometry,
    /// The actuators of the force-set files, replacing the model's forces when `replace`.
    pub added: Vec<ActuatorSpec>,
    pub replace: bool,
    pub external: Option<ExternalLoads>,
    pub controls: Controllers,
    /// The forces that act: muscles and actuators.
    pub generators: Vec<Generator>,
    /// The states file (its table, its path), if the setup names one.
    pub states: Option<(StorageTable, PathBuf)>,
    /// Every file read.
    pub read: Vec<PathBuf>,
}

impl ForwardModel {
    /// Reads `model` and the inputs `tool` names; an error names the file at fault.
    pub fn read(model: &Path, tool: &AnalyzeSetup) -> Result<ForwardModel, String> {
        let text = |e: &dyn std::fmt::Display| e.to_string();
        let spec = ModelSpec::read(&OsimDocument::read(model).map_err(|e| text(&e))?).map_err(|e| text(&e))?;
        let geometry = MuscleGeometry::new(&spec).map_err(|e| text(&e))?;
        let mut read = vec![model.to_path_buf()];
        let mut added = Vec::new();
        for file in &tool.force_set_files {
            added.extend(read_force_set(&read_document(&file.resolved).map_err(|e| text(&e))?).map_err(|e| text(&e))?);
            read.push(file.resolved.clone());
        }
        let replace = tool.replace_force_set && !tool.force_set_files.is_empty();
        let external = match &tool.external_loads_file {
            Some(file) => {
                let (loads, data) = ExternalLoads::read(&file.resolved, &geometry.multibody).map_err(|e| text(&e))?;
                read.extend([file.resolved.clone(), data]);
                Some(loads)
            }
            None => None,
        };
        let controls = Controllers::of_model(&spec, &tool.controllers, &added, replace)?;
        read.extend(controls.files.iter().cloned());
        let generators = force_generators(&spec, &geometry, &added, replace).map_err(|e| text(&e))?;
        let states = match &tool.states_file {
            Some(file) => {
                read.push(file.resolved.clone());
                Some((StorageTable::read(&file.resolved).map_err(|e| text(&e))?, file.resolved.clone()))
            }
            None => None,
        };
        Ok(ForwardModel { spec, geometry, added, replace, external, controls, generators, states, read })
    }

    /// The model with `body`'s mass center moved to `mass_center` (m, in the body), everything
    /// else as it is (RRA's adjusted model).
    pub fn with_mass_center(&self, body: &str, mass_center: [f64; 3]) -> Result<ForwardModel, String> {
        let mut spec = self.spec.clone();
        let adjusted = spec.bodies.iter_mut().find(|b| b.name == body).ok_or_else(|| format!("the model has no body {body:?}"))?;
        adjusted.mass_center = mass_center;
        let geometry = MuscleGeometry::new(&spec).map_err(|e| e.to_string())?;
        let generators = force_generators(&spec, &geometry, &self.added, self.replace).map_err(|e| e.to_string())?;
        Ok(ForwardModel { spec, geometry, generators, added: self.added.clone(), external: self.external.clone(), controls: self.controls.clone(), states: self.states.clone(), read: self.read.clone(), replace: self.replace })
    }

    /// The plant of the model, its locked coordinates at their defaults; controllers osim-tune
    /// does not apply are refused.
    pub fn plant(&self) -> Result<Plant<'_>, SimulationError> {
        if !self.controls.unapplied.is_empty() {
            return Err(SimulationError::Model(format!("controllers osim-tune does not apply: {}", self.controls.unapplied.join(", "))));
        }
        Plant::new(&self.spec, &self.geometry, &self.generators, self.external.as_ref(), &self.controls)
    }

    /// The model as the AnalyzeTool analyses of the simulated states see it.
    pub fn analysed(&self) -> AnalyzeModel<'_> {
        AnalyzeModel { spec: &self.spec, geometry: &self.geometry, added: &self.added, replace: self.replace, external: self.external.as_ref(), controls: &self.controls }
    }
}
