#!/usr/bin/env python3
"""Inverse kinematics with `from_file` coordinate tasks, as OpenSim 4.6 solves it: subject01's
walk (the scaled model and trial of the IK goldens) with the setup OpenSim ran
(fixtures/golden/ik/setup_ik_used.xml) plus three IKCoordinateTasks whose values come from a
`coordinate_file`: hip_flexion_r and knee_angle_r (weight 20) and lumbar_extension (weight 5).

The coordinate file is OpenSim's own IK solution of the walk (fixtures/golden/ik/
subject01_walk1_ik.mot, degrees) at every fourth frame with hip_flexion_r +8°, knee_angle_r −6°
and lumbar_extension +5°: the tasks pull those coordinates off the markers' pose, and between
the file's rows OpenSim follows its interpolating quintic GCV splines.

Writes fixtures/golden/ik/coordinate_file/: setup_ik.xml (accuracy 1e-10, 0.6–1.0 s),
coordinates.mot, and OpenSim's ik.mot and ik_marker_errors.sto.

    python3 oracle/gen_ik_coordinate_file.py
"""
import re
import shutil
import tempfile
from pathlib import Path

import opensim as osim
from tool_run import run_in

REPO = Path(__file__).resolve().parent.parent
GOLDEN = REPO / "fixtures" / "golden" / "ik"
OUT = GOLDEN / "coordinate_file"
OFFSETS = {"hip_flexion_r": 8.0, "knee_angle_r": -6.0, "lumbar_extension": 5.0}
WEIGHTS = {"hip_flexion_r": 20, "knee_angle_r": 20, "lumbar_extension": 5}
STRIDE = 4


def coordinate_file(source, destination):
    """Every STRIDE-th row of `source` with OFFSETS (degrees) added."""
    lines = source.read_text().splitlines()
    end = lines.index("endheader")
    labels = lines[end + 1].split("\t")
    rows = [line.split() for line in lines[end + 2:] if line.strip()][::STRIDE]
    for row in rows:
        for name, offset in OFFSETS.items():
            k = labels.index(name)
            row[k] = f"{float(row[k]) + offset:.8f}"
    header = [re.sub(r"^nRows=.*", f"nRows={len(rows)}", line) for line in lines[:end + 1]]
    body = ["\t".join(row) for row in rows]
    destination.write_text("\n".join(header + [lines[end + 1]] + body) + "\n")


def setup(source, destination):
    text = source.read_text()
    tasks = "".join(
        f"\t\t\t\t<IKCoordinateTask name=\"{name}\">\n\t\t\t\t\t<apply>true</apply>\n\t\t\t\t\t<weight>{weight}</weight>\n"
        f"\t\t\t\t\t<value_type>from_file</value_type>\n\t\t\t\t</IKCoordinateTask>\n" for name, weight in WEIGHTS.items())
    text = text.replace("\t\t\t</objects>\n\t\t\t<groups", tasks + "\t\t\t</objects>\n\t\t\t<groups", 1)
    assert "from_file" in text, "the task set's closing tag was not found"
    text = re.sub(r"<accuracy>[^<]*</accuracy>", "<accuracy>1e-10</accuracy>", text)
    text = re.sub(r"<time_range>[^<]*</time_range>", "<time_range>0.6 1.0</time_range>", text)
    text = re.sub(r"<coordinate_file>[^<]*</coordinate_file>", "<coordinate_file>coordinates.mot</coordinate_file>", text)
    text = re.sub(r"<output_motion_file>[^<]*</output_motion_file>", "<output_motion_file>ik.mot</output_motion_file>", text)
    destination.write_text(text)


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    coordinate_file(GOLDEN / "subject01_walk1_ik.mot", OUT / "coordinates.mot")
    setup(GOLDEN / "setup_ik_used.xml", OUT / "setup_ik.xml")
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        shutil.copy(REPO / "fixtures" / "golden" / "scale" / "subject01_simbody.osim", work / "subject01_simbody.osim")
        shutil.copy(REPO / "fixtures" / "subject01" / "subject01_walk1.trc", work / "subject01_walk1.trc")
        for name in ("coordinates.mot", "setup_ik.xml"):
            shutil.copy(OUT / name, work / name)
        run_in(work, osim.InverseKinematicsTool, "setup_ik.xml")
        shutil.copy(work / "ik.mot", OUT / "ik.mot")
        shutil.copy(next(work.glob("*marker_errors.sto")), OUT / "ik_marker_errors.sto")
    print("written", sorted(p.name for p in OUT.iterdir()))


if __name__ == "__main__":
    main()
