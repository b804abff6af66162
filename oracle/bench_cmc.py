#!/usr/bin/env python3
"""`cargo xtask bench`'s OpenSim side of computed muscle control: OpenSim 4.6's CMCTool on each
setup of fixtures/golden/cmc/ (inputs copied beside it, as gen_cmc.py runs them). Writes nothing
to the repository; prints `<case>_seconds=<wall time>` per case (the tool's run alone).

    python3 oracle/bench_cmc.py
"""
import shutil
import tempfile
import time
from pathlib import Path

import opensim as osim

from gen_cmc import CASES, OUT


def main():
    osim.Logger.setLevelString("error")
    for case, (inputs, _, _) in CASES.items():
        with tempfile.TemporaryDirectory() as work:
            work = Path(work)
            for file, source in inputs.items():
                shutil.copy(source, work / file)
            shutil.copy(OUT / case / "setup.xml", work / "setup.xml")
            tool = osim.CMCTool(str(work / "setup.xml"))
            begin = time.perf_counter()
            if not tool.run():
                raise SystemExit(f"CMCTool failed on {case}")
            print(f"{case}_seconds={time.perf_counter() - begin!r}", flush=True)


if __name__ == "__main__":
    main()
