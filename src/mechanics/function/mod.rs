//! Evaluation of OpenSim functions of one variable, agreeing with OpenSim 4.6 to the bit.
//!
//! OpenSim evaluates `SimmSpline` (alias `NaturalCubicSpline`), `PiecewiseLinearFunction`,
//! `PiecewiseConstantFunction` and `MultiplierFunction` with its own `calcValue` /
//! `calcDerivative` (and `Sine`), and hands `LinearFunction`, `PolynomialFunction`, `Constant`,
//! `StepFunction` and `GCVSpline` to Simbody (`Function::Linear`, `Function::Polynomial`,
//! `Function::Constant`, `Function::Step`, `Spline`); each family here follows the code OpenSim runs,
//! including extrapolation beyond the knots and which piece is used at a knot.

mod gcv_fit;
mod gcv_spline;
mod knots;
mod piecewise;
mod polynomial;
mod simm_spline;

use crate::model::FunctionSpec;
use gcv_fit::Smoothing;
use gcv_spline::GcvSpline;
use piecewise::{PiecewiseConstant, PiecewiseLinear};
use polynomial::Polynomial;
use simm_spline::SimmSpline;

/// A compiled OpenSim function of one variable: coefficients precomputed once.
#[derive(Debug, Clone)]
pub struct Function {
    kind: Kind,
}

#[derive(Debug, Clone)]
enum Kind {
    Constant(f64),
    /// y = slope·x + intercept.
    Linear { slope: f64, intercept: f64 },
    SimmSpline(SimmSpline),
    GcvSpline(GcvSpline),
    PiecewiseLinear(PiecewiseLinear),
    PiecewiseConstant(PiecewiseConstant),
    Polynomial(Polynomial),
    /// y = f(x)·scale, and likewise every derivative.
    Multiplier { scale: f64, function: Box<Function> },
    /// y = amplitude·sin(omega·x + phase) + offset.
    Sine { amplitude: f64, omega: f64, phase: f64, offset: f64 },
    Step(Step),
}

/// Simbody's `Function::Step`: y0 before x0, y1 beyond x1 (either order), between them
/// y0 + (y1 − y0)·stepUp(s), s = (x − x0)/(x1 − x0), stepUp(s) = 10s³ − 15s⁴ + 6s⁵.
#[derive(Debug, Clone)]
struct Step {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

impl Step {
    /// The fraction s of the way from x0 to x1, `None` outside the transition.
    fn fraction(&self, x: f64) -> Option<f64> {
        let sign = (self.x1 - self.x0).signum();
        ((x - self.x0) * sign > 0.0 && (x - self.x1) * sign < 0.0).then(|| (x - self.x0) / (self.x1 - self.x0))
    }

    fn value(&self, x: f64) -> f64 {
        match self.fraction(x) {
            Some(s) => self.y0 + s * s * s * (10.0 + s * (6.0 * s - 15.0)) * (self.y1 - self.y0),
            None if (x - self.x0) * (self.x1 - self.x0) <= 0.0 => self.y0,
            None => self.y1,
        }
    }

    /// dy/dx = (y1 − y0)/(x1 − x0) · 30s²(1 − s)².
    fn derivative(&self, x: f64) -> f64 {
        self.fraction(x).map_or(0.0, |s| 30.0 * s * s * (1.0 - s) * (1.0 - s) * (self.y1 - self.y0) / (self.x1 - self.x0))
    }

    /// d²y/dx² = (y1 − y0)/(x1 − x0)² · 60s(1 − s)(1 − 2s).
    fn second_derivative(&self, x: f64) -> f64 {
        self.fraction(x).map_or(0.0, |s| 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) * (self.y1 - self.y0) / ((self.x1 - self.x0) * (self.x1 - self.x0)))
    }
}

impl Function {
    /// Compiles a validated spec (x strictly increasing, lengths equal, enough points).
    pub fn new(spec: &FunctionSpec) -> Function {
        let kind = match spec {
            FunctionSpec::Constant { value } => Kind::Constant(*value),
            FunctionSpec::LinearFunction { slope, intercept } => Kind::Linear { slope: *slope, intercept: *intercept },
            FunctionSpec::SimmSpline { x, y } => {
                Kind::SimmSpline(SimmSpline::new(x, y))
            }
            FunctionSpec::GCVSpline { degree, error_variance, x, y } => {
                Kind::GcvSpline(GcvSpline::new(*degree, x, y, Smoothing::from_error_variance(*error_variance)))
            }
            FunctionSpec::PiecewiseLinearFunction { x, y } => Kind::PiecewiseLinear(PiecewiseLinear::new(x, y)),
            FunctionSpec::PiecewiseConstantFunction { x, y } => Kind::PiecewiseConstant(PiecewiseConstant::new(x, y)),
            FunctionSpec::PolynomialFunction { coefficients } => Kind::Polynomial(Polynomial::new(coefficients)),
            FunctionSpec::MultiplierFunction { scale, function } => {
                Kind::Multiplier { scale: *scale, function: Box::new(Function::new(function)) }
            }
            &FunctionSpec::Sine { amplitude, omega, phase, offset } => Kind::Sine { amplitude, omega, phase, offset },
            &FunctionSpec::StepFunction { start_time, end_time, start_value, end_value } => Kind::Step(Step { x0: start_time, x1: end_time, y0: start_value, y1: end_value }),
        };
        Function { kind }
    }

    /// y(x).
    pub fn value(&self, x: f64) -> f64 {
        match &self.kind {
            Kind::Constant(value) => *value,
            Kind::Linear { slope, intercept } => x * slope + intercept,
            Kind::SimmSpline(f) => f.value(x),
            Kind::GcvSpline(f) => f.value(x),
            Kind::PiecewiseLinear(f) => f.value(x),
            Kind::PiecewiseConstant(f) => f.value(x),
            Kind::Polynomial(f) => f.value(x),
            Kind::Multiplier { scale, function } => function.value(x) * scale,
            Kind::Sine { amplitude, omega, phase, offset } => amplitude * (omega * x + phase).sin() + offset,
            Kind::Step(f) => f.value(x),
        }
    }

    /// dy/dx, OpenSim's `calcDerivative({0}, x)`.
    pub fn derivative(&self, x: f64) -> f64 {
        match &self.kind {
            Kind::Constant(_) | Kind::PiecewiseConstant(_) => 0.0,
            Kind::Linear { slope, .. } => *slope,
            Kind::SimmSpline(f) => f.derivative(x),
            Kind::GcvSpline(f) => f.derivative(x),
            Kind::PiecewiseLinear(f) => f.derivative(x),
            Kind::Polynomial(f) => f.derivative(x),
            Kind::Multiplier { scale, function } => function.derivative(x) * scale,
            Kind::Sine { amplitude, omega, phase, .. } => amplitude * omega * (omega * x + phase).cos(),
            Kind::Step(f) => f.derivative(x),
        }
    }

    /// d²y/dx², OpenSim's `calcDerivative({0, 0}, x)`.
    pub fn second_derivative(&self, x: f64) -> f64 {
        match &self.kind {
            Kind::Constant(_) | Kind::Linear { .. } | Kind::PiecewiseLinear(_) | Kind::PiecewiseConstant(_) => 0.0,
            Kind::SimmSpline(f) => f.second_derivative(x),
            Kind::GcvSpline(f) => f.second_derivative(x),
            Kind::Polynomial(f) => f.second_derivative(x),
            Kind::Multiplier { scale, function } => function.second_derivative(x) * scale,
            Kind::Sine { amplitude, omega, phase, .. } => -amplitude * omega * omega * (omega * x + phase).sin(),
            Kind::Step(f) => f.second_derivative(x),
        }
    }

    /// (y, dy/dx) with one knot search, equal to (`value`, `derivative`).
    pub fn value_and_derivative(&self, x: f64) -> (f64, f64) {
        match &self.kind {
            Kind::SimmSpline(f) => f.value_and_derivative(x),
            Kind::GcvSpline(f) => f.value_and_derivative(x),
            Kind::PiecewiseLinear(f) => f.value_and_derivative(x),
            Kind::Multiplier { scale, function } => {
                let (value, derivative) = function.value_and_derivative(x);
                (value * scale, derivative * scale)
            }
            _ => (self.value(x), self.derivative(x)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn knots(x: &[f64], y: &[f64]) -> (Vec<f64>, Vec<f64>) {
        (x.to_vec(), y.to_vec())
    }

    #[test]
    fn linear_function_is_exact() {
        let f = Function::new(&FunctionSpec::LinearFunction { slope: -1.5, intercept: 0.25 });
        assert_eq!((f.value(2.0), f.derivative(2.0), f.second_derivative(2.0)), (-2.75, -1.5, 0.0));
    }

    #[test]
    fn constant_has_no_slope() {
        let f = Function::new(&FunctionSpec::Constant { value: 3.5 });
        assert_eq!((f.value(-9.0), f.derivative(1.0), f.second_derivative(1.0)), (3.5, 0.0, 0.0));
    }

    #[test]
    fn multiplier_scales_value_and_derivatives() {
        let (x, y) = knots(&[0.0, 1.0, 2.5, 3.0], &[1.0, 2.0, 0.5, 0.7]);
        let inner = FunctionSpec::SimmSpline { x, y };
        let f = Function::new(&inner);
        let scaled = Function::new(&FunctionSpec::MultiplierFunction { scale: 0.93, function: Box::new(inner) });
        for t in [-0.5, 0.3, 1.0, 2.9, 4.0] {
            assert_eq!(scaled.value(t), f.value(t) * 0.93);
            assert_eq!(scaled.derivative(t), f.derivative(t) * 0.93);
            assert_eq!(scaled.second_derivative(t), f.second_derivative(t) * 0.93);
            assert_eq!(scaled.value_and_derivative(t), (scaled.value(t), scaled.derivative(t)));
        }
    }

    /// A step holds its end values outside the transition, passes the midpoint halfway (stepUp
    /// is odd about s = ½), leaves and arrives with zero slope and curvature, and its derivatives
    /// are those of its values; reversed times mirror it.
    #[test]
    fn step_function_is_simbodys_quintic_step() {
        let step = |x0, x1| Function::new(&FunctionSpec::StepFunction { start_time: x0, end_time: x1, start_value: 2.0, end_value: -1.0 });
        let f = step(0.5, 1.5);
        assert_eq!([f.value(0.0), f.value(0.5), f.value(1.5), f.value(9.0)], [2.0, 2.0, -1.0, -1.0]);
        assert!((f.value(1.0) - 0.5).abs() < 1e-15 && (f.value(0.75) + f.value(1.25) - 1.0).abs() < 1e-15);
        assert!(f.derivative(0.5 + 1e-6).abs() < 1e-9 && f.second_derivative(1.5 - 1e-6).abs() < 1e-3);
        let h = 1e-6;
        for x in [0.6, 0.9, 1.2, 1.45] {
            assert!((f.derivative(x) - (f.value(x + h) - f.value(x - h)) / (2.0 * h)).abs() < 1e-8, "slope at {x}");
            assert!((f.second_derivative(x) - (f.derivative(x + h) - f.derivative(x - h)) / (2.0 * h)).abs() < 1e-6, "curvature at {x}");
        }
        let reversed = step(1.5, 0.5);
        assert_eq!([reversed.value(2.0), reversed.value(0.0)], [2.0, -1.0]);
        assert!((reversed.value(0.75) - f.value(1.25)).abs() < 1e-15);
    }

    #[test]
    fn sine_and_its_derivatives() {
        let f = Function::new(&FunctionSpec::Sine { amplitude: 0.3, omega: 4.0, phase: 0.5, offset: 0.2 });
        let x = 0.7;
        assert_eq!(f.value(x), 0.3 * (4.0f64 * 0.7 + 0.5).sin() + 0.2);
        let h = 1e-6;
        assert!((f.derivative(x) - (f.value(x + h) - f.value(x - h)) / (2.0 * h)).abs() < 1e-8);
        assert!((f.second_derivative(x) - (f.derivative(x + h) - f.derivative(x - h)) / (2.0 * h)).abs() < 1e-6);
    }

    #[test]
    fn gcv_spline_interpolates_with_zero_error_variance() {
        let (x, y) = knots(&[0.0, 0.4, 1.1, 1.5, 2.3, 3.0, 3.2, 4.1], &[0.1, 0.9, 1.3, 0.7, -0.4, -0.2, 0.3, 1.6]);
        for degree in [1, 3, 5, 7] {
            let f = Function::new(&FunctionSpec::GCVSpline { degree, error_variance: 0.0, x: x.clone(), y: y.clone() });
            for (xi, yi) in x.iter().zip(&y) {
                assert!((f.value(*xi) - yi).abs() < 1e-9, "degree {degree} at {xi}");
            }
        }
    }

    #[test]
    fn gcv_spline_derivative_matches_central_differences() {
        let (x, y) = knots(&[0.0, 0.4, 1.1, 1.5, 2.3, 3.0, 3.2, 4.1], &[0.1, 0.9, 1.3, 0.7, -0.4, -0.2, 0.3, 1.6]);
        let f = Function::new(&FunctionSpec::GCVSpline { degree: 5, error_variance: 0.0, x, y });
        let h = 1e-6;
        for t in [-0.5, 0.2, 1.3, 2.9, 4.5] {
            let slope = (f.value(t + h) - f.value(t - h)) / (2.0 * h);
            let curvature = (f.derivative(t + h) - f.derivative(t - h)) / (2.0 * h);
            assert!((f.derivative(t) - slope).abs() < 1e-6, "slope at {t}");
            assert!((f.second_derivative(t) - curvature).abs() < 1e-5, "curvature at {t}");
            assert_eq!(f.value_and_derivative(t), (f.value(t), f.derivative(t)));
        }
    }
}
