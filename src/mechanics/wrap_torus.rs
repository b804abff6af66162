//! One straight path segment wrapped over a `WrapTorus`, as OpenSim 4.6's `WrapTorus::wrapLine`
//! does it: in the torus' frame (its ring of radius `outer_radius` about z, in the plane
//! z = 0), find the point of the ring closest to the segment's line — by OpenSim's loosely
//! converged Levenberg–Marquardt ([`lmdif`]) from each end of the segment — and wrap the
//! segment over a cylinder of radius `inner_radius` there, tangent to the ring, on the side of
//! the torus' centre (quadrant +x of the cylinder's frame).

mod lmdif;

use super::spatial::{Mat3, Vec3};
use super::wrap_cylinder::Cylinder;
use super::wrap_math::{normalize_or_zero, sign};
use super::wrap_surface::{Quadrant, SurfacePath, Wrapping};

/// `CYL_LENGTH` (m): the cylinder is long enough never to end.
const CYLINDER_LENGTH: f64 = 10000.0;

/// A `WrapTorus` in its own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Torus {
    /// The tube's radius (m).
    pub inner_radius: f64,
    /// The ring's radius (m).
    pub outer_radius: f64,
    /// `None` on all sides; else the ring point must lie on the quadrant's side.
    pub quadrant: Option<Quadrant>,
}

impl Torus {
    /// Wraps the segment p1–p2 (m, in the torus' frame). Never a mandatory wrap. When the
    /// cylinder does not wrap the segment OpenSim still reports a wrap, with the tangent points
    /// a fresh `WrapResult` holds (NaN): a wrap whose length change is NaN, never the best.
    pub fn wrap_line(&self, p1: &Vec3, p2: &Vec3, single_wrap: bool) -> Wrapping {
        let Some(ring_point) = self.closest_ring_point(p1, p2) else { return Wrapping::NoWrap };
        let centre_side = -ring_point;
        let (x_axis, _) = normalize_or_zero(&centre_side);
        let y_axis = Vec3::new(0.0, 0.0, -1.0);
        let z_axis = x_axis.cross(&y_axis);
        // Rows: the cylinder's axes in the torus' frame; the ring point is its origin.
        let rotation = Mat3::from_rows(&[x_axis.transpose(), y_axis.transpose(), z_axis.transpose()]);
        let origin = rotation * centre_side;
        let into_cylinder = |p: &Vec3| rotation * p + origin;
        let from_cylinder = |p: &Vec3| rotation.transpose() * (p - origin);
        let cylinder = Cylinder { radius: self.inner_radius, length: CYLINDER_LENGTH, quadrant: Some(Quadrant { axis: 0, sign: 1 }) };
        match cylinder.wrap_line(&into_cylinder(p1), &into_cylinder(p2), single_wrap) {
            Wrapping::Mandatory(path) | Wrapping::Wrapped(path) => {
                Wrapping::Wrapped(SurfacePath { r1: from_cylinder(&path.r1), r2: from_cylinder(&path.r2), length: path.length })
            }
            Wrapping::NoWrap | Wrapping::InsideRadius => Wrapping::Wrapped(SurfacePath { r1: Vec3::repeat(f64::NAN), r2: Vec3::repeat(f64::NAN), length: 0.0 }),
        }
    }

    /// `findClosestPoint`: the points of the line nearest the ring found from p1 towards p2 and
    /// from p2 towards p1; the nearer (with a quadrant: the one on its side, the nearer if
    /// both are), projected onto the ring. `None` when neither lies on the quadrant's side.
    fn closest_ring_point(&self, p1: &Vec3, p2: &Vec3) -> Option<Vec3> {
        let radius = self.outer_radius;
        let from_p1 = nearest_line_point(radius, p1, p2);
        let from_p2 = nearest_line_point(radius, p2, p1);
        let distance = |a: &Vec3| (a.x * a.x + a.y * a.y + a.z * a.z + radius * radius - 2.0 * radius * (a.x * a.x + a.y * a.y).sqrt()).sqrt();
        let first_nearer = distance(&from_p1) < distance(&from_p2);
        let better = match self.quadrant {
            Some(quadrant) => {
                let on_side = |a: &Vec3| sign(a[quadrant.axis]) == quadrant.sign;
                match (on_side(&from_p1), on_side(&from_p2)) {
                    (true, true) => if first_nearer { from_p1 } else { from_p2 },
                    (true, false) => from_p1,
                    (false, true) => from_p2,
                    (false, false) => return None,
                }
            }
            None => if first_nearer { from_p1 } else { from_p2 },
        };
        let magnitude = (better.x * better.x + better.y * better.y).sqrt();
        Some(Vec3::new(better.x * radius / magnitude, better.y * radius / magnitude, 0.0))
    }
}

/// The point of the line from `start` towards `end` where OpenSim's iteration on the
/// stationarity of the squared distance to the ring (`calcCircleResids`) stops.
fn nearest_line_point(radius: f64, start: &Vec3, end: &Vec3) -> Vec3 {
    let direction = |from: &Vec3, to: &Vec3| {
        let magnitude = ((to[0] - from[0]) * (to[0] - from[0]) + (to[1] - from[1]) * (to[1] - from[1]) + (to[2] - from[2]) * (to[2] - from[2])).sqrt();
        Vec3::from_fn(|i, _| (to[i] - from[i]) / magnitude)
    };
    let n = direction(start, end);
    let c2 = 2.0 * (start[0] * n[0] + start[1] * n[1] + start[2] * n[2]);
    let c3 = start[0] * n[0] + start[1] * n[1];
    let c4 = n[0] * n[0] + n[1] * n[1];
    let c5 = start[0] * start[0] + start[1] * start[1];
    let u = lmdif::solve(|u| c2 + 2.0 * u - 2.0 * radius * (2.0 * c4 * u + 2.0 * c3) / (u * u * c4 + 2.0 * c3 * u + c5).sqrt());
    Vec3::from_fn(|i, _| start[i] + u * n[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const TORUS: Torus = Torus { inner_radius: 0.01, outer_radius: 0.05, quadrant: None };

    /// A segment along z through the tube at x = 0.045 (0.005 inside the ring): the ring point
    /// nearest its line is (0.05, 0, 0) and the path goes round the tube's inner side in the
    /// plane y = 0, tangent to its circle (centre (0.05, 0, 0), radius 0.01) at the polar angles
    /// (in x–z) φ ± acos(r/d) of the points, d their distance from the centre; the length is r
    /// times the angle between the tangent points. Never a mandatory wrap.
    #[test]
    fn segment_through_the_tube_wraps_round_its_inner_side() {
        let (p1, p2) = (Vec3::new(0.045, 0.0, 0.1), Vec3::new(0.045, 0.0, -0.1));
        let Wrapping::Wrapped(path) = TORUS.wrap_line(&p1, &p2, true) else { panic!() };
        let (r, d) = (0.01, (0.005f64.powi(2) + 0.1f64.powi(2)).sqrt());
        let phi = 0.1f64.atan2(-0.005) + (r / d).acos();
        assert_relative_eq!(path.r1, Vec3::new(0.05 + r * phi.cos(), 0.0, r * phi.sin()), epsilon = 1e-15);
        assert_relative_eq!(path.r2, Vec3::new(0.05 + r * phi.cos(), 0.0, -r * phi.sin()), epsilon = 1e-15);
        assert_relative_eq!(path.length, r * (2.0 * std::f64::consts::PI - 2.0 * phi), epsilon = 1e-15);
    }

    /// With a quadrant the ring point must lie on its side: none on −x for that segment.
    #[test]
    fn a_ring_point_off_the_quadrant_does_not_wrap() {
        let torus = Torus { quadrant: Some(Quadrant { axis: 0, sign: -1 }), ..TORUS };
        assert_eq!(torus.wrap_line(&Vec3::new(0.045, 0.0, 0.1), &Vec3::new(0.045, 0.0, -0.1), true), Wrapping::NoWrap);
        // Far from the tube, the cylinder does not wrap: OpenSim's NaN wrap, never the best.
        let Wrapping::Wrapped(path) = TORUS.wrap_line(&Vec3::new(0.01, 0.0, 0.1), &Vec3::new(0.01, 0.0, -0.1), true) else { panic!() };
        assert!(path.r1.x.is_nan());
    }
}
