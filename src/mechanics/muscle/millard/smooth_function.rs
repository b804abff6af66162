//! OpenSim's `SmoothSegmentedFunction`: a curve made of quintic Bézier segments inside its
//! domain [x0, x1] and straight lines outside it. x → u is found as OpenSim does: a cubic
//! interpolating spline of u(x) sampled at 100 points per segment gives the first guess, then
//! Newton's method on x(u) − x = 0 to 100 ε (at most 20 steps).

use super::bezier::{derivative_u, BezierSegment, Weights};
use crate::mechanics::Function;

/// Newton tolerance on x(u) − x: 100 ε (`UTOL`).
const U_TOLERANCE: f64 = f64::EPSILON * 1e2;
/// Newton step limit (`MAXITER`).
const MAX_U_ITERATIONS: usize = 20;
/// Samples of u per segment for the first-guess spline (`NUM_SAMPLE_PTS`).
const SAMPLES_PER_SEGMENT: usize = 100;

/// A C2 curve of quintic Bézier segments with linear extrapolation.
#[derive(Debug, Clone)]
pub struct SmoothSegmentedFunction {
    segments: Vec<BezierSegment>,
    /// First guesses u(x), one interpolating cubic spline per segment.
    u_guess: Vec<Function>,
    /// Domain [x0, x1].
    pub x0: f64,
    pub x1: f64,
    y0: f64,
    y1: f64,
    dydx0: f64,
    dydx1: f64,
}

impl SmoothSegmentedFunction {
    /// A curve through `segments` (x-ordered, joined end to start), continued left of x0 by the
    /// line through (x0, y0) with slope dydx0 and right of x1 by (x1, y1) with slope dydx1.
    pub fn new(
        segments: Vec<BezierSegment>,
        (x0, y0, dydx0): (f64, f64, f64),
        (x1, y1, dydx1): (f64, f64, f64),
    ) -> Self {
        let u_guess = segments.iter().map(u_guess_spline).collect();
        SmoothSegmentedFunction {
            segments,
            u_guess,
            x0,
            x1,
            y0,
            y1,
            dydx0,
            dydx1,
        }
    }

    pub fn value(&self, x: f64) -> f64 {
        self.derivatives(x, [true, false, false])[0]
    }

    /// dy/dx.
    pub fn derivative(&self, x: f64) -> f64 {
        self.derivatives(x, [false, true, false])[1]
    }

    /// d²y/dx².
    pub fn second_derivative(&self, x: f64) -> f64 {
        self.derivatives(x, [false, false, true])[2]
    }

    /// (y, dy/dx) with one x → u solve.
    pub fn value_and_derivative(&self, x: f64) -> (f64, f64) {
        let d = self.derivatives(x, [true, true, false]);
        (d[0], d[1])
    }

    /// Selected orders 0…2 at x (`calcSelectedDerivatives`); unselected entries are 0.
    #[inline]
    fn derivatives(&self, x: f64, selected: [bool; 3]) -> [f64; 3] {
        if x < self.x0 {
            return [self.y0 + self.dydx0 * (x - self.x0), self.dydx0, 0.0];
        }
        if x > self.x1 {
            return [self.y1 + self.dydx1 * (x - self.x1), self.dydx1, 0.0];
        }
        let index = self.segment_index(x);
        let segment = &self.segments[index];
        let (u, value_weights) = self.parameter(x, index);
        let mut out = [0.0; 3];
        if selected[0] {
            out[0] = value_weights.apply(&segment.y);
        }
        if selected[1] {
            out[1] = segment.dydx(u, 1);
        }
        if selected[2] {
            out[2] = segment.dydx(u, 2);
        }
        out
    }

    /// `calcIndex`: the segment whose [x_start, x_end) holds x; the last one at the right end.
    fn segment_index(&self, x: f64) -> usize {
        let found = self.segments.iter().position(|s| x >= s.x[0] && x < s.x[5]);
        found.unwrap_or(if Some(&x) == self.segments.last().map(|s| &s.x[5]) {
            self.segments.len() - 1
        } else {
            0
        })
    }

    /// `calcU`: u with x(u) = x on segment `index`, and the order-0 weights at u (the last
    /// Newton check computed them; y(u) needs the same).
    fn parameter(&self, x: f64, index: usize) -> (f64, Weights) {
        let points = &self.segments[index].x;
        let mut u = self.u_guess[index].value(x).clamp(0.0, 1.0);
        let mut weights = Weights::at(u, 0);
        let mut f = weights.apply(points) - x;
        let mut iterations = 0;
        while f.abs() > U_TOLERANCE && iterations < MAX_U_ITERATIONS {
            let df = derivative_u(u, points, 1);
            if df.abs() <= 0.0 {
                break;
            }
            u = (u - f / df).clamp(0.0, 1.0);
            weights = Weights::at(u, 0);
            f = weights.apply(points) - x;
            iterations += 1;
        }
        (u, weights)
    }
}

/// `SplineFitter::fitForSmoothingParameter(3, x, u, 0)` over 100 evenly spaced u.
fn u_guess_spline(segment: &BezierSegment) -> Function {
    let u: Vec<f64> = (0..SAMPLES_PER_SEGMENT)
        .map(|i| i as f64 / (SAMPLES_PER_SEGMENT - 1) as f64)
        .collect();
    let x: Vec<f64> = u.iter().map(|&u| derivative_u(u, &segment.x, 0)).collect();
    Function::spline_for_smoothing_parameter(3, &x, &u, 0.0)
}
