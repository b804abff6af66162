//! The contacts OpenSim's induced accelerations put in place of the external forces
//! (`setContactPointForInducedAccelerations`): while the k-th force exceeds the threshold, the
//! k-th constraint holds its body at the force's point. A `RollingOnSurfaceConstraint` there is
//! Simbody's PointInPlane (the normal), ConstantAngle (no spin about the normal, the follower
//! axis x̂ × n in the rolling body at the instant) and two NoSlip1D (ground's x and z), each row
//! held only while its unilateral condition holds (`unilateralConditionsSatisfied`). A
//! `PointConstraint` is Simbody's Ball between the setup's `location_body_1` and
//! `location_body_2`, as OpenSim 4.6 holds it: its contact-point update sets only properties,
//! which the system built before never reads.

use std::path::Path;

use nalgebra::DVector;

use crate::mechanics::{BodyLink, ContactRow, Kinematics, Marker, Multibody, Vec3, GROUND_INDEX};
use crate::setup::{ContactConstraintSetup, ContactSetup};

use super::InducedAccelerationsError;

/// A rolling contact's rows: PointInPlane, ConstantAngle, NoSlip1D along x, along z.
pub(super) const ROLLING_ROWS: usize = 4;

/// One contact constraint, on the bodies of a model.
#[derive(Debug, Clone)]
pub(super) struct Contact {
    pub name: String,
    /// The surface (or `body_1`) and the rolling body (or `body_2`, the force's body).
    pub bodies: [usize; 2],
    kind: Kind,
}

#[derive(Debug, Clone)]
enum Kind {
    /// The surface normal (unit, ground), the friction coefficient and the contact radius (m).
    Rolling { normal: Vec3, friction: f64, radius: f64 },
    /// The points, m, each in its body.
    Point([Vec3; 2]),
}

/// Which of a contact's rows hold; all of a point contact's.
pub(super) type RowsHeld = [bool; ROLLING_ROWS];

impl Contact {
    /// The constraints of `setups` (from the setup `file`) on `multibody`, the k-th replacing the
    /// force applied to `applied[k]`: as many as forces, each on its force's body (and a rolling
    /// one on ground).
    pub fn compile(setups: &[ContactConstraintSetup], multibody: &Multibody, applied: &[usize], file: &Path) -> Result<Vec<Contact>, InducedAccelerationsError> {
        let problem = |setup: Option<&ContactConstraintSetup>, problem: String| InducedAccelerationsError::Contact { file: file.into(), line: setup.map_or(0, |s| s.line), problem };
        if setups.len() != applied.len() {
            return Err(problem(setups.first(), format!("the ConstraintSet has {} constraints for {} external forces; InducedAccelerations replaces each force by one constraint, in order", setups.len(), applied.len())));
        }
        let mut contacts = Vec::new();
        for (setup, &force_body) in setups.iter().zip(applied) {
            let body = |name: &str| multibody.body_index(name).ok_or_else(|| problem(Some(setup), format!("{}: {name:?} is no body of the model", setup.name)));
            let (bodies, kind) = match &setup.contact {
                ContactSetup::Rolling { rolling_body, surface_body, surface_normal, friction_coefficient, contact_radius } => {
                    let bodies = [body(surface_body)?, body(rolling_body)?];
                    if bodies[0] != GROUND_INDEX {
                        return Err(problem(Some(setup), format!("{}: the surface_body must be ground (a contact replacing a force from the ground), not {surface_body:?}", setup.name)));
                    }
                    (bodies, Kind::Rolling { normal: Vec3::from(*surface_normal), friction: *friction_coefficient, radius: *contact_radius })
                }
                ContactSetup::Point { body_1, body_2, locations } => ([body(body_1)?, body(body_2)?], Kind::Point(locations.map(Vec3::from))),
                ContactSetup::Other { class } => {
                    return Err(problem(Some(setup), format!("{}: a {class} cannot replace an external force here; use a RollingOnSurfaceConstraint or a PointConstraint (OpenSim 4.6 fails on a WeldConstraint in this analysis)", setup.name)))
                }
            };
            if bodies[1] != force_body {
                let expected = &multibody.bodies[force_body].name;
                return Err(problem(Some(setup), format!("{} holds {}, but the external force it replaces is applied to {expected}", setup.name, multibody.bodies[bodies[1]].name)));
            }
            contacts.push(Contact { name: setup.name.clone(), bodies, kind });
        }
        Ok(contacts)
    }

    /// The contact placed at the force's `point` (m, ground) at the pose `kinematics` holds,
    /// with the rows `held` (in [`ROLLING_ROWS`]' order; a point contact holds all three).
    pub fn link(&self, kinematics: &Kinematics, point: &Vec3, held: &RowsHeld) -> BodyLink {
        let marker = |k: usize, location: Vec3| Marker { name: format!("{}/contact", self.name), body: self.bodies[k], location };
        match &self.kind {
            Kind::Rolling { normal, .. } => {
                let ends = [0, 1].map(|k| marker(k, kinematics.bodies[self.bodies[k]].inverse().apply(point)));
                let roller = kinematics.bodies[self.bodies[1]].rotation.transpose();
                let follower = (roller * Vec3::x()).cross(&(roller * normal)).normalize();
                let all = [ContactRow::Along(*normal), ContactRow::Spin { base: Vec3::x(), follower }, ContactRow::Along(Vec3::x()), ContactRow::Along(Vec3::z())];
                BodyLink::contact(&self.name, "RollingOnSurfaceConstraint", ends, all.into_iter().zip(held).filter(|(_, &h)| h).map(|(row, _)| row).collect())
            }
            Kind::Point(locations) => BodyLink::point(&self.name, "PointConstraint", [marker(0, locations[0]), marker(1, locations[1])]),
        }
    }

    /// The rows a rolling contact keeps after a solve gave its held rows `held` the multipliers
    /// `multipliers` (Simbody's sign): none unless the normal force −λ₀ pushes; the no-slip rows
    /// while the tangential force is within friction; the spin row then too while its torque
    /// λ₁ (signed, as OpenSim compares it) is within the contact radius' friction. A point
    /// contact keeps all.
    pub fn rows_kept(&self, held: &RowsHeld, multipliers: &[f64]) -> RowsHeld {
        let Kind::Rolling { friction, radius, .. } = self.kind else { return [true; ROLLING_ROWS] };
        let mut values = [0.0; ROLLING_ROWS];
        let mut next = multipliers.iter();
        for (value, _) in values.iter_mut().zip(held).filter(|(_, &h)| h) {
            *value = *next.next().unwrap_or(&0.0);
        }
        let [normal, torque] = [-values[0], values[1]];
        let tangential = values[2].hypot(values[3]);
        let mut kept = [false; ROLLING_ROWS];
        if held[0] && normal > 0.0 {
            kept[0] = true;
            if tangential <= friction * normal {
                (kept[2], kept[3]) = (true, true);
                kept[1] = torque <= radius * friction * normal;
            }
        }
        kept
    }

    /// OpenSim's record of the constraint (`Constraint::getRecordValues`) placed as `link`: on
    /// each of its two bodies the force (N, ground) and the moment about the body's origin (N·m,
    /// ground) that the multipliers `multipliers` of the link's rows generate (Gᵀλ, Simbody's
    /// sign). Simbody's Ball applies the first body's force where the second body's point is.
    pub fn record(&self, link: &BodyLink, kinematics: &Kinematics, multipliers: &DVector<f64>, values: &mut Vec<f64>) {
        let mut on = [[Vec3::zeros(); 2]; 2];
        let second_point = kinematics.bodies[link.ends[1].body].apply(&link.ends[1].location);
        for row in 0..link.rows() {
            for (k, term) in link.rate_terms(kinematics, row).into_iter().enumerate() {
                let force = multipliers[row] * term.linear;
                let point = if matches!(self.kind, Kind::Point(_)) { second_point } else { term.point };
                let arm = point - kinematics.bodies[term.body].translation;
                on[k][0] += force;
                on[k][1] += multipliers[row] * term.angular + arm.cross(&force);
            }
        }
        for [force, moment] in on {
            values.extend(force.iter().chain(moment.iter()));
        }
    }

    /// A point contact's note that it holds the setup's points, not the force's.
    pub fn fixed_points_note(&self, multibody: &Multibody) -> Option<String> {
        let Kind::Point(locations) = &self.kind else { return None };
        let [first, second] = [0, 1].map(|k| format!("{}'s point ({:.4}, {:.4}, {:.4}) m", multibody.bodies[self.bodies[k]].name, locations[k].x, locations[k].y, locations[k].z));
        Some(format!("InducedAccelerations: PointConstraint {} holds {second} at {first}, as OpenSim 4.6 holds it, not at the external force's point", self.name))
    }

    /// The labels of [`Contact::record`]: `<name>_<body>_F{x,y,z}` then `_M{x,y,z}` per body.
    pub fn record_labels(&self, multibody: &Multibody) -> Vec<String> {
        let mut labels = Vec::new();
        for body in self.bodies {
            let prefix = format!("{}_{}", self.name, multibody.bodies[body].name);
            labels.extend(["Fx", "Fy", "Fz", "Mx", "My", "Mz"].map(|axis| format!("{prefix}_{axis}")));
        }
        labels
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rolling(friction: f64, radius: f64) -> Contact {
        Contact { name: "foot".into(), bodies: [0, 1], kind: Kind::Rolling { normal: Vec3::y(), friction, radius } }
    }

    /// OpenSim's conditions: nothing without a pushing normal force (−λ₀ > 0); no slip while
    /// |(λ₂, λ₃)| ≤ μN; no spin then too while λ₁ ≤ rμN (signed).
    #[test]
    fn rolling_rows_follow_the_unilateral_conditions() {
        let contact = rolling(0.5, 0.01);
        let all = [true; ROLLING_ROWS];
        assert_eq!(contact.rows_kept(&all, &[-100.0, 0.4, 30.0, 40.0]), [true, true, true, true]);
        assert_eq!(contact.rows_kept(&all, &[-100.0, 0.6, 30.0, 40.0]), [true, false, true, true]);
        assert_eq!(contact.rows_kept(&all, &[-100.0, -5.0, 30.0, 40.0]), [true, true, true, true]);
        assert_eq!(contact.rows_kept(&all, &[-100.0, 0.0, 30.0, 41.0]), [true, false, false, false]);
        assert_eq!(contact.rows_kept(&all, &[100.0, 0.0, 0.0, 0.0]), [false; ROLLING_ROWS]);
        // Rows not held give no multiplier: a contact without its spin row keeps the order.
        assert_eq!(contact.rows_kept(&[true, false, true, true], &[-100.0, 30.0, 40.0]), [true, true, true, true]);
        assert_eq!(contact.rows_kept(&[false; ROLLING_ROWS], &[]), [false; ROLLING_ROWS]);
        let point = Contact { name: "p".into(), bodies: [0, 1], kind: Kind::Point([Vec3::zeros(); 2]) };
        assert_eq!(point.rows_kept(&all, &[1.0, 2.0, 3.0]), [true; ROLLING_ROWS]);
    }
}
