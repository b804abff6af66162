"""Goldens for `mechanics::function`: OpenSim 4.6 evaluates each test function.

Every function is written as an OpenSim XML object and read back with
`OpenSimObject.makeObjectFromFile`, so OpenSim builds it exactly as when it reads a
model (`updateFromXMLNode`, the `NaturalCubicSpline` → `SimmSpline` rename, GCVSpline's
`half_order`/`error_variance` properties). Writes to fixtures/golden/functions/:

- definitions.json: each function as {name, class, …} (degree, not half_order, for
  GCVSpline; `function` nests the MultiplierFunction's inner definition), every number as
  the text OpenSim read (lists space-separated) so it parses back exactly;
- <name>.csv: x, value, derivative, second_derivative (calcValue and calcDerivative with
  derivComponents [0] and [0, 0]) on a grid below, at, between and above the knots.

Run from the repository root: python3 oracle/gen_functions.py
"""

import json
import os
import tempfile

import opensim

OUT = os.path.join(os.path.dirname(__file__), "..", "fixtures", "golden", "functions")

# gait2392_millard2012muscle.osim: knee_r translation1 and rect_fem_r-P3 x_location.
KNEE_X = [-2.0944, -1.74533, -1.39626, -1.0472, -0.698132, -0.349066, -0.174533, 0.197344,
          0.337395, 0.490178, 1.52146, 2.0944]
KNEE_Y = [-0.0032, 0.00179, 0.00411, 0.0041, 0.00212, -0.001, -0.0031, -0.005227, -0.005435,
          -0.005574, -0.005435, -0.00525]
RECT_FEM_X = [-2.0944, -1.99997, -1.5708, -1.45752, -1.39626, -1.0472, -0.698132, -0.526391,
              -0.349066, -0.174533, 0, 0.00017453, 0.00034907, 0.0279253, 0.0872665, 0.174533,
              2.0944]
RECT_FEM_Y = [0.0155805, 0.0179938, 0.0275081, 0.0296564, 0.0307615, 0.0365695, 0.0422074,
              0.0450902, 0.048391, 0.0534299, 0.0617576, 0.0617669, 0.0617762, 0.0633083,
              0.066994, 0.0733035, 0.0573481]
GCV_X = [0.0, 0.4, 1.1, 1.5, 2.3, 3.0, 3.2, 4.1]
GCV_Y = [0.1, 0.9, 1.3, 0.7, -0.4, -0.2, 0.3, 1.6]
GCV_X10 = GCV_X + [4.6, 5.5]
GCV_Y10 = GCV_Y + [1.1, 0.2]

DEFINITIONS = [
    {"name": "simm_spline_2", "class": "SimmSpline", "x": [-0.5, 1.2], "y": [0.3, -0.7]},
    {"name": "simm_spline_3", "class": "SimmSpline", "x": [0.0, 0.7, 2.0], "y": [1.0, 0.2, 0.9]},
    {"name": "simm_spline_4", "class": "SimmSpline", "x": [-1.0, -0.3, 0.05, 1.6],
     "y": [0.5, 0.1, 0.4, -0.8]},
    {"name": "simm_spline_knee", "class": "SimmSpline", "x": KNEE_X, "y": KNEE_Y},
    {"name": "simm_spline_rect_fem", "class": "SimmSpline", "x": RECT_FEM_X, "y": RECT_FEM_Y},
    {"name": "natural_cubic_spline", "class": "NaturalCubicSpline",
     "x": [0.0, 0.5, 1.3, 2.0, 3.1], "y": [0.0, 0.8, 0.4, -0.3, 0.6]},
    {"name": "piecewise_linear", "class": "PiecewiseLinearFunction",
     "x": [-1.0, 0.0, 0.4, 1.5, 2.0], "y": [0.2, 1.0, 0.7, 0.9, -0.5]},
    {"name": "piecewise_linear_single", "class": "PiecewiseLinearFunction",
     "x": [0.3], "y": [1.7]},
    {"name": "piecewise_constant", "class": "PiecewiseConstantFunction",
     "x": [-1.0, 0.0, 0.4, 1.5, 2.0], "y": [0.2, 1.0, 0.7, 0.9, -0.5]},
    {"name": "polynomial_cubic", "class": "PolynomialFunction",
     "coefficients": [0.5, -1.2, 0.3, 2.0]},
    {"name": "polynomial_constant", "class": "PolynomialFunction", "coefficients": [1.25]},
    {"name": "linear", "class": "LinearFunction", "slope": -1.7, "intercept": 0.25},
    {"name": "constant", "class": "Constant", "value": 3.5},
    {"name": "multiplier_knee", "class": "MultiplierFunction", "scale": 0.93,
     "function": {"class": "SimmSpline", "x": KNEE_X, "y": KNEE_Y}},
    {"name": "gcv_spline_1", "class": "GCVSpline", "degree": 1, "x": GCV_X, "y": GCV_Y},
    {"name": "gcv_spline_3", "class": "GCVSpline", "degree": 3, "x": GCV_X, "y": GCV_Y},
    {"name": "gcv_spline_5", "class": "GCVSpline", "degree": 5, "x": GCV_X, "y": GCV_Y},
    {"name": "gcv_spline_7", "class": "GCVSpline", "degree": 7, "x": GCV_X10, "y": GCV_Y10},
    # Not reachable from FunctionSpec yet (it has no error_variance): smoothing by a given
    # error variance, and by generalized cross-validation (negative error variance).
    {"name": "gcv_spline_5_error_variance", "class": "GCVSpline", "degree": 5, "x": GCV_X10,
     "y": GCV_Y10, "error_variance": 0.01},
    {"name": "gcv_spline_5_cross_validated", "class": "GCVSpline", "degree": 5, "x": GCV_X10,
     "y": GCV_Y10, "error_variance": -1.0},
]


def numbers(values):
    return " ".join(repr(float(v)) for v in values)


def as_text(definition):
    """`definition` with its numbers as the text written into the XML."""
    text = {}
    for key, value in definition.items():
        if key == "function":
            text[key] = as_text(value)
        elif isinstance(value, list):
            text[key] = numbers(value)
        elif isinstance(value, float):
            text[key] = repr(value)
        else:
            text[key] = value
    return text


def xml(definition):
    """OpenSim XML of one function, as a model file would hold it."""
    cls = definition["class"]
    if cls in ("SimmSpline", "NaturalCubicSpline", "PiecewiseLinearFunction",
               "PiecewiseConstantFunction"):
        body = f"<x>{numbers(definition['x'])}</x><y>{numbers(definition['y'])}</y>"
    elif cls == "GCVSpline":
        half_order = (definition["degree"] + 1) // 2
        body = (f"<half_order>{half_order}</half_order>"
                f"<error_variance>{definition.get('error_variance', 0.0)!r}</error_variance>"
                f"<x>{numbers(definition['x'])}</x><y>{numbers(definition['y'])}</y>")
    elif cls == "PolynomialFunction":
        body = f"<coefficients>{numbers(definition['coefficients'])}</coefficients>"
    elif cls == "LinearFunction":
        body = f"<coefficients>{numbers([definition['slope'], definition['intercept']])}</coefficients>"
    elif cls == "Constant":
        body = f"<value>{definition['value']!r}</value>"
    elif cls == "MultiplierFunction":
        body = f"<function>{xml(definition['function'])}</function><scale>{definition['scale']!r}</scale>"
    else:
        raise ValueError(cls)
    return f"<{cls}>{body}</{cls}>"


def load(definition):
    return load_xml(xml(definition))


def load_xml(text):
    """An OpenSim Function read from its XML `text`, as a model file would give it (the Python
    bindings take no arrays for e.g. GCVSpline's and PiecewiseLinearFunction's constructors)."""
    document = f'<?xml version="1.0" encoding="UTF-8" ?>\n<OpenSimDocument Version="40600">{text}</OpenSimDocument>\n'
    with tempfile.NamedTemporaryFile("w", suffix=".xml", delete=False) as file:
        file.write(document)
    try:
        return opensim.Function.safeDownCast(opensim.OpenSimObject.makeObjectFromFile(file.name))
    finally:
        os.unlink(file.name)


def grid(definition):
    """Abscissae below, at, just beside, between and above the knots."""
    if "x" not in definition and "function" not in definition:
        return [-2.5, -2.0, -1.3, -1.0, -0.7, -0.5, -0.1, -1e-14, 0.0, 1e-14, 0.2, 0.5,
                0.9, 1.0, 1.1, 1.5, 1.9, 2.0, 2.3, 3.0, 7.5, -7.25]
    knots = definition["x"] if "x" in definition else definition["function"]["x"]
    first, last = knots[0], knots[-1]
    span = max(last - first, 1.0)
    points = [first - 1.0, first - 0.25 * span, first - 1e-13, first + 1e-13, first + 1e-9,
              last - 1e-13, last + 1e-13, last + 0.25 * span, last + 1.0]
    points += knots
    for left, right in zip(knots, knots[1:]):
        points += [0.5 * (left + right), left + 0.3 * (right - left)]
    return sorted(set(points))


def evaluate(function, x):
    at = opensim.Vector(1, x)
    first = opensim.StdVectorInt([0])
    second = opensim.StdVectorInt([0, 0])
    return (function.calcValue(at), function.calcDerivative(first, at),
            function.calcDerivative(second, at))


def main():
    os.makedirs(OUT, exist_ok=True)
    for definition in DEFINITIONS:
        function = load(definition)
        rows = ["x,value,derivative,second_derivative"]
        for x in grid(definition):
            rows.append(",".join(repr(float(v)) for v in (x, *evaluate(function, x))))
        with open(os.path.join(OUT, f"{definition['name']}.csv"), "w") as file:
            file.write("\n".join(rows) + "\n")
    with open(os.path.join(OUT, "definitions.json"), "w") as file:
        json.dump({"opensim_version": opensim.__version__,
                   "functions": [as_text(d) for d in DEFINITIONS]}, file,
                  indent=1)
        file.write("\n")


if __name__ == "__main__":
    main()
