#!/usr/bin/env python3
"""Static optimisation goldens beyond the subject01 pipeline: OpenSim 4.6's AnalyzeTool with a
StaticOptimization analysis on other muscles, paths and settings.

    python3 oracle/gen_static_optimization.py [case ...]

With no argument every case below is generated; naming cases generates only those.

Cases (each writes fixtures/golden/static_optimization/<case>/ with OpenSim's
`<case>_StaticOptimization_activation.sto` and `_force.sto`):

* `arm26` — fixtures/models/arm26.osim (Thelen2003Muscles, paths wrapping over cylinders and
  ellipsoids), a synthetic motion written here (`arm26_motion.mot`, 0–1 s at 100 Hz, degrees:
  r_shoulder_elev = 30 + 25 sin(2πt), r_elbow_flex = 70 + 45 sin(2π·1.5t + 0.3)), unfiltered,
  reserve CoordinateActuators on both coordinates (`arm26_reserves.xml`, optimal force 1,
  unbounded), exponent 2, every row 0.1–0.9 s.
* `arm26_exponent3` — the same with activation exponent 3.
* `leg6dof9musc` — fixtures/models/leg6dof9musc.osim (9 Thelen muscles, the patella coupled to
  the knee by a CoordinateCouplerConstraint), a synthetic motion written here (`leg_motion.mot`:
  pelvis still, hip, knee and ankle swinging, knee_angle_pat_r = knee_angle_r), reserve
  CoordinateActuators on the six independent coordinates (`leg_reserves.xml`), unfiltered,
  exponent 2, 0.1–0.9 s.
* `subject01_thelen` — the subject01 walk with the Thelen-muscle scaled model of
  fixtures/subject01/OutputReference/subject01_simbody.osim, its IK golden
  (fixtures/golden/ik/subject01_walk1_ik.mot), the ground reactions and the residual actuators
  of fixtures/subject01/, 6 Hz low-pass, exponent 2, 0.6–0.9 s, every row.
* `rajagopal` — fixtures/models/Rajagopal2016.osim (80 Millard2012EquilibriumMuscles, 34 with
  rigid tendons; the patellae coupled to the knees by CoordinateCouplerConstraints; its own 17
  CoordinateActuators on the lumbar and arm coordinates, which appear in the tables too) on
  fixtures/golden/forward/rajagopal/motion.mot (0–0.5 s, 100 Hz, degrees; only hip_flexion,
  knee_angle and ankle_angle of both legs), unfiltered, exponent 2, 0.1–0.4 s, every row.
  Reserves written here (`rajagopal_reserves.xml`, unbounded CoordinateActuators
  `reserve_<coordinate>`): optimal force 1000 on the six pelvis coordinates and 1 on
  hip_flexion, hip_adduction, hip_rotation, knee_angle and ankle_angle of both legs — every
  coordinate that is neither locked (subtalar, mtp and wrists are), nor a constraint's dependent
  coordinate (knee_angle_*_beta), nor driven by one of the model's actuators. What OpenSim does
  with the absent coordinates (formCompleteStorages, then Model::assemble per row): every one,
  the pelvis's included, is held at 0 (pelvis_ty at 0, not its default 0.94 m) with zero speed;
  knee_angle_*_beta is assembled onto its coupler (= knee_angle_* in radians) but its speed
  stays 0 (the speeds are splined from the unassembled zeros and assembly does not project
  them); the SO's acceleration targets cover the unconstrained coordinates only.
* `parallelogram` — a planar parallelogram four-bar built here (`parallelogram.osim`): a crank
  and a rocker 0.4 m long pinned to ground 0.3 m apart, their tips held 0.3 m apart by a
  ConstantDistanceConstraint (the coupler), three Millard2012EquilibriumMuscles (ground to the
  crank, ground to the rocker, crank to rocker), gravity −y, default pose 30°. The motion
  (`parallelogram_motion.mot`, 0–1 s at 100 Hz, degrees: crank = rocker = 30 + 25 sin(2πt))
  keeps the loop closed exactly, so its splined accelerations are consistent with the link.
  Reserve CoordinateActuators on both coordinates (`parallelogram_reserves.xml`, optimal force
  1). OpenSim tracks both coordinates' accelerations (a distance constraint constrains no
  coordinate), its forward dynamics carrying the link's force; 0.1–0.9 s, exponent 2. (A
  PointConstraint closing a planar loop has a redundant row normal to the plane, with which
  OpenSim's assembler cannot move the pose off its default: every row is analysed there.)
* `shoulder` — fixtures/models/ThoracoscapularShoulderModel.osim (33 Millard muscles wrapping
  over ellipsoids and cylinders, a ScapulothoracicJoint, the AC joint's PointConstraint closing
  the clavicle–scapula loop, which carries the arm) along a motion written here
  (`shoulder_motion.mot`, 0–1 s at 100 Hz, radians): the glenohumeral coordinates at their
  defaults plus sinusoids (0.2–0.4 rad, periods 0.8–2 s), each row assembled by OpenSim
  (`Model::assemble` at assembly accuracy 1e-12; the loop's coordinates stay at the default
  pose: a ScapulothoracicJoint's speeds are not its coordinates' rates, which the AnalyzeTool
  splines, so with the scapula moving OpenSim's static optimisation cannot meet its own
  constraints). Reserve CoordinateActuators
  (`shoulder_reserves.xml`): optimal force 1000 on the thorax's three rotations, 10 on the
  other unlocked coordinates; exponent 2, 0.1–0.5 s.
* `arm26_states` — arm26 from a `states_file` (fixtures/golden/analyze_tool/states/arm26_states.sto,
  OpenSim's forward simulation of it: coordinates and speeds as they are, the accelerations
  splined from the speeds), arm26's reserves, exponent 2, 0.05–0.25 s.

Muscles are not equilibrated (solve_for_equilibrium_for_auxiliary_states false) and tables are
printed with 20 digits (output_precision), as in the
pipeline golden. The tools run in a scratch folder; only the result tables are kept.
"""
import math
import shutil
import sys
import tempfile
from pathlib import Path

import opensim as osim

from model_parts import add_millard_muscle, write_model

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "fixtures" / "golden" / "static_optimization"
SUBJECT01 = REPO / "fixtures" / "subject01"


def write_motion(path, name, labels, rows, in_degrees):
    """A motion file `name` with columns `labels` (time first) and `rows` (lists of numbers)."""
    lines = ["\t".join(repr(v) for v in row) for row in rows]
    header = f"{name}\nversion=1\nnRows={len(lines)}\nnColumns={len(labels)}\ninDegrees={'yes' if in_degrees else 'no'}\nendheader\n" + "\t".join(labels) + "\n"
    path.write_text(header + "\n".join(lines) + "\n")


def write_reserves(path, strengths):
    """A ForceSet of CoordinateActuators `reserve_<coordinate>`, each with its optimal force
    (`strengths`: coordinate → N·m or N), unbounded controls."""
    forces = osim.ForceSet()
    for coordinate, optimal in strengths.items():
        actuator = osim.CoordinateActuator(coordinate)
        actuator.setName(f"reserve_{coordinate}")
        actuator.setOptimalForce(optimal)
        forces.cloneAndAppend(actuator)
    forces.printToXML(str(path))


def arm26_motion(path):
    rows = []
    for k in range(101):
        t = k / 100
        rows.append([t, 30 + 25 * math.sin(2 * math.pi * t), 70 + 45 * math.sin(2 * math.pi * 1.5 * t + 0.3)])
    write_motion(path, "arm26_motion", ["time", "r_shoulder_elev", "r_elbow_flex"], rows, True)


def arm26_reserves(path):
    write_reserves(path, {"r_shoulder_elev": 1.0, "r_elbow_flex": 1.0})


def parallelogram_model(path):
    """The linkage of the `parallelogram` case (see the module's doc)."""
    model = osim.Model()
    model.setName("parallelogram")
    model.setGravity(osim.Vec3(0, -9.80665, 0))
    ground = model.getGround()
    length, spacing = 0.4, 0.3

    def link(name, mass):
        body = osim.Body(name, mass, osim.Vec3(length / 2, 0, 0), osim.Inertia(0.001, mass * length**2 / 12, mass * length**2 / 12))
        model.addBody(body)
        return body

    crank, rocker = link("crank", 1.2), link("rocker", 0.9)
    # Default pose 30°: the assembler tracks each row's pose from the last, and cannot leave the
    # singular pose at 0° (the links in one line).
    for name, at, child, coordinate in [("crank_pin", osim.Vec3(0), crank, "crank_angle"), ("rocker_pin", osim.Vec3(spacing, 0, 0), rocker, "rocker_angle")]:
        joint = osim.PinJoint(name, ground, at, osim.Vec3(0), child, osim.Vec3(0), osim.Vec3(0))
        joint.upd_coordinates(0).setName(coordinate)
        joint.upd_coordinates(0).setRangeMin(-3.0)
        joint.upd_coordinates(0).setRangeMax(3.0)
        joint.upd_coordinates(0).setDefaultValue(math.radians(30))
        model.addJoint(joint)
    coupler = osim.ConstantDistanceConstraint(crank, osim.Vec3(length, 0, 0), rocker, osim.Vec3(length, 0, 0), spacing)
    coupler.setName("coupler")
    model.addConstraint(coupler)
    add_millard_muscle(model, "crank_flexor", 400.0, 0.15, 0.1, 0.0,
                       [("origin", ground, osim.Vec3(-0.1, 0.1, 0.02)), ("insertion", crank, osim.Vec3(0.2, 0.03, 0.0))])
    add_millard_muscle(model, "rocker_flexor", 300.0, 0.15, 0.1, 0.1,
                       [("origin", ground, osim.Vec3(0.2, 0.12, -0.02)), ("insertion", rocker, osim.Vec3(0.25, 0.03, 0.0))])
    add_millard_muscle(model, "crank_rocker", 200.0, 0.2, 0.1, 0.0,
                       [("origin", crank, osim.Vec3(0.1, -0.04, 0.0)), ("insertion", rocker, osim.Vec3(0.3, -0.03, 0.0))])
    write_model(model, path)


def parallelogram_motion(path):
    rows = []
    for k in range(101):
        t = k / 100
        crank = 30 + 25 * math.sin(2 * math.pi * t)
        rows.append([t, crank, crank])
    write_motion(path, "parallelogram_motion", ["time", "crank_angle", "rocker_angle"], rows, True)


def parallelogram_reserves(path):
    write_reserves(path, {"crank_angle": 1.0, "rocker_angle": 1.0})


SHOULDER_SWINGS = {
    # coordinate: (amplitude rad, period s, phase rad); the clavicle and scapula stay still (a
    # ScapulothoracicJoint's speeds are not its coordinates' rates, which the AnalyzeTool's
    # splines give: moving them, OpenSim's own static optimisation cannot meet its constraints).
    "plane_elv": (0.3, 2.0, 0.0),
    "shoulder_elv": (0.4, 1.6, 0.4),
    "axial_rot": (0.2, 0.8, 0.7),
}


def shoulder_motion(model_path, path):
    """Each row's pose assembled by OpenSim from the swinging coordinates' targets."""
    model = osim.Model(str(model_path))
    model.set_assembly_accuracy(1e-12)
    state = model.initSystem()
    coordinates = model.getCoordinateSet()
    names = [coordinates.get(i).getName() for i in range(coordinates.getSize())]
    defaults = {n: coordinates.get(n).getDefaultValue() for n in names}
    rows = []
    for k in range(101):
        t = k / 100
        for name, (amplitude, period, phase) in SHOULDER_SWINGS.items():
            coordinates.get(name).setValue(state, defaults[name] + amplitude * math.sin(2 * math.pi * t / period + phase), False)
        model.assemble(state)
        rows.append([t] + [coordinates.get(n).getValue(state) for n in names])
    write_motion(path, "shoulder_motion", ["time"] + names, rows, False)


def shoulder_reserves(model_path, path):
    """1000 N·m on the thorax's rotations, 10 on every other unlocked coordinate."""
    model = osim.Model(str(model_path))
    coordinates = model.getCoordinateSet()
    unlocked = [coordinates.get(i).getName() for i in range(coordinates.getSize()) if not coordinates.get(i).get_locked()]
    write_reserves(path, {name: 1000.0 if name.startswith("ground_thorax") else 10.0 for name in unlocked})


def leg_motion(path):
    """Pelvis still (tilt 0°, tx 0, ty 1.06 m), the hip, knee and ankle swinging; the patella's
    coordinate follows the knee as its coupler says (knee_angle_pat_r = knee_angle_r)."""
    rows = []
    for k in range(101):
        t = k / 100
        hip = 20 + 30 * math.sin(2 * math.pi * t)
        knee = -45 + 35 * math.sin(2 * math.pi * t + 0.8)
        ankle = 10 * math.sin(2 * math.pi * 2 * t)
        rows.append([t, 0.0, 0.0, 1.06004667, hip, knee, knee, ankle])
    labels = ["time", "pelvis_tilt", "pelvis_tx", "pelvis_ty", "hip_flexion_r", "knee_angle_r", "knee_angle_pat_r", "ankle_angle_r"]
    write_motion(path, "leg_motion", labels, rows, True)


def leg_reserves(path):
    write_reserves(path, {"pelvis_tilt": 100.0, "pelvis_tx": 1000.0, "pelvis_ty": 1000.0, "hip_flexion_r": 1.0, "knee_angle_r": 1.0, "ankle_angle_r": 1.0})


def analyze_tool(case, model, coordinates, force_sets, time_range, cutoff, loads, results, states=False):
    """An AnalyzeTool named `case` as the goldens run it: the force-set files added (not
    replacing the model's), muscles not equilibrated, tables printed with 20 digits, results in
    `results`, from `coordinates` (a states file with `states`); the analyses are the caller's to
    append."""
    tool = osim.AnalyzeTool()
    tool.setName(case)
    tool.setModelFilename(str(model))
    files = osim.ArrayStr()
    for f in force_sets:
        files.append(str(f))
    tool.setForceSetFiles(files)
    tool.setReplaceForceSet(False)
    tool.setResultsDir(str(results))
    tool.setInitialTime(time_range[0])
    tool.setFinalTime(time_range[1])
    if states:
        tool.setStatesFileName(str(coordinates))
    else:
        tool.setCoordinatesFileName(str(coordinates))
    tool.setLowpassCutoffFrequency(cutoff)
    tool.setSolveForEquilibrium(False)
    tool.setOutputPrecision(20)
    if loads:
        tool.setExternalLoadsFileName(str(loads))
    return tool


def run(case, model, coordinates, force_sets, time_range, cutoff, exponent, loads=None, states=False):
    """With `states`, `coordinates` is a states file (the tool's states_file)."""
    folder = OUT / case
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        tool = analyze_tool(case, model, coordinates, force_sets, time_range, cutoff, loads, scratch / "results", states)
        so = osim.StaticOptimization()
        so.setName("StaticOptimization")
        so.setStartTime(time_range[0])
        so.setEndTime(time_range[1])
        so.setStepInterval(1)
        so.setActivationExponent(exponent)
        so.setUseMusclePhysiology(True)
        so.setUseModelForceSet(True)
        tool.getAnalysisSet().cloneAndAppend(so)
        setup = scratch / "setup.xml"
        tool.printToXML(str(setup))
        if not osim.AnalyzeTool(str(setup)).run():
            raise SystemExit(f"{case}: AnalyzeTool failed")
        for kind in ["activation", "force"]:
            name = f"{case}_StaticOptimization_{kind}.sto"
            shutil.copyfile(scratch / "results" / name, folder / name)
    print(f"{folder.relative_to(REPO)}: done")


def rajagopal_reserves(model_path, path):
    """A CoordinateActuator `reserve_<coordinate>` on every coordinate that is not locked, not the
    dependent coordinate of a constraint (the patellae) and not already driven by one of the model's
    own CoordinateActuators (lumbar and arms): the six pelvis coordinates with optimal force 1000,
    the leg coordinates with 1; unbounded controls. Returns the coordinate names."""
    model = osim.Model(str(model_path))
    state = model.initSystem()
    driven = set()
    for i in range(model.getForceSet().getSize()):
        actuator = osim.CoordinateActuator.safeDownCast(model.getForceSet().get(i))
        if actuator:
            driven.add(actuator.get_coordinate())
    names = []
    for i in range(model.getCoordinateSet().getSize()):
        coordinate = model.getCoordinateSet().get(i)
        name = coordinate.getName()
        if not (coordinate.get_locked() or coordinate.isDependent(state) or name in driven):
            names.append(name)
    legs = [f"{c}_{side}" for side in "rl" for c in ["hip_flexion", "hip_adduction", "hip_rotation", "knee_angle", "ankle_angle"]]
    expected = ["pelvis_tilt", "pelvis_list", "pelvis_rotation", "pelvis_tx", "pelvis_ty", "pelvis_tz"] + legs
    if sorted(names) != sorted(expected):
        raise SystemExit(f"rajagopal reserves: unexpected coordinates {names}")
    write_reserves(path, {name: 1000.0 if name.startswith("pelvis_") else 1.0 for name in names})
    return names


CASES = ["arm26", "arm26_exponent3", "leg6dof9musc", "subject01_thelen", "rajagopal", "parallelogram", "shoulder", "arm26_states"]


def main(cases):
    unknown = [c for c in cases if c not in CASES]
    if unknown:
        raise SystemExit(f"unknown case(s) {unknown}; cases: {CASES}")
    wanted = set(cases or CASES)
    arm = OUT / "arm26"
    model = REPO / "fixtures" / "models" / "arm26.osim"
    if wanted & {"arm26", "arm26_exponent3"}:
        arm.mkdir(parents=True, exist_ok=True)
        arm26_motion(arm / "arm26_motion.mot")
        arm26_reserves(arm / "arm26_reserves.xml")
    if "arm26" in wanted:
        run("arm26", model, arm / "arm26_motion.mot", [arm / "arm26_reserves.xml"], (0.1, 0.9), -1, 2.0)
    if "arm26_exponent3" in wanted:
        run("arm26_exponent3", model, arm / "arm26_motion.mot", [arm / "arm26_reserves.xml"], (0.1, 0.9), -1, 3.0)
    if "leg6dof9musc" in wanted:
        leg = OUT / "leg6dof9musc"
        leg.mkdir(parents=True, exist_ok=True)
        leg_motion(leg / "leg_motion.mot")
        leg_reserves(leg / "leg_reserves.xml")
        run("leg6dof9musc", REPO / "fixtures" / "models" / "leg6dof9musc.osim", leg / "leg_motion.mot", [leg / "leg_reserves.xml"], (0.1, 0.9), -1, 2.0)
    if "subject01_thelen" in wanted:
        run("subject01_thelen", SUBJECT01 / "OutputReference" / "subject01_simbody.osim",
            REPO / "fixtures" / "golden" / "ik" / "subject01_walk1_ik.mot",
            [SUBJECT01 / "gait2392_SO_Residual_Actuators.xml"], (0.6, 0.9), 6, 2.0,
            loads=SUBJECT01 / "subject01_walk1_grf.xml")
    if "rajagopal" in wanted:
        raj = OUT / "rajagopal"
        raj.mkdir(parents=True, exist_ok=True)
        model = REPO / "fixtures" / "models" / "Rajagopal2016.osim"
        rajagopal_reserves(model, raj / "rajagopal_reserves.xml")
        run("rajagopal", model, REPO / "fixtures" / "golden" / "forward" / "rajagopal" / "motion.mot",
            [raj / "rajagopal_reserves.xml"], (0.1, 0.4), -1, 2.0)
    if "parallelogram" in wanted:
        folder = OUT / "parallelogram"
        folder.mkdir(parents=True, exist_ok=True)
        parallelogram_model(folder / "parallelogram.osim")
        parallelogram_motion(folder / "parallelogram_motion.mot")
        parallelogram_reserves(folder / "parallelogram_reserves.xml")
        run("parallelogram", folder / "parallelogram.osim", folder / "parallelogram_motion.mot", [folder / "parallelogram_reserves.xml"], (0.1, 0.9), -1, 2.0)
    if "arm26_states" in wanted:
        arm.mkdir(parents=True, exist_ok=True)
        arm26_reserves(arm / "arm26_reserves.xml")
        run("arm26_states", REPO / "fixtures" / "models" / "arm26.osim", REPO / "fixtures" / "golden" / "analyze_tool" / "states" / "arm26_states.sto", [arm / "arm26_reserves.xml"], (0.05, 0.25), -1, 2.0, states=True)
    if "shoulder" in wanted:
        folder = OUT / "shoulder"
        folder.mkdir(parents=True, exist_ok=True)
        model = REPO / "fixtures" / "models" / "ThoracoscapularShoulderModel.osim"
        shoulder_motion(model, folder / "shoulder_motion.mot")
        shoulder_reserves(model, folder / "shoulder_reserves.xml")
        run("shoulder", model, folder / "shoulder_motion.mot", [folder / "shoulder_reserves.xml"], (0.1, 0.5), -1, 2.0)


if __name__ == "__main__":
    main(sys.argv[1:])
