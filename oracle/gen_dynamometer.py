#!/usr/bin/env python3
"""Extended dynamometer set-up goldens (thesis ch. 5): a seated leg (femur, tibia, foot) whose
shank is strapped to a dynamometer crank with a 6-D load cell at the crank's origin.

    python3 oracle/gen_dynamometer.py [case ...]

Cases: `spatial` (knee and dynamometer axes misaligned, moving, 0–1 s at 200 Hz) and `planar`
(axes aligned, isometric, the knee axis on the crank line, 0–2 s at 100 Hz). Each writes the model
fixtures/models/dynamometer_<case>.osim (ground -CustomJoint hip- femur -PinJoint knee_r- tibia
-PinJoint ankle_r- foot; ground -PinJoint crank_joint- crank) and fixtures/golden/dynamometer/<case>/:
coordinates.mot, loadcell.mot/.xml (the load cell's wrench on the crank, crank frame, at its origin),
pad.mot/.xml (the crank's load on the tibia, ground), pad_truth.csv, inverse_dynamics.sto (OpenSim
4.6's InverseDynamicsTool with pad.xml; knee_angle_r_moment is the truth M3D) and README.md (details).
The load cell is the crank's Newton–Euler on the InverseDynamicsTool's own quintic GCV splines of the
coordinates. Fatal self-checks: ID with load cell + pad wrench on the crank leaves crank_angle's
generalized force ≈ 0, and all six of a 6-mobility crank's; planar: knee axis ∥ dynamometer axis, on
the crank line; files reload.
"""
import math
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import opensim as osim

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "fixtures" / "golden" / "dynamometer"
MODELS = REPO / "fixtures" / "models"
G = np.array([0.0, -9.80665, 0.0])  # m/s²
TWO_PI = 2 * math.pi
ROTATIONS = ["femur_rx", "femur_ry", "femur_rz", "knee_angle_r", "ankle_angle_r", "crank_angle"]
COORDS = ["femur_rx", "femur_ry", "femur_rz", "femur_tx", "femur_ty", "femur_tz",
          "knee_angle_r", "ankle_angle_r", "crank_angle"]
# case: rows, sampling rate (Hz), knee_r offset-frame orientation (rad, XYZ), dynamometer-axis frame
# orientation, D − K in the ground (m), pad point in the crank frame (m)
CASES = {
    "spatial": (201, 200, (math.radians(4), math.radians(-3), 0.0), (math.radians(2), 0.0, 0.0),
                np.array([0.028, -0.028, 0.01]), (0.05, 0.0, 0.01)),
    "planar": (201, 100, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), None, (0.05, 0.0, 0.0)),
}


def v3(x):
    return osim.Vec3(float(x[0]), float(x[1]), float(x[2]))


def arr(v):
    return np.array([v.get(0), v.get(1), v.get(2)])


def spatial_transform(names, rotation_axes):
    """A CustomJoint's transform: rotation1–3 about `rotation_axes`, translation1–3 along x, y, z,
    each by one coordinate of `names` (each coordinate its own mobility: q̇ = u)."""
    st = osim.SpatialTransform()
    for k, (coord, axis) in enumerate(zip(names, rotation_axes + [(1, 0, 0), (0, 1, 0), (0, 0, 1)])):
        coordinate = osim.ArrayStr()
        coordinate.append(coord)
        st.updTransformAxis(k).setCoordinateNames(coordinate)
        st.updTransformAxis(k).setAxis(v3(axis))
        st.updTransformAxis(k).set_function(osim.LinearFunction(1.0, 0.0))
    return st


def build_model(case, D, check=False):
    """The case's model with the dynamometer axis through D (ground, m). With `check`, the crank
    turns on a CustomJoint instead — crank_angle about Z first, then five `crank_check_*`
    coordinates the coordinates file leaves at 0 — so ID's generalized forces give the crank's
    whole residual wrench (self-check only)."""
    _, _, knee_tilt, dyn_tilt, _, _ = CASES[case]
    model = osim.Model()
    model.setName(f"dynamometer_{case}")
    model.setGravity(v3(G))
    ground = model.getGround()
    bodies = {}
    for name, mass, com, inertia in [
        ("femur", 8.0, (0, -0.17, 0), (0.11, 0.03, 0.11, 0, 0, 0)),
        ("tibia", 2.69, (0, -0.1875, 0), (0.035, 0.0045, 0.036, 0.001, 0, 0)),
        ("foot", 0.91, (0.053, -0.012, 0.008), (0.001, 0.004, 0.0042, 0.0003, 0, 0)),
        ("crank", 2.0, (0.02, -0.01, 0.015), (0.004, 0.02, 0.021, 0.0005, 0.0002, 0.0001)),
    ]:  # kg, m, kg·m² about the mass center (Ixx Iyy Izz Ixy Ixz Iyz)
        bodies[name] = osim.Body(name, mass, v3(com), osim.Inertia(*inertia))
        model.addBody(bodies[name])
    # hip: a CustomJoint rather than a FreeJoint, whose Euler-angle q̇ ≠ u
    zero = osim.Vec3(0)
    hip = spatial_transform(COORDS[:6], [(1, 0, 0), (0, 1, 0), (0, 0, 1)])
    crank_at = (ground, v3(D), v3(dyn_tilt), bodies["crank"], osim.Vec3(-0.25, 0, 0), zero)
    crank_check = ["crank_angle"] + [f"crank_check_{a}" for a in ["rx", "ry", "tx", "ty", "tz"]]
    joints = [
        osim.CustomJoint("hip", ground, zero, zero, bodies["femur"], zero, zero, hip),
        osim.PinJoint("knee_r", bodies["femur"], osim.Vec3(0, -0.40, 0), v3(knee_tilt),
                      bodies["tibia"], zero, v3(knee_tilt)),
        osim.PinJoint("ankle_r", bodies["tibia"], osim.Vec3(0, -0.40, 0), zero, bodies["foot"], zero, zero),
        osim.CustomJoint("crank_joint", *crank_at, spatial_transform(crank_check, [(0, 0, 1), (1, 0, 0), (0, 1, 0)]))
        if check else osim.PinJoint("crank_joint", *crank_at),
    ]
    for joint in joints:
        model.addJoint(joint)
    ranges = {"femur_rz": (0, 3), "femur_ty": (-1, 2), "knee_angle_r": (-2.5, 0.3), "crank_angle": (-math.pi, math.pi)}
    defaults = {"femur_rz": math.pi / 2, "femur_ty": 0.5, "knee_angle_r": -1.0}
    for joint in joints[1:4 - check]:  # the pins' coordinates (the check crank's are named already)
        joint.upd_coordinates(0).setName({"knee_r": "knee_angle_r", "ankle_r": "ankle_angle_r",
                                          "crank_joint": "crank_angle"}[joint.getName()])
    model.finalizeConnections()
    for name in COORDS:
        c = model.updCoordinateSet().get(name)
        c.setRangeMin(ranges.get(name, (-1, 1))[0])
        c.setRangeMax(ranges.get(name, (-1, 1))[1])
        c.setDefaultValue(defaults.get(name, 0.0))
    model.initSystem()
    return model


def pose(model, values, s=None):
    """A state (`s`, or a new default one) realized to position at the coordinate values (rad, m)."""
    s = model.initSystem() if s is None else s
    for name, value in values.items():
        model.getCoordinateSet().get(name).setValue(s, float(value), False)
    model.realizePosition(s)
    return s


def motion(case, t):
    """Coordinates (rad, m) at the times t (s), the crank angle excepted; and f(t) (N)."""
    if case == "planar":
        one = np.ones_like(t)
        q = {"femur_rx": 0 * one, "femur_ry": 0 * one, "femur_rz": math.pi / 2 * one, "femur_tx": 0 * one,
             "femur_ty": 0.5 * one, "femur_tz": 0 * one, "knee_angle_r": -1.0 * one, "ankle_angle_r": 0.1 * one}
        return q, 450 * np.sin(math.pi * t / 2) ** 2
    # knee: isokinetic-like sweep −1.6 → −0.4 rad, speed ramped by raised cosines over τ = 0.2 s
    tau = 0.2
    ramp = lambda x: x / 2 - tau / (2 * math.pi) * np.sin(math.pi * np.minimum(x, tau) / tau)
    s = np.where(t < tau, ramp(t), np.where(t > 1 - tau, 1 - tau - ramp(1 - t), t - tau / 2))
    q = {"femur_rx": 0.03 * np.sin(TWO_PI * 0.7 * t + 0.4), "femur_ry": 0.03 * np.sin(TWO_PI * 0.9 * t + 1.1),
         "femur_rz": math.pi / 2 + 0.03 * np.sin(TWO_PI * 0.6 * t + 2.0),
         "femur_tx": 0.005 * np.sin(TWO_PI * 0.8 * t), "femur_ty": 0.5 + 0.005 * np.sin(TWO_PI * 1.1 * t + 0.5),
         "femur_tz": 0.005 * np.sin(TWO_PI * 0.5 * t + 1.3),
         "knee_angle_r": -1.6 + 1.2 * s / (1 - tau), "ankle_angle_r": 0.05 * np.sin(TWO_PI * 1.5 * t)}
    return q, 450 - 150 * np.cos(TWO_PI * t)


def wrench_labels(prefix, point):
    """ExternalForce column labels: <prefix>_force_v{x,y,z}, [_force_p{x,y,z}], _torque_{x,y,z}."""
    return ([f"{prefix}_force_v{a}" for a in "xyz"] + [f"{prefix}_force_p{a}" for a in "xyz" if point]
            + [f"{prefix}_torque_{a}" for a in "xyz"])


def write_table(path, name, labels, columns, sep="\t"):
    """An OpenSim .mot (with `name`) or a CSV (name None): the first column time (shortest
    round-trip repr), then 17 significant digits."""
    rows = [sep.join([repr(float(r[0]))] + [f"{x + 0.0:.17g}" for x in r[1:]]) for r in np.column_stack(columns)]  # no "-0"
    header = "" if name is None else f"{name}\nversion=1\nnRows={len(rows)}\nnColumns={len(labels)}\ninDegrees=yes\nendheader\n"
    path.write_text(header + sep.join(labels) + "\n" + "\n".join(rows) + "\n")


def read_sto(path):
    table = osim.TimeSeriesTable(str(path))
    return {label: table.getDependentColumn(label).to_numpy() for label in table.getColumnLabels()}


def external_loads(path, datafile, forces):
    """ExternalLoads at `path` on `datafile` (relative to it); forces: (name, body, expressed in,
    force id, point id or None, torque id)."""
    loads = osim.ExternalLoads()
    loads.setName(path.stem)
    loads.setDataFileName(datafile)
    for name, body, frame, force_id, point_id, torque_id in forces:
        f = osim.ExternalForce()
        f.setName(name)
        f.setAppliedToBodyName(body)
        f.setForceExpressedInBodyName(frame)
        f.setForceIdentifier(force_id)
        if point_id:
            f.setPointExpressedInBodyName(frame)
            f.setPointIdentifier(point_id)
        f.setTorqueIdentifier(torque_id)
        loads.cloneAndAppend(f)
    loads.printToXML(str(path))


def inverse_dynamics(model_path, coordinates, loads, t_end, results):
    """OpenSim's InverseDynamicsTool, unfiltered, 20-digit output; returns its columns."""
    tool = osim.InverseDynamicsTool()
    tool.setName("dynamometer")
    tool.setModelFileName(str(model_path))
    tool.setCoordinatesFileName(str(coordinates))
    tool.setExternalLoadsFileName(str(loads))
    tool.setLowpassCutoffFrequency(-1)
    tool.setStartTime(0.0)
    tool.setEndTime(t_end)
    excluded = osim.ArrayStr()
    excluded.append("Muscles")
    tool.setExcludedForces(excluded)
    tool.setResultsDir(str(results.parent))
    tool.setOutputGenForceFileName(results.name)
    osim.IO.SetPrecision(20)  # Storage prints "%.20lf"
    try:
        if not tool.run():
            raise SystemExit("InverseDynamicsTool failed")
    finally:
        osim.IO.SetPrecision(8)
    return read_sto(results)


def run(case):
    n, rate, _, _, offset, pad_local = CASES[case]
    folder = OUT / case
    folder.mkdir(parents=True, exist_ok=True)
    model_path = MODELS / f"dynamometer_{case}.osim"
    t = np.arange(n) / rate  # s, the nearest doubles to k/rate
    q, f = motion(case, t)

    # Place D (and the crank angle's constant) from the knee at mid-motion, on a model whose D = 0.
    mid = n // 2
    probe = build_model(case, np.zeros(3))
    s = pose(probe, {k: v[mid] for k, v in q.items()})
    knee = probe.getJointSet().get("knee_r").getChildFrame()
    K = arr(knee.getPositionInGround(s))  # knee axis point (m, ground)
    e_s = arr(probe.getBodySet().get("tibia").expressVectorInGround(s, osim.Vec3(0, -1, 0)))  # knee → ankle
    dyn = probe.getJointSet().get("crank_joint").getParentFrame()
    R_D = np.column_stack([arr(dyn.expressVectorInGround(s, osim.Vec3(*e))) for e in np.eye(3)])
    if case == "planar":
        D = K + 0.03 * e_s  # the knee axis 3 cm behind D on the crank line
        q["crank_angle"] = np.full(n, math.atan2(e_s[1], e_s[0]))
    else:
        D = K + offset
        aim = R_D.T @ (K + 0.33 * e_s - D)  # the pad's mid-motion target, dynamometer frame
        wobble = 0.02 * np.sin(TWO_PI * 1.3 * t)
        shift = math.atan2(aim[1], aim[0]) - q["knee_angle_r"][mid] - wobble[mid]  # rad
        q["crank_angle"] = q["knee_angle_r"] + shift + wobble
    model = build_model(case, D)
    model.printToXML(str(model_path))

    # coordinates.mot: rotations in degrees, translations in m
    columns = [np.degrees(q[k]) if k in ROTATIONS else q[k] for k in COORDS]
    write_table(folder / "coordinates.mot", "coordinates", ["time"] + COORDS, [t] + columns)

    # The crank angle, its speed and acceleration as the InverseDynamicsTool splines them.
    storage = osim.Storage(str(folder / "coordinates.mot"))
    model.getSimbodyEngine().convertDegreesToRadians(storage)
    splines = osim.GCVSplineSet(5, storage)  # keep: it owns the spline
    spline = splines.get("crank_angle")
    crank = model.getBodySet().get("crank")
    m = crank.getMass()  # kg
    moments, products = arr(crank.getInertia().getMoments()), arr(crank.getInertia().getProducts())
    I_B = np.diag(moments)  # kg·m² about the mass center, crank frame
    I_B[[0, 1, 0, 2, 1, 2], [1, 0, 2, 0, 2, 1]] = np.repeat(products, 2)
    com_local = crank.getMassCenter()
    state = model.initSystem()
    rows = []
    for k, tk in enumerate(t):
        x = osim.Vector(1, float(tk))
        th = spline.calcValue(x)
        thd = spline.calcDerivative(osim.StdVectorInt([0]), x)
        thdd = spline.calcDerivative(osim.StdVectorInt([0, 0]), x)
        s = pose(model, {"crank_angle": th}, state)
        R = np.column_stack([arr(crank.expressVectorInGround(s, osim.Vec3(*e))) for e in np.eye(3)])
        O = arr(crank.getPositionInGround(s))  # sensor point (m)
        c = arr(crank.findStationLocationInGround(s, com_local))
        p = arr(crank.findStationLocationInGround(s, v3(pad_local)))
        frame = model.getJointSet().get("crank_joint").getParentFrame()
        Dk, Z = arr(frame.getPositionInGround(s)), arr(frame.expressVectorInGround(s, osim.Vec3(0, 0, 1)))
        e_c = R[:, 0]
        n_c = np.cross(Z, e_c)
        if case == "planar":
            F_tc, T_tc = f[k] * n_c, np.zeros(3)
        else:
            F_tc = f[k] * (n_c + 0.12 * e_c + 0.05 * Z)  # N, tibia on crank, ground
            T_tc = np.array([2 * math.sin(3 * tk), -1.5 * math.cos(2 * tk), 1.0 * math.sin(5 * tk)])  # N·m
        w, al = thd * Z, thdd * Z  # rad/s, rad/s²
        a_c = np.cross(al, c - Dk) + np.cross(w, np.cross(w, c - Dk))  # m/s²
        I_G = R @ I_B @ R.T
        euler = I_G @ al + np.cross(w, I_G @ w)
        F_r = m * (a_c - G) - F_tc  # load cell on crank (N, ground)
        M_r = euler + np.cross(c - O, m * (a_c - G)) - np.cross(p - O, F_tc) - T_tc  # about O
        dyn_moment = Z @ (np.cross(p - Dk, F_tc) + T_tc) - Z @ (euler + np.cross(c - Dk, m * a_c))
        rows.append((R.T @ F_r, R.T @ M_r, F_tc, p, T_tc, dyn_moment))
    F_r, M_r, F_tc, P, T_tc = (np.array([r[i] for r in rows]) for i in range(5))
    dyn_moment = np.array([r[5] for r in rows])

    write_table(folder / "loadcell.mot", "loadcell",
                ["time"] + wrench_labels("loadcell", False) + ["dynamometer_moment", "dynamometer_angle"],
                [t, *F_r.T, *M_r.T, dyn_moment, np.degrees(q["crank_angle"])])
    external_loads(folder / "loadcell.xml", "loadcell.mot",
                   [("loadcell", "crank", "crank", "loadcell_force_v", None, "loadcell_torque_")])
    write_table(folder / "pad.mot", "pad", ["time"] + wrench_labels("pad", True),
                [t, *(-F_tc).T, *P.T, *(-T_tc).T])
    external_loads(folder / "pad.xml", "pad.mot",
                   [("pad", "tibia", "ground", "pad_force_v", "pad_force_p", "pad_torque_")])
    write_table(folder / "pad_truth.csv", None, ["time"] + [f"{v}_{a}" for v in ["F_tc", "p", "T_tc"] for a in "xyz"]
                + ["dynamometer_moment"], [t, *F_tc.T, *P.T, *T_tc.T, dyn_moment], sep=",")

    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        truth = inverse_dynamics(model_path, folder / "coordinates.mot", folder / "pad.xml", t[-1], scratch / "id.sto")
        shutil.copyfile(scratch / "id.sto", folder / "inverse_dynamics.sto")
        # Self-check 1: load cell + pad wrench on the crank balance it in OpenSim's ID, about the
        # crank's axis (this model) and wholly (the 6-mobility crank of build_model(check=True)).
        write_table(scratch / "check.mot", "check", ["time"] + wrench_labels("loadcell", False)
                    + wrench_labels("crankpad", True), [t, *F_r.T, *M_r.T, *F_tc.T, *P.T, *T_tc.T])
        external_loads(scratch / "check.xml", "check.mot",
                       [("loadcell", "crank", "crank", "loadcell_force_v", None, "loadcell_torque_"),
                        ("crankpad", "crank", "ground", "crankpad_force_v", "crankpad_force_p", "crankpad_torque_")])
        check = inverse_dynamics(model_path, folder / "coordinates.mot", scratch / "check.xml", t[-1], scratch / "check.sto")
        build_model(case, D, check=True).printToXML(str(scratch / "check.osim"))
        whole = inverse_dynamics(scratch / "check.osim", folder / "coordinates.mot", scratch / "check.xml", t[-1], scratch / "whole.sto")
    residual = np.max(np.abs(check["crank_angle_moment"]))
    loaded = np.max(np.abs(truth["crank_angle_moment"]))
    crank_labels = [k for k in whole if k.startswith("crank_")]
    wholly = max(np.max(np.abs(whole[k])) for k in crank_labels)
    print(f"{case}: crank_angle moment, load cell + pad on crank: max |τ| = {residual:.3e} N·m "
          f"(no load on the crank: max {loaded:.3f} N·m); 6-mobility crank, max over {len(crank_labels)} "
          f"generalized forces: {wholly:.3e} (N·m, N)")
    if residual > 1e-6 or loaded < 1.0 or wholly > 1e-6 or len(crank_labels) != 6:
        raise SystemExit(f"{case}: self-check 1 failed")

    # Self-check 2 (planar): the knee axis ∥ Z and its point on the crank line, at the read-back pose.
    if case == "planar":
        labels, first = storage.getColumnLabels(), storage.getStateVector(0).getData()  # rad, m
        s = pose(model, {labels.get(j + 1): first.get(j) for j in range(first.getSize())})
        knee = model.getJointSet().get("knee_r").getChildFrame()
        axis, K = arr(knee.expressVectorInGround(s, osim.Vec3(0, 0, 1))), arr(knee.getPositionInGround(s))
        frame = model.getJointSet().get("crank_joint").getParentFrame()
        D, Z = arr(frame.getPositionInGround(s)), arr(frame.expressVectorInGround(s, osim.Vec3(0, 0, 1)))
        e_c = arr(crank.expressVectorInGround(s, osim.Vec3(1, 0, 0)))
        off_line, tilt = np.linalg.norm(np.cross(K - D, e_c)), np.linalg.norm(np.cross(axis, Z))
        print(f"planar: knee axis {axis}, knee point {K}, D {D}, e_c {e_c}, (K−D)·e_c = {(K - D) @ e_c:.17g} m; "
              f"distance off the crank line {off_line:.3e} m, |axis × Z| {tilt:.3e}")
        if off_line > 1e-12 or tilt > 1e-12:
            raise SystemExit("planar: self-check 2 failed")
        # Herzog's 2D relation, exact here: M_knee − M_knee(f = 0) = (0.33 / 0.30)·dynamometer moment
        herzog = truth["knee_angle_r_moment"] - truth["knee_angle_r_moment"][0] - 0.33 / 0.30 * dyn_moment
        print(f"planar: max |M_knee − M_knee(0) − 1.1 M_dyn| = {np.max(np.abs(herzog)):.3e} N·m")

    # Self-check 3: everything written reloads.
    osim.Model(str(model_path)).initSystem()
    for name, body in [("loadcell", "crank"), ("pad", "tibia")]:
        loads = osim.ExternalLoads(str(folder / f"{name}.xml"), True)
        if loads.getSize() != 1 or loads.get(0).getAppliedToBodyName() != body:
            raise SystemExit(f"{case}: {name}.xml did not reload")
        osim.Storage(str(folder / f"{name}.mot"))
    knee_moment = truth["knee_angle_r_moment"]
    print(f"{case}: truth knee_angle_r_moment in [{knee_moment.min():.6f}, {knee_moment.max():.6f}] N·m")
    write_readme(case, folder)


def write_readme(case, folder):
    what = {"spatial": "misaligned and moving: knee_r's offset frames turned (4°, −3°, 0) (XYZ), the dynamometer "
                       "axis frame (2°, 0, 0), D 4 cm from the mid-motion knee axis point in the sagittal plane, 1 cm along z; "
                       "knee −1.6 → −0.4 rad (raised-cosine speed ramps), small femur and ankle sinusoids, "
                       "crank_angle = knee + const + 0.02 sin(2π·1.3t); 0–1 s at 200 Hz. p = crank point "
                       "(0.05, 0, 0.01) m, F_tc = f (n_c + 0.12 e_c + 0.05 Z), f = 450 − 150 cos(2πt) N, "
                       "T_tc = (2 sin 3t, −1.5 cos 2t, sin 5t) N·m",
            "planar": "aligned and isometric: knee axis and dynamometer axis ∥ ground z, the knee axis point "
                      "= D − 0.03 e_c, femur fixed, knee −1.0 rad, ankle 0.1 rad; 0–2 s at 100 Hz. p = crank "
                      "point (0.05, 0, 0) m = D + 0.30 e_c, F_tc = f n_c, f = 450 sin²(πt/2) N, T_tc = 0"}
    (folder / "README.md").write_text(f"""# Dynamometer golden `{case}` (OpenSim {osim.__version__})

Written by `oracle/gen_dynamometer.py`; model `fixtures/models/dynamometer_{case}.osim`. Case: {what[case]}.

Conventions: the crank's origin is the load-cell sensor point and its axes the sensor's; crank_joint's
parent frame is at D on the dynamometer axis Z (its z axis), the sensor 0.25 m from D along the crank's
x axis e_c; n_c = Z × e_c; F_tc, T_tc: the tibia's load on the crank (ground). Every file has the
coordinates' rows; times are written shortest-round-trip, other values with 17 significant digits.

* `coordinates.mot` — every coordinate, rotations in degrees, translations in m (17 digits).
* `loadcell.mot` / `loadcell.xml` — the load cell's wrench ON THE CRANK at the crank origin (the sensor),
  force (N) and torque (N·m) expressed in the crank frame (ExternalForce `loadcell`, no point);
  `dynamometer_moment` (N·m, about the dynamometer axis Z: the limb's moment on the crank less the
  crank's inertia) and `dynamometer_angle` (deg, = crank_angle). Newton–Euler of the crank with the
  crank angle differentiated by OpenSim's GCVSplineSet(5) as the InverseDynamicsTool does; gravity
  (0, −9.80665, 0) included: F = m(a_c − g) − F_tc, M_O = I α + ω×Iω + (c−O)×m(a_c − g) − (p−O)×F_tc − T_tc.
* `pad.mot` / `pad.xml` — the crank's load ON THE TIBIA (−F_tc at p, torque −T_tc), in ground.
* `pad_truth.csv` — F_tc (N, tibia on crank), p (m), T_tc (N·m), all in ground, and dynamometer_moment.
* `inverse_dynamics.sto` — OpenSim's InverseDynamicsTool with `pad.xml` (no filtering, 20 digits);
  `knee_angle_r_moment` is the truth knee moment M3D about the knee's pin axis.
""")


def main(cases):
    unknown = [c for c in cases if c not in CASES]
    if unknown:
        raise SystemExit(f"unknown case(s) {unknown}; cases: {list(CASES)}")
    for case in cases or CASES:
        run(case)


if __name__ == "__main__":
    main(sys.argv[1:])
