//! OpenSim's `SmoothSegmentedFunction`: a curve made of quintic Bézier segments inside its
//! domain [x0, x1] and straight lines outside it. x → u is found as OpenSim finds it, Newton's
//! method on x(u) − x = 0 to 100 ε (at most 20 steps), from a first guess that is a septic
//! Hermite table of u(x) on a uniform x grid, looked up without a search (OpenSim interpolates a
//! spline through 100 samples uniform in u; from either guess Newton stops within 100 ε, so the
//! curves agree with OpenSim's to rounding). The table is accurate to a few ulp almost
//! everywhere on the Millard curves, so Newton usually stops at its first check with u as exact
//! as its steps would make it. Values and slopes are evaluated in power form, curvatures with
//! OpenSim's toolkit. Curves with equal segments share them, tables included: the muscles of a
//! model mostly keep the default curves, so the tables are built once and stay in cache.

use std::sync::{Arc, Mutex, PoisonError, Weak};

use super::bezier::{BezierSegment, PowerSegment};
use crate::mechanics::muscle::root::{bracketed_newton, RootFailure};

/// Newton tolerance on x(u) − x: 100 ε (`UTOL`).
const U_TOLERANCE: f64 = f64::EPSILON * 1e2;
/// Newton step limit (`MAXITER`).
const MAX_U_ITERATIONS: usize = 20;
/// Intervals of the first-guess table per segment.
const GUESS_INTERVALS: usize = 256;

/// A C2 curve of quintic Bézier segments with linear extrapolation. Cheap to clone: clones
/// share the segments.
#[derive(Debug, Clone)]
pub struct SmoothSegmentedFunction {
    segments: Arc<[Segment]>,
    /// Domain [x0, x1].
    pub x0: f64,
    pub x1: f64,
    y0: f64,
    y1: f64,
    dydx0: f64,
    dydx1: f64,
}

/// One Bézier segment with its power form and its first-guess table.
#[derive(Debug)]
struct Segment {
    bezier: BezierSegment,
    power: PowerSegment,
    u_guess: UGuess,
}

/// The segments of the curves alive, each under the bits of its control points.
type SharedSegments = Vec<(Vec<u64>, Weak<[Segment]>)>;

static SEGMENTS: Mutex<SharedSegments> = Mutex::new(Vec::new());

impl SmoothSegmentedFunction {
    /// A curve through `segments` (x-ordered, joined end to start), continued left of x0 by the
    /// line through (x0, y0) with slope dydx0 and right of x1 by (x1, y1) with slope dydx1.
    pub fn new(
        segments: Vec<BezierSegment>,
        (x0, y0, dydx0): (f64, f64, f64),
        (x1, y1, dydx1): (f64, f64, f64),
    ) -> Self {
        SmoothSegmentedFunction { segments: shared_segments(segments), x0, x1, y0, y1, dydx0, dydx1 }
    }

    /// The inverse relation y → x of a curve increasing throughout, its end slopes inverted (a
    /// flat end extrapolates vertically: evaluate the inverse only inside [y0, y1]).
    pub fn inverse(&self) -> SmoothSegmentedFunction {
        let segments = self.segments.iter().map(|s| s.bezier.transposed()).collect();
        SmoothSegmentedFunction::new(segments, (self.y0, self.x0, 1.0 / self.dydx0), (self.y1, self.x1, 1.0 / self.dydx1))
    }

    #[inline]
    pub fn value(&self, x: f64) -> f64 {
        match self.segment_at(x) {
            Some(segment) => segment.power.y(segment.parameter(x)),
            None => self.extrapolated(x).0,
        }
    }

    /// dy/dx.
    pub fn derivative(&self, x: f64) -> f64 {
        self.value_and_derivative(x).1
    }

    /// d²y/dx² (`calcQuinticBezierCurveDerivDYDX` of order 2).
    pub fn second_derivative(&self, x: f64) -> f64 {
        match self.segment_at(x) {
            Some(segment) => segment.bezier.dydx(segment.parameter(x), 2),
            None => 0.0,
        }
    }

    /// (y, dy/dx) with one x → u solve.
    #[inline]
    pub fn value_and_derivative(&self, x: f64) -> (f64, f64) {
        match self.segment_at(x) {
            Some(segment) => {
                let u = segment.parameter(x);
                (segment.power.y(u), segment.power.dydx(u))
            }
            None => self.extrapolated(x),
        }
    }

    /// (y, dy/dx) on the line continuing the curve beyond its domain.
    fn extrapolated(&self, x: f64) -> (f64, f64) {
        if x < self.x0 {
            (self.y0 + self.dydx0 * (x - self.x0), self.dydx0)
        } else {
            (self.y1 + self.dydx1 * (x - self.x1), self.dydx1)
        }
    }

    /// `calcIndex` inside the domain: the segment whose [x_start, x_end) holds x, the last one
    /// at the right end; `None` outside the domain.
    #[inline]
    fn segment_at(&self, x: f64) -> Option<&Segment> {
        if x < self.x0 || x > self.x1 {
            return None;
        }
        let found = self.segments.iter().find(|s| x >= s.bezier.x[0] && x < s.bezier.x[5]);
        found.or_else(|| match self.segments.last() {
            Some(last) if x == last.bezier.x[5] => Some(last),
            _ => self.segments.first(),
        })
    }
}

/// The segments built from `beziers`: those a living curve already holds, or new ones.
fn shared_segments(beziers: Vec<BezierSegment>) -> Arc<[Segment]> {
    let key: Vec<u64> = beziers.iter().flat_map(|s| s.x.iter().chain(&s.y)).map(|v| v.to_bits()).collect();
    let mut alive = SEGMENTS.lock().unwrap_or_else(PoisonError::into_inner);
    alive.retain(|(_, segments)| segments.strong_count() > 0);
    if let Some(segments) = alive.iter().find(|(k, _)| *k == key).and_then(|(_, segments)| segments.upgrade()) {
        return segments;
    }
    let segments: Arc<[Segment]> = beziers.into_iter().map(Segment::new).collect();
    alive.push((key, Arc::downgrade(&segments)));
    segments
}

impl Segment {
    fn new(bezier: BezierSegment) -> Segment {
        let power = PowerSegment::new(&bezier);
        Segment { u_guess: UGuess::new(&power, bezier.x[0], bezier.x[5]), bezier, power }
    }

    /// `calcU`: u with x(u) = x.
    #[inline]
    fn parameter(&self, x: f64) -> f64 {
        let mut u = self.u_guess.at(x).clamp(0.0, 1.0);
        let mut f = self.power.x(u) - x;
        let mut iterations = 0;
        while f.abs() > U_TOLERANCE && iterations < MAX_U_ITERATIONS {
            let df = self.power.dxdu(u);
            if df.abs() <= 0.0 {
                break;
            }
            u = (u - f / df).clamp(0.0, 1.0);
            f = self.power.x(u) - x;
            iterations += 1;
        }
        u
    }
}

/// u(x) of one segment as a septic Hermite interpolant through u and its first three
/// x-derivatives at GUESS_INTERVALS + 1 evenly spaced x, stored per interval as polynomial
/// coefficients in t ∈ [0, 1].
#[derive(Debug)]
struct UGuess {
    x_start: f64,
    /// 1/h, h the grid spacing in x.
    inverse_step: f64,
    intervals: Vec<Interval>,
}

/// u = c0 + c1 t + … + c7 t^7 on one interval, one cache line.
#[derive(Debug, Clone, Copy)]
#[repr(align(64))]
struct Interval([f64; 8]);

impl UGuess {
    /// The table of the segment `power` on [x_start, x_end].
    fn new(power: &PowerSegment, x_start: f64, x_end: f64) -> UGuess {
        let step = (x_end - x_start) / GUESS_INTERVALS as f64;
        let knots: Vec<Knot> = (0..=GUESS_INTERVALS)
            .map(|i| {
                let x = if i == GUESS_INTERVALS { x_end } else { x_start + step * i as f64 };
                Knot::at(power, x, step)
            })
            .collect();
        let intervals = knots.windows(2).map(|w| Knot::interval(&w[0], &w[1])).collect();
        UGuess { x_start, inverse_step: if step > 0.0 { 1.0 / step } else { 0.0 }, intervals }
    }

    /// The interpolated u at x.
    #[inline]
    fn at(&self, x: f64) -> f64 {
        let position = ((x - self.x_start) * self.inverse_step).clamp(0.0, GUESS_INTERVALS as f64);
        let i = (position as usize).min(GUESS_INTERVALS - 1);
        let t = position - i as f64;
        let c = &self.intervals[i].0;
        // Estrin's scheme: shorter dependency chains than Horner's.
        let (t2, t4) = (t * t, t * t * (t * t));
        let low = (c[0] + c[1] * t) + t2 * (c[2] + c[3] * t);
        let high = (c[4] + c[5] * t) + t2 * (c[6] + c[7] * t);
        low + t4 * high
    }
}

/// u at one grid x with its x-derivatives scaled by the grid spacing h (h·u′, h²·u″, h³·u‴);
/// no derivatives where x(u) is flat (a repeated control point).
struct Knot {
    u: f64,
    scaled_derivatives: Option<[f64; 3]>,
}

impl Knot {
    /// The knot at x of segment `power`, grid spacing `step`.
    fn at(power: &PowerSegment, x: f64, step: f64) -> Knot {
        let residual = |u: f64| (power.x(u) - x, power.dxdu(u));
        // To the last bit of x, or the best point when rounding keeps the residual above that; the
        // chord's u if x(u) = x has no bracketed root.
        let u = match bracketed_newton(residual, 0.0, 1.0, f64::EPSILON, f64::EPSILON * x.abs(), 100) {
            Ok(root) | Err(RootFailure::NotConverged(root)) => root.x,
            Err(_) => (x - power.x(0.0)) / (power.x(1.0) - power.x(0.0)),
        };
        // The inverse function's derivatives from those of x(u).
        let (x1, (x2, x3)) = (power.dxdu(u), power.higher_x_derivatives(u));
        let d = step / x1;
        let scaled = [d, -d * d * d * x2 / step, d.powi(5) * (3.0 * x2 * x2 - x1 * x3) / (step * step)];
        let usable = d.abs() < 1.0 && scaled.iter().all(|v| v.is_finite());
        Knot { u, scaled_derivatives: usable.then_some(scaled) }
    }

    /// The septic through knots `a` (t = 0) and `b` (t = 1); an end without derivatives takes
    /// the chord's slope.
    fn interval(a: &Knot, b: &Knot) -> Interval {
        let chord = b.u - a.u;
        let [d0, s0, j0] = a.scaled_derivatives.unwrap_or([chord, 0.0, 0.0]);
        let [d1, s1, j1] = b.scaled_derivatives.unwrap_or([chord, 0.0, 0.0]);
        let (c0, c1, c2, c3) = (a.u, d0, 0.5 * s0, j0 / 6.0);
        // What c4…c7 must add at t = 1 to the value and the first three derivatives.
        let v = b.u - (c0 + c1 + c2 + c3);
        let d = d1 - (c1 + 2.0 * c2 + 3.0 * c3);
        let s = s1 - (2.0 * c2 + 6.0 * c3);
        let j = j1 - 6.0 * c3;
        Interval([
            c0,
            c1,
            c2,
            c3,
            35.0 * v - 15.0 * d + 2.5 * s - j / 6.0,
            -84.0 * v + 39.0 * d - 7.0 * s + 0.5 * j,
            70.0 * v - 34.0 * d + 6.5 * s - 0.5 * j,
            -20.0 * v + 10.0 * d - 2.0 * s + j / 6.0,
        ])
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::super::curves;
    use super::U_TOLERANCE;

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

    /// On the default tendon, passive and active curves the table's first guess already meets
    /// Newton's tolerance, so evaluating a curve takes no Newton step.
    #[test]
    fn the_first_guess_meets_the_newton_tolerance() {
        let default_curves = [
            curves::tendon_force_length(0.049, 1.375 / 0.049, 2.0 / 3.0, 0.5).unwrap(),
            curves::fiber_force_length(0.0, 0.7, 0.2, 2.0 / 0.7, 0.75).unwrap(),
            curves::active_force_length([0.4441, 0.73, 1.0, 1.8123], 0.0, 0.8616, 1.0).unwrap(),
        ];
        for curve in &default_curves {
            for segment in curve.segments.iter() {
                let (x_start, x_end) = (segment.bezier.x[0], segment.bezier.x[5]);
                for i in 0..=10_000 {
                    let x = x_start + (x_end - x_start) * i as f64 / 10_000.0;
                    let u = segment.u_guess.at(x).clamp(0.0, 1.0);
                    assert!((segment.power.x(u) - x).abs() <= U_TOLERANCE, "x {x} of a segment on [{x_start}, {x_end}]");
                }
            }
        }
    }

    #[test]
    fn curves_with_equal_segments_share_them() {
        let tendon = || curves::tendon_force_length(0.049, 1.375 / 0.049, 2.0 / 3.0, 0.5).unwrap();
        let (a, b) = (tendon(), tendon());
        assert!(Arc::ptr_eq(&a.segments, &b.segments));
        let stiffer = curves::tendon_force_length(0.04, 1.375 / 0.04, 2.0 / 3.0, 0.5).unwrap();
        assert!(!Arc::ptr_eq(&a.segments, &stiffer.segments));
    }
}
