#!/usr/bin/env python3
"""OpenSim 4.6's InverseKinematicsTool on opensim-core's IK constraint test
(`fixtures/ik_constraint_test/`: `constraintTest_ikOnly.osim`, 8 CoordinateCouplerConstraints and
42 weighted markers, 9 frames of its trial at 0.33–0.37 s, its setup with that time range and
`accuracy` 1e-3): markers that the model cannot fit to better than ~12 cm RMS and coordinates
(the forearms' pronation) that the markers barely see.

Writes fixtures/golden/ik/constraint_test/: OpenSim's `ik.mot` and `ik_marker_errors.sto`.

    python3 oracle/gen_ik_constraint_test.py
"""
import shutil
from pathlib import Path

from tool_run import tool_results

REPO = Path(__file__).resolve().parent.parent
FIXTURE = REPO / "fixtures" / "ik_constraint_test"
OUT = REPO / "fixtures" / "golden" / "ik" / "constraint_test"


def main():
    inputs = {name: FIXTURE / name for name in ("constraintTest_ikOnly.osim", "constraintTest.trc")}
    setup = (FIXTURE / "constraintTest_setup_ik.xml").read_text()
    setup = setup.replace("constraintTest_ik_new.mot", "ik.mot").replace("</InverseKinematicsTool>", "<results_directory> Results </results_directory></InverseKinematicsTool>")
    OUT.mkdir(parents=True, exist_ok=True)
    with tool_results("InverseKinematicsTool", inputs, setup) as (_, results):
        shutil.copy(results.parent / "ik.mot", OUT / "ik.mot")
        shutil.copy(results / "_ik_marker_errors.sto", OUT / "ik_marker_errors.sto")
    print("->", OUT)


if __name__ == "__main__":
    main()
