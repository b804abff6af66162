//! Constraints between bodies other than couplers — OpenSim's `PointConstraint`,
//! `ConstantDistanceConstraint`, `PointOnLineConstraint` and `WeldConstraint` (Simbody's Ball,
//! Rod, PointOnLine and Weld) — as position errors that vanish when the constraint holds, and
//! each error's rate as a sum over the two linked bodies of `linear·v + angular·ω` (v the
//! velocity of a point of the body, ω its angular velocity, both in ground).
//!
//! Errors: Point, the second point from the first (m, ground, three rows); Distance, their
//! distance minus the constant (m); PointOnLine, the follower point from the line point along
//! two unit normals of the line fixed in the line body (m); Weld, the second frame's origin
//! from the first's (m) then Simbody's ConstantOrientation errors x₁·y₂, y₁·z₂, z₁·x₂; a
//! contact's rows ([`ContactRow`]), the second point from the first along a direction fixed in
//! the first body (m) or the cosine between two axes, one fixed in each body.

use nalgebra::{DMatrix, DVector};

use super::error::MechanicsError;
use super::inverse_dynamics::BodyLoad;
use super::kinematics::Kinematics;
use super::multibody::{Marker, Multibody};
use super::spatial::{Mat3, Transform, Vec3};
use crate::model::{ConstraintSpec, LinkSpec};

/// An enforced constraint between two bodies.
#[derive(Debug, Clone)]
pub struct BodyLink {
    pub name: String,
    /// The OpenSim class (`PointConstraint`, …).
    pub class: String,
    /// The linked points: the two points, the line point then the follower point, or the weld
    /// frames' origins.
    pub ends: [Marker; 2],
    kind: LinkKind,
}

#[derive(Debug, Clone)]
enum LinkKind {
    Point,
    /// The constant distance (m).
    Distance(f64),
    /// Two unit normals of the line, in the line body.
    PointOnLine([Vec3; 2]),
    /// Each weld frame's orientation in its body.
    Weld([Mat3; 2]),
    Contact(Vec<ContactRow>),
}

/// One row of a contact placed for an instant (OpenSim's induced accelerations replace an
/// external force by a contact at its point): on a fixed surface, Simbody's PointInPlane and
/// NoSlip1D are a point's acceleration along a direction, and ConstantAngle a spin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactRow {
    /// The second point moves with the first along this unit vector, fixed in the first body.
    Along(Vec3),
    /// The cosine of the angle between `base` (a unit vector fixed in the first body) and
    /// `follower` (fixed in the second) stays.
    Spin { base: Vec3, follower: Vec3 },
}

/// One body's share of an error's rate: `linear·v(point) + angular·ω(body)`.
#[derive(Debug, Clone, Copy)]
pub struct RateTerm {
    pub body: usize,
    /// The point whose velocity counts (m, ground).
    pub point: Vec3,
    pub linear: Vec3,
    pub angular: Vec3,
}

/// Simbody's ConstantOrientation pairs: (axis of frame 1, axis of frame 2) per error.
const ORIENTATION_PAIRS: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

impl BodyLink {
    /// The link of an enforced constraint `spec` with a [`LinkSpec`], on `multibody`'s bodies.
    pub fn new(multibody: &Multibody, spec: &ConstraintSpec, link: &LinkSpec) -> Result<BodyLink, MechanicsError> {
        let end = |frame, location: [f64; 3], role: &str| -> Result<(Marker, Transform), MechanicsError> {
            let (body, x_body_frame) = multibody.attach(frame, &spec.name)?;
            let location = x_body_frame.apply(&Vec3::from(location));
            Ok((Marker { name: format!("{}/{role}", spec.name), body, location }, x_body_frame))
        };
        let (ends, kind) = match link {
            LinkSpec::Point { frames, locations } => ([end(&frames[0], locations[0], "body_1")?.0, end(&frames[1], locations[1], "body_2")?.0], LinkKind::Point),
            LinkSpec::Distance { frames, locations, distance } => {
                ([end(&frames[0], locations[0], "body_1")?.0, end(&frames[1], locations[1], "body_2")?.0], LinkKind::Distance(*distance))
            }
            LinkSpec::PointOnLine { line, direction, point_on_line, follower, point_on_follower } => {
                let (line_point, x_line) = end(line, *point_on_line, "line")?;
                let follower_point = end(follower, *point_on_follower, "follower")?.0;
                let direction = x_line.rotation * Vec3::from(*direction);
                ([line_point, follower_point], LinkKind::PointOnLine(normals(&direction)))
            }
            LinkSpec::Weld { frames } => {
                let (first, x1) = end(&frames[0], [0.0; 3], "frame1")?;
                let (second, x2) = end(&frames[1], [0.0; 3], "frame2")?;
                ([first, second], LinkKind::Weld([x1.rotation, x2.rotation]))
            }
        };
        Ok(BodyLink { name: spec.name.clone(), class: spec.class.clone(), ends, kind })
    }

    /// Simbody's Ball named `name` between the points `ends` (a `PointConstraint`).
    pub fn point(name: &str, class: &str, ends: [Marker; 2]) -> BodyLink {
        BodyLink { name: name.to_string(), class: class.to_string(), ends, kind: LinkKind::Point }
    }

    /// A contact named `name` between the points `ends` holding `rows`.
    pub fn contact(name: &str, class: &str, ends: [Marker; 2], rows: Vec<ContactRow>) -> BodyLink {
        BodyLink { name: name.to_string(), class: class.to_string(), ends, kind: LinkKind::Contact(rows) }
    }

    /// How many errors the link has (its constraint equations).
    pub fn rows(&self) -> usize {
        match &self.kind {
            LinkKind::Point => 3,
            LinkKind::Distance(_) => 1,
            LinkKind::PointOnLine(_) => 2,
            LinkKind::Weld(_) => 6,
            LinkKind::Contact(rows) => rows.len(),
        }
    }

    /// The ends' points in ground at the realized pose.
    fn points(&self, kinematics: &Kinematics) -> [Vec3; 2] {
        self.ends.each_ref().map(|end| kinematics.bodies[end.body].apply(&end.location))
    }

    /// The weld frames' axes in ground (columns), at the realized pose.
    fn weld_axes(&self, kinematics: &Kinematics, rotations: &[Mat3; 2]) -> [Mat3; 2] {
        [0, 1].map(|k| kinematics.bodies[self.ends[k].body].rotation * rotations[k])
    }

    /// Appends the link's errors at the realized pose (see the module doc).
    pub fn errors(&self, kinematics: &Kinematics, errors: &mut Vec<f64>) {
        let [p1, p2] = self.points(kinematics);
        let gap = p2 - p1;
        match &self.kind {
            LinkKind::Point => errors.extend(gap.iter()),
            LinkKind::Distance(distance) => errors.push(gap.norm() - distance),
            LinkKind::PointOnLine(normals) => {
                let rotation = kinematics.bodies[self.ends[0].body].rotation;
                errors.extend(normals.iter().map(|n| (rotation * n).dot(&gap)));
            }
            LinkKind::Weld(rotations) => {
                errors.extend(gap.iter());
                let [a, b] = self.weld_axes(kinematics, rotations);
                errors.extend(ORIENTATION_PAIRS.iter().map(|&(i, j)| a.column(i).dot(&b.column(j))));
            }
            LinkKind::Contact(rows) => {
                let [r1, r2] = [0, 1].map(|k| kinematics.bodies[self.ends[k].body].rotation);
                errors.extend(rows.iter().map(|row| match row {
                    ContactRow::Along(direction) => (r1 * direction).dot(&gap),
                    ContactRow::Spin { base, follower } => (r1 * base).dot(&(r2 * follower)),
                }));
            }
        }
    }

    /// The two bodies' shares of error `row`'s rate at the realized pose.
    pub fn rate_terms(&self, kinematics: &Kinematics, row: usize) -> [RateTerm; 2] {
        let [p1, p2] = self.points(kinematics);
        let [b1, b2] = [self.ends[0].body, self.ends[1].body];
        let zero = Vec3::zeros();
        let translation = |direction: Vec3, angular: Vec3| [RateTerm { body: b1, point: p1, linear: -direction, angular }, RateTerm { body: b2, point: p2, linear: direction, angular: zero }];
        match &self.kind {
            LinkKind::Point => translation(Vec3::ith(row, 1.0), zero),
            // Coincident points: the distance's slope is any unit vector; x lets a solve part them.
            LinkKind::Distance(_) => translation((p2 - p1).try_normalize(1e-12).unwrap_or_else(Vec3::x), zero),
            LinkKind::PointOnLine(normals) => {
                let normal = kinematics.bodies[b1].rotation * normals[row];
                translation(normal, normal.cross(&(p2 - p1)))
            }
            LinkKind::Weld(_) if row < 3 => translation(Vec3::ith(row, 1.0), zero),
            LinkKind::Weld(rotations) => {
                let [a, b] = self.weld_axes(kinematics, rotations);
                let (i, j) = ORIENTATION_PAIRS[row - 3];
                let axis = a.column(i).cross(&b.column(j));
                [RateTerm { body: b1, point: p1, linear: zero, angular: axis }, RateTerm { body: b2, point: p2, linear: zero, angular: -axis }]
            }
            LinkKind::Contact(rows) => {
                let [r1, r2] = [b1, b2].map(|b| kinematics.bodies[b].rotation);
                match rows[row] {
                    ContactRow::Along(direction) => {
                        let along = r1 * direction;
                        translation(along, along.cross(&(p2 - p1)))
                    }
                    ContactRow::Spin { base, follower } => {
                        let axis = (r1 * base).cross(&(r2 * follower));
                        [RateTerm { body: b1, point: p1, linear: zero, angular: axis }, RateTerm { body: b2, point: p2, linear: zero, angular: -axis }]
                    }
                }
            }
        }
    }
}

impl Multibody {
    /// The links' velocity rows G at the realized pose: row r's entry for coordinate c is the
    /// rate of link error r per unit speed of c (the links in order, each's rows in order).
    pub fn link_jacobian(&self, kinematics: &Kinematics) -> DMatrix<f64> {
        let n = self.coordinates.len();
        let rows: usize = self.links.iter().map(BodyLink::rows).sum();
        let mut g = DMatrix::zeros(rows, n);
        let mut row = 0;
        for link in &self.links {
            for link_row in 0..link.rows() {
                for term in link.rate_terms(kinematics, link_row) {
                    for c in 0..n {
                        let velocity = kinematics.point_partial(self, term.body, &term.point, c);
                        let angular = if self.is_moved_by(term.body, self.coordinate_joint(c)) { kinematics.axes[c].angular } else { Vec3::zeros() };
                        g[(row, c)] += term.linear.dot(&velocity) + term.angular.dot(&angular);
                    }
                }
                row += 1;
            }
        }
        g
    }

    /// The body loads of the links' multipliers `multipliers` (one per row of
    /// [`Multibody::link_jacobian`]): on each rate term's body, −λ·linear at its point and
    /// −λ·angular as a torque — generalized forces −Gᵀλ.
    pub fn link_loads(&self, kinematics: &Kinematics, multipliers: &DVector<f64>) -> Vec<BodyLoad> {
        let mut loads = Vec::new();
        let mut row = 0;
        for link in &self.links {
            for link_row in 0..link.rows() {
                let lambda = multipliers[row];
                loads.extend(link.rate_terms(kinematics, link_row).map(|t| BodyLoad { body: t.body, force: -lambda * t.linear, point: t.point, torque: -lambda * t.angular }));
                row += 1;
            }
        }
        loads
    }
}

/// Two unit vectors perpendicular to `direction` and to each other.
fn normals(direction: &Vec3) -> [Vec3; 2] {
    let unit = direction.normalize();
    let least = (0..3).min_by(|&a, &b| unit[a].abs().total_cmp(&unit[b].abs())).unwrap_or(0);
    let first = unit.cross(&Vec3::ith(least, 1.0)).normalize();
    [first, unit.cross(&first)]
}

#[cfg(test)]
mod tests {
    use super::normals;
    use crate::mechanics::Vec3;

    #[test]
    fn line_normals_are_orthonormal_to_the_line() {
        for direction in [Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.3, -2.0, 0.7), Vec3::new(1.0, 0.0, 0.0)] {
            let [a, b] = normals(&direction);
            let unit = direction.normalize();
            for (x, y, expected) in [(a, a, 1.0), (b, b, 1.0), (a, b, 0.0), (a, unit, 0.0), (b, unit, 0.0)] {
                assert!((x.dot(&y) - expected).abs() < 1e-15, "{direction:?}");
            }
        }
    }
}
