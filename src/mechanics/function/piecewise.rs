//! OpenSim's `PiecewiseLinearFunction` and `PiecewiseConstantFunction`.

use super::knots::{locate, Segment, TINY_INTERVAL};

/// Straight segments between knots, extended beyond the ends with the end segments' slopes.
#[derive(Debug, Clone)]
pub(super) struct PiecewiseLinear {
    x: Vec<f64>,
    y: Vec<f64>,
    /// Slope of the segment starting at each knot; the last knot repeats the previous one
    /// (a single knot has slope 0).
    slope: Vec<f64>,
}

impl PiecewiseLinear {
    /// Slopes (y_{i+1} − y_i)/max(1e-7, x_{i+1} − x_i), as `calcCoefficients`.
    pub(super) fn new(x: &[f64], y: &[f64]) -> PiecewiseLinear {
        let mut slope: Vec<f64> =
            x.windows(2).zip(y.windows(2)).map(|(x, y)| (y[1] - y[0]) / TINY_INTERVAL.max(x[1] - x[0])).collect();
        slope.push(slope.last().copied().unwrap_or(0.0));
        PiecewiseLinear { x: x.to_vec(), y: y.to_vec(), slope }
    }

    pub(super) fn value(&self, x: f64) -> f64 {
        self.value_in(locate(&self.x, x), x)
    }

    pub(super) fn derivative(&self, x: f64) -> f64 {
        self.slope_in(locate(&self.x, x))
    }

    pub(super) fn value_and_derivative(&self, x: f64) -> (f64, f64) {
        let segment = locate(&self.x, x);
        (self.value_in(segment, x), self.slope_in(segment))
    }

    fn value_in(&self, segment: Segment, x: f64) -> f64 {
        let last = self.x.len() - 1;
        match segment {
            Segment::Before => self.y[0] + (x - self.x[0]) * self.slope[0],
            Segment::After => self.y[last] + (x - self.x[last]) * self.slope[last],
            Segment::AtFirst => self.y[0],
            Segment::AtLast => self.y[last],
            Segment::Interval(k) => self.y[k] + (x - self.x[k]) * self.slope[k],
        }
    }

    /// The slope of the segment holding x; at an interior knot, of the segment OpenSim's
    /// bisection picks.
    fn slope_in(&self, segment: Segment) -> f64 {
        match segment {
            Segment::Before | Segment::AtFirst => self.slope[0],
            Segment::After | Segment::AtLast => self.slope[self.x.len() - 1],
            Segment::Interval(k) => self.slope[k],
        }
    }
}

/// y_k on [x_k, x_{k+1}], y_0 before the first knot, y_{n−1} after the last.
#[derive(Debug, Clone)]
pub(super) struct PiecewiseConstant {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl PiecewiseConstant {
    pub(super) fn new(x: &[f64], y: &[f64]) -> PiecewiseConstant {
        PiecewiseConstant { x: x.to_vec(), y: y.to_vec() }
    }

    /// At an interior knot x_k, y_k or y_{k−1} depending on OpenSim's bisection path.
    pub(super) fn value(&self, x: f64) -> f64 {
        match locate(&self.x, x) {
            Segment::Before | Segment::AtFirst => self.y[0],
            Segment::After | Segment::AtLast => self.y[self.y.len() - 1],
            Segment::Interval(k) => self.y[k],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piecewise_linear_passes_through_its_knots() {
        let f = PiecewiseLinear::new(&[0.0, 1.0, 3.0], &[1.0, 3.0, 2.0]);
        assert_eq!([f.value(0.0), f.value(1.0), f.value(3.0)], [1.0, 3.0, 2.0]);
        assert_eq!(f.value(2.0), 2.5);
        assert_eq!([f.derivative(-1.0), f.derivative(2.0), f.derivative(4.0)], [2.0, -0.5, -0.5]);
        assert_eq!(f.value(-1.0), -1.0);
    }

    #[test]
    fn single_knot_is_constant() {
        let f = PiecewiseLinear::new(&[0.3], &[1.7]);
        assert_eq!([f.value(-5.0), f.value(0.3), f.value(9.0)], [1.7, 1.7, 1.7]);
        assert_eq!(f.derivative(2.0), 0.0);
    }

    #[test]
    fn piecewise_constant_holds_the_left_value() {
        let f = PiecewiseConstant::new(&[0.0, 1.0, 2.0], &[5.0, 6.0, 7.0]);
        assert_eq!([f.value(-1.0), f.value(0.5), f.value(1.5), f.value(2.0), f.value(3.0)], [5.0, 5.0, 6.0, 7.0, 7.0]);
    }
}
