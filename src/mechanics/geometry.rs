//! `MuscleGeometry`: a model's tree and its muscles' paths, and `PathEvaluation`, which
//! evaluates the lengths and moment arms of a chosen set of muscles pose after pose without
//! allocating.

use super::error::MechanicsError;
use super::kinematics::Kinematics;
use super::multibody::Multibody;
use super::path::{GeometryPath, PathScratch};
use crate::model::ModelSpec;

/// The multibody tree and every muscle's path (ForceSet order).
#[derive(Debug, Clone)]
pub struct MuscleGeometry {
    pub multibody: Multibody,
    pub paths: Vec<GeometryPath>,
}

impl MuscleGeometry {
    pub fn new(model: &ModelSpec) -> Result<MuscleGeometry, MechanicsError> {
        let multibody = Multibody::new(model)?;
        let paths = model.muscles().map(|m| GeometryPath::new(&multibody, model, m)).collect::<Result<_, _>>()?;
        Ok(MuscleGeometry { multibody, paths })
    }

    pub fn path_index(&self, muscle: &str) -> Option<usize> {
        self.paths.iter().position(|p| p.name == muscle)
    }
}

/// Lengths and moment arms (about the coordinates each path spans) of chosen muscles.
#[derive(Debug, Clone)]
pub struct PathEvaluation {
    muscles: Vec<usize>,
    /// `moment_arms[offsets[k]..offsets[k + 1]]` belong to muscle k.
    offsets: Vec<usize>,
    lengths: Vec<f64>,
    moment_arms: Vec<f64>,
    kinematics: Kinematics,
    scratch: PathScratch,
}

impl PathEvaluation {
    /// Prepares buffers for `muscles` (indices into [`MuscleGeometry::paths`]).
    pub fn new(geometry: &MuscleGeometry, muscles: &[usize]) -> PathEvaluation {
        let mut offsets = vec![0];
        for &m in muscles {
            offsets.push(offsets.last().copied().unwrap_or(0) + geometry.paths[m].spanned.len());
        }
        PathEvaluation {
            muscles: muscles.to_vec(),
            lengths: vec![0.0; muscles.len()],
            moment_arms: vec![0.0; offsets.last().copied().unwrap_or(0)],
            offsets,
            kinematics: geometry.multibody.kinematics(),
            scratch: PathScratch::default(),
        }
    }

    /// Evaluates every chosen muscle at coordinate values `q` (rad or m, CoordinateSet order).
    pub fn evaluate(&mut self, geometry: &MuscleGeometry, q: &[f64]) {
        geometry.multibody.realize(q, &mut self.kinematics);
        for (k, &m) in self.muscles.iter().enumerate() {
            let path = &geometry.paths[m];
            let out = &mut self.moment_arms[self.offsets[k]..self.offsets[k + 1]];
            self.lengths[k] = path.moment_arms(&geometry.multibody, &self.kinematics, q, &mut self.scratch, &path.spanned, out);
        }
    }

    /// Length (m) of the k-th chosen muscle at the last pose.
    pub fn length(&self, k: usize) -> f64 {
        self.lengths[k]
    }

    /// Moment arms of the k-th chosen muscle about its path's `spanned` coordinates.
    pub fn moment_arms(&self, k: usize) -> &[f64] {
        &self.moment_arms[self.offsets[k]..self.offsets[k + 1]]
    }

    /// The body poses of the last pose.
    pub fn kinematics(&self) -> &Kinematics {
        &self.kinematics
    }
}
