//! `ScaleSetup`: a `<ScaleTool>` setup file (2.x/3.x and 4.x dialects), typed.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::error::SetupError;
use super::marker_placer::MarkerPlacer;
use super::model_scaler::ModelScaler;
use super::object::{expect_class, read_document, read_object};
use super::path::{directory_of, SetupPath};
use super::property::{name_or_empty, optional_path, optional_string};
use crate::io::osim::OsimDocument;
use crate::model::ComponentReader;

/// A ScaleTool setup with OpenSim's defaults (`ScaleTool.cpp`) for absent properties. A section
/// is `None` when absent: OpenSim then skips it (or, without `GenericModelMaker`, has no model).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScaleSetup {
    /// The setup file, for messages.
    pub file: PathBuf,
    /// The directory relative file names resolve against (the setup file's).
    pub directory: PathBuf,
    /// The document's `Version` (10500 when the file has no `<OpenSimDocument>`).
    pub version: u32,
    /// The subject's name; OpenSim names the scaled model so.
    pub name: String,
    /// kg; the scaled model's total mass. ≤ 0 keeps the mass the scaling gives (default −1).
    pub mass: f64,
    /// mm, for information only (default −1).
    pub height: f64,
    /// years, for information only (default −1).
    pub age: f64,
    pub notes: Option<String>,
    pub generic_model_maker: Option<GenericModelMaker>,
    pub model_scaler: Option<ModelScaler>,
    pub marker_placer: Option<MarkerPlacer>,
}

/// `GenericModelMaker`: the unscaled model and the markers put on it before scaling.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GenericModelMaker {
    pub model_file: Option<SetupPath>,
    /// A `MarkerSet` file that replaces the model's markers of the same names.
    pub marker_set_file: Option<SetupPath>,
}

impl ScaleSetup {
    /// Reads the ScaleTool setup file `path`.
    pub fn read(path: &Path) -> Result<ScaleSetup, SetupError> {
        Self::from_document(&read_document(path)?)
    }

    /// The ScaleTool of `document`; objects it gives by reference are read from their files.
    pub fn from_document(document: &OsimDocument) -> Result<ScaleSetup, SetupError> {
        let tool = ComponentReader::new(document, document.object);
        expect_class(tool, "ScaleTool")?;
        let directory = directory_of(document.xml.file());
        let generic_model_maker = read_object(tool, "GenericModelMaker", &directory, |maker| Ok(GenericModelMaker::read(maker, &directory)))?;
        let model_scaler = read_object(tool, "ModelScaler", &directory, |scaler| ModelScaler::read(scaler, &directory))?;
        let marker_placer = read_object(tool, "MarkerPlacer", &directory, |placer| MarkerPlacer::read(placer, &directory))?;
        Ok(ScaleSetup {
            file: document.xml.file().into(),
            version: document.version.number,
            name: name_or_empty(tool),
            mass: tool.number_or("mass", -1.0)?,
            height: tool.number_or("height", -1.0)?,
            age: tool.number_or("age", -1.0)?,
            notes: optional_string(tool, "notes"),
            generic_model_maker,
            model_scaler,
            marker_placer,
            directory,
        })
    }
}

impl GenericModelMaker {
    fn read(maker: ComponentReader, directory: &Path) -> GenericModelMaker {
        GenericModelMaker {
            model_file: optional_path(maker, "model_file", directory),
            marker_set_file: optional_path(maker, "marker_set_file", directory),
        }
    }
}
