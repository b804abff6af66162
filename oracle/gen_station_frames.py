#!/usr/bin/env python3
"""StationDefinedFrames (OpenSim 4.5+) as OpenSim 4.6 places them:

- fixtures/models/station_frames.osim: a thigh on a PinJoint to ground and a shank on a
  PinJoint whose parent frame is `knee_frame`, a StationDefinedFrame on the thigh (ab_axis -y,
  ab_x_ac_axis z; two of its stations on an offset frame of the thigh, the origin its own
  station); on the shank a second one (`ankle_frame`, default axes +x, +y) with an offset frame
  `ankle_offset` on it; markers on `knee_frame`, `ankle_offset` and the shank; a muscle with a
  path point on `knee_frame`.
- fixtures/golden/station_frames.json: each station-defined frame's transform in its body
  (rotation matrix rows, origin) and, at three poses, the markers in ground and the muscle's
  length.

    python3 oracle/gen_station_frames.py
"""
import json
from pathlib import Path

import opensim as osim

from model_parts import add_millard_muscle, write_model

REPO = Path(__file__).resolve().parent.parent
MODEL = REPO / "fixtures" / "models" / "station_frames.osim"
GOLDEN = REPO / "fixtures" / "golden" / "station_frames.json"
POSES = [[0.0, 0.0], [0.4, -0.9], [-0.3, -1.6]]


def v(x, y, z):
    return osim.Vec3(x, y, z)


def station(model, name, frame, location):
    s = osim.Station(frame, location)
    s.setName(name)
    model.addComponent(s)
    return s


def sdf(model, name, a, b, c, origin, ab_axis=None, ab_x_ac_axis=None):
    frame = osim.StationDefinedFrame()
    frame.setName(name)
    if ab_axis:
        frame.set_ab_axis(ab_axis)
    if ab_x_ac_axis:
        frame.set_ab_x_ac_axis(ab_x_ac_axis)
    frame.connectSocket_point_a(a)
    frame.connectSocket_point_b(b)
    frame.connectSocket_point_c(c)
    frame.connectSocket_origin_point(origin)
    model.addComponent(frame)
    return frame


def build():
    model = osim.Model()
    model.setName("station_frames")
    thigh = osim.Body("thigh", 8.0, v(0, -0.2, 0), osim.Inertia(0.1, 0.02, 0.1))
    shank = osim.Body("shank", 3.5, v(0, -0.18, 0), osim.Inertia(0.05, 0.005, 0.05))
    model.addBody(thigh)
    model.addBody(shank)
    model.addJoint(osim.PinJoint("hip", model.getGround(), v(0, 1.0, 0), v(0, 0, 0), thigh, v(0, 0, 0), v(0, 0, 0)))
    condyles = osim.PhysicalOffsetFrame("condyles", thigh, osim.Transform(osim.Rotation(0.2, v(0, 1, 0)), v(0.01, -0.39, 0.0)))
    thigh.addComponent(condyles)
    a = station(model, "greater_trochanter", thigh, v(0.02, -0.01, 0.06))
    b = station(model, "lateral_condyle", condyles, v(0.0, 0.0, 0.045))
    c = station(model, "medial_condyle", condyles, v(0.005, -0.002, -0.04))
    origin = station(model, "knee_centre", condyles, v(0.002, 0.003, 0.001))
    knee_frame = sdf(model, "knee_frame", a, b, c, origin, "-y", "z")
    d = station(model, "lateral_malleolus", shank, v(0.0, -0.4, 0.035))
    e = station(model, "medial_malleolus", shank, v(0.01, -0.39, -0.03))
    f = station(model, "tibial_tuberosity", shank, v(0.03, -0.05, 0.0))
    ankle_frame = sdf(model, "ankle_frame", d, e, f, d)
    ankle_offset = osim.PhysicalOffsetFrame("ankle_offset", ankle_frame, osim.Transform(osim.Rotation(-0.3, v(1, 0, 0)), v(0.02, 0.01, -0.015)))
    model.addComponent(ankle_offset)
    model.addJoint(osim.PinJoint("knee", knee_frame, v(0, 0, 0), v(0, 0, 0), shank, v(0, 0.01, 0), v(0, 0, 0)))
    model.addMarker(osim.Marker("knee_marker", knee_frame, v(0.03, 0.02, 0.01)))
    model.addMarker(osim.Marker("ankle_marker", ankle_offset, v(0.0, 0.01, 0.04)))
    model.addMarker(osim.Marker("shank_marker", shank, v(0.04, -0.2, 0.0)))
    points = [("origin", thigh, v(0.03, -0.2, 0.02)), ("patella", knee_frame, v(0.01, 0.05, 0.05)), ("insertion", shank, v(0.04, -0.08, 0.0))]
    add_millard_muscle(model, "vasti", 3000.0, 0.09, 0.2, 0.05, points)
    write_model(model, MODEL)


def main():
    build()
    model = osim.Model(str(MODEL))
    state = model.initSystem()
    frames = {}
    for name in ("knee_frame", "ankle_frame"):
        transform = osim.StationDefinedFrame.safeDownCast(model.getComponent(f"/{name}")).findTransformInBaseFrame()
        rotation = transform.R().asMat33()
        frames[name] = {"rotation": [[rotation.get(i, j) for j in range(3)] for i in range(3)], "origin": triple(transform.p())}
    coordinates = model.getCoordinateSet()
    poses = []
    for q in POSES:
        for k, value in enumerate(q):
            coordinates.get(k).setValue(state, value, False)
        model.realizePosition(state)
        markers = model.getMarkerSet()
        poses.append({
            "q": q,
            "markers_in_ground": {markers.get(m).getName(): triple(markers.get(m).getLocationInGround(state)) for m in range(markers.getSize())},
            "length": model.getMuscles().get("vasti").getLength(state),
        })
    golden = {"source": "OpenSim 4.6, oracle/gen_station_frames.py", "frames_in_body": frames, "poses": poses}
    GOLDEN.write_text(json.dumps(golden, indent=1) + "\n")
    print(json.dumps(frames))


def triple(p):
    return [p.get(0), p.get(1), p.get(2)]


if __name__ == "__main__":
    main()
