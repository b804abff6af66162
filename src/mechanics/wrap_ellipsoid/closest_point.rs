//! `WrapEllipsoid::findClosestPoint` and `closestPointToEllipse`: the point of an ellipsoid
//! (ellipse) centred on the origin closest to a point, by Eberly's Newton iteration (Graphics
//! Gems IV) with OpenSim's special cases for points near the coordinate planes (axes).

use super::super::spatial::Vec3;
use super::super::wrap_math::ROUNDOFF_ERROR;

/// Newton steps of both iterations.
const ITERATIONS: usize = 64;
/// Absolute tolerance on the iterations' polynomial.
const TOLERANCE: f64 = 1e-9;

/// `EQUAL_WITHIN_ERROR(0.0, x)`.
fn near_zero(x: f64) -> bool {
    x.abs() <= ROUNDOFF_ERROR
}

/// `findClosestPoint`: the point of the ellipsoid with radii `a` closest to `point`. For a point
/// within `ROUNDOFF_ERROR` of a coordinate plane it solves in that elliptical cross-section —
/// the one whose `dimensions` (unnormalised radii) sum least when there are several — else it
/// iterates on the ellipsoid. `None` when that iteration does not converge in 64 steps: OpenSim
/// then leaves its output variables as they were.
pub(super) fn on_ellipsoid(a: &Vec3, dimensions: &Vec3, point: &Vec3) -> Option<Vec3> {
    match nearest_plane(dimensions, point) {
        Some(axis) => Some(on_cross_section(a, point, axis)),
        None => on_ellipsoid_off_planes(a, point),
    }
}

/// `findClosestPoint` told the plane: the closest point of the elliptical cross-section through
/// `point` normal to `axis` (0, 1, 2 for x, y, z), the point's coordinate along the axis kept.
pub(super) fn on_cross_section(a: &Vec3, point: &Vec3, axis: usize) -> Vec3 {
    let (u, v, w) = (point[0], point[1], point[2]);
    match axis {
        0 => {
            let (y, z) = on_ellipse(a[1], a[2], v, w);
            Vec3::new(u, y, z)
        }
        1 => {
            let (z, x) = on_ellipse(a[2], a[0], w, u);
            Vec3::new(x, v, z)
        }
        _ => {
            let (x, y) = on_ellipse(a[0], a[1], u, v);
            Vec3::new(x, y, w)
        }
    }
}

/// The coordinate plane `point` lies on within `ROUNDOFF_ERROR` whose cross-section has the
/// least sum of radii (the first such on ties), if any.
fn nearest_plane(dimensions: &Vec3, point: &Vec3) -> Option<usize> {
    let mut nearest = None;
    let mut least = f64::INFINITY;
    for axis in (0..3).filter(|&axis| near_zero(point[axis])) {
        let sum = (0..3).filter(|&j| j != axis).fold(0.0, |sum, j| sum + dimensions[j]);
        if least > sum {
            nearest = Some(axis);
            least = sum;
        }
    }
    nearest
}

/// The general case: Newton on t, the closest point being (a²u/(t+a²), b²v/(t+b²), c²w/(t+c²)).
fn on_ellipsoid_off_planes(radii: &Vec3, point: &Vec3) -> Option<Vec3> {
    let (a, b, c) = (radii[0], radii[1], radii[2]);
    let (u, v, w) = (point[0], point[1], point[2]);
    let (a2, b2, c2) = (a * a, b * b, c * c);
    let (a2u2, b2v2, c2w2) = (a2 * (u * u), b2 * (v * v), c2 * (w * w));
    let mut t = if (u / a) * (u / a) + (v / b) * (v / b) + (w / c) * (w / c) < 1.0 { 0.0 } else { a.max(b).max(c) * (u * u + v * v + w * w).sqrt() };
    for _ in 0..ITERATIONS {
        let (p, q, r) = (t + a2, t + b2, t + c2);
        let (p2, q2, r2) = (p * p, q * q, r * r);
        let f = p2 * q2 * r2 - a2u2 * q2 * r2 - b2v2 * p2 * r2 - c2w2 * p2 * q2;
        if f.abs() < TOLERANCE {
            return Some(Vec3::new(a2 * u / p, b2 * v / q, c2 * w / r));
        }
        let (pq, pr, qr) = (p * q, p * r, q * r);
        let pqr = p * q * r;
        let fp = 2.0 * (pqr * (qr + pr + pq) - a2u2 * qr * (q + r) - b2v2 * pr * (p + r) - c2w2 * pq * (p + q));
        t -= f / fp;
    }
    None
}

/// `closestPointToEllipse`: the point of the ellipse (x/a)² + (y/b)² = 1 closest to (u, v).
/// After 64 Newton steps without convergence it takes the last iterate.
fn on_ellipse(a: f64, b: f64, u: f64, v: f64) -> (f64, f64) {
    let (a2, b2) = (a * a, b * b);
    let (a2u2, b2v2) = (a2 * (u * u), b2 * (v * v));
    match (near_zero(u), near_zero(v)) {
        (true, true) => return if a < b { (if u < 0.0 { -a } else { a }, v) } else { (u, if v < 0.0 { -b } else { b }) },
        (true, false) => {
            if a >= b || v.abs() >= b - a2 / b {
                return (u, if v >= 0.0 { b } else { -b });
            }
            let y = b2 * v / (b2 - a2);
            let ydb = y / b;
            return (a * (1.0 - ydb * ydb).abs().sqrt(), y);
        }
        (false, true) => {
            if b >= a || u.abs() >= a - b2 / a {
                return (if u >= 0.0 { a } else { -a }, v);
            }
            let x = a2 * u / (a2 - b2);
            let xda = x / a;
            return (x, b * (1.0 - xda * xda).abs().sqrt());
        }
        (false, false) => {}
    }
    let mut t = if (u / a) * (u / a) + (v / b) * (v / b) < 1.0 { 0.0 } else { a.max(b) * (u * u + v * v).sqrt() };
    let (mut p, mut q) = (f64::NAN, f64::NAN);
    for _ in 0..ITERATIONS {
        (p, q) = (t + a2, t + b2);
        let f = p * p * (q * q) - a2u2 * (q * q) - b2v2 * (p * p);
        if f.abs() < TOLERANCE {
            break;
        }
        let fp = 2.0 * (p * q * (p + q) - a2u2 * q - b2v2 * p);
        t -= f / fp;
    }
    (a2 * u / p, b2 * v / q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The closest point of a surface to an outside point is where the surface's normal points
    /// at it: (x − u) is parallel to the gradient (x/a², y/b², z/c²).
    #[test]
    fn closest_points_lie_on_the_surface_along_its_normal() {
        let radii = Vec3::new(1.4, 0.8, 0.8);
        for point in [Vec3::new(1.5, 0.9, 0.4), Vec3::new(-0.2, 0.3, 1.1), Vec3::new(0.3, -0.2, 0.1)] {
            let x = on_ellipsoid(&radii, &radii, &point).unwrap();
            // Newton stops at |f| < 1e-9, which leaves a point inside 2e-7 off the surface.
            assert_relative_eq!(x.component_div(&radii).norm_squared(), 1.0, epsilon = 1e-6);
            let normal = x.component_div(&radii.component_mul(&radii));
            assert_relative_eq!((point - x).normalize().cross(&normal.normalize()).norm(), 0.0, epsilon = 1e-15);
        }
        // In the cross-section z = w: the same conditions in two dimensions.
        let point = Vec3::new(1.2, 0.9, 0.3);
        let x = on_cross_section(&radii, &point, 2);
        assert_eq!(x.z, 0.3);
        assert_relative_eq!((x.x / 1.4).powi(2) + (x.y / 0.8).powi(2), 1.0, epsilon = 1e-9);
        assert_relative_eq!((x.x / 1.4).powi(2) + (x.y / 0.8).powi(2), 1.0, epsilon = 1e-9);
        assert_relative_eq!((point.x - x.x) * x.y / 0.64 - (point.y - x.y) * x.x / 1.96, 0.0, epsilon = 1e-15);
    }

    /// On the minor axis inside the evolute the closest point leaves the axis; on the major axis
    /// it is the vertex.
    #[test]
    fn points_on_an_axis_use_the_closed_forms() {
        let (a, b) = (1.0, 2.0);
        assert_eq!(on_ellipse(a, b, 0.0, 3.0), (0.0, 2.0));
        let (x, y) = on_ellipse(a, b, 0.0, 0.5);
        assert_relative_eq!(y, 4.0 * 0.5 / 3.0, epsilon = 1e-15);
        assert_relative_eq!(x, (1.0 - (y / b).powi(2)).sqrt(), epsilon = 1e-15);
        assert_eq!(on_ellipse(a, b, 0.5, 0.0), (1.0, 0.0));
    }
}
