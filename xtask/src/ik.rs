//! Inverse-kinematics rows of the validation table: subject01 walk1 against OpenSim 4.6 at the
//! setup's accuracy (1e-5) and run to convergence (1e-10), with `from_file` coordinate tasks,
//! OpenSim's constrained shoulder case
//! (a PointConstraint) and the linked mechanisms (every constraint class between bodies) at
//! 1e-10.

use osim_tune::validation::ik::{compare_ik, IkCase, IkFrames};

use crate::root;
use crate::validate::Row;

pub fn rows() -> Vec<Row> {
    let cases = [
        ("walk1", "accuracy 1e-5", IkCase::subject01_walk1(&root())),
        ("walk1", "accuracy 1e-10", IkCase::subject01_walk1_converged(&root())),
        ("walk1 with from_file coordinate tasks", "accuracy 1e-10", IkCase::subject01_coordinate_file(&root())),
        ("shoulder (PointConstraint)", "accuracy 1e-10", IkCase::shoulder_point_constraint(&root())),
        ("linked mechanisms (point, distance, point-on-line, weld)", "accuracy 1e-10", IkCase::linked_mechanisms(&root())),
    ];
    cases.into_iter().flat_map(|(trial, label, case)| case_rows(trial, label, &case)).collect()
}

fn case_rows(trial: &str, label: &str, case: &IkCase) -> Vec<Row> {
    let reference = format!("OpenSim 4.6 IK, {label}");
    let comparison = match compare_ik(case, IkFrames::Trial) {
        Ok(comparison) => comparison,
        Err(error) => return vec![Row { what: format!("IK {trial} ({label})"), reference, worst: f64::INFINITY, tolerance: 0.0, at: error.to_string() }],
    };
    let coordinate = |rotational: bool| comparison.coordinates.iter().filter(|c| c.rotational == rotational).max_by(|a, b| a.worst.total_cmp(&b.worst)).cloned();
    let mut rows = Vec::new();
    for (rotational, unit) in [(true, "°"), (false, "m")] {
        if let Some(c) = coordinate(rotational) {
            rows.push(Row { what: format!("IK {trial} coordinates ({unit}), {} frames", comparison.frames), reference: reference.clone(), worst: c.worst, tolerance: c.tolerance, at: format!("{} at t = {} s", c.name, c.at) });
        }
    }
    rows.push(Row {
        what: format!("IK {trial} objective, ours − OpenSim's (relative, worst frame)"),
        reference,
        worst: comparison.objective_excess,
        tolerance: comparison.objective_slack,
        at: format!("{} unconverged frames", comparison.unconverged),
    });
    rows
}
