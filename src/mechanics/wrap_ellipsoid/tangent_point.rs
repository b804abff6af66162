//! `WrapEllipsoid::calcTangentPoint`: the tangent point of the line from a path point to the
//! ellipsoid within the wrapping plane, by OpenSim's damped Gauss–Newton (Levenberg–Marquardt)
//! iteration, step by step — it stops at a squared residual of 1e-8, far from convergence, so
//! its result depends on the exact steps taken. All quantities are normalised and the ellipsoid
//! is centred on the origin.

use nalgebra::Matrix4;

use super::super::spatial::Vec3;
use super::super::wrap_math::normalize_or_zero;
use super::{ellipsoid_level, WrappingPlane};

/// `ELLIPSOID_TINY`: the squared residual at which the iteration stops.
const ELLIPSOID_TINY: f64 = 1e-8;
/// `maxit`: outer iterations.
const MAX_ITERATIONS: usize = 50;
/// `maxit2`: steps of each damping and each step-doubling loop.
const MAX_INNER_ITERATIONS: usize = 1000;

type Mat4 = Matrix4<f64>;

/// The problem: the path point p, the radii a and the wrapping plane.
struct Problem<'a> {
    p: &'a Vec3,
    a: &'a Vec3,
    plane: &'a WrappingPlane,
}

/// The iteration's state: the unknowns (r, the tangent point, and d, the offset of the tangent
/// plane n·x + d = 0, n = 2r/a²), the current and previous sums of squared residuals, and the
/// Marquardt parameter.
struct State {
    r: Vec3,
    d: f64,
    ssq: f64,
    ssqo: f64,
    alpha: f64,
}

/// `calcTangentPoint`: moves `start` (on the ellipsoid) to the tangent point of the line from
/// `p` within the wrapping plane. `p_level`: p's `(x/a)² − 1`; within 1e-4 of the surface
/// p itself is the tangent point.
pub(super) fn tangent_point(p_level: f64, start: Vec3, p: &Vec3, a: &Vec3, plane: &WrappingPlane) -> Vec3 {
    if p_level.abs() < 0.0001 {
        return *p;
    }
    let problem = Problem { p, a, plane };
    let d = -problem.normal(&start).dot(&start);
    let ssq = squared(&problem.residuals(&start, d));
    let mut state = State { r: start, d, ssq, ssqo: ssq, alpha: 0.01 };
    let mut iterations = 0;
    while state.ssq > ELLIPSOID_TINY && iterations < MAX_ITERATIONS {
        iterations += 1;
        if problem.iterate(&mut state).is_none() {
            break;
        }
    }
    state.r
}

impl Problem<'_> {
    /// 2r/a², the ellipsoid's (unnormalised) normal at r.
    fn normal(&self, r: &Vec3) -> Vec3 {
        Vec3::from_fn(|i, _| 2.0 * r[i] / (self.a[i] * self.a[i]))
    }

    /// The residuals: r on the wrapping plane, on the ellipsoid, on its tangent plane, and p on
    /// that tangent plane.
    fn residuals(&self, r: &Vec3, d: f64) -> [f64; 4] {
        let normal = self.normal(r);
        [self.plane.vs.dot(r) + self.plane.vs4, ellipsoid_level(r, self.a), normal.dot(r) + d, normal.dot(self.p) + d]
    }

    /// The Jacobian, transposed: row i < 3 holds ∂/∂r_i of the residuals, row 3 ∂/∂d.
    fn jacobian(&self, r: &Vec3) -> Mat4 {
        Mat4::from_fn(|i, j| {
            if i == 3 {
                return [0.0, 0.0, 1.0, 1.0][j];
            }
            let a2 = self.a[i] * self.a[i];
            [self.plane.vs[i], 2.0 * r[i] / a2, 2.0 * (2.0 * r[i]) / a2, 2.0 * self.p[i] / a2][j]
        })
    }

    /// One outer iteration: Marquardt steps (a sixteenth of the damped Gauss–Newton step,
    /// shortened by [`damping_factor`]), each added to the unknowns, with growing damping until
    /// the residual stops growing; then steps doubling along the last one while it shrinks, and
    /// one back. `None` when the damped matrix is singular.
    fn iterate(&self, state: &mut State) -> Option<()> {
        let ee = self.residuals(&state.r, state.d);
        let dedth = self.jacobian(&state.r);
        let gradient: [f64; 4] = std::array::from_fn(|i| (0..4).fold(0.0, |v, j| v - dedth[(i, j)] * ee[j]));
        let normal_matrix = Mat4::from_fn(|i, j| (0..4).fold(0.0, |s, k| s + dedth[(i, k)] * dedth[(j, k)]));
        let damping = damping_factor(self.p, &state.r);
        let mut step = [0.0; 4];
        let mut tries = 0;
        while state.ssq >= state.ssqo && tries < MAX_INNER_ITERATIONS {
            let mut damped = normal_matrix;
            damped.set_diagonal(&normal_matrix.diagonal().map(|d| d * (1.0 + state.alpha)));
            // Simbody's `Mat44::invert` is LAPACK's getrf/getri, an LU factorisation with partial
            // pivoting; nalgebra's stands in (a transcription of getrf/getri, or a cofactor
            // inverse, gave the same lengths over arm26's 174 golden poses). Simbody throws when
            // it is singular.
            let inverse = damped.lu().try_inverse()?;
            step = std::array::from_fn(|i| (0..4).fold(0.0, |s, j| s + damping * inverse[(i, j)] * gradient[j] / 16.0));
            self.advance(state, &step, 1.0);
            state.alpha *= 4.0;
            tries += 1;
        }
        state.alpha /= 8.0;
        let mut factor = 0.5;
        tries = 0;
        while state.ssq <= state.ssqo && tries < MAX_INNER_ITERATIONS {
            factor *= 2.0;
            self.advance(state, &step, factor);
            tries += 1;
        }
        self.advance(state, &step, -factor);
        state.ssqo = state.ssq;
        Some(())
    }

    /// Adds `factor` times `step` to the unknowns (a negative factor gives OpenSim's subtraction
    /// of `step * fakt` to the bit) and shifts the sums of squares.
    fn advance(&self, state: &mut State, step: &[f64; 4], factor: f64) {
        state.r = Vec3::from_fn(|i, _| state.r[i] + step[i] * factor);
        state.d += step[3] * factor;
        state.ssqo = state.ssq;
        state.ssq = squared(&self.residuals(&state.r, state.d));
    }
}

/// Sum of squares of the residuals.
fn squared(ee: &[f64; 4]) -> f64 {
    ee[0] * ee[0] + ee[1] * ee[1] + ee[2] * ee[2] + ee[3] * ee[3]
}

/// `dd`: shortens the steps as r comes in line with p and the centre: 1 − cos¹⁰⁰ of the angle
/// at p between them, when the cosine exceeds 0.1.
fn damping_factor(p: &Vec3, r: &Vec3) -> f64 {
    let (from_r, _) = normalize_or_zero(&(p - r));
    let (from_centre, _) = normalize_or_zero(p);
    let cosine = from_r.dot(&from_centre);
    if cosine > 0.1 { 1.0 - cosine.powf(100.0) } else { 1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// A circle's tangent from (0, 2) in the plane z = 0 of the unit sphere touches it at
    /// (±√3/2, 1/2): the iteration stops within its tolerance of that point.
    #[test]
    fn tangent_point_of_a_sphere_from_a_point() {
        let (a, p) = (Vec3::new(1.0, 1.0, 1.0), Vec3::new(0.0, 2.0, 0.0));
        let plane = WrappingPlane { vs: Vec3::new(0.0, 0.0, 1.0), vs4: 0.0 };
        let r = tangent_point(ellipsoid_level(&p, &a), Vec3::new(0.6, 0.8, 0.0), &p, &a, &plane);
        assert_relative_eq!(r, Vec3::new(0.75f64.sqrt(), 0.5, 0.0), epsilon = 1e-3);
    }
}
