//! The thesis' comparison of two knee axes (ch. 4): orientation as the angles between the axes'
//! projections on the transversal and frontal planes, location as the distance between their
//! intersections with a sagittal plane.
//!
//! Planes follow OpenSim's anatomical convention: x anterior, y superior, z right (lateral for
//! a right leg). Transversal ⟂ y, frontal ⟂ x, sagittal ⟂ z.

use nalgebra::{Rotation3, Vector2, Vector3};

use super::{Axis, AxisError};

/// Where the anatomical directions point in the frame the compared axes are expressed in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnatomicalFrame {
    /// Anatomical → axes' frame: its columns are the anterior (x), superior (y) and right (z)
    /// unit vectors in the axes' frame. Identity for axes given in an OpenSim body frame.
    pub rotation: Rotation3<f64>,
}

impl Default for AnatomicalFrame {
    fn default() -> Self {
        AnatomicalFrame { rotation: Rotation3::identity() }
    }
}

impl AnatomicalFrame {
    /// The frame with the given anterior and (approximately) superior directions: superior is
    /// made orthogonal to anterior, right = anterior × superior.
    pub fn from_anterior_superior(anterior: Vector3<f64>, superior: Vector3<f64>) -> Result<AnatomicalFrame, AxisError> {
        let x = Axis::new(Vector3::zeros(), anterior)?.direction;
        let y = Axis::new(Vector3::zeros(), superior - x * superior.dot(&x)).map_err(|_| AxisError::DegenerateComparison {
            what: "the superior direction is parallel to the anterior direction".into(),
        })?;
        let matrix = nalgebra::Matrix3::from_columns(&[x, y.direction, x.cross(&y.direction)]);
        Ok(AnatomicalFrame { rotation: Rotation3::from_matrix_unchecked(matrix) })
    }

    /// A vector of the axes' frame in anatomical components (anterior, superior, right).
    pub fn to_anatomical(&self, vector: &Vector3<f64>) -> Vector3<f64> {
        self.rotation.inverse() * vector
    }
}

/// How far an axis is from a reference axis. Angles in rad, unsigned and independent of the
/// axes' direction signs, in [0, π/2].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisComparison {
    /// Angle between the projections on the transversal plane (⟂ superior), rad.
    pub transversal_angle: f64,
    /// Angle between the projections on the frontal plane (⟂ anterior), rad.
    pub frontal_angle: f64,
    /// Distance between the axes' intersections with the sagittal plane (m).
    pub sagittal_distance: f64,
    /// The other axis' intersection minus the reference axis', (anterior, superior) (m).
    pub sagittal_offset: Vector2<f64>,
    /// The angle between the axes in space, rad.
    pub spatial_angle: f64,
}

/// Compares `other` with `reference` (both in the same frame, whose anatomical directions are
/// `frame`). The sagittal plane passes through `sagittal_point` (default: `reference.point`).
/// Errors if an axis is (nearly) parallel to superior or anterior (no transversal or frontal
/// projection) or lies (nearly) in the sagittal plane (no intersection).
pub fn compare_axes(reference: &Axis, other: &Axis, frame: &AnatomicalFrame, sagittal_point: Option<Vector3<f64>>) -> Result<AxisComparison, AxisError> {
    let (r, o) = (frame.to_anatomical(&reference.direction), frame.to_anatomical(&other.direction));
    let transversal_angle = projected_angle(Vector2::new(r.x, r.z), Vector2::new(o.x, o.z), "transversal")?;
    let frontal_angle = projected_angle(Vector2::new(r.y, r.z), Vector2::new(o.y, o.z), "frontal")?;
    let through = frame.to_anatomical(&sagittal_point.unwrap_or(reference.point));
    let at_reference = sagittal_intersection(&frame.to_anatomical(&reference.point), &r, through.z, "reference")?;
    let at_other = sagittal_intersection(&frame.to_anatomical(&other.point), &o, through.z, "other")?;
    let offset = at_other - at_reference;
    Ok(AxisComparison {
        transversal_angle,
        frontal_angle,
        sagittal_distance: offset.norm(),
        sagittal_offset: Vector2::new(offset.x, offset.y),
        spatial_angle: reference.angle_to(other),
    })
}

/// Smallest projected length (relative to the unit direction) that still defines a projection.
const PROJECTION_TOLERANCE: f64 = 1e-9;

/// The unsigned angle (rad, [0, π/2]) between two lines with 2-D directions `a` and `b`.
fn projected_angle(a: Vector2<f64>, b: Vector2<f64>, plane: &str) -> Result<f64, AxisError> {
    if a.norm() < PROJECTION_TOLERANCE || b.norm() < PROJECTION_TOLERANCE {
        return Err(AxisError::DegenerateComparison { what: format!("an axis is perpendicular to the {plane} plane, so its projection has no direction") });
    }
    let cross = (a.x * b.y - a.y * b.x).abs();
    Ok(cross.atan2(a.dot(&b).abs()))
}

/// Where the line (point, direction) in anatomical components meets the plane z = `z`.
fn sagittal_intersection(point: &Vector3<f64>, direction: &Vector3<f64>, z: f64, which: &str) -> Result<Vector3<f64>, AxisError> {
    if direction.z.abs() < PROJECTION_TOLERANCE {
        return Err(AxisError::DegenerateComparison { what: format!("the {which} axis lies parallel to the sagittal plane, so it does not intersect it") });
    }
    Ok(point + direction * ((z - point.z) / direction.z))
}
