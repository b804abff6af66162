//! The knee-moment model of isometric dynamometry (thesis ch. 6): in each trial's posture every
//! muscle crossing the knee is in static equilibrium (zero fiber velocity) at its activation, and
//! the knee moment is Σ F_t · r over those muscles, r the moment arm about the knee coordinate
//! (OpenSim's `computeMomentArm`, so the moment has the sign of the coordinate's generalized
//! force).
//!
//! The geometry (path lengths L_mt and moment arms per trial, and L_mt at rest) does not depend
//! on the muscle parameters and is computed once, in [`KneeMomentModel::new`]; so is the moment
//! of the muscles that are not estimated. An evaluation then costs one equilibrium per estimated
//! muscle and trial. The estimated muscles live in an explicit workspace, [`EstimatedMuscles`],
//! which updates Millard muscles in place, bit-identical to a rebuild (their curves do not
//! depend on the parameters), and rebuilds muscles of the other classes.
//!
//! Postures: the trial's knee, hip and ankle angles on the coordinates named by
//! [`DynamometryData::columns`], every other coordinate at its default value (couplers'
//! dependent coordinates follow their independent ones). Activations: the trial file's value
//! for each muscle with an activation column (the agonists of that direction), every other
//! muscle at its `minimum_activation` (activation columns of muscles that do not cross the knee
//! change nothing). Rest: every coordinate 0 (pelvis translations included),
//! every muscle at its minimum activation.

use std::path::PathBuf;

use super::error::FunctionalError;
use super::parameters::MuscleParameters;
use super::trials::{DynamometryData, IsometricTrial};
use crate::mechanics::muscle::{FiberEquilibrium, HillMuscle, MuscleError};
use crate::mechanics::{MuscleGeometry, PathEvaluation};
use crate::model::{ModelSpec, MuscleModelSpec, MuscleSpec};

/// A muscle crossing the knee coordinate, with its geometry in every trial.
#[derive(Debug, Clone)]
pub struct KneeMuscle {
    pub name: String,
    /// Position among the estimated muscles, when estimated.
    pub estimated: Option<usize>,
    /// The model's properties.
    pub spec: MuscleSpec,
    /// The muscle's `minimum_activation` (0 for `DeGrooteFregly2016Muscle`, which has none).
    pub minimum_activation: f64,
    /// L_mt per trial, m.
    pub mt_lengths: Vec<f64>,
    /// Moment arm about the knee coordinate per trial, m (OpenSim's sign: positive when tension
    /// drives the coordinate up).
    pub moment_arms: Vec<f64>,
    /// Activation per trial.
    pub activations: Vec<f64>,
    /// L_mt at rest (every coordinate 0), m.
    pub rest_mt_length: f64,
}

/// How each muscle's static equilibrium is found.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum EquilibriumMethod {
    /// The exact static balance ([`HillMuscle::equilibrium`], |F_m cos α − F_t| ≤ 5e-10 N): smooth
    /// in the parameters, the method for estimation.
    #[default]
    Exact,
    /// OpenSim 4.6's `Model::equilibrateMuscles` iteration for Millard muscles
    /// ([`Millard2012Muscle::opensim_equilibrium`](crate::mechanics::muscle::Millard2012Muscle::opensim_equilibrium)),
    /// which stops at |F_m cos α − F_t| ≤ 1e-8·F_max: reproduces the numbers OpenSim reports
    /// (and data generated with it) rather than the balance. Other classes: exact.
    OpenSim,
}

/// Trials, geometry and fixed contributions of one subject's knee moments.
#[derive(Debug, Clone)]
pub struct KneeMomentModel {
    /// The model file.
    pub model_file: PathBuf,
    /// The knee coordinate the moments are about.
    pub knee_coordinate: String,
    /// How equilibria are found.
    pub method: EquilibriumMethod,
    trials: Vec<IsometricTrial>,
    /// Every muscle crossing the knee coordinate, in the model's ForceSet order.
    muscles: Vec<KneeMuscle>,
    /// Index into `muscles` of each estimated muscle, in the trials' estimated-muscle order.
    estimated: Vec<usize>,
    /// Σ F_t·r of the muscles that are not estimated, per trial, N·m.
    fixed_moments: Vec<f64>,
    /// The Hill muscle of every knee muscle with the model's parameters.
    nominal: Vec<HillMuscle>,
}

/// The estimated muscles at given parameters: the workspace of moment evaluations.
#[derive(Debug, Clone)]
pub struct EstimatedMuscles {
    parameters: Vec<MuscleParameters>,
    muscles: Vec<HillMuscle>,
}

impl KneeMomentModel {
    /// Precomputes poses, path lengths, moment arms and activations of `data`'s trials for the
    /// muscles of `model` that cross the knee coordinate. Fails when a trial coordinate or an
    /// estimated or activated muscle is not in the model, when an estimated muscle does not
    /// cross the knee, when a knee muscle has no muscle mechanics or a wrapping path, or when a
    /// non-estimated muscle has no equilibrium in some trial. Equilibria are exact
    /// ([`EquilibriumMethod::Exact`]).
    pub fn new(model: &ModelSpec, data: &DynamometryData) -> Result<KneeMomentModel, FunctionalError> {
        KneeMomentModel::with_method(model, data, EquilibriumMethod::Exact)
    }

    /// [`KneeMomentModel::new`] with equilibria found by `method`.
    pub fn with_method(model: &ModelSpec, data: &DynamometryData, method: EquilibriumMethod) -> Result<KneeMomentModel, FunctionalError> {
        let geometry = MuscleGeometry::new(model)?;
        let multibody = &geometry.multibody;
        let coordinate = |name: &str| {
            let problem = "is not a coordinate of the model (a column of the trial files names it)";
            multibody.coordinate_index(name).ok_or_else(|| model_error(model, "coordinate", name, problem.into()))
        };
        let columns = &data.columns;
        let trial_coordinates = [coordinate(&columns.knee_angle)?, coordinate(&columns.hip_flexion)?, coordinate(&columns.ankle_angle)?];
        let knee = trial_coordinates[0];
        for name in data.estimated_muscles.iter().chain(data.trials.iter().flat_map(|t| t.activations.iter().map(|(m, _)| m))) {
            if geometry.path_index(name).is_none() {
                return Err(model_error(model, "muscle", name, "is not a muscle of the model (the subject file or a trial file names it)".into()));
            }
        }
        let paths: Vec<usize> = (0..geometry.paths.len()).filter(|&p| geometry.paths[p].spanned.contains(&knee)).collect();
        let mut muscles = paths.iter().map(|&p| KneeMuscle::new(model, &geometry, p, data)).collect::<Result<Vec<_>, _>>()?;
        let estimated = data
            .estimated_muscles
            .iter()
            .map(|name| {
                let problem = || model_error(model, "muscle", name, format!("is estimated but does not cross {}", columns.knee_angle));
                muscles.iter().position(|m| &m.name == name).ok_or_else(problem)
            })
            .collect::<Result<Vec<_>, _>>()?;
        add_geometry(&geometry, &paths, trial_coordinates, &data.trials, &mut muscles);
        let nominal = muscles
            .iter()
            .map(|m| HillMuscle::new(&m.name, &m.spec).map_err(|source| construction_error(model, &m.name, source)))
            .collect::<Result<Vec<_>, _>>()?;
        let mut knee_model = KneeMomentModel {
            model_file: model.file.clone(),
            knee_coordinate: columns.knee_angle.clone(),
            method,
            trials: data.trials.clone(),
            muscles,
            estimated,
            fixed_moments: Vec::new(),
            nominal,
        };
        knee_model.fixed_moments = knee_model.not_estimated_moments()?;
        Ok(knee_model)
    }

    /// This model for `trials`, which differ from its own in their activations only (same
    /// poses, same order): no new geometry.
    pub fn with_activations(&self, trials: Vec<IsometricTrial>) -> Result<KneeMomentModel, FunctionalError> {
        let mut model = self.clone();
        for muscle in &mut model.muscles {
            for (activation, trial) in muscle.activations.iter_mut().zip(&trials) {
                *activation = trial.activation(&muscle.name).unwrap_or(muscle.minimum_activation);
            }
        }
        model.trials = trials;
        model.fixed_moments = model.not_estimated_moments()?;
        Ok(model)
    }

    /// Σ F_t·r of the muscles that are not estimated, with the model's parameters, per trial.
    fn not_estimated_moments(&self) -> Result<Vec<f64>, FunctionalError> {
        let mut fixed = vec![0.0; self.trials.len()];
        for k in (0..self.muscles.len()).filter(|&k| self.muscles[k].estimated.is_none()) {
            for (t, moment) in fixed.iter_mut().enumerate() {
                *moment += self.contribution(k, &self.nominal[k], t)?;
            }
        }
        Ok(fixed)
    }

    /// The trials, in the order of every per-trial vector.
    pub fn trials(&self) -> &[IsometricTrial] {
        &self.trials
    }

    /// Every muscle crossing the knee coordinate, in the model's ForceSet order.
    pub fn knee_muscles(&self) -> &[KneeMuscle] {
        &self.muscles
    }

    /// The estimated muscles' names, in order.
    pub fn estimated_names(&self) -> impl Iterator<Item = &str> {
        self.estimated.iter().map(|&k| self.muscles[k].name.as_str())
    }

    /// The index into [`KneeMomentModel::knee_muscles`] of estimated muscle `e`.
    pub fn estimated_knee_index(&self, e: usize) -> usize {
        self.estimated[e]
    }

    /// The knee muscle of estimated muscle `e`.
    pub fn estimated_knee_muscle(&self, e: usize) -> &KneeMuscle {
        &self.muscles[self.estimated[e]]
    }

    /// The model's parameters of the estimated muscles, in order.
    pub fn nominal_parameters(&self) -> Vec<MuscleParameters> {
        self.estimated.iter().map(|&k| MuscleParameters::from_spec(&self.muscles[k].name, &self.muscles[k].spec)).collect()
    }

    /// Σ F_t·r of the muscles that are not estimated, per trial, N·m.
    pub fn fixed_moments(&self) -> &[f64] {
        &self.fixed_moments
    }

    /// The workspace for evaluations at the model's parameters.
    pub fn nominal_muscles(&self) -> EstimatedMuscles {
        EstimatedMuscles {
            parameters: self.nominal_parameters(),
            muscles: self.estimated.iter().map(|&k| self.nominal[k].clone()).collect(),
        }
    }

    /// The workspace for evaluations at `parameters` (one per estimated muscle, in order).
    pub fn estimated_muscles(&self, parameters: &[MuscleParameters]) -> Result<EstimatedMuscles, FunctionalError> {
        let mut muscles = self.nominal_muscles();
        muscles.set_all(self, parameters)?;
        Ok(muscles)
    }

    /// Knee moments (N·m, one per trial) at `parameters` (one per estimated muscle, in order).
    /// Builds the muscles each call; for repeated evaluations keep an [`EstimatedMuscles`] and
    /// use [`KneeMomentModel::moments_into`].
    pub fn moments(&self, parameters: &[MuscleParameters]) -> Result<Vec<f64>, FunctionalError> {
        let muscles = self.estimated_muscles(parameters)?;
        let mut moments = vec![0.0; self.trials.len()];
        self.moments_into(&muscles, &mut moments)?;
        Ok(moments)
    }

    /// Knee moments (N·m) of the trials into `moments` (one slot per trial), without allocating.
    ///
    /// # Panics
    /// If `moments` does not have one slot per trial.
    pub fn moments_into(&self, muscles: &EstimatedMuscles, moments: &mut [f64]) -> Result<(), FunctionalError> {
        assert_eq!(moments.len(), self.trials.len(), "one moment per trial");
        moments.copy_from_slice(&self.fixed_moments);
        for (&k, muscle) in self.estimated.iter().zip(&muscles.muscles) {
            for (t, moment) in moments.iter_mut().enumerate() {
                *moment += self.contribution(k, muscle, t)?;
            }
        }
        Ok(())
    }

    /// F_t·r (N·m) of knee muscle `k` (index into [`KneeMomentModel::knee_muscles`]) in trial
    /// `trial` when it is `muscle`.
    pub fn contribution(&self, k: usize, muscle: &HillMuscle, trial: usize) -> Result<f64, FunctionalError> {
        Ok(self.state(k, muscle, trial)?.tendon_force * self.muscles[k].moment_arms[trial])
    }

    /// The equilibrium of knee muscle `k` in trial `trial` when it is `muscle`.
    pub fn state(&self, k: usize, muscle: &HillMuscle, trial: usize) -> Result<FiberEquilibrium, FunctionalError> {
        let knee_muscle = &self.muscles[k];
        self.equilibrium(muscle, knee_muscle.activations[trial], knee_muscle.mt_lengths[trial])
            .map_err(|source| self.trial_error(k, trial, source))
    }

    /// The equilibrium of `muscle` at `activation` and path length `mt_length` (m) by the
    /// model's method.
    pub fn equilibrium(&self, muscle: &HillMuscle, activation: f64, mt_length: f64) -> Result<FiberEquilibrium, MuscleError> {
        match (self.method, muscle) {
            (EquilibriumMethod::OpenSim, HillMuscle::Millard(millard)) => millard.opensim_equilibrium(activation, mt_length),
            _ => muscle.equilibrium(activation, mt_length),
        }
    }

    /// Equilibrium states `[knee muscle][trial]` (knee muscles in [`KneeMomentModel::knee_muscles`]
    /// order), the estimated muscles as `muscles` holds them, the others at the model's values.
    pub fn states(&self, muscles: &EstimatedMuscles) -> Result<Vec<Vec<FiberEquilibrium>>, FunctionalError> {
        (0..self.muscles.len())
            .map(|k| {
                let muscle = self.muscles[k].estimated.map_or(&self.nominal[k], |e| &muscles.muscles[e]);
                (0..self.trials.len()).map(|t| self.state(k, muscle, t)).collect()
            })
            .collect()
    }

    /// The rest state of every estimated muscle (every coordinate 0, minimum activation), in
    /// order; `fiber_length` is the rest fiber length along the fibre.
    pub fn rest_states(&self, muscles: &EstimatedMuscles) -> Result<Vec<FiberEquilibrium>, FunctionalError> {
        (0..self.estimated.len()).map(|e| self.rest_state(e, muscles)).collect()
    }

    /// The rest state of estimated muscle `e`.
    pub fn rest_state(&self, e: usize, muscles: &EstimatedMuscles) -> Result<FiberEquilibrium, FunctionalError> {
        let knee_muscle = &self.muscles[self.estimated[e]];
        self.equilibrium(&muscles.muscles[e], knee_muscle.minimum_activation, knee_muscle.rest_mt_length).map_err(|source| FunctionalError::Muscle {
            file: self.model_file.clone(),
            muscle: knee_muscle.name.clone(),
            context: "the rest posture (every coordinate 0, minimum activation)".into(),
            source: Box::new(source),
        })
    }

    fn trial_error(&self, k: usize, trial: usize, source: MuscleError) -> FunctionalError {
        let t = &self.trials[trial];
        FunctionalError::Muscle {
            file: t.file.clone(),
            muscle: self.muscles[k].name.clone(),
            context: format!("trial {} (line {})", t.number, t.line),
            source: Box::new(source),
        }
    }
}

impl KneeMuscle {
    /// The muscle of path `path` without geometry yet; refused when it has no muscle mechanics
    /// or wraps over objects whose wrapping osim-tune does not compute (so its moment arm would be
    /// wrong).
    fn new(model: &ModelSpec, geometry: &MuscleGeometry, path: usize, data: &DynamometryData) -> Result<KneeMuscle, FunctionalError> {
        let path = &geometry.paths[path];
        let name = &path.name;
        let knee = &data.columns.knee_angle;
        if !path.ignored_wraps.is_empty() {
            let problem = format!("crosses {knee} through wrap objects ({}) among which one of a class OpenSim 4.6 does not have, which osim-tune does not wrap over", path.ignored_wraps.join(", "));
            return Err(model_error(model, "muscle", name, problem));
        }
        let force = model.forces.iter().find(|f| &f.name == name);
        let spec = force.and_then(|f| f.muscle.clone()).ok_or_else(|| {
            let class = force.map_or("?", |f| f.class.as_str());
            model_error(model, "muscle", name, format!("crosses {knee} but its class {class} has no muscle mechanics in osim-tune"))
        })?;
        let n = data.trials.len();
        Ok(KneeMuscle {
            name: name.clone(),
            estimated: data.estimated_muscles.iter().position(|m| m == name),
            minimum_activation: minimum_activation(&spec),
            spec,
            mt_lengths: Vec::with_capacity(n),
            moment_arms: Vec::with_capacity(n),
            activations: Vec::with_capacity(n),
            rest_mt_length: 0.0,
        })
    }
}

/// Fills each knee muscle's (muscle k on path `paths[k]`) path lengths, knee moment arms and
/// activations per trial, and its rest length. `trial_coordinates`: knee, hip, ankle.
fn add_geometry(geometry: &MuscleGeometry, paths: &[usize], trial_coordinates: [usize; 3], trials: &[IsometricTrial], muscles: &mut [KneeMuscle]) {
    let multibody = &geometry.multibody;
    let knee = trial_coordinates[0];
    let slots: Vec<usize> = paths.iter().map(|&p| geometry.paths[p].spanned.iter().position(|&c| c == knee).unwrap_or(0)).collect();
    let mut evaluation = PathEvaluation::new(geometry, paths);
    let defaults = multibody.default_pose();
    let mut pose = defaults.clone();
    for trial in trials {
        pose.copy_from_slice(&defaults);
        for (&c, value) in trial_coordinates.iter().zip([trial.knee_angle, trial.hip_flexion, trial.ankle_angle]) {
            pose[c] = value;
        }
        multibody.follow_couplers(&mut pose, &trial_coordinates);
        evaluation.evaluate(geometry, &pose);
        for (k, muscle) in muscles.iter_mut().enumerate() {
            muscle.mt_lengths.push(evaluation.length(k));
            muscle.moment_arms.push(evaluation.moment_arms(k)[slots[k]]);
            muscle.activations.push(trial.activation(&muscle.name).unwrap_or(muscle.minimum_activation));
        }
    }
    pose.fill(0.0);
    multibody.follow_couplers(&mut pose, &[]);
    evaluation.evaluate(geometry, &pose);
    for (k, muscle) in muscles.iter_mut().enumerate() {
        muscle.rest_mt_length = evaluation.length(k);
    }
}

impl EstimatedMuscles {
    /// The parameters of each estimated muscle, in order.
    pub fn parameters(&self) -> &[MuscleParameters] {
        &self.parameters
    }

    /// The Hill muscle of estimated muscle `e`.
    pub fn muscle(&self, e: usize) -> &HillMuscle {
        &self.muscles[e]
    }

    /// Sets estimated muscle `e`'s parameters (`parameters.name` must be its name). A Millard
    /// muscle is updated in place (its curves do not depend on the parameters; bit-identical to
    /// a rebuild); other classes are rebuilt from the model's properties.
    pub fn set(&mut self, model: &KneeMomentModel, e: usize, parameters: &MuscleParameters) -> Result<(), FunctionalError> {
        let knee_muscle = model.estimated_knee_muscle(e);
        if parameters.name != knee_muscle.name {
            return Err(FunctionalError::Parameters {
                muscle: parameters.name.clone(),
                problem: format!("given in place {e} of the estimated muscles, which is {:?}", knee_muscle.name),
            });
        }
        parameters.check()?;
        let invalid = |source: MuscleError| FunctionalError::Parameters { muscle: parameters.name.clone(), problem: source.to_string() };
        match &mut self.muscles[e] {
            HillMuscle::Millard(muscle) => {
                muscle.set_fiber_geometry(parameters.optimal_fiber_length, parameters.pennation_angle_at_optimal).map_err(invalid)?;
                muscle.tendon_slack_length = parameters.tendon_slack_length;
                muscle.max_isometric_force = parameters.max_isometric_force;
                muscle.max_contraction_velocity = parameters.max_contraction_velocity;
            }
            slot => *slot = HillMuscle::new(&knee_muscle.name, &parameters.apply_to(&knee_muscle.spec)).map_err(invalid)?,
        }
        self.parameters[e].clone_from(parameters);
        Ok(())
    }

    /// Sets every estimated muscle's parameters (one per estimated muscle, in order).
    pub fn set_all(&mut self, model: &KneeMomentModel, parameters: &[MuscleParameters]) -> Result<(), FunctionalError> {
        if parameters.len() != self.parameters.len() {
            let names: Vec<&str> = model.estimated_names().collect();
            return Err(FunctionalError::Parameters {
                muscle: parameters.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", "),
                problem: format!("{} parameter sets given; expected one per estimated muscle ({})", parameters.len(), names.join(", ")),
            });
        }
        for (e, p) in parameters.iter().enumerate() {
            self.set(model, e, p)?;
        }
        Ok(())
    }
}

/// The lowest activation a muscle's dynamics allow (OpenSim's `minimum_activation`; the
/// DeGroote–Fregly class has no such property and reaches 0).
fn minimum_activation(spec: &MuscleSpec) -> f64 {
    match &spec.model {
        MuscleModelSpec::Millard2012(m) => m.minimum_activation,
        MuscleModelSpec::Thelen2003(t) => t.minimum_activation,
        MuscleModelSpec::DeGrooteFregly2016(_) => 0.0,
    }
}


fn model_error(model: &ModelSpec, what: &'static str, name: &str, problem: String) -> FunctionalError {
    FunctionalError::Model { model: model.file.clone(), what, name: name.to_string(), problem }
}

fn construction_error(model: &ModelSpec, muscle: &str, source: MuscleError) -> FunctionalError {
    FunctionalError::Muscle { file: model.file.clone(), muscle: muscle.into(), context: "the model's properties".into(), source: Box::new(source) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tuning::functional::test_data::{subject01, train01};
    use crate::tuning::functional::TrialOptions;

    #[test]
    fn new_activations_give_the_moments_of_a_rebuilt_model() {
        let spec = subject01();
        let mut data = train01(&TrialOptions::default());
        let model = KneeMomentModel::new(&spec, &data).unwrap();
        for (t, trial) in data.trials.iter_mut().enumerate() {
            trial.activations.iter_mut().for_each(|(_, a)| *a *= 0.7 + 0.004 * t as f64);
        }
        let parameters = model.nominal_parameters();
        let reactivated = model.with_activations(data.trials.clone()).unwrap().moments(&parameters).unwrap();
        let rebuilt = KneeMomentModel::new(&spec, &data).unwrap().moments(&parameters).unwrap();
        let before = model.moments(&parameters).unwrap();
        assert!(reactivated.iter().zip(&before).all(|(a, b)| (a - b).abs() > 1.0), "the activations changed every moment");
        assert_eq!(reactivated, rebuilt);
    }
}
