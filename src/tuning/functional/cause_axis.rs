//! An offset of the knee's axis as a single cause (METHOD.md §8): the joint's rotation centre
//! moved by d perpendicular to the axis, the bones left where they are at the rest pose (every
//! coordinate 0) — a model whose knee turns about another point than the subject's (a
//! functional axis, `knee-axis`, would place it). The move is two offsets: d in the joint's
//! parent frame F and R_FMᵀ d in its child frame M (R_FM at the rest pose), so X_FM is unchanged
//! at rest and the child body moves by (I − R(q)) d in F elsewhere. d = x₁e₁ + x₂e₂ (mm), with
//! e₁ F's X made perpendicular to the axis at rest (its Y when the axis lies along X) and
//! e₂ = axis × e₁: one candidate of two variables. Each evaluation rebuilds the knee-moment model
//! from the moved joint (about 1 ms of geometry for 70 trials).

use serde::Serialize;

use super::cause::{Candidate, Cause};
use super::error::FunctionalError;
use super::knee_moment::KneeMomentModel;
use super::parameters::MuscleParameters;
use super::trials::DynamometryData;
use crate::mechanics::{Mat3, Multibody, PartialVelocity, Vec3};
use crate::model::{ModelSpec, Offset};

/// Largest axis offset tried along each direction perpendicular to the axis, mm.
pub const AXIS_OFFSET_LIMIT_MM: f64 = 20.0;

/// A joint's rotation centre moved: the offset d added to its parent frame and R_FMᵀ d to its
/// child frame, mm, each in that frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxisMove {
    pub in_parent: [f64; 3],
    pub in_child: [f64; 3],
}

/// The knee's axis moved in the plane perpendicular to it, as a two-variable model of the
/// moment residuals: x are the distances along e₁ and e₂, mm.
pub(super) struct AxisCandidate<'a> {
    spec: &'a ModelSpec,
    data: &'a DynamometryData,
    model: &'a KneeMomentModel,
    initial: Vec<MuscleParameters>,
    measured: &'a [f64],
    /// Index of the knee joint in `spec.joints`.
    joint: usize,
    /// e₁ and e₂ in F.
    directions: [Vec3; 2],
    /// R_FM at rest.
    rest_rotation: Mat3,
}

/// The axis candidate of the joint of `data`'s knee coordinate: none when the coordinate turns
/// nothing at rest (a translation) or its joint is not in the compiled model.
pub(super) fn axis_candidate<'a>(
    spec: &'a ModelSpec,
    model: &'a KneeMomentModel,
    data: &'a DynamometryData,
    initial: &[MuscleParameters],
    measured: &'a [f64],
) -> Result<Option<AxisCandidate<'a>>, FunctionalError> {
    let multibody = Multibody::new(spec)?;
    let Some(coordinate) = multibody.coordinate_index(&data.columns.knee_angle) else { return Ok(None) };
    let compiled = &multibody.joints[multibody.coordinate_joint(coordinate)];
    let Some(joint) = spec.joints.iter().position(|j| j.name == compiled.name) else { return Ok(None) };
    let rest = vec![0.0; compiled.coordinates.len()];
    let mut partials = vec![PartialVelocity { angular: Vec3::zeros(), linear: Vec3::zeros() }; compiled.coordinates.len()];
    compiled.mobilizer.partial_velocities(&rest, &mut partials);
    let k = compiled.coordinates.iter().position(|&c| c == coordinate).expect("the coordinate's joint has it");
    let Some(axis) = partials[k].angular.try_normalize(1e-12) else { return Ok(None) };
    let rest_rotation = compiled.mobilizer.transform(&rest).rotation;
    let first = perpendicular(&axis);
    let directions = [first, axis.cross(&first)];
    Ok(Some(AxisCandidate { spec, data, model, initial: initial.to_vec(), measured, joint, directions, rest_rotation }))
}

/// F's X made perpendicular to the unit `axis` (F's Y when the axis lies along X).
fn perpendicular(axis: &Vec3) -> Vec3 {
    [Vec3::x(), Vec3::y()].into_iter().map(|e| e - e.dot(axis) * axis).find_map(|v| v.try_normalize(1e-6)).expect("X or Y is off a unit axis")
}

/// `spec` with joint `joint`'s frames moved by `parent` (m, in F) and `child` (m, in M).
fn moved_joint(spec: &ModelSpec, joint: usize, parent: Vec3, child: Vec3) -> ModelSpec {
    let mut moved = spec.clone();
    let offset = |v: Vec3| Offset { translation: [v.x, v.y, v.z], orientation: [0.0; 3] };
    moved.joints[joint].parent.offsets.push(offset(parent));
    moved.joints[joint].child.offsets.push(offset(child));
    moved
}

impl AxisCandidate<'_> {
    pub fn cause(&self) -> Cause {
        Cause::AxisOffset { joint: self.spec.joints[self.joint].name.clone() }
    }

    /// d in F and R_FMᵀ d in M at x, mm.
    fn offsets(&self, x: &[f64]) -> [Vec3; 2] {
        let in_parent = x[0] * self.directions[0] + x[1] * self.directions[1];
        [in_parent, self.rest_rotation.transpose() * in_parent]
    }
}

impl Candidate for AxisCandidate<'_> {
    fn variables(&self) -> usize {
        2
    }

    fn residuals(&mut self, x: &[f64], out: &mut [f64]) -> Result<(), FunctionalError> {
        let [in_parent, in_child] = self.offsets(x);
        let moved = moved_joint(self.spec, self.joint, in_parent / 1000.0, in_child / 1000.0);
        let model = KneeMomentModel::with_method(&moved, self.data, self.model.method)?;
        for ((r, m), y) in out.iter_mut().zip(model.moments(&self.initial)?).zip(self.measured) {
            *r = m - y;
        }
        Ok(())
    }

    fn bounds(&self) -> Vec<[f64; 2]> {
        vec![[-AXIS_OFFSET_LIMIT_MM, AXIS_OFFSET_LIMIT_MM]; 2]
    }

    /// The distance moved, mm.
    fn value(&self, x: &[f64]) -> f64 {
        x[0].hypot(x[1])
    }

    fn axis_move(&self, x: &[f64]) -> Option<AxisMove> {
        let [in_parent, in_child] = self.offsets(x).map(|v| [v.x, v.y, v.z]);
        Some(AxisMove { in_parent, in_child })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perpendicular_directions_are_unit_and_orthogonal() {
        for axis in [Vec3::z(), Vec3::x(), Vec3::new(0.3, -0.2, 0.9).normalize()] {
            let first = perpendicular(&axis);
            assert!((first.norm() - 1.0).abs() < 1e-15 && first.dot(&axis).abs() < 1e-15, "{axis:?}");
        }
        assert_eq!(perpendicular(&Vec3::z()), Vec3::x());
        assert_eq!(perpendicular(&Vec3::x()), Vec3::y());
    }
}
