//! `mechanics::function::Function` against OpenSim 4.6's own evaluation of the same functions
//! (`fixtures/golden/functions/`, from `oracle/gen_functions.py`).
//!
//! Bound: every value and both derivatives equal OpenSim's to the bit (`==`), which is
//! stricter than the 1e-12·max(1, |y|) on values and 1e-10 relative on derivatives we promise.

mod common;

use osim_tune::mechanics::function::Function;
use osim_tune::model::FunctionSpec;
use osim_tune::validation::GoldenTable;
use serde_json::Value;

/// The functions in definitions.json.
fn golden_functions() -> Vec<(String, FunctionSpec)> {
    let text = std::fs::read_to_string(common::fixture("golden/functions/definitions.json")).unwrap();
    let definitions: Value = serde_json::from_str(&text).unwrap();
    definitions["functions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| (d["name"].as_str().unwrap().to_string(), spec(d)))
        .collect()
}

/// Numbers are stored as the text OpenSim read (serde_json's own float parsing is not
/// always correctly rounded).
fn spec(definition: &Value) -> FunctionSpec {
    let numbers = |key: &str| -> Vec<f64> {
        definition[key].as_str().unwrap().split_whitespace().map(|v| v.parse().unwrap()).collect()
    };
    let number = |key: &str| numbers(key)[0];
    match definition["class"].as_str().unwrap() {
        "Constant" => FunctionSpec::Constant { value: number("value") },
        "LinearFunction" => FunctionSpec::LinearFunction { slope: number("slope"), intercept: number("intercept") },
        // OpenSim reads a `NaturalCubicSpline` as a `SimmSpline`, and so does osim-tune.
        "SimmSpline" | "NaturalCubicSpline" => FunctionSpec::SimmSpline { x: numbers("x"), y: numbers("y") },
        "GCVSpline" => {
            let degree = definition["degree"].as_u64().unwrap() as usize;
            let error_variance = definition.get("error_variance").map_or(0.0, |_| number("error_variance"));
            FunctionSpec::GCVSpline { degree, error_variance, x: numbers("x"), y: numbers("y") }
        }
        "PiecewiseLinearFunction" => FunctionSpec::PiecewiseLinearFunction { x: numbers("x"), y: numbers("y") },
        "PiecewiseConstantFunction" => FunctionSpec::PiecewiseConstantFunction { x: numbers("x"), y: numbers("y") },
        "PolynomialFunction" => FunctionSpec::PolynomialFunction { coefficients: numbers("coefficients") },
        "MultiplierFunction" => {
            let function = Box::new(spec(&definition["function"]));
            FunctionSpec::MultiplierFunction { scale: number("scale"), function }
        }
        other => panic!("unknown class {other}"),
    }
}

/// Rows (x, value, derivative, second derivative) of `<name>.csv`.
fn golden_rows(name: &str) -> Vec<[f64; 4]> {
    let table = GoldenTable::read(&common::fixture(&format!("golden/functions/{name}.csv"))).unwrap();
    (0..table.rows.len()).map(|r| [0, 1, 2, 3].map(|c| table.number(r, c).unwrap())).collect()
}

#[test]
fn every_function_class_matches_opensim_to_the_bit() {
    let functions = golden_functions();
    assert_eq!(functions.len(), 20, "functions in definitions.json");
    for (name, spec) in functions {
        let function = Function::new(&spec);
        let rows = golden_rows(&name);
        assert!(rows.len() >= 8, "{name}: {} rows", rows.len());
        for [x, value, derivative, second] in rows {
            assert_eq!(function.value(x), value, "{name}: value at x = {x:?}");
            assert_eq!(function.derivative(x), derivative, "{name}: derivative at x = {x:?}");
            assert_eq!(function.second_derivative(x), second, "{name}: second derivative at x = {x:?}");
            assert_eq!(function.value_and_derivative(x), (value, derivative), "{name}: value_and_derivative at {x:?}");
        }
    }
}
