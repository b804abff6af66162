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

/// What a [`PathEvaluation`]'s "moment arms" are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Arms {
    /// Moment arms about the coordinates each path spans ([`GeometryPath::spanned`]).
    Spanned,
    /// Moment arms about the coordinates its tension loads ([`GeometryPath::loaded`]).
    Loaded,
    /// About those, a unit tension's generalized forces with the links between bodies aside
    /// ([`GeometryPath::unit_tension_forces`]).
    Applied,
}

impl Arms {
    fn coordinates(self, path: &GeometryPath) -> &[usize] {
        if self == Arms::Spanned { &path.spanned } else { &path.loaded }
    }
}

/// Lengths and moment arms of chosen muscles, about the coordinates each path spans
/// ([`GeometryPath::spanned`]) or loads ([`GeometryPath::loaded`]).
#[derive(Debug, Clone)]
pub struct PathEvaluation {
    muscles: Vec<usize>,
    arms: Arms,
    /// `moment_arms[offsets[k]..offsets[k + 1]]` belong to muscle k.
    offsets: Vec<usize>,
    lengths: Vec<f64>,
    /// dL/dt (m/s), when evaluated with speeds.
    lengthening_speeds: Vec<f64>,
    moment_arms: Vec<f64>,
    kinematics: Kinematics,
    scratch: PathScratch,
}

impl PathEvaluation {
    /// Prepares buffers for `muscles` (indices into [`MuscleGeometry::paths`]), moment arms
    /// about the coordinates each spans.
    pub fn new(geometry: &MuscleGeometry, muscles: &[usize]) -> PathEvaluation {
        PathEvaluation::with(geometry, muscles, Arms::Spanned)
    }

    /// As [`PathEvaluation::new`], moment arms about the coordinates each path's tension loads
    /// as OpenSim applies it: the generalized forces of a unit tension.
    pub fn loading(geometry: &MuscleGeometry, muscles: &[usize]) -> PathEvaluation {
        PathEvaluation::with(geometry, muscles, Arms::Loaded)
    }

    /// As [`PathEvaluation::loading`], the "moment arms" being the generalized forces a unit
    /// tension applies with the links between bodies aside (the same without links): what the
    /// forward dynamics applies, the links' forces to be added.
    pub fn applying(geometry: &MuscleGeometry, muscles: &[usize]) -> PathEvaluation {
        PathEvaluation::with(geometry, muscles, Arms::Applied)
    }

    fn with(geometry: &MuscleGeometry, muscles: &[usize], arms: Arms) -> PathEvaluation {
        let mut offsets = vec![0];
        for &m in muscles {
            let path = &geometry.paths[m];
            offsets.push(offsets.last().copied().unwrap_or(0) + arms.coordinates(path).len());
        }
        PathEvaluation {
            muscles: muscles.to_vec(),
            arms,
            lengths: vec![0.0; muscles.len()],
            lengthening_speeds: vec![0.0; muscles.len()],
            moment_arms: vec![0.0; offsets.last().copied().unwrap_or(0)],
            offsets,
            kinematics: geometry.multibody.kinematics(),
            scratch: PathScratch::default(),
        }
    }

    /// Evaluates every chosen muscle at coordinate values `q` (rad or m, CoordinateSet order).
    pub fn evaluate(&mut self, geometry: &MuscleGeometry, q: &[f64]) {
        self.evaluate_moving(geometry, q, None);
    }

    /// [`PathEvaluation::evaluate`], and with speeds `u` (rad/s or m/s) each path's lengthening
    /// speed ([`GeometryPath::lengthening_speed`] over the coordinates it loads).
    pub fn evaluate_moving(&mut self, geometry: &MuscleGeometry, q: &[f64], u: Option<&[f64]>) {
        let multibody = &geometry.multibody;
        multibody.realize(q, &mut self.kinematics);
        for (k, &m) in self.muscles.iter().enumerate() {
            let path = &geometry.paths[m];
            let out = &mut self.moment_arms[self.offsets[k]..self.offsets[k + 1]];
            let coordinates = self.arms.coordinates(path);
            self.lengths[k] = if self.arms == Arms::Applied {
                path.unit_tension_forces(multibody, &self.kinematics, q, &mut self.scratch, coordinates, out)
            } else {
                path.moment_arms(multibody, &self.kinematics, q, &mut self.scratch, coordinates, out)
            };
            if let Some(u) = u {
                self.lengthening_speeds[k] = path.lengthening_speed(multibody, &self.kinematics, q, &self.scratch, &path.loaded, u);
            }
        }
    }

    /// dL/dt (m/s) of the k-th chosen muscle at the last [`PathEvaluation::evaluate_moving`].
    pub fn lengthening_speed(&self, k: usize) -> f64 {
        self.lengthening_speeds[k]
    }

    /// The coordinates the k-th chosen muscle's moment arms are about.
    pub fn coordinates<'g>(&self, geometry: &'g MuscleGeometry, k: usize) -> &'g [usize] {
        let path = &geometry.paths[self.muscles[k]];
        self.arms.coordinates(path)
    }

    /// Length (m) of the k-th chosen muscle at the last pose.
    pub fn length(&self, k: usize) -> f64 {
        self.lengths[k]
    }

    /// Moment arms of the k-th chosen muscle about its [`PathEvaluation::coordinates`].
    pub fn moment_arms(&self, k: usize) -> &[f64] {
        &self.moment_arms[self.offsets[k]..self.offsets[k + 1]]
    }

    /// The body poses of the last pose.
    pub fn kinematics(&self) -> &Kinematics {
        &self.kinematics
    }
}
