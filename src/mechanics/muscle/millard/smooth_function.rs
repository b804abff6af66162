//! OpenSim's `SmoothSegmentedFunction`: a curve made of quintic Bézier segments inside its
//! domain [x0, x1] and straight lines outside it. x → u is found as OpenSim finds it, Newton's
//! method on x(u) − x = 0 to 100 ε (at most 20 steps), from a first guess that is a cubic
//! Hermite table of u(x) on a uniform x grid, looked up without a search (OpenSim interpolates a
//! spline through 100 samples uniform in u; from either guess Newton stops within 100 ε, so the
//! curves agree with OpenSim's to rounding).

use super::bezier::{derivative_u, BezierSegment, Weights};
use crate::mechanics::muscle::root::bracketed_newton;

/// Newton tolerance on x(u) − x: 100 ε (`UTOL`).
const U_TOLERANCE: f64 = f64::EPSILON * 1e2;
/// Newton step limit (`MAXITER`).
const MAX_U_ITERATIONS: usize = 20;
/// Intervals of the first-guess table per segment.
const GUESS_INTERVALS: usize = 64;

/// A C2 curve of quintic Bézier segments with linear extrapolation.
#[derive(Debug, Clone)]
pub struct SmoothSegmentedFunction {
    segments: Vec<BezierSegment>,
    /// First guesses u(x), one table per segment.
    u_guess: Vec<UGuess>,
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
        let u_guess = segments.iter().map(UGuess::new).collect();
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

    /// The inverse relation y → x of a curve increasing throughout, its end slopes inverted (a
    /// flat end extrapolates vertically: evaluate the inverse only inside [y0, y1]).
    pub fn inverse(&self) -> SmoothSegmentedFunction {
        let segments = self.segments.iter().map(BezierSegment::transposed).collect();
        SmoothSegmentedFunction::new(segments, (self.y0, self.x0, 1.0 / self.dydx0), (self.y1, self.x1, 1.0 / self.dydx1))
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
        let mut u = self.u_guess[index].at(x).clamp(0.0, 1.0);
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

/// u(x) of one segment as a cubic Hermite interpolant through u and du/dx at GUESS_INTERVALS + 1
/// evenly spaced x, stored per interval as polynomial coefficients in t ∈ [0, 1].
#[derive(Debug, Clone)]
struct UGuess {
    x_start: f64,
    /// 1/h, h the grid spacing in x.
    inverse_step: f64,
    /// u = c0 + t (c1 + t (c2 + t c3)) on each interval.
    intervals: Vec<[f64; 4]>,
}

impl UGuess {
    fn new(segment: &BezierSegment) -> UGuess {
        let (x_start, x_end) = (segment.x[0], segment.x[5]);
        let step = (x_end - x_start) / GUESS_INTERVALS as f64;
        // (u, h·du/dx) at each grid x; NaN slope where x(u) is flat (a repeated control point).
        let knots: Vec<(f64, f64)> = (0..=GUESS_INTERVALS)
            .map(|i| {
                let x = x_start + step * i as f64;
                let residual = |u: f64| (derivative_u(u, &segment.x, 0) - x, derivative_u(u, &segment.x, 1));
                let u = bracketed_newton(residual, 0.0, 1.0, 1e-15, U_TOLERANCE, 200).map_or(i as f64 / GUESS_INTERVALS as f64, |r| r.x);
                let slope = step / derivative_u(u, &segment.x, 1);
                (u, if slope.is_finite() && slope.abs() < 1.0 { slope } else { f64::NAN })
            })
            .collect();
        let intervals = knots
            .windows(2)
            .map(|w| {
                let ((u0, m0), (u1, m1)) = (w[0], w[1]);
                // A flat end falls back to the chord.
                let chord = u1 - u0;
                let (m0, m1) = (if m0.is_nan() { chord } else { m0 }, if m1.is_nan() { chord } else { m1 });
                [u0, m0, 3.0 * chord - 2.0 * m0 - m1, -2.0 * chord + m0 + m1]
            })
            .collect();
        UGuess { x_start, inverse_step: if step > 0.0 { 1.0 / step } else { 0.0 }, intervals }
    }

    /// The interpolated u at x.
    #[inline]
    fn at(&self, x: f64) -> f64 {
        let position = ((x - self.x_start) * self.inverse_step).clamp(0.0, GUESS_INTERVALS as f64);
        let i = (position as usize).min(GUESS_INTERVALS - 1);
        let t = position - i as f64;
        let [c0, c1, c2, c3] = self.intervals[i];
        c0 + t * (c1 + t * (c2 + t * c3))
    }
}

#[cfg(test)]
mod tests {
    use super::super::curves;

    /// The inverse undoes the curve, across the toe and into the linear extrapolation.
    #[test]
    fn the_inverse_of_the_tendon_curve_returns_the_length() {
        let curve = curves::tendon_force_length(0.049, 1.375 / 0.049, 2.0 / 3.0, 0.5).unwrap();
        let inverse = curve.inverse();
        for i in 1..=80 {
            let length = 1.0 + 0.08 * i as f64 / 80.0;
            let back = inverse.value(curve.value(length));
            assert!((back - length).abs() < 1e-13, "{length}: {back}");
        }
    }
}
