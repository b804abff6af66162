"""Prints, as JSON, the pose of a child body in its parent body computed by OpenSim 4.6 for
one coordinate value, every other coordinate at its default (used by `cargo xtask validate` to
check a swapped knee joint).

usage: python3 oracle/knee_pose.py MODEL.osim PARENT_BODY CHILD_BODY COORDINATE VALUE_RAD
"""
import json
import sys

import opensim


def main():
    model_file, parent, child, coordinate, value = sys.argv[1:6]
    model = opensim.Model(model_file)
    state = model.initSystem()
    model.getCoordinateSet().get(coordinate).setValue(state, float(value), False)
    model.realizePosition(state)
    bodies = model.getBodySet()
    pose = bodies.get(child).findTransformBetween(state, bodies.get(parent))
    rotation = pose.R()
    translation = pose.p()
    print(json.dumps({
        "rotation": [[rotation.get(i, j) for j in range(3)] for i in range(3)],
        "translation": [translation.get(i) for i in range(3)],
    }))


if __name__ == "__main__":
    main()
