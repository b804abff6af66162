#!/usr/bin/env python3
"""Goldens for `Thelen2003Muscle::fiber_velocity`: OpenSim 4.6's fiber-length state derivative of
Thelen2003Muscle at set activation, fiber length and path length.

    python3 oracle/gen_thelen_velocity.py     (from the repository root; needs `import opensim`, 4.6)

For each muscle of MUSCLES, the muscle is read from the repository model, and a bench model is
built: ground -SliderJoint-> block, path from the ground origin to the block origin (path
length = slider coordinate), one Thelen2003Muscle carrying every property of the model's muscle
(copied property by property). For each (activation, fiber length, path length) of the grid:
fresh copy of the initial state, slider value = path length (speed 0), `setActivation`,
`setFiberLength`, `realizeAcceleration`, then the muscle's `getStateVariableDerivativeValue(s,
"fiber_length")` (the forward-simulation state derivative), `getFiberVelocity`,
`getNormalizedFiberVelocity`, `getForceVelocityMultiplier`, `getTendonForce`.

Grid: activations 0 (OpenSim raises it to minimum_activation 0.01), 0.3, 1; fiber lengths
0.5 * minimum (below the minimum: OpenSim clamps), the minimum itself, and 0.5, 0.8, 1.0, 1.3,
1.7 optimal fiber lengths (the first two only for pennated muscles, whose minimum is > 0); path
lengths = fiber length along the tendon + (1 + strain) * tendon slack length for tendon strains
-0.005 (slack), 0.003 (toe), 0.03 and 0.06 (linear region). These cover concentric and
eccentric fibers, both linear extrapolations of the force-velocity curve and the clamp at the
minimum fiber length.

Writes fixtures/golden/muscle/thelen_velocity/fiber_velocity.csv with columns
    model, muscle, activation, fiber_length, mt_length, fiber_length_derivative, fiber_velocity,
    normalized_fiber_velocity, force_velocity_multiplier, tendon_force
"""
import math
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
OUT_DIR = REPO / "fixtures" / "golden" / "muscle" / "thelen_velocity"
MODELS = {
    "gait2392_thelen2003muscle": REPO / "models" / "gait2392_thelen2003muscle.osim",
    "arm26": REPO / "fixtures" / "models" / "arm26.osim",
}
MUSCLES = [
    ("gait2392_thelen2003muscle", "semimem_r"),
    ("gait2392_thelen2003muscle", "rect_fem_r"),
    ("gait2392_thelen2003muscle", "med_gas_r"),
    ("arm26", "TRIlong"),
    ("arm26", "BIClong"),
]
PROPERTIES = ["max_isometric_force", "optimal_fiber_length", "tendon_slack_length",
              "pennation_angle_at_optimal", "max_contraction_velocity", "activation_time_constant",
              "deactivation_time_constant", "minimum_activation", "maximum_pennation_angle",
              "FmaxTendonStrain", "FmaxMuscleStrain", "KshapeActive", "KshapePassive", "Af",
              "Flen", "fv_linear_extrap_threshold"]
ACTIVATIONS = [0.0, 0.3, 1.0]
NORMALIZED_FIBER_LENGTHS = [0.5, 0.8, 1.0, 1.3, 1.7]
TENDON_STRAINS = [-0.005, 0.003, 0.03, 0.06]
COLUMNS = ["model", "muscle", "activation", "fiber_length", "mt_length", "fiber_length_derivative",
           "fiber_velocity", "normalized_fiber_velocity", "force_velocity_multiplier", "tendon_force"]


def fmt(x):
    """Shortest round-trip decimal of a double."""
    return repr(float(x))


def model_muscle(stem, name):
    """The muscle and its model (which must outlive it)."""
    model = osim.Model(str(MODELS[stem]))
    return model, osim.Thelen2003Muscle.safeDownCast(model.getMuscles().get(name))


def bench(source):
    model = osim.Model()
    model.setName("thelen_velocity_bench")
    block = osim.Body("block", 1.0, osim.Vec3(0), osim.Inertia(0.01, 0.01, 0.01))
    slider = osim.SliderJoint("slider", model.getGround(), block)
    slider.updCoordinate().setName("mt_length")
    slider.updCoordinate().setRangeMin(0.0)
    slider.updCoordinate().setRangeMax(10.0)
    model.addBody(block)
    model.addJoint(slider)
    muscle = osim.Thelen2003Muscle()
    muscle.setName(source.getName())
    for name in PROPERTIES:
        value = osim.PropertyHelper.getValueDouble(source.getPropertyByName(name))
        osim.PropertyHelper.setValueDouble(value, muscle.updPropertyByName(name))
    muscle.addNewPathPoint("origin", model.updGround(), osim.Vec3(0, 0, 0))
    muscle.addNewPathPoint("insertion", block, osim.Vec3(0, 0, 0))
    model.addForce(muscle)
    state = model.initSystem()
    muscle = osim.Thelen2003Muscle.safeDownCast(model.getMuscles().get(0))
    return model, state, muscle, model.getCoordinateSet().get("mt_length")


def fiber_length_along_tendon(muscle, fiber_length):
    """MuscleFixedWidthPennationModel: fiber clamped to its minimum, sin(alpha) = h / L_m."""
    minimum = muscle.getMinimumFiberLength()
    length = max(fiber_length, minimum)
    alpha_opt = muscle.getPennationAngleAtOptimalFiberLength()
    if alpha_opt <= 2.220446049250313e-16:
        return length
    height = muscle.getOptimalFiberLength() * math.sin(alpha_opt)
    alpha_max = muscle.get_maximum_pennation_angle()
    sin_alpha = height / length
    alpha = math.asin(sin_alpha) if length > minimum and sin_alpha < math.sin(alpha_max) else alpha_max
    return length * math.cos(alpha)


def fiber_lengths(muscle):
    minimum = muscle.getMinimumFiberLength()
    lengths = [0.5 * minimum, minimum] if minimum > 0 else []
    return lengths + [x * muscle.getOptimalFiberLength() for x in NORMALIZED_FIBER_LENGTHS]


def rows_for(stem, name):
    _owner, source = model_muscle(stem, name)
    model, initial, muscle, coordinate = bench(source)
    rows = []
    for activation in ACTIVATIONS:
        for fiber_length in fiber_lengths(muscle):
            for strain in TENDON_STRAINS:
                mt_length = fiber_length_along_tendon(muscle, fiber_length) \
                    + (1.0 + strain) * muscle.getTendonSlackLength()
                state = osim.State(initial)
                coordinate.setValue(state, mt_length, False)
                coordinate.setSpeedValue(state, 0.0)
                muscle.setActivation(state, activation)
                muscle.setFiberLength(state, fiber_length)
                model.realizeAcceleration(state)
                rows.append([stem, name, fmt(activation), fmt(fiber_length), fmt(muscle.getLength(state)),
                             fmt(muscle.getStateVariableDerivativeValue(state, "fiber_length")),
                             fmt(muscle.getFiberVelocity(state)),
                             fmt(muscle.getNormalizedFiberVelocity(state)),
                             fmt(muscle.getForceVelocityMultiplier(state)),
                             fmt(muscle.getTendonForce(state))])
    return rows


def main():
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    rows = [row for stem, name in MUSCLES for row in rows_for(stem, name)]
    with open(OUT_DIR / "fiber_velocity.csv", "w") as out:
        out.write(",".join(COLUMNS) + "\n")
        out.write("".join(",".join(row) + "\n" for row in rows))
    print(len(rows), "rows,", osim.GetVersionAndDate())


if __name__ == "__main__":
    main()
