#!/usr/bin/env python3
"""Inverse dynamics goldens: OpenSim 4.6's InverseDynamicsSolver at random states.

    python3 oracle/gen_inverse_dynamics.py

For each model below, every force in its ForceSet is disabled (gravity, which OpenSim applies
outside the ForceSet, stays), and at 8 states — random coordinate values q within each
coordinate's range (the ground joint's translations within ±0.2 m of their default), random
generalized speeds u ~ N(0, 1.5²) and accelerations u̇ ~ N(0, 8²) (rad/s, rad/s², m/s, m/s²;
state 0 has u = u̇ = 0, so its forces hold up the model against gravity) — it calls
`InverseDynamicsSolver.solve(state, udot)`: the generalized forces τ (N·m or N) that give the
accelerations u̇, constraints ignored (Simbody's calcResidualForceIgnoringConstraints). A coupled
coordinate takes its CoordinateCouplerConstraint's value; q is set without assembly; a locked coordinate keeps its
default (OpenSim refuses the new value), and the file records the values the state holds.

u is Simbody's generalized speed of the coordinate (q̇, but for a BallJoint's or FreeJoint's
rotations the angular velocity of the child frame in the parent frame, expressed in the parent).
The mapping from coordinates to Simbody's mobility order is found by setting one coordinate's
speed at a time and reading the state's U.

Writes fixtures/golden/inverse_dynamics/<stem>.csv with columns
    state,coordinate,q,u,udot,generalized_force
(one row per state and coordinate, CoordinateSet order; floats as Python repr). Deterministic:
random.Random(20261126).
"""
import random
import sys
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
OUT_DIR = REPO / "fixtures" / "golden" / "inverse_dynamics"
MODELS = {
    "gait2392_millard2012muscle": REPO / "models" / "gait2392_millard2012muscle.osim",
    "arm26": REPO / "fixtures" / "models" / "arm26.osim",
    "leg6dof9musc": REPO / "fixtures" / "models" / "leg6dof9musc.osim",
    "Rajagopal2016": REPO / "fixtures" / "models" / "Rajagopal2016.osim",
    "joint_zoo": REPO / "fixtures" / "models" / "joint_zoo.osim",
}
SEED = 20261126
STATES = 8
SPEED_SD = 1.5
ACCELERATION_SD = 8.0
GROUND_TRANSLATION = 0.2


def speed_indices(model, state):
    """Simbody's U index of each coordinate (CoordinateSet order); leaves every speed at 0."""
    coordinates = model.getCoordinateSet()
    indices = []
    for i in range(coordinates.getSize()):
        for j in range(coordinates.getSize()):
            coordinates.get(j).setSpeedValue(state, 0.0)
        coordinates.get(i).setSpeedValue(state, 1.0)
        u = state.getU()
        hits = [k for k in range(u.size()) if u.get(k) == 1.0]
        if len(hits) != 1:
            sys.exit(f"coordinate {coordinates.get(i).getName()}: {len(hits)} speeds moved")
        indices.append(hits[0])
    for j in range(coordinates.getSize()):
        coordinates.get(j).setSpeedValue(state, 0.0)
    return indices


def draw_value(coordinate, rng):
    joint = coordinate.getJoint()
    on_ground = joint.getParentFrame().findBaseFrame().getName() == "ground"
    u = rng.random()
    if on_ground and coordinate.getMotionType() != 1:  # 1 = Rotational
        return coordinate.getDefaultValue() + (2.0 * u - 1.0) * GROUND_TRANSLATION
    lo, hi = coordinate.getRangeMin(), coordinate.getRangeMax()
    return lo + (hi - lo) * u


def couple(model, q):
    """Sets each CoordinateCouplerConstraint's dependent coordinate to its function of the
    independent ones (Rajagopal2016's patellae; their ranges are ±99999)."""
    coordinates = model.getCoordinateSet()
    names = [coordinates.get(i).getName() for i in range(coordinates.getSize())]
    constraints = model.getConstraintSet()
    for i in range(constraints.getSize()):
        coupler = osim.CoordinateCouplerConstraint.safeDownCast(constraints.get(i))
        if coupler is None:
            continue
        independent = coupler.getIndependentCoordinateNames()
        x = osim.Vector(independent.getSize(), 0.0)
        for k in range(independent.getSize()):
            x.set(k, q[names.index(independent.get(k))])
        q[names.index(coupler.getDependentCoordinateName())] = coupler.getFunction().calcValue(x)


def golden(stem, path, rng):
    model = osim.Model(str(path))
    forces = model.getForceSet()
    for i in range(forces.getSize()):
        forces.get(i).set_appliesForce(False)
    state = model.initSystem()
    coordinates = model.getCoordinateSet()
    n = coordinates.getSize()
    indices = speed_indices(model, state)
    solver = osim.InverseDynamicsSolver(model)
    rows = []
    for k in range(STATES):
        q = [draw_value(coordinates.get(i), rng) for i in range(n)]
        couple(model, q)
        u = [0.0 if k == 0 else rng.gauss(0.0, SPEED_SD) for _ in range(n)]
        udot = [0.0 if k == 0 else rng.gauss(0.0, ACCELERATION_SD) for _ in range(n)]
        for i in range(n):
            coordinates.get(i).setValue(state, q[i], False)
            coordinates.get(i).setSpeedValue(state, u[i])
        model.realizeVelocity(state)
        q = [coordinates.get(i).getValue(state) for i in range(n)]  # a locked coordinate keeps its value
        u = [coordinates.get(i).getSpeedValue(state) for i in range(n)]
        simbody_udot = osim.Vector(state.getNU(), 0.0)
        for i in range(n):
            simbody_udot.set(indices[i], udot[i])
        tau = solver.solve(state, simbody_udot)
        for i in range(n):
            rows.append(f"{k},{coordinates.get(i).getName()},{q[i]!r},{u[i]!r},{udot[i]!r},{tau.get(indices[i])!r}")
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    out = OUT_DIR / f"{stem}.csv"
    out.write_text("state,coordinate,q,u,udot,generalized_force\n" + "\n".join(rows) + "\n")
    print(f"{out.relative_to(REPO)}: {STATES} states x {n} coordinates")


def main():
    rng = random.Random(SEED)
    for stem, path in MODELS.items():
        golden(stem, path, rng)


if __name__ == "__main__":
    main()
