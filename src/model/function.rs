//! OpenSim functions of one variable as they appear in model files (`SimmSpline`,
//! `LinearFunction`, …), validated on reading. Evaluation lives with the kinematics.

use serde::Serialize;

use super::error::ModelError;
use super::reader::ComponentReader;

/// A function y = f(x) as written in the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "class")]
pub enum FunctionSpec {
    Constant { value: f64 },
    /// y = slope·x + intercept (`coefficients` = slope intercept).
    LinearFunction { slope: f64, intercept: f64 },
    /// Also a `NaturalCubicSpline`, which OpenSim registers as a renamed `SimmSpline`.
    SimmSpline { x: Vec<f64>, y: Vec<f64> },
    /// Woltring's smoothing spline of odd `degree` (= 2·`half_order` − 1); `error_variance` 0
    /// interpolates, > 0 smooths, < 0 picks the smoothing by generalized cross-validation.
    GCVSpline { degree: usize, error_variance: f64, x: Vec<f64>, y: Vec<f64> },
    PiecewiseLinearFunction { x: Vec<f64>, y: Vec<f64> },
    PiecewiseConstantFunction { x: Vec<f64>, y: Vec<f64> },
    /// y = c_0·x^p + c_1·x^(p−1) + … + c_p with p = len − 1: highest power first, as OpenSim's
    /// `PolynomialFunction` (Simbody's `Function::Polynomial`).
    PolynomialFunction { coefficients: Vec<f64> },
    /// y = scale · f(x).
    MultiplierFunction { scale: f64, function: Box<FunctionSpec> },
    /// y = amplitude·sin(omega·x + phase) + offset (omega rad per unit of x).
    Sine { amplitude: f64, omega: f64, phase: f64, offset: f64 },
    /// `start_value` up to `transition_start_time`, `end_value` from `transition_end_time`, and
    /// between them Simbody's quintic `stepUp` (10s³ − 15s⁴ + 6s⁵ of the fraction s of the way;
    /// the times may be in either order).
    StepFunction { start_time: f64, end_time: f64, start_value: f64, end_value: f64 },
}

impl FunctionSpec {
    /// Reads the function object `reader` points at.
    pub fn read(reader: ComponentReader) -> Result<FunctionSpec, ModelError> {
        let function = match reader.class() {
            "Constant" => FunctionSpec::Constant { value: reader.number_or("value", 0.0)? },
            "LinearFunction" => {
                let c = reader.numbers_or("coefficients", &[1.0, 0.0])?;
                FunctionSpec::LinearFunction { slope: c[0], intercept: c[1] }
            }
            "SimmSpline" | "NaturalCubicSpline" => {
                let (x, y) = knots(reader, 2)?;
                FunctionSpec::SimmSpline { x, y }
            }
            "GCVSpline" => {
                let half_order = reader.number("half_order")?;
                if ![1.0, 2.0, 3.0, 4.0].contains(&half_order) {
                    return Err(reader.bad("half_order", "1, 2, 3 or 4", &half_order.to_string()));
                }
                let half_order = half_order as usize;
                let (x, y) = knots(reader, 2 * half_order)?;
                FunctionSpec::GCVSpline { degree: 2 * half_order - 1, error_variance: reader.number_or("error_variance", 0.0)?, x, y }
            }
            "PiecewiseLinearFunction" => {
                let (x, y) = knots(reader, 1)?;
                FunctionSpec::PiecewiseLinearFunction { x, y }
            }
            "PiecewiseConstantFunction" => {
                let (x, y) = knots(reader, 1)?;
                FunctionSpec::PiecewiseConstantFunction { x, y }
            }
            "PolynomialFunction" => FunctionSpec::PolynomialFunction { coefficients: reader.numbers("coefficients", None)? },
            "MultiplierFunction" => {
                let inner = reader.object_property("function").ok_or_else(|| reader.missing("function"))?;
                FunctionSpec::MultiplierFunction { scale: reader.number_or("scale", 1.0)?, function: Box::new(FunctionSpec::read(inner)?) }
            }
            "Sine" => FunctionSpec::Sine {
                amplitude: reader.number_or("amplitude", 1.0)?,
                omega: reader.number_or("omega", 1.0)?,
                phase: reader.number_or("phase", 0.0)?,
                offset: reader.number_or("offset", 0.0)?,
            },
            "StepFunction" => {
                let (start_time, end_time) = (reader.number_or("transition_start_time", 0.99)?, reader.number_or("transition_end_time", 1.01)?);
                if end_time == start_time {
                    return Err(reader.bad("transition_end_time", "a time other than transition_start_time", &end_time.to_string()));
                }
                FunctionSpec::StepFunction { start_time, end_time, start_value: reader.number_or("start_value", 0.0)?, end_value: reader.number_or("end_value", 1.0)? }
            }
            other => return Err(reader.bad("function", "a supported OpenSim function", other)),
        };
        Ok(function)
    }

    /// Whether the function is `LinearFunction` with slope ±1 (OpenSim's test for a pure
    /// rotation or translation of a `TransformAxis`).
    pub fn is_unit_linear(&self) -> bool {
        matches!(self, FunctionSpec::LinearFunction { slope, .. } if slope.abs() == 1.0)
    }
}

/// `x` and `y` of a spline: equal lengths, at least `minimum` points, x strictly increasing.
fn knots(reader: ComponentReader, minimum: usize) -> Result<(Vec<f64>, Vec<f64>), ModelError> {
    let x = reader.numbers("x", None)?;
    let y = reader.numbers("y", None)?;
    if x.len() != y.len() {
        let found = format!("{} x values and {} y values", x.len(), y.len());
        return Err(reader.bad("y", "as many values as <x>", &found));
    }
    if x.len() < minimum {
        return Err(reader.bad("x", &format!("at least {minimum} points"), &x.len().to_string()));
    }
    if let Some(i) = x.windows(2).position(|w| w[1] <= w[0]) {
        let found = format!("x[{}] = {} after x[{i}] = {}", i + 1, x[i + 1], x[i]);
        return Err(reader.bad("x", "strictly increasing values", &found));
    }
    Ok((x, y))
}
