#!/usr/bin/env python3
"""Inverse kinematics with a PointConstraint, as OpenSim 4.6 solves it, on OpenSim's own test
case (opensim-core `Applications/IK/tests/resources`: subject1_abdbonepin.osim, a 3.x shoulder
model — ScapulothoracicJoint, the acromioclavicular PointConstraint `AC`, a Windows-1252 byte in
its notes — with abdbonepin.trc and setup_ik_abdbonepin.xml):

- fixtures/ik_point_constraint/: the model (unchanged), the trial's first second
  (`abdbonepin_1s.trc`, 101 frames; its header's NumFrames made true) and the setup with that
  time range and `accuracy` 1e-10;
- fixtures/golden/ik/point_constraint/: OpenSim's coordinates (`ik.mot`) and marker errors
  (`ik_marker_errors.sto`) at that accuracy.

    python3 oracle/gen_ik_point_constraint.py OPENSIM_CORE_CHECKOUT
"""
import re
import shutil
import sys
import tempfile
from pathlib import Path

import opensim as osim
from tool_run import run_in

REPO = Path(__file__).resolve().parent.parent
FIXTURE = REPO / "fixtures" / "ik_point_constraint"
GOLDEN = REPO / "fixtures" / "golden" / "ik" / "point_constraint"
END_TIME = 1.0


def slice_trc(source, destination):
    """The frames up to END_TIME with the header's NumFrames and OrigNumFrames set to their
    count."""
    lines = source.read_bytes().split(b"\n")
    rows = [line for line in lines[5:] if line.strip() and float(line.split(b"\t")[1]) <= END_TIME + 1e-9]
    values = lines[2].split(b"\t")
    values[2] = str(len(rows)).encode()
    values[7] = str(len(rows)).encode() + (b"\r" if values[7].endswith(b"\r") else b"")
    destination.write_bytes(b"\n".join(lines[:2] + [b"\t".join(values)] + lines[3:5] + rows) + b"\n")
    return len(rows)


def main():
    resources = Path(sys.argv[1]) / "Applications" / "IK" / "tests" / "resources"
    FIXTURE.mkdir(parents=True, exist_ok=True)
    GOLDEN.mkdir(parents=True, exist_ok=True)
    shutil.copy(resources / "subject1_abdbonepin.osim", FIXTURE / "subject1_abdbonepin.osim")
    frames = slice_trc(resources / "abdbonepin.trc", FIXTURE / "abdbonepin_1s.trc")
    setup = (resources / "setup_ik_abdbonepin.xml").read_text()
    setup = re.sub(r"<accuracy>[^<]*</accuracy>", "<accuracy>1e-10</accuracy>", setup)
    setup = re.sub(r"<time_range>[^<]*</time_range>", f"<time_range> 0 {END_TIME}</time_range>", setup)
    setup = re.sub(r"<marker_file>[^<]*</marker_file>", "<marker_file>abdbonepin_1s.trc</marker_file>", setup)
    setup = re.sub(r"<report_errors>[^<]*</report_errors>", "<report_errors>true</report_errors>", setup)
    setup = re.sub(r"<output_motion_file>[^<]*</output_motion_file>", "<output_motion_file>ik.mot</output_motion_file>", setup)
    (FIXTURE / "setup_ik.xml").write_text(setup)
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        for name in ("subject1_abdbonepin.osim", "abdbonepin_1s.trc", "setup_ik.xml"):
            shutil.copy(FIXTURE / name, work / name)
        run_in(work, osim.InverseKinematicsTool, "setup_ik.xml")
        shutil.copy(work / "ik.mot", GOLDEN / "ik.mot")
        errors = next(work.glob("*marker_errors.sto"))
        shutil.copy(errors, GOLDEN / "ik_marker_errors.sto")
    print(f"{frames} frames")


if __name__ == "__main__":
    main()
