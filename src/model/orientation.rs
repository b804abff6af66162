//! OpenSim's orientation convention: an `orientation` property holds body-fixed X-Y-Z Euler
//! angles (rad), R = Rx(a)·Ry(b)·Rz(c).

use nalgebra::Matrix3;

/// Body-fixed X-Y-Z Euler angles (rad): R = Rx(a)·Ry(b)·Rz(c).
pub fn body_fixed_xyz(angles: [f64; 3]) -> Matrix3<f64> {
    let (s1, c1) = angles[0].sin_cos();
    let (s2, c2) = angles[1].sin_cos();
    let (s3, c3) = angles[2].sin_cos();
    Matrix3::new(
        c2 * c3,
        -c2 * s3,
        s2,
        s1 * s2 * c3 + c1 * s3,
        -s1 * s2 * s3 + c1 * c3,
        -s1 * c2,
        -c1 * s2 * c3 + s1 * s3,
        c1 * s2 * s3 + s1 * c3,
        c1 * c2,
    )
}

/// The body-fixed X-Y-Z Euler angles (rad) of a rotation matrix, the inverse of
/// [`body_fixed_xyz`]; the middle angle lies in [−π/2, π/2] (at ±π/2 the first angle is 0).
pub fn body_fixed_xyz_angles(rotation: &Matrix3<f64>) -> [f64; 3] {
    let sin_b = rotation[(0, 2)].clamp(-1.0, 1.0);
    let b = sin_b.asin();
    if sin_b.abs() > 1.0 - 1e-12 {
        return [0.0, b, rotation[(1, 0)].atan2(rotation[(1, 1)])];
    }
    [(-rotation[(1, 2)]).atan2(rotation[(2, 2)]), b, (-rotation[(0, 1)]).atan2(rotation[(0, 0)])]
}
