//! subject01's walk through inverse dynamics and static optimisation, as OpenSim 4.6's pipeline
//! golden ran it (`reference/pipelines/gait2392_subject01/`, copied or sliced into
//! `fixtures/golden/`): the scaled model, its IK, the ground reactions on both feet, 6 Hz
//! low-pass; the six residual actuators for static optimisation, 0.5–2 s.

use std::path::{Path, PathBuf};

use super::geometry::Worst;
use crate::analysis::{generators, inverse_dynamics, muscle_state_names, named_joints, physiological_inverse, static_optimization, Contraction, Criterion, ExternalLoads, Generator, MotionInput, PhysiologicalInverseResult, PhysiologicalInverseSettings, InverseDynamicsSettings, ReferenceControls, StaticOptimizationResult, StaticOptimizationSettings};
use crate::io::osim::OsimDocument;
use crate::io::table::StorageTable;
use crate::mechanics::MuscleGeometry;
use crate::model::{read_force_set, ModelSpec};

/// The walk's inputs, read from the repository at `root`.
pub struct Subject01Walk {
    /// The scaled model's file.
    pub model: PathBuf,
    pub geometry: MuscleGeometry,
    /// The model's muscles, then the residual actuators.
    pub generators: Vec<Generator>,
    pub loads: ExternalLoads,
    pub coordinates: StorageTable,
    pub coordinates_file: PathBuf,
}

/// How OpenSim's static optimisation compares with ours on the same problem.
#[derive(Debug, Clone, Default)]
pub struct WalkStaticOptimization {
    /// Frames of OpenSim's table judged.
    pub frames: usize,
    /// OpenSim's controls against our constraints, N·m or N.
    pub violation: Worst,
    /// How far OpenSim's controls leave our bounds.
    pub bound_violation: f64,
    /// (OpenSim's Σ|a|ᵖ − ours) / max(ours, 0.01): largest and smallest (relative to ours, except
    /// at frames whose optimum costs almost nothing, where OpenSim's absolute stopping tolerance
    /// dominates).
    pub largest_gap: f64,
    pub smallest_gap: f64,
    /// Force per unit control (OpenSim's force / activation) against ours, relative to
    /// max(1, |F|).
    pub unit_force: Worst,
    /// The external loads' records in the force table, N, m or N·m (∞ when the labels differ).
    pub load_records: Worst,
}

impl Subject01Walk {
    pub fn load(root: &Path) -> Result<Subject01Walk, Box<dyn std::error::Error>> {
        let fixture = |relative: &str| root.join("fixtures").join(relative);
        let (_, geometry, generators) = muscles_and_actuators(&fixture("golden/scale/subject01_simbody.osim"), &fixture("subject01/gait2392_SO_Residual_Actuators.xml"))?;
        let (loads, _) = ExternalLoads::read(&fixture("subject01/subject01_walk1_grf.xml"), &geometry.multibody)?;
        let coordinates_file = fixture("golden/ik/subject01_walk1_ik.mot");
        let coordinates = StorageTable::read(&coordinates_file)?;
        Ok(Subject01Walk { model: fixture("golden/scale/subject01_simbody.osim"), geometry, generators, loads, coordinates, coordinates_file })
    }

    /// The InverseDynamicsTool run of subject01's setup (0.4–1.6 s) against OpenSim's table
    /// `golden`: the worst absolute difference (N·m or N), or ∞ if the rows or columns differ;
    /// with `body_forces`, the equivalent body forces of every joint against OpenSim's
    /// `joints_to_report_body_forces` ALL table instead.
    pub fn inverse_dynamics(&self, golden: &StorageTable, body_forces: bool) -> Result<Worst, Box<dyn std::error::Error>> {
        let settings = InverseDynamicsSettings { time_range: [0.4, 1.6], lowpass_cutoff: Some(6.0) };
        let spec = ModelSpec::read(&OsimDocument::read(&self.model)?)?;
        let joints = if body_forces { named_joints(&spec, &self.geometry.multibody, &["ALL".into()])? } else { Vec::new() };
        let motion = settings.motion(&self.geometry.multibody, &self.coordinates, &self.coordinates_file)?;
        let result = inverse_dynamics(&self.geometry.multibody, &motion, Some(&self.loads), &joints)?;
        let ours = if body_forces { result.body_forces.ok_or("no body forces")? } else { result.forces };
        let mut worst = Worst::default();
        if ours.labels() != golden.labels() || ours.n_rows() != golden.n_rows() {
            worst.update(f64::INFINITY, || format!("{} rows of {:?} against OpenSim's {} of {:?}", ours.n_rows(), ours.labels(), golden.n_rows(), golden.labels()));
            return Ok(worst);
        }
        for (ours, theirs) in ours.rows().zip(golden.rows()) {
            for (label, (a, b)) in golden.labels().iter().zip(ours.iter().zip(theirs)) {
                worst.update((a - b).abs(), || format!("t = {} s, {label}", theirs[0]));
            }
        }
        Ok(worst)
    }

    /// Our static optimisation (0.5–2 s, every row), with OpenSim's controls `activations` (from
    /// `file`) judged on it.
    pub fn static_optimization(&self, activations: &StorageTable, file: &Path) -> Result<StaticOptimizationResult, Box<dyn std::error::Error>> {
        let settings = StaticOptimizationSettings { time_range: [0.5, 2.0], lowpass_cutoff: Some(6.0), step_interval: 1, use_muscle_physiology: true, activation_exponent: 2.0 };
        let reference = ReferenceControls { table: activations, file };
        Ok(static_optimization(&self.geometry, &self.generators, MotionInput::Coordinates(&self.coordinates), &self.coordinates_file, Some(&self.loads), &settings, Some(reference))?)
    }
}

impl Subject01Walk {
    /// The physiological inverse approach's settings over 0.5–2 s (6 Hz, every row) by
    /// `criterion`, with every muscle's time constants multiplied by `time_constant_scale`, rigid
    /// tendons and exact rows.
    pub fn pia_settings(criterion: Criterion, time_constant_scale: f64) -> PhysiologicalInverseSettings {
        let frames = StaticOptimizationSettings { time_range: [0.5, 2.0], lowpass_cutoff: Some(6.0), step_interval: 1, use_muscle_physiology: true, activation_exponent: 2.0 };
        PhysiologicalInverseSettings { frames, criterion, time_constant_scale, contraction: Contraction::RigidTendon, moment_weight: None }
    }

    /// The physiological inverse approach on the walk with `settings`.
    pub fn physiological_inverse(&self, settings: &PhysiologicalInverseSettings) -> Result<PhysiologicalInverseResult, Box<dyn std::error::Error>> {
        Ok(physiological_inverse(&self.geometry, &self.generators, MotionInput::Coordinates(&self.coordinates), &self.coordinates_file, Some(&self.loads), settings)?)
    }
}

/// OpenSim's static optimisation tables (`activations`, `forces`) against `ours`.
pub fn compare_static_optimization(ours: &StaticOptimizationResult, activations: &StorageTable, forces: &StorageTable) -> WalkStaticOptimization {
    let mut comparison = WalkStaticOptimization { frames: ours.reference.len(), largest_gap: f64::NEG_INFINITY, smallest_gap: f64::INFINITY, ..Default::default() };
    for frame in &ours.reference {
        comparison.violation.update(frame.violation, || format!("t = {} s", frame.time));
        comparison.bound_violation = comparison.bound_violation.max(frame.bound_violation);
        let gap = (frame.objective - frame.our_objective) / frame.our_objective.max(0.01);
        (comparison.largest_gap, comparison.smallest_gap) = (comparison.largest_gap.max(gap), comparison.smallest_gap.min(gap));
    }
    let our_rows: Vec<(&[f64], &[f64])> = ours.activations.rows().zip(ours.forces.rows()).collect();
    for (control, force) in activations.rows().zip(forces.rows()) {
        let Some((our_control, our_force)) = our_rows.iter().find(|(a, _)| (a[0] - control[0]).abs() <= 1e-9) else {
            comparison.unit_force.update(f64::INFINITY, || format!("t = {} s: no such row of ours", control[0]));
            continue;
        };
        for j in 1..activations.n_columns().min(our_control.len()) {
            // A control of exactly 0 (an actuator on a locked coordinate: ours) has no ratio; its
            // force must then be 0.
            let error = if our_control[j] == 0.0 || control[j] == 0.0 {
                our_force[j].abs()
            } else {
                let (unit, our_unit) = (force[j] / control[j], our_force[j] / our_control[j]);
                (unit - our_unit).abs() / unit.abs().max(1.0)
            };
            comparison.unit_force.update(error, || format!("t = {} s, {}", control[0], activations.labels()[j]));
        }
        for j in activations.n_columns()..forces.n_columns() {
            let error = if ours.forces.labels().get(j) == forces.labels().get(j) { (force[j] - our_force[j]).abs() } else { f64::INFINITY };
            comparison.load_records.update(error, || format!("t = {} s, {}", control[0], forces.labels()[j]));
        }
    }
    comparison
}

/// One of OpenSim 4.6's AnalyzeTool runs of `oracle/gen_static_optimization.py`
/// (`fixtures/golden/static_optimization/<case>/`), with the bounds our tests and
/// `cargo xtask validate` hold it to.
pub struct StaticOptimizationCase {
    pub case: &'static str,
    /// Repository-relative files.
    pub model: &'static str,
    /// The coordinates file, or with `states` the states file.
    pub coordinates: &'static str,
    pub states: bool,
    pub force_set: &'static str,
    pub loads: Option<&'static str>,
    pub settings: StaticOptimizationSettings,
    /// OpenSim's controls against our constraints (N·m or N): its IPOPT or assembly leaves this.
    pub violation: f64,
    /// Forces per unit control against OpenSim's, relative.
    pub unit_force: f64,
}

/// The cases: arm26 (wrapping Thelen muscles, reserves; exponents 2 and 3), leg6dof9musc (its
/// patella coupled to the knee), Rajagopal2016, a parallelogram four-bar (a loop closed by a
/// ConstantDistanceConstraint), the ThoracoscapularShoulderModel (its AC PointConstraint) and the
/// walk with the Thelen-muscle model.
pub fn static_optimization_cases() -> Vec<StaticOptimizationCase> {
    let settings = |time_range: [f64; 2], lowpass_cutoff: Option<f64>, activation_exponent: f64| StaticOptimizationSettings { time_range, lowpass_cutoff, step_interval: 1, use_muscle_physiology: true, activation_exponent };
    let arm = |case, exponent, violation| StaticOptimizationCase {
        case,
        model: "fixtures/models/arm26.osim",
        coordinates: "fixtures/golden/static_optimization/arm26/arm26_motion.mot",
        states: false,
        force_set: "fixtures/golden/static_optimization/arm26/arm26_reserves.xml",
        loads: None,
        settings: settings([0.1, 0.9], None, exponent),
        violation,
        unit_force: 1e-12,
    };
    vec![
        arm("arm26", 2.0, 1e-9),
        // IPOPT meets the constraints less tightly with exponent 3 (found 2.1e-7 N·m).
        arm("arm26_exponent3", 3.0, 1e-6),
        // From a states file (OpenSim's forward simulation of arm26): its coordinates and
        // speeds as they are, the accelerations splined from the speeds. Found 2.1e-14 N·m.
        StaticOptimizationCase {
            case: "arm26_states",
            coordinates: "fixtures/golden/analyze_tool/states/arm26_states.sto",
            states: true,
            settings: settings([0.05, 0.25], None, 2.0),
            ..arm("arm26_states", 2.0, 1e-9)
        },
        // OpenSim's assembly moves the knee within its accuracy while it puts the patella back
        // (found 4.5e-7 N·m and 1.4e-9), see `AnalyzeStates`.
        StaticOptimizationCase {
            case: "leg6dof9musc",
            model: "fixtures/models/leg6dof9musc.osim",
            coordinates: "fixtures/golden/static_optimization/leg6dof9musc/leg_motion.mot",
            states: false,
            force_set: "fixtures/golden/static_optimization/leg6dof9musc/leg_reserves.xml",
            loads: None,
            settings: settings([0.1, 0.9], None, 2.0),
            violation: 1e-6,
            unit_force: 1e-8,
        },
        // OpenSim's IPOPT meets its constraints to 9.0e-5 N·m here (80 muscles, 33 actuators);
        // forces per unit control agree to 4.0e-6, the printing of a control of 1.2e-15 with six
        // digits (lumbar_bend at 0.18 s). The gastrocnemii's lengthening speed over their two
        // wrap cylinders includes OpenSim's stale same-body pairs (`GeometryPath::lengthening_speed`);
        // without them their force was 1.7 % off and OpenSim's controls 1.7e-2 N·m.
        StaticOptimizationCase {
            case: "rajagopal",
            model: "fixtures/models/Rajagopal2016.osim",
            coordinates: "fixtures/golden/forward/rajagopal/motion.mot",
            states: false,
            force_set: "fixtures/golden/static_optimization/rajagopal/rajagopal_reserves.xml",
            loads: None,
            settings: settings([0.1, 0.4], None, 2.0),
            violation: 2e-4,
            unit_force: 1e-5,
        },
        // A closed loop: the ConstantDistanceConstraint's force eliminated along the one motion
        // it allows. IPOPT leaves 1.1e-6 rad/s² of its constraints at 0.34 s (its log): found
        // 6.0e-8 N·m there, 1e-13 elsewhere.
        StaticOptimizationCase {
            case: "parallelogram",
            model: "fixtures/golden/static_optimization/parallelogram/parallelogram.osim",
            coordinates: "fixtures/golden/static_optimization/parallelogram/parallelogram_motion.mot",
            states: false,
            force_set: "fixtures/golden/static_optimization/parallelogram/parallelogram_reserves.xml",
            loads: None,
            settings: settings([0.1, 0.9], None, 2.0),
            violation: 1e-7,
            unit_force: 1e-12,
        },
        // OpenSim's ThoracoscapularShoulderModel (33 Millard muscles wrapping over ellipsoids
        // and cylinders): its AC PointConstraint carries the arm, its force eliminated along the
        // motions the loop allows. Found 1.1e-9 N·m and 1.8e-9.
        StaticOptimizationCase {
            case: "shoulder",
            model: "fixtures/models/ThoracoscapularShoulderModel.osim",
            coordinates: "fixtures/golden/static_optimization/shoulder/shoulder_motion.mot",
            states: false,
            force_set: "fixtures/golden/static_optimization/shoulder/shoulder_reserves.xml",
            loads: None,
            settings: settings([0.1, 0.5], None, 2.0),
            violation: 1e-8,
            unit_force: 1e-8,
        },
        StaticOptimizationCase {
            case: "subject01_thelen",
            model: "fixtures/subject01/OutputReference/subject01_simbody.osim",
            coordinates: "fixtures/golden/ik/subject01_walk1_ik.mot",
            states: false,
            force_set: "fixtures/subject01/gait2392_SO_Residual_Actuators.xml",
            loads: Some("fixtures/subject01/subject01_walk1_grf.xml"),
            settings: settings([0.6, 0.9], Some(6.0), 2.0),
            violation: 1e-9,
            unit_force: 1e-12,
        },
    ]
}

impl StaticOptimizationCase {
    /// Our static optimisation of the case, and OpenSim's tables judged on it.
    pub fn run(&self, root: &Path) -> Result<(StaticOptimizationResult, WalkStaticOptimization), Box<dyn std::error::Error>> {
        let (spec, geometry, generators) = muscles_and_actuators(&root.join(self.model), &root.join(self.force_set))?;
        let loads = self.loads.map(|file| ExternalLoads::read(&root.join(file), &geometry.multibody)).transpose()?.map(|(loads, _)| loads);
        let folder = root.join("fixtures/golden/static_optimization").join(self.case);
        let table = |kind: &str| StorageTable::read(&folder.join(format!("{}_StaticOptimization_{kind}.sto", self.case)));
        let (activations, forces) = (table("activation")?, table("force")?);
        let coordinates = root.join(self.coordinates);
        let reference = ReferenceControls { table: &activations, file: &folder };
        let (input, muscles) = (StorageTable::read(&coordinates)?, muscle_state_names(&spec));
        let result = static_optimization(&geometry, &generators, self.motion(&input, &muscles), &coordinates, loads.as_ref(), &self.settings, Some(reference))?;
        let comparison = compare_static_optimization(&result, &activations, &forces);
        Ok((result, comparison))
    }

    /// The case's input `table` as the tool reads it: a states file's or a coordinates file's
    /// (`muscles`: [`muscle_state_names`] of the model).
    pub fn motion<'a>(&self, table: &'a StorageTable, muscles: &'a [(String, &'static str)]) -> MotionInput<'a> {
        if self.states {
            MotionInput::States { table, muscles }
        } else {
            MotionInput::Coordinates(table)
        }
    }
}

/// The model's geometry and its generators: its own muscles and actuators, then those of the
/// `<ForceSet>` file `force_set`.
pub(super) fn muscles_and_actuators(model: &Path, force_set: &Path) -> Result<(ModelSpec, MuscleGeometry, Vec<Generator>), Box<dyn std::error::Error>> {
    let spec = ModelSpec::read(&OsimDocument::read(model)?)?;
    let geometry = MuscleGeometry::new(&spec)?;
    let actuators = read_force_set(&OsimDocument::read(force_set)?)?;
    let generators = generators(&spec, &geometry, &actuators, false)?;
    Ok((spec, geometry, generators))
}
