#!/usr/bin/env python3
"""Wrap zoo: a small synthetic arm whose muscles wrap over what the bundled models do not have
(WrapSphere, WrapTorus, WrapEllipsoid by the midpoint and axial methods), and its OpenSim 4.6
geometry goldens.

    python3 oracle/gen_wrap_zoo.py

Builds, with the opensim Python API, ground --PinJoint "shoulder"--> arm --BallJoint "elbow"-->
forearm, and Thelen2003Muscles wrapping over
    elbow_sphere       WrapSphere on the arm at the elbow, all quadrants (never a mandatory wrap:
                       the segment changing the length least is chosen)
    elbow_sphere_back  WrapSphere at the elbow, quadrant -x (mandatory wraps; the anterior
                       muscles' points both lie on +x, and flexor_close's so near the sphere
                       that its path goes round the far side: OpenSim gives it a negative length)
    shoulder_cylinder  WrapCylinder at the shoulder, with elbow_sphere on one path (OpenSim's
                       passes over two wraps)
    elbow_ellipsoid    WrapEllipsoid at the elbow, turned, all quadrants, wrapped over by the
                       methods hybrid, midpoint and axial
    elbow_ellipsoid_back  WrapEllipsoid at the elbow, quadrant -x, by each method under anterior
                       muscles (c1 mirrored onto the back)
    elbow_torus        WrapTorus about the arm's axis at the elbow, all quadrants, and
    elbow_torus_x      another with quadrant +x: rings the muscles pass through
Writes (paths relative to the repository root, resolved from this file):
    fixtures/models/wrap_zoo.osim               the model as printed by OpenSim
    fixtures/golden/geometry/wrap_zoo/          coordinates.csv, poses.csv, bodies.csv,
                                                lengths.csv, muscle_coordinates.csv,
                                                moment_arms.csv, path_points.csv
in the format of ../shared/reference/README.md ("geometry/<stem>/"), computed on the model
loaded back from the printed file. Poses: rand_000 ... rand_039 (random.Random(20260407), one
draw per coordinate per pose in CoordinateSet order, uniform over the coordinate's range) and
elbow_e+000 ... elbow_e+140 (elbow_rz from 0 to 140 degrees in 10 degree steps, the other
coordinates at their defaults; elbow_rz's default, 1.2, keeps flexor_close off the far side,
whose negative length would make ScaleTool fail on the model). path_points.csv is
GeometryPath::getCurrentPath (the points, their ground locations and, on a wrap's second point,
the wrap length). Moment arms are not checked against -dL/dq: with wrapping they differ (see
the reference README).
Prints how many poses wrap each muscle over each object.
"""
import math
import random
import sys
from pathlib import Path

import opensim as osim

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gen_joint_zoo import (BODY_HEADER, add_body, apply_pose, body_rows, coord_list,  # noqa: E402
                           fmt, joints_between, printed, set_coordinates, vec, write_coordinates,
                           write_csv, write_muscle_coordinates)

REPO = Path(__file__).resolve().parent.parent
MODEL_FILE = REPO / "fixtures" / "models" / "wrap_zoo.osim"
OUT_DIR = REPO / "fixtures" / "golden" / "geometry" / "wrap_zoo"

SEED = 20260407
N_RANDOM = 40
ELBOW = (0.0, -0.3, 0.0)  # the elbow in the arm's frame (m)


def wrap_object(cls, name, translation, quadrant, **shape):
    w = getattr(osim, cls)()
    w.setName(name)
    w.set_translation(vec(*translation))
    w.set_quadrant(quadrant)
    for prop, value in shape.items():
        getattr(w, "set_" + prop)(value)
    return w


def muscle(model, name, points, wraps, method="hybrid"):
    m = osim.Thelen2003Muscle(name, 500.0, 0.1, 0.2, 0.0)
    for k, (frame, loc) in enumerate(points):
        m.addNewPathPoint("%s-P%d" % (name, k + 1), frame, vec(*loc))
    for w in wraps:
        m.updGeometryPath().addPathWrap(w)
    for k in range(m.getGeometryPath().getWrapSet().getSize()):
        m.updGeometryPath().updWrapSet().get(k).set_method(method)
    model.addForce(m)


def build_model():
    model = osim.Model()
    model.setName("wrap_zoo")
    ground = model.getGround()
    arm = add_body(model, "arm", 2.0)
    forearm = add_body(model, "forearm", 1.0)
    shoulder = osim.PinJoint("shoulder", ground, vec(0.0, 1.0, 0.0), vec(0.0, 0.0, 0.0),
                             arm, vec(0.0, 0.0, 0.0), vec(0.0, 0.0, 0.0))
    set_coordinates(shoulder, [("shoulder_flex", 0.2, 1.2)])
    elbow = osim.BallJoint("elbow", arm, vec(*ELBOW), vec(0.0, 0.0, 0.0),
                           forearm, vec(0.0, 0.0, 0.0), vec(0.0, 0.0, 0.0))
    set_coordinates(elbow, [("elbow_rx", 0.0, 0.4), ("elbow_ry", 0.0, 0.5), ("elbow_rz", 1.2, 1.2)])
    for j in (shoulder, elbow):
        model.addJoint(j)
    cs = model.getCoordinateSet()
    cs.get("elbow_rz").setRangeMin(0.0)
    cs.get("elbow_rz").setRangeMax(2.4)

    sphere = wrap_object("WrapSphere", "elbow_sphere", ELBOW, "all", radius=0.025)
    back = wrap_object("WrapSphere", "elbow_sphere_back", ELBOW, "-x", radius=0.035)
    cylinder = wrap_object("WrapCylinder", "shoulder_cylinder", (0.0, 1.0, 0.0), "all", radius=0.03, length=0.2)
    ellipsoid = wrap_object("WrapEllipsoid", "elbow_ellipsoid", ELBOW, "all", dimensions=vec(0.04, 0.025, 0.03))
    ellipsoid.set_xyz_body_rotation(vec(0.3, -0.2, 0.5))
    ellipsoid_back = wrap_object("WrapEllipsoid", "elbow_ellipsoid_back", ELBOW, "-x", dimensions=vec(0.03, 0.04, 0.035))
    ellipsoid_back.set_xyz_body_rotation(vec(-0.1, 0.1, 0.7))
    # Tori about the arm's axis (their z) at the elbow: a ring the muscles pass through.
    torus = wrap_object("WrapTorus", "elbow_torus", ELBOW, "all", inner_radius=0.012, outer_radius=0.05)
    torus.set_xyz_body_rotation(vec(math.pi / 2, 0.0, 0.0))
    torus_x = wrap_object("WrapTorus", "elbow_torus_x", ELBOW, "+x", inner_radius=0.01, outer_radius=0.045)
    torus_x.set_xyz_body_rotation(vec(math.pi / 2, 0.0, 0.0))
    for w in (sphere, back, ellipsoid, ellipsoid_back, torus, torus_x):
        arm.addWrapObject(w)
    ground.addWrapObject(cylinder)

    # Posterior, over the elbow sphere (all quadrants), three points on two bodies.
    muscle(model, "extensor", [(arm, (-0.03, -0.1, 0.005)), (arm, (-0.032, -0.22, 0.0)),
                               (forearm, (-0.02, -0.04, 0.01))], [sphere])
    # The same over the sphere with quadrant -x.
    muscle(model, "extensor_back", [(arm, (-0.03, -0.12, -0.01)), (forearm, (-0.025, -0.05, 0.0))],
           [back])
    # Anterior, over the sphere with quadrant -x: sent round the back when its line crosses.
    muscle(model, "flexor_back", [(arm, (0.03, -0.2, 0.0)), (forearm, (0.025, -0.05, 0.005))],
           [back])
    # Anterior and close to the sphere with quadrant -x: the tangent points facing the back
    # still lie in front, and the path goes round the far side (a negative length in OpenSim).
    muscle(model, "flexor_close", [(arm, (0.03, -0.275, 0.002)), (forearm, (0.03, -0.025, -0.002))], [back])
    # From ground over the shoulder cylinder and the elbow sphere.
    muscle(model, "long_head", [(ground, (-0.05, 1.06, 0.0)), (arm, (-0.04, -0.15, 0.0)),
                                (forearm, (-0.02, -0.03, -0.005))], [cylinder, sphere])
    # The ellipsoid by each method, posterior, and anterior over the one with quadrant -x.
    for method in ("hybrid", "midpoint", "axial"):
        muscle(model, "ellipsoid_" + method, [(arm, (-0.03, -0.12, 0.0)), (forearm, (-0.02, -0.04, 0.01))],
               [ellipsoid], method)
        muscle(model, "ellipsoid_back_" + method, [(arm, (0.02, -0.2, 0.0)), (forearm, (0.015, -0.06, 0.005))],
               [ellipsoid_back], method)
    # Through the rings: pushed against the tube's inner side as the elbow flexes.
    muscle(model, "through_ring", [(arm, (0.0, -0.15, 0.005)), (forearm, (0.0, -0.12, 0.0))], [torus])
    muscle(model, "through_ring_x", [(arm, (-0.01, -0.15, 0.0)), (forearm, (-0.03, -0.12, 0.01))], [torus_x])
    model.finalizeConnections()
    return model


def muscle_coordinates(model, m, tree):
    """{coordinate: 'chain'}: the joints between the bodies of the path points and wrap objects."""
    path = m.getGeometryPath()
    pps = path.getPathPointSet()
    bodies = [pps.get(i).getParentFrame().findBaseFrame().getName() for i in range(pps.getSize())]
    wraps = path.getWrapSet()
    for k in range(wraps.getSize()):
        bodies.append(wraps.get(k).getWrapObject().getFrame().findBaseFrame().getName())
    names = set()
    for j in joints_between(tree, bodies):
        names.update(j.get_coordinates(k).getName() for k in range(j.numCoordinates()))
    return {c.getName(): "chain" for c in coord_list(model) if c.getName() in names}


def pose_values(model):
    rng = random.Random(SEED)
    coords = coord_list(model)
    poses = []
    for p in range(N_RANDOM):
        poses.append(("rand_%03d" % p, {c.getName(): c.getRangeMin() + (c.getRangeMax() - c.getRangeMin()) * rng.random()
                                         for c in coords}))
    for degrees in range(0, 141, 10):
        poses.append(("elbow_e+%03d" % degrees, {"elbow_rz": math.radians(degrees)}))
    return poses


def path_rows(pid, m, s, counts):
    path = m.getGeometryPath().getCurrentPath(s)
    rows = []
    for i in range(path.getSize()):
        point = path.get(i)
        pwp = osim.PathWrapPoint.safeDownCast(point)
        wrap = pwp.getWrapObject().getName() if pwp is not None else ""
        length = fmt(pwp.getWrapLength(s)) if pwp is not None else ""
        if pwp is not None and pwp.getWrapLength(s) != 0.0:
            counts[(m.getName(), wrap)] = counts.get((m.getName(), wrap), 0) + 1
        g = point.getLocationInGround(s)
        rows.append([pid, m.getName(), str(i), point.getName(), point.getConcreteClassName(),
                     point.getParentFrame().findBaseFrame().getName()]
                    + [fmt(g.get(k)) for k in range(3)] + [wrap, length])
    return rows


def generate(model):
    s0 = model.initSystem()
    coords = coord_list(model)
    cs = model.getCoordinateSet()
    write_coordinates(model, s0, OUT_DIR)
    mlist, mcoords = write_muscle_coordinates(model, muscle_coordinates, OUT_DIR)
    blist = [model.getBodySet().get(i) for i in range(model.getBodySet().getSize())]
    pose_rows, len_rows, ma_rows, bodies, point_rows, counts = [], [], [], [], [], {}
    for pid, vals in pose_values(model):
        s = apply_pose(model, vals)
        pose_rows.append([pid] + [fmt(c.getValue(s)) for c in coords])
        len_rows.append([pid] + [fmt(m.getLength(s)) for m in mlist])
        for m, mc in zip(mlist, mcoords):
            ma_rows.extend([pid, m.getName(), cn, fmt(m.computeMomentArm(s, cs.get(cn)))] for cn in mc)
            point_rows.extend(path_rows(pid, m, s, counts))
        bodies.extend(body_rows(pid, blist, s))
    write_csv(OUT_DIR / "poses.csv", ["pose_id"] + [c.getName() for c in coords], pose_rows)
    write_csv(OUT_DIR / "lengths.csv", ["pose_id"] + [m.getName() for m in mlist], len_rows)
    write_csv(OUT_DIR / "moment_arms.csv", ["pose_id", "muscle", "coordinate", "moment_arm"], ma_rows)
    write_csv(OUT_DIR / "bodies.csv", BODY_HEADER, bodies)
    write_csv(OUT_DIR / "path_points.csv",
              ["pose_id", "muscle", "index", "point", "kind", "body", "gx", "gy", "gz", "wrap_object",
               "wrap_length"], point_rows)
    print("wrap_zoo: poses=%d muscles=%d moment_arm_rows=%d" % (len(pose_rows), len(mlist), len(ma_rows)))
    for (name, wrap), n in sorted(counts.items()):
        print("  %s wraps over %s in %d poses" % (name, wrap, n))


def main():
    generate(printed(build_model(), MODEL_FILE))


if __name__ == "__main__":
    main()
