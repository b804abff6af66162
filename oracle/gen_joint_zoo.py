#!/usr/bin/env python3
"""Joint zoo: a small synthetic model with every joint class OpenSim offers besides those of the
standard models, and its OpenSim 4.6 geometry goldens.

    python3 oracle/gen_joint_zoo.py

Builds, with the opensim Python API, a model with
    ground --FreeJoint--> pelvis --BallJoint--> thigh --CustomJoint--> shank
           --GimbalJoint--> foot --PinJoint--> toes
    pelvis --PlanarJoint--> arm --SliderJoint--> forearm
where the CustomJoint ("knee") turns about an oblique unnormalised axis (0.3, 0.9, 0.1), about a
second axis through LinearFunction(0.5, 0.1) of another coordinate and about a third by a
constant angle, and translates along two axes through SimmSplines of its first coordinate. Most
joints sit on PhysicalOffsetFrames translated and rotated on both the parent and the child side.
Six markers (one on a joint's offset frame) and four Thelen2003Muscles whose paths cross several
joints: one with a point on an offset frame, one with a MovingPathPoint (x: SimmSpline, y and z:
LinearFunctions of knee_flex; OpenSim 4.6 requires one coordinate for all three), one with a
ConditionalPathPoint, one from ground across the FreeJoint. No wrap objects, no constraints.

Writes (paths relative to the repository root, resolved from this file):
    fixtures/models/joint_zoo.osim               the model as printed by OpenSim
    fixtures/golden/geometry/joint_zoo/          coordinates.csv, poses.csv, bodies.csv,
                                                 markers.csv, lengths.csv,
                                                 muscle_coordinates.csv, moment_arms.csv
in the format of ../shared/reference/README.md ("geometry/<stem>/"), computed on the model
loaded back from the printed file. Poses: rand_000 ... rand_039 (random.Random(20261121), one
draw per coordinate per pose in CoordinateSet order, uniform over the coordinate's range, the
FreeJoint's coordinates included) and `default` (every coordinate at its default value).
coordinates.csv's sampling_rule is `uniform_range` for every coordinate (no free-body rule here).
Also checks that computeMomentArm = -dL/du (central differences, h = 1e-6) within 1e-6 for
every (muscle, coordinate) pair and pose, and prints the worst difference; u is the
coordinate's Simbody generalized speed: q itself except for the rotations of the BallJoint and
FreeJoint, whose speeds are the angular velocity in the parent frame (see step_along_speed).
Exits non-zero if the check fails.
"""
import math
import random
import sys
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
MODEL_FILE = REPO / "fixtures" / "models" / "joint_zoo.osim"
OUT_DIR = REPO / "fixtures" / "golden" / "geometry" / "joint_zoo"

SEED = 20261121
N_RANDOM = 40
ROT = 1.2    # rad, every rotational coordinate: [-1.2, 1.2]
TRANS = 0.1  # m, every translational coordinate: [-0.1, 0.1]
FD_H = 1e-6
FD_TOLERANCE = 1e-6


# ---------------------------------------------------------------------------------------
# Building the model
# ---------------------------------------------------------------------------------------
def vec(x, y, z):
    return osim.Vec3(x, y, z)


def spline(xs, ys):
    f = osim.SimmSpline()
    for x, y in zip(xs, ys):
        f.addPoint(x, y)
    return f


def add_body(model, name, mass=1.0):
    b = osim.Body(name, mass, vec(0, 0, 0), osim.Inertia(0.01, 0.01, 0.01))
    model.addBody(b)
    return b


def set_coordinates(joint, specs):
    """specs: [(name, default, half range)] in the joint's coordinate order; the range is
    [-half, half] (ROT rad or TRANS m)."""
    for k, (name, default, half) in enumerate(specs):
        c = joint.upd_coordinates(k)
        c.setName(name)
        c.setRangeMin(-half)
        c.setRangeMax(half)
        c.setDefaultValue(default)


def knee_transform():
    """Oblique, coupled CustomJoint: rotations about (0.3, 0.9, 0.1) by knee_flex, about
    (1, 0, 0.2) by 0.5 knee_tilt + 0.1, about (0.1, 0.2, 1) by a constant 0.15; translations
    along x and y by SimmSplines of knee_flex, along z by nothing."""
    st = osim.SpatialTransform()
    axes = [
        ("knee_flex", (0.3, 0.9, 0.1), osim.LinearFunction(1.0, 0.0)),
        ("knee_tilt", (1.0, 0.0, 0.2), osim.LinearFunction(0.5, 0.1)),
        (None, (0.1, 0.2, 1.0), osim.Constant(0.15)),
        ("knee_flex", (1.0, 0.0, 0.0),
         spline([-1.3, -0.8, -0.3, 0.2, 0.7, 1.3], [-0.012, -0.006, 0.0, 0.003, 0.009, 0.02])),
        ("knee_flex", (0.0, 1.0, 0.0),
         spline([-1.3, -0.6, 0.0, 0.6, 1.3], [0.01, -0.004, -0.008, -0.003, 0.012])),
        (None, (0.0, 0.0, 1.0), osim.Constant(0.0)),
    ]
    for k, (coord, axis, function) in enumerate(axes):
        ta = st.updTransformAxis(k)
        if coord is not None:
            names = osim.ArrayStr()
            names.append(coord)
            ta.setCoordinateNames(names)
        ta.setAxis(vec(*axis))
        ta.set_function(function)
    return st


def build_model():
    model = osim.Model()
    model.setName("joint_zoo")
    ground = model.getGround()
    pelvis = add_body(model, "pelvis", 10.0)
    thigh = add_body(model, "thigh", 5.0)
    shank = add_body(model, "shank", 3.0)
    foot = add_body(model, "foot", 1.0)
    toes = add_body(model, "toes", 0.2)
    arm = add_body(model, "arm", 2.0)
    forearm = add_body(model, "forearm", 1.0)

    # (name, parent, loc, orient, child, loc, orient): the constructor adds offset frames
    # "<parent>_offset" and "<child>_offset" owned by the joint.
    free = osim.FreeJoint("ground_pelvis", ground, vec(0.1, 0.9, -0.05), vec(0.05, 0.3, -0.1),
                          pelvis, vec(0.02, -0.03, 0.01), vec(0.1, 0.0, 0.2))
    set_coordinates(free, [("pelvis_rx", 0.05, ROT), ("pelvis_ry", -0.1, ROT),
                           ("pelvis_rz", 0.2, ROT), ("pelvis_tx", 0.03, TRANS),
                           ("pelvis_ty", 0.05, TRANS), ("pelvis_tz", -0.02, TRANS)])
    hip = osim.BallJoint("hip", pelvis, vec(-0.05, -0.08, 0.09), vec(0.2, -0.1, 0.15),
                         thigh, vec(0.01, 0.19, -0.01), vec(-0.1, 0.25, 0.05))
    set_coordinates(hip, [("hip_rx", 0.2, ROT), ("hip_ry", 0.0, ROT), ("hip_rz", -0.1, ROT)])
    knee = osim.CustomJoint("knee", thigh, vec(0.0, -0.21, 0.01), vec(0.1, 0.05, -0.2),
                            shank, vec(0.02, 0.2, 0.0), vec(0.05, -0.15, 0.1), knee_transform())
    knee.finalizeFromProperties()  # a CustomJoint makes its coordinates from its SpatialTransform
    set_coordinates(knee, [("knee_flex", 0.3, ROT), ("knee_tilt", 0.0, ROT)])
    ankle = osim.GimbalJoint("ankle", shank, vec(0.0, -0.22, 0.0), vec(0.0, 0.0, 0.0),
                             foot, vec(-0.04, 0.03, 0.0), vec(0.0, 0.0, 0.0))
    set_coordinates(ankle, [("ankle_rx", 0.0, ROT), ("ankle_ry", -0.1, ROT), ("ankle_rz", 0.0, ROT)])
    toe = osim.PinJoint("toe", foot, vec(0.12, -0.02, 0.0), vec(0.0, 0.3, 0.0),
                        toes, vec(-0.02, 0.0, 0.0), vec(0.2, 0.0, 0.0))
    set_coordinates(toe, [("toe_flex", 0.0, ROT)])
    shoulder = osim.PlanarJoint("shoulder", pelvis, vec(0.0, 0.25, 0.15), vec(1.2, 0.0, 0.3),
                                arm, vec(0.0, 0.12, 0.0), vec(0.0, 0.0, -0.2))
    set_coordinates(shoulder, [("shoulder_rot", 0.1, ROT), ("shoulder_tx", 0.0, TRANS),
                               ("shoulder_ty", 0.0, TRANS)])
    elbow = osim.SliderJoint("elbow", arm, vec(0.0, -0.15, 0.0), vec(0.0, 0.0, -1.4),
                             forearm, vec(0.0, 0.1, 0.0), vec(0.1, 0.2, 0.0))
    set_coordinates(elbow, [("elbow_slide", 0.02, TRANS)])
    for j in (free, hip, knee, ankle, toe, shoulder, elbow):
        model.addJoint(j)

    coords = model.getCoordinateSet()
    hip_pelvis_offset = hip.get_frames(0)    # /jointset/hip/pelvis_offset
    knee_shank_offset = knee.get_frames(1)   # /jointset/knee/shank_offset

    for name, frame, loc in [("PELV", pelvis, (0.05, 0.05, 0.1)),
                             ("THI", thigh, (0.06, -0.1, 0.05)),
                             ("KNEE_OFF", knee_shank_offset, (0.04, 0.01, 0.05)),
                             ("FOOT", foot, (0.08, 0.01, -0.03)),
                             ("TOE", toes, (0.03, 0.0, 0.02)),
                             ("HAND", forearm, (0.0, -0.12, 0.02))]:
        model.addMarker(osim.Marker(name, frame, vec(*loc)))

    # 1: pelvis (point on the hip's parent offset frame) -> thigh -> shank: Ball + Custom.
    m = osim.Thelen2003Muscle("hip_knee", 800.0, 0.12, 0.2, 0.0)
    m.addNewPathPoint("hip_knee-P1", hip_pelvis_offset, vec(0.03, 0.04, 0.0))
    m.addNewPathPoint("hip_knee-P2", thigh, vec(0.03, -0.05, 0.03))
    m.addNewPathPoint("hip_knee-P3", shank, vec(0.03, 0.12, 0.02))
    model.addForce(m)

    # 2: thigh -> shank (MovingPathPoint) -> foot -> toes: Custom + Gimbal + Pin; the moving
    # point's neighbours are on other bodies.
    m = osim.Thelen2003Muscle("knee_toe", 600.0, 0.08, 0.3, 0.1)
    m.addNewPathPoint("knee_toe-P1", thigh, vec(-0.02, -0.1, -0.02))
    mp = osim.MovingPathPoint()
    mp.setName("knee_toe-P2")
    mp.setParentFrame(shank)
    mp.set_x_location(spline([-1.3, -0.5, 0.0, 0.5, 1.3], [-0.05, -0.035, -0.03, -0.032, -0.045]))
    mp.set_y_location(osim.LinearFunction(0.02, 0.05))
    mp.set_z_location(osim.LinearFunction(0.01, 0.02))
    mp.setXCoordinate(coords.get("knee_flex"))
    mp.setYCoordinate(coords.get("knee_flex"))
    mp.setZCoordinate(coords.get("knee_flex"))
    m.updGeometryPath().updPathPointSet().adoptAndAppend(mp)
    m.addNewPathPoint("knee_toe-P3", foot, vec(-0.05, 0.02, 0.01))
    m.addNewPathPoint("knee_toe-P4", toes, vec(0.03, 0.0, 0.0))
    model.addForce(m)

    # 3: pelvis -> arm (ConditionalPathPoint, active for shoulder_rot in [-0.4, 0.9]) -> arm
    # -> forearm: Planar + Slider.
    m = osim.Thelen2003Muscle("arm_muscle", 400.0, 0.1, 0.15, 0.0)
    m.addNewPathPoint("arm_muscle-P1", pelvis, vec(0.02, 0.15, 0.05))
    cp = osim.ConditionalPathPoint()
    cp.setName("arm_muscle-P2")
    cp.setParentFrame(arm)
    cp.set_location(vec(0.03, 0.0, 0.02))
    cp.setCoordinate(coords.get("shoulder_rot"))
    cp.setRangeMin(-0.4)
    cp.setRangeMax(0.9)
    m.updGeometryPath().updPathPointSet().adoptAndAppend(cp)
    m.addNewPathPoint("arm_muscle-P3", arm, vec(0.02, -0.08, 0.0))
    m.addNewPathPoint("arm_muscle-P4", forearm, vec(0.01, 0.05, 0.02))
    model.addForce(m)

    # 4: ground -> pelvis -> thigh: Free + Ball.
    m = osim.Thelen2003Muscle("ground_thigh", 1000.0, 0.1, 0.4, 0.05)
    m.addNewPathPoint("ground_thigh-P1", ground, vec(0.2, 0.8, 0.1))
    m.addNewPathPoint("ground_thigh-P2", pelvis, vec(0.05, 0.0, 0.06))
    m.addNewPathPoint("ground_thigh-P3", thigh, vec(0.04, 0.1, 0.04))
    model.addForce(m)

    model.finalizeConnections()
    return model


# ---------------------------------------------------------------------------------------
# Goldens (helpers follow ../shared/tools/oracle/oracle_common.py; this model has no
# constraints, so the coupler parts are left out)
# ---------------------------------------------------------------------------------------
def fmt(x):
    """Python repr: the shortest string that parses back to the identical double."""
    x = float(x)
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


def write_csv(path, header, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="\n") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(r) + "\n")


def coord_list(model):
    cs = model.getCoordinateSet()
    return [cs.get(i) for i in range(cs.getSize())]


def motion_type_name(c):
    mt = c.getMotionType()
    return {1: "rotational", 2: "translational", 3: "coupled"}.get(int(mt), str(mt))


def is_translational(c):
    """'coupled' coordinates count as rotational if they drive any rotation axis of their
    CustomJoint, else as translational."""
    mt = motion_type_name(c)
    if mt in ("translational", "rotational"):
        return mt == "translational"
    cj = osim.CustomJoint.safeDownCast(c.getJoint())
    if cj is None:
        return False
    st = cj.getSpatialTransform()

    def drives(k):
        names = st.getTransformAxis(k).getCoordinateNamesInArray()
        return any(names.get(i) == c.getName() for i in range(names.getSize()))

    if any(drives(k) for k in range(0, 3)):
        return False
    return any(drives(k) for k in range(3, 6))


def body_tree(model):
    """child body name -> (joint, parent body name)."""
    tree = {}
    js = model.getJointSet()
    for i in range(js.getSize()):
        j = js.get(i)
        tree[j.getChildFrame().findBaseFrame().getName()] = (j, j.getParentFrame().findBaseFrame().getName())
    return tree


def ancestors(tree, body):
    out = [body]
    while body in tree:
        body = tree[body][1]
        out.append(body)
    return out


def joints_between(tree, bodies):
    """Joints on the tree paths joining all given bodies."""
    bodies = list(dict.fromkeys(bodies))
    if len(bodies) <= 1:
        return []
    anc = [ancestors(tree, b) for b in bodies]
    common = set(anc[0])
    for a in anc[1:]:
        common &= set(a)
    lca = next(b for b in anc[0] if b in common)
    joints = {}
    for a in anc:
        for b in a:
            if b == lca:
                break
            joints[tree[b][0].getName()] = tree[b][0]
    return list(joints.values())


REASON_ORDER = ("chain", "moving_point", "conditional_point")


def muscle_coordinates(model, muscle, tree):
    """{coordinate: '+'-joined reasons} in CoordinateSet order (see the README: chain,
    moving_point, conditional_point)."""
    pps = muscle.getGeometryPath().getPathPointSet()
    bodies, out = [], {}
    for i in range(pps.getSize()):
        pp = pps.get(i)
        bodies.append(pp.getParentFrame().findBaseFrame().getName())
        cp = osim.ConditionalPathPoint.safeDownCast(pp)
        if cp is not None and cp.hasCoordinate():
            out.setdefault(cp.getCoordinate().getName(), set()).add("conditional_point")
        mp = osim.MovingPathPoint.safeDownCast(pp)
        if mp is not None:
            for has, get in ((mp.hasXCoordinate, mp.getXCoordinate),
                             (mp.hasYCoordinate, mp.getYCoordinate),
                             (mp.hasZCoordinate, mp.getZCoordinate)):
                if has():
                    out.setdefault(get().getName(), set()).add("moving_point")
    assert muscle.getGeometryPath().getWrapSet().getSize() == 0
    for j in joints_between(tree, bodies):
        for k in range(j.numCoordinates()):
            out.setdefault(j.get_coordinates(k).getName(), set()).add("chain")
    return {c.getName(): "+".join(r for r in REASON_ORDER if r in out[c.getName()])
            for c in coord_list(model) if c.getName() in out}


def pose_values(model):
    """[(pose id, {coordinate: value})]: N_RANDOM random poses, then `default` (no value set)."""
    rng = random.Random(SEED)
    coords = coord_list(model)
    poses = []
    for p in range(N_RANDOM):
        vals = {}
        for c in coords:
            u = rng.random()
            lo, hi = c.getRangeMin(), c.getRangeMax()
            vals[c.getName()] = lo + (hi - lo) * u
        poses.append(("rand_%03d" % p, vals))
    poses.append(("default", {}))
    return poses


def apply_pose(model, values):
    """Fresh default state, setValue(s, v, False) per coordinate, realizePosition."""
    s = model.initializeState()
    cs = model.getCoordinateSet()
    for name, v in values.items():
        cs.get(name).setValue(s, float(v), False)
    model.realizePosition(s)
    return s


# OpenSim's computeMomentArm is the generalized force of a unit tension on the coordinate's
# *mobility* (Simbody generalized speed u), not -dL/dq. u = qdot for every joint here except
# the rotations of BallJoint and FreeJoint, whose u is the angular velocity of the child frame
# in the parent frame, expressed in the parent frame (Simbody's RBNodeBall/RBNodeFree; OpenSim
# switches them to X-Y-Z body-fixed Euler angles for q). For those the finite difference is
# taken along u: the joint's rotation is turned by +-h about the parent frame's axis and the
# three angles are recomputed.
SPEED_IS_ANGULAR_VELOCITY = ("BallJoint", "FreeJoint")


def rotation_about(k, angle):
    c, s = math.cos(angle), math.sin(angle)
    i, j = (k + 1) % 3, (k + 2) % 3
    r = [[1.0 if a == b else 0.0 for b in range(3)] for a in range(3)]
    r[i][i], r[i][j], r[j][i], r[j][j] = c, -s, s, c
    return r


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def body_fixed_xyz(q):
    return matmul(matmul(rotation_about(0, q[0]), rotation_about(1, q[1])), rotation_about(2, q[2]))


def to_body_fixed_xyz(r):
    return [math.atan2(-r[1][2], r[2][2]), math.asin(max(-1.0, min(1.0, r[0][2]))),
            math.atan2(-r[0][1], r[0][0])]


def step_along_speed(model, s, coordinate, h):
    """Coordinate values {name: value} after a step h of the coordinate's generalized speed."""
    c = model.getCoordinateSet().get(coordinate)
    joint = c.getJoint()
    names = [joint.get_coordinates(k).getName() for k in range(joint.numCoordinates())]
    k = names.index(coordinate)
    if joint.getConcreteClassName() not in SPEED_IS_ANGULAR_VELOCITY or k >= 3:
        return {coordinate: c.getValue(s) + h}
    cs = model.getCoordinateSet()
    q = [cs.get(n).getValue(s) for n in names[:3]]
    turned = to_body_fixed_xyz(matmul(rotation_about(k, h), body_fixed_xyz(q)))
    return dict(zip(names[:3], turned))


def fd_moment_arm(model, s, muscle, coordinate, along_speed, h=FD_H):
    """-dL/dq (along_speed False) or -dL/du (True) by central differences on copies of the
    posed state."""
    def length(step):
        st = osim.State(s)
        if along_speed:
            values = step_along_speed(model, s, coordinate, step)
        else:
            values = {coordinate: model.getCoordinateSet().get(coordinate).getValue(s) + step}
        for name, value in values.items():
            model.getCoordinateSet().get(name).setValue(st, value, False)
        model.realizePosition(st)
        return model.getMuscles().get(muscle).getLength(st)

    return -(length(h) - length(-h)) / (2 * h)


def write_coordinates(model, s0, out_dir):
    """coordinates.csv: every coordinate sampled uniformly over its range."""
    rows = []
    for c in coord_list(model):
        rows.append([c.getName(), c.getJoint().getName(), motion_type_name(c),
                     "translational" if is_translational(c) else "rotational",
                     fmt(c.getRangeMin()), fmt(c.getRangeMax()), fmt(c.getDefaultValue()),
                     str(int(c.getDefaultLocked())), str(int(c.getDefaultClamped())),
                     str(int(c.isDependent(s0))), "", "uniform_range"])
    write_csv(out_dir / "coordinates.csv",
              ["coordinate", "joint", "motion_type", "unit_kind", "range_min", "range_max",
               "default_value", "locked", "clamped", "dependent", "independent_coordinates",
               "sampling_rule"], rows)


BODY_HEADER = ["pose_id", "body", "px", "py", "pz", "r11", "r12", "r13", "r21", "r22", "r23",
               "r31", "r32", "r33"]


def body_rows(pid, bodies, s):
    """bodies.csv rows: each body's transform in ground at the posed state."""
    rows = []
    for b in bodies:
        T = b.getTransformInGround(s)
        p, R = T.p(), T.R()
        rows.append([pid, b.getName()] + [fmt(p.get(i)) for i in range(3)]
                    + [fmt(R.get(i, j)) for i in range(3) for j in range(3)])
    return rows


def write_muscle_coordinates(model, spanned, out_dir):
    """muscle_coordinates.csv from `spanned(model, muscle, tree)` ({coordinate: reason});
    returns the muscles and their coordinates."""
    muscles = model.getMuscles()
    mlist = [muscles.get(i) for i in range(muscles.getSize())]
    tree = body_tree(model)
    mcoords = [spanned(model, m, tree) for m in mlist]
    write_csv(out_dir / "muscle_coordinates.csv", ["muscle", "coordinate", "reason"],
              [[m.getName(), cn, reason] for m, mc in zip(mlist, mcoords) for cn, reason in mc.items()])
    return mlist, mcoords


def generate(model):
    s0 = model.initSystem()
    coords = coord_list(model)
    cnames = [c.getName() for c in coords]
    cs = model.getCoordinateSet()
    write_coordinates(model, s0, OUT_DIR)
    mlist, mcoords = write_muscle_coordinates(model, muscle_coordinates, OUT_DIR)

    blist = [model.getBodySet().get(i) for i in range(model.getBodySet().getSize())]
    mklist = [model.getMarkerSet().get(i) for i in range(model.getMarkerSet().getSize())]
    pose_rows, len_rows, ma_rows, bodies, marker_rows = [], [], [], [], []
    n_zero_skipped = 0
    worst_fd = (0.0, "")
    worst_q = (0.0, "")
    for pid, vals in pose_values(model):
        s = apply_pose(model, vals)
        pose_rows.append([pid] + [fmt(c.getValue(s)) for c in coords])
        len_rows.append([pid] + [fmt(m.getLength(s)) for m in mlist])
        for m, mc in zip(mlist, mcoords):
            for cn in mc:
                ma = m.computeMomentArm(s, cs.get(cn))
                fd = fd_moment_arm(model, s, m.getName(), cn, along_speed=True)
                if abs(ma - fd) >= worst_fd[0]:
                    worst_fd = (abs(ma - fd), "%s / %s about %s (ma %r, fd %r)" % (pid, m.getName(), cn, ma, fd))
                if step_along_speed(model, s, cn, 1.0).keys() != {cn}:
                    fd_q = fd_moment_arm(model, s, m.getName(), cn, along_speed=False)
                    if abs(ma - fd_q) >= worst_q[0]:
                        worst_q = (abs(ma - fd_q), "%s / %s about %s" % (pid, m.getName(), cn))
                if ma == 0.0:
                    n_zero_skipped += 1
                    continue
                ma_rows.append([pid, m.getName(), cn, fmt(ma)])
        bodies.extend(body_rows(pid, blist, s))
        for mk in mklist:
            x = mk.getLocationInGround(s)
            marker_rows.append([pid, mk.getName()] + [fmt(x.get(i)) for i in range(3)])

    write_csv(OUT_DIR / "poses.csv", ["pose_id"] + cnames, pose_rows)
    write_csv(OUT_DIR / "lengths.csv", ["pose_id"] + [m.getName() for m in mlist], len_rows)
    write_csv(OUT_DIR / "moment_arms.csv", ["pose_id", "muscle", "coordinate", "moment_arm"], ma_rows)
    write_csv(OUT_DIR / "bodies.csv", BODY_HEADER, bodies)
    write_csv(OUT_DIR / "markers.csv", ["pose_id", "marker", "x", "y", "z"], marker_rows)
    print("joint_zoo: poses=%d muscles=%d pairs=%d ma_rows=%d zero_skipped=%d bodies=%d markers=%d"
          % (len(pose_rows), len(mlist), sum(len(mc) for mc in mcoords), len(ma_rows),
             n_zero_skipped, len(blist), len(mklist)))
    print("worst |computeMomentArm + dL/du| (h=%g; u = qdot except Ball/Free rotations): %.3e at %s"
          % (FD_H, worst_fd[0], worst_fd[1]))
    print("(for comparison, Ball/Free rotations: worst |computeMomentArm + dL/dq| = %.3e at %s)"
          % worst_q)
    return worst_fd[0]


def printed(model, path):
    """`model` printed to `path` (OpenSim's log quietened) and loaded back: goldens are computed
    on the model as printed."""
    print("OpenSim", osim.GetVersionAndDate(), flush=True)
    osim.Logger.removeFileSink()
    osim.Logger.setLevelString("error")
    path.parent.mkdir(parents=True, exist_ok=True)
    model.printToXML(str(path))
    return osim.Model(str(path))


def main():
    worst = generate(printed(build_model(), MODEL_FILE))
    if worst > FD_TOLERANCE:
        sys.exit("moment arms disagree with -dL/dq by %.3e > %g" % (worst, FD_TOLERANCE))


if __name__ == "__main__":
    main()
