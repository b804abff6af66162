//! OpenSim's `SimmSpline` (and `NaturalCubicSpline`, which OpenSim reads as a `SimmSpline`):
//! an interpolating cubic spline whose end conditions match the third derivative of the
//! cubic through the first (last) four knots, extrapolated linearly beyond the ends.

use super::knots::{locate, Segment, TINY_INTERVAL};

/// Piecewise cubic y = y_k + b_k·dx + c_k·dx² + d_k·dx³ with dx = x − x_k on [x_k, x_{k+1}].
#[derive(Debug, Clone)]
pub(super) struct SimmSpline {
    x: Vec<f64>,
    y: Vec<f64>,
    /// b_k: slope at knot k (dy/dx).
    slope: Vec<f64>,
    /// c_k: half the second derivative at knot k.
    half_curvature: Vec<f64>,
    /// d_k: a sixth of the third derivative on interval k.
    sixth_jerk: Vec<f64>,
}

impl SimmSpline {
    /// Fits the spline through (x_i, y_i), n ≥ 2, as `SimmSpline::calcCoefficients`.
    pub(super) fn new(x: &[f64], y: &[f64]) -> SimmSpline {
        let (slope, half_curvature, sixth_jerk) =
            if x.len() == 2 { straight_line(x, y) } else { cubic_coefficients(x, y) };
        SimmSpline { x: x.to_vec(), y: y.to_vec(), slope, half_curvature, sixth_jerk }
    }

    pub(super) fn value(&self, x: f64) -> f64 {
        self.value_in(locate(&self.x, x), x)
    }

    pub(super) fn derivative(&self, x: f64) -> f64 {
        self.derivative_in(locate(&self.x, x), x)
    }

    /// Zero outside the knots (linear extrapolation), 2·c at the end knots.
    pub(super) fn second_derivative(&self, x: f64) -> f64 {
        let last = self.x.len() - 1;
        match locate(&self.x, x) {
            Segment::Before | Segment::After => 0.0,
            Segment::AtFirst => 2.0 * self.half_curvature[0],
            Segment::AtLast => 2.0 * self.half_curvature[last],
            Segment::Interval(k) => 2.0 * self.half_curvature[k] + 6.0 * (x - self.x[k]) * self.sixth_jerk[k],
        }
    }

    pub(super) fn value_and_derivative(&self, x: f64) -> (f64, f64) {
        let segment = locate(&self.x, x);
        (self.value_in(segment, x), self.derivative_in(segment, x))
    }

    /// Linear beyond the ends, the knot's y within 2e-13 of an end, the cubic inside.
    fn value_in(&self, segment: Segment, x: f64) -> f64 {
        let last = self.x.len() - 1;
        match segment {
            Segment::Before => self.y[0] + (x - self.x[0]) * self.slope[0],
            Segment::After => self.y[last] + (x - self.x[last]) * self.slope[last],
            Segment::AtFirst => self.y[0],
            Segment::AtLast => self.y[last],
            Segment::Interval(k) => self.cubic_value(k, x - self.x[k]),
        }
    }

    fn derivative_in(&self, segment: Segment, x: f64) -> f64 {
        let last = self.x.len() - 1;
        match segment {
            Segment::Before | Segment::AtFirst => self.slope[0],
            Segment::After | Segment::AtLast => self.slope[last],
            Segment::Interval(k) => self.cubic_derivative(k, x - self.x[k]),
        }
    }

    /// y_k + dx·(b_k + dx·(c_k + dx·d_k)).
    fn cubic_value(&self, k: usize, dx: f64) -> f64 {
        self.y[k] + dx * (self.slope[k] + dx * (self.half_curvature[k] + dx * self.sixth_jerk[k]))
    }

    /// b_k + dx·(2c_k + 3dx·d_k).
    fn cubic_derivative(&self, k: usize, dx: f64) -> f64 {
        self.slope[k] + dx * (2.0 * self.half_curvature[k] + 3.0 * dx * self.sixth_jerk[k])
    }
}

/// Coefficients (b, c, d) per knot.
type Coefficients = (Vec<f64>, Vec<f64>, Vec<f64>);

/// Two knots: the straight line through them, b = Δy/Δx at both knots.
fn straight_line(x: &[f64], y: &[f64]) -> Coefficients {
    let slope = (y[1] - y[0]) / width(x, 0);
    (vec![slope; 2], vec![0.0; 2], vec![0.0; 2])
}

/// x_{i+1} − x_i, at least `TINY_INTERVAL`.
fn width(x: &[f64], i: usize) -> f64 {
    TINY_INTERVAL.max(x[i + 1] - x[i])
}

/// Forsythe–Malcolm–Moler `spline` as in `SimmSpline::calcCoefficients` (n ≥ 3): solves the
/// symmetric tridiagonal system for σ_i (a third of c_i), then b, c = 3σ, d per interval.
/// Operations keep OpenSim's order so the coefficients agree to the bit.
fn cubic_coefficients(x: &[f64], y: &[f64]) -> Coefficients {
    let n = x.len();
    let last = n - 1;
    let h: Vec<f64> = (0..last).map(|i| width(x, i)).collect();
    let secant = |i: usize| (y[i + 1] - y[i]) / h[i];

    // Tridiagonal system: diagonal, off-diagonal h, right-hand side σ.
    let mut diagonal = vec![0.0; n];
    let mut sigma = vec![0.0; n];
    for i in 1..last {
        diagonal[i] = 2.0 * (h[i - 1] + h[i]);
        sigma[i] = secant(i) - secant(i - 1);
    }
    diagonal[0] = -h[0];
    diagonal[last] = -h[last - 1];
    if n > 3 {
        (sigma[0], sigma[last]) = third_derivative_ends(x, &h, &sigma);
    }

    // Forward elimination and back substitution.
    for i in 1..n {
        let t = h[i - 1] / diagonal[i - 1];
        diagonal[i] -= t * h[i - 1];
        sigma[i] -= t * sigma[i - 1];
    }
    sigma[last] /= diagonal[last];
    for i in (0..last).rev() {
        sigma[i] = (sigma[i] - h[i] * sigma[i + 1]) / diagonal[i];
    }

    let mut slope = vec![0.0; n];
    let mut sixth_jerk = vec![0.0; n];
    slope[last] = (y[last] - y[last - 1]) / h[last - 1] + h[last - 1] * (sigma[last - 1] + 2.0 * sigma[last]);
    for i in 0..last {
        slope[i] = (y[i + 1] - y[i]) / h[i] - h[i] * (sigma[i + 1] + 2.0 * sigma[i]);
        sixth_jerk[i] = (sigma[i + 1] - sigma[i]) / h[i];
    }
    sixth_jerk[last] = sixth_jerk[last - 1];
    let half_curvature = sigma.iter().map(|s| s * 3.0).collect();
    (slope, half_curvature, sixth_jerk)
}

/// End rows of the system (n > 3): σ_0 and σ_{n−1} from third divided differences of the
/// first and last four knots. `sigma[1..n−1]` holds the interior second differences.
fn third_derivative_ends(x: &[f64], h: &[f64], sigma: &[f64]) -> (f64, f64) {
    let n = x.len();
    let (last, wide) = (n - 1, |i: usize, j: usize| TINY_INTERVAL.max(x[j] - x[i]));
    let first = sigma[2] / wide(1, 3) - sigma[1] / wide(0, 2);
    let end = sigma[n - 2] / wide(n - 3, last) - sigma[n - 3] / wide(n - 4, n - 2);
    let first = first * h[0] * h[0] / wide(0, 3);
    let end = -end * h[last - 1] * h[last - 1] / wide(n - 4, last);
    (first, end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_a_cubic_through_four_or_more_knots() {
        // The end conditions match the data's third derivative, so a cubic is exact.
        let cubic = |x: f64| 0.5 * x * x * x - x * x + 2.0 * x - 1.0;
        let x = [-1.0, -0.2, 0.5, 1.1, 2.0];
        let y = x.map(cubic);
        let spline = SimmSpline::new(&x, &y);
        for t in [-0.9, 0.1, 0.77, 1.9] {
            assert!((spline.value(t) - cubic(t)).abs() < 1e-12);
            assert!((spline.derivative(t) - (1.5 * t * t - 2.0 * t + 2.0)).abs() < 1e-12);
            assert!((spline.second_derivative(t) - (3.0 * t - 2.0)).abs() < 1e-11);
        }
    }

    #[test]
    fn extrapolates_linearly_with_the_end_slopes() {
        let spline = SimmSpline::new(&[0.0, 1.0, 3.0], &[0.0, 2.0, 1.0]);
        let slope = spline.derivative(3.0);
        assert_eq!(spline.value(5.0), 1.0 + 2.0 * slope);
        assert_eq!(spline.derivative(5.0), slope);
        assert_eq!(spline.second_derivative(5.0), 0.0);
    }
}
