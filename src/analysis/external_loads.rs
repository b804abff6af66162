//! External loads as OpenSim's `ExternalForce` applies them: force, point and torque columns of
//! a data table, interpolated in time, expressed in named frames and applied to a body.

use std::path::{Path, PathBuf};

use super::signal::{increasing, spline, SignalError};
use crate::io::table::{StorageTable, TableError};
use crate::mechanics::{BodyLoad, Function, Kinematics, Multibody, Vec3, GROUND_INDEX};
use crate::model::{FunctionSpec, GROUND};
use crate::setup::{ExternalForceSpec, ExternalLoadsSetup, SetupError};

/// Why external loads cannot be applied to a model.
#[derive(Debug, thiserror::Error)]
pub enum ExternalLoadsError {
    #[error("{}:{line}: ExternalForce {force}: {problem}", file.display())]
    Force { file: PathBuf, line: usize, force: String, problem: String },
    #[error("{}: {problem}", file.display())]
    Data { file: PathBuf, problem: String },
    #[error(transparent)]
    Setup(#[from] SetupError),
    #[error(transparent)]
    Table(#[from] TableError),
}

/// The loads of an `ExternalLoads` file on a model, ready to evaluate at any time.
#[derive(Debug, Clone)]
pub struct ExternalLoads {
    forces: Vec<AppliedForce>,
    /// What OpenSim warns about while reading the file (an ignored
    /// `external_loads_model_kinematics_file`).
    pub warnings: Vec<String>,
}

/// One `ExternalForce`: frames as body indices, columns as functions of time.
#[derive(Debug, Clone)]
struct AppliedForce {
    /// `<body>_<force>`, the prefix of OpenSim's record labels.
    label: String,
    body: usize,
    force_frame: usize,
    point_frame: usize,
    force: Option<[Function; 3]>,
    point: Option<[Function; 3]>,
    torque: Option<[Function; 3]>,
}

impl ExternalLoads {
    /// Reads the `ExternalLoads` file `file` and its datafile, and compiles them on `multibody`;
    /// also returns the datafile's path.
    pub fn read(file: &Path, multibody: &Multibody) -> Result<(ExternalLoads, PathBuf), ExternalLoadsError> {
        let setup = ExternalLoadsSetup::read(file)?;
        let data_file = setup.datafile.as_ref().ok_or_else(|| ExternalLoadsError::Data { file: file.into(), problem: "the ExternalLoads names no datafile".into() })?.resolved.clone();
        let data = StorageTable::read(&data_file)?;
        Ok((ExternalLoads::new(&setup, &data, &data_file, multibody)?, data_file))
    }

    /// Compiles `setup`'s forces on `multibody` with their columns from `data` (read from
    /// `data_file`). Columns are found by their identifier as a prefix and must be exactly
    /// three; they are interpolated as OpenSim does: constant for one row, piecewise linear for
    /// two or three, else an interpolating cubic GCV spline.
    pub fn new(setup: &ExternalLoadsSetup, data: &StorageTable, data_file: &Path, multibody: &Multibody) -> Result<ExternalLoads, ExternalLoadsError> {
        // OpenSim 4 no longer re-expresses the points through the motion it names
        // (`ExternalLoads::updateFromXMLNode`: "not supported anymore. Results may change").
        let warnings = setup.model_kinematics_file.iter().map(|kinematics| {
            format!("{}: external_loads_model_kinematics_file {} is ignored, as OpenSim 4 ignores it: each point is used in the frame its force names", setup.file.display(), kinematics.written)
        });
        let warnings = warnings.collect();
        let times = data.times();
        if times.is_empty() {
            return Err(ExternalLoadsError::Data { file: data_file.into(), problem: "the table has no rows".into() });
        }
        if let Err(SignalError::TimesNotIncreasing { row, time, previous }) = increasing(&times) {
            return Err(ExternalLoadsError::Data { file: data_file.into(), problem: format!("times must increase strictly, but row {} is at {time} s after {previous} s", row + 1) });
        }
        let forces = setup.forces.iter().map(|spec| AppliedForce::new(spec, &setup.file, data, data_file, &times, multibody)).collect::<Result<_, _>>()?;
        Ok(ExternalLoads { forces, warnings })
    }

    /// The loads at `time` (s), in ground, for the pose in `kinematics`.
    pub fn at(&self, time: f64, kinematics: &Kinematics) -> Vec<BodyLoad> {
        self.forces.iter().map(|f| f.at(time, kinematics)).collect()
    }

    /// The body each force is applied to ([`Multibody::bodies`] indices), in the file's order.
    pub fn applied_bodies(&self) -> Vec<usize> {
        self.forces.iter().map(|f| f.body).collect()
    }

    /// Whether some force is applied to `body` ([`Multibody::bodies`] index).
    pub fn loads_body(&self, body: usize) -> bool {
        self.forces.iter().any(|f| f.body == body)
    }

    /// OpenSim's `ForceReporter` labels: per force `<body>_<name>_F{x,y,z}`, `_p{x,y,z}` when it
    /// has a point and `_T{x,y,z}` when it has a torque.
    pub fn record_labels(&self) -> Vec<String> {
        let mut labels = Vec::new();
        for force in &self.forces {
            for (prefix, present) in [("F", force.force.is_some()), ("p", force.point.is_some()), ("T", force.torque.is_some())] {
                if present {
                    labels.extend(["x", "y", "z"].map(|axis| format!("{}_{prefix}{axis}", force.label)));
                }
            }
        }
        labels
    }

    /// The values of [`ExternalLoads::record_labels`] at `time`: force and torque in ground (N,
    /// N·m), the point in the body it acts on (m).
    pub fn record_values(&self, time: f64, kinematics: &Kinematics) -> Vec<f64> {
        let mut values = Vec::new();
        for force in &self.forces {
            let load = force.at(time, kinematics);
            if force.force.is_some() {
                values.extend(load.force.iter());
            }
            if force.point.is_some() {
                values.extend(kinematics.bodies[force.body].inverse().apply(&load.point).iter());
            }
            if force.torque.is_some() {
                values.extend(load.torque.iter());
            }
        }
        values
    }
}

impl AppliedForce {
    fn new(spec: &ExternalForceSpec, file: &Path, data: &StorageTable, data_file: &Path, times: &[f64], multibody: &Multibody) -> Result<AppliedForce, ExternalLoadsError> {
        let problem = |problem: String| ExternalLoadsError::Force { file: file.into(), line: spec.line, force: spec.name.clone(), problem };
        let frame = |name: &str, what: &str| {
            let bare = name.strip_prefix("./bodyset/").or_else(|| name.strip_prefix("/bodyset/")).unwrap_or(name);
            let bare = if bare == "/ground" { GROUND } else { bare };
            multibody.body_index(bare).ok_or_else(|| problem(format!("{what} {name:?} is not a body of the model {}", multibody.file.display())))
        };
        let columns = |identifier: &Option<String>| -> Result<Option<[Function; 3]>, ExternalLoadsError> {
            let Some(identifier) = identifier else { return Ok(None) };
            let found: Vec<usize> = data.labels().iter().enumerate().skip(1).filter(|(_, l)| l.starts_with(identifier.as_str())).map(|(i, _)| i).collect();
            if found.len() != 3 {
                let labels: Vec<&str> = found.iter().map(|&i| data.labels()[i].as_str()).collect();
                return Err(problem(format!("{} must hold exactly 3 columns starting with {identifier:?}, found {} {labels:?}", data_file.display(), found.len())));
            }
            let function = |column: usize| {
                let values: Vec<f64> = data.rows().map(|row| row[column]).collect();
                interpolate(times, &values).map_err(|e| problem(format!("{}: {e}", data_file.display())))
            };
            Ok(Some([function(found[0])?, function(found[1])?, function(found[2])?]))
        };
        Ok(AppliedForce {
            label: format!("{}_{}", spec.applied_to_body, spec.name),
            body: frame(&spec.applied_to_body, "applied_to_body")?,
            force_frame: frame(&spec.force_expressed_in_body, "force_expressed_in_body")?,
            point_frame: if spec.point_identifier.is_some() { frame(&spec.point_expressed_in_body, "point_expressed_in_body")? } else { GROUND_INDEX },
            force: columns(&spec.force_identifier)?,
            point: columns(&spec.point_identifier)?,
            torque: columns(&spec.torque_identifier)?,
        })
    }

    fn at(&self, time: f64, kinematics: &Kinematics) -> BodyLoad {
        let value = |functions: &Option<[Function; 3]>| functions.as_ref().map_or(Vec3::zeros(), |f| Vec3::new(f[0].value(time), f[1].value(time), f[2].value(time)));
        let rotation = kinematics.bodies[self.force_frame].rotation;
        let point = match &self.point {
            Some(_) => kinematics.bodies[self.point_frame].apply(&value(&self.point)),
            None => kinematics.bodies[self.body].translation,
        };
        BodyLoad { body: self.body, force: rotation * value(&self.force), point, torque: rotation * value(&self.torque) }
    }
}

/// OpenSim's choice by the number of rows: constant, piecewise linear, or cubic GCV spline.
pub(super) fn interpolate(times: &[f64], values: &[f64]) -> Result<Function, SignalError> {
    match times.len() {
        1 => Ok(Function::new(&FunctionSpec::Constant { value: values[0] })),
        2 | 3 => Ok(Function::new(&FunctionSpec::PiecewiseLinearFunction { x: times.to_vec(), y: values.to_vec() })),
        _ => spline(3, times, values),
    }
}
