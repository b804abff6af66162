//! One straight path segment wrapped over a `WrapSphere`, as OpenSim 4.6's
//! `WrapSphere::wrapLine` does it: pure geometry in the sphere's frame (centred on the origin).
//! A segment wraps when its straight line passes through the sphere; the path runs over the
//! great circle in the plane of the line and the centre, between the tangent points from the
//! two path points, and its length is the radius times the angle between them. Without a
//! quadrant the wrap is never mandatory: the path's other segments may wrap with a smaller
//! length change.

use super::spatial::Vec3;
use super::wrap_math::{closest_point_on_line, line_crossings, normalize_or_zero, sign, within_segment};
use super::wrap_surface::{Quadrant, SurfacePath, Wrapping};

/// A `WrapSphere` in its own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// m.
    pub radius: f64,
    /// `None` wraps on all sides.
    pub quadrant: Option<Quadrant>,
}

/// The two tangent points from one path point, on the great circle normal to `n`.
#[derive(Debug, Clone, Copy)]
struct Candidates {
    a: Vec3,
    b: Vec3,
}

impl Sphere {
    /// Wraps the segment p1–p2 (m, in the sphere's frame).
    pub fn wrap_line(&self, p1: &Vec3, p2: &Vec3) -> Wrapping {
        let radius = self.radius;
        if p1.norm() < radius || p2.norm() < radius {
            return Wrapping::InsideRadius;
        }
        if !self.line_passes_through(p1, p2) {
            return Wrapping::NoWrap;
        }
        let (p1p2, _) = normalize_or_zero(&(p1 - p2));
        let (np2, _) = normalize_or_zero(p2);
        let hp2 = p1p2.cross(&np2);
        if hp2.norm() < 0.00001 {
            // The line passes within 1e-5 of the centre: OpenSim takes the tangent points of
            // this PathWrap's previous wrap times its `factor`, which a WrapResult never keeps
            // (NaN): a wrap whose length change is NaN, never the best.
            return Wrapping::Wrapped(SurfacePath { r1: Vec3::repeat(f64::NAN), r2: Vec3::repeat(f64::NAN), length: f64::NAN });
        }
        let (n, _) = normalize_or_zero(&hp2);
        let (first, second) = (self.candidates(p1, &n), self.candidates(p2, &n));
        let (r1, r2) = most_aligned(&first, &second);
        let (mandatory, far_side, r1, r2) = match self.quadrant {
            Some(quadrant) => match self.quadrant_side(quadrant, [p1, p2], &p1p2, [first, second], [r1, r2]) {
                Some(side) => side,
                None => return Wrapping::NoWrap,
            },
            None => (false, false, r1, r2),
        };
        let path = SurfacePath { r1, r2, length: self.arc_length(&r1, &r2, far_side) };
        if mandatory { Wrapping::Mandatory(path) } else { Wrapping::Wrapped(path) }
    }

    /// Whether the line p1–p2 enters and leaves the sphere strictly between p1 and p2.
    fn line_passes_through(&self, p1: &Vec3, p2: &Vec3) -> bool {
        let ri = p1 - p2;
        let mp = Vec3::from_fn(|i, _| 0.0 - p2[i]);
        let crossings = line_crossings(ri.dot(&ri), -2.0 * mp.dot(&ri), mp.dot(&mp) - self.radius * self.radius);
        crossings.is_some_and(|(l1, l2)| within_segment(l1) && within_segment(l2) && l1 >= l2)
    }

    /// The tangent points from `p` on the great circle normal to `n`: the direction to the
    /// centre turned by ±asin(R/|p|) about n, at the tangent distance |p| cos(asin(R/|p|)).
    fn candidates(&self, p: &Vec3, n: &Vec3) -> Candidates {
        let (y, _) = normalize_or_zero(&Vec3::from_fn(|i, _| 0.0 - p[i]));
        let z = n.cross(&y);
        let distance = p.norm();
        let angle = (self.radius / distance).asin();
        let cos = angle.cos();
        // Simbody's rotation about x by ±angle, whose sines enter negated.
        let point = |sin: f64| Vec3::from_fn(|i, _| p[i] + (y[i] * cos + z[i] * -sin) * distance * cos);
        Candidates { a: point(angle.sin()), b: point((-angle).sin()) }
    }

    /// With a quadrant: `None` (no wrap) when a point lies on the quadrant's side and the line
    /// neither crosses the sphere within 1 m of p1 nor passes it on the other side between
    /// points on opposite sides. When a point lies off the side, the candidates facing the
    /// centre from the path points, flipped to the other pair if the path would leave them
    /// against the quadrant's direction. Returns (mandatory, far side, r1, r2).
    fn quadrant_side(&self, quadrant: Quadrant, [p1, p2]: [&Vec3; 2], p1p2: &Vec3, [first, second]: [Candidates; 2], [r1, r2]: [Vec3; 2]) -> Option<(bool, bool, Vec3, Vec3)> {
        let (axis, on_side) = (quadrant.axis, |p: &Vec3| sign(p[quadrant.axis]) == quadrant.sign);
        let mut mandatory = false;
        if on_side(p1) || on_side(p2) {
            // OpenSim's line parameter here is a distance (p1p2 is a unit vector), compared with 1.
            let (closest, t) = closest_point_on_line(&Vec3::zeros(), p1, p1p2);
            let t = -t;
            if (Vec3::zeros() - closest).norm_squared() < self.radius * self.radius && t > 0.0 && t < 1.0 {
                mandatory = true;
            } else if !(sign(p1[axis]) != sign(p2[axis]) && sign(closest[axis]) != quadrant.sign) {
                return None;
            }
        }
        if on_side(p1) && on_side(p2) {
            return Some((mandatory, false, r1, r2));
        }
        let (r1, r2) = constrained_tangent_points(quadrant, [p1, p2], [first, second]);
        let sum_muscle = (r1 - p1) + (r2 - p2);
        let sum_radial = (r1 - Vec3::zeros()) + (r2 - Vec3::zeros());
        Some((mandatory, sum_radial.dot(&sum_muscle) < 0.0, r1, r2))
    }

    /// `radius` times the angle between the tangent points; the far side gives −(2π − angle):
    /// OpenSim's far-side wrap over a sphere has a negative length (the wrap zoo's flexor_close
    /// down to −0.154 m, its path 0.31 m shorter than one over the surface).
    fn arc_length(&self, r1: &Vec3, r2: &Vec3, far_side: bool) -> f64 {
        let (r1n, _) = normalize_or_zero(r1);
        let (r2n, _) = normalize_or_zero(r2);
        let angle = r1n.dot(&r2n).acos();
        self.radius * if far_side { -(2.0 * std::f64::consts::PI - angle) } else { angle }
    }
}

/// Without a quadrant: the pair of candidates whose directions from the centre are most aligned.
fn most_aligned(first: &Candidates, second: &Candidates) -> (Vec3, Vec3) {
    let unit = |r: &Vec3| normalize_or_zero(r).0;
    let (r1am, r1bm, r2am, r2bm) = (unit(&first.a), unit(&first.b), unit(&second.a), unit(&second.b));
    let (j1, j2, j3, j4) = (r1am.dot(&r2am), r1am.dot(&r2bm), r1bm.dot(&r2am), r1bm.dot(&r2bm));
    if j1 > j2 && j1 > j3 && j1 > j4 {
        (first.a, second.a)
    } else if j2 > j3 && j2 > j4 {
        (first.a, second.b)
    } else if j3 > j4 {
        (first.b, second.a)
    } else {
        (first.b, second.b)
    }
}

/// With a quadrant and a point off its side: for each path point the candidate whose direction
/// from the centre is nearer that of −(p1 + p2); both swapped for the other candidates when
/// (r1 − p1) + (r2 − p2) points against the quadrant's axis.
fn constrained_tangent_points(quadrant: Quadrant, [p1, p2]: [&Vec3; 2], [first, second]: [Candidates; 2]) -> (Vec3, Vec3) {
    let unit = |r: &Vec3| normalize_or_zero(r).0;
    let (towards_centre, _) = normalize_or_zero(&Vec3::from_fn(|i, _| (0.0 - p1[i]) + (0.0 - p2[i])));
    let pick = |c: &Candidates| if unit(&c.a).dot(&towards_centre) > unit(&c.b).dot(&towards_centre) { (c.a, c.b) } else { (c.b, c.a) };
    let ((r1, other1), (r2, other2)) = (pick(&first), pick(&second));
    let mut wrap_axis = Vec3::zeros();
    wrap_axis[quadrant.axis] = f64::from(quadrant.sign);
    let (direction, _) = normalize_or_zero(&((r1 - p1) + (r2 - p2)));
    if direction.dot(&wrap_axis) < 0.0 { (other1, other2) } else { (r1, r2) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const SPHERE: Sphere = Sphere { radius: 0.02, quadrant: None };

    /// Polar angle φ (rad, in the z = 0 plane) on the sphere.
    fn on_circle(phi: f64) -> Vec3 {
        Vec3::new(0.02 * phi.cos(), 0.02 * phi.sin(), 0.0)
    }

    /// A segment from (−a, h, 0) to (a, h, 0), h < R, wraps over the +y side of the great circle
    /// z = 0, with tangent points at the polar angles of its points ∓ acos(R/d), d = √(a² + h²),
    /// and the length R times the angle between them. Without a quadrant the wrap is not
    /// mandatory.
    #[test]
    fn segment_through_the_sphere_wraps_over_the_great_circle() {
        let (a, h) = (0.05, 0.005);
        let Wrapping::Wrapped(path) = SPHERE.wrap_line(&Vec3::new(-a, h, 0.0), &Vec3::new(a, h, 0.0)) else { panic!() };
        let d = (a * a + h * h).sqrt();
        let (phi1, phi2) = (h.atan2(-a) - (0.02 / d).acos(), h.atan2(a) + (0.02 / d).acos());
        assert_relative_eq!(path.r1, on_circle(phi1), epsilon = 1e-15);
        assert_relative_eq!(path.r2, on_circle(phi2), epsilon = 1e-15);
        assert_relative_eq!(path.length, 0.02 * (phi1 - phi2), epsilon = 1e-15);
        // With the quadrant +y and the points on its side, the same wrap is mandatory.
        let upper = Sphere { quadrant: Some(Quadrant { axis: 1, sign: 1 }), ..SPHERE };
        assert_eq!(upper.wrap_line(&Vec3::new(-a, h, 0.0), &Vec3::new(a, h, 0.0)), Wrapping::Mandatory(path));
    }

    /// Points close under the sphere with the quadrant +y: the tangent points facing up lie below
    /// the centre, at polar angles π ± (atan(h/a) − acos(R/d)), and the path goes round the far
    /// side, over the top — with OpenSim's negative length, −R(2π − θ).
    #[test]
    fn far_side_wraps_have_a_negative_length() {
        let (a, h) = (0.012, 0.018);
        let upper = Sphere { quadrant: Some(Quadrant { axis: 1, sign: 1 }), ..SPHERE };
        let Wrapping::Wrapped(path) = upper.wrap_line(&Vec3::new(-a, -h, 0.0), &Vec3::new(a, -h, 0.0)) else { panic!() };
        let phi1 = std::f64::consts::PI + (h / a).atan() - (0.02 / (a * a + h * h).sqrt()).acos();
        assert_relative_eq!(path.r1, on_circle(phi1), epsilon = 1e-15);
        assert_relative_eq!(path.r2, on_circle(std::f64::consts::PI - phi1), epsilon = 1e-15);
        let theta = path.r1.angle(&path.r2);
        assert_relative_eq!(path.length, -0.02 * (2.0 * std::f64::consts::PI - theta), epsilon = 1e-15);
        assert!(path.length < -0.02 * std::f64::consts::PI);
    }

    #[test]
    fn segments_that_miss_start_inside_or_pass_through_the_centre() {
        assert_eq!(SPHERE.wrap_line(&Vec3::new(-0.05, 0.03, 0.0), &Vec3::new(0.05, 0.03, 0.0)), Wrapping::NoWrap);
        assert_eq!(SPHERE.wrap_line(&Vec3::new(-0.01, 0.0, 0.0), &Vec3::new(0.05, 0.0, 0.0)), Wrapping::InsideRadius);
        assert_eq!(SPHERE.wrap_line(&Vec3::new(-0.08, 0.0, 0.0), &Vec3::new(-0.05, 0.0, 0.0)), Wrapping::NoWrap);
        // Through the centre OpenSim reuses a previous wrap's NaN tangent points.
        let Wrapping::Wrapped(path) = SPHERE.wrap_line(&Vec3::new(-0.05, 0.0, 0.0), &Vec3::new(0.05, 0.0, 0.0)) else { panic!() };
        assert!(path.length.is_nan() && path.r1.x.is_nan());
    }
}
