#!/usr/bin/env python3
"""Golden for the InverseDynamicsTool's `joints_to_report_body_forces`: OpenSim 4.6 runs
subject01's walk as fixtures/subject01/subject01_Setup_InverseDynamics.xml says (0.4–1.6 s,
6 Hz low-pass, muscles excluded, the ground reactions) on the scaled model
fixtures/golden/scale/subject01_simbody.osim with the IK golden
fixtures/golden/ik/subject01_walk1_ik.mot, every joint reported (`ALL`), 20-digit output.

    python3 oracle/gen_body_forces.py

Writes fixtures/golden/inverse_dynamics/subject01_walk1_body_forces.sto (OpenSim's
`output_body_forces_file`); the generalized forces it also writes are not kept (the pipeline
golden subject01_walk1_InverseDynamics.sto has them).
"""
import shutil
import tempfile
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
SUBJECT01 = REPO / "fixtures" / "subject01"
OUT = REPO / "fixtures" / "golden" / "inverse_dynamics" / "subject01_walk1_body_forces.sto"


def main():
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        tool = osim.InverseDynamicsTool(str(SUBJECT01 / "subject01_Setup_InverseDynamics.xml"))
        tool.setModelFileName(str(REPO / "fixtures" / "golden" / "scale" / "subject01_simbody.osim"))
        tool.setCoordinatesFileName(str(REPO / "fixtures" / "golden" / "ik" / "subject01_walk1_ik.mot"))
        tool.setExternalLoadsFileName(str(SUBJECT01 / "subject01_walk1_grf.xml"))
        tool.setResultsDir(str(scratch))
        tool.setOutputGenForceFileName("forces.sto")
        setup = scratch / "setup.xml"
        tool.printToXML(str(setup))
        text = setup.read_text()
        added = "<joints_to_report_body_forces>ALL</joints_to_report_body_forces>" \
                "<output_body_forces_file>body_forces.sto</output_body_forces_file>"
        text = text.replace("</InverseDynamicsTool>", added + "</InverseDynamicsTool>")
        setup.write_text(text)
        if not osim.InverseDynamicsTool(str(setup)).run():
            raise SystemExit("InverseDynamicsTool failed")
        shutil.copyfile(scratch / "body_forces.sto", OUT)
    print(f"{OUT.relative_to(REPO)}: done")


if __name__ == "__main__":
    main()
