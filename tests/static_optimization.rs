//! Static optimisation of subject01's walk against OpenSim 4.6's StaticOptimization (the pipeline
//! golden: AnalyzeTool with subject01's IK, 6 Hz low-pass, GRF on both feet, the six residual
//! actuators, activation exponent 2, muscle physiology; every 5th of its 95 rows in
//! `fixtures/golden/static_optimization/`).
//!
//! OpenSim's IPOPT stops at its convergence criterion (1e-4), ours at the QP's optimum, so the
//! controls are compared through the problem: OpenSim's controls must satisfy our constraints
//! (generalized forces = inverse dynamics) to rounding — which checks every muscle's force at
//! activation 1, its moment arms, the actuators, the loads and the tracked accelerations — and
//! cost no less than ours.

mod common;

use osim_tune::analysis::{generators, static_optimization, ExternalLoads, ReferenceControls, StaticOptimizationResult, StaticOptimizationSettings};
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::StorageTable;
use osim_tune::mechanics::MuscleGeometry;
use osim_tune::model::{read_force_set, ModelSpec};
use osim_tune::setup::ExternalLoadsSetup;

fn golden(kind: &str) -> StorageTable {
    StorageTable::read(&common::fixture(&format!("golden/static_optimization/subject01_walk1_StaticOptimization_{kind}.sto"))).unwrap()
}

fn walk(reference: &StorageTable) -> StaticOptimizationResult {
    let spec = ModelSpec::read(&OsimDocument::read(&common::fixture("golden/scale/subject01_simbody.osim")).unwrap()).unwrap();
    let geometry = MuscleGeometry::new(&spec).unwrap();
    let residuals = read_force_set(&OsimDocument::read(&common::fixture("subject01/gait2392_SO_Residual_Actuators.xml")).unwrap()).unwrap();
    let generators = generators(&spec, &geometry, &residuals, false).unwrap();
    let setup = ExternalLoadsSetup::read(&common::fixture("subject01/subject01_walk1_grf.xml")).unwrap();
    let data_file = setup.datafile.clone().unwrap().resolved;
    let loads = ExternalLoads::new(&setup, &StorageTable::read(&data_file).unwrap(), &data_file, &geometry.multibody).unwrap();
    let ik = common::fixture("golden/ik/subject01_walk1_ik.mot");
    let settings = StaticOptimizationSettings { time_range: [0.5, 2.0], lowpass_cutoff: Some(6.0), step_interval: 1, use_muscle_physiology: true };
    let reference = ReferenceControls { table: reference, file: &common::fixture("golden/static_optimization") };
    static_optimization(&geometry, &generators, &StorageTable::read(&ik).unwrap(), &ik, Some(&loads), &settings, Some(reference)).unwrap()
}

#[test]
fn opensims_controls_solve_our_problem_and_cost_no_less_than_ours() {
    let activations = golden("activation");
    let result = walk(&activations);
    assert!(result.failures.is_empty(), "{:?}", result.failures);
    assert!(result.max_violation <= 1e-9, "our constraint violation {:e}", result.max_violation);
    assert_eq!(result.activations.labels(), activations.labels());
    assert_eq!(result.activations.n_rows(), 95, "OpenSim solved 95 rows, 0.494–1.998 s");
    assert_eq!(result.reference.len(), activations.n_rows(), "every golden row's time is one of ours");
    for frame in &result.reference {
        assert!(frame.violation <= 1e-9, "t = {}: OpenSim's controls miss our constraints by {:e} N·m", frame.time, frame.violation);
        assert!(frame.bound_violation == 0.0, "t = {}: OpenSim's controls leave our bounds by {:e}", frame.time, frame.bound_violation);
        assert!(frame.objective >= frame.our_objective * (1.0 - 1e-12), "t = {}: OpenSim's Σa² {} below ours {}", frame.time, frame.objective, frame.our_objective);
        assert!(frame.objective <= frame.our_objective * 1.002, "t = {}: OpenSim's Σa² {} more than 0.2 % above ours {}", frame.time, frame.objective, frame.our_objective);
    }
}

/// Force per unit control (a muscle's force at activation 1 with a rigid tendon, or an actuator's
/// optimal force) and the external loads' records equal OpenSim's, row by row.
#[test]
fn unit_forces_and_load_records_equal_opensims() {
    let (activations, forces) = (golden("activation"), golden("force"));
    let result = walk(&activations);
    assert_eq!(result.forces.labels(), forces.labels());
    let ours: Vec<(&[f64], &[f64])> = result.activations.rows().zip(result.forces.rows()).collect();
    let generators = activations.n_columns() - 1;
    for (control, force) in activations.rows().zip(forces.rows()) {
        let (our_control, our_force) = ours.iter().find(|(a, _)| (a[0] - control[0]).abs() <= 1e-9).unwrap();
        for j in 1..=generators {
            let (unit, our_unit) = (force[j] / control[j], our_force[j] / our_control[j]);
            assert!((unit - our_unit).abs() <= 1e-9 * unit.abs().max(1.0), "t = {}: {} {unit} vs ours {our_unit}", control[0], forces.labels()[j]);
        }
        for j in generators + 1..forces.n_columns() {
            assert!((force[j] - our_force[j]).abs() <= 1e-9, "t = {}: {} {} vs ours {}", control[0], forces.labels()[j], force[j], our_force[j]);
        }
    }
}
