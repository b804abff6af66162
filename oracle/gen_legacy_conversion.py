#!/usr/bin/env python3
"""OpenSim 4.6's conversion of a 3.x model whose values have more digits than it keeps:

- fixtures/legacy/pendulum_leg_v30000_digits.osim: fixtures/legacy/pendulum_leg_v30000.osim with
  the knee's location_in_parent, orientation_in_parent and location, the thigh's inertia and the
  shank's mass center written with 9–11 significant digits, the shank's `inertia_zz` left out
  (OpenSim's conversion then takes 1) and the knee coordinate's motion_type written `Rotational`.
- fixtures/golden/legacy_conversion.json: what OpenSim 4.6 computes with it — the knee's offset
  frames and the bodies' inertias as it converted them (its C++ streams keep six significant
  digits), and at three poses the marker in ground, the vasti's path length and the inverse
  dynamics generalized forces (InverseDynamicsSolver, gravity only) for given speeds and
  accelerations.

    python3 oracle/gen_legacy_conversion.py
"""
import json
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
SOURCE = REPO / "fixtures" / "legacy" / "pendulum_leg_v30000.osim"
FIXTURE = REPO / "fixtures" / "legacy" / "pendulum_leg_v30000_digits.osim"
GOLDEN = REPO / "fixtures" / "golden" / "legacy_conversion.json"
EDITS = [
    ("<location_in_parent> 0 -0.4 0</location_in_parent>", "<location_in_parent> 0.00123456789 -0.40000004321 0.00087654321</location_in_parent>"),
    ("<orientation_in_parent> 0 0 0</orientation_in_parent>\n\t\t\t\t\t\t\t<location> 0 0.02 0</location>",
     "<orientation_in_parent> 0.0123456789 0 -0.0098765432</orientation_in_parent>\n\t\t\t\t\t\t\t<location> 0 0.0212345678 0</location>"),
    ("<inertia_xx>0.1339</inertia_xx>", "<inertia_xx>0.133912345</inertia_xx>"),
    ("<inertia_zz>0.0511</inertia_zz>\n", ""),
    ("<mass_center> 0 -0.18 0</mass_center>", "<mass_center> 0 -0.1801234567 0</mass_center>"),
]
POSES = [(0.3, -1.2), (-0.2, -0.3), (0.0, 0.1)]
SPEEDS = (0.7, -1.1)
ACCELERATIONS = (2.0, -3.0)


def main():
    text = SOURCE.read_text()
    for old, new in EDITS:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    knee = text.index('<CustomJoint name="knee">')
    motion = text.index("<motion_type>rotational</motion_type>", knee)
    text = text[:motion] + "<motion_type>Rotational</motion_type>" + text[motion + len("<motion_type>rotational</motion_type>"):]
    FIXTURE.write_text(text)
    model = osim.Model(str(FIXTURE))
    state = model.initSystem()
    joint = model.getJointSet().get("knee")
    frames = {}
    for side, frame in (("parent", joint.getParentFrame()), ("child", joint.getChildFrame())):
        offset = osim.PhysicalOffsetFrame.safeDownCast(frame)
        frames[side] = {"translation": vec(offset.get_translation()), "orientation": vec(offset.get_orientation())}
    inertias = {}
    for name in ("thigh", "shank"):
        body = model.getBodySet().get(name)
        moments, products = body.getInertia().getMoments(), body.getInertia().getProducts()
        inertias[name] = vec(moments) + vec(products)
    solver = osim.InverseDynamicsSolver(model)
    coordinates = model.getCoordinateSet()
    poses = []
    for q in POSES:
        for index, value in enumerate(q):
            coordinates.get(index).setValue(state, value, False)
            coordinates.get(index).setSpeedValue(state, SPEEDS[index])
        model.realizeDynamics(state)
        udot = osim.Vector(2, 0.0)
        for index, value in enumerate(ACCELERATIONS):
            udot.set(index, value)
        forces = solver.solve(state, udot)
        poses.append({
            "q": list(q),
            "u": list(SPEEDS),
            "udot": list(ACCELERATIONS),
            "markers_in_ground": {"knee_lateral": vec(model.getMarkerSet().get("knee_lateral").getLocationInGround(state))},
            "length": model.getMuscles().get("vasti").getLength(state),
            "generalized_forces": [forces.get(i) for i in range(forces.size())],
        })
    golden = {
        "source": "OpenSim 4.6 reading fixtures/legacy/pendulum_leg_v30000_digits.osim (oracle/gen_legacy_conversion.py)",
        "coordinates": [coordinates.get(i).getName() for i in range(coordinates.getSize())],
        "knee_frames": frames,
        "inertia": inertias,
        "poses": poses,
    }
    GOLDEN.write_text(json.dumps(golden, indent=1) + "\n")
    print(json.dumps(frames), json.dumps(inertias))


def vec(v):
    return [v.get(0), v.get(1), v.get(2)]


if __name__ == "__main__":
    main()
