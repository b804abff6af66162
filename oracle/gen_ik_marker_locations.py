#!/usr/bin/env python3
"""The model's marker locations OpenSim 4.6's InverseKinematicsTool reports
(`report_marker_locations`): subject01's walk with the scaled model and the setup of the IK
goldens (fixtures/golden/ik/setup_ik_used.xml) at `accuracy` 1e-10 over 1.0–1.1 s.

Writes fixtures/golden/ik/marker_locations/: setup_ik.xml, and OpenSim's ik.mot and
subject01_ik_model_marker_locations.sto (`<marker>_tx/_ty/_tz` in ground, m, for the markers IK
tracks in its order).

    python3 oracle/gen_ik_marker_locations.py
"""
import re
import shutil
import tempfile
from pathlib import Path

import opensim as osim
from tool_run import run_in

REPO = Path(__file__).resolve().parent.parent
GOLDEN = REPO / "fixtures" / "golden" / "ik"
OUT = GOLDEN / "marker_locations"
LOCATIONS = "subject01_ik_model_marker_locations.sto"


def setup(source, destination):
    text = source.read_text()
    text = re.sub(r"<accuracy>[^<]*</accuracy>", "<accuracy>1e-10</accuracy>", text)
    text = re.sub(r"<time_range>[^<]*</time_range>", "<time_range>1.0 1.1</time_range>", text)
    text = re.sub(r"<output_motion_file>[^<]*</output_motion_file>", "<output_motion_file>ik.mot</output_motion_file>", text)
    text = text.replace("</report_errors>", "</report_errors>\n\t\t<report_marker_locations>true</report_marker_locations>", 1)
    assert "report_marker_locations" in text, "no report_errors to follow"
    destination.write_text(text)


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    setup(GOLDEN / "setup_ik_used.xml", OUT / "setup_ik.xml")
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        shutil.copy(REPO / "fixtures" / "golden" / "scale" / "subject01_simbody.osim", work / "subject01_simbody.osim")
        shutil.copy(REPO / "fixtures" / "subject01" / "subject01_walk1.trc", work / "subject01_walk1.trc")
        shutil.copy(OUT / "setup_ik.xml", work / "setup_ik.xml")
        run_in(work, osim.InverseKinematicsTool, "setup_ik.xml")
        shutil.copy(work / "ik.mot", OUT / "ik.mot")
        shutil.copy(work / LOCATIONS, OUT / LOCATIONS)
    print("written", sorted(p.name for p in OUT.iterdir()))


if __name__ == "__main__":
    main()
