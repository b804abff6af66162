//! Inverse-kinematics rows of the validation table: subject01 walk1 against OpenSim 4.6 at the
//! setup's accuracy (1e-5) and run to convergence (1e-10).

use osim_tune::validation::ik::{compare_ik, IkCase, IkFrames};

use crate::root;
use crate::validate::Row;

pub fn rows() -> Vec<Row> {
    let cases = [("accuracy 1e-5", IkCase::subject01_walk1(&root())), ("accuracy 1e-10", IkCase::subject01_walk1_converged(&root()))];
    cases.into_iter().flat_map(|(label, case)| case_rows(label, &case)).collect()
}

fn case_rows(label: &str, case: &IkCase) -> Vec<Row> {
    let reference = format!("OpenSim 4.6 IK, {label}");
    let comparison = match compare_ik(case, IkFrames::Trial) {
        Ok(comparison) => comparison,
        Err(error) => return vec![Row { what: format!("IK subject01 walk1 ({label})"), reference, worst: f64::INFINITY, tolerance: 0.0, at: error.to_string() }],
    };
    let coordinate = |rotational: bool| comparison.coordinates.iter().filter(|c| c.rotational == rotational).max_by(|a, b| a.worst.total_cmp(&b.worst)).cloned();
    let mut rows = Vec::new();
    for (rotational, unit) in [(true, "°"), (false, "m")] {
        if let Some(c) = coordinate(rotational) {
            rows.push(Row { what: format!("IK walk1 coordinates ({unit}), 151 frames"), reference: reference.clone(), worst: c.worst, tolerance: c.tolerance, at: format!("{} at t = {} s", c.name, c.at) });
        }
    }
    rows.push(Row {
        what: "IK walk1 objective, ours − OpenSim's (relative, worst frame)".into(),
        reference,
        worst: comparison.objective_excess,
        tolerance: osim_tune::validation::ik::OBJECTIVE_SLACK,
        at: format!("{} unconverged frames", comparison.unconverged),
    });
    rows
}
