//! Dynamics rows of the validation table: inverse dynamics at random states of five models
//! against OpenSim 4.6's `InverseDynamicsSolver`, and subject01's walk through OpenSim 4.6's
//! InverseDynamicsTool and StaticOptimization (all 95 rows of the latter when
//! `../shared/reference` or `$OSIM_TUNE_REFERENCE` has the pipeline goldens, else the fixture
//! slice), and the physiological inverse approach on the walk against static optimisation and
//! first principles (OpenSim has none), and muscle-driven forward simulation along prescribed
//! kinematics against OpenSim 4.6's integration of the same prescribed model, joint reactions
//! against OpenSim 4.6's JointReaction analysis, and the extended dynamometer set-up against
//! OpenSim 4.6's inverse dynamics with the pad's load known.

use std::path::PathBuf;

use osim_tune::analysis::{Contraction, Criterion, PhysiologicalInverseSettings, MAX_LINEARISATIONS};
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::mechanics::Multibody;
use osim_tune::model::ModelSpec;
use osim_tune::validation::{
    compare_forward, compare_inverse_dynamics, compare_static_optimization, static_optimization_cases, DynamometerCase, ForwardCase, JointReactionCase, StaticOptimizationCase, Subject01Walk,
    DYNAMOMETER_CASES, FORWARD_CASES, JOINT_REACTION_CASES,
};
use osim_tune::validation::{compare_forward_tool, FORWARD_TOOL_CASES, FORWARD_TOOL_VALIDATE_CASES};

use crate::root;
use crate::validate::Row;

const RANDOM_STATE_MODELS: [(&str, &str); 5] = [
    ("gait2392_millard2012muscle", "models/gait2392_millard2012muscle.osim"),
    ("arm26", "fixtures/models/arm26.osim"),
    ("leg6dof9musc", "fixtures/models/leg6dof9musc.osim"),
    ("Rajagopal2016", "fixtures/models/Rajagopal2016.osim"),
    ("joint_zoo", "fixtures/models/joint_zoo.osim"),
];

pub fn rows() -> Vec<Row> {
    let mut rows: Vec<Row> = RANDOM_STATE_MODELS.iter().map(|(stem, model)| random_states(stem, model)).collect();
    match Subject01Walk::load(&root()) {
        Ok(walk) => {
            rows.extend(walk_inverse_dynamics(&walk));
            rows.extend(walk_static_optimization(&walk));
            rows.extend(walk_physiological_inverse(&walk));
            rows.extend(static_optimization_cases().iter().flat_map(other_static_optimization));
        }
        Err(error) => rows.push(failed("subject01 walk inputs", "OpenSim 4.6 pipeline", error.to_string())),
    }
    rows.extend(FORWARD_CASES.iter().flat_map(forward));
    rows.extend(FORWARD_TOOL_CASES.iter().chain(&FORWARD_TOOL_VALIDATE_CASES).flat_map(|case| forward_tool(case)));
    rows.extend(JOINT_REACTION_CASES.iter().flat_map(joint_reaction));
    rows.extend(DYNAMOMETER_CASES.iter().flat_map(dynamometer));
    rows
}

/// The extended dynamometer set-up (thesis ch. 5): from the load cell, the knee moment, the
/// pad's load and the dynamometer's reading against OpenSim's inverse dynamics with the pad's
/// load known, and Herzog's estimate where it is exact.
fn dynamometer(case: &DynamometerCase) -> Vec<Row> {
    let reference = "OpenSim 4.6 InverseDynamicsTool, pad load known";
    match case.compare(&root()) {
        Ok(c) => [(Some(&c.knee_moment), "M3D (N·m)"), (Some(&c.pad_load), "pad force, moment (N, N·m)"), (Some(&c.dynamometer_moment), "dynamometer reading (N·m)"), (c.herzog.as_ref(), "Herzog M2D, exact here (N·m)")]
            .into_iter()
            .filter_map(|(w, what)| Some(Row { what: format!("dynamometer, {}: {what}", case.case), reference: reference.into(), worst: w?.error, tolerance: case.tolerance, at: w?.at.clone() }))
            .collect(),
        Err(error) => vec![failed(&format!("dynamometer, {}", case.case), reference, error.to_string())],
    }
}

/// Every joint's load on its child and on its parent, driven by OpenSim's static optimisation
/// forces; each case's bounds are OpenSim's assembly (see `JOINT_REACTION_CASES`).
fn joint_reaction(case: &JointReactionCase) -> Vec<Row> {
    let reference = "OpenSim 4.6 JointReaction";
    match case.compare(&root()) {
        Ok(c) => ["child", "parent"]
            .iter()
            .enumerate()
            .flat_map(|(k, side)| {
                [(&c.loads[k], case.load, "force, moment (N, N·m)"), (&c.points[k], case.point, "point (m)")]
                    .map(|(w, tolerance, what)| Row { what: format!("joint reaction, {} on {side}: {what}", case.case), reference: reference.into(), worst: w.error, tolerance, at: w.at.clone() })
            })
            .collect(),
        Err(error) => vec![failed(&format!("joint reaction, {}", case.case), reference, error.to_string())],
    }
}

/// States, tendon forces and generalized forces of a forward simulation at accuracy 1e-12;
/// OpenSim's run at 1e-10 carries its own integration error (see `tests/forward.rs`).
fn forward(case: &ForwardCase) -> Vec<Row> {
    let reference = "OpenSim 4.6 Manager, RK-Merson 1e-10";
    match compare_forward(&root(), case, 1e-12, false) {
        Ok(c) => [(&c.activation, case.activation_tolerance, "activation"), (&c.fiber_length, case.fiber_length_tolerance, "fiber length (m)"), (&c.tendon_force, 5e-5, "tendon force (rel.)"), (&c.generalized_force, 5e-5, "muscle generalized force (rel.)")]
            .into_iter()
            .map(|(w, tolerance, what)| Row { what: format!("forward simulation, {}: {what}", case.case), reference: reference.into(), worst: w.error, tolerance, at: w.at.clone() })
            .collect(),
        Err(error) => vec![failed(&format!("forward simulation, {}", case.case), reference, error)],
    }
}

/// A ForwardTool golden: our states at OpenSim's recorded times (both integrators at 1e-9 per
/// state and step, so the bounds are the two integrations' global errors) and the controls.
fn forward_tool(case: &str) -> Vec<Row> {
    match compare_forward_tool(&root(), case) {
        Ok(c) => {
            let reference = format!("OpenSim 4.6 ForwardTool (tolerance {:e})", c.tolerance);
            let rows = [(c.value, 1e-6, "coordinate values (rad)"), (c.speed, 3e-5, "speeds (rad/s)"), (c.activation, 1e-6, "activations"), (c.fiber_length, 2e-7, "fiber lengths (m)"), (c.control, 1e-12, "controls"), ((c.start[0] - c.start[1]).abs(), 1e-15, "initial time (s)")];
            rows.into_iter().map(|(worst, tolerance, what)| Row { what: format!("ForwardTool {case}: {what}"), reference: reference.clone(), worst, tolerance, at: format!("{} rows", c.rows) }).collect()
        }
        Err(error) => vec![failed(&format!("ForwardTool {case}"), "OpenSim 4.6 ForwardTool", error)],
    }
}

fn failed(what: &str, reference: &str, error: String) -> Row {
    Row { what: what.into(), reference: reference.into(), worst: f64::INFINITY, tolerance: 0.0, at: error }
}

/// Generalized forces relative to max(1, |τ|) at 8 random (q, u, u̇).
fn random_states(stem: &str, model: &str) -> Row {
    let (what, reference) = (format!("inverse dynamics, random states, {stem}"), "OpenSim 4.6 InverseDynamicsSolver");
    let compared = OsimDocument::read(&root().join(model))
        .map_err(|e| e.to_string())
        .and_then(|document| ModelSpec::read(&document).map_err(|e| e.to_string()))
        .and_then(|spec| Multibody::new(&spec).map_err(|e| e.to_string()))
        .and_then(|multibody| compare_inverse_dynamics(&multibody, &root().join(format!("fixtures/golden/inverse_dynamics/{stem}.csv"))).map_err(|e| e.to_string()));
    match compared {
        Ok(worst) => Row { what, reference: reference.into(), worst: worst.error, tolerance: 1e-12, at: worst.at },
        Err(error) => failed(&what, reference, error),
    }
}

/// The pipeline golden's folder, when present.
fn pipeline_folder() -> Option<PathBuf> {
    let reference = std::env::var_os("OSIM_TUNE_REFERENCE").map(PathBuf::from).unwrap_or_else(|| root().join("../shared/reference"));
    Some(reference.join("pipelines/gait2392_subject01")).filter(|f| f.join("subject01_walk1_StaticOptimization_activation.sto").exists())
}

/// Every generalized force against OpenSim's table (printed to 8 decimals).
fn walk_inverse_dynamics(walk: &Subject01Walk) -> Vec<Row> {
    let cases = [
        ("ID tool, subject01 walk, 76 frames (N·m, N)", "subject01_walk1_InverseDynamics.sto", false),
        ("ID tool body forces at all 12 joints, subject01 walk (N, N·m)", "subject01_walk1_body_forces.sto", true),
    ];
    let reference = "OpenSim 4.6 InverseDynamicsTool (1e-8)";
    cases
        .into_iter()
        .map(|(what, file, body_forces)| {
            let golden = StorageTable::read(&root().join("fixtures/golden/inverse_dynamics").join(file));
            match golden.map_err(|e| e.to_string()).and_then(|g| walk.inverse_dynamics(&g, body_forces).map_err(|e| e.to_string())) {
                Ok(worst) => Row { what: what.into(), reference: reference.into(), worst: worst.error, tolerance: 6e-9, at: worst.at },
                Err(error) => failed(what, reference, error),
            }
        })
        .collect()
}

/// OpenSim's controls judged on our problem, and its forces per unit control.
fn walk_static_optimization(walk: &Subject01Walk) -> Vec<Row> {
    let (folder, reference) = match pipeline_folder() {
        Some(folder) => (folder, "OpenSim 4.6 StaticOptimization, 95 rows"),
        None => (root().join("fixtures/golden/static_optimization"), "OpenSim 4.6 StaticOptimization, slice"),
    };
    let table = |kind: &str| StorageTable::read(&folder.join(format!("subject01_walk1_StaticOptimization_{kind}.sto"))).map_err(|e| e.to_string());
    let compared = table("activation").and_then(|activations| {
        let forces = table("force")?;
        let result = walk.static_optimization(&activations, &folder).map_err(|e| e.to_string())?;
        let failures = result.failures.len();
        Ok((compare_static_optimization(&result, &activations, &forces), result.max_violation, failures))
    });
    let (c, our_violation, failures) = match compared {
        Ok(compared) => compared,
        Err(error) => return vec![failed("SO walk", reference, error)],
    };
    let row = |what: &str, worst: f64, tolerance: f64, at: String| Row { what: what.into(), reference: reference.into(), worst, tolerance, at };
    vec![
        row("SO walk: our frames without a solution", failures as f64, 0.0, String::new()),
        row("SO walk: our |Σ a·F·R − τ_ID| (N·m, N)", our_violation, 1e-9, String::new()),
        row("SO walk: OpenSim's controls on our constraints (N·m, N)", c.violation.error, 1e-9, format!("{} frames; {}", c.frames, c.violation.at)),
        row("SO walk: OpenSim's controls outside our bounds", c.bound_violation, 0.0, String::new()),
        row("SO walk: OpenSim's Σa² below ours (relative)", (-c.smallest_gap).max(0.0), 1e-12, String::new()),
        row("SO walk: OpenSim's Σa² above ours (IPOPT at 1e-4)", c.largest_gap, 2e-3, String::new()),
        row("SO walk: force per unit control (relative)", c.unit_force.error, 1e-9, c.unit_force.at),
        row("SO walk: external load records (N, m, N·m)", c.load_records.error, 1e-9, c.load_records.at),
    ]
}

/// One of the other OpenSim runs: its controls on our problem, and its forces per unit control.
fn other_static_optimization(case: &StaticOptimizationCase) -> Vec<Row> {
    let reference = "OpenSim 4.6 StaticOptimization";
    match case.run(&root()) {
        Ok((result, c)) => {
            let unsolved = if result.failures.is_empty() { 0.0 } else { f64::INFINITY };
            let constraints = c.violation.error.max(c.bound_violation).max(unsolved);
            vec![
                Row { what: format!("SO {}: OpenSim's controls on our constraints", case.case), reference: reference.into(), worst: constraints, tolerance: case.violation, at: format!("{} frames; {}", c.frames, c.violation.at) },
                Row { what: format!("SO {}: our Σ|a|ᵖ above OpenSim's (relative)", case.case), reference: reference.into(), worst: (-c.smallest_gap).max(0.0), tolerance: case.violation, at: String::new() },
                Row { what: format!("SO {}: OpenSim's Σ|a|ᵖ above ours (relative)", case.case), reference: reference.into(), worst: c.largest_gap, tolerance: 0.05, at: String::new() },
                Row { what: format!("SO {}: force per unit control (relative)", case.case), reference: reference.into(), worst: c.unit_force.error, tolerance: case.unit_force, at: c.unit_force.at },
            ]
        }
        Err(error) => vec![failed(&format!("SO {}", case.case), reference, error.to_string())],
    }
}

/// PIA with activation dynamics made immaterial against static optimisation, and with the
/// model's time constants against inverse dynamics — with rigid tendons (a·F₁) and with the Hill
/// model's compliant-tendon equilibrium forces once the linearised re-solves settle.
fn walk_physiological_inverse(walk: &Subject01Walk) -> Vec<Row> {
    let reference = "static optimisation / first principles";
    let golden = root().join("fixtures/golden/static_optimization");
    let compared = StorageTable::read(&golden.join("subject01_walk1_StaticOptimization_activation.sto")).map_err(|e| e.to_string()).and_then(|activations| {
        let so = walk.static_optimization(&activations, &golden).map_err(|e| e.to_string())?;
        let free = walk.physiological_inverse(&Subject01Walk::pia_settings(Criterion::SumOfSquares, 1e-6)).map_err(|e| e.to_string())?;
        let bound = walk.physiological_inverse(&Subject01Walk::pia_settings(Criterion::MinMax, 1.0)).map_err(|e| e.to_string())?;
        let compliant = PhysiologicalInverseSettings { contraction: Contraction::CompliantTendon { max_linearisations: MAX_LINEARISATIONS }, ..Subject01Walk::pia_settings(Criterion::MinMax, 1.0) };
        let compliant = walk.physiological_inverse(&compliant).map_err(|e| e.to_string())?;
        let difference = free.activations.values().iter().zip(so.activations.values()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        Ok((difference, bound.max_violation, compliant))
    });
    match compared {
        Ok((difference, violation, compliant)) => vec![
            Row { what: "PIA walk, dynamics immaterial: |a − SO's a|".into(), reference: reference.into(), worst: difference, tolerance: 2e-5, at: String::new() },
            Row { what: "PIA walk, min–max: |Σ a·F·R − τ_ID| (N·m, N)".into(), reference: reference.into(), worst: violation, tolerance: 1e-6, at: String::new() },
            Row {
                what: "PIA walk, min–max, compliant tendons: |Σ F(a)·R − τ_ID| (N·m, N)".into(),
                reference: reference.into(),
                worst: compliant.max_violation,
                tolerance: 1e-6,
                at: format!("{} re-solves", compliant.iterations),
            },
        ],
        Err(error) => vec![failed("PIA walk", reference, error)],
    }
}
