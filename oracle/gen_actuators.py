#!/usr/bin/env python3
"""Actuator goldens: the generalized forces of a unit actuation of OpenSim 4.6's
CoordinateActuator, PointActuator and TorqueActuator.

    python3 oracle/gen_actuators.py

The model is gait2392_millard2012muscle with every force of its ForceSet disabled and gravity
set to zero. Appended to it: the six residual actuators of
fixtures/subject01/gait2392_SO_Residual_Actuators.xml (a 2.x file: PointActuators FX/FY/FZ on
the pelvis, force in ground, and TorqueActuators MX/MY/MZ between pelvis and ground, axis in
ground), and the actuators this script builds and writes to
fixtures/golden/actuators/extra_actuators.xml (4.x), read back from that file:

- knee_r: a CoordinateActuator on knee_angle_r;
- tibia_push: a PointActuator on tibia_r whose point is given in ground (point_is_global) and
  whose direction, not of unit length, is in the tibia (force_is_global false);
- knee_twist: a TorqueActuator between femur_r and tibia_r whose axis, not of unit length, is in
  the femur (torque_is_global false).

At 6 poses — random coordinate values within each coordinate's range (the ground joint's
translations within ±0.2 m of their default; a locked coordinate keeps its default, and the
file records the values the state holds), q set without assembly, u = 0 — every actuator in
turn has its actuation overridden to 1 (N or N·m; `overrideActuation`, optimal force and
controls unused) with the others overridden to 0. The generalized forces it produces are
τ(0) − τ(1), where τ(a) is `InverseDynamicsSolver.solve(state, u̇ = 0)` (M u̇ + C − applied)
with the actuator at a. With no gravity, no speeds and no other force τ(0) is exactly zero (the
script checks it), so the golden is −τ(1) to the last bit.

Columns follow Simbody's generalized speeds: a coordinate's speed index is found by setting one
coordinate's speed at a time and reading the state's U (gait2392's speeds are all q̇).

Writes fixtures/golden/actuators/:
    actuators.csv           actuator,class,optimal_force,min_control,max_control,applies_force
                            as OpenSim read them from the two files
    poses.csv               pose_id, then one column per coordinate (CoordinateSet order)
    generalized_forces.csv  pose_id,actuator,coordinate,generalized_force
                            (every pose × actuator × coordinate; N·m or N per unit actuation)
    extra_actuators.xml     the ForceSet of the three built actuators
Floats as Python repr. Deterministic: random.Random(20261203).
"""
import random
import sys
from pathlib import Path

import opensim as osim

from gen_inverse_dynamics import speed_indices

REPO = Path(__file__).resolve().parent.parent
MODEL = REPO / "models" / "gait2392_millard2012muscle.osim"
RESIDUALS = REPO / "fixtures" / "subject01" / "gait2392_SO_Residual_Actuators.xml"
OUT_DIR = REPO / "fixtures" / "golden" / "actuators"
EXTRA = OUT_DIR / "extra_actuators.xml"
SEED = 20261203
POSES = 6
GROUND_TRANSLATION = 0.2


def extra_actuators():
    """The three built actuators, every property set so that the file states it."""
    knee = osim.CoordinateActuator("knee_angle_r")
    knee.setName("knee_r")
    knee.set_optimal_force(250.0)
    knee.set_min_control(-2.0)
    knee.set_max_control(3.0)

    push = osim.PointActuator("tibia_r")
    push.setName("tibia_push")
    push.set_point(osim.Vec3(0.1, 0.4, 0.05))
    push.set_point_is_global(True)
    push.set_direction(osim.Vec3(0.3, -2.0, 0.5))
    push.set_force_is_global(False)
    push.set_optimal_force(40.0)
    push.set_min_control(-1.0)
    push.set_max_control(1.0)

    twist = osim.TorqueActuator()
    twist.setName("knee_twist")
    twist.set_bodyA("femur_r")
    twist.set_bodyB("tibia_r")
    twist.set_axis(osim.Vec3(1.0, 2.0, -0.5))
    twist.set_torque_is_global(False)
    twist.set_optimal_force(15.0)
    twist.set_min_control(-1.0)
    twist.set_max_control(1.0)

    actuators = osim.ForceSet()
    actuators.setName("extra_actuators")
    for actuator in (knee, push, twist):
        actuator.set_appliesForce(True)
        actuators.cloneAndAppend(actuator)
    return actuators


def draw_value(coordinate, rng):
    joint = coordinate.getJoint()
    on_ground = joint.getParentFrame().findBaseFrame().getName() == "ground"
    u = rng.random()
    if on_ground and coordinate.getMotionType() != 1:  # 1 = Rotational
        return coordinate.getDefaultValue() + (2.0 * u - 1.0) * GROUND_TRANSLATION
    lo, hi = coordinate.getRangeMin(), coordinate.getRangeMax()
    return lo + (hi - lo) * u


def build_model():
    """The model with its forces off, no gravity, and the actuators read from the two files;
    returns it with the actuators' names in file order."""
    model = osim.Model(str(MODEL))
    forces = model.getForceSet()
    for i in range(forces.getSize()):
        forces.get(i).set_appliesForce(False)
    model.setGravity(osim.Vec3(0.0, 0.0, 0.0))
    names = []
    for path in (RESIDUALS, EXTRA):
        actuators = osim.ForceSet(str(path))
        for i in range(actuators.getSize()):
            names.append(actuators.get(i).getName())
            model.updForceSet().cloneAndAppend(actuators.get(i))
    return model, names


def main():
    rng = random.Random(SEED)
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    extra_actuators().printToXML(str(EXTRA))
    model, names = build_model()
    state = model.initSystem()
    actuators = [osim.ScalarActuator.safeDownCast(model.getForceSet().get(name)) for name in names]
    for actuator in actuators:
        actuator.overrideActuation(state, True)
    coordinates = model.getCoordinateSet()
    n = coordinates.getSize()
    coordinate_names = [coordinates.get(i).getName() for i in range(n)]
    indices = speed_indices(model, state)
    solver = osim.InverseDynamicsSolver(model)
    udot = osim.Vector(state.getNU(), 0.0)

    def tau(active):
        for actuator in actuators:
            actuator.setOverrideActuation(state, 1.0 if actuator is active else 0.0)
        result = solver.solve(state, udot)
        return [result.get(indices[i]) for i in range(n)]

    pose_rows, force_rows = [], []
    for k in range(POSES):
        pose = f"pose_{k}"
        for i in range(n):
            coordinates.get(i).setValue(state, draw_value(coordinates.get(i), rng), False)
        model.realizeVelocity(state)
        q = [coordinates.get(i).getValue(state) for i in range(n)]
        pose_rows.append(",".join([pose] + [repr(v) for v in q]))
        idle = tau(None)
        if any(v != 0.0 for v in idle):
            sys.exit(f"{pose}: nonzero generalized forces with every actuator at 0: {idle}")
        for actuator in actuators:
            applied = [a - b for a, b in zip(idle, tau(actuator))]
            for name, value in zip(coordinate_names, applied):
                force_rows.append(f"{pose},{actuator.getName()},{name},{value!r}")
    properties = [
        f"{a.getName()},{a.getConcreteClassName()},{a.getOptimalForce()!r},{a.get_min_control()!r},"
        f"{a.get_max_control()!r},{str(a.get_appliesForce()).lower()}"
        for a in actuators
    ]
    (OUT_DIR / "actuators.csv").write_text(
        "actuator,class,optimal_force,min_control,max_control,applies_force\n" + "\n".join(properties) + "\n"
    )
    (OUT_DIR / "poses.csv").write_text(",".join(["pose_id"] + coordinate_names) + "\n" + "\n".join(pose_rows) + "\n")
    (OUT_DIR / "generalized_forces.csv").write_text(
        "pose_id,actuator,coordinate,generalized_force\n" + "\n".join(force_rows) + "\n"
    )
    print(f"{OUT_DIR.relative_to(REPO)}: {POSES} poses x {len(actuators)} actuators x {n} coordinates")


if __name__ == "__main__":
    main()
