//! OpenSim's `WrapMath` and `SimmMacros` helpers shared by the wrap objects, with their
//! tolerances: vector normalisation, closest points of lines, segment–plane intersection.

use super::spatial::Vec3;

/// Simbody's machine epsilon, below which `WrapMath::NormalizeOrZero` zeroes a vector.
const EPSILON: f64 = f64::EPSILON;
/// `ROUNDOFF_ERROR` (SimmMacros.h): `EQUAL_WITHIN_ERROR`'s tolerance; lines whose directions'
/// cross product has a smaller squared norm are parallel.
pub(super) const ROUNDOFF_ERROR: f64 = 2e-13;
/// `LINE_EPSILON` (WrapMath.cpp) of the segment–plane intersection.
const LINE_EPSILON: f64 = 1e-5;

/// `DSIGN`: +1 for a ≥ 0, else −1.
pub(super) fn sign(a: f64) -> i32 {
    if a >= 0.0 { 1 } else { -1 }
}

/// `WrapMath::NormalizeOrZero`: the unit vector and the norm (zero below machine epsilon).
pub(super) fn normalize_or_zero(v: &Vec3) -> (Vec3, f64) {
    let norm = v.norm();
    if norm >= EPSILON { (v * (1.0 / norm), norm) } else { (Vec3::zeros(), norm) }
}

/// The parameters l1 ≥ l2 (for a > 0) of the points where a line p2 + l (p1 − p2) meets a
/// quadric, the roots of a l² + b l + c = 0 as OpenSim's `wrapLine`s compute them; `None` when
/// the line misses it.
pub(super) fn line_crossings(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    Some(((-b + disc.sqrt()) / (2.0 * a), (-b - disc.sqrt()) / (2.0 * a)))
}

/// Whether a line parameter lies strictly between the segment's points (0 and 1).
pub(super) fn within_segment(l: f64) -> bool {
    0.0 < l && l < 1.0
}

/// `WrapMath::GetClosestPointOnLineToPoint`: the point of the line through `line_point` along
/// `line` (any length) closest to `point`, and its parameter in units of `line`.
pub(super) fn closest_point_on_line(point: &Vec3, line_point: &Vec3, line: &Vec3) -> (Vec3, f64) {
    let (v1, magnitude) = normalize_or_zero(&(point - line_point));
    let (v2, magnitude2) = normalize_or_zero(line);
    let t = v1.dot(&v2) * magnitude;
    (line_point + t * v2, t / magnitude2)
}

/// The closest points of two lines.
pub(super) struct ClosestPoints {
    pub on_first: Vec3,
    /// Parameter of `on_first` from p1 (0) to p2 (1).
    pub s: f64,
    pub on_second: Vec3,
}

/// `WrapMath::IntersectLines`: the closest points of the lines p1–p2 and p3–p4; `None` when
/// they are parallel.
pub(super) fn intersect_lines(p1: &Vec3, p2: &Vec3, p3: &Vec3, p4: &Vec3) -> Option<ClosestPoints> {
    let (direction1, magnitude1) = normalize_or_zero(&(p2 - p1));
    let (direction2, _) = normalize_or_zero(&(p4 - p3));
    let cross = direction1.cross(&direction2);
    let denominator = cross.norm_squared();
    if denominator.abs() <= ROUNDOFF_ERROR {
        return None;
    }
    let offset = p3 - p1;
    let t = det3(&offset, &direction1, &cross) / denominator;
    let s = det3(&offset, &direction2, &cross) / denominator;
    Some(ClosestPoints { on_first: p1 + s * direction1, s: s / magnitude1, on_second: p3 + t * direction2 })
}

/// Determinant of the matrix with rows a, b, c.
fn det3(a: &Vec3, b: &Vec3, c: &Vec3) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// `WrapMath::IntersectLineSegPlane`: where the segment meets the plane n·x + d = 0 (with
/// OpenSim's tolerances), or `None`.
pub(super) fn intersect_segment_plane(from: &Vec3, to: &Vec3, normal: &Vec3, d: f64) -> Option<Vec3> {
    let segment = to - from;
    let along = segment.dot(normal);
    if along.abs() < LINE_EPSILON {
        return None;
    }
    let t = (-d - normal[0] * from[0] - normal[1] * from[1] - normal[2] * from[2]) / along;
    if !(-LINE_EPSILON..=1.0 + LINE_EPSILON).contains(&t) {
        return None;
    }
    Some(from + t * segment)
}
