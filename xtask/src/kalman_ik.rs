//! Kalman-smoothed IK rows of the validation table: the synthetic-walk study
//! (`validation::kalman_ik`) over seeds and marker noise, printed as a table, with one row
//! that the smoother beats per-frame IK on the coordinates and one that its accelerations beat
//! the ID tool's 6 Hz low-pass of per-frame IK.

use std::time::Instant;

use osim_tune::validation::kalman_ik::{kalman_ik_study, KalmanIkStudy, STUDY_COORDINATES};

use crate::root;
use crate::validate::Row;

const SEEDS: [u64; 3] = [1, 2, 3];
const NOISE_MM: [f64; 2] = [2.0, 5.0];
const CUTOFF: f64 = 6.0;

pub fn rows() -> Vec<Row> {
    let started = Instant::now();
    let mut studies = Vec::new();
    for noise in NOISE_MM {
        for seed in SEEDS {
            match kalman_ik_study(&root(), noise * 1e-3, seed, CUTOFF, 200) {
                Ok(study) => studies.push((noise, seed, study)),
                Err(error) => return vec![failed(&error.to_string())],
            }
        }
    }
    print_study(&studies, started.elapsed().as_secs_f64());
    let ratio = |pick: &dyn Fn(&KalmanIkStudy, usize) -> f64| -> (f64, String) {
        let mut worst = (0.0, String::new());
        for (noise, seed, study) in &studies {
            for (k, name) in STUDY_COORDINATES.iter().enumerate() {
                let r = pick(study, k);
                if r > worst.0 {
                    worst = (r, format!("{name}, {noise} mm, seed {seed}"));
                }
            }
        }
        worst
    };
    let coordinates = ratio(&|s, k| s.coordinate[k][2] / s.coordinate[k][0]);
    let accelerations = ratio(&|s, k| s.acceleration[k][2] / s.acceleration[k][1]);
    vec![
        Row { what: "Kalman IK 6 Hz: q RMS / per-frame IK's".into(), reference: "synthetic walk, known kinematics".into(), worst: coordinates.0, tolerance: 1.0, at: coordinates.1 },
        Row { what: "Kalman IK 6 Hz: q̈ RMS / (IK + ID's 6 Hz low-pass)'s".into(), reference: "synthetic walk, known kinematics".into(), worst: accelerations.0, tolerance: 1.0, at: accelerations.1 },
    ]
}

fn failed(error: &str) -> Row {
    Row { what: "Kalman IK study".into(), reference: "synthetic walk, known kinematics".into(), worst: f64::INFINITY, tolerance: 0.0, at: error.into() }
}

fn print_study(studies: &[(f64, u64, KalmanIkStudy)], seconds: f64) {
    println!(
        "Kalman-smoothed IK, synthetic walk (subject01's IK motion low-passed at 6 Hz as the truth, every model marker with Gaussian noise, {} frames at 60 Hz; {seconds:.1} s): RMS errors",
        studies.first().map_or(0, |s| s.2.frames)
    );
    println!("{:<6} {:<5} {:<14} {:>27} {:>33}", "noise", "seed", "coordinate", "q ° IK / IK+6 Hz / Kalman", "q̈ °/s² IK / IK+6 Hz / Kalman");
    for (noise, seed, study) in studies {
        for (k, name) in STUDY_COORDINATES.iter().enumerate() {
            let (q, a) = (study.coordinate[k].map(f64::to_degrees), study.acceleration[k].map(f64::to_degrees));
            println!("{noise:>3} mm {seed:<5} {name:<14} {:>8.3} {:>8.3} {:>8.3} {:>10.0} {:>10.0} {:>10.0}", q[0], q[1], q[2], a[0], a[1], a[2]);
        }
    }
    println!();
}
