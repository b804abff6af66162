//! Inverse kinematics against OpenSim 4.6 and from first principles.

mod common;

use osim_tune::validation::ik::{compare_ik, IkCase, IkFrames};

#[test]
fn subject01_walk1_matches_opensim() {
    let case = IkCase::subject01_walk1(&common::root());
    let start = std::time::Instant::now();
    let comparison = compare_ik(&case, IkFrames::Trial).unwrap();
    eprintln!("{:?}", start.elapsed());
    for c in &comparison.coordinates {
        eprintln!("{:<20} {:>12.3e} at {}", c.name, c.worst, c.at);
    }
    eprintln!("{comparison:#?}");
    assert!(comparison.passes());
}
