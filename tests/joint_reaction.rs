//! Joint reactions against OpenSim 4.6's JointReaction analyses (`oracle/gen_joint_reaction.py`),
//! driven by OpenSim's own static optimisation forces; each case states its bounds and why.

use std::path::Path;

use osim_tune::validation::JOINT_REACTION_CASES;

#[test]
fn joint_reactions_match_opensim() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for case in &JOINT_REACTION_CASES {
        let comparison = case.compare(root).unwrap();
        for (k, side) in ["child", "parent"].iter().enumerate() {
            let (loads, points) = (&comparison.loads[k], &comparison.points[k]);
            println!("{} on {side}: loads {:.2e} at {} ({} values), points {:.2e}", case.case, loads.error, loads.at, loads.count, points.error);
            assert!(loads.count > 900, "{}: only {} values compared", case.case, loads.count);
            assert!(loads.error <= case.load, "{} on {side}: {:e} N or N·m at {}", case.case, loads.error, loads.at);
            assert!(points.error <= case.point, "{} on {side}: {:e} m at {}", case.case, points.error, points.at);
        }
    }
}
