#!/usr/bin/env python3
"""Joint reaction goldens: OpenSim 4.6's AnalyzeTool with JointReaction analyses, driven by the
actuator forces OpenSim's own StaticOptimization found (the goldens of gen_static_optimization.py).

    python3 oracle/gen_joint_reaction.py [case ...]

Each case runs the same model, coordinates, force-set files, external loads, time range and
low-pass filter as its static optimisation golden, with two JointReaction analyses whose
`forces_file` is that golden's `<case>_StaticOptimization_force.sto`:

* `JointReaction` — every joint (`ALL`), the load on the child, expressed as the case says below;
* `JointReactionParent` — every joint, the load on the parent, expressed in the case's second frame.

Cases (each writes fixtures/golden/joint_reaction/<case>/<case>_<analysis>_ReactionLoads.sto):

* `arm26` — Thelen muscles over wrap cylinders and ellipsoids, reserves; child in ground,
  parent in `child`.
* `leg6dof9musc` — a CoordinateCouplerConstraint (patella); child in `parent`, parent in ground.
* `subject01_thelen` — the walk with ground reactions, residual Point/TorqueActuators and
  reserves, 6 Hz low-pass; child in `child`, parent in `parent`.
* `rajagopal` — rigid and elastic Millard tendons, locked coordinates, patellae coupled to the
  knees; child in ground, parent in `tibia_r` (a body named as the frame).
* `parallelogram` — a closed loop: the crank's and rocker's tips held apart by a
  ConstantDistanceConstraint, whose force the joints carry too; child in `child`, parent in ground.
* `arm26_states` — arm26 from a states file (its coordinates and speeds as they are); child in
  `parent`, parent in `child`.
* `shoulder` — the ThoracoscapularShoulderModel, its AC PointConstraint carrying the arm (the
  scapulothoracic joint's parent side as OpenSim takes it); child in ground, parent in `parent`.

Muscles are not equilibrated (the forces file overrides every actuator, so their states do not
matter) and tables are printed with 20 digits. The tools run in a scratch folder; only the result
tables are kept.
"""
import shutil
import sys
import tempfile
import time
from pathlib import Path

import opensim as osim

from gen_static_optimization import analyze_tool

REPO = Path(__file__).resolve().parent.parent
SO = REPO / "fixtures" / "golden" / "static_optimization"
OUT = REPO / "fixtures" / "golden" / "joint_reaction"
SUBJECT01 = REPO / "fixtures" / "subject01"
MODELS = REPO / "fixtures" / "models"

# case: (model, coordinates, force sets, time range, cutoff, external loads, child frame, parent frame)
CASES = {
    "arm26": (MODELS / "arm26.osim", SO / "arm26" / "arm26_motion.mot", [SO / "arm26" / "arm26_reserves.xml"], (0.1, 0.9), -1, None, "ground", "child"),
    "leg6dof9musc": (MODELS / "leg6dof9musc.osim", SO / "leg6dof9musc" / "leg_motion.mot", [SO / "leg6dof9musc" / "leg_reserves.xml"], (0.1, 0.9), -1, None, "parent", "ground"),
    "subject01_thelen": (
        SUBJECT01 / "OutputReference" / "subject01_simbody.osim",
        REPO / "fixtures" / "golden" / "ik" / "subject01_walk1_ik.mot",
        [SUBJECT01 / "gait2392_SO_Residual_Actuators.xml"],
        (0.6, 0.9),
        6,
        SUBJECT01 / "subject01_walk1_grf.xml",
        "child",
        "parent",
    ),
    "rajagopal": (
        MODELS / "Rajagopal2016.osim",
        REPO / "fixtures" / "golden" / "forward" / "rajagopal" / "motion.mot",
        [SO / "rajagopal" / "rajagopal_reserves.xml"],
        (0.1, 0.4),
        -1,
        None,
        "ground",
        "tibia_r",
    ),
    "parallelogram": (
        SO / "parallelogram" / "parallelogram.osim",
        SO / "parallelogram" / "parallelogram_motion.mot",
        [SO / "parallelogram" / "parallelogram_reserves.xml"],
        (0.1, 0.9),
        -1,
        None,
        "child",
        "ground",
    ),
    "arm26_states": (MODELS / "arm26.osim", REPO / "fixtures" / "golden" / "analyze_tool" / "states" / "arm26_states.sto", [SO / "arm26" / "arm26_reserves.xml"], (0.05, 0.25), -1, None, "parent", "child"),
    "shoulder": (
        MODELS / "ThoracoscapularShoulderModel.osim",
        SO / "shoulder" / "shoulder_motion.mot",
        [SO / "shoulder" / "shoulder_reserves.xml"],
        (0.1, 0.5),
        -1,
        None,
        "ground",
        "parent",
    ),
}

# Cases whose input is a states file (the tool's states_file), not coordinates.
STATES_CASES = {"arm26_states"}


def reaction(name, forces, on, frame):
    analysis = osim.JointReaction()
    analysis.setName(name)
    analysis.setForcesFileName(str(forces))
    for setter, value in [(analysis.setJointNames, "ALL"), (analysis.setOnBody, on), (analysis.setInFrame, frame)]:
        values = osim.ArrayStr()
        values.append(value)
        setter(values)
    return analysis


def run(case, keep=True):
    """Runs the case's two analyses; with `keep`, copies their tables into the golden folder.
    Returns the AnalyzeTool's wall time (s)."""
    model, coordinates, force_sets, time_range, cutoff, loads, child_frame, parent_frame = CASES[case]
    forces = SO / case / f"{case}_StaticOptimization_force.sto"
    folder = OUT / case
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        tool = analyze_tool(case, model, coordinates, force_sets, time_range, cutoff, loads, scratch / "results", case in STATES_CASES)
        tool.getAnalysisSet().cloneAndAppend(reaction("JointReaction", forces, "child", child_frame))
        tool.getAnalysisSet().cloneAndAppend(reaction("JointReactionParent", forces, "parent", parent_frame))
        setup = scratch / "setup.xml"
        tool.printToXML(str(setup))
        analyze = osim.AnalyzeTool(str(setup))
        start = time.perf_counter()
        if not analyze.run():
            raise SystemExit(f"{case}: AnalyzeTool failed")
        elapsed = time.perf_counter() - start
        if keep:
            folder.mkdir(parents=True, exist_ok=True)
            for analysis in ["JointReaction", "JointReactionParent"]:
                name = f"{case}_{analysis}_ReactionLoads.sto"
                shutil.copyfile(scratch / "results" / name, folder / name)
            print(f"{folder.relative_to(REPO)}: done")
    return elapsed


def main(cases):
    unknown = [c for c in cases if c not in CASES]
    if unknown:
        raise SystemExit(f"unknown case(s) {unknown}; cases: {list(CASES)}")
    for case in cases or CASES:
        run(case)


if __name__ == "__main__":
    main(sys.argv[1:])
