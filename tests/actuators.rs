//! CoordinateActuator, PointActuator and TorqueActuator against OpenSim 4.6
//! (`fixtures/golden/actuators/`, `oracle/gen_actuators.py`): the residual actuators of
//! subject01's static optimisation (a 2.x `<ForceSet>` file) and three built ones (a 4.x file:
//! a point given in ground with a direction in the body, an axis in body A, neither of unit
//! length) on gait2392, read as OpenSim reads them and their generalized forces per unit
//! actuation at 6 random poses; and the actuators of a model's ForceSet.

mod common;

use common::golden_rows::rows;
use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::{Actuator, Multibody};
use osim_tune::model::{read_force_set, ActuatorKind, ActuatorSpec, ModelSpec};
use osim_tune::validation::{GoldenPoses, GoldenTable};

fn model(relative: &str) -> ModelSpec {
    ModelSpec::read(&OsimDocument::read(&common::root().join(relative)).unwrap()).unwrap_or_else(|e| panic!("{e}"))
}

/// The residual actuators, then the built ones, as the oracle appended them to the model.
fn golden_actuators() -> Vec<ActuatorSpec> {
    ["subject01/gait2392_SO_Residual_Actuators.xml", "golden/actuators/extra_actuators.xml"]
        .iter()
        .flat_map(|file| read_force_set(&OsimDocument::read(&common::fixture(file)).unwrap()).unwrap_or_else(|e| panic!("{e}")))
        .collect()
}

fn golden(file: &str) -> GoldenTable {
    GoldenTable::read(&common::fixture(&format!("golden/actuators/{file}"))).unwrap()
}

#[test]
fn force_set_files_read_as_opensim_reads_them() {
    let actuators = golden_actuators();
    let table = golden("actuators.csv");
    assert_eq!(actuators.len(), table.rows.len());
    for (actuator, row) in actuators.iter().zip(rows(&table)) {
        assert_eq!((actuator.name.as_str(), actuator.class.as_str()), (row.text("actuator"), row.text("class")));
        let bounds = (actuator.optimal_force, actuator.min_control, actuator.max_control);
        assert_eq!(bounds, (row.number("optimal_force"), row.number("min_control"), row.number("max_control")), "{}", actuator.name);
        assert_eq!(actuator.applies_force.to_string(), row.text("applies_force"));
    }
    let fx = ActuatorKind::Point { body: "pelvis".into(), point: [-0.0724376, 0.0, 0.0], point_is_global: false, direction: [-1.0, -0.0, -0.0], force_is_global: true };
    assert_eq!(actuators[0].kind, fx);
    let mz = ActuatorKind::Torque { body_a: "pelvis".into(), body_b: "ground".into(), axis: [-0.0, -0.0, -1.0], torque_is_global: true };
    assert_eq!(actuators[5].kind, mz);
}

/// Generalized forces of a unit actuation within 1e-12 of OpenSim's, relative to max(1, |τ|)
/// (found: ≤ 3.4e-16, the point actuators' rounding; the coordinate and torque actuators agree
/// bit for bit).
#[test]
fn generalized_forces_agree_with_opensim() {
    let multibody = Multibody::new(&model("models/gait2392_millard2012muscle.osim")).unwrap();
    let actuators: Vec<Actuator> = golden_actuators().iter().map(|spec| Actuator::new(spec, &multibody).unwrap_or_else(|e| panic!("{e}"))).collect();
    let poses = GoldenPoses::read(&common::fixture("golden/actuators/poses.csv"), &multibody).unwrap();
    let table = golden("generalized_forces.csv");
    assert_eq!(table.rows.len(), poses.ids.len() * actuators.len() * multibody.coordinates.len());
    let mut kinematics = multibody.kinematics();
    let mut forces = vec![0.0; multibody.coordinates.len()];
    let (mut worst, mut at) = (0.0_f64, String::new());
    let mut current = None;
    for r in 0..table.rows.len() {
        let (pose, name, coordinate) = (table.text_at(r, "pose_id").unwrap(), table.text_at(r, "actuator").unwrap(), table.text_at(r, "coordinate").unwrap());
        if current != Some((pose, name)) {
            multibody.realize(&poses.values[pose], &mut kinematics);
            let actuator = actuators.iter().find(|a| a.name == name).unwrap();
            actuator.generalized_forces(&multibody, &kinematics, &mut forces);
            current = Some((pose, name));
        }
        let ours = forces[multibody.coordinate_index(coordinate).unwrap()];
        let expected = table.number_at(r, "generalized_force").unwrap();
        let error = (ours - expected).abs() / expected.abs().max(1.0);
        if error > worst {
            (worst, at) = (error, format!("{pose} {name} {coordinate}: {ours} vs {expected}"));
        }
    }
    assert!(worst <= 1e-12, "off by {worst:e} at {at}");
}

/// Rajagopal2016's ForceSet holds 17 CoordinateActuators among its muscles (optimal force 10,
/// controls unbounded as `-Inf`/`Inf`, applied — as OpenSim 4.6 reads them); each drives its
/// coordinate alone.
#[test]
fn a_models_force_set_actuators() {
    let spec = model("fixtures/models/Rajagopal2016.osim");
    assert_eq!(spec.actuators.len(), 17);
    assert!(model("models/gait2392_millard2012muscle.osim").actuators.is_empty());
    let multibody = Multibody::new(&spec).unwrap();
    let mut kinematics = multibody.kinematics();
    multibody.realize(&multibody.default_pose(), &mut kinematics);
    let mut forces = vec![0.0; multibody.coordinates.len()];
    for actuator in &spec.actuators {
        assert_eq!((actuator.optimal_force, actuator.min_control, actuator.max_control, actuator.applies_force), (10.0, f64::NEG_INFINITY, f64::INFINITY, true));
        let ActuatorKind::Coordinate { coordinate } = &actuator.kind else { panic!("{}: {:?}", actuator.name, actuator.kind) };
        Actuator::new(actuator, &multibody).unwrap().generalized_forces(&multibody, &kinematics, &mut forces);
        let index = multibody.coordinate_index(coordinate).unwrap();
        assert!(forces.iter().enumerate().all(|(c, &f)| f == if c == index { 1.0 } else { 0.0 }), "{}", actuator.name);
    }
}

/// A residual file whose actuator names a body the model lacks fails to compile, naming file,
/// line and actuator.
#[test]
fn an_unknown_body_names_the_actuator() {
    let multibody = Multibody::new(&model("fixtures/models/arm26.osim")).unwrap();
    let residuals = &golden_actuators()[0];
    let message = Actuator::new(residuals, &multibody).unwrap_err().to_string();
    assert!(message.contains("gait2392_SO_Residual_Actuators.xml") && message.contains("PointActuator FX (line 256)") && message.contains("\"pelvis\""), "{message}");
}
