#!/usr/bin/env python3
"""`cargo xtask bench`'s OpenSim side of the AnalyzeTool: OpenSim 4.6's AnalyzeTool runs each golden
setup of gen_analyze_tool.py and gen_induced_accelerations.py
(fixtures/golden/analyze_tool/<case>/setup.xml) in a folder with its
inputs, writing nothing kept. Prints `<case>_seconds=<wall time of AnalyzeTool.run>` per case.

    python3 oracle/bench_analyze_tool.py
"""
import os
import shutil
import tempfile
import time
from pathlib import Path

import opensim as osim

from gen_analyze_tool import CASES, INPUTS, MOTION, OUT
from gen_induced_accelerations import CASES as INDUCED_CASES


def main():
    osim.Logger.setLevelString("error")
    for case in list(CASES) + list(INDUCED_CASES):
        with tempfile.TemporaryDirectory() as work:
            work = Path(work)
            for name, source in list(INPUTS.items()) + [("subject01_walk1_ik.mot", MOTION)]:
                shutil.copy(source, work / name)
            shutil.copy(OUT / case / "setup.xml", work / "setup.xml")
            cwd = os.getcwd()
            os.chdir(work)
            try:
                start = time.perf_counter()
                osim.AnalyzeTool("setup.xml").run()
                seconds = time.perf_counter() - start
            finally:
                os.chdir(cwd)
        print(f"{case}_seconds={seconds!r}", flush=True)


if __name__ == "__main__":
    main()
