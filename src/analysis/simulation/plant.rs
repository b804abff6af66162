//! The simulated system: the model's force generators and muscles on its multibody, and the
//! layout of its states in the integrator's vector — [q_free, u_free, a, s]: the free
//! coordinates' values and speeds, the activations of the muscles with activation dynamics, the
//! second states of the muscles with compliant tendons.

use super::SimulationError;
use crate::analysis::controllers::Controllers;
use crate::analysis::external_loads::ExternalLoads;
use crate::analysis::forward::{driven_muscles, DrivenMuscle};
use crate::analysis::reporters::coordinate_state_paths;
use crate::analysis::static_optimization::Generator;
use crate::mechanics::{AppliedForces, Kinematics, MuscleGeometry, PathScratch, ProjectionError};
use crate::model::{ModelSpec, SecondState};

/// One state of the simulated model.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedState {
    /// Coordinate values and speeds (rad or m, rad/s or m/s, [`crate::mechanics::Multibody::coordinates`] order).
    pub q: Vec<f64>,
    pub u: Vec<f64>,
    /// Per muscle ([`Plant::muscles`] order): its activation (a muscle without activation
    /// dynamics: its excitation) and second state (fiber length in m or normalized tendon
    /// force; `None` beside a rigid tendon).
    pub activations: Vec<f64>,
    pub seconds: Vec<Option<f64>>,
}

/// The model as the simulation moves it.
pub struct Plant<'a> {
    pub spec: &'a ModelSpec,
    pub geometry: &'a MuscleGeometry,
    pub generators: &'a [Generator],
    /// The muscles among the generators, with their dynamics.
    pub muscles: Vec<DrivenMuscle>,
    pub external: Option<&'a ExternalLoads>,
    /// The model's and the tool's controllers.
    pub controls: &'a Controllers,
    /// Each generator's muscle among `muscles`, and each muscle's generator.
    muscle_of: Vec<Option<usize>>,
    generator_of: Vec<usize>,
    /// The coordinates' state paths in OpenSim's order of state variables, with their indices.
    pub(super) state_coordinates: Vec<(String, usize)>,
    /// The coordinates integrated (neither locked nor a coupler's dependent).
    free: Vec<usize>,
    /// The muscles with activation dynamics and with a second state.
    with_activation: Vec<usize>,
    with_second: Vec<usize>,
    /// The pose the free coordinates are set into (locked coordinates keep their values).
    held: Vec<f64>,
}

/// The buffers one evaluation of the state derivative needs.
pub struct Workspace {
    kinematics: Kinematics,
    scratch: PathScratch,
}

impl<'a> Plant<'a> {
    /// The plant of `spec` (`geometry` its paths) with `generators` (the model's muscles and
    /// actuators that apply force), `external` loads and `controls`, its locked coordinates held
    /// at their defaults ([`Plant::hold`] moves them). A muscle we cannot simulate is refused.
    pub fn new(spec: &'a ModelSpec, geometry: &'a MuscleGeometry, generators: &'a [Generator], external: Option<&'a ExternalLoads>, controls: &'a Controllers) -> Result<Plant<'a>, SimulationError> {
        let multibody = &geometry.multibody;
        let names: Vec<String> = generators.iter().filter(|g| g.muscle_path().is_some()).map(|g| g.name.clone()).collect();
        let muscles = driven_muscles(spec, geometry, &names, false).map_err(|e| SimulationError::Model(e.to_string()))?;
        let muscle_of: Vec<Option<usize>> = generators.iter().map(|g| muscles.iter().position(|m| m.name == g.name)).collect();
        let generator_of = (0..muscles.len()).map(|k| muscle_of.iter().position(|&m| m == Some(k)).expect("every muscle is a generator")).collect();
        let state_coordinates = coordinate_state_paths(spec, multibody);
        let free = (0..multibody.coordinates.len()).filter(|&c| !multibody.coordinates[c].locked && !multibody.is_dependent(c)).collect();
        let with_activation = (0..muscles.len()).filter(|&k| muscles[k].activation.is_some()).collect();
        let with_second = (0..muscles.len()).filter(|&k| !muscles[k].muscle.has_rigid_tendon()).collect();
        let held = multibody.default_pose();
        Ok(Plant { spec, geometry, generators, muscles, external, controls, muscle_of, generator_of, state_coordinates, free, with_activation, with_second, held })
    }

    /// Holds the locked coordinates at their values in pose `q` (e.g. the initial state's).
    pub fn hold(&mut self, q: &[f64]) {
        self.held = q.to_vec();
    }

    /// The excitation (control) of muscle or actuator `name` at `time` (s).
    pub fn control(&self, name: &str, time: f64) -> f64 {
        self.controls.control(name, time)
    }

    /// Each generator's control at `time` (s).
    pub fn generator_controls(&self, time: f64) -> Vec<f64> {
        self.generators.iter().map(|g| self.control(&g.name, time)).collect()
    }

    /// How many coordinates are integrated (the integrator's vector holds their values, then
    /// their speeds, then the muscles' states).
    pub fn coordinate_states(&self) -> usize {
        self.free.len()
    }

    /// The second state of muscle k (`None` beside a rigid tendon).
    pub fn second_state(&self, k: usize) -> Option<SecondState> {
        let muscle = &self.muscles[k];
        if muscle.muscle.has_rigid_tendon() {
            None
        } else if muscle.tendon_force_state().is_some() {
            Some(SecondState::NormalizedTendonForce)
        } else {
            Some(SecondState::FiberLength)
        }
    }

    /// The integrator's vector of `state`.
    pub fn pack(&self, state: &SimulatedState) -> Vec<f64> {
        let free = || self.free.iter();
        free().map(|&c| state.q[c])
            .chain(free().map(|&c| state.u[c]))
            .chain(self.with_activation.iter().map(|&k| state.activations[k]))
            .chain(self.with_second.iter().map(|&k| state.seconds[k].unwrap_or(0.0)))
            .collect()
    }

    /// The state at `time` (s) of the integrator's vector `y`: dependents following their
    /// couplers, a muscle without activation dynamics at its excitation.
    pub fn unpack(&self, time: f64, y: &[f64]) -> SimulatedState {
        self.unpack_with(y, &self.generator_controls(time))
    }

    /// [`Plant::unpack`] with the generators' `controls` at its time.
    fn unpack_with(&self, y: &[f64], controls: &[f64]) -> SimulatedState {
        let (q, u) = self.pose(y);
        self.with_muscle_states(q, u, &y[2 * self.free.len()..], controls)
    }

    /// The muscles' states of `state` as the integrator holds them after the speeds: the
    /// activations of the muscles with activation dynamics, then the second states.
    pub fn muscle_states(&self, state: &SimulatedState) -> Vec<f64> {
        self.pack(state)[2 * self.free.len()..].to_vec()
    }

    /// The state of pose `q`, speeds `u` and muscles' states `z` ([`Plant::muscle_states`]
    /// order), a muscle without activation dynamics at its generator's control in `controls`.
    pub fn with_muscle_states(&self, q: Vec<f64>, u: Vec<f64>, z: &[f64], controls: &[f64]) -> SimulatedState {
        let mut activations: Vec<f64> = self.generator_of.iter().map(|&g| controls[g]).collect();
        for (i, &k) in self.with_activation.iter().enumerate() {
            activations[k] = z[i];
        }
        let mut seconds = vec![None; self.muscles.len()];
        for (i, &k) in self.with_second.iter().enumerate() {
            seconds[k] = Some(z[self.with_activation.len() + i]);
        }
        SimulatedState { q, u, activations, seconds }
    }

    /// Every coordinate's value and speed from `y`.
    fn pose(&self, y: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let multibody = &self.geometry.multibody;
        let (mut q, mut u) = (self.held.clone(), vec![0.0; self.held.len()]);
        for (i, &c) in self.free.iter().enumerate() {
            q[c] = y[i];
            u[c] = y[self.free.len() + i];
        }
        multibody.follow_couplers(&mut q, &[]);
        multibody.follow_coupler_speeds(&q, &mut u);
        (q, u)
    }

    /// Whether the pose or speeds of `y` have drifted off the links between bodies by more than
    /// `tolerance` (m, m/s).
    pub(super) fn drifted(&self, y: &[f64], tolerance: f64) -> bool {
        let multibody = &self.geometry.multibody;
        if multibody.links.is_empty() {
            return false;
        }
        let (q, u) = self.pose(y);
        let (position, rate) = multibody.link_drift(&q, &u);
        position > tolerance || rate > tolerance
    }

    /// `y` with its pose and speeds projected back onto the links
    /// ([`Multibody::project_onto_links`](crate::mechanics::Multibody::project_onto_links), to a
    /// thousandth of `tolerance`).
    pub(super) fn project(&self, y: &[f64], tolerance: f64) -> Result<Vec<f64>, ProjectionError> {
        let (mut q, mut u) = self.pose(y);
        self.geometry.multibody.project_onto_links(&mut q, &mut u, 1e-3 * tolerance)?;
        let mut projected = y.to_vec();
        let n = self.free.len();
        for (i, &c) in self.free.iter().enumerate() {
            (projected[i], projected[n + i]) = (q[c], u[c]);
        }
        Ok(projected)
    }

    pub fn workspace(&self) -> Workspace {
        Workspace { kinematics: self.geometry.multibody.kinematics(), scratch: PathScratch::default() }
    }

    /// ẏ at `time` (s) and `y` into `dy`; an error names why it has none (a muscle's state out
    /// of its domain, a singular mass matrix).
    pub fn derivatives(&self, time: f64, y: &[f64], dy: &mut [f64], work: &mut Workspace) -> Result<(), String> {
        let multibody = &self.geometry.multibody;
        let controls = self.generator_controls(time);
        let state = self.unpack_with(y, &controls);
        let (q, u) = (&state.q, &state.u);
        multibody.realize(q, &mut work.kinematics);
        let mut applied = AppliedForces { loads: self.external.map(|e| e.at(time, &work.kinematics)).unwrap_or_default(), mobility: vec![0.0; q.len()] };
        let (forces, rates) = self.forces_and_rates(time, &state, &controls, work)?;
        for (generator, &force) in self.generators.iter().zip(&forces) {
            generator.apply(self.geometry, &work.kinematics, q, &mut work.scratch, force, &mut applied);
        }
        let udot = multibody.accelerations(&work.kinematics, q, u, &applied.loads, &applied.mobility).map_err(|e| e.to_string())?;
        let qdot = multibody.coordinate_rates(q, u);
        let n = self.free.len();
        for (i, &c) in self.free.iter().enumerate() {
            dy[i] = qdot[c];
            dy[n + i] = udot[c];
        }
        self.write_muscle_rates(&state, &controls, &rates, &mut dy[2 * n..]);
        Ok(())
    }

    /// The muscles' state rates ż ([`Plant::muscle_states`] order) at `state` and `time` (s)
    /// under the generators' `controls` — the muscles alone, their paths moving as `state`'s
    /// coordinates and speeds say (CMC's actuator subsystem).
    pub fn muscle_state_rates(&self, time: f64, state: &SimulatedState, controls: &[f64], dz: &mut [f64], work: &mut Workspace) -> Result<(), String> {
        self.geometry.multibody.realize(&state.q, &mut work.kinematics);
        let (_, rates) = self.forces_and_rates(time, state, controls, work)?;
        self.write_muscle_rates(state, controls, &rates, dz);
        Ok(())
    }

    /// Each generator's force (N or N·m) at `state` and `time` (s) under `controls`: a muscle's
    /// tendon force, an actuator's control × optimal force.
    pub fn actuations(&self, time: f64, state: &SimulatedState, controls: &[f64], work: &mut Workspace) -> Result<Vec<f64>, String> {
        self.geometry.multibody.realize(&state.q, &mut work.kinematics);
        Ok(self.forces_and_rates(time, state, controls, work)?.0)
    }

    /// Each generator's force and each muscle's second-state rate at `state`, whose pose
    /// `work`'s kinematics holds.
    fn forces_and_rates(&self, time: f64, state: &SimulatedState, controls: &[f64], work: &mut Workspace) -> Result<(Vec<f64>, Vec<f64>), String> {
        let mut rates = vec![0.0; self.muscles.len()];
        let mut forces = Vec::with_capacity(self.generators.len());
        for (g, generator) in self.generators.iter().enumerate() {
            forces.push(match self.muscle_of[g] {
                Some(k) => {
                    let (force, rate) = self.muscle_force(k, state, time, work)?;
                    rates[k] = rate;
                    force
                }
                None => controls[g] * generator.unit_force(false, 0.0, 0.0),
            });
        }
        Ok((forces, rates))
    }

    /// ż into `dz`: the activations' rates from the excitations, then the second states' `rates`.
    fn write_muscle_rates(&self, state: &SimulatedState, controls: &[f64], rates: &[f64], dz: &mut [f64]) {
        for (i, &k) in self.with_activation.iter().enumerate() {
            let dynamics = self.muscles[k].activation.as_ref().expect("a muscle with activation dynamics");
            dz[i] = dynamics.rate(state.activations[k], controls[self.generator_of[k]]);
        }
        for (i, &k) in self.with_second.iter().enumerate() {
            dz[self.with_activation.len() + i] = rates[k];
        }
    }

    /// Muscle k's tendon force (N) at `state` and the rate of its second state (fiber velocity,
    /// m/s, or a DeGroote muscle's df̃_T/dt, 1/s; 0 beside a rigid tendon).
    fn muscle_force(&self, k: usize, state: &SimulatedState, time: f64, work: &mut Workspace) -> Result<(f64, f64), String> {
        let muscle = &self.muscles[k];
        let path = &self.geometry.paths[muscle.path];
        let (length, speed) = path.length_and_speed(&self.geometry.multibody, &work.kinematics, &state.q, &mut work.scratch, &path.loaded, &state.u);
        let activation = state.activations[k].clamp(0.0, 1.0);
        let second = state.seconds[k].unwrap_or(0.0);
        let at = muscle.muscle.state(activation, second, length, speed).map_err(|e| format!("at {time} s: {e}"))?;
        let rate = match (state.seconds[k], muscle.tendon_force_state()) {
            (None, _) => 0.0,
            (Some(f), Some(degroote)) => degroote.normalized_tendon_force_rate(activation, f, length, speed),
            (Some(_), None) => at.fiber_velocity,
        };
        Ok((at.report.tendon_force, rate))
    }
}
