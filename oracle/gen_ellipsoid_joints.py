#!/usr/bin/env python3
"""Joints that glide on an ellipsoid, as OpenSim 4.6 builds them:

- fixtures/models/ellipsoid_joints.osim: a thorax welded to ground (tilted), a scapula on a
  ScapulothoracicJoint (thoracic ellipsoid radii 0.07 0.15 0.08 m, winging axis origin
  (-0.05, -0.03) m and direction 0.3 rad, offset frames on both sides) and an arm on an
  EllipsoidJoint on the scapula (radii 0.03 0.04 0.05 m); markers on scapula and arm; a
  Millard muscle thorax → scapula → arm; masses and inertias on every body.
- fixtures/golden/ellipsoid_joints.json: at four poses (coordinate values, speeds and
  accelerations given) the markers in ground, the muscle's length, its moment arm about each
  coordinate (`computeMomentArm`) and the InverseDynamicsSolver's generalized forces (gravity and
  inertia; the muscle applies no force).
  The ellipsoid coordinates' speeds are Simbody's: the angular velocity of the moving frame in
  the joint's (for the scapula, quarter-turned) parent frame.

    python3 oracle/gen_ellipsoid_joints.py
"""
import json
from pathlib import Path

import opensim as osim

from model_parts import add_millard_muscle, write_model

REPO = Path(__file__).resolve().parent.parent
MODEL = REPO / "fixtures" / "models" / "ellipsoid_joints.osim"
GOLDEN = REPO / "fixtures" / "golden" / "ellipsoid_joints.json"
POSES = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.3, -0.2, 0.4, 0.15, -0.5, 0.35, 0.9],
    [-0.6, 0.5, -0.3, -0.25, 0.8, -0.7, -0.4],
    [1.1, 0.9, 0.2, 0.4, 0.2, 1.2, -1.3],
]


def vec3(x, y, z):
    return osim.Vec3(x, y, z)


def build():
    model = osim.Model()
    model.setName("ellipsoid_joints")
    thorax = osim.Body("thorax", 20.0, vec3(0.0, -0.1, 0.0), osim.Inertia(0.4, 0.3, 0.35, 0.01, -0.02, 0.015))
    scapula = osim.Body("scapula", 0.7, vec3(-0.03, -0.02, 0.01), osim.Inertia(0.002, 0.003, 0.0025, 0.0002, 0.0001, -0.0003))
    arm = osim.Body("arm", 2.1, vec3(0.01, -0.15, 0.005), osim.Inertia(0.012, 0.003, 0.011, 0.0004, -0.0002, 0.0001))
    for body in (thorax, scapula, arm):
        model.addBody(body)
    model.addJoint(osim.WeldJoint("ground_thorax", model.getGround(), vec3(0.0, 1.3, 0.0), vec3(0.1, 0.2, -0.05), thorax, osim.Vec3(0), osim.Vec3(0)))
    scapulothoracic = osim.ScapulothoracicJoint(
        "scapulothoracic", thorax, vec3(-0.02, 0.03, 0.06), vec3(0.05, -0.2, 0.1),
        scapula, vec3(-0.06, -0.04, -0.055), vec3(0.0, -0.87, -0.6),
        vec3(0.07, 0.15, 0.08), osim.Vec2(-0.05, -0.03), 0.3)
    names = ["scapula_abduction", "scapula_elevation", "scapula_upward_rot", "scapula_winging"]
    for index, name in enumerate(names):
        scapulothoracic.upd_coordinates(index).setName(name)
    model.addJoint(scapulothoracic)
    shoulder = osim.EllipsoidJoint("shoulder", scapula, vec3(-0.01, -0.03, 0.02), vec3(0.2, 0.1, 0.0), arm, vec3(0.0, 0.02, 0.0), vec3(0.0, 0.0, 0.3), vec3(0.03, 0.04, 0.05))
    for index, name in enumerate(["shoulder_x", "shoulder_y", "shoulder_z"]):
        shoulder.upd_coordinates(index).setName(name)
    model.addJoint(shoulder)
    model.addMarker(osim.Marker("scapula_tip", scapula, vec3(-0.08, 0.02, -0.03)))
    model.addMarker(osim.Marker("elbow", arm, vec3(0.01, -0.3, 0.02)))
    points = [("origin", thorax, vec3(0.04, 0.05, 0.08)), ("via", scapula, vec3(-0.02, 0.01, 0.03)), ("insertion", arm, vec3(0.02, -0.12, 0.01))]
    add_millard_muscle(model, "deltoid", 800.0, 0.1, 0.05, 0.2, points)
    write_model(model, MODEL)


def main():
    build()
    model = osim.Model(str(MODEL))
    model.getMuscles().get("deltoid").set_appliesForce(False)  # inverse dynamics of gravity and inertia only
    state = model.initSystem()
    coordinates = model.getCoordinateSet()
    names = [coordinates.get(i).getName() for i in range(coordinates.getSize())]
    solver = osim.InverseDynamicsSolver(model)
    muscle = model.getMuscles().get("deltoid")
    poses = []
    for index, q in enumerate(POSES):
        u = [0.4 * (k - 3) + 0.1 * index for k in range(len(q))]
        udot = [1.5 - 0.5 * k + 0.2 * index for k in range(len(q))]
        for k, name in enumerate(names):
            coordinates.get(name).setValue(state, q[k], False)
            coordinates.get(name).setSpeedValue(state, u[k])
        model.realizeDynamics(state)
        accelerations = osim.Vector(len(q), 0.0)
        for k, value in enumerate(udot):
            accelerations.set(k, value)
        forces = solver.solve(state, accelerations)
        markers = model.getMarkerSet()
        poses.append({
            "q": q, "u": u, "udot": udot,
            "markers_in_ground": {markers.get(m).getName(): triple(markers.get(m).getLocationInGround(state)) for m in range(markers.getSize())},
            "length": muscle.getLength(state),
            "moment_arms": {name: muscle.computeMomentArm(state, coordinates.get(name)) for name in names},
            "generalized_forces": [forces.get(k) for k in range(forces.size())],
        })
    golden = {"source": "OpenSim 4.6, oracle/gen_ellipsoid_joints.py", "coordinates": names, "poses": poses}
    GOLDEN.write_text(json.dumps(golden, indent=1) + "\n")
    print(f"{len(poses)} poses; lengths {[p['length'] for p in poses]}")


def triple(v):
    return [v.get(0), v.get(1), v.get(2)]


if __name__ == "__main__":
    main()
