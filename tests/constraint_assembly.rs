//! Constraints between bodies as OpenSim 4.6 holds them (`oracle/gen_constraint_assembly.py`):
//! the default pose `initSystem` assembles, and inverse kinematics with every link class.

mod common;

use osim_tune::io::osim::OsimDocument;
use osim_tune::mechanics::Multibody;
use osim_tune::model::ModelSpec;
use osim_tune::solvers::assemble;
use osim_tune::validation::compare_assembly;
use osim_tune::validation::ik::{compare_ik, IkCase, IkFrames};

/// The largest coordinate (rad or m) and marker (m) differences of our assembled default pose
/// from OpenSim's.
fn assembled_differences(model: &str) -> (f64, f64) {
    let comparison = compare_assembly(&common::root(), model).unwrap_or_else(|e| panic!("{e}"));
    assert!(comparison.markers.count > 0);
    (comparison.coordinates.error, comparison.markers.error)
}

/// Five mechanisms whose default values break their constraints (a point loop, a constant
/// distance, a point on a line with a coordinate free to satisfy it, a weld, a coupler driven
/// through the weld): assembly moves them as OpenSim's does, to OpenSim's assembly accuracy
/// (1e-12 in the model; the nearest-pose problem is well conditioned here).
#[test]
fn the_default_pose_of_linked_mechanisms_is_assembled_as_opensim_assembles_it() {
    let (coordinates, markers) = assembled_differences("linked_mechanisms.osim");
    assert!(coordinates < 1e-9 && markers < 1e-9, "{coordinates:e} rad or m, {markers:e} m");
}

/// A model whose only constraint is a coupler: the dependent follows its independent
/// coordinate (2e-8 rad from its own default value); OpenSim's assembler, at its default
/// accuracy 1e-9, leaves the others within 5e-10 of their defaults.
#[test]
fn a_coupled_default_pose_follows_the_coupler() {
    let (coordinates, markers) = assembled_differences("leg6dof9musc.osim");
    assert!(coordinates < 1e-9 && markers < 1e-9, "{coordinates:e} rad or m, {markers:e} m");
    let path = common::fixture("models/leg6dof9musc.osim");
    let multibody = Multibody::new(&ModelSpec::read(&OsimDocument::read(&path).unwrap()).unwrap()).unwrap();
    let defaults: Vec<f64> = multibody.coordinates.iter().map(|c| c.default_value).collect();
    assert_eq!(multibody.default_pose(), assemble(&multibody, &defaults).unwrap());
}

/// Inverse kinematics holds every link class exactly and matches OpenSim over the trial.
#[test]
fn inverse_kinematics_holds_every_link_class_as_opensim() {
    let comparison = compare_ik(&IkCase::linked_mechanisms(&common::root()), IkFrames::Trial).unwrap();
    assert_eq!(comparison.frames, 20);
    assert!(comparison.passes(), "{comparison:?}");
}
