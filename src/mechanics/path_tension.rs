//! What a muscle path's tension applies, as OpenSim applies it: the moment arm
//! (`Muscle::computeMomentArm`, the generalized force a unit tension produces), the generalized
//! forces with the links between bodies aside, the body loads and mobility forces of a tension
//! (`GeometryPath::produceForces`) and the lengthening speed (`computeLengtheningSpeed`), all on
//! the path [`GeometryPath::place_with_directions`] placed.

use super::coupling;
use super::inverse_dynamics::{AppliedForces, BodyLoad};
use super::kinematics::Kinematics;
use super::multibody::Multibody;
use super::path::{ActivePoint, GeometryPath, MovingAxis, PathPoint, PathScratch, PointKind, Source};
use super::spatial::Vec3;

impl GeometryPath {
    /// Path length (m), and in `moment_arms[k]` the moment arm about `coordinates[k]`: m for a
    /// rotational coordinate, m/m for a translational one; positive when tension drives q up.
    /// For a path without wrapping r = −∂L/∂q, except about `BallJoint`/`FreeJoint` rotations,
    /// where OpenSim's generalized speed is an angular velocity and r the torque about the
    /// parent frame's axis. Over a wrap object the tangent points count as fixed on its body,
    /// and the segments' directions are those OpenSim sees: OpenSim's stale ground locations of moved tangent points.
    ///
    /// Computed as OpenSim does: the unit tension acts at each active point next to a point on
    /// another body, along the segment, and its generalized force is the moment arm; a
    /// `MovingPathPoint` adds the work of its motion in its frame to the coordinate of its x
    /// location. Generalized forces on coordinates tied by couplers are summed along the
    /// constraint (`q` must satisfy the couplers); with links, along OpenSim's projected
    /// coupling vector ([`coupling::projected_coupling`]; `q` must satisfy the links), 0 about a
    /// coordinate the constraints fix.
    pub fn moment_arms(
        &self,
        multibody: &Multibody,
        kinematics: &Kinematics,
        q: &[f64],
        scratch: &mut PathScratch,
        coordinates: &[usize],
        moment_arms: &mut [f64],
    ) -> f64 {
        if multibody.links.is_empty() {
            return self.unit_tension_forces(multibody, kinematics, q, scratch, coordinates, moment_arms);
        }
        let length = self.place_with_directions(kinematics, q, scratch);
        for (&coordinate, moment_arm) in coordinates.iter().zip(moment_arms.iter_mut()) {
            *moment_arm = 0.0;
            for (c, weight) in coupling::projected_coupling(multibody, kinematics, q, coordinate).weights {
                *moment_arm += weight * self.generalized_force(multibody, kinematics, q, scratch, c);
            }
        }
        length
    }

    /// The generalized forces (N·m or N per N) a unit tension applies about `coordinates`, as
    /// [`GeometryPath::moment_arms`] finds them but with the links between bodies aside: each
    /// summed along its couplers only, as the forward dynamics applies them (the links then
    /// answer with their own forces). The path's length (m) is returned.
    pub fn unit_tension_forces(&self, multibody: &Multibody, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch, coordinates: &[usize], forces: &mut [f64]) -> f64 {
        let length = self.place_with_directions(kinematics, q, scratch);
        for (&coordinate, force) in coordinates.iter().zip(forces.iter_mut()) {
            *force = 0.0;
            coupling::for_each_coupling(&multibody.couplers, q, coordinate, |c, weight| *force += weight * self.generalized_force(multibody, kinematics, q, scratch, c));
        }
        length
    }

    /// The loads OpenSim's `GeometryPath::produceForces` applies for `tension` (N): at each
    /// active point next to a point on another body, the tension along each such segment, pulling
    /// the point towards its neighbour (body loads, in ground); and for a `MovingPathPoint` the
    /// work of its motion in its frame, as a mobility force on the coordinate of its x location.
    pub fn tension_loads(&self, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch, tension: f64, applied: &mut AppliedForces) {
        self.place_with_directions(kinematics, q, scratch);
        for (pair, d) in scratch.active.windows(2).zip(&scratch.directions) {
            let (from, to) = (&pair[0], &pair[1]);
            if from.body == to.body {
                continue;
            }
            let force = tension * d;
            applied.loads.push(BodyLoad { body: from.body, force, point: from.location, torque: Vec3::zeros() });
            applied.loads.push(BodyLoad { body: to.body, force: -force, point: to.location, torque: Vec3::zeros() });
            for (point, sign) in [(from, 1.0), (to, -1.0)] {
                if let Some((coordinate, rate)) = self.moving_point_rate(kinematics, q, point) {
                    applied.mobility[coordinate] += sign * rate.dot(&force);
                }
            }
        }
    }

    /// dL/dt (m/s) of the path `moment_arms` last placed in `scratch`, at speeds `u` of
    /// `coordinates` (each alone, no coupling applied; a coupler's dependent speed counts as the
    /// state holds it), as OpenSim's `computeLengtheningSpeed` sums `calcSpeedBetween` over every
    /// pair of consecutive points: their relative velocity along the segment's direction, wrap
    /// tangent points moving with their wrap object's body. Those directions are the stale ones
    /// OpenSim sees (`observed`), so a pair on one body — two tangent points of a wrap, or a
    /// tangent point and a path point — adds a little where the tangent points moved after they
    /// were first measured (Rajagopal2016's gastrocnemii over their two cylinders: 9.4e-4 m/s),
    /// which the pair's unit-tension forces (skipped on one body) do not.
    pub fn lengthening_speed(&self, multibody: &Multibody, kinematics: &Kinematics, q: &[f64], scratch: &PathScratch, coordinates: &[usize], u: &[f64]) -> f64 {
        let mut speed = 0.0;
        for (pair, d) in scratch.active.windows(2).zip(&scratch.directions) {
            if d.iter().all(|x| x.is_finite()) {
                speed -= coordinates.iter().map(|&c| self.pair_force(multibody, kinematics, q, pair, d, c) * u[c]).sum::<f64>();
            } else if pair[0].body != pair[1].body {
                // Coincident points: OpenSim's `calcSpeedBetween` takes their relative speed.
                speed += coordinates.iter().map(|&c| self.pair_rate(multibody, kinematics, q, pair, c) * u[c]).sum::<Vec3>().norm();
            } // (coincident points on one body do not separate)
        }
        speed
    }

    /// Path length (m) and [`GeometryPath::lengthening_speed`] (m/s) at coordinates `q` and speeds
    /// `u` of `coordinates`, without the moment arms.
    pub fn length_and_speed(&self, multibody: &Multibody, kinematics: &Kinematics, q: &[f64], scratch: &mut PathScratch, coordinates: &[usize], u: &[f64]) -> (f64, f64) {
        let length = self.place_with_directions(kinematics, q, scratch);
        (length, self.lengthening_speed(multibody, kinematics, q, scratch, coordinates, u))
    }

    /// The generalized force about `coordinate` of a unit tension along the placed path: the
    /// pairs of consecutive points on different bodies.
    fn generalized_force(&self, multibody: &Multibody, kinematics: &Kinematics, q: &[f64], scratch: &PathScratch, coordinate: usize) -> f64 {
        scratch
            .active
            .windows(2)
            .zip(&scratch.directions)
            .filter(|(pair, _)| pair[0].body != pair[1].body)
            .map(|(pair, d)| self.pair_force(multibody, kinematics, q, pair, d, coordinate))
            .sum()
    }

    /// The generalized force about `coordinate` of a unit tension pulling the two points of `pair`
    /// together along the unit direction `d`: d·(∂v_from/∂u − ∂v_to/∂u), a `MovingPathPoint`'s
    /// motion in its frame included.
    fn pair_force(&self, multibody: &Multibody, kinematics: &Kinematics, q: &[f64], pair: &[ActivePoint], d: &Vec3, coordinate: usize) -> f64 {
        d.dot(&self.pair_rate(multibody, kinematics, q, pair, coordinate))
    }

    /// ∂(v_from − v_to)/∂u of `pair`'s two points, u the speed of `coordinate`, a
    /// `MovingPathPoint`'s motion in its frame included.
    fn pair_rate(&self, multibody: &Multibody, kinematics: &Kinematics, q: &[f64], pair: &[ActivePoint], coordinate: usize) -> Vec3 {
        let rate = |point: &ActivePoint| kinematics.point_partial(multibody, point.body, &point.location, coordinate) + self.moving_work(kinematics, q, point, coordinate);
        rate(&pair[0]) - rate(&pair[1])
    }

    /// OpenSim's `getdPointdQ` in ground for a `MovingPathPoint` whose x location is driven by
    /// `coordinate` (all three slopes, at the unclamped values); zero otherwise.
    fn moving_work(&self, kinematics: &Kinematics, q: &[f64], active: &ActivePoint, coordinate: usize) -> Vec3 {
        match self.moving_point(active) {
            Some((point, axes)) if axes[0].coordinate == coordinate => moving_point_rate(kinematics, q, point, axes),
            _ => Vec3::zeros(),
        }
    }

    /// For a `MovingPathPoint`: the coordinate of its x location and OpenSim's `getdPointdQ` in
    /// ground.
    fn moving_point_rate(&self, kinematics: &Kinematics, q: &[f64], active: &ActivePoint) -> Option<(usize, Vec3)> {
        self.moving_point(active).map(|(point, axes)| (axes[0].coordinate, moving_point_rate(kinematics, q, point, axes)))
    }

    /// The path point of `active` and its axes, when it is a `MovingPathPoint`.
    fn moving_point(&self, active: &ActivePoint) -> Option<(&PathPoint, &[MovingAxis; 3])> {
        let Source::Point(index) = active.source else { return None };
        let point = &self.points[index];
        match &point.kind {
            PointKind::Moving(axes) => Some((point, axes)),
            _ => None,
        }
    }
}

/// OpenSim's `getdPointdQ` of a `MovingPathPoint` in ground: all three slopes at the unclamped
/// coordinate values, turned from the point's frame.
fn moving_point_rate(kinematics: &Kinematics, q: &[f64], point: &PathPoint, axes: &[MovingAxis; 3]) -> Vec3 {
    let slopes = Vec3::from_fn(|k, _| axes[k].function.derivative(q[axes[k].coordinate]));
    kinematics.bodies[point.body].rotation * point.frame.rotation * slopes
}
