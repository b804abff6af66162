#!/usr/bin/env python3
"""Constraints between bodies as OpenSim 4.6 holds them: at the default pose (`initSystem`
assembles the model) and in inverse kinematics.

fixtures/models/linked_mechanisms.osim, built here with OpenSim's API: five small mechanisms,
each with default values that break its constraint so that assembly has to move them:
- a PointConstraint closing a loop (a BallJoint arm and a PinJoint forearm whose tip is
  pinned to a sled on a SliderJoint);
- a ConstantDistanceConstraint between a crank and a rocker on tilted pins, the rocker
  carrying a locked pin;
- a PointOnLineConstraint holding a point of a FreeJoint block on a slanted ground line, the
  block's x translation `is_free_to_satisfy_constraints`;
- a WeldConstraint welding a FreeJoint cap, through offset frames, to a PinJoint lever;
- a CoordinateCouplerConstraint whose dependent's default value (0) is not the coupler's value
  (OpenSim overrides it);
and five Millard muscles across them, whose moment arms OpenSim computes through the
constraints (MomentArmSolver: the coordinate's speed lit, the others projected onto the
velocity constraints).
`assembly_accuracy` is 1e-12 so that the goldens are near exact.

fixtures/golden/constraint_assembly.json: per model — linked_mechanisms.osim and
leg6dof9musc.osim, whose only constraint is a coupler with a default value 2e-8 rad off — the
coordinates, their default values and OpenSim's assembled default pose with every marker in
ground there; for linked_mechanisms also `poses` (the assembled default pose and three of the
trial's assembled poses) with each muscle's length and `computeMomentArm` about every
coordinate.

fixtures/ik_linked_mechanisms/: a 20-frame trial (poses scattered about the defaults, each
assembled by OpenSim, markers with seeded 1 mm noise, in mm at 60 Hz) and an IK setup (every
marker weight 1, `accuracy` 1e-10); fixtures/golden/ik/linked_mechanisms/: OpenSim's `ik.mot`
and `ik_marker_errors.sto`.

fixtures/golden/analyze_linked/: OpenSim's AnalyzeTool with a MuscleAnalysis on the same model
along OpenSim's IK solution with elbow_flexion moved 3° (perturbed.mot: the point loop no
longer closes, and AnalyzeTool assembles every row) — its Length.sto.

fixtures/golden/scale_linked/: ScaleTool by measurements on the same model and the trial's
first five frames — marker pairs across the elbow, the rod and the weld, whose distances at the
default state depend on how the model assembles — setup.xml and OpenSim's scaled.osim.

    python3 oracle/gen_constraint_assembly.py
"""
import json
import math
import random
import shutil
import tempfile
from pathlib import Path

import opensim as osim

from gen_scale_measured import measured_scale_setup, measurement_xml, write_trc
from gen_scale_zoo import run_scale_tool
from model_parts import add_millard_muscle, write_model
from tool_run import run_in

REPO = Path(__file__).resolve().parent.parent
MODEL = REPO / "fixtures" / "models" / "linked_mechanisms.osim"
GOLDEN = REPO / "fixtures" / "golden" / "constraint_assembly.json"
IK_FIXTURE = REPO / "fixtures" / "ik_linked_mechanisms"
IK_GOLDEN = REPO / "fixtures" / "golden" / "ik" / "linked_mechanisms"
SCALE_GOLDEN = REPO / "fixtures" / "golden" / "scale_linked"
ANALYZE_GOLDEN = REPO / "fixtures" / "golden" / "analyze_linked"
MEASUREMENTS = [("elbow_span", "arm_m1", "forearm_m2", ["arm", "forearm"]), ("rod_span", "crank_m1", "rocker_m1", ["crank", "rocker", "rocker_tip"]),
                ("weld_span", "lever_m2", "cap_m1", ["lever", "cap"])]
V = osim.Vec3
MUSCLES = [("loop_muscle", [("ground", (0.3, 1.2, 0.05)), ("arm", (0.05, -0.1, 0.02)), ("forearm", (0.03, -0.2, 0.01))]),
           ("rod_muscle", [("crank", (0.05, 0.02, 0.0)), ("rocker_tip", (0.04, 0.01, 0.0))]),
           ("rail_muscle", [("ground", (3.2, 0.9, 0.1)), ("block", (0.02, 0.04, 0.0))]),
           ("cap_muscle", [("ground", (4.2, 1.3, 0.0)), ("cap", (0.02, 0.03, 0.01))]),
           ("follower_muscle", [("lever", (0.1, 0.05, 0.0)), ("follower", (0.05, 0.02, 0.0))])]
TRIAL_POSES_WITH_MOMENT_ARMS = [3, 9, 16]


def add_body(model, name, markers):
    body = osim.Body(name, 1.0, V(0.01, -0.02, 0.0), osim.Inertia(0.02, 0.015, 0.01, 0.001, 0.0, 0.0))
    model.addBody(body)
    for k, location in enumerate(markers):
        model.addMarker(osim.Marker(f"{name}_m{k + 1}", body, V(*location)))
    return body


def set_defaults(joint, values, names):
    for k, (value, name) in enumerate(zip(values, names)):
        coordinate = joint.upd_coordinates(k)
        coordinate.setName(name)
        coordinate.setDefaultValue(value)


def build():
    model = osim.Model()
    model.setName("linked_mechanisms")
    model.set_assembly_accuracy(1e-12)
    ground = model.getGround()
    # A closed loop: ball-jointed arm, pinned forearm, forearm tip held at a ground point.
    arm = add_body(model, "arm", [(0.05, -0.2, 0.03), (-0.04, -0.3, 0.0)])
    forearm = add_body(model, "forearm", [(0.04, -0.15, 0.02), (-0.03, -0.25, 0.0)])
    shoulder = osim.BallJoint("shoulder", ground, V(0, 1, 0), V(0, 0, 0), arm, V(0, 0, 0), V(0, 0, 0))
    set_defaults(shoulder, [0.1, 0.2, -0.3], ["shoulder_x", "shoulder_y", "shoulder_z"])
    elbow = osim.PinJoint("elbow", arm, V(0, -0.4, 0), V(0.2, 0, 0), forearm, V(0, 0, 0), V(0, 0, 0))
    set_defaults(elbow, [0.5], ["elbow_flexion"])
    model.addJoint(shoulder)
    model.addJoint(elbow)
    sled = add_body(model, "sled", [(0.03, 0.02, 0.0)])
    rail_joint = osim.SliderJoint("sled_slider", ground, V(0.25, 0.45, 0.1), V(0, 0, 0.2), sled, V(0, 0, 0), V(0, 0, 0))
    set_defaults(rail_joint, [0.05], ["sled_x"])
    model.addJoint(rail_joint)
    model.addConstraint(osim.PointConstraint(forearm, V(0, -0.3, 0), sled, V(0, 0, 0)))
    # A crank and a rocker a constant distance apart; a locked pin on the rocker.
    crank = add_body(model, "crank", [(0.08, 0.02, 0.01)])
    rocker = add_body(model, "rocker", [(0.2, 0.03, 0.02), (0.1, -0.02, 0.05)])
    rocker_tip = add_body(model, "rocker_tip", [(0.05, 0.0, 0.02), (0.0, 0.06, -0.02)])
    crank_pin = osim.PinJoint("crank_pin", ground, V(1.5, 0.5, 0), V(0, 0, 0), crank, V(0, 0, 0), V(0, 0, 0))
    set_defaults(crank_pin, [0.3], ["crank_angle"])
    rocker_pin = osim.PinJoint("rocker_pin", ground, V(2.0, 0.5, 0), V(0.3, 0, 0), rocker, V(0, 0, 0), V(0, 0, 0))
    set_defaults(rocker_pin, [-0.2], ["rocker_angle"])
    tip_pin = osim.PinJoint("tip_pin", rocker, V(0.3, 0, 0), V(0, 0.4, 0), rocker_tip, V(0, 0, 0), V(0, 0, 0))
    set_defaults(tip_pin, [0.1], ["tip_angle"])
    tip_pin.upd_coordinates(0).setDefaultLocked(True)
    for joint in (crank_pin, rocker_pin, tip_pin):
        model.addJoint(joint)
    rod = osim.ConstantDistanceConstraint(crank, V(0.1, 0, 0), rocker, V(0.25, 0, 0.02), 0.45)
    rod.setName("rod")
    model.addConstraint(rod)
    # A point of a free block on a slanted ground line.
    block = add_body(model, "block", [(0.05, 0.05, 0.0), (-0.05, 0.02, 0.04), (0.0, -0.04, -0.05)])
    block_free = osim.FreeJoint("block_free", ground, V(0, 0, 0), V(0, 0, 0), block, V(0, 0, 0), V(0, 0, 0))
    set_defaults(block_free, [0.1, -0.2, 0.3, 3.0, 0.6, 0.2], [f"block_{n}" for n in ("rx", "ry", "rz", "tx", "ty", "tz")])
    block_free.upd_coordinates(3).set_is_free_to_satisfy_constraints(True)
    model.addJoint(block_free)
    rail = osim.PointOnLineConstraint(ground, V(1, 0.2, 0.1), V(3.0, 0.5, 0.0), block, V(0.05, 0.02, 0.0))
    rail.setName("rail")
    model.addConstraint(rail)
    # A free cap welded to a pinned lever through offset frames.
    lever = add_body(model, "lever", [(0.15, 0.02, 0.03), (0.3, -0.03, 0.0)])
    cap = add_body(model, "cap", [(0.04, 0.03, 0.0), (-0.03, 0.05, 0.02), (0.0, -0.02, 0.06)])
    lever_pin = osim.PinJoint("lever_pin", ground, V(4.0, 1.0, 0), V(0, 0.2, 0), lever, V(0, 0, 0), V(0, 0, 0))
    set_defaults(lever_pin, [0.4], ["lever_angle"])
    cap_free = osim.FreeJoint("cap_free", ground, V(0, 0, 0), V(0, 0, 0), cap, V(0, 0, 0), V(0, 0, 0))
    set_defaults(cap_free, [0.2, 0.1, -0.1, 4.1, 0.8, 0.05], [f"cap_{n}" for n in ("rx", "ry", "rz", "tx", "ty", "tz")])
    model.addJoint(lever_pin)
    model.addJoint(cap_free)
    weld = osim.WeldConstraint("weld", lever, V(0.2, -0.1, 0), V(0, 0, 0.3), cap, V(0.01, 0.02, 0), V(0.1, 0, 0))
    model.addConstraint(weld)
    # A coupler whose dependent's default value is not the coupler's.
    follower = add_body(model, "follower", [(0.1, 0.02, 0.0), (0.0, -0.1, 0.03)])
    follower_pin = osim.PinJoint("follower_pin", ground, V(5.0, 1.0, 0), V(0, 0, 0), follower, V(0, 0, 0), V(0, 0, 0))
    set_defaults(follower_pin, [0.0], ["follower_angle"])
    model.addJoint(follower_pin)
    coupler = osim.CoordinateCouplerConstraint()
    coupler.setName("follower_coupler")
    coupler.setIndependentCoordinateNames(osim.ArrayStr("lever_angle", 1))
    coupler.setDependentCoordinateName("follower_angle")
    coupler.setFunction(osim.LinearFunction(2.0, 0.1))
    model.addConstraint(coupler)
    for name, points in MUSCLES:
        path = [(f"{name}_point{k + 1}", ground if frame == "ground" else model.getBodySet().get(frame), V(*location)) for k, (frame, location) in enumerate(points)]
        add_millard_muscle(model, name, 100.0, 0.1, 0.2, 0.0, path)
    write_model(model, MODEL)


def coordinates(model):
    return [model.getCoordinateSet().get(i) for i in range(model.getCoordinateSet().getSize())]


def markers_in_ground(model, state):
    markers = model.getMarkerSet()
    return {markers.get(i).getName(): list(markers.get(i).getLocationInGround(state).to_numpy()) for i in range(markers.getSize())}


def default_golden(model):
    state = model.initSystem()
    model.realizePosition(state)
    return {
        "coordinates": [c.getName() for c in coordinates(model)],
        "default_values": [c.getDefaultValue() for c in coordinates(model)],
        "assembled": [c.getValue(state) for c in coordinates(model)],
        "markers_in_ground": markers_in_ground(model, state),
    }


def trial_poses(model, state):
    """The trial's 20 poses, each scattered about the assembled defaults and assembled, set in
    `state` in turn."""
    defaults = [c.getValue(state) for c in coordinates(model)]
    for k in range(20):
        for coordinate, value in zip(coordinates(model), defaults):
            if not coordinate.getDefaultLocked():
                coordinate.setValue(state, value + 0.3 * math.sin(0.4 * k + 1.7 * len(coordinate.getName())), False)
        model.assemble(state)
        model.realizePosition(state)
        yield k


def trial_frames(model):
    state = model.initSystem()
    rng = random.Random(20261127)
    frames = []
    for _ in trial_poses(model, state):
        frames.append([[1000.0 * (p + rng.gauss(0.0, 0.001)) for p in position] for position in markers_in_ground(model, state).values()])
    return frames


def finite_or_none(value):
    """JSON has no NaN: OpenSim's 0/0 moment arm about a coordinate the constraints fix is null."""
    return value if math.isfinite(value) else None


def moment_arm_pose(model, state):
    muscles = [model.getMuscles().get(i) for i in range(model.getMuscles().getSize())]
    return {
        "q": [c.getValue(state) for c in coordinates(model)],
        "lengths": {m.getName(): m.getLength(state) for m in muscles},
        "moment_arms": {m.getName(): {c.getName(): finite_or_none(m.computeMomentArm(state, c)) for c in coordinates(model)} for m in muscles},
    }


def moment_arm_poses(model):
    state = model.initSystem()
    model.realizePosition(state)
    poses = [moment_arm_pose(model, state)]
    poses += [moment_arm_pose(model, state) for k in trial_poses(model, state) if k in TRIAL_POSES_WITH_MOMENT_ARMS]
    return poses


SETUP = """<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40000">
  <InverseKinematicsTool name="linked_mechanisms">
    <model_file>linked_mechanisms.osim</model_file>
    <constraint_weight>Inf</constraint_weight>
    <accuracy>1e-10</accuracy>
    <IKTaskSet><objects>{tasks}</objects></IKTaskSet>
    <marker_file>trial.trc</marker_file>
    <time_range> 0 1</time_range>
    <report_errors>true</report_errors>
    <output_motion_file>ik.mot</output_motion_file>
  </InverseKinematicsTool>
</OpenSimDocument>
"""


def ik_golden(model):
    IK_FIXTURE.mkdir(parents=True, exist_ok=True)
    IK_GOLDEN.mkdir(parents=True, exist_ok=True)
    names = list(markers_in_ground(model, model.initSystem()).keys())
    write_trc(IK_FIXTURE / "trial.trc", names, trial_frames(model))
    tasks = "".join(f'<IKMarkerTask name="{n}"><apply>true</apply><weight>1</weight></IKMarkerTask>' for n in names)
    (IK_FIXTURE / "setup_ik.xml").write_text(SETUP.format(tasks=tasks))
    shutil.copy(MODEL, IK_FIXTURE / MODEL.name)
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        for name in (MODEL.name, "trial.trc", "setup_ik.xml"):
            shutil.copy(IK_FIXTURE / name, work / name)
        run_in(work, osim.InverseKinematicsTool, "setup_ik.xml")
        shutil.copy(work / "ik.mot", IK_GOLDEN / "ik.mot")
        shutil.copy(next(work.glob("*marker_errors.sto")), IK_GOLDEN / "ik_marker_errors.sto")


def scale_setup(model_file, trial_file):
    measurements = "".join(measurement_xml(name, [(a, b)], bodies, "X Y Z") for name, a, b, bodies in MEASUREMENTS)
    return measured_scale_setup("linked_subject", 10.5, model_file, measurements, trial_file, "0 0.07", "scaled.osim")


def scale_golden():
    SCALE_GOLDEN.mkdir(parents=True, exist_ok=True)
    run_scale_tool(scale_setup(MODEL.name, "trial.trc"), [MODEL, IK_FIXTURE / "trial.trc"], {"scaled.osim": SCALE_GOLDEN / "scaled.osim"})
    (SCALE_GOLDEN / "setup.xml").write_text(scale_setup("../../models/linked_mechanisms.osim", "../../ik_linked_mechanisms/trial.trc"))


ANALYZE_SETUP = """<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40000">
<AnalyzeTool name="linked">
<model_file>linked_mechanisms.osim</model_file>
<results_directory>.</results_directory>
<initial_time>0</initial_time>
<final_time>1</final_time>
<AnalysisSet name="Analyses"><objects>
<MuscleAnalysis name="MuscleAnalysis"><on>true</on><start_time>0</start_time><end_time>1</end_time><step_interval>1</step_interval>
<in_degrees>true</in_degrees><muscle_list> all</muscle_list><moment_arm_coordinate_list> all</moment_arm_coordinate_list>
<compute_moments>false</compute_moments></MuscleAnalysis>
</objects></AnalysisSet>
<coordinates_file>perturbed.mot</coordinates_file>
</AnalyzeTool>
</OpenSimDocument>
"""


def analyze_golden():
    """OpenSim's IK solution with elbow_flexion moved 3°, and AnalyzeTool's muscle lengths."""
    ANALYZE_GOLDEN.mkdir(parents=True, exist_ok=True)
    lines = (IK_GOLDEN / "ik.mot").read_text().splitlines()
    end = lines.index("endheader")
    elbow = lines[end + 1].split("\t").index("elbow_flexion")
    rows = [line.split() for line in lines[end + 2:] if line.strip()]
    for row in rows:
        row[elbow] = f"{float(row[elbow]) + 3.0:.8f}"
    (ANALYZE_GOLDEN / "perturbed.mot").write_text("\n".join(lines[:end + 2] + ["\t".join(row) for row in rows]) + "\n")
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        shutil.copy(MODEL, work / MODEL.name)
        shutil.copy(ANALYZE_GOLDEN / "perturbed.mot", work / "perturbed.mot")
        (work / "setup.xml").write_text(ANALYZE_SETUP)
        run_in(work, osim.AnalyzeTool, "setup.xml")
        shutil.copy(work / "linked_MuscleAnalysis_Length.sto", ANALYZE_GOLDEN / "Length.sto")


def main():
    build()
    goldens = {path.name: default_golden(osim.Model(str(path))) for path in (MODEL, MODEL.parent / "leg6dof9musc.osim")}
    goldens[MODEL.name]["poses"] = moment_arm_poses(osim.Model(str(MODEL)))
    GOLDEN.write_text(json.dumps(goldens, indent=1) + "\n")
    ik_golden(osim.Model(str(MODEL)))
    analyze_golden()
    scale_golden()
    print("written", *(p.relative_to(REPO) for p in (MODEL, GOLDEN, IK_GOLDEN, ANALYZE_GOLDEN, SCALE_GOLDEN)))


if __name__ == "__main__":
    main()
