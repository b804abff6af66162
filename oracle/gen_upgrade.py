#!/usr/bin/env python3
"""OpenSim 4.6's own conversion of 2.x/3.x models into its 4.x format: each model loaded (which
runs OpenSim's updateFromXMLNode conversions) and printed, into fixtures/golden/upgrade/<name>.osim,
for the pendulum leg with long numbers (3.x), arm26 (2.x: wrap objects, display geometry) and
leg6dof9musc (2.x: moving and conditional path points, a coupler, weld joints).

    python3 oracle/gen_upgrade.py

`python3 oracle/gen_upgrade.py --check OURS.osim ORIGINAL.osim` instead loads both models in
OpenSim and prints the lines where OpenSim writes them differently (none when osim-tune's
conversion OURS reads in OpenSim as the ORIGINAL does; socket paths compared in their absolute
form, which OpenSim writes once a model is built).
"""
import difflib
import sys
import tempfile
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
MODELS = {"pendulum_leg_v30000_digits": "legacy/pendulum_leg_v30000_digits.osim",
          "arm26_v20303": "legacy/arm26_v20303.osim",
          "leg6dof9musc_v20303": "legacy/leg6dof9musc_v20303.osim"}
OUT = REPO / "fixtures" / "golden" / "upgrade"


def printed(path):
    with tempfile.TemporaryDirectory() as work:
        out = Path(work) / "model.osim"
        osim.Model(str(path)).printToXML(str(out))
        return out.read_bytes().decode("utf-8", "replace").replace(">../../../", ">/").splitlines()


def main():
    if sys.argv[1:2] == ["--check"]:
        diff = list(difflib.unified_diff(printed(sys.argv[3]), printed(sys.argv[2]), lineterm="", n=1))
        print("\n".join(diff) if diff else "identical")
        return
    OUT.mkdir(parents=True, exist_ok=True)
    for name, source in MODELS.items():
        osim.Model(str(REPO / "fixtures" / source)).printToXML(str(OUT / f"{name}.osim"))
        print(name)


if __name__ == "__main__":
    main()
