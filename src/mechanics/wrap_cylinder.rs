//! One straight path segment wrapped over a `WrapCylinder`, as OpenSim 4.6's
//! `WrapCylinder::wrapLine` does it: pure geometry in the cylinder's frame (axis = z through the
//! origin, the cylinder's length centred on z = 0). The tangent points and the helical surface
//! length are OpenSim's, including its heuristics: the axial slide of the tangent points through
//! the plane of the two path points and an "apex", the `quadrant` side rules, and — when a path
//! has more than one wrap — the iterative tangent adjustment of `_make_spiral_path`.

use super::spatial::{rotation_about, Vec3};
use super::wrap_math::{closest_point_on_line, intersect_lines, intersect_segment_plane, normalize_or_zero, sign, within_segment};
use super::wrap_surface::{Quadrant, SurfacePath, Wrapping};

/// `TANGENCY_THRESHOLD` of `_adjust_tangent_point`: 0.1° (the source comment says 1°).
const TANGENCY_THRESHOLD: f64 = 0.1 * std::f64::consts::PI / 180.0;
/// `MAX_ITERATIONS` of the tangent adjustment.
const MAX_ITERATIONS: usize = 100;
/// Length (m) of the surface pieces `_make_spiral_path` samples when it adjusts tangent points.
const SURFACE_PIECE: f64 = 0.002;

/// A `WrapCylinder` in its own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// m.
    pub radius: f64,
    /// m.
    pub length: f64,
    /// `None` wraps on all sides.
    pub quadrant: Option<Quadrant>,
}

const AXIS_POINT: Vec3 = Vec3::new(0.0, 0.0, -1.0);
const AXIS: Vec3 = Vec3::new(0.0, 0.0, 1.0);

impl Cylinder {
    /// Wraps the segment p1–p2 (m, in the cylinder's frame). `single_wrap`: the path has only
    /// this one `PathWrap`, so OpenSim (without a visualizer) keeps the first tangent points;
    /// otherwise it adjusts them towards tangency with the helix.
    pub fn wrap_line(&self, p1: &Vec3, p2: &Vec3, single_wrap: bool) -> Wrapping {
        let radius = self.radius;
        let r_squared = radius * radius;
        if distance_squared_to_axis(p1) < r_squared || distance_squared_to_axis(p2) < r_squared {
            return Wrapping::InsideRadius;
        }
        let cylinder_start = Vec3::new(0.0, 0.0, -0.5 * self.length);
        let cylinder_end = Vec3::new(0.0, 0.0, 0.5 * self.length);
        let (near12, t12, near00) = match intersect_lines(p1, p2, &cylinder_start, &cylinder_end) {
            Some(closest) => (closest.on_first, closest.s, closest.on_second),
            None => (Vec3::repeat(f64::NAN), f64::NAN, Vec3::repeat(f64::NAN)),
        };
        let crosses = (near12 - near00).norm_squared() < r_squared && within_segment(t12);
        let mut mandatory = false;
        if self.quadrant.is_none() {
            if !crosses {
                return Wrapping::NoWrap;
            }
            mandatory = true;
        }

        let (p11, _) = closest_point_on_line(p1, &AXIS_POINT, &AXIS);
        let (p22, _) = closest_point_on_line(p2, &AXIS_POINT, &AXIS);
        let (r1a, r1b, p11_distance) = tangent_candidates(p1, &p11, radius);
        let (r2a, r2b, p22_distance) = tangent_candidates(p2, &p22, radius);
        let (r1, r2, far_side_wrap, long_wrap) = match self.quadrant {
            Some(quadrant) => {
                if sign(p1[quadrant.axis]) == quadrant.sign || sign(p2[quadrant.axis]) == quadrant.sign {
                    if crosses {
                        mandatory = true;
                    } else if !(sign(p1[quadrant.axis]) != sign(p2[quadrant.axis]) && sign(near12[quadrant.axis]) != quadrant.sign) {
                        return Wrapping::NoWrap;
                    }
                }
                quadrant_tangent_points(quadrant, [p1, p2], [&p11, &p22], [r1a, r1b], [r2a, r2b])
            }
            None => {
                let (r1, r2) = most_aligned_tangent_points([&p11, &p22], [r1a, r1b], [r2a, r2b]);
                (r1, r2, false, false)
            }
        };
        let apex = self.apex(p1, p2, p11_distance / (p11_distance + p22_distance), far_side_wrap);
        let (r1, r2) = slide_onto_apex_plane(p1, p2, &apex, [&p11, &p22], r1, r2);

        let half_length = self.length / 2.0;
        let beyond = |r: &Vec3| r[2] < -half_length || r[2] > half_length;
        if beyond(&r1) && beyond(&r2) {
            return Wrapping::NoWrap;
        }
        let path = self.spiral_path(p1, p2, long_wrap, r1, r2, single_wrap);
        if mandatory { Wrapping::Mandatory(path) } else { Wrapping::Wrapped(path) }
    }

    /// The apex: where the plane through p1, p2 and the axis point under the segment (at the
    /// fraction `t` of it) meets the surface, on the near side (far side for a far-side wrap).
    fn apex(&self, p1: &Vec3, p2: &Vec3, t: f64, far_side_wrap: bool) -> Vec3 {
        let middle = p1 + t * (p2 - p1);
        let (axis_point, _) = closest_point_on_line(&middle, &AXIS_POINT, &AXIS);
        let (l1, _) = normalize_or_zero(&(p1 - axis_point));
        let (l2, _) = normalize_or_zero(&(p2 - axis_point));
        let (plane_normal, _) = normalize_or_zero(&unit(&l1.cross(&l2)));
        let (vertical1, _) = normalize_or_zero(&AXIS.cross(&plane_normal));
        let (vertical2, _) = normalize_or_zero(&plane_normal.cross(&AXIS));
        let apex1 = axis_point + self.radius * vertical1;
        let apex2 = axis_point + self.radius * vertical2;
        let first_nearer = (middle - apex1).norm_squared() < (middle - apex2).norm_squared();
        if first_nearer != far_side_wrap { apex1 } else { apex2 }
    }

    /// `_make_spiral_path`: the helix from r1 to r2 (the long way round for `long_wrap`); for a
    /// path with several wraps, r1 and r2 first slide until the lines from p1 and p2 meet the
    /// helix within [`TANGENCY_THRESHOLD`] of tangency (at most [`MAX_ITERATIONS`] times).
    fn spiral_path(&self, p1: &Vec3, p2: &Vec3, long_wrap: bool, mut r1: Vec3, mut r2: Vec3, single_wrap: bool) -> SurfacePath {
        let sense = if long_wrap { -1.0 } else { 1.0 };
        let mut iterations = 0;
        loop {
            let (r1_axis, _) = closest_point_on_line(&r1, &AXIS_POINT, &AXIS);
            let (r2_axis, _) = closest_point_on_line(&r2, &AXIS_POINT, &AXIS);
            let axial_distance = (r2_axis - r1_axis).dot(&AXIS);
            let (u, v) = (r1 - r1_axis, r2 - r2_axis);
            let mut theta = u.cross(&v).dot(&AXIS).atan2(u.dot(&v));
            if long_wrap {
                theta = 2.0 * std::f64::consts::PI - theta;
            }
            let x = self.radius * theta;
            let length = (x * x + axial_distance * axial_distance).sqrt();
            let pieces = ((length / SURFACE_PIECE) as usize).max(1);
            if single_wrap || pieces < 2 || iterations >= MAX_ITERATIONS {
                return SurfacePath { r1, r2, length };
            }
            // OpenSim's lambda reads r1 when called: the second point uses the adjusted r1.
            let helix = |r1: &Vec3, t: f64| rotation_about(&AXIS, sense * t * theta) * r1 + AXIS * (t * axial_distance);
            let t = 1.0 / pieces as f64;
            let w1 = helix(&r1, t);
            let adjusted_r1 = adjust_tangent_point(p1, &mut r1, &w1);
            let w2 = helix(&r1, 1.0 - t);
            let adjusted_r2 = adjust_tangent_point(p2, &mut r2, &w2);
            if !(adjusted_r1 || adjusted_r2) {
                return SurfacePath { r1, r2, length };
            }
            iterations += 1;
        }
    }
}

/// With a quadrant: OpenSim's choice between the pairs (r1a, r2b) and (r1b, r2a) by which
/// candidates lie on the quadrant's side, whether the wrap goes round the far side, and whether
/// it is the long way round. Returns (r1, r2, far side, long wrap).
fn quadrant_tangent_points(quadrant: Quadrant, [p1, p2]: [&Vec3; 2], [p11, p22]: [&Vec3; 2], [r1a, r1b]: [Vec3; 2], [r2a, r2b]: [Vec3; 2]) -> (Vec3, Vec3, bool, bool) {
    let (r1am, r1bm, r2am, r2bm) = (r1a - p11, r1b - p11, r2a - p22, r2b - p22);
    let alpha = (r1am.dot(&r2bm) / (r1am.norm() * r2bm.norm())).acos();
    let beta = (r1bm.dot(&r2am) / (r1bm.norm() * r2am.norm())).acos();
    let on_side = |r: &Vec3| sign(r[quadrant.axis]) == quadrant.sign;
    // The first pair is the far side when alpha > beta, the second when not.
    let first_far = alpha > beta;
    let a_b = (r1a, r2b, first_far);
    let b_a = (r1b, r2a, !first_far);
    let (r1, r2, far_side_wrap) = match (on_side(&r1a), on_side(&r1b)) {
        (true, true) => {
            if on_side(&r2a) { b_a } else { a_b }
        }
        (true, false) => a_b,
        (false, true) => b_a,
        (false, false) => {
            if on_side(&r2a) {
                b_a
            } else if on_side(&r2b) {
                a_b
            } else if first_far {
                (r1a, r2b, true)
            } else {
                (r1b, r2a, true)
            }
        }
    };
    let sum_muscle = (r1 - p1) + (r2 - p2);
    let sum_radial = (r1 - p11) + (r2 - p22);
    (r1, r2, far_side_wrap, sum_radial.dot(&sum_muscle) < 0.0)
}

/// Without a quadrant: the pair of candidates whose radial directions are most aligned.
fn most_aligned_tangent_points([p11, p22]: [&Vec3; 2], [r1a, r1b]: [Vec3; 2], [r2a, r2b]: [Vec3; 2]) -> (Vec3, Vec3) {
    let (r1am, _) = normalize_or_zero(&(r1a - p11));
    let (r1bm, _) = normalize_or_zero(&(r1b - p11));
    let (r2am, _) = normalize_or_zero(&(r2a - p22));
    let (r2bm, _) = normalize_or_zero(&(r2b - p22));
    let (dot1, dot2, dot3, dot4) = (r1am.dot(&r2am), r1am.dot(&r2bm), r1bm.dot(&r2am), r1bm.dot(&r2bm));
    if dot1 > dot2 && dot1 > dot3 && dot1 > dot4 {
        (r1a, r2a)
    } else if dot2 > dot3 && dot2 > dot4 {
        (r1a, r2b)
    } else if dot3 > dot4 {
        (r1b, r2a)
    } else {
        (r1b, r2b)
    }
}

/// Slides r1 and r2 along the axis onto the plane through p1, p2 and the apex, where that
/// keeps each on its own side of the other's foot on the axis.
fn slide_onto_apex_plane(p1: &Vec3, p2: &Vec3, apex: &Vec3, [p11, p22]: [&Vec3; 2], mut r1: Vec3, mut r2: Vec3) -> (Vec3, Vec3) {
    let (u, _) = normalize_or_zero(&(p1 - apex));
    let (v, _) = normalize_or_zero(&(p2 - apex));
    let plane_normal = unit(&u.cross(&v));
    let d = -p1.dot(&plane_normal);
    let on_plane = |r: &Vec3| intersect_segment_plane(&(r - 10.0 * AXIS), &(r + 10.0 * AXIS), &plane_normal, d);
    let (r1_on_plane, r2_on_plane) = (on_plane(&r1), on_plane(&r2));
    // OpenSim passes p22 (a point) as the line's direction here: the axis, unless p22 = 0.
    if let Some(r1p) = r1_on_plane {
        let (r1_axis, _) = closest_point_on_line(&r1p, p11, p22);
        if (r1_axis - p22).norm_squared() < (p11 - p22).norm_squared() {
            r1 = r1p;
        }
    }
    if let Some(r2p) = r2_on_plane {
        let (r2_axis, _) = closest_point_on_line(&r2p, p11, p22);
        if (r2_axis - p11).norm_squared() < (p22 - p11).norm_squared() {
            r2 = r2p;
        }
    }
    (r1, r2)
}

/// `_adjust_tangent_point`: when the line p–r and the helix direction r–w differ in their
/// angle to the axis by more than the threshold, moves r 1.5 times towards where the line p–w
/// crosses the axial line through r; returns whether it moved.
fn adjust_tangent_point(p: &Vec3, r: &mut Vec3, w: &Vec3) -> bool {
    let (pr, _) = normalize_or_zero(&(*r - p));
    let (rw, _) = normalize_or_zero(&(w - *r));
    let alpha = pr.dot(&AXIS).acos();
    let omega = rw.dot(&AXIS).acos();
    if (alpha - omega).abs() <= TANGENCY_THRESHOLD {
        return false;
    }
    let (p_axial, _) = closest_point_on_line(p, r, &AXIS);
    let (w_axial, _) = closest_point_on_line(w, r, &AXIS);
    let crossing = intersect_lines(p, w, &p_axial, &w_axial).map_or(Vec3::repeat(f64::NAN), |c| c.on_second);
    *r += 1.5 * (crossing - *r);
    true
}

/// The two tangent points on the circle of the cylinder through `axis_point` (p's foot on the
/// axis) seen from p, and p's distance from the axis.
fn tangent_candidates(p: &Vec3, axis_point: &Vec3, radius: f64) -> (Vec3, Vec3, f64) {
    let (outward, distance) = normalize_or_zero(&(p - axis_point));
    let sin_theta = radius / distance;
    let along = radius * sin_theta;
    let middle = axis_point + along * outward;
    let across = (radius * radius - along * along).sqrt();
    let sideways = AXIS.cross(&outward);
    (middle + across * sideways, middle - across * sideways, distance)
}

/// `WrapMath::CalcDistanceSquaredPointToLine` for the cylinder's axis.
fn distance_squared_to_axis(point: &Vec3) -> f64 {
    let to_line = AXIS_POINT - point;
    let n = AXIS.normalize();
    (to_line - to_line.dot(&n) * n).norm_squared()
}

/// `UnitVec3(v)`: v divided by its norm (NaN for a zero vector).
fn unit(v: &Vec3) -> Vec3 {
    v / v.norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const UNBOUNDED: Cylinder = Cylinder { radius: 0.1, length: 1.0, quadrant: None };

    fn surface(wrap: Wrapping) -> SurfacePath {
        match wrap {
            Wrapping::Wrapped(path) | Wrapping::Mandatory(path) => path,
            other => panic!("{other:?}"),
        }
    }

    /// A segment from (−a, h, 0) to (a, h, 0) over a cylinder of radius r (h < r): each tangent
    /// point lies at the polar angle of its path point ∓ acos(r/d), d = √(a²+h²), over the +y
    /// side, and the surface length is r times the angle between them.
    #[test]
    fn symmetric_segment_wraps_over_the_near_side_by_tangent_lines() {
        let (r, a, h) = (0.1, 0.3, 0.05);
        let wrap = UNBOUNDED.wrap_line(&Vec3::new(-a, h, 0.0), &Vec3::new(a, h, 0.0), true);
        let Wrapping::Mandatory(path) = wrap else { panic!("{wrap:?}") };
        let d = (a * a + h * h).sqrt();
        // Polar angles (from +x) of the tangent points: φ(p) ∓ acos(r/d), over the +y side.
        let phi1 = h.atan2(-a) - (r / d).acos();
        let phi2 = h.atan2(a) + (r / d).acos();
        assert_relative_eq!(path.r1, Vec3::new(r * phi1.cos(), r * phi1.sin(), 0.0), epsilon = 1e-15);
        assert_relative_eq!(path.r2, Vec3::new(r * phi2.cos(), r * phi2.sin(), 0.0), epsilon = 1e-15);
        assert_relative_eq!(path.length, r * (phi1 - phi2), epsilon = 1e-15);
        // Tangency: the line from each point meets its tangent point at right angles to the radius.
        assert_relative_eq!((path.r1 - Vec3::new(-a, h, 0.0)).dot(&path.r1), 0.0, epsilon = 1e-15);
    }

    /// Points offset along the axis: the path is a helix whose length is √((rθ)² + Δz²), and
    /// the tangent points lie on the plane through the two points and the apex.
    #[test]
    fn oblique_segment_follows_a_helix() {
        let (p1, p2) = (Vec3::new(-0.3, 0.02, -0.1), Vec3::new(0.25, 0.03, 0.15));
        let path = surface(UNBOUNDED.wrap_line(&p1, &p2, true));
        let theta = path.r1.xy().angle(&path.r2.xy());
        let dz = path.r2.z - path.r1.z;
        assert_relative_eq!(path.length, ((0.1 * theta).powi(2) + dz * dz).sqrt(), epsilon = 1e-15);
        assert_relative_eq!(path.r1.xy().norm(), 0.1, epsilon = 1e-15);
        assert_relative_eq!(path.r2.xy().norm(), 0.1, epsilon = 1e-15);
        // Both straight parts are tangent to the circle in the cross-section.
        assert_relative_eq!((path.r1 - p1).xy().dot(&path.r1.xy()), 0.0, epsilon = 1e-15);
        assert_relative_eq!((path.r2 - p2).xy().dot(&path.r2.xy()), 0.0, epsilon = 1e-15);
        // The tangent adjustment of multi-wrap paths makes the straight parts meet the helix
        // at its pitch: the angle to the axis of p1→r1 matches the helix direction at r1.
        let adjusted = surface(UNBOUNDED.wrap_line(&p1, &p2, false));
        let pitch = (adjusted.r2.z - adjusted.r1.z) / adjusted.length;
        assert!(((adjusted.r1 - p1).normalize().z - pitch).abs() < 0.01, "{adjusted:?}");
    }

    #[test]
    fn segments_that_miss_or_start_inside_do_not_wrap() {
        let outside = UNBOUNDED.wrap_line(&Vec3::new(-0.3, 0.2, 0.0), &Vec3::new(0.3, 0.2, 0.0), true);
        assert_eq!(outside, Wrapping::NoWrap);
        let inside = UNBOUNDED.wrap_line(&Vec3::new(-0.05, 0.0, 0.0), &Vec3::new(0.3, 0.2, 0.0), true);
        assert_eq!(inside, Wrapping::InsideRadius);
        // Beyond the cylinder's ends: the tangent points lie outside its length.
        let beyond = UNBOUNDED.wrap_line(&Vec3::new(-0.3, 0.05, 0.8), &Vec3::new(0.3, 0.05, 0.8), true);
        assert_eq!(beyond, Wrapping::NoWrap);
    }

    /// With a quadrant, a segment that misses the cylinder still wraps when its points lie on
    /// opposite sides of the quadrant's plane and it passes on the other side; it does not when
    /// it passes on the allowed side; with both points on the other side OpenSim wraps anyway.
    #[test]
    fn quadrant_wraps_segments_that_pass_on_the_wrong_side() {
        let on_surface = |path: &SurfacePath| (path.r1.xy().norm() - 0.1).abs() < 1e-15 && (path.r2.xy().norm() - 0.1).abs() < 1e-15;
        let cylinder = Cylinder { quadrant: Some(Quadrant { axis: 1, sign: 1 }), ..UNBOUNDED };
        let (p1, p2) = (Vec3::new(0.2, -0.3, 0.0), Vec3::new(0.3, 0.3, 0.0));
        assert_eq!(UNBOUNDED.wrap_line(&p1, &p2, true), Wrapping::NoWrap);
        let Wrapping::Wrapped(path) = cylinder.wrap_line(&p1, &p2, true) else { panic!() };
        assert!(on_surface(&path), "{path:?}");
        let away = Cylinder { quadrant: Some(Quadrant { axis: 1, sign: -1 }), ..UNBOUNDED };
        assert_eq!(away.wrap_line(&p1, &p2, true), Wrapping::NoWrap);
        let Wrapping::Wrapped(path) = away.wrap_line(&Vec3::new(-0.3, 0.2, 0.0), &Vec3::new(0.3, 0.3, 0.0), true) else { panic!() };
        assert!(on_surface(&path), "{path:?}");
    }
}
