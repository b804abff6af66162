#!/usr/bin/env python3
"""Moment arms through a PointConstraint on a published model: opensim-core's
ThoracoscapularShoulderModel (Seth et al. 2019: scapulothoracic joints, the acromioclavicular
PointConstraint `AC`, 33 muscles), copied unchanged to fixtures/models/.

fixtures/golden/shoulder_moment_arms.json, in the layout of constraint_assembly.json: the
coordinates, their default values, OpenSim 4.6's assembled default pose with the markers there,
and `poses` — the assembled default pose and two poses reached by moving the shoulder's
coordinates off their defaults and assembling — with each muscle's length and
`computeMomentArm` about every coordinate.

    python3 oracle/gen_shoulder_moment_arms.py OPENSIM_CORE_CHECKOUT
"""
import json
import shutil
import sys
from pathlib import Path

import opensim as osim

from gen_constraint_assembly import coordinates, default_golden, moment_arm_pose

REPO = Path(__file__).resolve().parent.parent
MODEL = REPO / "fixtures" / "models" / "ThoracoscapularShoulderModel.osim"
GOLDEN = REPO / "fixtures" / "golden" / "shoulder_moment_arms.json"
OFFSETS = [0.15, -0.2]


def main():
    shutil.copy(Path(sys.argv[1]) / "OpenSim" / "Tests" / "shared" / MODEL.name, MODEL)
    golden = default_golden(osim.Model(str(MODEL)))
    model = osim.Model(str(MODEL))
    state = model.initSystem()
    model.realizePosition(state)
    defaults = [c.getValue(state) for c in coordinates(model)]
    golden["poses"] = [moment_arm_pose(model, state)]
    for offset in OFFSETS:
        for k, (coordinate, value) in enumerate(zip(coordinates(model), defaults)):
            if not coordinate.getDefaultLocked():
                coordinate.setValue(state, value + offset * (1 + 0.3 * (k % 3)), False)
        model.assemble(state)
        model.realizePosition(state)
        golden["poses"].append(moment_arm_pose(model, state))
    GOLDEN.write_text(json.dumps({MODEL.name: golden}, indent=1) + "\n")
    print("written", MODEL.relative_to(REPO), GOLDEN.relative_to(REPO))


if __name__ == "__main__":
    main()
