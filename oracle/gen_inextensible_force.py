#!/usr/bin/env python3
"""Goldens for `HillMuscle::inextensible_tendon_active_fiber_force`: OpenSim 4.6's
`Muscle::calcInextensibleTendonActiveFiberForce(state, activation)`, the active fiber force with
the tendon held at its slack length that StaticOptimization (use_muscle_physiology) takes as a
muscle's force at full activation.

    python3 oracle/gen_inextensible_force.py     (from the repository root; needs `import opensim`, 4.6)

For each model of MODELS, at POSES seeded random states (random.Random(SEED), one stream over the
models in order): every unlocked coordinate's value uniform in its range (the gait2392 models) or,
for the DeGroote bench, each slider (= its muscle's path length) at L_ts + u L_opt with u uniform
in [-0.1, 1.9] (u < 0: a fiber along the tendon shorter than nothing); every unlocked
coordinate's speed uniform in [-w, w] with w = SPEED_SCALES[pose] (rad/s or m/s; the later
poses are fast enough to drive the fibers past their maximum shortening and lengthening
velocities). Values are set with `setValue(state, q, False)` (no assembly) and
`setSpeedValue`, then `model.realizeVelocity(state)`. For every muscle of MUSCLES and every
activation of ACTIVATIONS (and ACTIVATIONS_FIRST_POSE at pose 0 only: below the minimum
activation, which the Millard and Thelen muscles raise to their minimum) the row records
`getLength`, `getLengtheningSpeed` and `calcInextensibleTendonActiveFiberForce(state, a)`.
The full-range gait2392 poses put several fibers at or below their minimum length (force 0).

Writes fixtures/golden/muscle/inextensible/<model>.csv with columns
    model,muscle,activation,mt_length,lengthening_speed,force
(floats as Python repr). `calcInextensibleTendonActiveFiberForce` is exposed on `Muscle` by the
Python bindings (dispatched to the class's override, protected in DeGrooteFregly2016Muscle).
"""
import random
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
OUT_DIR = REPO / "fixtures" / "golden" / "muscle" / "inextensible"
SEED = 20260821
POSES = 10
SPEED_SCALES = {
    "gait2392": [1.0, 1.0, 2.0, 2.0, 4.0, 4.0, 8.0, 15.0, 30.0, 60.0],
    "degroote_bench": [0.05, 0.05, 0.1, 0.1, 0.2, 0.4, 0.8, 1.5, 3.0, 6.0],
}
ACTIVATIONS = [1.0, 0.5]
ACTIVATIONS_FIRST_POSE = [0.0]
KNEE_R = ["bifemlh_r", "bifemsh_r", "grac_r", "lat_gas_r", "med_gas_r", "rect_fem_r", "sar_r",
          "semimem_r", "semiten_r", "tfl_r", "vas_int_r", "vas_lat_r", "vas_med_r"]
GAIT2392_MUSCLES = KNEE_R + ["gem_r", "glut_med1_r", "soleus_r"]
MODELS = {
    "gait2392_millard2012muscle": (REPO / "models" / "gait2392_millard2012muscle.osim", "gait2392"),
    "gait2392_thelen2003muscle": (REPO / "models" / "gait2392_thelen2003muscle.osim", "gait2392"),
    "degroote_bench": (REPO / "fixtures" / "models" / "degroote_bench.osim", "degroote_bench"),
}
COLUMNS = ["model", "muscle", "activation", "mt_length", "lengthening_speed", "force"]


def fmt(x):
    """Shortest round-trip decimal of a double."""
    return repr(float(x))


def unlocked(model, state):
    coordinates = model.getCoordinateSet()
    return [coordinates.get(i) for i in range(coordinates.getSize())
            if not coordinates.get(i).getLocked(state)]


def set_gait2392_pose(model, state, rng):
    for coordinate in unlocked(model, state):
        coordinate.setValue(state, rng.uniform(coordinate.getRangeMin(), coordinate.getRangeMax()), False)


def set_bench_pose(model, state, rng):
    """Each slider at L_ts + u L_opt of the muscle it carries (the bench's coordinate is named
    <muscle>_length)."""
    muscles = model.getMuscles()
    for i in range(muscles.getSize()):
        muscle = muscles.get(i)
        coordinate = model.getCoordinateSet().get(muscle.getName() + "_length")
        length = muscle.getTendonSlackLength() + rng.uniform(-0.1, 1.9) * muscle.getOptimalFiberLength()
        coordinate.setValue(state, length, False)


def rows_for(stem, path, kind, rng):
    model = osim.Model(str(path))
    initial = model.initSystem()
    muscles = model.getMuscles()
    names = GAIT2392_MUSCLES if kind == "gait2392" else [muscles.get(i).getName() for i in range(muscles.getSize())]
    rows = []
    for pose in range(POSES):
        state = osim.State(initial)
        if kind == "gait2392":
            set_gait2392_pose(model, state, rng)
        else:
            set_bench_pose(model, state, rng)
        scale = SPEED_SCALES[kind][pose]
        for coordinate in unlocked(model, state):
            coordinate.setSpeedValue(state, rng.uniform(-scale, scale))
        model.realizeVelocity(state)
        activations = ACTIVATIONS + (ACTIVATIONS_FIRST_POSE if pose == 0 else [])
        for name in names:
            muscle = muscles.get(name)
            for activation in activations:
                force = muscle.calcInextensibleTendonActiveFiberForce(state, activation)
                rows.append([stem, name, fmt(activation), fmt(muscle.getLength(state)),
                             fmt(muscle.getLengtheningSpeed(state)), fmt(force)])
    return rows


def main():
    osim.Logger.removeFileSink()
    osim.Logger.setLevelString("error")
    rng = random.Random(SEED)
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    for stem, (path, kind) in MODELS.items():
        rows = rows_for(stem, path, kind, rng)
        out = OUT_DIR / f"{stem}.csv"
        out.write_text(",".join(COLUMNS) + "\n" + "".join(",".join(row) + "\n" for row in rows))
        zero = sum(1 for row in rows if float(row[-1]) == 0.0)
        print(f"{out.relative_to(REPO)}: {len(rows)} rows, {zero} with force 0")
    print(osim.GetVersionAndDate())


if __name__ == "__main__":
    main()
