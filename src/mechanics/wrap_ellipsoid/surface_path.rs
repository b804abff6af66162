//! `WrapEllipsoid::CalcDistanceOnEllipsoid`: the path over the ellipsoid from r1 to r2, a
//! polyline through points of the curve where the wrapping plane cuts the surface, and its
//! length. Quantities are normalised (the ellipsoid centred on the origin); `factor` converts
//! back to metres (m = normalised / factor).

use super::super::spatial::Vec3;
use super::super::wrap_math::normalize_or_zero;
use super::WrappingPlane;

/// `desiredSegLength` (m): the polyline's pieces are about this long.
const PIECE: f64 = 0.001;
/// At most this many pieces.
const MAX_PIECES: usize = 499;

/// The polyline over the surface.
pub(super) struct Polyline {
    /// Its length (normalised).
    pub length: f64,
    /// Its first and last interior points, when it has any.
    pub inner_ends: Option<(Vec3, Vec3)>,
}

/// The polyline from r1 to r2 in the wrapping plane: N = ⌊|r1 − r2| / 1 mm⌋ pieces (at
/// most 499) whose interior points are where rays from a point a0 of the plane, at equal angle
/// steps from r1 towards r2 (the other way round for `far_side`), leave the ellipsoid. Under
/// 1 mm apart, the chord.
pub(super) fn polyline(r1: &Vec3, r2: &Vec3, a: &Vec3, plane: &WrappingPlane, far_side: bool, factor: f64) -> Polyline {
    let chord = (r1 - r2).norm() / factor;
    if chord < PIECE {
        return Polyline { length: chord * factor, inner_ends: None };
    }
    let pieces = ((chord / PIECE) as usize).min(MAX_PIECES);
    // a0: where the plane meets the axis it is most normal to.
    let vs = &plane.vs;
    let axis = (1..3).fold(0, |best, i| if vs[i].abs() > vs[best].abs() { i } else { best });
    let mut a0 = Vec3::zeros();
    a0[axis] = -plane.vs4 / vs[axis];
    let (ar1, _) = normalize_or_zero(&(r1 - a0));
    let (ar2, _) = normalize_or_zero(&(r2 - a0));
    let phi0 = ar1.dot(&ar2).acos();
    let step = if far_side { -(2.0 * std::f64::consts::PI - phi0) / pieces as f64 } else { phi0 / pieces as f64 };
    let (vsz, _) = normalize_or_zero(&ar1.cross(&ar2));
    let vsy = vsz.cross(&ar1);
    let f2 = a0.component_div(a);
    let (dot22, mut length, mut previous) = (f2.dot(&f2) - 1.0, 0.0, *r1);
    let mut first = None;
    for i in 0..pieces - 1 {
        let phi = (i + 1) as f64 * step;
        let ray = ar1 * phi.cos() + vsy * phi.sin();
        let f1 = ray.component_div(a);
        let (aa, bb) = (f1.dot(&f1), 2.0 * f1.dot(&f2));
        let along = (-bb + (bb * bb - 4.0 * aa * dot22).sqrt()) / (2.0 * aa);
        let point = a0 + along * ray;
        length += (point - previous).norm();
        first.get_or_insert(point);
        previous = point;
    }
    length += (r2 - previous).norm();
    Polyline { length, inner_ends: first.map(|first| (first, previous)) }
}
