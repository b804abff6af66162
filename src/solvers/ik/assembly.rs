//! OpenSim's `Model::assemble`, which `initSystem` runs on the default state: the pose nearest
//! given coordinate values that satisfies every constraint.
//!
//! As OpenSim's `AssemblySolver` sets it up: each coordinate that is neither a coupler's
//! dependent, nor locked, nor `is_free_to_satisfy_constraints` is a goal of weight 1 at its
//! value, Σ (q_j − q̂_j)²; locked coordinates stay at their default values, clamped ones within
//! their range; couplers and links (point, distance, point-on-line and weld constraints) hold
//! exactly. A model whose only constraints are couplers needs no solve
//! ([`Multibody::default_pose`]). Simbody stops at `assembly_accuracy` (1e-9 by default); we
//! close the links to 1e-10 m (rad) and stop at steps of 1e-10.

use super::coordinates::{ConstraintWeight, CoordinateMap};
use super::frame::{moving_coordinates, FrameModel};
use super::held::minimize_holding_links;
use super::solver::IkWorkspace;
use super::tasks::TrackedCoordinate;
use crate::mechanics::Multibody;
use crate::solvers::least_squares::LeastSquaresOptions;
use crate::solvers::IkError;

/// The pose nearest `values` (rad or m per coordinate) at which every constraint holds (see the
/// module doc); the default pose of OpenSim's `initSystem` for `values` the default values.
pub fn assemble(multibody: &Multibody, values: &[f64]) -> Result<Vec<f64>, IkError> {
    let mut q = values.to_vec();
    if !(multibody.couplers.is_empty() && multibody.links.is_empty() && multibody.unheld_constraints.is_empty()) {
        // OpenSim assembles only a model with constraints, and then holds every locked
        // coordinate at its default value and keeps every clamped one within its range.
        for (c, coordinate) in multibody.coordinates.iter().enumerate().filter(|(c, _)| !multibody.is_dependent(*c)) {
            if coordinate.locked {
                q[c] = coordinate.default_value;
            } else if coordinate.clamped {
                q[c] = q[c].clamp(coordinate.range[0], coordinate.range[1]);
            }
        }
    }
    multibody.follow_couplers(&mut q, &[]);
    if multibody.links.is_empty() {
        return Ok(q);
    }
    if let Some(constraint) = multibody.unheld_constraints.first() {
        let what = "an enforced constraint of a class osim-tune does not hold".into();
        return Err(IkError::Unsupported { model: multibody.file.clone(), component: constraint.clone(), what });
    }
    let map = CoordinateMap::new(multibody, ConstraintWeight::Infinite, &vec![false; q.len()])?;
    let goals = (0..q.len()).filter(|&c| {
        let coordinate = &multibody.coordinates[c];
        !(multibody.is_dependent(c) || coordinate.locked || coordinate.free_to_satisfy_constraints)
    });
    let coordinates = goals.map(|c| TrackedCoordinate { coordinate: c, weight: 1.0, target: values[c], trajectory: None }).collect();
    let link_coordinates = multibody.links.iter().map(|link| link.ends.each_ref().map(|end| moving_coordinates(multibody, &map, end.body))).collect();
    let model = FrameModel { multibody, markers: Vec::new(), coordinates, marker_coordinates: Vec::new(), link_coordinates };
    let mut workspace = IkWorkspace::new(&model, &map);
    workspace.start_from(&map, &q);
    minimize_holding_links(&model, &map, &[], &mut workspace, &LeastSquaresOptions::default(), true, &mut q).map_err(|open| {
        let link = &multibody.links[open.link];
        IkError::NotAssembled { model: multibody.file.clone(), constraint: format!("{} ({})", link.name, link.class), error: open.error, rounds: open.rounds }
    })?;
    Ok(q)
}

/// The pose of OpenSim's default state: the default values assembled ([`assemble`]).
pub fn assembled_default_pose(multibody: &Multibody) -> Result<Vec<f64>, IkError> {
    assemble(multibody, &multibody.default_pose())
}
