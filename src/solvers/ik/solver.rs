//! `InverseKinematics`: the per-frame problem compiled once for a model, a trial and tasks, and
//! the loop over the trial's frames (OpenSim's `InverseKinematicsTool::run`).

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use nalgebra::{DMatrix, DVector};

use super::assembly::assembled_default_pose;
use super::coordinates::{ConstraintWeight, CoordinateMap};
use super::frame::{link_rows, moving_coordinates, FrameModel, FrameObjective, FrameScratch, LinkTerms};
use super::held::{minimize_holding_links, LINK_ROOT_WEIGHT};
use super::report::{IkFrame, IkSolution, MarkerErrors};
use super::tasks::{resolve_coordinates, resolve_markers, IgnoredMarkerTask, IkTasks};
use crate::io::table::MarkerTable;
use crate::mechanics::{Multibody, Vec3};
use crate::solvers::least_squares::{LeastSquares, LeastSquaresOptions, LeastSquaresProblem, LeastSquaresStatus};
use crate::solvers::IkError;

/// How to solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkSettings {
    /// [`ConstraintWeight::Infinite`] is what OpenSim 4.6's tool does (see there).
    pub constraint_weight: ConstraintWeight,
    /// Stopping rules of each frame's minimisation. The defaults (steps ≤ 1e-10 rad or m,
    /// gradient ≤ 1e-14) are far tighter than OpenSim's `accuracy` (1e-5 by default), which
    /// is the convergence tolerance of Simbody's L-BFGS on the gradient.
    pub convergence: LeastSquaresOptions,
}

impl Default for IkSettings {
    fn default() -> Self {
        IkSettings { constraint_weight: ConstraintWeight::Infinite, convergence: LeastSquaresOptions::default() }
    }
}

/// Inverse kinematics of one trial: what is tracked, compiled; solve frame by frame.
#[derive(Debug, Clone)]
pub struct InverseKinematics<'m> {
    pub(super) model: FrameModel<'m>,
    map: CoordinateMap,
    settings: IkSettings,
    trial_file: PathBuf,
    times: Vec<f64>,
    /// Frame-major observations of the tracked markers (m); `None` when missing or NaN.
    observed: Vec<Option<Vec3>>,
    ignored_marker_tasks: Vec<IgnoredMarkerTask>,
    locked_coordinate_tasks: Vec<String>,
}

/// A frame's IK residuals r and Jacobian J = ∂r/∂x at free values x, and the total weight of
/// its markers with data.
pub(super) struct Linearisation {
    pub x: Vec<f64>,
    pub residuals: DVector<f64>,
    pub jacobian: DMatrix<f64>,
    pub total_weight: f64,
}

impl Linearisation {
    /// The frame's information on its free values, W·JᵀJ (in units of 1/σ²).
    pub fn information(&self) -> DMatrix<f64> {
        self.jacobian.transpose() * &self.jacobian * self.total_weight
    }
}

/// Buffers of a solve, reused from frame to frame; make one with
/// [`InverseKinematics::workspace`] of the solver that uses it.
#[derive(Debug, Clone)]
pub struct IkWorkspace {
    pub(super) frame: FrameScratch,
    pub(super) least_squares: LeastSquares,
    pub(super) x: Vec<f64>,
    pub(super) scales: Vec<f64>,
    /// Per coordinate task: its target in the frame being solved (rad or m).
    pub(super) targets: Vec<f64>,
    /// The links' augmented-Lagrangian shifts (multiplier / weight²) per link error, kept from
    /// frame to frame as a warm start.
    pub(super) link_shifts: Vec<f64>,
}

impl IkWorkspace {
    pub(super) fn new(model: &FrameModel, map: &CoordinateMap) -> IkWorkspace {
        let n = map.variable_count();
        IkWorkspace {
            frame: FrameScratch::new(model.multibody),
            least_squares: LeastSquares::new(n, model.residual_count(map)),
            x: vec![0.0; n],
            scales: vec![0.0; model.markers.len()],
            targets: model.coordinates.iter().map(|task| task.target).collect(),
            link_shifts: vec![0.0; link_rows(model.multibody)],
        }
    }

    /// Starts the next minimisation from pose `q`.
    pub(super) fn start_from(&mut self, map: &CoordinateMap, q: &[f64]) {
        map.free_values(q, &mut self.x);
    }
}

impl<'m> InverseKinematics<'m> {
    /// Matches `tasks` with `multibody`'s markers and coordinates and the markers of `trial`
    /// (read from `trial_file`, any length unit), as OpenSim does: markers are used in trial
    /// column order when they are tasked and in the model ([`InverseKinematics::ignored_marker_tasks`]
    /// lists the others); a coordinate task naming no coordinate is an error; a task on a
    /// locked coordinate is dropped and the coordinate held
    /// ([`InverseKinematics::locked_coordinate_tasks`]).
    pub fn new(multibody: &'m Multibody, trial: &MarkerTable, trial_file: &Path, tasks: &IkTasks, settings: IkSettings) -> Result<Self, IkError> {
        let trial = trial.in_meters();
        if trial.n_frames() == 0 {
            return Err(IkError::EmptyTrial { trial: trial_file.into() });
        }
        let (markers, ignored_marker_tasks) = resolve_markers(multibody, &trial, trial_file, &tasks.markers)?;
        let all_coordinates = resolve_coordinates(multibody, tasks)?;
        let mut tasked = vec![false; multibody.coordinates.len()];
        for task in &all_coordinates {
            tasked[task.coordinate] = true;
        }
        if let Some(constraint) = multibody.unheld_constraints.first() {
            let what = "an enforced constraint of a class osim-tune does not hold (OpenSim would hold it; disable it with isEnforced false to solve without it)".into();
            return Err(IkError::Unsupported { model: multibody.file.clone(), component: constraint.clone(), what });
        }
        let map = CoordinateMap::new(multibody, settings.constraint_weight, &tasked)?;
        let (coordinates, locked): (Vec<_>, Vec<_>) = all_coordinates.into_iter().partition(|t| !multibody.coordinates[t.coordinate].locked);
        let locked_coordinate_tasks = locked.iter().map(|t| multibody.coordinates[t.coordinate].name.clone()).collect();
        let moving = |body: usize| moving_coordinates(multibody, &map, body);
        let marker_coordinates = markers.iter().map(|m| moving(m.body)).collect();
        let link_coordinates = multibody.links.iter().map(|link| link.ends.each_ref().map(|end| moving(end.body))).collect();
        let mut observed = Vec::with_capacity(trial.n_frames() * markers.len());
        for frame in 0..trial.n_frames() {
            for marker in &markers {
                let position = trial.position(frame, marker.trial_column).filter(|p| p.iter().all(|v| v.is_finite()));
                observed.push(position.map(Vec3::from));
            }
        }
        Ok(InverseKinematics {
            model: FrameModel { multibody, markers, coordinates, marker_coordinates, link_coordinates },
            map,
            settings,
            trial_file: trial_file.into(),
            times: trial.times().to_vec(),
            observed,
            ignored_marker_tasks,
            locked_coordinate_tasks,
        })
    }

    /// Names of the markers in use, in trial column order (the order OpenSim reports them in).
    pub fn marker_names(&self) -> Vec<String> {
        self.model.markers.iter().map(|m| m.name.clone()).collect()
    }

    /// Marker tasks that name a marker missing from the model or the trial (OpenSim ignores
    /// them silently).
    pub fn ignored_marker_tasks(&self) -> &[IgnoredMarkerTask] {
        &self.ignored_marker_tasks
    }

    /// Coordinates that have a task but are locked: held at their default value, task dropped.
    pub fn locked_coordinate_tasks(&self) -> &[String] {
        &self.locked_coordinate_tasks
    }

    /// Frame times of the trial (s).
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The frames of `time_range` (s; `None`: all) as OpenSim picks them: the range is clipped
    /// to the trial's, then each end goes to the nearest frame (ties to the later one).
    /// A range that does not overlap the trial (or ends before it starts) is an error.
    pub fn frames(&self, time_range: Option<[f64; 2]>) -> Result<RangeInclusive<usize>, IkError> {
        let (first, last) = (self.times[0], self.times[self.times.len() - 1]);
        let Some([start, end]) = time_range else { return Ok(0..=self.times.len() - 1) };
        let (clipped_start, clipped_end) = (start.max(first), end.min(last));
        if clipped_end < clipped_start || clipped_end.is_nan() || clipped_start.is_nan() {
            return Err(IkError::TimeRange { trial: self.trial_file.clone(), start, end, first, last });
        }
        Ok(nearest_frame(&self.times, clipped_start)..=nearest_frame(&self.times, clipped_end))
    }

    /// Buffers for [`InverseKinematics::solve_frame`].
    pub fn workspace(&self) -> IkWorkspace {
        IkWorkspace::new(&self.model, &self.map)
    }

    /// The pose the first frame starts from, as OpenSim's `assemble` starts from the model's
    /// default state: default values, dependents following their couplers, the links held
    /// ([`assembled_default_pose`]; a model that does not assemble starts from its default
    /// values).
    pub fn initial_pose(&self) -> Vec<f64> {
        let multibody = self.model.multibody;
        let mut q = assembled_default_pose(multibody).unwrap_or_else(|_| multibody.default_pose());
        let mut x = vec![0.0; self.map.variable_count()];
        self.map.free_values(&q, &mut x);
        self.map.pose(multibody, &x, &mut q);
        q
    }

    /// Solves frame `frame` starting from `q` (rad or m per coordinate); `q` becomes the
    /// solution (held coordinates at their values, dependents following their couplers).
    ///
    /// Links (point, distance, point-on-line and weld constraints) are held exactly (OpenSim's
    /// default) by an augmented Lagrangian: the frame is solved with each link error's residual
    /// shifted by its multiplier estimate, which moves by the error, until every error is
    /// within LINK_TOLERANCE; with a finite constraint weight they are goals, √w·e.
    pub fn solve_frame(&self, frame: usize, q: &mut [f64], workspace: &mut IkWorkspace) -> Result<IkFrame, IkError> {
        let observed = self.prepare(frame, q, workspace)?;
        let exact = self.exact_links();
        let found = minimize_holding_links(&self.model, &self.map, observed, workspace, &self.settings.convergence, exact, q).map_err(|open| {
            let link = &self.model.multibody.links[open.link];
            let constraint = format!("{} ({})", link.name, link.class);
            IkError::LinkNotMet { trial: self.trial_file.clone(), frame, time: self.times[frame], constraint, error: open.error, rounds: open.rounds }
        })?;
        let cost = if exact { self.objective(frame, q, workspace)? } else { found.cost };
        Ok(self.frame_at(frame, q, observed, &mut workspace.frame, (cost, found.iterations, found.status)))
    }

    /// Whether links are held exactly (there are some, and the weight is infinite).
    pub(super) fn exact_links(&self) -> bool {
        !self.model.multibody.links.is_empty() && self.settings.constraint_weight == ConstraintWeight::Infinite
    }

    /// The links' terms of a reported objective: none when they are held exactly (they are
    /// then constraints, not goals), else √w·e.
    fn reported_links(&self) -> LinkTerms<'static> {
        if self.exact_links() { LinkTerms::NONE } else { LinkTerms { root_weight: self.map.root_weight, shifts: &[] } }
    }

    /// The frame's report at the pose `q` (realized into `scratch`) with the objective there and
    /// how it was found (iterations, status).
    fn frame_at(&self, frame: usize, q: &[f64], observed: &[Option<Vec3>], scratch: &mut FrameScratch, (objective, iterations, status): (f64, usize, LeastSquaresStatus)) -> IkFrame {
        self.model.multibody.realize(q, &mut scratch.kinematics);
        let errors = MarkerErrors::measure(&self.model.markers, observed, |m| scratch.kinematics.bodies[m.body].apply(&m.location));
        let missing_markers = observed.iter().enumerate().filter(|(_, o)| o.is_none()).map(|(i, _)| i).collect();
        IkFrame { frame, time: self.times[frame], q: q.to_vec(), errors, missing_markers, objective, iterations, status }
    }

    /// Frame `frame`'s residuals and Jacobian at pose `q` over the free values
    /// ([`InverseKinematics::free_values`]), with the total weight W of its markers with data:
    /// the residuals' variance is σ²/W for markers of weight 1 and noise σ. Links held exactly
    /// enter as residuals √w·e of the augmented Lagrangian's first √weight (`LINK_ROOT_WEIGHT`,
    /// 1e3 per m): measurements a million times surer than a marker's.
    pub(super) fn linearise(&self, frame: usize, q: &[f64], workspace: &mut IkWorkspace) -> Result<Linearisation, IkError> {
        let observed = self.prepare(frame, q, workspace)?;
        let total_weight = self.model.markers.iter().zip(observed).filter(|(_, o)| o.is_some()).map(|(m, _)| m.weight).sum();
        let links = if self.exact_links() { LinkTerms { root_weight: LINK_ROOT_WEIGHT, shifts: &[] } } else { self.reported_links() };
        let mut objective = FrameObjective { model: &self.model, map: &self.map, scratch: &mut workspace.frame, observed, scales: &workspace.scales, targets: &workspace.targets, links };
        let mut residuals = vec![0.0; objective.residual_count()];
        let mut jacobian = DMatrix::zeros(objective.residual_count(), objective.variable_count());
        objective.evaluate(&workspace.x, &mut residuals, Some(&mut jacobian));
        Ok(Linearisation { x: workspace.x.clone(), residuals: DVector::from_vec(residuals), jacobian, total_weight })
    }

    /// The pose of free values `x` (held coordinates at their values, dependents from their
    /// couplers).
    pub(super) fn pose_of(&self, x: &[f64]) -> Vec<f64> {
        let mut q = self.model.multibody.default_pose();
        self.map.pose(self.model.multibody, x, &mut q);
        q
    }

    /// Every coordinate's speed and acceleration at pose `q` for the free values' rates.
    pub(super) fn rates(&self, q: &[f64], x_dot: &[f64], x_ddot: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.map.rates(self.model.multibody, q, x_dot, x_ddot)
    }

    /// The free values of pose `q`.
    pub(super) fn free_values(&self, q: &[f64]) -> Vec<f64> {
        let mut x = vec![0.0; self.map.variable_count()];
        self.map.free_values(q, &mut x);
        x
    }

    /// The pose of free values `x` clamped to their bounds.
    pub(super) fn clamped_pose(&self, x: &[f64]) -> Vec<f64> {
        let clamped: Vec<f64> = x.iter().enumerate().map(|(i, &v)| v.max(self.map.bounds.lower[i]).min(self.map.bounds.upper[i])).collect();
        self.pose_of(&clamped)
    }

    /// Frame `frame`'s report at pose `q` with the objective there, for a pose found otherwise
    /// (`iterations`, `status` say how).
    pub(super) fn frame_at_pose(&self, frame: usize, q: &[f64], workspace: &mut IkWorkspace, iterations: usize, status: LeastSquaresStatus) -> Result<IkFrame, IkError> {
        let objective = self.objective(frame, q, workspace)?;
        let observed = &self.observed[frame * self.model.markers.len()..(frame + 1) * self.model.markers.len()];
        Ok(self.frame_at(frame, q, observed, &mut workspace.frame, (objective, iterations, status)))
    }

    /// The objective of frame `frame` at pose `q` (held coordinates taken at their values and
    /// dependents from their couplers, as the solver sees it): what [`IkFrame::objective`]
    /// reports, for comparing another solution (e.g. OpenSim's) with ours.
    pub fn objective(&self, frame: usize, q: &[f64], workspace: &mut IkWorkspace) -> Result<f64, IkError> {
        let observed = self.prepare(frame, q, workspace)?;
        let mut objective = FrameObjective { model: &self.model, map: &self.map, scratch: &mut workspace.frame, observed, scales: &workspace.scales, targets: &workspace.targets, links: self.reported_links() };
        let mut residuals = vec![0.0; objective.residual_count()];
        objective.evaluate(&workspace.x, &mut residuals, None);
        Ok(0.5 * residuals.iter().map(|r| r * r).sum::<f64>())
    }

    /// Checks `q`, sets the marker scales of `frame` and the free values of `q`; returns the
    /// frame's observations.
    fn prepare(&self, frame: usize, q: &[f64], workspace: &mut IkWorkspace) -> Result<&[Option<Vec3>], IkError> {
        let multibody = self.model.multibody;
        if q.len() != multibody.coordinates.len() {
            return Err(IkError::PoseLength { expected: multibody.coordinates.len(), found: q.len() });
        }
        if frame >= self.times.len() {
            return Err(IkError::NoFrame { trial: self.trial_file.clone(), frame, frames: self.times.len() });
        }
        let n_markers = self.model.markers.len();
        if workspace.frame.q.len() != q.len() || workspace.scales.len() != n_markers || workspace.targets.len() != self.model.coordinates.len() || workspace.x.len() != self.map.variable_count() {
            *workspace = self.workspace();
        }
        let observed = &self.observed[frame * n_markers..(frame + 1) * n_markers];
        let total_weight: f64 = self.model.markers.iter().zip(observed).filter(|(_, o)| o.is_some()).map(|(m, _)| m.weight).sum();
        if total_weight.is_nan() || total_weight <= 0.0 {
            return Err(IkError::NoUsableMarkers { trial: self.trial_file.clone(), frame, time: self.times[frame] });
        }
        for ((scale, marker), observation) in workspace.scales.iter_mut().zip(&self.model.markers).zip(observed) {
            *scale = if observation.is_some() { (marker.weight / total_weight).sqrt() } else { 0.0 };
        }
        for (target, task) in workspace.targets.iter_mut().zip(&self.model.coordinates) {
            *target = task.target_at(self.times[frame]);
        }
        self.map.free_values(q, &mut workspace.x);
        Ok(observed)
    }

    /// Solves the frames of `time_range` in order, each starting from the previous solution and
    /// the first from [`InverseKinematics::initial_pose`] (OpenSim's `assemble` then `track`).
    pub fn solve(&self, time_range: Option<[f64; 2]>) -> Result<IkSolution, IkError> {
        let frames = self.frames(time_range)?;
        let mut workspace = self.workspace();
        let mut q = self.initial_pose();
        let mut solved = Vec::with_capacity(frames.clone().count());
        for frame in frames {
            solved.push(self.solve_frame(frame, &mut q, &mut workspace)?);
        }
        let multibody = self.model.multibody;
        Ok(IkSolution {
            markers: self.marker_names(),
            coordinates: multibody.coordinates.iter().map(|c| c.name.clone()).collect(),
            frames: solved,
        })
    }
}

/// OpenSim's `TimeSeriesTable::getNearestRowIndexForTime`: the first time ≥ `time` unless
/// the one before is strictly nearer.
fn nearest_frame(times: &[f64], time: f64) -> usize {
    let after = times.partition_point(|t| *t < time);
    if after == times.len() {
        return times.len() - 1;
    }
    if after == 0 || times[after] - time <= time - times[after - 1] {
        after
    } else {
        after - 1
    }
}

#[cfg(test)]
mod tests {
    use super::nearest_frame;

    #[test]
    fn nearest_frame_as_opensim() {
        let times = [0.0, 0.5, 1.0, 1.5];
        assert_eq!(nearest_frame(&times, -1.0), 0);
        assert_eq!(nearest_frame(&times, 0.0), 0);
        assert_eq!(nearest_frame(&times, 0.2), 0);
        assert_eq!(nearest_frame(&times, 0.25), 1);
        assert_eq!(nearest_frame(&times, 1.2), 2);
        assert_eq!(nearest_frame(&times, 9.0), 3);
    }
}
